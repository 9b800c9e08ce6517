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

// the scene from the description: scene.js (buildScene)

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

// ---------------- live camera images: images.js (setupImages) ----------------

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
