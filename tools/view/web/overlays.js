// ohrp view's balance overlays in 3D (docs/view.md, "Balance in 3D"): the measured contact
// forces as arrows at the soles (1 mm per N, from each loaded foot's centre of pressure), the
// measured ZMP as a red disc on the floor, the centre of mass (yellow ball) and its ground
// projection, and the support polygon (the convex hull of the loaded soles' bottom corners,
// green). Each has a box in the top bar; one whose log columns are missing is greyed out with a
// note naming them. The server sends each frame's "zmp" and "balance" (geometry.h, Balance).
// Loaded after plots.js, before view.js, whose globals (scene3, render, $, stateEl) these use
// when called. window.ohrpOverlay.state() reads back what is drawn (for tests).
'use strict';

const kArrowMPerN = 0.001;  // arrow length per newton of force [m/N]
const overlayNames = {forces: 'contact forces', zmp: 'ZMP', com: 'CoM', polygon: 'support polygon'};
const ov = {group: null, arrows: [], zmp: null, com: null, comGround: null, comLine: null,
            polygon: null, polygonLine: null, missing: {}};

// the log columns each overlay needs (replay), by sole sensor S; live frames always have them
function overlayNeeds(soles) {
  const per = (axes) => soles.flatMap((s) => axes.map((a) => s + '_' + a));
  return {
    forces: per(['fx', 'fy', 'fz']),
    zmp: per(['fz', 'tx', 'ty']),
    com: ['base_x', 'base_y', 'base_z', 'base_qw', 'base_qx', 'base_qy', 'base_qz'],
    polygon: per(['fz']),
  };
}

// on top of the robot (an arrow from the sole runs up through the foot and shin)
function overlayMaterial(color, extra) {
  return Object.assign({color, depthTest: false, transparent: true}, extra || {});
}

function setupOverlays(hello) {
  const soles = hello.scene.soles || [];
  const needs = overlayNeeds(soles);
  for (const k of Object.keys(needs)) {
    ov.missing[k] = hello.mode === 'replay' ? needs[k].filter((c) => !hello.columns.includes(c)) : [];
    if (!soles.length && k !== 'com') ov.missing[k] = ['a force sensor under a *_SOLE geom'];
  }
  ov.group = new THREE.Group();
  ov.group.renderOrder = 10;
  scene3.add(ov.group);
  // the arrows, one per sole sensor
  ov.arrows = soles.map((s) => {
    const a = new THREE.ArrowHelper(new THREE.Vector3(0, 0, 1), new THREE.Vector3(), 0.1, 0xff3030, 0.04, 0.025);
    a.line.material = new THREE.LineBasicMaterial(overlayMaterial(0xff3030));
    a.cone.material = new THREE.MeshBasicMaterial(overlayMaterial(0xff3030));
    a.userData.sensor = s;
    a.visible = false;
    ov.group.add(a);
    return a;
  });
  const disc = (r, color) => {
    const g = new THREE.CircleBufferGeometry(r, 24);
    const m = new THREE.Mesh(g, new THREE.MeshBasicMaterial(overlayMaterial(color, {side: THREE.DoubleSide})));
    m.visible = false;
    ov.group.add(m);
    return m;
  };
  ov.zmp = disc(0.025, 0xff2020);
  ov.comGround = disc(0.018, 0xffd000);
  ov.com = new THREE.Mesh(new THREE.SphereBufferGeometry(0.03, 16, 10), new THREE.MeshBasicMaterial(overlayMaterial(0xffd000)));
  ov.com.visible = false;
  ov.group.add(ov.com);
  ov.comLine = new THREE.Line(new THREE.BufferGeometry().setFromPoints([new THREE.Vector3(), new THREE.Vector3()]),
                              new THREE.LineBasicMaterial(overlayMaterial(0xffd000)));
  ov.comLine.visible = false;
  ov.group.add(ov.comLine);
  ov.polygon = new THREE.Mesh(new THREE.BufferGeometry(), new THREE.MeshBasicMaterial(
      overlayMaterial(0x30e060, {opacity: 0.35, side: THREE.DoubleSide})));
  ov.polygonLine = new THREE.LineLoop(new THREE.BufferGeometry(), new THREE.LineBasicMaterial(overlayMaterial(0x30e060)));
  ov.polygon.visible = ov.polygonLine.visible = false;
  ov.group.add(ov.polygon, ov.polygonLine);
  // the boxes: greyed out (and unticked) with a note when the log lacks a column
  const notes = [];
  $('overlays').innerHTML = Object.keys(overlayNames).map((k) =>
    '<label id="ov_label_' + k + '"><input id="ov_' + k + '" type="checkbox"> ' + overlayNames[k] + '</label>').join(' ');
  for (const k of Object.keys(overlayNames)) {
    const box = $('ov_' + k), miss = ov.missing[k];
    box.checked = !miss.length;
    box.disabled = miss.length > 0;
    if (miss.length) {
      $('ov_label_' + k).className = 'off';
      $('ov_label_' + k).title = 'missing: ' + miss.join(', ');
      notes.push(overlayNames[k] + ': no ' + miss.slice(0, 3).join(', ') + (miss.length > 3 ? ' (+' + (miss.length - 3) + ')' : '') + ' in the log');
    }
    box.onchange = () => { applyOverlay(lastOverlayFrame); render(); };
  }
  $('overlay_note').textContent = notes.join('; ');
}

let lastOverlayFrame = null;

// places the overlays for a frame ({zmp, balance}); called by showFrame
function applyOverlay(f) {
  if (!ov.group || !f) return;
  lastOverlayFrame = f;
  const on = (k) => $('ov_' + k).checked;
  const b = f.balance || {feet: [], com: null};
  const feet = new Map((b.feet || []).map((ft) => [ft.sensor, ft]));
  for (const a of ov.arrows) {
    const ft = feet.get(a.userData.sensor);
    const n = ft ? Math.hypot(...ft.f) : 0;
    a.visible = on('forces') && !!ft && ft.loaded && n > 0;
    if (!a.visible) continue;
    a.position.set(...ft.cop);
    a.setDirection(new THREE.Vector3(...ft.f).normalize());
    const len = n * kArrowMPerN;
    a.setLength(len, Math.min(0.04, 0.3 * len), Math.min(0.025, 0.2 * len));
  }
  ov.zmp.visible = on('zmp') && !!f.zmp;
  if (ov.zmp.visible) ov.zmp.position.set(f.zmp[0], f.zmp[1], 0.002);
  const com = b.com;
  ov.com.visible = ov.comGround.visible = ov.comLine.visible = on('com') && !!com;
  if (com) {
    ov.com.position.set(...com);
    ov.comGround.position.set(com[0], com[1], 0.003);
    ov.comLine.geometry.setFromPoints([new THREE.Vector3(...com), new THREE.Vector3(com[0], com[1], 0.003)]);
  }
  const hull = convexHull((b.feet || []).filter((ft) => ft.loaded).flatMap((ft) => ft.corners));
  ov.polygon.visible = ov.polygonLine.visible = on('polygon') && hull.length >= 3;
  if (ov.polygon.visible) {
    const pts = hull.map((p) => new THREE.Vector3(p[0], p[1], p[2] + 0.001));
    ov.polygonLine.geometry.setFromPoints(pts);
    const fan = [];
    for (let i = 1; i + 1 < pts.length; ++i) fan.push(pts[0], pts[i], pts[i + 1]);
    ov.polygon.geometry.setFromPoints(fan);
  }
  ov.hull = hull;
}

// the convex hull (x, y) of points [x, y, z], counter-clockwise (Andrew's monotone chain);
// each kept point keeps its z
function convexHull(points) {
  const p = points.slice().sort((a, b) => a[0] - b[0] || a[1] - b[1]);
  if (p.length < 3) return p;
  const cross = (o, a, b) => (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
  const half = (list) => {
    const h = [];
    for (const q of list) {
      while (h.length >= 2 && cross(h[h.length - 2], h[h.length - 1], q) <= 0) h.pop();
      h.push(q);
    }
    h.pop();
    return h;
  };
  return half(p).concat(half(p.slice().reverse()));
}

// for tests and scripts: what is drawn, read back from the three.js objects
window.ohrpOverlay = {
  state() {
    const v = (o) => [o.position.x, o.position.y, o.position.z];
    if (ov.group) ov.group.updateMatrixWorld(true);
    return {
      enabled: Object.fromEntries(Object.keys(overlayNames).map((k) => [k, $('ov_' + k) ? $('ov_' + k).checked : false])),
      missing: ov.missing,
      arrows: ov.arrows.map((a) => {
        const tip = a.localToWorld(a.cone.position.clone());
        return {sensor: a.userData.sensor, visible: a.visible, origin: v(a), tip: [tip.x, tip.y, tip.z],
                length: a.position.distanceTo(tip)};
      }),
      zmp: ov.zmp && ov.zmp.visible ? v(ov.zmp) : null,
      com: ov.com && ov.com.visible ? v(ov.com) : null,
      comGround: ov.comGround && ov.comGround.visible ? v(ov.comGround) : null,
      polygon: ov.polygon && ov.polygon.visible ? ov.hull.map((p) => [p[0], p[1]]) : null,
    };
  },
};
