// isorad view: the page. Holds the streamed solution (hello, mesh, light,
// status), draws it when something changed, and publishes the test hooks
// on window.isorad.

import { connect, control, probe } from './connection.js';
import { createRenderer, boundsGeometry, boundsOf, project } from './renderer.js';
import { createNavigation, helloCamera } from './navigation.js';
import { castRay, pixelRay } from './picking.js';
import { createUi } from './ui.js';

/** Quiet time after a "done" status before the page calls itself settled, ms. */
const SETTLE_QUIET_MS = 300;

const canvas = document.getElementById('view');

/** The solution as received. */
const state = {
  hello: null,
  status: null,
  mesh: null,
  /** A light for a mesh version not (yet) held. */
  pendingLight: null,
  centre: [0, 0, 0],
  diagonal: 1,
  /** Scene units in a metre: 1, or 1000 for a scene modelled in millimetres. */
  unitsPerMetre: 1,
  /** Whether the mesh held has a light uploaded. */
  meshLit: false,
  /** Lights applied so far (never reset), and the count at the last draw. */
  lightSerial: 0,
  drawnSerial: 0,
  /** lightSerial when the first "done" status arrived, and when. */
  doneSerial: null,
  doneTime: 0,
  /** Whether the "loading" message is up. */
  loadingShown: false,
  /** The probed point and its normal, for the marker. */
  probePoint: null,
  probeSerial: 0,
};

/** The test hooks. */
const hooks = {
  status: null,
  hello: null,
  meshVersion: null,
  lightApplied: false,
  framesDrawn: 0,
  lastProbe: null,
  settled: false,
  /** The current camera: eye, target, up, vfov_deg, mode. */
  get camera() {
    const c = navigation.camera;
    return c && { eye: c.eye, target: c.target, up: c.up, vfov_deg: c.vfov, mode: navigation.mode };
  },
  /** The canvas as a PNG data URL (the last frame drawn). */
  canvasDataURL() {
    return canvas.toDataURL('image/png');
  },
};
window.isorad = hooks;

const ui = createUi({
  changed: redraw,
  control: (action) => control(action).catch((e) => ui.message(String(e.message || e))),
  savePng,
  toggleMode: () => navigation.toggleMode(),
  home: () => navigation.home(),
});

let renderer = null;
try {
  renderer = createRenderer(canvas);
} catch (e) {
  ui.message(`Cannot draw: ${e.message}`, 0);
}

const navigation = createNavigation(canvas, {
  mesh: () => state.mesh,
  diagonal: () => state.diagonal,
  unitsPerMetre: () => state.unitsPerMetre,
  changed: redraw,
  click: probeAt,
  modeChanged: (mode) => ui.showMode(mode),
});
ui.showMode(navigation.mode);
ui.showConnection(false);

// ---- drawing -------------------------------------------------------------

let pending = null;
let lastTime = null;

/**
 * Asks for a frame: on the next animation frame, or after 100 ms when
 * animation frames do not come (a hidden page); one frame per request.
 */
function redraw() {
  if (pending) return;
  const request = {};
  const run = (time) => {
    if (pending !== request) return;
    pending = null;
    cancelAnimationFrame(request.frame);
    clearTimeout(request.timer);
    frame(time);
  };
  pending = request;
  request.frame = requestAnimationFrame(run);
  request.timer = setTimeout(() => run(performance.now()), 100);
}

/** Draws one frame; keeps the loop going while walk keys are held. */
function frame(time) {
  if (navigation.moving()) {
    const dt = lastTime === null ? 0 : (time - lastTime) / 1000;
    navigation.tick(dt);
    lastTime = time;
  } else {
    lastTime = null;
  }
  draw();
  if (navigation.moving()) redraw();
}

/** Draws the solution and moves the probe marker with the view. */
function draw() {
  if (!renderer) return;
  const matrix = renderer.draw(navigation.camera, state.centre, state.diagonal, ui.view());
  hooks.framesDrawn += 1;
  if (state.mesh && state.meshLit) {
    hooks.lightApplied = true;
    state.drawnSerial = state.lightSerial;
  }
  if (matrix && state.probePoint) {
    ui.placeProbe(project(matrix, state.centre, state.probePoint, canvas.clientWidth, canvas.clientHeight));
  }
  checkSettled();
}

/**
 * settled: the status is "done" and the latest light has been drawn, and
 * either a light arrived after the "done" status (the final one) or none
 * came for SETTLE_QUIET_MS after it (the final light came first).
 */
function checkSettled() {
  const s = state.status;
  if (!s || s.state !== 'done' || !hooks.lightApplied || state.drawnSerial !== state.lightSerial) {
    return;
  }
  const waited = performance.now() - state.doneTime;
  if (state.lightSerial > state.doneSerial || waited >= SETTLE_QUIET_MS) {
    hooks.settled = true;
  } else {
    setTimeout(checkSettled, SETTLE_QUIET_MS - waited + 1);
  }
}

// ---- messages ------------------------------------------------------------

/** Tallest scene (along up) taken to be modelled in metres, scene units. */
const TALLEST_IN_METRES = 300;

/**
 * Scene units in a metre, guessed from the scene's height along the
 * camera's up: a scene taller than 300 units (the Cornell box, 549) is
 * taken as modelled in millimetres (1000), any other in metres (1).
 */
function unitsPerMetre(bounds, up) {
  const n = Math.hypot(up[0], up[1], up[2]) || 1;
  const height = Math.abs(
    (bounds.max[0] - bounds.min[0]) * up[0] + (bounds.max[1] - bounds.min[1]) * up[1]
      + (bounds.max[2] - bounds.min[2]) * up[2]) / n;
  return height > TALLEST_IN_METRES ? 1000 : 1;
}

/** The scene's bounds changed: centre and diagonal, and the mesh re-uploaded. */
function setBounds(bounds) {
  const g = boundsGeometry(bounds);
  const moved = g.centre.some((c, k) => c !== state.centre[k]);
  state.centre = g.centre;
  state.diagonal = g.diagonal;
  if (moved && state.mesh && renderer) {
    renderer.setMesh(state.mesh, state.centre);
    state.meshLit = false;
    hooks.lightApplied = false;
  }
}

function onHello(m) {
  const first = state.hello === null || state.hello.scene !== m.scene;
  state.hello = m;
  hooks.hello = m;
  if (m.bounds) setBounds(m.bounds);
  if (m.bounds && m.camera) state.unitsPerMetre = unitsPerMetre(m.bounds, m.camera.up);
  if (m.camera) navigation.setHome(helloCamera(m), first);
  ui.showHello(m);
}

function onMesh(m) {
  state.mesh = m;
  hooks.meshVersion = m.version;
  if (!state.hello || !state.hello.bounds) setBounds(boundsOf(m.positions));
  if (renderer) renderer.setMesh(m, state.centre);
  state.meshLit = false;
  hooks.lightApplied = false;
  const pending = state.pendingLight;
  state.pendingLight = null;
  if (pending && pending.meshVersion === m.version) onLight(pending);
}

function onLight(m) {
  const mesh = state.mesh;
  if (!mesh || m.meshVersion !== mesh.version) {
    state.pendingLight = m;
    return;
  }
  if (m.vertexCount !== mesh.vertexCount) {
    ui.message(`light for ${m.vertexCount} vertices, mesh has ${mesh.vertexCount}`);
    return;
  }
  if (renderer) renderer.setLight(m);
  state.meshLit = true;
  state.lightSerial += 1;
}

function onStatus(m) {
  state.status = m;
  hooks.status = m;
  if (m.state === 'done') {
    if (state.doneSerial === null) {
      state.doneSerial = state.lightSerial;
      state.doneTime = performance.now();
    }
  } else {
    state.doneSerial = null;
    hooks.settled = false;
  }
  ui.showStatus(m);
  // Before the first mesh, and on failure, the view itself says why it is
  // empty (the panel may be faded).
  if (m.state === 'failed') {
    ui.message(`the scene could not be solved: ${m.error ?? ''}`, 0);
  } else if (m.state === 'loading' && !state.mesh) {
    ui.message('loading and meshing the scene…', 0);
    state.loadingShown = true;
  } else if (state.loadingShown) {
    ui.clearMessage();
    state.loadingShown = false;
  }
}

/** Dispatches one decoded message, then redraws. */
function onMessage(m) {
  if (m.type === 'hello') onHello(m);
  else if (m.type === 'mesh') onMesh(m);
  else if (m.type === 'light') onLight(m);
  else if (m.type === 'status') onStatus(m);
  redraw();
}

connect({
  message: onMessage,
  connected: (up) => {
    ui.showConnection(up);
    if (up) {
      // A reconnecting page gets the whole state again.
      state.doneSerial = null;
    }
  },
  error: (e) => ui.message(`bad message: ${e.message}`),
});

// ---- probe, PNG ----------------------------------------------------------

/**
 * Probes the surface under canvas point (px, py): casts the pixel's ray
 * at the mesh, asks the server at the hit point with the normal facing the
 * eye, and shows the answer in #probe.
 */
async function probeAt(px, py) {
  const camera = navigation.camera;
  const mesh = state.mesh;
  if (!camera || !mesh) return;
  const ray = pixelRay(camera, px, py, canvas.clientWidth, canvas.clientHeight);
  const hit = castRay(mesh, ray.origin, ray.direction);
  const serial = ++state.probeSerial;
  if (!hit) {
    state.probePoint = null;
    ui.probePending(px, py);
    ui.probeResult(false, { error: 'no surface here' });
    ui.placeProbe(null);
    ui.hideProbe(2500);
    return;
  }
  state.probePoint = hit.point;
  const [x, y, z] = hit.point;
  const [nx, ny, nz] = hit.normal;
  const request = { x, y, z, nx, ny, nz };
  ui.probePending(px, py);
  let answer;
  try {
    answer = await probe(request);
  } catch (e) {
    answer = { ok: false, body: { error: `probe failed: ${e.message}` } };
  }
  if (serial !== state.probeSerial) return;
  hooks.lastProbe = { request, response: answer.body };
  ui.probeResult(answer.ok, answer.body);
  redraw(); // places the popup for its new size
}

/** Saves the canvas as isorad-view.png. */
function savePng() {
  draw();
  canvas.toBlob((blob) => {
    if (!blob) return;
    const a = document.createElement('a');
    a.href = URL.createObjectURL(blob);
    a.download = 'isorad-view.png';
    document.body.appendChild(a);
    a.click();
    a.remove();
    setTimeout(() => URL.revokeObjectURL(a.href), 1000);
  }, 'image/png');
}

window.addEventListener('resize', redraw);
window.addEventListener('keydown', (e) => {
  if (e.code !== 'Escape') return;
  state.probePoint = null;
  ui.hideProbe();
});
redraw();
