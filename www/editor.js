// The layout editor: draw a coarse quad layout on the shown mesh. Nodes snap to mesh
// vertices, edges are traced as geodesics by the core, waypoints bend edges, a node dropped
// on an edge splits it at a T-vertex, edges are tagged for alignment, faces get chart types.
// An incomplete layout is normal while drawing: the core's error is shown in words and on
// the mesh (the nodes and edges it names in red), and the drawing stays visible.
//
// The parts: the session (layout-session.js: document, history, autosave, the core's
// check; no DOM), the drawing (editor-draw.js, three.js), picking (editor-pick.js), pointer
// and keys (editor-input.js), the controls (editor-toolbar.js) and the guidance per face
// (editor-guide.js: curvature, distortion, "add a node here"). This class holds what they
// share (the tool, the hovered element, the node an edge starts at) and wires them together.
// After every check the window gets a `quadlay-layout` event, detail { summary, error }
// (summary null while the layout is invalid), for other parts of the page.
import { EditorDrawing } from './editor-draw.js';
import { EditorGuide } from './editor-guide.js';
import { EditorInput } from './editor-input.js';
import { EditorPicker } from './editor-pick.js';
import { EditorToolbar, MODES } from './editor-toolbar.js';
import { LayoutSession } from './layout-session.js';
import { faceColors } from './layout-view.js';

export { MODES };

export class Editor {
  /**
   * @param {object} o
   * @param {import('./viewer.js').Viewer} o.viewer
   * @param {import('./client.js').CoreClient} o.client
   * @param {HTMLElement} o.viewport the element around the canvas (toolbar and hints go in it)
   * @param {(summary: object|null, error: string|null) => void} [o.onChange] after every check
   * @param {() => void} [o.onCoreLost] the worker lost the mesh (it crashed): load it again
   */
  constructor({ viewer, client, viewport, onChange = () => {}, onCoreLost = null }) {
    this.viewer = viewer;
    this.client = client;
    this.viewport = viewport;
    this.onChange = onChange;
    this.canvas = viewer.renderer.domElement;
    /** The tool (a key of MODES). */
    this.mode = 'view';
    /** Edge mode: the node the next edge starts at, or null. */
    this.pending = null;
    /** The node, edge or waypoint under the pointer: { kind, index, via? }, or null. */
    this.hover = null;
    /** The layout file about to be placed on the next mesh (main.js says), or null. */
    this.placing = null;
    /** The mesh's size (sizes of dots and dashes, pick tolerances). */
    this.radius = viewer.radius;

    this.session = new LayoutSession({ client, onCoreLost, onUpdate: (what, detail) => this.sessionChanged(what, detail) });
    this.toolbar = new EditorToolbar(this, viewport);
    this.picker = new EditorPicker(this);
    this.drawing = new EditorDrawing(this, viewport);
    this.guide = new EditorGuide(this, viewport);
    this.input = new EditorInput(this);
    this.setMode('view');
    // Meshes are framed beside the tool palette and above the status lines (the check line
    // is empty now: room for it too, about as tall as the hint line and the gaps below).
    const view = viewport.getBoundingClientRect();
    const bar = this.toolbar.bar.getBoundingClientRect();
    const status = this.toolbar.status.getBoundingClientRect();
    viewer.setInsets({ left: bar.right - view.left, bottom: view.bottom - status.top });
  }

  get mesh() { return this.session.mesh; }
  get doc() { return this.session.doc; }
  get view() { return this.session.view; }
  get error() { return this.session.error; }
  get problem() { return this.session.problem; }
  get nodeVertex() { return this.session.nodeVertex; }
  get history() { return this.session.history; }
  get checking() { return this.session.checking; }
  get layoutName() { return this.session.layoutName; }

  /** Follows the session: a new mesh, an edit, the core's answer, the restore offer. */
  sessionChanged(what, detail) {
    if (what === 'mesh') {
      this.picker.resetMesh();
      this.drawing.resetMesh(detail);
      if (detail.kept) return;
      this.guide.set(null);
      this.pending = null;
      this.hover = null;
      this.radius = this.viewer.radius;
      // Built when the browser is idle, before the first pointer move needs it.
      const build = () => this.picker.ensureBvh();
      if (window.requestIdleCallback) requestIdleCallback(build, { timeout: 1500 });
      else setTimeout(build, 200);
      this.toolbar.showOffer(this.session.offer);
      this.draw();
      this.updateUi();
    } else if (what === 'edit') {
      // Until the core answers: the old curves where edges are unchanged, no stale highlights.
      if (this.pending != null && !(this.pending < (this.doc.nodes?.length ?? 0))) this.pending = null;
      this.hover = null;
      // The numbers were about the layout before this edit.
      this.guide.set(null);
      this.draw();
      this.updateUi();
    } else if (what === 'checked') {
      const view = this.view;
      if (view) this.drawing.keepCurves(view);
      if (view?.faces) this.guide.set(view.faces);
      this.viewer.setSurfaceColors(view ? faceColors(view.vertex_face) : null);
      this.hover = null;
      this.draw();
      this.input.updatePointer();
      this.updateUi();
      const summary = view?.summary ?? null;
      this.onChange(summary, this.error);
      window.dispatchEvent(new CustomEvent('quadlay-layout', { detail: { summary, error: this.error } }));
    } else if (what === 'offer') {
      this.toolbar.showOffer(this.session.offer);
    }
  }

  /**
   * A new mesh is shown: the editor starts empty on it, and offers the autosaved layout of
   * the same mesh if there is one.
   */
  setMesh(mesh, name, options) {
    this.session.setMesh(mesh, name, options);
  }

  /**
   * Says that the layout `name` is about to be placed (null: no longer), so the status line
   * says so instead of "No layout yet" while the mesh loads and the core places it.
   */
  expectLayout(name) {
    this.placing = name;
    this.updateUi();
  }

  /**
   * The faces' guidance of a run's report (report.faces) for the current layout; null
   * forgets it. The next edit forgets it too.
   */
  setGuidance(faces) {
    this.guide.set(faces);
    this.updateUi();
  }

  /** Opens a layout file's text as the document (LayoutSession.open). */
  async open(text, name, options) {
    try {
      return await this.session.open(text, name, options);
    } finally {
      if (this.placing) this.expectLayout(null);
    }
  }

  /** Makes `doc` the current document and has the core check it (LayoutSession.apply). */
  apply(doc, options) {
    return this.session.apply(doc, options);
  }

  undo() {
    return this.session.undo();
  }

  redo() {
    return this.session.redo();
  }

  /** The layout file's text (format v1). */
  text() {
    return this.session.text();
  }

  /** Downloads the layout as NAME.layout.json; returns the file's text. */
  save() {
    const text = this.text();
    const url = URL.createObjectURL(new Blob([text], { type: 'application/json' }));
    const a = document.createElement('a');
    a.href = url;
    a.download = this.layoutName ?? 'layout.layout.json';
    document.body.append(a);
    a.click();
    a.remove();
    setTimeout(() => URL.revokeObjectURL(url), 10_000);
    this.say(`Saved ${a.download}`);
    return text;
  }


  /** Shows a short message in the hint line for a moment. */
  say(text) {
    this.toolbar.say(text);
  }

  updateUi() {
    this.toolbar.update();
  }

  draw() {
    this.drawing.draw();
  }

  /** Picks the tool (a key of MODES). */
  setMode(mode) {
    if (!MODES[mode]) throw new Error(`unknown mode '${mode}' (${Object.keys(MODES).join(', ')})`);
    this.mode = mode;
    this.input.hoverHint = null;
    if (mode !== 'edge') this.pending = null;
    this.hover = null;
    this.canvas.style.cursor = mode === 'view' ? '' : 'crosshair';
    this.drawing.drawTransient(null);
    this.draw();
    this.input.updatePointer();
    this.updateUi();
  }

  /** What scripts and tests see as `window.quadlay.editor` (documented in main.js). */
  get api() {
    const ed = this;
    return {
      get doc() { return structuredClone(ed.doc); },
      get mode() { return ed.mode; },
      setMode: (m) => ed.setMode(m),
      get error() { return ed.error; },
      get fault() { return structuredClone(ed.session.fault); },
      get checking() { return ed.checking; },
      get summary() { return ed.view?.summary ?? null; },
      get problem() {
        const p = ed.problem;
        return { nodes: [...p.nodes], edges: [...p.edges], patches: [...p.patches], vertices: [...p.vertices], points: p.points };
      },
      get nodeVertices() { return [...ed.nodeVertex]; },
      get pending() { return ed.pending; },
      get canUndo() { return ed.history.canUndo; },
      get canRedo() { return ed.history.canRedo; },
      get offer() { const o = ed.session.offer; return o ? { time: o.time, doc: structuredClone(o.doc) } : null; },
      get layoutName() { return ed.layoutName; },
      /** Per layout face: { face, curvature_deg, needs_node, length_error?, suggestion? }. */
      get guidance() { return structuredClone(ed.guide.faces); },
      /** Turns face f's "add a node here" into a node (an undoable edit). */
      acceptSuggestion: (f) => ed.guide.accept(f),
      /** Stops the worker as a crash would (for tests): the next edit finds it restarted. */
      stopCore: () => ed.client.terminate('the quadlay core was stopped (test)'),
      /** Restarts the worker as after a crash (the client sends the mesh again; for tests). */
      restartCore: () => ed.client.restart?.('the quadlay core was restarted (test)'),
      undo: () => ed.undo(),
      redo: () => ed.redo(),
      settled: () => ed.session.settled(),
      setDoc: (doc) => ed.apply(structuredClone(doc), { label: 'script' }),
      text: () => ed.text(),
      save: () => ed.save(),
      screenOf: (target) => ed.picker.screenOf(target),
      /** Edge i as drawn (its curve, or straight segments until traced): [[x, y, z], ...]. */
      edgePoints: (i) => {
        const p = ed.drawing.edgePoints[i] ?? [];
        return Array.from({ length: p.length / 3 }, (_, k) => [p[3 * k], p[3 * k + 1], p[3 * k + 2]]);
      },
      pick: (x, y) => {
        const hit = ed.picker.pick(x, y);
        return hit && { kind: hit.kind, index: hit.index, via: hit.via, vertex: hit.vertex, point: hit.point };
      },
      /** The layout face (index into summary.face_list) under page pixel (x, y), or -1. */
      faceAt: (x, y) => ed.picker.faceAt(ed.picker.surfaceAt(x, y) && { kind: 'surface', ...ed.picker.surfaceAt(x, y) }),
      /** The mesh vertex a node placed at page pixel (x, y) would snap to, or -1. */
      vertexAt: (x, y) => ed.picker.surfaceAt(x, y)?.vertex ?? -1,
    };
  }
}
