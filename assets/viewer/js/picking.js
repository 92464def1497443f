// Geometry on the CPU: small vector helpers, the camera frame, the ray
// through a pixel, and ray casts against the mesh (Möller–Trumbore), for
// the probe on click and walk mode's floor.

/** a + b */
export const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
/** a − b */
export const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
/** s · a */
export const scale = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
/** a · b */
export const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
/** a × b */
export const cross = (a, b) => [
  a[1] * b[2] - a[2] * b[1],
  a[2] * b[0] - a[0] * b[2],
  a[0] * b[1] - a[1] * b[0],
];
/** |a| */
export const length = (a) => Math.hypot(a[0], a[1], a[2]);
/** a / |a| (a itself when |a| = 0) */
export function normalize(a) {
  const l = length(a);
  return l > 0 ? scale(a, 1 / l) : a.slice();
}

/**
 * The camera frame, as `isorad render` builds it (right-handed):
 * forward = normalize(target − eye), right = normalize(forward × up),
 * up' = right × forward.
 * @param {{eye:number[], target:number[], up:number[]}} camera
 * @returns {{forward:number[], right:number[], up:number[]}}
 */
export function cameraFrame(camera) {
  const forward = normalize(sub(camera.target, camera.eye));
  const right = normalize(cross(forward, camera.up));
  return { forward, right, up: cross(right, forward) };
}

/**
 * The ray from the eye through canvas point (px, py) (CSS pixels from the
 * top-left, pixel centres at +0.5) of a width × height canvas:
 *   x = (2 px / W − 1) · tan(vfov/2) · W/H,  y = (1 − 2 py / H) · tan(vfov/2),
 *   direction = normalize(x · right + y · up' + forward).
 * @param {{eye:number[], target:number[], up:number[], vfov:number}} camera
 * @returns {{origin:number[], direction:number[]}}
 */
export function pixelRay(camera, px, py, width, height) {
  const frame = cameraFrame(camera);
  const halfHeight = Math.tan((0.5 * camera.vfov * Math.PI) / 180);
  const x = ((2 * px) / width - 1) * halfHeight * (width / height);
  const y = (1 - (2 * py) / height) * halfHeight;
  const direction = normalize(
    add(add(scale(frame.right, x), scale(frame.up, y)), frame.forward),
  );
  return { origin: camera.eye.slice(), direction };
}

/**
 * The nearest hit of a ray with the mesh's triangles, both sides counting
 * (Möller–Trumbore): for a triangle (p0, p1, p2), e1 = p1 − p0,
 * e2 = p2 − p0, q = d × e2, det = e1 · q; s = o − p0, u = s · q / det,
 * r = s × e1, v = d · r / det, t = e2 · r / det; a hit when u ≥ 0, v ≥ 0,
 * u + v ≤ 1 and t > 0.
 *
 * The normal is the triangle's geometric normal e1 × e2 (the front of a
 * counter-clockwise triangle), normalised and flipped to face the ray's
 * origin: the side the viewer sees.
 * @param {{positions:Float32Array, indices:Uint32Array}} mesh world space
 * @param {number[]} origin
 * @param {number[]} direction
 * @returns {{t:number, point:number[], normal:number[], triangle:number,
 *   front:boolean} | null}
 */
export function castRay(mesh, origin, direction) {
  const p = mesh.positions;
  const idx = mesh.indices;
  const [ox, oy, oz] = origin;
  const [dx, dy, dz] = direction;
  let best = Infinity;
  let bestTriangle = -1;
  for (let k = 0; k < idx.length; k += 3) {
    const i0 = 3 * idx[k], i1 = 3 * idx[k + 1], i2 = 3 * idx[k + 2];
    const ax = p[i0], ay = p[i0 + 1], az = p[i0 + 2];
    const e1x = p[i1] - ax, e1y = p[i1 + 1] - ay, e1z = p[i1 + 2] - az;
    const e2x = p[i2] - ax, e2y = p[i2 + 1] - ay, e2z = p[i2 + 2] - az;
    const qx = dy * e2z - dz * e2y, qy = dz * e2x - dx * e2z, qz = dx * e2y - dy * e2x;
    const det = e1x * qx + e1y * qy + e1z * qz;
    if (det === 0 || !Number.isFinite(det)) continue;
    const inv = 1 / det;
    const sx = ox - ax, sy = oy - ay, sz = oz - az;
    const u = (sx * qx + sy * qy + sz * qz) * inv;
    if (u < 0 || u > 1) continue;
    const rx = sy * e1z - sz * e1y, ry = sz * e1x - sx * e1z, rz = sx * e1y - sy * e1x;
    const v = (dx * rx + dy * ry + dz * rz) * inv;
    if (v < 0 || u + v > 1) continue;
    const t = (e2x * rx + e2y * ry + e2z * rz) * inv;
    if (t > 0 && t < best) {
      best = t;
      bestTriangle = k / 3;
    }
  }
  if (bestTriangle < 0) return null;
  return hitAt(mesh, origin, direction, best, bestTriangle);
}

/** The hit record of triangle `triangle` at ray parameter t (see castRay). */
function hitAt(mesh, origin, direction, t, triangle) {
  const vertex = (j) => {
    const i = 3 * mesh.indices[3 * triangle + j];
    return [mesh.positions[i], mesh.positions[i + 1], mesh.positions[i + 2]];
  };
  const a = vertex(0);
  const normal = normalize(cross(sub(vertex(1), a), sub(vertex(2), a)));
  const front = dot(normal, direction) < 0;
  return {
    t,
    point: add(origin, scale(direction, t)),
    normal: front ? normal : scale(normal, -1),
    triangle,
    front,
  };
}

/**
 * The floor below a point: the nearest hit of the ray from `point` along
 * −up (straight down), or null when there is none.
 * @returns {{t:number, point:number[], normal:number[]} | null}
 */
export function floorBelow(mesh, point, up) {
  return castRay(mesh, point, scale(normalize(up), -1));
}
