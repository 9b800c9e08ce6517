// ohrp view's reach plan in 3D (docs/view.md, "The reach plan in 3D"), from reach's plan.csv in
// a replayed run folder (tools/view/src/replay_reach.cc): each goal's planned motion as the
// paths of the group's hands (green lines, the waypoints as dots), placed where the robot stood
// when that motion began; the goal under way (or the next one) bright, the others dim. One box
// in the top bar ("reach plan"); without plan.csv (or live: reach writes it when it ends) the box
// is greyed out with the reason. The server sends hello.reach ({goals, hands} or {note}) once.
// Loaded after overlays.js (overlayMaterial), before view.js (scene3, render, $).
// window.ohrpReach.state() reads back what is drawn (for tests).
'use strict';

const rp = {group: null, goals: [], note: '', current: -1};

function setupReach(hello) {
  const r = hello.reach || {note: 'no reach plan from the server'};
  rp.note = r.note || '';
  rp.group = new THREE.Group();
  rp.group.renderOrder = 12;
  scene3.add(rp.group);
  rp.goals = (r.goals || []).map((g) => {
    const lines = g.paths.map((path) => {
      const pts = path.map((p) => new THREE.Vector3(p[0], p[1], p[2]));
      const line = new THREE.Line(new THREE.BufferGeometry().setFromPoints(pts),
                                  new THREE.LineBasicMaterial(overlayMaterial(0x30e060)));
      rp.group.add(line);
      return line;
    });
    const dots = [];
    for (const way of g.waypoints) {
      for (const p of way) {
        const dot = new THREE.Mesh(new THREE.SphereBufferGeometry(0.008, 10, 8),
                                   new THREE.MeshBasicMaterial(overlayMaterial(0x30e060)));
        dot.position.set(p[0], p[1], p[2]);
        rp.group.add(dot);
        dots.push(dot);
      }
    }
    return {goal: g, lines, dots};
  });
  const span = document.createElement('span');
  span.innerHTML = ' <label id="rp_label"><input id="rp_show" type="checkbox"> reach plan</label>';
  $('plan_overlays').appendChild(span);
  const box = $('rp_show');
  box.checked = rp.goals.length > 0;
  box.disabled = rp.goals.length === 0;
  if (box.disabled) {
    $('rp_label').className = 'off';
    $('rp_label').title = rp.note;
  }
  box.onchange = () => { applyReach(rp.last); render(); };
}

// the goal under way at t bright (else the next to come), the others dim
function applyReach(f) {
  if (!rp.group || !f) return;
  rp.last = f;
  const on = $('rp_show') && $('rp_show').checked;
  let current = rp.goals.findIndex((g) => f.t >= g.goal.t_start && f.t <= g.goal.t_end);
  if (current < 0) current = rp.goals.findIndex((g) => g.goal.t_start > f.t);
  rp.current = current;
  rp.goals.forEach((g, i) => {
    const opacity = i === current ? 1 : 0.3;
    for (const o of g.lines.concat(g.dots)) {
      o.visible = on;
      o.material.opacity = opacity;
    }
  });
}

window.ohrpReach = {
  state() {
    return {
      enabled: $('rp_show') ? $('rp_show').checked : false,
      disabled: $('rp_show') ? $('rp_show').disabled : true,
      note: rp.note,
      current: rp.current,
      goals: rp.goals.map((g) => ({goal: g.goal.goal, t_start: g.goal.t_start, t_end: g.goal.t_end,
                                   visible: g.lines.length > 0 && g.lines[0].visible,
                                   first: g.goal.paths.map((p) => p[0]),
                                   last: g.goal.paths.map((p) => p[p.length - 1])})),
    };
  },
};
