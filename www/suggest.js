// The "Automatic layout" card: asks the core for a coarse quad layout made from the mesh's
// cross field (issue 22; the command line's `quadlay layout`) and places it into the editor
// as one undoable edit, so the user starts from it and edits it like their own (Ctrl+Z
// returns the previous layout). It also switches the field view (field-view.js) on and off.
//
// The core makes one proposal per tracing (along the field, along the iso-lines of its two
// seamless parameterizations, along the smoothest field and along two fields in smoothed
// frames) and keeps the best. With more than one processor they are made at once in WORKERS
// workers: helper workers beside the page's load the mesh too, and the core picks the one it
// would have kept (the same layout as one request makes). The progress line counts the seconds, and Cancel
// stops the helpers and restarts the page's worker (it gets the mesh and the placed layout
// again), as the solve's Cancel does for a long step.
//
// Adds to `window.quadlay` (see main.js):
//   suggestion  { state: 'idle'|'running'|'done'|'cancelled'|'error', error, seconds (in the
//               workers), faces (of the placed proposal), ms (page time from click to
//               checked), workers (how many made the proposals at once), proposals (how many
//               the workers made and judged, one per tracing; null where one request made
//               them all) }
//   suggest(options?) → Promise<layout summary>: proposes with the card's options overridden
//               by { patches: number|null, featureAngle: number }, places it as one edit;
//               rejects with the core's error in words
//   cancelSuggest() stops a proposal in progress
//   showField(on = true) → Promise<field summary|null>: the field view on or off
//   field       what the field view shows: { vertices, crosses, singularities: { 3: n, 5: n,
//               other: n } } or null while it is off
import { FieldView } from './field-view.js';
import { parseDoc } from './layout-doc.js';

const DEFAULT_FEATURE_ANGLE = 35;
/**
 * The workers a proposal runs in where there is more than one processor, each making the
 * tracings j, j + WORKERS, … of the core's six. Three on two processors beat two (measured
 * when the core had three tracings, bunny_28k in headless Chromium on two cores: 26.2 s in
 * one worker, 22.0 s in two, 19.7 s in three); each worker holds the mesh, so no more.
 */
const WORKERS = 3;

class Cancelled extends Error {
  constructor() {
    super('cancelled');
    this.name = 'Cancelled';
  }
}

/** Terminates the helper workers of a proposal (`token.helpers`: promises of their clients). */
function stopHelpers(token) {
  for (const h of token.helpers ?? []) h.then((client) => client.terminate(), () => {});
}

export class Suggester {
  /**
   * @param {object} o
   * @param {import('./client.js').CoreClient} o.client
   * @param {import('./editor.js').Editor} o.editor where the proposal is placed
   * @param {import('./viewer.js').Viewer} o.viewer
   * @param {object} o.quadlay `window.quadlay`
   * @param {HTMLElement} o.after the panel card this card goes after
   * @param {() => number|null} [o.askedQuads] the quads the Solve card asks for, or null
   */
  constructor({ client, editor, viewer, quadlay, after, askedQuads = () => null }) {
    this.client = client;
    /** The quads the user asked for in the Solve card, or null (the proposals are judged at them). */
    this.askedQuads = askedQuads;
    this.editor = editor;
    this.quadlay = quadlay;
    this.field = new FieldView(viewer, document.getElementById('viewport'));
    /** The proposal in progress: { cancelled } or null. */
    this.current = null;
    this.timer = 0;
    this.createUi(after);
    Object.assign(quadlay, {
      suggestion: { state: 'idle' },
      field: null,
      suggest: (options) => this.suggest(options),
      cancelSuggest: () => this.cancel(),
      showField: (on = true) => this.showField(on),
    });
    client.onChange((event) => {
      if (event.type !== 'mesh') return;
      this.stop();
      this.card.hidden = false;
      this.setMessage('', null);
      this.quadlay.suggestion = { state: 'idle' };
      // The field view follows the new mesh.
      if (this.field.visible) this.showField(true).catch(() => {});
    });
  }

  createUi(after) {
    const el = (tag, props = {}, ...children) => {
      const e = Object.assign(document.createElement(tag), props);
      e.append(...children);
      return e;
    };
    const card = el('section', { className: 'card suggest-card', id: 'suggest-card', hidden: true });
    card.setAttribute('aria-labelledby', 'suggest-title');
    const patches = el('input', { type: 'number', id: 'opt-patches', min: 1, step: 1, placeholder: 'auto' });
    patches.title = 'about how many faces the layout should have (empty: as many as the field gives)';
    const angle = el('input', { type: 'number', id: 'opt-feature-angle', min: 0, max: 180, step: 1, value: DEFAULT_FEATURE_ANGLE });
    angle.title = 'mesh edges whose dihedral angle exceeds this (degrees) are sharp features: layout edges follow them and are tagged';
    const form = el('div', { className: 'solve-form' },
      el('label', { htmlFor: 'opt-patches', textContent: 'Patches' }), patches,
      el('label', { htmlFor: 'opt-feature-angle', textContent: 'Feature angle' }), angle);
    const run = el('button', { type: 'button', className: 'button primary', id: 'suggest-run', textContent: 'Suggest layout' });
    run.title = 'a coarse quad layout from the mesh\'s cross field, placed as one edit (Ctrl+Z takes it back)';
    const cancel = el('button', { type: 'button', className: 'button', id: 'suggest-cancel', textContent: 'Cancel', hidden: true });
    const fieldToggle = el('button', { type: 'button', className: 'tool', id: 'field-toggle', textContent: 'Field view' });
    fieldToggle.setAttribute('aria-pressed', 'false');
    fieldToggle.title = 'the cross field as small crosses and its singularities coloured by valence';
    const progress = el('div', { className: 'solve-progress', id: 'suggest-progress', hidden: true },
      el('div', { className: 'progress-track' }, el('div', { className: 'progress-bar indeterminate', id: 'suggest-bar' })),
      el('p', { className: 'progress-text', id: 'suggest-progress-text' }));
    const message = el('p', { className: 'suggest-message', id: 'suggest-message', hidden: true });
    message.setAttribute('role', 'status');
    card.append(
      el('h2', { id: 'suggest-title', textContent: 'Automatic layout' }),
      form,
      el('div', { className: 'solve-buttons' }, run, cancel, fieldToggle),
      progress,
      message,
    );
    after.after(card);
    run.addEventListener('click', () => this.suggest().catch(() => {}));
    cancel.addEventListener('click', () => this.cancel());
    fieldToggle.addEventListener('click', () => this.showField(!this.field.visible).catch(() => {}));
    angle.addEventListener('change', () => {
      if (this.field.visible) this.showField(true).catch(() => {});
    });
    Object.assign(this, { card, patches, angle, runButton: run, cancelButton: cancel, progress, message, fieldToggle });
  }

  /**
   * The card's options as the core takes them, with the quads the Solve card asks for where
   * the user typed them (the core judges its proposals by their quads at that count, as
   * `quadlay remesh --layout auto --quads N` does).
   */
  options() {
    const n = Math.round(Number(this.patches.value));
    const a = Number(this.angle.value);
    const quads = this.askedQuads();
    return {
      ...(this.patches.value !== '' && n >= 1 ? { patches: n } : {}),
      featureAngle: this.angle.value !== '' && a > 0 && a < 180 ? a : DEFAULT_FEATURE_ANGLE,
      ...(quads >= 1 ? { quads } : {}),
    };
  }

  /**
   * Proposes a layout and places it into the editor as one undoable edit.
   * @returns {Promise<object>} the placed layout's summary
   */
  async suggest(overrides = {}) {
    if ('patches' in overrides) this.patches.value = overrides.patches == null ? '' : String(overrides.patches);
    if (Number.isFinite(overrides.featureAngle)) this.angle.value = String(overrides.featureAngle);
    if (!this.editor.mesh) throw this.fail(new Error('load a mesh first'));
    this.stop();
    const token = { cancelled: false };
    this.current = token;
    const options = this.options();
    const t0 = performance.now();
    this.quadlay.suggestion = { state: 'running' };
    this.setRunning(true, t0);
    try {
      let answer;
      try {
        answer = await this.propose(options, token);
      } catch (err) {
        if (token.cancelled) throw new Cancelled();
        throw err;
      }
      if (token.cancelled) throw new Cancelled();
      // The field the proposal was made from is the one the field view would ask for.
      if (this.field.visible && this.editor.mesh) this.quadlay.field = this.field.show(this.editor.mesh, answer.field);
      this.setProgressText('Placing the proposal…');
      // One edit: Ctrl+Z returns whatever was drawn before.
      await this.editor.apply(parseDoc(answer.text), { label: 'suggest layout' });
      if (token.cancelled) throw new Cancelled();
      const summary = this.editor.view?.summary;
      if (this.editor.error || !summary) {
        throw new Error(`the proposed layout was not accepted: ${this.editor.error ?? 'no answer from the core'}`);
      }
      const ms = performance.now() - t0;
      const workers = answer.workers ?? 1;
      this.quadlay.suggestion = { state: 'done', seconds: answer.seconds, faces: summary.faces, ms, workers, proposals: answer.proposals ?? null };
      const t = summary.t_vertices ? `, ${summary.t_vertices} T-vertices` : '';
      const note = answer.note ? ` ${answer.note}.` : '';
      const apart = workers > 1 ? ` (${workers} workers at once)` : '';
      this.setMessage(`Suggested ${summary.faces} faces, ${summary.edges} edges (${summary.aligned_edges} tagged)${t} in ${(answer.seconds).toFixed(2)} s${apart}.${note} Edit it like your own; Ctrl+Z returns the previous layout.`, 'ok');
      return summary;
    } catch (err) {
      if (err instanceof Cancelled) {
        this.quadlay.suggestion = { state: 'cancelled' };
        this.setMessage('Cancelled: the layout is as it was.', null);
        throw err;
      }
      throw this.fail(err);
    } finally {
      if (this.current === token) {
        this.current = null;
        this.setRunning(false);
      }
    }
  }

  /**
   * The core's proposal, its tracings made at once in WORKERS workers where there is more
   * than one processor; in one request where there is one, or where a helper worker could
   * not be started. `token.helpers`: the helpers' clients (promises), for Cancel.
   */
  async propose(options, token) {
    if ((navigator.hardwareConcurrency || 1) < 2) return this.client.suggestLayout(options);
    const workers = WORKERS;
    const t0 = performance.now();
    const helpers = Array.from({ length: workers - 1 }, () => this.client.helper());
    token.helpers = helpers;
    // The answers by tracing; the progress line counts them (`token.made`).
    const made = [];
    token.made = made;
    try {
      // Worker j makes tracings j, j + workers, … while there are that many.
      const run = async (client, j) => {
        for (let k = j; ; k += workers) {
          const answer = await client.suggestLayout({ ...options, tracing: k });
          if (answer.tracings <= k) return;
          made[k] = answer;
          token.tracings = answer.tracings;
        }
      };
      await Promise.all([run(this.client, 0), ...helpers.map((h, i) => h.then((client) => run(client, i + 1)))]);
    } catch (err) {
      // A helper that failed, or no field: one request does it all, or says why not.
      if (token.cancelled) throw err;
      return this.client.suggestLayout(options);
    } finally {
      stopHelpers(token);
    }
    const kept = await this.client.pickSuggestion(made.map((a) => (a?.text == null ? null : { judged: a.judged, curves: a.curves })));
    // None made: one request makes the tracings' proposals again (on the field this worker
    // keeps) and then the Voronoi cells' layout, and answers with the field, or says why
    // there is no layout.
    if (kept == null) return this.client.suggestLayout(options);
    const { layout } = await this.client.finishSuggestion(made[kept].text, made[kept].judged, options);
    return { ...made[kept], text: layout, seconds: (performance.now() - t0) / 1000, workers, proposals: made.filter(Boolean).length };
  }

  /** Shows why no layout was proposed, in words; returns the error. */
  fail(err) {
    const message = err?.message || String(err);
    this.quadlay.suggestion = { state: 'error', error: message };
    this.setMessage(`No layout suggested: ${message}`, 'error');
    return err;
  }

  /** Cancel from the card or a script: the worker is restarted with the mesh and layout. */
  cancel() {
    if (!this.current) return;
    this.current.cancelled = true;
    stopHelpers(this.current);
    this.client.restart('the suggestion was cancelled');
  }

  /** Forgets a proposal in progress without touching the page's worker (a new mesh came). */
  stop() {
    if (this.current) {
      this.current.cancelled = true;
      stopHelpers(this.current);
    }
    this.current = null;
    this.setRunning(false);
  }

  setRunning(on, t0 = 0) {
    clearInterval(this.timer);
    this.runButton.disabled = on;
    this.cancelButton.hidden = !on;
    this.progress.hidden = !on;
    if (!on) return;
    this.message.hidden = true;
    const bar = document.getElementById('suggest-bar');
    bar.classList.add('indeterminate');
    bar.style.width = '';
    const tick = () => {
      const p = this.current;
      // Once a proposal is made the line and the bar show how many: each takes about as long.
      const made = p?.tracings ? p.made.filter(Boolean).length : 0;
      const count = p?.tracings ? `, ${made} of ${p.tracings} proposals made` : '';
      this.setProgressText(`Proposing a layout from the cross field… ${((performance.now() - t0) / 1000).toFixed(1)} s${count}`);
      if (p?.tracings) {
        bar.classList.remove('indeterminate');
        bar.style.width = `${Math.round((100 * made) / p.tracings)}%`;
      }
    };
    tick();
    this.timer = setInterval(tick, 100);
  }

  setProgressText(text) {
    document.getElementById('suggest-progress-text').textContent = text;
  }

  setMessage(text, state) {
    this.message.hidden = !text;
    this.message.textContent = text;
    if (state) this.message.dataset.state = state;
    else delete this.message.dataset.state;
  }

  /**
   * Turns the field view on (computed in the worker with the card's feature angle) or off.
   * @returns {Promise<object|null>} what it shows (quadlay.field)
   */
  async showField(on) {
    this.fieldToggle.setAttribute('aria-pressed', String(on));
    if (!on) {
      this.field.hide();
      this.quadlay.field = null;
      return null;
    }
    this.fieldToggle.disabled = true;
    try {
      const data = await this.client.crossField({ featureAngle: this.options().featureAngle });
      const mesh = this.editor.mesh;
      if (this.fieldToggle.getAttribute('aria-pressed') !== 'true' || !mesh) return null;
      this.quadlay.field = this.field.show(mesh, data);
      return this.quadlay.field;
    } catch (err) {
      this.fieldToggle.setAttribute('aria-pressed', 'false');
      this.field.hide();
      this.setMessage(`No field view: ${err?.message || err}`, 'error');
      throw err;
    } finally {
      this.fieldToggle.disabled = false;
    }
  }
}
