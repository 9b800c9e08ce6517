// ohrp view --control, by the mouse in the 3D view (docs/view.md "Control from the page"):
// - a press on a body picks it for the push; dragging from it sets the push: the drag in the
//   camera's plane through the point pressed (the arrow follows the mouse) is the force's
//   direction, its length the impulse (kPushNsPerM, at most kPushMaxNs), given over 0.1 s;
//   the release sends it to sim_host (a press without a drag only picks the body);
// - Ctrl + click on the floor (the plane z = 0) sends walk a goal there, facing along the way
//   from the feet; Ctrl + drag from the point sets the heading (the drag's direction on the
//   floor). The goal goes as `goal_now X Y YAW_DEG` in the frame of the feet's middle as the last
//   frame shows them (walk re-plans it from the stance after the step under way).
// A press elsewhere turns or pans the camera as before (view.js).
'use strict';

const kPushNsPerM = 100;   // impulse per metre of drag [N s / m]
const kPushMaxNs = 150;    // the largest impulse a drag gives [N s]
const kGoalMinDrag = 0.05; // a shorter Ctrl-drag is a click: facing along the way [m]
const kDragPixels = 4;     // a press that moves less is a click [px]

let bench = null;          // the drag under way: {kind: 'push' | 'goal', ...}
let benchArrow = null;     // what the drag draws

function benchRay(e) {
  const r = canvas.getBoundingClientRect();
  const ndc = new THREE.Vector2(2 * (e.clientX - r.left) / r.width - 1, 1 - 2 * (e.clientY - r.top) / r.height);
  placeCamera();
  camera.updateMatrixWorld();
  const ray = new THREE.Raycaster();
  ray.setFromCamera(ndc, camera);
  return ray;
}

function onPlane(ray, plane) {
  const p = new THREE.Vector3();
  return ray.ray.intersectPlane(plane, p) ? p : null;
}

// the middle of the soles in the last frame (their bottom corners, balance.feet) and their mean
// heading (each sole's x axis): {x, y, yaw}, or null without two soles
function feetNow() {
  const f = typeof lastOverlayFrame !== 'undefined' ? lastOverlayFrame : null;
  const soles = ((f && f.balance && f.balance.feet) || []).filter((s) => s.corners && s.corners.length === 4);
  if (soles.length < 2) return null;
  let x = 0, y = 0, cx = 0, cy = 0;
  for (const s of soles) {
    const c = s.corners;  // (+x,+y), (+x,-y), (-x,-y), (-x,+y) in the sole's frame
    x += (c[0][0] + c[1][0] + c[2][0] + c[3][0]) / 4;
    y += (c[0][1] + c[1][1] + c[2][1] + c[3][1]) / 4;
    const yaw = Math.atan2(c[0][1] + c[1][1] - c[2][1] - c[3][1], c[0][0] + c[1][0] - c[2][0] - c[3][0]);
    cx += Math.cos(yaw); cy += Math.sin(yaw);
  }
  return {x: x / soles.length, y: y / soles.length, yaw: Math.atan2(cy, cx)};
}

// `goal_now X Y YAW_DEG` for a world point and heading, in the frame of the feet now
function goalLine(p, heading) {
  const m = feetNow();
  if (!m) return null;
  const dx = p.x - m.x, dy = p.y - m.y, c = Math.cos(m.yaw), s = Math.sin(m.yaw);
  if (heading === null) heading = Math.hypot(dx, dy) > 1e-6 ? Math.atan2(dy, dx) : m.yaw;
  const turn = Math.atan2(Math.sin(heading - m.yaw), Math.cos(heading - m.yaw));
  return 'goal_now ' + (c * dx + s * dy).toFixed(3) + ' ' + (-s * dx + c * dy).toFixed(3) + ' ' +
         (turn * 180 / Math.PI).toFixed(1);
}

function drawArrow(from, to, color) {
  if (!benchArrow) {
    benchArrow = new THREE.ArrowHelper(new THREE.Vector3(1, 0, 0), new THREE.Vector3(), 1, color);
    benchArrow.renderOrder = 10;
    scene3.add(benchArrow);
  }
  benchArrow.setColor(new THREE.Color(color));
  const d = new THREE.Vector3().subVectors(to, from), len = d.length();
  benchArrow.visible = len > 1e-4;
  if (benchArrow.visible) {
    benchArrow.position.copy(from);
    benchArrow.setDirection(d.normalize());
    benchArrow.setLength(len, Math.min(0.08, 0.3 * len), Math.min(0.05, 0.2 * len));
  }
  render();
}

// the push a drag from `start` to `end` gives: the force over kPushSeconds (control.js)
function pushOfDrag(body, start, end) {
  const d = new THREE.Vector3().subVectors(end, start);
  const impulse = Math.min(kPushMaxNs, kPushNsPerM * d.length());
  const f = d.lengthSq() > 0 ? d.normalize().multiplyScalar(impulse / kPushSeconds) : d;
  return {impulse, line: 'push ' + body + ' ' + f.x.toFixed(3) + ' ' + f.y.toFixed(3) + ' ' +
                         f.z.toFixed(3) + ' ' + kPushSeconds};
}

function benchDown(e, can) {
  stateEl.dataset.benchPress = 'none';  // for tests: what the last press started
  if (e.button !== 0 || e.target !== canvas) return;
  const ray = benchRay(e);
  if (e.ctrlKey && can.walk) {
    const p = onPlane(ray, new THREE.Plane(new THREE.Vector3(0, 0, 1), 0));
    if (!p) return;
    bench = {kind: 'goal', start: p, x: e.clientX, y: e.clientY};
  } else if (can.sim && !e.ctrlKey) {
    const hit = ray.intersectObjects(moving.filter((o) => o), true)[0];
    if (!hit) return;  // not on the robot: the camera turns (view.js)
    let o = hit.object;
    while (o && moving.indexOf(o) < 0) o = o.parent;
    if (!o || !o.userData.body) return;
    $('push_body').value = o.userData.body;
    const normal = new THREE.Vector3();
    camera.getWorldDirection(normal);
    bench = {kind: 'push', body: o.userData.body, start: hit.point.clone(), x: e.clientX, y: e.clientY,
             plane: new THREE.Plane().setFromNormalAndCoplanarPoint(normal, hit.point)};
  } else {
    return;
  }
  stateEl.dataset.benchPress = bench.kind;
  e.stopPropagation();  // the camera stays
  e.preventDefault();
}

function benchMove(e) {
  if (!bench) return;
  e.stopPropagation();
  const moved = Math.abs(e.clientX - bench.x) + Math.abs(e.clientY - bench.y) > kDragPixels;
  const ray = benchRay(e);
  if (bench.kind === 'push') {
    const p = onPlane(ray, bench.plane);
    if (!p || !moved) return;
    bench.end = p;
    drawArrow(bench.start, p, 0xff3030);
    $('control_reply').textContent = pushOfDrag(bench.body, bench.start, p).impulse.toFixed(1) + ' N s on ' + bench.body;
  } else {
    const p = onPlane(ray, new THREE.Plane(new THREE.Vector3(0, 0, 1), 0));
    if (!p || !moved) return;
    bench.end = p;
    drawArrow(bench.start.clone().setZ(0.01), p.clone().setZ(0.01), 0x30c0ff);
  }
}

function benchUp(e) {
  if (!bench) return;
  e.stopPropagation();
  const b = bench;
  bench = null;
  if (benchArrow) { benchArrow.visible = false; render(); }
  if (b.kind === 'push') {
    if (!b.end) return;  // a click: the body is picked, nothing is sent
    const push = pushOfDrag(b.body, b.start, b.end);
    stateEl.dataset.dragPush = push.line;
    sendControl('sim', push.line);
    return;
  }
  const d = b.end ? new THREE.Vector3().subVectors(b.end, b.start) : null;
  const heading = d && Math.hypot(d.x, d.y) > kGoalMinDrag ? Math.atan2(d.y, d.x) : null;
  const line = goalLine(b.start, heading);
  if (!line) {
    $('control_reply').textContent = 'goal: no soles in the frame to start from';
    $('control_reply').className = 'warn';
    return;
  }
  stateEl.dataset.goalLine = line;
  stateEl.dataset.goalPoint = JSON.stringify([b.start.x, b.start.y, heading]);
  sendControl('walk', line);
}

// control.js calls it once the panel is up
function setupWorkbench(can) {
  window.addEventListener('mousedown', (e) => benchDown(e, can), true);  // before view.js's
  window.addEventListener('mousemove', benchMove, true);
  window.addEventListener('mouseup', benchUp, true);
}
