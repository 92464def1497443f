// Anti-aliasing in linear light, as `isorad render` does it: the scene is
// drawn into a multisampled floating-point target holding linear radiance
// (RGB) and the irradiance's luminance Y(H) (alpha), the samples are
// averaged (a box filter, the renderer's), and only then does each pixel
// get the exposure and the sRGB curve, or its false colour:
//
//   pixel = srgb(clamp(2^exposure · mean(L), 0, 1))      (radiance)
//   pixel = band colour of 179 · Y(mean(L)) or 179 · mean(Y(H))
//
// Averaging after the sRGB curve instead (the browser's own
// anti-aliasing) darkens every outline: the curve is concave. The target
// needs EXT_color_buffer_float; without it the page draws straight to the
// canvas and anti-aliases there.

import { FALSE_COLOUR_GLSL, bandColoursUniform, EFFICACY } from './falsecolor.js';

const SCREEN_VERTEX = `#version 300 es
void main() {
  // One triangle over the whole screen.
  vec2 corner = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
  gl_Position = vec4(corner, 0.0, 1.0);
}
`;

const SCREEN_FRAGMENT = `#version 300 es
precision highp float;
precision highp int;
uniform sampler2D u_image;
uniform float u_scale;     // 2^exposure
uniform int u_display;     // 0 radiance, 1 luminance, 2 illuminance
uniform float u_max;
uniform bool u_log;
out vec4 outColour;
${FALSE_COLOUR_GLSL}
float srgb(float v) {
  return v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1.0 / 2.4) - 0.055;
}
void main() {
  vec4 p = texelFetch(u_image, ivec2(gl_FragCoord.xy), 0);
  vec3 colour;
  if (u_display == 0) {
    vec3 v = max(p.rgb, vec3(0.0)) * u_scale;
    colour = clamp(vec3(srgb(v.r), srgb(v.g), srgb(v.b)), 0.0, 1.0);
  } else {
    float y = u_display == 1 ? dot(p.rgb, vec3(0.2126, 0.7152, 0.0722)) : p.a;
    colour = falseColour(${EFFICACY.toFixed(1)} * y, u_max, u_log);
  }
  outColour = vec4(colour, 1.0);
}
`;

/** Compiles and links a program; throws with the driver's log. */
export function linkProgram(gl, vertex, fragment) {
  const p = gl.createProgram();
  for (const [type, source] of [[gl.VERTEX_SHADER, vertex], [gl.FRAGMENT_SHADER, fragment]]) {
    const shader = gl.createShader(type);
    gl.shaderSource(shader, source);
    gl.compileShader(shader);
    if (!gl.getShaderParameter(shader, gl.COMPILE_STATUS)) {
      throw new Error('shader: ' + gl.getShaderInfoLog(shader));
    }
    gl.attachShader(p, shader);
  }
  gl.linkProgram(p);
  if (!gl.getProgramParameter(p, gl.LINK_STATUS)) {
    throw new Error('program: ' + gl.getProgramInfoLog(p));
  }
  return p;
}

/**
 * The linear-light target, or null where floating-point targets cannot be
 * drawn to. `begin(width, height)` binds it for the scene's draw;
 * `finish(view)` averages its samples and draws the canvas's pixels.
 */
export function createLinearTarget(gl) {
  if (!gl.getExtension('EXT_color_buffer_float')) return null;
  const samples = Math.min(8, gl.getParameter(gl.MAX_SAMPLES) || 1);
  const screen = linkProgram(gl, SCREEN_VERTEX, SCREEN_FRAGMENT);
  const uniform = (name) => gl.getUniformLocation(screen, name);
  const loc = {
    image: uniform('u_image'),
    scale: uniform('u_scale'),
    display: uniform('u_display'),
    max: uniform('u_max'),
    log: uniform('u_log'),
    bandColours: uniform('u_bandColours[0]') || uniform('u_bandColours'),
  };
  gl.useProgram(screen);
  gl.uniform3fv(loc.bandColours, bandColoursUniform());
  const empty = gl.createVertexArray();
  const drawn = { fbo: gl.createFramebuffer(), colour: null, depth: null };
  const resolved = { fbo: gl.createFramebuffer(), texture: null };
  let size = [0, 0];

  /** (Re)allocates the targets at width × height; false if incomplete. */
  function allocate(width, height) {
    for (const r of [drawn.colour, drawn.depth]) if (r) gl.deleteRenderbuffer(r);
    if (resolved.texture) gl.deleteTexture(resolved.texture);
    drawn.colour = gl.createRenderbuffer();
    gl.bindRenderbuffer(gl.RENDERBUFFER, drawn.colour);
    gl.renderbufferStorageMultisample(gl.RENDERBUFFER, samples, gl.RGBA16F, width, height);
    drawn.depth = gl.createRenderbuffer();
    gl.bindRenderbuffer(gl.RENDERBUFFER, drawn.depth);
    gl.renderbufferStorageMultisample(gl.RENDERBUFFER, samples, gl.DEPTH_COMPONENT24, width, height);
    gl.bindFramebuffer(gl.FRAMEBUFFER, drawn.fbo);
    gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.RENDERBUFFER, drawn.colour);
    gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.DEPTH_ATTACHMENT, gl.RENDERBUFFER, drawn.depth);
    const drawnComplete = gl.checkFramebufferStatus(gl.FRAMEBUFFER) === gl.FRAMEBUFFER_COMPLETE;
    resolved.texture = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, resolved.texture);
    gl.texStorage2D(gl.TEXTURE_2D, 1, gl.RGBA16F, width, height);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
    gl.bindFramebuffer(gl.FRAMEBUFFER, resolved.fbo);
    gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, resolved.texture, 0);
    const resolvedComplete = gl.checkFramebufferStatus(gl.FRAMEBUFFER) === gl.FRAMEBUFFER_COMPLETE;
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    size = [width, height];
    return drawnComplete && resolvedComplete;
  }

  return {
    /** Binds the multisampled target for the scene; false if unusable. */
    begin(width, height) {
      if ((size[0] !== width || size[1] !== height) && !allocate(width, height)) return false;
      gl.bindFramebuffer(gl.FRAMEBUFFER, drawn.fbo);
      gl.viewport(0, 0, width, height);
      gl.clearColor(0, 0, 0, 0);
      gl.clearDepth(1);
      gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
      return true;
    },
    /**
     * Averages the samples into the resolved texture, then draws each
     * canvas pixel from it.
     * @param {{exposure:number, display:string, max:number, log:boolean}} view
     * @param {number} display the shader's display code
     */
    finish(view, display) {
      const [width, height] = size;
      gl.bindFramebuffer(gl.READ_FRAMEBUFFER, drawn.fbo);
      gl.bindFramebuffer(gl.DRAW_FRAMEBUFFER, resolved.fbo);
      gl.blitFramebuffer(0, 0, width, height, 0, 0, width, height, gl.COLOR_BUFFER_BIT, gl.NEAREST);
      gl.bindFramebuffer(gl.FRAMEBUFFER, null);
      gl.viewport(0, 0, width, height);
      gl.disable(gl.DEPTH_TEST);
      gl.useProgram(screen);
      gl.activeTexture(gl.TEXTURE0);
      gl.bindTexture(gl.TEXTURE_2D, resolved.texture);
      gl.uniform1i(loc.image, 0);
      gl.uniform1f(loc.scale, Math.pow(2, view.exposure));
      gl.uniform1i(loc.display, display);
      gl.uniform1f(loc.max, view.max > 0 && Number.isFinite(view.max) ? view.max : 1);
      gl.uniform1i(loc.log, view.log ? 1 : 0);
      gl.bindVertexArray(empty);
      gl.drawArrays(gl.TRIANGLES, 0, 3);
      gl.bindVertexArray(null);
    },
  };
}
