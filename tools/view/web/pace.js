// How often the 3D view is drawn (docs/view.md "The page's cost to a real-time run"): at most
// ?fps= times a second (default 15; 1-60). Software rendering of the scene is most of what a
// page costs the machine (a headless Chromium drawing 30 times a second took 0.85 of a core, 15
// times 0.6), and on a two-core machine that time is taken from a real-time run. Loaded before
// view.js, whose render() draws through paceDraw.
'use strict';

const kDrawFps = Math.max(1, Math.min(60, Number(new URLSearchParams(location.search).get('fps') || 15)));
let lastDrawAt = -1e9;

// `draw` at the next browser frame at least 1 / kDrawFps after the last draw
function paceDraw(draw) {
  const go = () => requestAnimationFrame(() => { lastDrawAt = performance.now(); draw(); });
  const wait = lastDrawAt + 1000 / kDrawFps - performance.now();
  if (wait > 0) setTimeout(go, wait); else go();
}
