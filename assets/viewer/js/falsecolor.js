// False colour: the banded viridis scale of `isorad`'s false-colour
// pictures (src/calculation/falsecolor_scale.rs), for the viewer's shader
// and its legend.
//
// A value v on a scale up to `max` with `steps` bands falls in band
//
//   b = floor(t · steps), clamped to 0 … steps − 1,
//   t = v / max                      (linear)
//   t = 1 + log10(v / max) / 3       (log: the 3 decades below max)
//
// and is painted viridis(b / (steps − 1)). The band is chosen per pixel in
// the fragment shader (FALSE_COLOUR_GLSL); the band colours are computed
// here once, rounded to 8 bits as the Rust scale rounds them, and passed to
// the shader as a uniform array, so the legend and the picture agree.

/** Bands of the scale. */
export const STEPS = 8;

/** Decades below the maximum a log scale spans. */
export const LOG_DECADES = 3;

/** Lumens per watt of the luminous-efficacy convention: cd/m² = 179 · Y. */
export const EFFICACY = 179;

/** Viridis at 0, 1/8, …, 1 (8-bit sRGB). */
export const VIRIDIS = [
  [68, 1, 84],
  [71, 45, 123],
  [59, 82, 139],
  [44, 114, 142],
  [33, 144, 140],
  [39, 173, 129],
  [93, 200, 99],
  [170, 220, 50],
  [253, 231, 37],
];

/**
 * Viridis at s in [0, 1] (clamped; NaN counts as 0), 8-bit: linear
 * interpolation between the nine colours 1/8 apart, rounded.
 * @param {number} s
 * @returns {number[]} [r, g, b] in 0…255
 */
export function viridis(s) {
  const scaled = (Number.isNaN(s) ? 0 : Math.min(Math.max(s, 0), 1)) * 8;
  const below = Math.min(Math.floor(scaled), 7);
  const f = scaled - below;
  const a = VIRIDIS[below];
  const b = VIRIDIS[below + 1];
  return [0, 1, 2].map((k) => Math.round(a[k] + f * (b[k] - a[k])));
}

/**
 * The colour of band b: viridis(b / (steps − 1)), 8-bit.
 * @param {number} band 0 … steps − 1
 * @returns {number[]}
 */
export function bandColour(band) {
  return viridis(band / (STEPS - 1));
}

/**
 * The band colours as a flat Float32Array of steps × 3 values in [0, 1],
 * for the shader's uniform vec3 array.
 * @returns {Float32Array}
 */
export function bandColoursUniform() {
  const out = new Float32Array(STEPS * 3);
  for (let b = 0; b < STEPS; b++) {
    const c = bandColour(b);
    out.set([c[0] / 255, c[1] / 255, c[2] / 255], 3 * b);
  }
  return out;
}

/**
 * The band of a value (the shader's rule, for tests and the probe):
 * floor(t · steps) clamped to 0 … steps − 1, NaN to 0.
 * @param {number} value
 * @param {number} max
 * @param {boolean} log
 * @returns {number}
 */
export function bandOf(value, max, log) {
  const t = log ? 1 + Math.log10(value / max) / LOG_DECADES : value / max;
  if (Number.isNaN(t)) return 0;
  return Math.min(Math.max(Math.floor(t * STEPS), 0), STEPS - 1);
}

/**
 * The values between the bands, bottom to top (steps + 1 of them):
 * max · i / steps (linear) or max · 10^(−3 · (1 − i / steps)) (log).
 * @param {number} max
 * @param {boolean} log
 * @returns {number[]}
 */
export function legendBoundaries(max, log) {
  const out = [];
  for (let i = 0; i <= STEPS; i++) {
    const t = i / STEPS;
    out.push(log ? max * Math.pow(10, -LOG_DECADES * (1 - t)) : max * t);
  }
  return out;
}

/**
 * A number to 3 significant digits without exponent for 1e-3 ≤ |v| < 1e6:
 * 1234 → "1230", 12.345 → "12.3", 0.01234 → "0.0123".
 * @param {number} v
 * @returns {string}
 */
export function format3(v) {
  if (!Number.isFinite(v)) return String(v);
  if (v === 0) return '0';
  const a = Math.abs(v);
  if (a < 1e-3 || a >= 1e6) return v.toExponential(2);
  const digits = Math.floor(Math.log10(a));
  if (digits >= 2) {
    const unit = Math.pow(10, digits - 2);
    return String(Math.round(v / unit) * unit);
  }
  return v.toFixed(2 - digits);
}

/**
 * GLSL ES 3.00 source of
 *   vec3 falseColour(float value, float maxValue, bool logScale)
 * using the uniform `u_bandColours[STEPS]`. log10 x = log2 x · log10 2.
 * Values ≤ 0 on a log scale and NaN go to band 0.
 */
export const FALSE_COLOUR_GLSL = `
const int FC_STEPS = ${STEPS};
uniform vec3 u_bandColours[FC_STEPS];
vec3 falseColour(float value, float maxValue, bool logScale) {
  float t;
  if (logScale) {
    t = value > 0.0
      ? 1.0 + log2(value / maxValue) * 0.30102999566398120 / ${LOG_DECADES.toFixed(1)}
      : -1.0;
  } else {
    t = value / maxValue;
  }
  if (!(t == t)) t = 0.0;
  int band = int(clamp(floor(t * float(FC_STEPS)), 0.0, float(FC_STEPS - 1)));
  return u_bandColours[band];
}
`;
