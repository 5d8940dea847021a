// The charts in 2D (paper Fig. 9): every layout face's chart quadrilateral (from its four
// corners) with the face's triangles at their uv inside it, laid out side by side at one
// common scale, so sizes and shapes compare. Drawn on a canvas in a floating panel; the
// triangles are drawn in slices, one slice per task, so a big mesh never blocks the page.
import { colorAt } from './heatmap.js';

const PALETTE = ['#9ad0ec', '#f6c28b', '#b5e2a0', '#e7a9c9', '#cdb4f0', '#f3e58c', '#9fe0d3', '#f2a89b',
  '#a9bff5', '#d7e89a', '#f0b9e8', '#8fd6b4'];
/** Triangles drawn per task. */
const SLICE = 1500;

export class ChartPanel {
  constructor() {
    const pane = document.createElement('section');
    pane.className = 'chart-pane';
    pane.id = 'chart-pane';
    pane.setAttribute('aria-label', 'Charts');
    pane.hidden = true;
    pane.innerHTML = `
      <header class="chart-pane-head">
        <h2>Charts <span class="chart-pane-note" id="chart-pane-note"></span></h2>
        <div class="segmented" role="radiogroup" aria-label="Chart scale">
          <button type="button" role="radio" data-chart-scale="common" aria-checked="true" title="all charts at one scale: sizes compare">One scale</button>
          <button type="button" role="radio" data-chart-scale="each" aria-checked="false" title="every chart fills its cell: shapes are easier to see">Fit each</button>
        </div>
        <div class="segmented" role="radiogroup" aria-label="Triangle colours">
          <button type="button" role="radio" data-chart-fill="face" aria-checked="true">Faces</button>
          <button type="button" role="radio" data-chart-fill="distortion" aria-checked="false">Distortion</button>
        </div>
        <button type="button" class="chart-pane-close" id="chart-pane-close" aria-label="Close the charts">×</button>
      </header>`;
    this.canvas = document.createElement('canvas');
    this.canvas.className = 'chart-canvas';
    this.canvas.width = 560;
    this.canvas.height = 400;
    pane.append(this.canvas);
    document.body.append(pane);
    this.pane = pane;
    // A CPU canvas: every slice is drawn when it runs (an accelerated one records them all
    // and rasterizes them in one go at the next paint, seconds for a big mesh).
    this.ctx = this.canvas.getContext('2d', { willReadFrequently: true });
    // Its backing store is made at the first drawing, a quarter of a second in headless
    // Chromium: made while the page is idle, not when the user first opens the panel.
    const warm = () => this.ctx.fillRect(0, 0, 1, 1);
    if (window.requestIdleCallback) requestIdleCallback(warm);
    else setTimeout(warm, 0);
    this.fill = 'face';
    /** 'common': one scale for all charts; 'each': every chart fills its cell. */
    this.scaleMode = 'common';
    this.data = null;
    this.drawing = 0;
    /** Settles when the last draw has finished (for tests). */
    this.drawn = Promise.resolve();
    pane.querySelector('#chart-pane-close').addEventListener('click', () => this.show(false));
    for (const b of pane.querySelectorAll('[data-chart-fill]')) {
      b.addEventListener('click', () => {
        this.fill = b.dataset.chartFill;
        for (const o of pane.querySelectorAll('[data-chart-fill]')) o.setAttribute('aria-checked', String(o === b));
        this.draw();
      });
    }
    for (const b of pane.querySelectorAll('[data-chart-scale]')) {
      b.addEventListener('click', () => {
        this.scaleMode = b.dataset.chartScale;
        for (const o of pane.querySelectorAll('[data-chart-scale]')) o.setAttribute('aria-checked', String(o === b));
        this.draw();
      });
    }
    this.onToggle = null;
  }

  get visible() {
    return !this.pane.hidden;
  }

  show(on) {
    this.pane.hidden = !on;
    this.onToggle?.(on);
    if (on) this.draw();
  }

  /**
   * @param {{charts: {kind: string, corners: number[][]}[], uv: Float32Array, face: Uint32Array,
   *   triangleDistortion: Float32Array}|null} data
   * @param {[number, number]} range the heat map's log10 ends
   * @param {string} note e.g. 'quad charts'
   */
  set(data, range, note = '') {
    this.data = data;
    this.range = range;
    this.pane.querySelector('#chart-pane-note').textContent = note;
    if (this.visible) this.draw();
  }

  /** Draws everything again; returns a promise that settles when the last slice is drawn. */
  draw() {
    const run = ++this.drawing;
    const ctx = this.ctx;
    const { width: W, height: H } = this.canvas;
    ctx.fillStyle = '#171a20';
    ctx.fillRect(0, 0, W, H);
    const data = this.data;
    if (!data) return (this.drawn = Promise.resolve());
    const n = data.charts.length;
    const cols = Math.ceil(Math.sqrt((n * W) / H));
    const rows = Math.ceil(n / cols);
    const cw = W / cols, ch = H / rows;
    const pad = 14;
    // One scale for all charts (from the largest extent), or one per chart.
    const extents = data.charts.map((c) => {
      const xs = c.corners.map((p) => p[0]), ys = c.corners.map((p) => p[1]);
      const box = [Math.min(...xs), Math.min(...ys), Math.max(...xs), Math.max(...ys)];
      return { box, extent: Math.max((box[2] - box[0]) / (cw - 2 * pad), (box[3] - box[1]) / (ch - 2 * pad - 12)) };
    });
    const common = Math.max(...extents.map((e) => e.extent));
    // Chart f's uv → canvas: centred in its cell, v up.
    const frames = extents.map(({ box: b, extent }, f) => {
      const e = this.scaleMode === 'each' ? extent : common;
      const scale = e > 0 ? 1 / e : 1;
      const cx = (f % cols) * cw + cw / 2, cy = Math.floor(f / cols) * ch + ch / 2 + 6;
      const mx = (b[0] + b[2]) / 2, my = (b[1] + b[3]) / 2;
      return [cx - mx * scale, cy + my * scale, scale];
    });
    const X = (f, u) => frames[f][0] + u * frames[f][2];
    const Y = (f, v) => frames[f][1] - v * frames[f][2];

    // Chart quads, filled faintly, with their kind.
    ctx.font = '11px system-ui, sans-serif';
    ctx.textAlign = 'center';
    data.charts.forEach((c, f) => {
      ctx.beginPath();
      c.corners.forEach((p, k) => (k ? ctx.lineTo(X(f, p[0]), Y(f, p[1])) : ctx.moveTo(X(f, p[0]), Y(f, p[1]))));
      ctx.closePath();
      ctx.fillStyle = 'rgba(255,255,255,0.04)';
      ctx.fill();
      ctx.fillStyle = '#8d96a5';
      ctx.fillText(`${f} · ${c.kind}`, (f % cols) * cw + cw / 2, Math.floor(f / cols) * ch + 12);
    });

    const outline = () => {
      ctx.lineWidth = 2;
      ctx.strokeStyle = '#ff9d2e';
      data.charts.forEach((c, f) => {
        ctx.beginPath();
        c.corners.forEach((p, k) => (k ? ctx.lineTo(X(f, p[0]), Y(f, p[1])) : ctx.moveTo(X(f, p[0]), Y(f, p[1]))));
        ctx.closePath();
        ctx.stroke();
        ctx.fillStyle = '#ff4d6d';
        for (const p of c.corners) ctx.fillRect(X(f, p[0]) - 2.5, Y(f, p[1]) - 2.5, 5, 5);
      });
    };

    const { uv, face, triangleDistortion: distortion } = data;
    const total = face.length;
    const [lo, hi] = this.range ?? [-4, 1];
    const byDistortion = this.fill === 'distortion';
    const drawSlice = (start) => {
      const end = Math.min(total, start + SLICE);
      ctx.lineWidth = 0.5;
      for (let t = start; t < end; t++) {
        const f = face[t];
        const o = 6 * t;
        ctx.beginPath();
        ctx.moveTo(X(f, uv[o]), Y(f, uv[o + 1]));
        ctx.lineTo(X(f, uv[o + 2]), Y(f, uv[o + 3]));
        ctx.lineTo(X(f, uv[o + 4]), Y(f, uv[o + 5]));
        ctx.closePath();
        let color;
        const signed = (uv[o + 2] - uv[o]) * (uv[o + 5] - uv[o + 1]) - (uv[o + 3] - uv[o + 1]) * (uv[o + 4] - uv[o]);
        if (byDistortion && signed <= 0) {
          color = '#ff296b'; // flipped, as in the heat map
        } else if (byDistortion) {
          const c = colorAt((Math.log10(Math.max(distortion[t], 1e-30)) - lo) / (hi - lo));
          color = `rgb(${Math.round(c[0] * 255)},${Math.round(c[1] * 255)},${Math.round(c[2] * 255)})`;
        } else {
          color = PALETTE[f % PALETTE.length];
        }
        ctx.fillStyle = color;
        ctx.globalAlpha = byDistortion ? 1 : 0.55;
        ctx.fill();
        ctx.globalAlpha = 1;
        ctx.strokeStyle = 'rgba(10,12,16,0.35)';
        ctx.stroke();
      }
      return end;
    };
    this.drawn = new Promise((resolve) => {
      const next = (start) => {
        if (run !== this.drawing) return resolve(false);
        const end = drawSlice(start);
        if (end < total) setTimeout(() => next(end), 0);
        else {
          outline();
          resolve(true);
        }
      };
      next(0);
    });
    return this.drawn;
  }
}
