// ohrp view's walk-plan overlays in 3D (docs/view.md, "The walk's plan in 3D"), from the walk
// controller's walk.csv in a replayed run folder (tools/view/src/plan.cc): the desired ZMP (a
// magenta disc), the DCM (the stabilizer's: a cyan ring; the plan's capture point, from the CoM
// reference and its velocity: a cyan disc) and the footstep plan (every planned sole rectangle:
// left blue, right orange; the ones already landed dim, the supporting ones and the next landing
// bright). Each has a box in the top bar; without walk.csv (or live: walk.csv is written when
// the walk ends) or without its columns a box is greyed out with the reason. The server sends
// hello.plan ({footsteps, missing} or {note}) once and each frame's "plan" ({zmp_des, dcm, cp,
// support}). Loaded after overlays.js (overlayMaterial), before view.js (scene3, render, $).
// window.ohrpPlan.state() reads back what is drawn (for tests).
'use strict';

const planNames = {desired_zmp: 'desired ZMP', dcm: 'DCM', footsteps: 'footsteps'};
const pl = {group: null, zmpDes: null, dcm: null, cp: null, steps: [], missing: {}, last: null, next: -1};

function setupPlan(hello) {
  const p = hello.plan || {note: 'no plan from the server'};
  for (const k of Object.keys(planNames)) pl.missing[k] = p.note ? [p.note] : (p.missing[k] || []);
  pl.group = new THREE.Group();
  pl.group.renderOrder = 11;
  scene3.add(pl.group);
  const flat = (geo, color, opacity) => {
    const m = new THREE.Mesh(geo, new THREE.MeshBasicMaterial(overlayMaterial(color, {side: THREE.DoubleSide, opacity: opacity || 1})));
    m.visible = false;
    pl.group.add(m);
    return m;
  };
  pl.zmpDes = flat(new THREE.CircleBufferGeometry(0.02, 24), 0xff30ff);
  pl.cp = flat(new THREE.CircleBufferGeometry(0.018, 24), 0x20e0ff);
  pl.dcm = flat(new THREE.RingBufferGeometry(0.026, 0.036, 24), 0x20e0ff);
  // the footsteps: an outline and a translucent fill per planned sole
  pl.steps = (p.footsteps || []).map((s) => {
    const color = s.side === 'left' ? 0x3080ff : 0xff9020;
    const pts = s.corners.map((c) => new THREE.Vector3(c[0], c[1], c[2] + 0.004));
    const line = new THREE.LineLoop(new THREE.BufferGeometry().setFromPoints(pts),
                                    new THREE.LineBasicMaterial(overlayMaterial(color)));
    const fill = flat(new THREE.BufferGeometry().setFromPoints([pts[0], pts[1], pts[2], pts[0], pts[2], pts[3]]), color, 0.35);
    line.visible = false;
    pl.group.add(line);
    return {step: s, line, fill};
  });
  $('plan_overlays').innerHTML = Object.keys(planNames).map((k) =>
    '<label id="pl_label_' + k + '"><input id="pl_' + k + '" type="checkbox"> ' + planNames[k] + '</label>').join(' ');
  const notes = [];
  for (const k of Object.keys(planNames)) {
    const box = $('pl_' + k), miss = pl.missing[k];
    box.checked = !miss.length;
    box.disabled = miss.length > 0;
    if (miss.length) {
      $('pl_label_' + k).className = 'off';
      $('pl_label_' + k).title = p.note ? p.note : 'missing in walk.csv: ' + miss.join(', ');
      if (!p.note) notes.push(planNames[k] + ': no ' + miss.slice(0, 3).join(', ') + (miss.length > 3 ? ' (+' + (miss.length - 3) + ')' : '') + ' in walk.csv');
    }
    box.onchange = () => { applyPlan(pl.last); render(); };
  }
  if (p.note) notes.push('walk plan: ' + p.note.split(' (')[0]);  // the whole note on hover
  $('plan_note').textContent = notes.join('; ');
}

// places the plan overlays for a frame (its "plan": null before the walk's first row)
function applyPlan(f) {
  if (!pl.group || !f) return;
  pl.last = f;
  const on = (k) => $('pl_' + k).checked;
  const p = f.plan || null;
  const place = (obj, xyz, shown) => {
    obj.visible = shown && !!xyz;
    if (obj.visible) obj.position.set(xyz[0], xyz[1], xyz[2] + 0.005);
  };
  place(pl.zmpDes, p && p.zmp_des, on('desired_zmp'));
  place(pl.dcm, p && p.dcm, on('dcm'));
  place(pl.cp, p && p.cp, on('dcm'));
  // the footsteps: landed before t dim, the next landing and the soles that support now bright
  pl.next = pl.steps.findIndex((s) => s.step.t > f.t);
  const current = {};  // per side, the last step landed by t
  pl.steps.forEach((s, i) => { if (s.step.t <= f.t) current[s.step.side] = i; });
  const sup = p && p.support ? {left: p.support[0], right: p.support[1]} : {left: true, right: true};
  pl.steps.forEach((s, i) => {
    const bright = i === pl.next || (current[s.step.side] === i && sup[s.step.side]);
    s.line.visible = on('footsteps');
    s.line.material.opacity = bright || s.step.t > f.t ? 1 : 0.35;
    s.fill.visible = on('footsteps') && bright;
    s.bright = bright;
  });
}

// for tests and scripts: what is drawn, read back from the three.js objects
window.ohrpPlan = {
  state() {
    const v = (o) => (o && o.visible ? [o.position.x, o.position.y, o.position.z] : null);
    return {
      enabled: Object.fromEntries(Object.keys(planNames).map((k) => [k, $('pl_' + k) ? $('pl_' + k).checked : false])),
      missing: pl.missing,
      note: $('plan_note') ? $('plan_note').textContent : '',
      zmpDes: v(pl.zmpDes), dcm: v(pl.dcm), cp: v(pl.cp),
      next: pl.next,
      steps: pl.steps.map((s) => ({side: s.step.side, t: s.step.t, visible: s.line.visible, bright: !!s.bright,
                                   corners: s.step.corners, center: s.step.center, yaw: s.step.yaw})),
    };
  },
};
