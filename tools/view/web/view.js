// ohrp view's page: builds the scene from the server's description (geoms with world poses
// computed by the server), places the robot's geoms on every frame, frames the camera from the
// robot's size, feeds the plots (plots.js) and shows the camera images (docs/view.md).
// URL options: ?joints=A,B,C  the joints plotted; ?columns=A,B  log columns plotted in the last
// panel (replay: any column of log.csv; live: q_J, qref_J, SENSOR_fz, zmp_x, zmp_y);
// ?t=T (replay) start paused at time T [s];
// ?window=S (live) seconds of history in the plots; ?images=1 (live) show the camera images
// at once (otherwise the "camera images" box turns them on); ?token=T (--control) the control
// panel (control.js).
'use strict';

const params = new URLSearchParams(location.search);
const stateEl = document.getElementById('state');
const $ = (id) => document.getElementById(id);

// ---------------- the 3D view (z up, SI units) ----------------
const canvas = $('view3d');
const renderer = new THREE.WebGLRenderer({canvas, antialias: true, preserveDrawingBuffer: true});
renderer.setClearColor(0xc8d4e0);
const scene3 = new THREE.Scene();
const camera = new THREE.PerspectiveCamera(40, 1, 0.01, 200);
camera.up.set(0, 0, 1);
scene3.add(new THREE.AmbientLight(0xffffff, 0.55));
const sun = new THREE.DirectionalLight(0xffffff, 0.6);
sun.position.set(2, -3, 5);
scene3.add(sun);
const orbit = {azimuth: -0.6, elevation: 0.18, distance: 3.0, target: new THREE.Vector3(0, 0, 0.5)};
let home = null;  // the framing of the robot (from its size in the first frame), for 'reset view'
let moving = [];  // meshes of the robot's geoms, in the server's order

// frames the robot from its size: the camera looks at the middle of its bounding box from far
// enough that its height (and width) fills about 70 % of the view, with room to rise or bend
function frameRobot() {
  const box = new THREE.Box3();
  for (const o of moving) if (o) box.expandByObject(o);
  if (box.isEmpty()) return;
  const size = box.getSize(new THREE.Vector3()), mid = box.getCenter(new THREE.Vector3());
  const half = Math.tan(camera.fov * Math.PI / 360);  // tan of half the vertical field of view
  const across = Math.max(size.z, Math.hypot(size.x, size.y) / Math.max(camera.aspect, 0.1));
  home = {distance: Math.max(0.3, 0.5 * across / half / 0.7), z: mid.z};
  resetView();
  const d = stateEl.dataset;
  d.frameTop = box.max.z; d.frameBottom = box.min.z; d.frameDistance = home.distance;
}

function resetView() {
  if (!home) return;
  orbit.azimuth = -0.6; orbit.elevation = 0.18;
  orbit.distance = home.distance; orbit.target.z = home.z;
  $('follow').checked = true;
  if (lastBase) { orbit.target.x = lastBase[0]; orbit.target.y = lastBase[1]; }
  render();
}

function placeCamera() {
  const o = orbit, c = Math.cos(o.elevation);
  camera.position.set(o.target.x + o.distance * c * Math.cos(o.azimuth),
                      o.target.y + o.distance * c * Math.sin(o.azimuth),
                      o.target.z + o.distance * Math.sin(o.elevation));
  camera.lookAt(o.target);
}

function resize() {
  const w = canvas.clientWidth, h = canvas.clientHeight;
  renderer.setSize(w, h, false);
  camera.aspect = w / Math.max(1, h);
  camera.updateProjectionMatrix();
}

let meshes = [];  // the description's meshes as three.js geometries, shared by their geoms

// base64 to the bytes it encodes
function bytesOf(b64) {
  const s = atob(b64), out = new Uint8Array(s.length);
  for (let i = 0; i < s.length; ++i) out[i] = s.charCodeAt(i);
  return out.buffer;
}

// one of the description's meshes (vertices and triangles in the frame its geoms' poses place;
// little-endian float32 and uint32 arrays in base64)
function makeMesh(m) {
  const geo = new THREE.BufferGeometry();
  geo.setAttribute('position', new THREE.BufferAttribute(new Float32Array(bytesOf(m.vertices)), 3));
  geo.setIndex(new THREE.BufferAttribute(new Uint32Array(bytesOf(m.faces)), 1));
  geo.computeVertexNormals();
  return geo;
}

let hfields = [];  // the description's height fields as three.js geometries

// one of the description's height fields: a grid of triangles over the samples, row r at
// y = -sy + 2 sy r / (nrow - 1), column c at x = -sx + 2 sx c / (ncol - 1) in its geom's frame,
// at the elevations [m] of the float32 array (row-major, base64)
function makeHfield(h) {
  const z = new Float32Array(bytesOf(h.heights)), nr = h.nrow, nc = h.ncol;
  const sx = h.size[0], sy = h.size[1];
  const pos = new Float32Array(3 * nr * nc);
  for (let r = 0; r < nr; ++r) {
    for (let c = 0; c < nc; ++c) {
      const k = r * nc + c;
      pos[3 * k] = -sx + 2 * sx * c / (nc - 1);
      pos[3 * k + 1] = -sy + 2 * sy * r / (nr - 1);
      pos[3 * k + 2] = z[k];
    }
  }
  const idx = new Uint32Array(6 * (nr - 1) * (nc - 1));
  let i = 0;
  for (let r = 0; r + 1 < nr; ++r) {
    for (let c = 0; c + 1 < nc; ++c) {
      const a = r * nc + c, b = a + 1, d = a + nc, e = d + 1;
      idx.set([a, b, e, a, e, d], i);  // counter-clockwise seen from above
      i += 6;
    }
  }
  const geo = new THREE.BufferGeometry();
  geo.setAttribute('position', new THREE.BufferAttribute(pos, 3));
  geo.setIndex(new THREE.BufferAttribute(idx, 1));
  geo.computeVertexNormals();
  return geo;
}

// one geom as a three.js object (MuJoCo sizes are half-lengths and radii)
function makeGeom(g) {
  const s = g.size, color = new THREE.Color(g.rgba[0], g.rgba[1], g.rgba[2]);
  const mat = new THREE.MeshLambertMaterial({color, transparent: g.rgba[3] < 1, opacity: g.rgba[3]});
  let obj;
  if (g.type === 'box') {
    obj = new THREE.Mesh(new THREE.BoxBufferGeometry(2 * s[0], 2 * s[1], 2 * s[2]), mat);
  } else if (g.type === 'sphere' || g.type === 'ellipsoid') {
    obj = new THREE.Mesh(new THREE.SphereBufferGeometry(1, 20, 14), mat);
    obj.scale.set(s[0], g.type === 'sphere' ? s[0] : s[1], g.type === 'sphere' ? s[0] : s[2]);
  } else if (g.type === 'cylinder' || g.type === 'capsule') {
    const cyl = new THREE.CylinderBufferGeometry(s[0], s[0], 2 * s[1], 20);
    cyl.rotateX(Math.PI / 2);  // three's cylinders run along y, MuJoCo's along z
    obj = new THREE.Group();
    obj.add(new THREE.Mesh(cyl, mat));
    if (g.type === 'capsule') {
      for (const z of [-s[1], s[1]]) {
        const cap = new THREE.Mesh(new THREE.SphereBufferGeometry(s[0], 16, 10), mat);
        cap.position.z = z;
        obj.add(cap);
      }
    }
  } else if (g.type === 'mesh') {
    if (meshes[g.mesh]) obj = new THREE.Mesh(meshes[g.mesh], mat);
  } else if (g.type === 'hfield') {
    if (hfields[g.hfield]) obj = new THREE.Mesh(hfields[g.hfield], mat);
  } else if (g.type === 'plane') {
    const w = s[0] > 0 ? 2 * s[0] : 40, h = s[1] > 0 ? 2 * s[1] : 40;
    // a checker of 0.5 m squares (as in the paper's video): walking progress shows while the
    // camera follows the robot (thin grid lines mostly vanish in software rendering)
    const floor = new THREE.MeshLambertMaterial({map: checkerTexture(w / 0.5, h / 0.5)});
    obj = new THREE.Group();
    obj.add(new THREE.Mesh(new THREE.PlaneBufferGeometry(w, h), floor));
  }
  return obj;
}

// a texture of 2 x 2 squares (dark, light) repeated `nx` x `ny` times over a plane
function checkerTexture(nx, ny) {
  const c = document.createElement('canvas');
  c.width = c.height = 2;
  const g = c.getContext('2d');
  g.fillStyle = '#3c4650'; g.fillRect(0, 0, 2, 2);
  g.fillStyle = '#6a7886'; g.fillRect(0, 0, 1, 1); g.fillRect(1, 1, 1, 1);
  const t = new THREE.CanvasTexture(c);
  t.magFilter = THREE.NearestFilter;  // sharp edges near, mipmapped (grey) far
  t.wrapS = t.wrapT = THREE.RepeatWrapping;
  t.repeat.set(nx / 2, ny / 2);
  return t;
}

function setPose(obj, p) {
  obj.position.set(p[0], p[1], p[2]);
  obj.quaternion.set(p[4], p[5], p[6], p[3]);  // three: (x, y, z, w)
}

function buildScene(desc) {
  meshes = (desc.meshes || []).map(makeMesh);
  hfields = (desc.hfields || []).map((h) => (h.nrow > 1 && h.ncol > 1 ? makeHfield(h) : null));
  for (const g of desc.static) {
    const o = makeGeom(g);
    if (o) { setPose(o, g.pose); scene3.add(o); }
  }
  moving = desc.moving.map((g) => {
    const o = makeGeom(g);
    if (o) { o.userData.body = g.body; scene3.add(o); }  // the body: control.js picks it by a click
    return o;
  });
}

// draws the scene once at the browser's next frame, however many poses and camera moves came
// before it: a robot of heavy meshes then draws less often but never falls behind the frames
let renderPending = false;
function render() {
  if (renderPending) return;
  renderPending = true;
  paceDraw(() => {  // pace.js: live at most 5 draws a second (?fps=N), more while the mouse moves it
    renderPending = false;
    placeCamera();
    renderer.render(scene3, camera);
  });
}

let lastBase = null;
function showPoses(poses) {
  poses.forEach((p, i) => { if (moving[i]) setPose(moving[i], p); });
  if (poses.length) lastBase = poses[0];
  if (!home) frameRobot();
  // the camera follows the robot horizontally (unless 'follow' is off)
  if (poses.length && $('follow').checked) { orbit.target.x = poses[0][0]; orbit.target.y = poses[0][1]; }
  render();
}
$('reset_view').onclick = resetView;
$('follow').onchange = () => {
  if ($('follow').checked && lastBase) { orbit.target.x = lastBase[0]; orbit.target.y = lastBase[1]; }
  render();
};

// mouse: drag turns the camera, shift-drag or right-drag pans it (in the view's plane: the
// point under the mouse stays under it; follow turns off), the wheel brings it closer
let drag = null;
canvas.addEventListener('contextmenu', (e) => e.preventDefault());
canvas.addEventListener('mousedown', (e) => { drag = {x: e.clientX, y: e.clientY, pan: e.button === 2 || e.shiftKey}; });
window.addEventListener('mouseup', () => { drag = null; });
window.addEventListener('mousemove', (e) => {
  if (!drag) return;
  const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
  drag.x = e.clientX; drag.y = e.clientY;
  if (drag.pan) {
    // metres per pixel at the target's distance
    const scale = 2 * orbit.distance * Math.tan(camera.fov * Math.PI / 360) / Math.max(1, canvas.clientHeight);
    placeCamera();
    camera.updateMatrixWorld();
    const right = new THREE.Vector3().setFromMatrixColumn(camera.matrixWorld, 0);
    const up = new THREE.Vector3().setFromMatrixColumn(camera.matrixWorld, 1);
    orbit.target.addScaledVector(right, -dx * scale).addScaledVector(up, dy * scale);
    $('follow').checked = false;
  } else {
    orbit.azimuth -= 0.01 * dx;
    orbit.elevation = Math.max(-0.2, Math.min(1.4, orbit.elevation + 0.01 * dy));
  }
  render();
});
canvas.addEventListener('wheel', (e) => {
  orbit.distance = Math.max(0.5, orbit.distance * (e.deltaY > 0 ? 1.1 : 0.9));
  render();
  e.preventDefault();
});

// ---------------- status line ----------------
function showFrame(f) {
  $('time').textContent = 't = ' + f.t.toFixed(3) + ' s' + (f.cycle !== undefined ? ' (cycle ' + f.cycle + ')' : '');
  if (f.status) $('status').innerHTML = f.status.map((s) => '<span>' + s + '</span>').join('');
  if (f.counters) $('counters').textContent = 'late ' + f.counters.late_commands + ', rejected ' +
      f.counters.rejected_commands + (f.ended ? ' - the producer has ended' : '');
  if (f.base) {
    $('base').textContent = 'base pose: ' + f.base;
    $('base').className = f.base === 'ground truth' ? '' : 'warn';
  }
  applyOverlay(f);  // before the poses: drawn in the same browser frame
  applyPlan(f);
  applyReach(f);
  if (f.t !== undefined) showRecorded(f.t);
  showPoses(f.poses);
  cursorT = f.t;
  stateEl.dataset.t = f.t;
  stateEl.dataset.frames = Number(stateEl.dataset.frames) + 1;
}

// ---------------- live: append each frame to the plots ----------------
const windowS = Number(params.get('window') || 10);
let lastDraw = 0;
function liveFrame(f) {
  showFrame(f);
  if (f.images && f.images.startsWith('refused')) { $('cameras').textContent = 'camera images ' + f.images; $('cameras').className = 'warn'; }
  const add = (ds, y) => { if (y !== null && y !== undefined) ds.data.push({x: f.t, y}); };
  const q = charts.q.data.datasets, n = plotJoints.length;
  jointIndex.forEach((j, i) => { add(q[i], f.q[j]); if (f.qref) add(q[n + i], f.qref[j]); });
  charts.fz.data.datasets.forEach((ds, i) => add(ds, f.fz[i]));
  if (f.zmp) { add(charts.zmp.data.datasets[0], f.zmp[0]); add(charts.zmp.data.datasets[1], f.zmp[1]); }
  charts.cols.data.datasets.forEach((ds) => add(ds, liveColumn[ds.label](f)));
  for (const c of Object.values(charts)) {
    for (const ds of c.data.datasets) while (ds.data.length && ds.data[0].x < f.t - windowS) ds.data.shift();
    c.options.scales.x.min = Math.max(0, f.t - windowS);
    c.options.scales.x.max = Math.max(windowS, f.t);
  }
  // the plots are redrawn at most 10 times a second
  const now = performance.now();
  if (now - lastDraw > 100 || f.ended) { redrawCharts(); lastDraw = now; }
}

// ---------------- replay: whole curves, a slider and play/pause ----------------
let replay = null;
function startReplay(h, ws) {
  // each curve {t, y}: min/max decimated by the server, every peak kept
  const s = h.series;
  const pts = (c) => c.t.map((x, i) => ({x, y: c.y[i]})).filter((p) => p.y !== null);
  const q = charts.q.data.datasets, n = plotJoints.length;
  plotJoints.forEach((j, i) => { q[i].data = pts(s.q[j]); q[n + i].data = pts(s.qref[j]); });
  charts.fz.data.datasets.forEach((ds) => { ds.data = pts(s.fz[ds.label]); });
  charts.zmp.data.datasets[0].data = pts(s.zmp_x);
  charts.zmp.data.datasets[1].data = pts(s.zmp_y);
  const slider = $('slider');
  slider.min = h.t0; slider.max = h.t1; slider.step = (h.t1 - h.t0) / 2000 || 0.001;
  $('range').textContent = h.t0.toFixed(2) + ' - ' + h.t1.toFixed(2) + ' s';
  replay = {ws, t: h.t0, t0: h.t0, t1: h.t1, playing: !params.has('t'), waiting: false, wanted: null};
  if (params.has('t')) replay.t = Number(params.get('t'));
  $('play').textContent = replay.playing ? 'pause' : 'play';
  $('play').onclick = () => {
    replay.playing = !replay.playing;
    if (replay.playing && replay.t >= replay.t1) replay.t = replay.t0;
    $('play').textContent = replay.playing ? 'pause' : 'play';
  };
  slider.oninput = () => { replay.playing = false; $('play').textContent = 'play'; seek(Number(slider.value)); };
  seek(replay.t);
  let last = performance.now();
  const tick = (now) => {
    if (replay.playing) {
      replay.t = Math.min(replay.t1, replay.t + (now - last) / 1000);
      if (replay.t >= replay.t1) { replay.playing = false; $('play').textContent = 'play'; }
      slider.value = replay.t;
      seek(replay.t);
    }
    last = now;
    requestAnimationFrame(tick);
  };
  requestAnimationFrame(tick);
}

// one request in flight: the newest wanted time is asked when the answer comes
function seek(t) {
  replay.t = t;
  if (replay.waiting) { replay.wanted = t; return; }
  replay.waiting = true;
  replay.ws.send(JSON.stringify({t}));
}

function replayFrame(f) {
  replay.waiting = false;
  showFrame(f);
  $('slider').value = f.t;
  redrawCharts();
  if (replay.wanted !== null) { const t = replay.wanted; replay.wanted = null; seek(t); }
}

// ---------------- live camera images ----------------
// A second WebSocket, open only while the images are shown (the box ticked and the page
// visible): the server asks the producer for images only while some page holds one open.
// Each message: int32 camera, width, height, 0; float64 time, frame; then RGB8 rows.
let imagesWs = null, cameraList = [];
function setupImages(h) {
  cameraList = h.camera_list || [];
  if (!cameraList.length) return;
  $('images_toggle').hidden = false;
  $('images').innerHTML = cameraList.map((c, i) => '<figure><canvas id="camimg' + i + '" width="' + c.width +
      '" height="' + c.height + '"></canvas><figcaption id="camcap' + i + '">' + c.name +
      ': no image yet</figcaption></figure>').join('');
  const box = $('show_images');
  box.checked = params.get('images') === '1';
  box.onchange = updateImages;
  document.addEventListener('visibilitychange', updateImages);
  updateImages();
}

function updateImages() {
  const want = $('show_images').checked && !document.hidden;
  $('images').style.display = want ? 'flex' : 'none';
  if (want && !imagesWs) {
    const ws = new WebSocket('ws://' + location.host + '/ws/images');
    ws.binaryType = 'arraybuffer';
    // each image drawn is answered: the server sends the next (the newest) only then, so
    // images never queue behind a slow page
    ws.onmessage = (e) => {
      try {
        drawImage(e.data);
        $('images_note').textContent = '';
      } finally {  // answered even when drawing failed: the server would wait forever
        if (ws.readyState === WebSocket.OPEN) ws.send('drawn');
      }
    };
    // closed by the server while still wanted (it restarted, or a network hiccup): said on the
    // page, and asked again every second
    ws.onclose = () => {
      if (imagesWs !== ws) return;
      imagesWs = null;
      $('images_note').textContent = 'camera images: connection lost, reconnecting...';
      setTimeout(updateImages, 1000);
    };
    imagesWs = ws;
  } else if (!want && imagesWs) {
    imagesWs.close();
    imagesWs = null;
  }
  if (!want) $('images_note').textContent = '';
}

function drawImage(buf) {
  const head = new DataView(buf, 0, 32);
  const cam = head.getInt32(0, true), w = head.getInt32(4, true), h = head.getInt32(8, true);
  const t = head.getFloat64(16, true), frame = head.getFloat64(24, true);
  const canvas = $('camimg' + cam);
  if (!canvas || buf.byteLength < 32 + 3 * w * h) return;
  if (canvas.width !== w || canvas.height !== h) { canvas.width = w; canvas.height = h; }
  const rgb = new Uint8Array(buf, 32, 3 * w * h), img = new ImageData(w, h), px = img.data;
  for (let i = 0, j = 0; i < w * h; ++i, j += 3) {
    px[4 * i] = rgb[j]; px[4 * i + 1] = rgb[j + 1]; px[4 * i + 2] = rgb[j + 2]; px[4 * i + 3] = 255;
  }
  canvas.getContext('2d').putImageData(img, 0, 0);
  $('camcap' + cam).textContent = cameraList[cam].name + ': frame ' + frame + ', t = ' + t.toFixed(3) + ' s';
  stateEl.dataset.images = Number(stateEl.dataset.images) + 1;
  if (cam === 0) { stateEl.dataset.imageFrame = frame; stateEl.dataset.imageT = t; }
}

// ---------------- the connection ----------------
function connect() {
  const ws = new WebSocket('ws://' + location.host + '/ws');
  let hello = null;
  ws.onmessage = (e) => {
    const m = JSON.parse(e.data);
    if (!hello) {
      hello = m;
      document.title = 'ohrp view: ' + m.title;
      $('title').textContent = m.title + (m.producer ? ' (' + m.producer + ')' : '');
      if (m.mode === 'live') { $('timeline').style.display = 'none'; }
      if (m.mode === 'replay') setupRecorded(m);
      else if (m.cameras > 0) $('cameras').textContent = m.cameras + ' camera(s):';
      if (m.mode === 'live') setupImages(m);
      resize();
      buildScene(m.scene);
      setupOverlays(m);
      setupPlan(m);
      setupReach(m);
      buildCharts(m.scene);
      if (m.mode === 'replay') startReplay(m, ws);
      setupPicker(m);
      setupControl(m);
      stateEl.dataset.ready = 1;
      return;
    }
    if (hello.mode === 'live') liveFrame(m);
    else if (m.column !== undefined) columnAnswer(m);
    else replayFrame(m);
  };
  ws.onclose = () => { $('counters').textContent += ' (viewer disconnected)'; };
}

window.addEventListener('resize', () => { resize(); render(); });
resize();
placeCamera();
connect();
