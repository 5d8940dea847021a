// The layout editor's controls around the 3D view: the tool buttons, undo/redo/save, the
// status line (the core's verdict, the hint for the tool or for what is under the pointer),
// the Layout card of the side panel, and the offer to restore an autosaved layout.
import { formatTime } from './autosave.js';

/** The tools; `key` is the keyboard shortcut. */
export const MODES = {
  view: { key: 'v', label: 'View', hint: 'Drag to orbit, right-drag to pan, scroll to zoom. Pick a tool to edit the layout.' },
  node: { key: 'n', label: 'Node', hint: 'Click the surface to add a node (it snaps to the nearest vertex, near the rim to the rim). Click an edge to split it at a new node (T-vertex). Drag a node to move it.' },
  edge: { key: 'e', label: 'Edge', hint: 'Click a node, then another to connect them. Clicking the surface (or an edge: a T-vertex) adds a node and connects it. Esc ends the chain.' },
  bend: { key: 'b', label: 'Bend', hint: 'Drag an edge to bend it through a waypoint; drag a waypoint (cyan) or a node to move it.' },
  align: { key: 'a', label: 'Align', hint: 'Click an edge to tag it for alignment (thick orange) or untag it (thin blue).' },
  chart: { key: 'c', label: 'Chart', hint: 'Click a face to change its chart type: quad → rect → unit.' },
  delete: { key: 'd', label: 'Delete', hint: 'Click a node, an edge or a waypoint to delete it (Delete key: the one under the pointer).' },
};

export class EditorToolbar {
  /**
   * @param {import('./editor.js').Editor} ed the editor the controls drive
   * @param {HTMLElement} viewport the element around the canvas (toolbar and hints go in it)
   */
  constructor(ed, viewport) {
    this.ed = ed;
    this.viewport = viewport;
    this.notice = null;
    this.createUi();
  }

  createUi() {
    const el = (tag, cls, text) => {
      const e = document.createElement(tag);
      if (cls) e.className = cls;
      if (text) e.textContent = text;
      return e;
    };
    const bar = el('div', 'editor-bar');
    bar.setAttribute('role', 'toolbar');
    bar.setAttribute('aria-label', 'Layout tools');
    const tools = el('div', 'segmented');
    tools.setAttribute('role', 'radiogroup');
    tools.setAttribute('aria-label', 'Tool');
    this.modeButtons = Object.entries(MODES).map(([mode, { key, label }]) => {
      const b = el('button', null);
      b.type = 'button';
      b.setAttribute('role', 'radio');
      b.dataset.mode = mode;
      b.title = `${label} (${key.toUpperCase()})`;
      b.append(label, el('kbd', null, key.toUpperCase()));
      b.addEventListener('click', () => this.ed.setMode(mode));
      tools.append(b);
      return b;
    });
    const action = (id, label, title, fn, shortcut) => {
      const b = el('button', 'tool', label);
      if (shortcut) b.append(el('kbd', null, shortcut));
      b.type = 'button';
      b.id = id;
      b.title = title;
      b.addEventListener('click', fn);
      return b;
    };
    this.undoButton = action('layout-undo', 'Undo', 'Undo (Ctrl+Z)', () => this.ed.undo(), '^Z');
    this.redoButton = action('layout-redo', 'Redo', 'Redo (Ctrl+Shift+Z, Ctrl+Y)', () => this.ed.redo(), '^Y');
    this.saveButton = action('layout-save', 'Save', 'Download the layout file (Ctrl+S)', () => this.ed.save(), '^S');
    bar.append(tools, this.undoButton, this.redoButton, this.saveButton);

    const status = el('div', 'editor-status');
    this.checkText = el('p', 'editor-check');
    this.checkText.id = 'layout-check';
    this.checkText.setAttribute('aria-live', 'polite');
    this.hintText = el('p', 'editor-hint');
    this.hintText.id = 'layout-hint';
    status.append(this.checkText, this.hintText);

    this.offerBox = el('div', 'restore-offer');
    this.offerBox.id = 'restore-offer';
    this.offerBox.setAttribute('role', 'alertdialog');
    this.offerBox.setAttribute('aria-label', 'Restore the autosaved layout');
    this.offerText = el('span', 'restore-text');
    const restore = action('restore-yes', 'Restore', 'Bring back the layout saved in this browser', () => this.ed.session.answerOffer(true));
    restore.classList.add('primary');
    const discard = action('restore-no', 'Discard', 'Forget the saved layout', () => this.ed.session.answerOffer(false));
    this.offerBox.append(this.offerText, restore, discard);
    this.offerBox.hidden = true;

    this.viewport.append(bar, status, this.offerBox);
    this.bar = bar;
    this.status = status;
    // The old help line says the same as the View tool's hint.
    this.viewport.querySelector('.view-help')?.remove();
  }

  /** Shows a short message in the hint line for a moment. */
  say(text) {
    this.notice = text;
    this.update();
    clearTimeout(this.noticeTimer);
    this.noticeTimer = setTimeout(() => {
      this.notice = null;
      this.update();
    }, 2500);
  }

  /** Brings the controls up to date with the editor's state. */
  update() {
    for (const b of this.modeButtons) b.setAttribute('aria-checked', String(b.dataset.mode === this.ed.mode));
    this.undoButton.disabled = !this.ed.history.canUndo;
    this.redoButton.disabled = !this.ed.history.canRedo;
    this.undoButton.title = `Undo ${this.ed.history.undoLabel ?? ''} (Ctrl+Z)`;
    this.redoButton.title = `Redo ${this.ed.history.redoLabel ?? ''} (Ctrl+Shift+Z)`;
    const has = (this.ed.doc.nodes?.length ?? 0) + (this.ed.doc.edges?.length ?? 0) > 0;
    this.saveButton.disabled = !has;

    let hint = MODES[this.ed.mode].hint;
    if (this.ed.mode === 'edge' && this.ed.pending != null) hint = `From nodes[${this.ed.pending}]: click a node to connect it, or the surface for a new node. Esc ends the chain.`;
    this.hintText.textContent = this.notice ?? this.ed.input.hoverHint ?? hint;

    const check = this.checkText;
    if (this.ed.placing && !has) {
      check.dataset.state = 'checking';
      check.textContent = `Placing ${this.ed.placing}…`;
    } else if (!this.ed.mesh) {
      check.dataset.state = 'empty';
      check.textContent = '';
    } else if (this.ed.checking) {
      check.dataset.state = 'checking';
      check.textContent = 'Checking the layout…';
    } else if (this.ed.error) {
      check.dataset.state = 'error';
      // A mesh without nodes is where every layout starts, not a mistake.
      const empty = !has && this.ed.session.fault?.kind === 'component_without_nodes';
      check.textContent = empty ? 'No layout yet: add nodes.' : this.ed.error;
      if (!has) check.dataset.state = 'empty';
    } else if (this.ed.view) {
      const s = this.ed.view.summary;
      check.dataset.state = 'ok';
      check.textContent = `Valid layout: ${s.faces} face${s.faces === 1 ? '' : 's'}, ${s.edges} edge${s.edges === 1 ? '' : 's'} (${s.aligned_edges} tagged)${s.t_vertices ? `, ${s.t_vertices} T-vertices` : ''}`;
    } else {
      check.dataset.state = 'empty';
      check.textContent = 'No layout yet: pick Node (N) and click the surface.';
    }
    this.renderPanel(has);
  }

  /** The Layout card of the side panel: counts, and the problem in words. */
  renderPanel(has) {
    const card = document.getElementById('layout-card');
    if (!card) return;
    let problem = document.getElementById('layout-problem');
    if (!problem) {
      problem = document.createElement('p');
      problem.id = 'layout-problem';
      problem.className = 'layout-problem';
      card.append(problem);
    }
    card.hidden = !has;
    if (!has) return;
    document.getElementById('layout-name').textContent = this.ed.layoutName ?? '';
    const dl = document.getElementById('layout-summary');
    const s = this.ed.view?.summary;
    const edges = this.ed.doc.edges ?? [];
    const rows = [
      ['nodes', 'Nodes', s?.nodes ?? this.ed.doc.nodes?.length ?? 0],
      ['edges', 'Edges', `${edges.length} (${edges.filter((e) => e.align).length} tagged)`],
      ['boundary_pieces', 'Boundary edges', s?.boundary_pieces ?? '—'],
      ['faces', 'Faces', s?.faces ?? '—'],
      ['t_vertices', 'T-vertices', s?.t_vertices ?? '—'],
      ['charts', 'Charts', s ? `${s.charts[0]} quad · ${s.charts[1]} rect · ${s.charts[2]} unit` : '—'],
    ];
    dl.replaceChildren(...rows.flatMap(([key, label, value, cls]) => {
      const dt = document.createElement('dt');
      const dd = document.createElement('dd');
      dt.textContent = label;
      dd.textContent = typeof value === 'number' ? value.toLocaleString('en-US') : String(value);
      dd.dataset.key = key;
      if (cls) dd.className = cls;
      const note = key === 'faces' ? this.ed.guide.facesNote() : null;
      if (note) {
        const why = document.createElement('span');
        why.className = 'warn';
        why.dataset.key = 'needs-node';
        why.textContent = note.text;
        why.title = `${note.words}: the Gaussian curvature a face encloses cannot lie flat in its chart; beyond 45° it needs a node inside (a corner of 3 or 5 faces). Hover a face for its numbers; Show turns the view to where a node would help`;
        dd.append(' ', why);
        // The suggested places may be on the far side: the button turns the view to the next
        // one, where its "add a node here" marker shows.
        const show = document.createElement('button');
        show.type = 'button';
        show.className = 'guide-show';
        show.textContent = 'Show';
        show.title = 'turn the view to the next place where a node would help';
        show.addEventListener('click', () => {
          const at = this.ed.guide.nextSuggestion();
          if (at) this.ed.viewer.flyTo(at);
        });
        dd.append(' ', show);
      }
      return [dt, dd];
    }));
    problem.hidden = !this.ed.error || this.ed.checking;
    problem.textContent = this.ed.error ?? '';
  }

  /** Shows the session's offer to restore an autosaved layout, or hides it. */
  showOffer(saved) {
    this.offerBox.hidden = !saved;
    if (saved) {
      const n = saved.doc.nodes.length, m = saved.doc.edges?.length ?? 0;
      this.offerText.textContent = `Restore your layout from ${formatTime(saved.time)}? (${n} node${n === 1 ? '' : 's'}, ${m} edge${m === 1 ? '' : 's'})`;
    }
  }
}
