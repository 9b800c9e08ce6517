// ohrp view's plots (Chart.js from Debian's libjs-chart.js): joints (q and qref), the force
// sensors' Fz, the ZMP and any log column picked by name, against simulated time, with a cursor
// at the time shown; in a replay a click on a plot seeks (docs/view.md). Loaded before view.js,
// whose globals ($, params, stateEl, replay, seek) these functions use when called.
'use strict';

// ---------------- the plots (Chart.js), with a cursor at the time shown ----------------
let cursorT = null;
const cursorPlugin = {
  id: 'cursor',
  afterDatasetsDraw(chart) {
    if (cursorT === null) return;
    const x = chart.scales.x.getPixelForValue(cursorT), a = chart.chartArea;
    if (x < a.left || x > a.right) return;
    const ctx = chart.ctx;
    ctx.save(); ctx.strokeStyle = '#f44'; ctx.lineWidth = 1.5;
    ctx.beginPath(); ctx.moveTo(x, a.top); ctx.lineTo(x, a.bottom); ctx.stroke(); ctx.restore();
  },
};
Chart.defaults.color = '#ccd';
Chart.defaults.animation = false;
const palette = ['#4e79a7', '#f28e2b', '#59a14f', '#e15759', '#b07aa1', '#76b7b2'];

// replay: a click on a plot shows the robot at the clicked time (and pauses)
function clickToSeek(e, elements, chart) {
  if (!replay) return;
  const t = Math.min(replay.t1, Math.max(replay.t0, chart.scales.x.getValueForPixel(e.x)));
  replay.playing = false;
  $('play').textContent = 'play';
  $('slider').value = t;
  seek(t);
}

function makeChart(id, title, unit, labels) {
  return new Chart($(id), {
    type: 'line',
    data: {datasets: labels.map((l, i) => ({label: l, data: [], borderColor: palette[i % palette.length],
      borderDash: l.startsWith('ref ') ? [5, 3] : [], borderWidth: 1.5, pointRadius: 0}))},
    options: {responsive: true, maintainAspectRatio: false, parsing: false, normalized: true, onClick: clickToSeek,
      // small titles and legends: four panels share the height of a laptop's screen
      plugins: {title: {display: true, text: title, padding: 2, font: {size: 11}},
                legend: {labels: {boxWidth: 10, padding: 4, font: {size: 10}}}},
      scales: {x: {type: 'linear', title: {display: true, text: 't [s]', padding: 0, font: {size: 10}}},
               y: {title: {display: true, text: unit}}}},
    plugins: [cursorPlugin],
  });
}

let charts = null, plotJoints = [], jointIndex = [], columnNotes = [];
// a note under the plots: names that were asked for and cannot be plotted (never dropped silently)
function noteColumn(text) {
  columnNotes.push(text);
  $('column_note').textContent = columnNotes.join('; ');
}

function buildCharts(desc) {
  const all = desc.joints;
  const wanted = params.get('joints') ? params.get('joints').split(',').filter((j) => j)
    : ['RLEG_HIP_P', 'RLEG_KNEE', 'RLEG_ANKLE_P'].filter((j) => all.includes(j));
  plotJoints = wanted.filter((j) => all.includes(j));
  const unknown = wanted.filter((j) => !all.includes(j));
  if (unknown.length) noteColumn('no joint ' + unknown.map((j) => "'" + j + "'").join(', ') + ' in the robot');
  if (!plotJoints.length) plotJoints = all.slice(0, 3);
  jointIndex = plotJoints.map((j) => all.indexOf(j));
  charts = {
    q: makeChart('plot_q', 'joints: q (solid), qref (dashed)', '[rad]',
                 plotJoints.concat(plotJoints.map((j) => 'ref ' + j))),
    fz: makeChart('plot_fz', 'force sensors: Fz (ankles, wrists)', '[N]', desc.forces),
    zmp: makeChart('plot_zmp', 'ZMP', '[m]', ['zmp x', 'zmp y']),
    cols: makeChart('plot_cols', 'log columns (pick below)', '', []),
  };
}

// ---------------- the column picker: any log column by name ----------------
// replay: the server sends the column's min/max decimated curve, or says it has none; live: the
// frames' values by the log's names (q_J, qref_J, SENSOR_fz, zmp_x, zmp_y)
let columnNames = [], liveColumn = {};
function setupPicker(h) {
  if (h.mode === 'replay') {
    columnNames = h.columns.filter((c) => c !== 'time');
  } else {
    const d = h.scene;
    d.joints.forEach((j, i) => {
      liveColumn['q_' + j] = (f) => f.q[i];
      liveColumn['qref_' + j] = (f) => (f.qref ? f.qref[i] : null);
    });
    d.forces.forEach((n, i) => { liveColumn[n + '_fz'] = (f) => f.fz[i]; });
    liveColumn.zmp_x = (f) => (f.zmp ? f.zmp[0] : null);
    liveColumn.zmp_y = (f) => (f.zmp ? f.zmp[1] : null);
    columnNames = Object.keys(liveColumn);
  }
  $('column_list').innerHTML = columnNames.map((c) => '<option value="' + c + '">').join('');
  $('picker').onsubmit = (e) => {
    e.preventDefault();
    const name = $('column_name').value.trim();
    if (name) addColumn(name);
    $('column_name').value = '';
  };
  for (const name of (params.get('columns') || '').split(',')) if (name) addColumn(name);
}

function addColumn(name) {
  if (charts.cols.data.datasets.some((ds) => ds.label === name)) return;
  if (replay) { replay.ws.send(JSON.stringify({column: name})); return; }
  if (!liveColumn[name]) { noteColumn("no column '" + name + "' in the live frames"); return; }
  pushColumn(name, []);
}

function pushColumn(name, data) {
  const ds = charts.cols.data.datasets, i = ds.length;
  ds.push({label: name, data, borderColor: palette[i % palette.length], borderWidth: 1.5, pointRadius: 0});
  redrawCharts();
}

// replay: the server's answer to {column}
function columnAnswer(m) {
  if (m.error) { noteColumn(m.error); return; }
  pushColumn(m.column, m.t.map((x, i) => ({x, y: m.y[i]})).filter((p) => p.y !== null));
}

function redrawCharts() {
  for (const c of Object.values(charts)) c.update('none');
  let points = 0;
  for (const c of Object.values(charts)) for (const d of c.data.datasets) points += d.data.length;
  stateEl.dataset.points = points;
}

