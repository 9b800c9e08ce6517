// ohrp view --control (docs/view.md "Control from the page"): buttons that pause, resume, step
// and reset the simulation, a push on a body (picked in the list or by clicking it in the 3D
// view; direction and impulse), and walk commands from on-screen arrows, the keyboard and a game
// pad (the browser's Gamepad API, polled). Each request carries the run's token (?token= in the
// URL) to /control; the server forwards the line to sim_host's or walk's socket and returns its
// one reply line, shown here. Without a token in the URL the panel stays hidden.
'use strict';

const controlToken = params.get('token');
let controlQueue = Promise.resolve();

// one line to 'sim' or 'walk', in order (the sockets take one client at a time)
function sendControl(to, line) {
  controlQueue = controlQueue.then(async () => {
    const url = '/control?token=' + encodeURIComponent(controlToken) + '&to=' + to +
                '&line=' + encodeURIComponent(line);
    let text;
    try {
      const r = await fetch(url);
      text = (r.ok ? '' : r.status + ' ') + (await r.text()).trim();
    } catch (e) {
      text = 'error: ' + e;
    }
    $('control_reply').textContent = to + ': ' + line + ' -> ' + text;
    $('control_reply').className = text.startsWith('ok') ? '' : 'warn';
    stateEl.dataset.controlReplies = Number(stateEl.dataset.controlReplies || 0) + 1;
    stateEl.dataset.controlReply = text;
  });
  return controlQueue;
}

// the push: the body's name, the horizontal direction [deg, 0 = +x, 90 = +y], the impulse [N s]
// given over 0.1 s of simulated time
const kPushSeconds = 0.1;
function pushLine() {
  const body = $('push_body').value;
  const dir = Number($('push_dir').value) * Math.PI / 180, impulse = Number($('push_impulse').value);
  const f = impulse / kPushSeconds;
  return 'push ' + body + ' ' + (f * Math.cos(dir)).toFixed(3) + ' ' + (f * Math.sin(dir)).toFixed(3) +
         ' 0 ' + kPushSeconds;
}

// walk: the velocity a key or an arrow asks for [m/s, m/s, deg/s]; stop closes the feet
const kWalk = {
  forward: 'velocity 0.2 0 0', back: 'velocity -0.1 0 0', left: 'velocity 0 0 15',
  right: 'velocity 0 0 -15', stop: 'stop',
};
const kKeys = {
  ArrowUp: 'forward', w: 'forward', ArrowDown: 'back', s: 'back', ArrowLeft: 'left', a: 'left',
  ArrowRight: 'right', d: 'right', ' ': 'stop',
};
let lastWalk = '';
function walk(what) {
  const line = kWalk[what];
  if (line === lastWalk && what !== 'stop') return;  // a held key repeats: sent once
  lastWalk = line;
  sendControl('walk', line);
}

function setupControl(hello) {
  if (!controlToken || hello.mode !== 'live') return;
  fetch('/control?token=' + encodeURIComponent(controlToken)).then((r) => r.json()).then((can) => {
    const panel = $('control');
    panel.hidden = false;
    const bodies = [...new Set(hello.scene.moving.map((g) => g.body).filter((b) => b))];
    let html = '';
    if (can.sim) {
      html += '<button id="c_pause">pause</button><button id="c_resume">resume</button>' +
        '<button id="c_step">step</button><button id="c_reset">reset</button> ' +
        'push <select id="push_body">' + bodies.map((b) => '<option>' + b + '</option>').join('') +
        '</select> dir <input id="push_dir" value="0" size="3"> deg, <input id="push_impulse" value="10" ' +
        'size="3"> N s <button id="c_push">push</button> (or drag on a body) ';
    }
    if (can.walk) {
      html += 'walk <button id="w_left">&#8630;</button><button id="w_forward">&#8593;</button>' +
        '<button id="w_back">&#8595;</button><button id="w_right">&#8631;</button>' +
        '<button id="w_stop">stop</button> (keys: arrows / WASD, space stops; a game pad; ' +
        'Ctrl-click the floor: a goal, Ctrl-drag: its heading) ';
    }
    panel.innerHTML = html + '<span id="control_reply"></span>';
    if (can.sim) {
      for (const c of ['pause', 'resume', 'step', 'reset']) $('c_' + c).onclick = () => sendControl('sim', c);
      $('c_push').onclick = () => sendControl('sim', pushLine());
    }
    if (can.walk) {
      for (const w of Object.keys(kWalk)) $('w_' + w).onclick = () => walk(w);
      window.addEventListener('keydown', (e) => {
        if (e.target.tagName === 'INPUT') return;
        const what = kKeys[e.key];
        if (!what) return;
        walk(what);
        e.preventDefault();
      });
      setInterval(pollGamepad, 100);
    }
    setupWorkbench(can);  // the mouse in the 3D view: drag a body to push, Ctrl-click a goal
    stateEl.dataset.control = 'ready';
  });
}

// the game pad: left stick forward/back and turn, sent when the rounded command changes;
// button 1 stops. (Headless browsers have no game pads: view_control_test gives the page a fake
// navigator.getGamepads before its scripts run.)
let padLine = '';
function pollGamepad() {
  const pads = navigator.getGamepads ? navigator.getGamepads() : [];
  const pad = [...pads].find((p) => p);
  if (!pad) return;
  const dead = (v) => (Math.abs(v) < 0.2 ? 0 : v);
  const vx = -dead(pad.axes[1] || 0) * 0.2, wz = -dead(pad.axes[0] || 0) * 15;
  let line = 'velocity ' + vx.toFixed(2) + ' 0 ' + wz.toFixed(0);
  if (vx === 0 && wz === 0) line = 'stop';
  if (pad.buttons[1] && pad.buttons[1].pressed) line = 'stop';
  if (line === padLine) return;
  padLine = line;
  lastWalk = line;
  sendControl('walk', line);
}
