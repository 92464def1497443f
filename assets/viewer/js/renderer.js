// The WebGL2 renderer: one draw of indexed triangles shaded exactly as
// `isorad render` shades them (src/render/tone_map.rs), or in false colour.
//
// Radiance: per-vertex linear radiance L (W/(m²·sr)) interpolated
// perspective-correctly; per channel v = L · 2^exposure, then the sRGB
// curve (12.92 v for v ≤ 0.0031308, else 1.055 v^(1/2.4) − 0.055), clamped
// to [0, 1]. Back faces (clockwise on screen) are black but still hide what
// is behind them. No lighting, no fog. Background black.
//
// Where the browser can draw to floating-point targets, the scene is drawn
// in linear light and its samples averaged before the curve (linear.js),
// as the renderer averages its samples; else straight to the canvas.
//
// Positions are uploaded relative to the scene's bounds centre c (f32
// precision stays where the scene is); the view matrix is built in f64
// from eye − c.

import { FALSE_COLOUR_GLSL, bandColoursUniform, EFFICACY } from './falsecolor.js';
import { sub, dot, length, cameraFrame } from './picking.js';
import { createLinearTarget, linkProgram } from './linear.js';

const VERTEX_SHADER = `#version 300 es
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_radiance;
layout(location = 2) in float a_illuminance;
uniform mat4 u_viewProjection;
out vec3 v_radiance;
out float v_illuminance;
void main() {
  gl_Position = u_viewProjection * vec4(a_position, 1.0);
  v_radiance = a_radiance;
  v_illuminance = a_illuminance;
}
`;

const FRAGMENT_SHADER = `#version 300 es
precision highp float;
precision highp int;
in vec3 v_radiance;
in float v_illuminance;
uniform float u_scale;     // 2^exposure
uniform int u_display;     // 0 radiance, 1 luminance, 2 illuminance
uniform float u_max;       // false-colour maximum
uniform bool u_log;        // false-colour log scale
uniform bool u_linear;     // write linear radiance and Y(H) for linear.js
out vec4 outColour;
${FALSE_COLOUR_GLSL}
float srgb(float v) {
  return v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1.0 / 2.4) - 0.055;
}
void main() {
  if (u_linear) {
    outColour = gl_FrontFacing
      ? vec4(v_radiance, v_illuminance / ${EFFICACY.toFixed(1)})
      : vec4(0.0);
    return;
  }
  if (!gl_FrontFacing) {
    outColour = vec4(0.0, 0.0, 0.0, 1.0);
    return;
  }
  vec3 colour;
  if (u_display == 0) {
    vec3 v = v_radiance * u_scale;
    colour = clamp(vec3(srgb(v.r), srgb(v.g), srgb(v.b)), 0.0, 1.0);
  } else {
    float value = u_display == 1
      ? ${EFFICACY.toFixed(1)} * dot(v_radiance, vec3(0.2126, 0.7152, 0.0722))
      : v_illuminance;
    colour = falseColour(value, u_max, u_log);
  }
  outColour = vec4(colour, 1.0);
}
`;

/** Display modes, as the shader's u_display. */
export const DISPLAY = { radiance: 0, luminance: 1, illuminance: 2 };

/**
 * The centre and diagonal of a bounds box {min, max}:
 * c = (min + max) / 2, d = |max − min| (at least 1e-9).
 */
export function boundsGeometry(bounds) {
  const centre = [0, 1, 2].map((k) => 0.5 * (bounds.min[k] + bounds.max[k]));
  return { centre, diagonal: Math.max(length(sub(bounds.max, bounds.min)), 1e-9) };
}

/** The bounds {min, max} of a flat xyz position array. */
export function boundsOf(positions) {
  const min = [Infinity, Infinity, Infinity];
  const max = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i < positions.length; i += 3) {
    for (let k = 0; k < 3; k++) {
      min[k] = Math.min(min[k], positions[i + k]);
      max[k] = Math.max(max[k], positions[i + k]);
    }
  }
  return positions.length ? { min, max } : { min: [0, 0, 0], max: [0, 0, 0] };
}

/**
 * The view-projection matrix (column-major, f64 entries) for positions
 * relative to `centre`, with e = eye − centre and the frame (R, U, F):
 *   V = [R, −R·e; U, −U·e; −F, F·e; 0 0 0 1],
 *   P = perspective with f = 1/tan(vfov/2), aspect a = W/H,
 *       near n = 1e-3 · diagonal, far = |e| + 2 · diagonal:
 *   P = [f/a 0 0 0; 0 f 0 0; 0 0 (far+n)/(n−far) 2·far·n/(n−far); 0 0 −1 0].
 * @returns {Float64Array} 16 entries, column-major, P·V
 */
export function viewProjection(camera, centre, diagonal, aspect) {
  const { right: r, up: u, forward: f } = cameraFrame(camera);
  const e = sub(camera.eye, centre);
  const view = [
    r[0], u[0], -f[0], 0,
    r[1], u[1], -f[1], 0,
    r[2], u[2], -f[2], 0,
    -dot(r, e), -dot(u, e), dot(f, e), 1,
  ];
  const near = 1e-3 * diagonal;
  const far = length(e) + 2 * diagonal;
  const focal = 1 / Math.tan((0.5 * camera.vfov * Math.PI) / 180);
  const projection = [
    focal / aspect, 0, 0, 0,
    0, focal, 0, 0,
    0, 0, (far + near) / (near - far), -1,
    0, 0, (2 * far * near) / (near - far), 0,
  ];
  return multiply(projection, view);
}

/** a · b for 4×4 column-major matrices. */
function multiply(a, b) {
  const out = new Float64Array(16);
  for (let col = 0; col < 4; col++) {
    for (let row = 0; row < 4; row++) {
      let s = 0;
      for (let k = 0; k < 4; k++) s += a[4 * k + row] * b[4 * col + k];
      out[4 * col + row] = s;
    }
  }
  return out;
}

/**
 * Where a world point lands on a W × H canvas (CSS px from the top left),
 * or null when it is behind the eye: clip = M (p − c, 1),
 * x = (clip.x/clip.w + 1) W/2, y = (1 − clip.y/clip.w) H/2.
 */
export function project(matrix, centre, point, width, height) {
  const p = sub(point, centre);
  const clip = [0, 1, 2, 3].map(
    (row) => matrix[row] * p[0] + matrix[4 + row] * p[1] + matrix[8 + row] * p[2] + matrix[12 + row],
  );
  if (clip[3] <= 0) return null;
  return [((clip[0] / clip[3] + 1) * width) / 2, ((1 - clip[1] / clip[3]) * height) / 2];
}

/**
 * Creates the renderer on `canvas` (WebGL2, antialias, preserved drawing
 * buffer so screenshots and toDataURL see the last frame).
 * @throws {Error} when WebGL2 is missing or the shaders fail
 */
export function createRenderer(canvas) {
  const gl = canvas.getContext('webgl2', {
    antialias: true,
    preserveDrawingBuffer: true,
    alpha: false,
    depth: true,
  });
  if (!gl) throw new Error('WebGL2 is not available');
  const program = linkProgram(gl, VERTEX_SHADER, FRAGMENT_SHADER);
  const uniform = (name) => gl.getUniformLocation(program, name);
  const loc = {
    viewProjection: uniform('u_viewProjection'),
    scale: uniform('u_scale'),
    display: uniform('u_display'),
    max: uniform('u_max'),
    log: uniform('u_log'),
    linear: uniform('u_linear'),
    bandColours: uniform('u_bandColours[0]') || uniform('u_bandColours'),
  };
  let linear = null;
  try {
    linear = createLinearTarget(gl);
  } catch (error) {
    console.warn('drawing without the linear target:', error);
  }
  const vao = gl.createVertexArray();
  const buffers = {
    position: gl.createBuffer(),
    radiance: gl.createBuffer(),
    illuminance: gl.createBuffer(),
    index: gl.createBuffer(),
  };
  gl.bindVertexArray(vao);
  const attribute = (location, buffer, size) => {
    gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
    gl.enableVertexAttribArray(location);
    gl.vertexAttribPointer(location, size, gl.FLOAT, false, 0, 0);
  };
  attribute(0, buffers.position, 3);
  attribute(1, buffers.radiance, 3);
  attribute(2, buffers.illuminance, 1);
  gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, buffers.index);
  gl.bindVertexArray(null);
  gl.useProgram(program);
  gl.uniform3fv(loc.bandColours, bandColoursUniform());

  let indexCount = 0;
  let vertexCount = 0;

  const upload = (buffer, data, usage) => {
    gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
    gl.bufferData(gl.ARRAY_BUFFER, data, usage);
  };

  return {
    gl,
    /**
     * Uploads a mesh: positions − centre (computed in f64, stored f32),
     * the indices, and zero light until setLight.
     */
    setMesh(mesh, centre) {
      const p = new Float32Array(mesh.positions.length);
      for (let i = 0; i < p.length; i += 3) {
        p[i] = mesh.positions[i] - centre[0];
        p[i + 1] = mesh.positions[i + 1] - centre[1];
        p[i + 2] = mesh.positions[i + 2] - centre[2];
      }
      gl.bindVertexArray(vao);
      upload(buffers.position, p, gl.STATIC_DRAW);
      upload(buffers.radiance, new Float32Array(3 * mesh.vertexCount), gl.DYNAMIC_DRAW);
      upload(buffers.illuminance, new Float32Array(mesh.vertexCount), gl.DYNAMIC_DRAW);
      gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, mesh.indices, gl.STATIC_DRAW);
      gl.bindVertexArray(null);
      indexCount = mesh.indices.length;
      vertexCount = mesh.vertexCount;
    },
    /** Uploads per-vertex radiance and illuminance of the mesh held. */
    setLight(light) {
      if (light.vertexCount !== vertexCount) throw new Error('light does not match the mesh');
      upload(buffers.radiance, light.radiance, gl.DYNAMIC_DRAW);
      upload(buffers.illuminance, light.illuminance, gl.DYNAMIC_DRAW);
    },
    /**
     * Draws one frame at the canvas's CSS size.
     * @param {{exposure:number, display:string, max:number, log:boolean}} view
     * @returns {Float64Array|null} the view-projection used
     */
    draw(camera, centre, diagonal, view) {
      const width = Math.max(1, canvas.clientWidth);
      const height = Math.max(1, canvas.clientHeight);
      if (canvas.width !== width || canvas.height !== height) {
        canvas.width = width;
        canvas.height = height;
      }
      gl.bindFramebuffer(gl.FRAMEBUFFER, null);
      gl.viewport(0, 0, width, height);
      gl.clearColor(0, 0, 0, 1);
      gl.clearDepth(1);
      gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
      if (!camera || indexCount === 0) return null;
      const inLinear = linear !== null && linear.begin(width, height);
      const matrix = viewProjection(camera, centre, diagonal, width / height);
      gl.enable(gl.DEPTH_TEST);
      gl.depthFunc(gl.LESS);
      gl.frontFace(gl.CCW);
      gl.useProgram(program);
      gl.uniformMatrix4fv(loc.viewProjection, false, new Float32Array(matrix));
      gl.uniform1f(loc.scale, Math.pow(2, view.exposure));
      gl.uniform1i(loc.display, DISPLAY[view.display] ?? 0);
      gl.uniform1f(loc.max, view.max > 0 && Number.isFinite(view.max) ? view.max : 1);
      gl.uniform1i(loc.log, view.log ? 1 : 0);
      gl.uniform1i(loc.linear, inLinear ? 1 : 0);
      gl.bindVertexArray(vao);
      // Front faces first, then back faces pushed back a little: where a
      // front and a back face coincide (the walls two rooms share), the
      // front face wins, as it does in the renderer, which draws only the
      // camera's room.
      gl.enable(gl.CULL_FACE);
      gl.cullFace(gl.BACK);
      gl.drawElements(gl.TRIANGLES, indexCount, gl.UNSIGNED_INT, 0);
      gl.cullFace(gl.FRONT);
      gl.enable(gl.POLYGON_OFFSET_FILL);
      gl.polygonOffset(1, 4);
      gl.drawElements(gl.TRIANGLES, indexCount, gl.UNSIGNED_INT, 0);
      gl.disable(gl.POLYGON_OFFSET_FILL);
      gl.disable(gl.CULL_FACE);
      gl.bindVertexArray(null);
      if (inLinear) linear.finish(view, DISPLAY[view.display] ?? 0);
      return matrix;
    },
  };
}
