// Navigation: the viewer's camera and how the mouse and keys move it.
//
// The camera is {eye, target, up, vfov}: eye and target in world space, up
// the world's up (unit), vfov the vertical field of view in degrees. Its
// frame is picking.js's cameraFrame, the one `isorad render` uses.
//
// Orbit (default): left-drag turns the eye about the target keeping the
// world up, the wheel dollies, right-drag or shift+left-drag pans.
// Walk: WASD / arrows move on the horizontal plane, Q/E down/up, a drag
// turns (yaw about the world up, pitch within ±85°). H: the scene camera.
// A click (less than 4 px of movement) on the canvas probes.

import {
  add, sub, scale, dot, cross, length, normalize, cameraFrame, floorBelow, castRay,
} from './picking.js';

const DEG = Math.PI / 180;
/** Radians of turn per pixel of drag. */
const TURN_PER_PIXEL = 0.005;
/** Movement below which a press and release is a click, CSS pixels. */
const CLICK_SLOP = 4;
/** Orbit elevation limit, radians (keeps the frame defined). */
const ORBIT_LIMIT = 89 * DEG;
/** Walk pitch limit, radians. */
const PITCH_LIMIT = 85 * DEG;
/** Eye height above the floor in walk mode, metres. */
export const EYE_HEIGHT = 1.6;
/** Walking speed, metres per second; Shift × 3. */
export const WALK_SPEED = 1.4;

/**
 * A unit basis (a, b) of the plane perpendicular to the unit vector u,
 * with b = u × a; always the same for the same u.
 */
function horizontalBasis(u) {
  const axis = Math.abs(u[0]) < 0.9 ? [1, 0, 0] : [0, 1, 0];
  const a = normalize(cross(axis, u));
  return { a, b: cross(u, a) };
}

/**
 * Azimuth θ and elevation φ of a vector w about the unit up u:
 * θ = atan2(w·b, w·a), φ = asin(w·u / |w|).
 */
function angles(w, u) {
  const { a, b } = horizontalBasis(u);
  const r = length(w);
  const s = r > 0 ? Math.min(Math.max(dot(w, u) / r, -1), 1) : 0;
  return { theta: Math.atan2(dot(w, b), dot(w, a)), phi: Math.asin(s), r };
}

/**
 * The vector of length r at azimuth θ and elevation φ about u:
 * r (cos φ (cos θ a + sin θ b) + sin φ u).
 */
function fromAngles(theta, phi, r, u) {
  const { a, b } = horizontalBasis(u);
  const h = add(scale(a, Math.cos(theta)), scale(b, Math.sin(theta)));
  return scale(add(scale(h, Math.cos(phi)), scale(u, Math.sin(phi))), r);
}

/** The camera of a hello message: eye = position, target = look_at. */
export function helloCamera(hello) {
  const c = hello.camera;
  return {
    eye: c.position.slice(),
    target: c.look_at.slice(),
    up: normalize(c.up),
    vfov: c.vfov_deg,
  };
}

/**
 * Orbit: turns the eye about the target: azimuth −= dx·k, elevation += dy·k
 * (clamped to ±89°), k = 0.005 rad/px; the scene follows the mouse.
 */
export function orbit(camera, dx, dy) {
  const o = angles(sub(camera.eye, camera.target), camera.up);
  const phi = Math.min(Math.max(o.phi + dy * TURN_PER_PIXEL, -ORBIT_LIMIT), ORBIT_LIMIT);
  const offset = fromAngles(o.theta - dx * TURN_PER_PIXEL, phi, o.r, camera.up);
  return { ...camera, eye: add(camera.target, offset) };
}

/**
 * Dolly: distance to the target × exp(delta · 0.001), at least `minimum`.
 */
export function dolly(camera, delta, minimum) {
  const offset = sub(camera.eye, camera.target);
  const r = Math.max(length(offset) * Math.exp(delta * 0.001), minimum);
  return { ...camera, eye: add(camera.target, scale(normalize(offset), r)) };
}

/**
 * Pan: eye and target move by (−dx · right + dy · up') · s, with
 * s = 2 r tan(vfov/2) / H the world size of a pixel at the target.
 */
export function pan(camera, dx, dy, height) {
  const f = cameraFrame(camera);
  const r = length(sub(camera.target, camera.eye));
  const s = (2 * r * Math.tan(0.5 * camera.vfov * DEG)) / Math.max(height, 1);
  const move = add(scale(f.right, -dx * s), scale(f.up, dy * s));
  return { ...camera, eye: add(camera.eye, move), target: add(camera.target, move) };
}

/**
 * Walk turn: yaw −= dx·k about the world up, pitch −= dy·k clamped to
 * ±85°; the target stays at the same distance in front of the eye.
 */
export function look(camera, dx, dy) {
  const o = angles(sub(camera.target, camera.eye), camera.up);
  const pitch = Math.min(Math.max(o.phi - dy * TURN_PER_PIXEL, -PITCH_LIMIT), PITCH_LIMIT);
  const r = o.r > 0 ? o.r : 1;
  return { ...camera, target: add(camera.eye, fromAngles(o.theta - dx * TURN_PER_PIXEL, pitch, r, camera.up)) };
}

/**
 * Walk step: moves eye and target by forward·f_h + strafe·r_h + rise·u
 * (f_h the view direction made horizontal, r_h = f_h × u).
 */
export function step(camera, forward, strafe, rise) {
  const u = camera.up;
  const frame = cameraFrame(camera);
  let fh = sub(frame.forward, scale(u, dot(frame.forward, u)));
  if (length(fh) < 1e-6) fh = sub(frame.up, scale(u, dot(frame.up, u)));
  fh = normalize(fh);
  const rh = cross(fh, u);
  const move = add(add(scale(fh, forward), scale(rh, strafe)), scale(u, rise));
  return { ...camera, eye: add(camera.eye, move), target: add(camera.target, move) };
}

/** Keys of walk mode: [forward, strafe, rise] per key code. */
const WALK_KEYS = {
  KeyW: [1, 0, 0], ArrowUp: [1, 0, 0],
  KeyS: [-1, 0, 0], ArrowDown: [-1, 0, 0],
  KeyA: [0, -1, 0], ArrowLeft: [0, -1, 0],
  KeyD: [0, 1, 0], ArrowRight: [0, 1, 0],
  KeyQ: [0, 0, -1], KeyE: [0, 0, 1],
};

/** Whether a key event belongs to a form field rather than the view. */
function typing(event) {
  const t = event.target;
  return t && (t.tagName === 'INPUT' || t.tagName === 'SELECT' || t.tagName === 'TEXTAREA');
}

/**
 * Attaches navigation to `canvas`.
 * @param {HTMLCanvasElement} canvas
 * @param {{mesh:()=>object|null, diagonal:()=>number, unitsPerMetre:()=>number, changed:()=>void,
 *   click:(px:number, py:number)=>void, modeChanged:(mode:string)=>void}} host
 */
export function createNavigation(canvas, host) {
  let camera = null;
  let home = null;
  let mode = 'orbit';
  const held = new Set();
  let shift = false;
  let drag = null;

  const set = (next) => {
    camera = next;
    host.changed();
  };
  const metre = () => host.unitsPerMetre();
  const walkSpeed = () => WALK_SPEED * metre();

  function setMode(next) {
    if (next === mode || !camera) {
      mode = next;
      host.modeChanged(mode);
      return;
    }
    const mesh = host.mesh();
    if (next === 'walk') {
      let c = look(camera, 0, 0); // clamps the pitch
      const floor = mesh ? floorBelow(mesh, c.eye, c.up) : null;
      if (floor) {
        const lift = scale(c.up, EYE_HEIGHT * metre() - dot(sub(c.eye, floor.point), c.up));
        c = { ...c, eye: add(c.eye, lift), target: add(c.target, lift) };
      }
      camera = c;
    } else {
      const f = cameraFrame(camera);
      const hit = mesh ? castRay(mesh, camera.eye, f.forward) : null;
      const r = hit ? hit.t : length(sub(camera.target, camera.eye));
      camera = { ...camera, target: add(camera.eye, scale(f.forward, r)) };
    }
    mode = next;
    host.modeChanged(mode);
    host.changed();
  }

  function onPointerDown(e) {
    if (!camera) return;
    canvas.setPointerCapture(e.pointerId);
    drag = {
      id: e.pointerId, x: e.clientX, y: e.clientY, startX: e.clientX, startY: e.clientY,
      pan: e.button === 2 || e.button === 1 || (e.button === 0 && e.shiftKey), moving: false,
    };
  }

  function onPointerMove(e) {
    if (!drag || e.pointerId !== drag.id) return;
    if (!drag.moving) {
      const far = Math.hypot(e.clientX - drag.startX, e.clientY - drag.startY) >= CLICK_SLOP;
      if (!far) return;
      drag.moving = true;
    }
    const dx = e.clientX - drag.x;
    const dy = e.clientY - drag.y;
    drag.x = e.clientX;
    drag.y = e.clientY;
    if (mode === 'walk') set(look(camera, dx, dy));
    else if (drag.pan) set(pan(camera, dx, dy, canvas.clientHeight));
    else set(orbit(camera, dx, dy));
  }

  function onPointerUp(e) {
    if (!drag || e.pointerId !== drag.id) return;
    const wasClick = !drag.moving && e.type === 'pointerup';
    drag = null;
    if (wasClick) {
      const box = canvas.getBoundingClientRect();
      host.click(e.clientX - box.left, e.clientY - box.top);
    }
  }

  function onWheel(e) {
    if (!camera) return;
    e.preventDefault();
    const delta = e.deltaY * (e.deltaMode === 1 ? 33 : e.deltaMode === 2 ? 400 : 1);
    if (mode === 'walk') set(step(camera, -delta * 0.0025 * walkSpeed() / WALK_SPEED, 0, 0));
    else set(dolly(camera, delta, 1e-4 * host.diagonal()));
  }

  function onKeyDown(e) {
    shift = e.shiftKey;
    if (typing(e) || e.ctrlKey || e.metaKey || e.altKey) return;
    if (e.code === 'KeyH') {
      goHome();
      return;
    }
    if (mode === 'walk' && WALK_KEYS[e.code]) {
      e.preventDefault();
      const first = held.size === 0;
      held.add(e.code);
      if (first) host.changed(); // starts the render loop that calls tick
    }
  }

  function goHome() {
    if (home) set({ ...home, eye: home.eye.slice(), target: home.target.slice() });
  }

  canvas.addEventListener('pointerdown', onPointerDown);
  canvas.addEventListener('pointermove', onPointerMove);
  canvas.addEventListener('pointerup', onPointerUp);
  canvas.addEventListener('pointercancel', onPointerUp);
  canvas.addEventListener('contextmenu', (e) => e.preventDefault());
  canvas.addEventListener('wheel', onWheel, { passive: false });
  window.addEventListener('keydown', onKeyDown);
  window.addEventListener('keyup', (e) => {
    shift = e.shiftKey;
    held.delete(e.code);
  });
  window.addEventListener('blur', () => {
    held.clear();
    shift = false;
  });

  return {
    /** The current camera (a copy), or null before the hello. */
    get camera() {
      return camera && { ...camera, eye: camera.eye.slice(), target: camera.target.slice() };
    },
    get mode() {
      return mode;
    },
    /** Sets the scene camera; moves there when `go` (the first hello). */
    setHome(c, go) {
      home = c;
      if (go || !camera) set({ ...c, eye: c.eye.slice(), target: c.target.slice() });
    },
    home: goHome,
    setMode,
    toggleMode() {
      setMode(mode === 'orbit' ? 'walk' : 'orbit');
    },
    /** Whether walk keys are held (the render loop keeps calling tick). */
    moving() {
      return mode === 'walk' && held.size > 0;
    },
    /**
     * Advances walking by dt seconds: speed 1.4 m/s in scene units,
     * × 3 with Shift; diagonal key pairs no faster. Returns whether the
     * camera moved.
     */
    tick(dt) {
      if (!camera || mode !== 'walk' || held.size === 0) return false;
      let m = [0, 0, 0];
      for (const code of held) m = add(m, WALK_KEYS[code] || [0, 0, 0]);
      if (length(m) === 0) return false;
      m = normalize(m);
      const d = walkSpeed() * (shift ? 3 : 1) * Math.min(dt, 0.1);
      camera = step(camera, m[0] * d, m[1] * d, m[2] * d);
      return true;
    },
  };
}
