// Solving and looking: the "Parameterize & remesh" card. Runs the paper's loop in the
// worker one message per step (start = initial solve with unit charts, k chart-optimization
// iterations, finish = the final solve with the user's tags), with a progress bar and Cancel
// between steps (a long single step is cut short by restarting the worker, which gets the
// mesh and layout again); shows the result as a checkerboard or a distortion heat map on
// the surface, the charts in 2D, the three chart types side by side, and offers downloads.
// The page's thread only ever sets up three.js objects on arrays built in the worker.
//
// Adds to `window.quadlay` (see main.js):
//   solve    { state: 'idle'|'running'|'done'|'cancelled'|'error', step, total, label,
//              iteration, distortion: { mean, max, flipped }, error, ms }
//   param    the shown run: { chart, distortion, history, charts: [kind per face],
//              triangles (of the refined mesh), ms (page time from Solve to drawn) }
//   quads    the shown quad mesh: { vertices, faces, edge_length, ms } or null
//   result   the report of the last finished run (the CLI's --report JSON, cli.md, made by
//            the core: quads measured, seconds in the worker); null until the run is
//            complete (quad mesh extracted and measured), set once per run
//   paramReport  the partial report of the shown parameterization before (or without) its
//            quad mesh: the same JSON with `quads: null`

//   runs     after compareCharts(): { unit, rect, quad } each { distortion, history, ms }
//   run(options?) → Promise<report>: solve with the card's options, overridden by
//            { iterations, chart: 'quad'|'rect'|'unit'|'' , align, edge, quads }; rejects on
//            error (edge: the target quad edge length; quads: the target quad count instead)
//   cancel() stops the run in progress
//   compareCharts(options?) → Promise<runs>
//   remesh(edge?) → Promise<report>: the quad mesh of the shown run again (new edge length)
//   setView('surface'|'checker'|'distortion'|'quads'), showRun('unit'|'rect'|'quad'),
//   showCharts(bool) → Promise (settles when the chart panel is drawn)
//   exportFile('param-obj'|'cut-obj'|'quad-obj'|'quad-ply'|'quad-glb') → Promise<{ name, size }>
//            (also offered as a download)
//   setOptions({ iterations, chart, align, edge, quads }) fills the card's fields (edge and
//            quads exclude each other: setting one clears the other)
import { CoreError } from './client.js';
import { ChartPanel } from './chart-panel.js';
import { download, exportName, EXPORTS } from './export.js';
import { renderLegend, scaleRange } from './heatmap.js';
import { ParamView } from './param-view.js';
import { Verdict, lengthErrorOf, percent } from './verdict.js';

const $ = (id) => document.getElementById(id);
const CHARTS = ['unit', 'rect', 'quad'];
/** After Cancel, how long a step in flight may still take before the worker is restarted. */
const CANCEL_GRACE_MS = 250;

class Cancelled extends Error {
  constructor() {
    super('cancelled');
    this.name = 'Cancelled';
  }
}

export class Solver {
  /**
   * @param {{client: import('./client.js').CoreClient, viewer: import('./viewer.js').Viewer,
   *   quadlay: object, panel: object}} deps
   */
  constructor({ client, viewer, quadlay, panel }) {
    this.client = client;
    this.viewer = viewer;
    this.quadlay = quadlay;
    this.panel = panel;
    this.view = new ParamView(viewer);
    this.charts = new ChartPanel();
    this.verdict = new Verdict({ viewer, container: $('solve-progress') });
    this.legend = document.createElement('div');
    this.legend.className = 'legend';
    this.legend.id = 'legend';
    this.legend.hidden = true;
    $('viewport').append(this.legend);
    /** The run in progress: { cancelled, waiting } or null. */
    this.current = null;
    /** Shown results by chart type name ('' = the layout's own types), for switching. */
    this.results = new Map();
    this.shown = null;
    this.mode = 'checker';
    this.layoutReady = false;
    /** Solve again when the layout changes (set once a run finished on this mesh). */
    this.autoSolve = false;
    this.autoTimer = 0;
    this.layoutSeconds = 0;
    /** Called with every finished run's report (main.js hands its faces to the editor). */
    this.onResult = () => {};
    /** Surface area of the shown mesh (setMesh), for the edge length of a quad count. */
    this.area = 0;

    Object.assign(quadlay, {
      solve: { state: 'idle' },
      param: null,
      quads: null,
      result: null,
      paramReport: null,
      runs: null,
      remesh: (edge) => this.remeshShown(edge),
      run: (options) => this.run(options),
      cancel: () => this.cancel(),
      compareCharts: (options) => this.compare(options),
      setView: (mode) => this.setMode(mode),
      showRun: (name) => this.showRun(name),
      showCharts: (on = true) => this.showCharts(on),
      exportFile: (what) => this.exportFile(what),
      setOptions: (options) => this.setOptions(options),
    });

    client.onChange((event) => this.onCoreChange(event));
    this.wire();
  }

  // ---- controls ------------------------------------------------------------------------

  wire() {
    $('solve-run').addEventListener('click', () => this.run().catch(() => {}));
    $('solve-cancel').addEventListener('click', () => this.cancel());
    $('solve-compare').addEventListener('click', () => this.compare().catch(() => {}));
    for (const b of document.querySelectorAll('[data-param-view]')) {
      b.addEventListener('click', () => this.setMode(b.dataset.paramView));
    }
    $('charts-toggle').addEventListener('click', () => this.showCharts(!this.charts.visible));
    this.charts.onToggle = (on) => $('charts-toggle').setAttribute('aria-pressed', String(on));
    $('quads-toggle').addEventListener('click', () => {
      const on = $('quads-toggle').getAttribute('aria-pressed') !== 'true';
      $('quads-toggle').setAttribute('aria-pressed', String(on));
      this.view.setShowQuads(on);
    });
    // The edge length and the quad count say the same thing two ways: one of them is used.
    $('opt-edge').addEventListener('input', () => { $('opt-quads').value = ''; });
    $('opt-quads').addEventListener('input', () => { $('opt-edge').value = ''; });
    for (const id of ['opt-edge', 'opt-quads']) {
      $(id).addEventListener('change', () => {
        this.view.setCell(this.edgeLength());
        this.setPlaceholders();
        if (this.shown !== null && !this.current) this.remeshShown().catch(() => {});
      });
    }
    const exports = $('export-buttons');
    for (const [what, { label, title }] of Object.entries(EXPORTS)) {
      const b = document.createElement('button');
      b.type = 'button';
      b.className = 'button';
      b.dataset.export = what;
      b.textContent = label;
      b.title = `download ${title}`;
      b.addEventListener('click', () => this.exportFile(what).catch(() => {}));
      exports.append(b);
    }
  }

  /** The card's options. */
  options() {
    const iterations = Math.max(0, Math.min(50, Math.round(Number($('opt-iterations').value) || 0)));
    return {
      iterations,
      chart: $('opt-chart').value || '',
      align: $('opt-align').checked,
      edge: this.edgeLength(),
      quads: this.quadCount(),
    };
  }

  /** Fills the card's fields; unknown or empty values are left alone. */
  setOptions({ iterations, chart, align, edge, quads } = {}) {
    if (Number.isFinite(Number(iterations)) && iterations !== null && iterations !== '') $('opt-iterations').value = String(iterations);
    if (chart !== undefined && ['', 'quad', 'rect', 'unit'].includes(chart ?? '')) $('opt-chart').value = chart ?? '';
    if (typeof align === 'boolean') $('opt-align').checked = align;
    if (Number(edge) > 0) {
      $('opt-edge').value = String(edge);
      $('opt-quads').value = '';
    } else if (Number(quads) >= 1) {
      $('opt-quads').value = String(Math.round(Number(quads)));
      $('opt-edge').value = '';
    }
    this.view.setCell(this.edgeLength());
    this.setPlaceholders();
  }

  /** The target quad count typed in the card, or null. */
  quadCount() {
    const n = Math.round(Number($('opt-quads').value));
    return n >= 1 ? n : null;
  }

  /**
   * The quads the user asked for: the count typed, else that of the edge length typed (area /
   * edge², as the core computes it); null where neither was typed (the default density).
   */
  askedQuads() {
    const edge = this.typedEdge();
    return this.quadCount() ?? (edge && this.area > 0 ? Math.max(1, this.quadsAt(edge)) : null);
  }

  /** The target edge length typed in the card, or null. */
  typedEdge() {
    const typed = Number($('opt-edge').value);
    return typed > 0 ? typed : null;
  }

  /** About how many quads of edge length `edge` the shown mesh gets (area / edge²). */
  quadsAt(edge) {
    return Math.round(this.area / (edge * edge));
  }

  /**
   * The target edge length: the field's, else that of the quad count (√(area / quads), as
   * the core computes it), else 1/40 of the bounding-box diagonal.
   */
  edgeLength() {
    const typed = this.typedEdge();
    if (typed) return typed;
    const quads = this.quadCount();
    if (quads && this.area > 0) return Math.sqrt(this.area / quads);
    return this.defaultEdge();
  }

  /** The shown mesh's surface area (main.js measures it when the mesh is loaded). */
  setMeshArea(area) {
    this.area = area;
    this.setPlaceholders();
  }

  /** The empty fields show what the other one means: the edge length, the quad count. */
  setPlaceholders() {
    const edge = this.edgeLength();
    $('opt-edge').placeholder = this.quadlay.summary ? short(edge) : '';
    $('opt-quads').placeholder = this.area > 0 ? this.quadsAt(edge).toLocaleString('en-US') : '';
  }

  defaultEdge() {
    const box = this.quadlay.summary?.bounding_box;
    if (!box) return 1;
    const [lo, hi] = box;
    return Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]) / 40 || 1;
  }

  // ---- the worker's mesh and layout change ---------------------------------------------

  onCoreChange(event) {
    if (event.type === 'mesh') {
      this.stop('a new mesh');
      this.autoSolve = false;
      this.layoutReady = false;
      this.clearResults();
      $('opt-edge').value = '';
      $('solve-card').hidden = true;
    } else if (event.type === 'layout') {
      this.layoutReady = true;
      this.view.warmUp();
      $('solve-card').hidden = false;
      this.setPlaceholders();
      const wasRunning = Boolean(this.current);
      this.stop('the layout changed');
      this.clearResults();
      this.setButtons();
      // A changed layout solves again on the mesh the worker has (nothing reloaded).
      if (this.autoSolve || wasRunning) {
        clearTimeout(this.autoTimer);
        this.autoTimer = setTimeout(() => this.run().catch(() => {}), 800);
      }
    } else if (event.type === 'layout-error') {
      this.layoutReady = false;
      this.stop('the layout changed');
      this.clearResults();
      this.setButtons();
    }
  }

  clearResults() {
    this.results.clear();
    this.shown = null;
    this.view.clear();
    this.charts.set(null);
    this.legend.hidden = true;
    $('solve-results').hidden = true;
    $('compare-runs').hidden = true;
    $('solve-stats').replaceChildren();
    this.verdict.show(null);
    Object.assign(this.quadlay, { param: null, quads: null, result: null, paramReport: null, runs: null });
    this.hasQuads = false;
    $('quads-toggle').hidden = true;
    this.quadlay.solve = { state: 'idle' };
    $('solve-progress').hidden = true;
  }

  // ---- running -------------------------------------------------------------------------

  /**
   * Solves with the card's options (overridden by `overrides`) and shows the result.
   * @returns {Promise<object>} the report
   */
  async run(overrides = {}) {
    this.setOptions(overrides);
    const options = { ...this.options(), ...pick(overrides, ['iterations', 'chart', 'align']) };
    const steps = options.iterations + 2;
    return this.runJob(steps + 1, async (token, progress) => {
      const t0 = performance.now();
      const result = await this.solveOnce(options, options.chart, token, progress, 0);
      const ms = performance.now() - t0;
      this.results.clear();
      this.results.set(options.chart, { result, ms });
      $('compare-runs').hidden = true;
      this.quadlay.runs = null;
      await this.show(options.chart);
      this.quadlay.param.ms = performance.now() - t0;
      this.setProgress(steps, steps + 1, 'Extracting the quad mesh…', 'running');
      await this.remesh(token);
      return this.quadlay.result;
    });
  }

  /**
   * Solves with unit, rectangle and quad charts (paper Figs. 2 and 8), keeps all three and
   * shows the quad one; the buttons above the view switch between them.
   */
  async compare(overrides = {}) {
    this.setOptions(overrides);
    const options = { ...this.options(), ...pick(overrides, ['iterations', 'align']) };
    const steps = options.iterations + 2;
    return this.runJob(3 * steps + 1, async (token, progress) => {
      this.results.clear();
      for (const [i, chart] of CHARTS.entries()) {
        const t0 = performance.now();
        const result = await this.solveOnce(options, chart, token, progress, i * steps, `${chart} charts: `);
        this.results.set(chart, { result, ms: performance.now() - t0 });
        await this.client.keepParam(chart);
      }
      await this.client.useParam('quad');
      this.quadlay.runs = Object.fromEntries(
        [...this.results].map(([k, { result, ms }]) => [k, { distortion: result.distortion, history: result.history, ms }]),
      );
      this.renderCompare();
      await this.show('quad');
      await this.remesh(token);
      return this.quadlay.runs;
    });
  }

  /** Runs `job(token, progress)` as the one run in progress, with progress and Cancel. */
  async runJob(total, job) {
    if (!this.layoutReady) {
      const err = new Error('place a valid layout on the mesh first');
      this.fail(err);
      throw err;
    }
    this.stop('a new run');
    clearTimeout(this.autoTimer);
    // The worker's active run is replaced at once: what is shown must not outlive it (a
    // cancelled run would leave a picture whose exports are another run's).
    this.clearResults();
    const token = { cancelled: false, waiting: false };
    this.current = token;
    const t0 = performance.now();
    this.quadlay.solve = { state: 'running', step: 0, total, label: 'starting' };
    this.setButtons();
    this.setProgress(0, total, 'Starting…', 'running');
    const progress = (step, label, stats) => {
      const d = stats.distortion;
      Object.assign(this.quadlay.solve, { step, label, iteration: stats.iteration, distortion: d });
      this.setProgress(step, total, `${label} · lengths ≈ ${percent(lengthErrorOf(d.mean))} off (mean ${fmtD(d.mean)} · max ${fmtD(d.max)} · ${d.flipped} flipped)`, 'running');
    };
    try {
      const report = await job(token, progress);
      if (this.current !== token) throw new Cancelled();
      const ms = performance.now() - t0;
      this.quadlay.solve = { ...this.quadlay.solve, state: 'done', step: total, ms };
      // Not a plain "done" when the core warns about the result (the verdict lists why).
      const warned = this.quadlay.result?.warnings?.length > 0;
      this.setProgress(total, total, `Done in ${(ms / 1000).toFixed(1)} s`, warned ? 'warn' : 'done');
      this.autoSolve = true;
      this.panel.setStatus('ready', `Solved in ${(ms / 1000).toFixed(1)} s`);
      return report;
    } catch (err) {
      if (token.cancelled || err instanceof Cancelled) {
        if (this.current === token || this.current === null) {
          this.quadlay.solve = { ...this.quadlay.solve, state: 'cancelled' };
          this.setProgress(this.quadlay.solve.step ?? 0, total, `Cancelled (${token.reason || 'by you'})`, 'cancelled');
        }
        throw new Cancelled();
      }
      this.fail(err);
      throw err;
    } finally {
      if (this.current === token) this.current = null;
      this.setButtons();
    }
  }

  /** One parameterization: start, iterations, finish; reports progress after each. */
  async solveOnce(options, chart, token, progress, base, prefix = '') {
    const step = async (promise) => {
      token.waiting = true;
      try {
        return await promise;
      } finally {
        token.waiting = false;
        if (token.cancelled) throw new Cancelled();
      }
    };
    let stats = await step(this.client.startParam({ align: options.align, chart: chart || null }));
    progress(base + 1, `${prefix}initial solve`, stats);
    for (let k = 1; k <= options.iterations; k++) {
      stats = await step(this.client.stepParam());
      progress(base + 1 + k, `${prefix}iteration ${k}/${options.iterations}`, stats);
    }
    const result = await step(this.client.finishParam());
    progress(base + options.iterations + 2, `${prefix}final solve`, { iteration: stats.iteration, distortion: result.distortion });
    return result;
  }

  /**
   * Extracts and shows the quad mesh of the active run. An extraction error is shown, but
   * the parameterization stays (it is fine; the layout's counts or the edge length are not).
   */
  async remesh(token = null) {
    const edge = this.edgeLength();
    const quads = this.quadCount();
    const t0 = performance.now();
    let q;
    try {
      if (token) token.waiting = true;
      // A quad count goes to the core as it is (it knows the surface area exactly).
      q = await this.client.remesh(quads ? { quads } : { edge_length: edge });
    } catch (err) {
      if (token?.cancelled) throw new Cancelled();
      this.view.setQuads(null);
      this.verdict.show(null);
      this.hasQuads = false;
      $('quads-toggle').hidden = true;
      this.quadlay.quads = null;
      throw Object.assign(new Error(`no quad mesh: ${err?.message || err}`), { title: 'Could not extract the quad mesh' });
    } finally {
      if (token) token.waiting = false;
    }
    if (token?.cancelled) throw new Cancelled();
    this.view.setQuads(q);
    this.hasQuads = true;
    $('quads-toggle').hidden = false;
    const ms = performance.now() - t0;
    this.quadlay.quads = { vertices: q.vertices, faces: q.faces, edge_length: edge, ms };
    this.quadlay.result = q.report;
    this.verdict.show(q.report);
    this.onResult(q.report);
    this.renderStats(this.results.get(this.shown).result, this.results.get(this.shown).ms, q.report);
    this.setButtons();
    await this.viewer.nextFrame();
    return q.report;
  }

  /** The quad mesh of the shown run again, e.g. for a new edge length. */
  async remeshShown(edge) {
    if (edge !== undefined) this.setOptions({ edge });
    if (this.shown === null) throw new Error('solve first');
    try {
      return await this.remesh();
    } catch (err) {
      this.fail(err);
      throw err;
    }
  }

  /** Cancels the run in progress (between steps; a long step restarts the worker). */
  cancel(reason = '') {
    const token = this.current;
    if (!token) return;
    token.cancelled = true;
    token.reason = reason;
    this.setProgress(this.quadlay.solve.step ?? 0, this.quadlay.solve.total ?? 1, 'Cancelling…', 'running');
    setTimeout(() => {
      if (token.waiting) this.client.restart('cancelled');
    }, CANCEL_GRACE_MS);
  }

  /**
   * Drops the run in progress, e.g. because the mesh or layout changed under it: its step
   * in flight finishes in the worker, but nothing more is asked and nothing shown.
   */
  stop(reason) {
    const token = this.current;
    if (!token) return;
    token.cancelled = true;
    token.reason = reason;
    this.current = null;
  }

  fail(err) {
    const message = err?.message || String(err);
    this.quadlay.solve = { ...this.quadlay.solve, state: 'error', error: message };
    this.quadlay.error = message;
    this.setProgress(this.quadlay.solve.step ?? 0, this.quadlay.solve.total ?? 1, message, 'error');
    this.panel.showError(err?.title || 'Could not parameterize', message);
    this.panel.setStatus('error', err?.title ? 'Quad extraction failed' : 'Parameterization failed');
  }

  // ---- showing -------------------------------------------------------------------------

  /** Shows the kept result `name` (a chart type, or '' for the layout's own types). */
  async show(name) {
    const { result, ms } = this.results.get(name);
    this.shown = name;
    const range = scaleRange(result.distortion.max);
    this.range = range;
    this.view.setCell(this.edgeLength());
    this.view.setParam(result, range);
    if (this.mode === 'surface') this.mode = 'checker';
    this.setMode(this.mode);
    renderLegend(this.legend, range, result.distortion);
    const kinds = result.charts.map((c) => c.kind);
    this.charts.set(result, range, `${name ? `${name} charts` : 'charts as the layout says'} · mean ${fmtD(result.distortion.mean)}`);
    this.renderStats(result, ms);
    $('solve-results').hidden = false;
    for (const b of $('compare-runs').querySelectorAll('button')) b.setAttribute('aria-checked', String(b.dataset.run === name));
    this.quadlay.param = {
      chart: name || null,
      distortion: result.distortion,
      history: result.history,
      charts: kinds,
      triangles: result.triangles,
      ms,
    };
    this.quadlay.paramReport = this.report(result);
    this.panel.hideError();
    await this.viewer.nextFrame();
  }

  async showRun(name) {
    if (!this.results.has(name) || this.current) return false;
    const previous = this.shown;
    // The shown run's report goes until this one's quad mesh is measured.
    Object.assign(this.quadlay, { result: null, quads: null });
    if (previous !== name) await this.client.useParam(name, previous);
    await this.show(name);
    await this.remeshShown().catch(() => {});
    return true;
  }

  renderCompare() {
    const box = $('compare-runs');
    box.replaceChildren();
    for (const chart of CHARTS) {
      const entry = this.results.get(chart);
      if (!entry) continue;
      const b = document.createElement('button');
      b.type = 'button';
      b.setAttribute('role', 'radio');
      b.dataset.run = chart;
      const d = entry.result.distortion;
      b.title = `show the ${chart}-chart result: lengths on the surface and in the charts differ by about `
        + `${percent(lengthErrorOf(d.mean))} (mean ‖JᵀJ − I‖² ${fmtD(d.mean)}); ${d.flipped} triangles are flipped `
        + '(turned over in their chart, where quads fold)';
      b.append(chart);
      const small = document.createElement('small');
      small.textContent = `≈${percent(lengthErrorOf(d.mean))} · ${d.flipped} flipped`;
      b.append(small);
      b.addEventListener('click', () => this.showRun(chart).catch((err) => this.fail(err)));
      box.append(b);
    }
    box.hidden = false;
  }

  /** @param {'surface'|'checker'|'distortion'|'quads'} mode */
  setMode(mode) {
    this.mode = mode;
    this.view.setMode(this.results.size ? mode : 'surface');
    for (const b of document.querySelectorAll('[data-param-view]')) b.setAttribute('aria-checked', String(b.dataset.paramView === mode));
    this.legend.hidden = !(mode === 'distortion' && this.view.hasParam);
  }

  async showCharts(on) {
    this.charts.show(on);
    return this.charts.drawn;
  }

  renderStats(result, ms, report = null) {
    const d = result.distortion;
    const measured = report?.parameterization?.length_error;
    const rows = [
      ['Iterations', String(result.history.length - 1)],
      ['Length error', Number.isFinite(measured) ? `${percent(measured)} typical` : `≈ ${percent(lengthErrorOf(d.mean))} typical`,
        'how much lengths on the surface and in the charts differ (area-weighted root mean square): what the quads inherit as uneven sizes'],
      ['Distortion mean', fmtD(d.mean), 'area-weighted mean of ‖JᵀJ − I‖² (the paper\'s measure; about 8 × the squared length error)'],
      ['Distortion max', fmtD(d.max), 'the largest ‖JᵀJ − I‖² of a triangle'],
      ['Flipped triangles', String(d.flipped), 'triangles turned over in their chart: the quads there fold'],
      ['Refined triangles', new Intl.NumberFormat('en-US').format(result.triangles)],
      ['Solve time', `${(ms / 1000).toFixed(2)} s`],
    ];
    if (report) {
      const q = report.quads;
      const fmt = new Intl.NumberFormat('en-US');
      rows.push(['Quads', fmt.format(q.faces)], ['Quad vertices', fmt.format(q.vertices)], ['Irregular vertices', fmt.format(q.irregular_vertices)]);
      if (Number.isFinite(q.hausdorff)) {
        rows.push(['Surface distance', `${percent(q.hausdorff, 2)} of the diagonal`,
          'Hausdorff distance between the quad mesh and the input, both ways, over the bounding-box diagonal']);
      }
      if (q.flipped_quads !== undefined) rows.push(['Flipped quads', fmt.format(q.flipped_quads)]);
      if (q.angle_deviation_mean_deg !== undefined) rows.push(['Angle deviation', `${q.angle_deviation_mean_deg.toFixed(1)}° mean`]);
      rows.push(['Extraction time', `${report.seconds.mesh.toFixed(2)} s`]);
    }
    const dl = $('solve-stats');
    dl.replaceChildren();
    for (const [k, v, title] of rows) {
      const dt = document.createElement('dt');
      const dd = document.createElement('dd');
      dt.textContent = k;
      dd.textContent = v;
      if (title) dt.title = dd.title = title;
      dd.dataset.key = k.toLowerCase().replace(/ /g, '_');
      dl.append(dt, dd);
    }
  }

  /** The report of cli.md for the shown run (quads once the quad mesh exists). */
  report(result) {
    const s = this.quadlay.summary ?? {};
    const l = this.quadlay.layout ?? {};
    const parameterize = result.history.reduce((a, h) => a + h.seconds, 0);
    return {
      input: { vertices: s.vertices, triangles: s.triangles },
      layout: { nodes: l.nodes, edges: l.edges, faces: l.faces, t_vertices: l.t_vertices },
      iterations: result.history.map((h) => ({ iteration: h.iteration, distortion: h.distortion.mean, seconds: h.seconds })),
      parameterization: {
        distortion_mean: result.distortion.mean,
        distortion_max: result.distortion.max,
        flipped_triangles: result.distortion.flipped,
      },
      quads: null,
      seconds: {
        load: result.seconds.load,
        layout: result.seconds.layout,
        parameterize,
        mesh: 0,
        total: result.seconds.load + result.seconds.layout + parameterize,
      },
    };
  }

  // ---- files ---------------------------------------------------------------------------

  async exportFile(what) {
    if (!EXPORTS[what]) throw new Error(`unknown export '${what}'`);
    try {
      const { bytes, mime } = await this.client.exportFile(what);
      const name = exportName(this.quadlay.name, what);
      download(bytes, name, mime);
      this.panel.setStatus('ready', `Saved ${name} (${new Intl.NumberFormat('en-US').format(bytes.byteLength)} bytes)`);
      return { name, size: bytes.byteLength };
    } catch (err) {
      this.panel.showError(`Could not export ${EXPORTS[what].label}`, err?.message || String(err));
      throw err;
    }
  }

  // ---- the card's state ----------------------------------------------------------------

  setButtons() {
    const running = Boolean(this.current);
    $('solve-run').disabled = running || !this.layoutReady;
    $('solve-compare').disabled = running || !this.layoutReady;
    $('solve-cancel').hidden = !running;
    $('solve-run').title = this.layoutReady ? 'parameterize with these options' : 'place a valid layout first';
    for (const b of document.querySelectorAll('[data-export]')) {
      b.disabled = running || (b.dataset.export.startsWith('quad') && !this.hasQuads);
    }
  }

  setProgress(step, total, text, state) {
    $('solve-progress').hidden = false;
    $('solve-progress').dataset.state = state;
    $('solve-bar').style.width = `${Math.round((100 * step) / Math.max(total, 1))}%`;
    $('solve-progress-text').textContent = text;
  }
}

function pick(obj, keys) {
  return Object.fromEntries(keys.filter((k) => obj[k] !== undefined).map((k) => [k, obj[k]]));
}

/** A distortion, three significant digits. */
function fmtD(x) {
  if (!Number.isFinite(x)) return String(x);
  if (x === 0) return '0';
  return Math.abs(x) >= 1e-3 && Math.abs(x) < 1e4 ? String(Number(x.toPrecision(3))) : x.toExponential(2);
}

function short(x) {
  return String(Number(x.toPrecision(3)));
}

export { CoreError };
