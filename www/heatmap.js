// The distortion colour scale: ‖JᵀJ − I‖² of a triangle (paper 3.1) on a log scale, from
// `lo` (isometric enough: the darkest colour) to `hi` (the brightest). The same stops are
// used by the shader (param-view.js) and the legend below, so they cannot disagree.
import { lengthErrorOf, percent } from './verdict.js';

/** Viridis, five stops: dark violet (isometric) → yellow (distorted). */
export const STOPS = [
  [0.267, 0.005, 0.329],
  [0.231, 0.322, 0.545],
  [0.129, 0.569, 0.549],
  [0.369, 0.788, 0.384],
  [0.992, 0.906, 0.145],
];

/**
 * The log10 range of the scale for a set of per-triangle distortions: from 1e-4 (below it
 * a map is isometric to the eye) to the decade above the largest value, at least 1e-1.
 * @param {number} max the largest distortion
 * @returns {[number, number]} [log10 lo, log10 hi]
 */
export function scaleRange(max) {
  const hi = Math.max(-1, Math.ceil(Math.log10(Math.max(max, 1e-12))));
  return [Math.min(-4, hi - 1), Math.min(hi, 4)];
}

/** The colour of t ∈ [0, 1] on the scale, as [r, g, b] in 0..1. */
export function colorAt(t) {
  const x = Math.min(1, Math.max(0, t)) * (STOPS.length - 1);
  const i = Math.min(STOPS.length - 2, Math.floor(x));
  const f = x - i;
  return STOPS[i].map((c, k) => c + f * (STOPS[i + 1][k] - c));
}

/** GLSL of `vec3 heat(float t)`, the same piecewise-linear scale. */
export function glslHeat() {
  const v = (c) => `vec3(${c.map((x) => x.toFixed(4)).join(', ')})`;
  const n = STOPS.length - 1;
  let body = `  float x = clamp(t, 0.0, 1.0) * ${n.toFixed(1)};\n`;
  for (let i = 0; i < n; i++) {
    const last = i === n - 1;
    body += `  ${last ? '' : `if (x < ${(i + 1).toFixed(1)}) `}return mix(${v(STOPS[i])}, ${v(STOPS[i + 1])}, x - ${i.toFixed(1)});\n`;
  }
  return `vec3 heat(float t) {\n${body}}\n`;
}

/**
 * Fills the legend element: a gradient bar with a tick per decade, the mean and max marked.
 * @param {HTMLElement} el
 * @param {[number, number]} range log10 lo, hi
 * @param {{mean: number, max: number, flipped: number}} distortion
 */
export function renderLegend(el, [lo, hi], distortion) {
  const gradient = STOPS.map((c, i) => `rgb(${c.map((x) => Math.round(x * 255)).join(',')}) ${(100 * i) / (STOPS.length - 1)}%`);
  el.replaceChildren();
  const title = document.createElement('div');
  title.className = 'legend-title';
  title.textContent = 'Distortion ‖JᵀJ − I‖² (log scale)';
  const bar = document.createElement('div');
  bar.className = 'legend-bar';
  bar.style.background = `linear-gradient(to right, ${gradient.join(', ')})`;
  const ticks = document.createElement('div');
  ticks.className = 'legend-ticks';
  const at = (value) => (100 * (Math.log10(Math.max(value, 1e-30)) - lo)) / (hi - lo);
  const every = Math.ceil((hi - lo) / 5);
  for (let d = hi; d >= lo; d -= every) {
    const tick = document.createElement('span');
    tick.style.left = `${(100 * (d - lo)) / (hi - lo)}%`;
    tick.textContent = d === 0 ? '1' : `1e${d}`;
    tick.style.transform = d === hi ? 'translateX(-100%)' : d === lo ? 'none' : 'translateX(-50%)';
    ticks.append(tick);
  }
  for (const [key, label] of [['mean', 'mean'], ['max', 'max']]) {
    const mark = document.createElement('span');
    mark.className = `legend-mark ${key}`;
    mark.style.left = `${Math.min(100, Math.max(0, at(distortion[key])))}%`;
    mark.title = `${label} ${distortion[key].toPrecision(3)}`;
    bar.append(mark);
  }
  const note = document.createElement('div');
  note.className = 'legend-note';
  note.textContent = `mean ${distortion.mean.toPrecision(3)} ▲ (lengths ≈ ${percent(lengthErrorOf(distortion.mean))} off) · max ${distortion.max.toPrecision(3)} △ · `;
  const flipped = document.createElement('span');
  flipped.className = 'legend-flipped';
  flipped.textContent = `${distortion.flipped} flipped`;
  flipped.title = 'triangles whose chart image is turned over, painted in this colour';
  note.append(flipped);
  el.append(title, bar, ticks, note);
}
