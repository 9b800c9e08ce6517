// How often the 3D view is drawn (docs/view.md "The page's cost to a real-time run"). Software
// rendering of the scene is most of what a page costs the machine (a headless Chromium drawing
// 30 times a second took 0.85 of a core, 15 times 0.65, 5 times 0.4; a walk still had 1.3x the
// late commands with a page drawing 5 times a second), and on a two-core machine
// that time is taken from a real-time run. So a live page draws at most 5 times a second
// (?fps=N for 1-60), and at up to 60 while the mouse moves the camera, drags or turns the wheel
// (and 0.5 s after); a replay draws at up to 60. Loaded before view.js, whose render() draws
// through paceDraw.
'use strict';

const kAskedFps = Number(new URLSearchParams(location.search).get('fps') || 0);
const kLiveFps = 5;
let lastDrawAt = -1e9, paceTimer = null, paceFn = null, interactingUntil = 0;

function drawFps() {
  if (performance.now() < interactingUntil) return 60;
  const replaying = typeof replay !== 'undefined' && replay;
  return Math.max(1, Math.min(60, kAskedFps || (replaying ? 60 : kLiveFps)));
}

function paceGo() {
  paceTimer = null;
  requestAnimationFrame(() => { lastDrawAt = performance.now(); paceFn(); });
}

// `draw` at the next browser frame at least 1 / drawFps() after the last draw
function paceDraw(draw) {
  paceFn = draw;
  if (paceTimer !== null) return;
  const wait = lastDrawAt + 1000 / drawFps() - performance.now();
  if (wait > 0) paceTimer = setTimeout(paceGo, wait); else paceGo();
}

// the user moves the view: draw at once, and briskly for a while
function paceInteract(e) {
  if (e.type === 'mousemove' && !e.buttons) return;
  interactingUntil = performance.now() + 500;
  if (paceTimer !== null) { clearTimeout(paceTimer); paceGo(); }
}
for (const type of ['mousedown', 'mousemove', 'wheel', 'keydown']) window.addEventListener(type, paceInteract, true);
