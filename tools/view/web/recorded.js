// ohrp view, replay: the cameras' images recorded in the run folder (sim_host --record-images,
// docs/view.md), each camera's latest image at or before the time shown, in the images panel.
// The hello's recorded_images: {cameras, frames: {camera: {t: [s], rgb: [file]}}} or {note}.
'use strict';

let recorded = null;  // {cameras, frames} of the run, or null

function setupRecorded(m) {
  const r = m.recorded_images || {};
  if (!r.cameras || r.cameras.length === 0) {
    $('cameras').textContent = r.note || 'no recorded images';
    return;
  }
  recorded = r;
  $('cameras').textContent = r.cameras.length + ' camera(s) recorded:';
  $('images').innerHTML = r.cameras.map((c, i) => '<figure><img id="recimg' + i + '" width="240" alt="' + c +
      '"><figcaption id="reccap' + i + '">' + c + '</figcaption></figure>').join('');
  $('images').style.display = 'flex';
}

// the index of the last time <= t in a sorted list (-1: none)
function lastAtOrBefore(times, t) {
  let lo = 0, hi = times.length - 1, at = -1;
  while (lo <= hi) {
    const mid = (lo + hi) >> 1;
    if (times[mid] <= t + 1e-9) { at = mid; lo = mid + 1; } else hi = mid - 1;
  }
  return at;
}

function showRecorded(t) {
  if (!recorded) return;
  recorded.cameras.forEach((c, i) => {
    const f = recorded.frames[c], k = lastAtOrBefore(f.t, t), img = $('recimg' + i);
    if (!img) return;
    const src = k < 0 ? '' : '/recorded/' + f.rgb[k];
    if (img.dataset.src !== src) {
      img.dataset.src = src;
      if (src) img.src = src; else img.removeAttribute('src');
      $('reccap' + i).textContent = c + (k < 0 ? ': none yet' : ': t = ' + f.t[k].toFixed(3) + ' s');
    }
    if (i === 0) { stateEl.dataset.recordedT = k < 0 ? -1 : f.t[k]; stateEl.dataset.recordedSrc = src; }
  });
}
