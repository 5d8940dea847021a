// The layout session: the document being drawn on one mesh, its undo history, its autosave
// and the core's verdict on it. No DOM and no three.js, so Node runs it against the wasm core
// (tests/wasm/layout-session.test.mjs); the editor (editor.js) draws it and edits it.
//
// Every edit is a new document handed to `apply`; the core checks it (`client.setLayout`,
// one request at a time, the latest edit next) and answers with its LayoutView or the rule
// that fails, whose culprits `problem` holds for drawing in red. An incomplete layout is
// normal while drawing, so an error is a state here, not an exception.
import * as autosave from './autosave.js';
import { History } from './history.js';
import * as L from './layout-doc.js';
import { nearestVertex } from './picking.js';

export class LayoutSession {
  /**
   * @param {object} o
   * @param {{setLayout: (text: string) => Promise<object>}} o.client the core (client.js's
   *   CoreClient in the page; anything with `setLayout` in tests)
   * @param {(what: 'mesh'|'edit'|'checked'|'offer', detail?: object) => void} [o.onUpdate]
   *   after a new mesh ({ kept }: the same mesh again after a restarted core, the document
   *   kept), an edit (before the core answers), the core's answer, and the restore offer
   *   changing
   * @param {() => void} [o.onCoreLost] the core lost the mesh (its worker crashed): load it
   *   again; the session keeps its document and places it again on the same mesh
   * @param {typeof autosave} [o.store] where documents are autosaved (autosave.js)
   */
  constructor({ client, onUpdate = () => {}, onCoreLost = null, store = autosave }) {
    this.client = client;
    this.onUpdate = onUpdate;
    this.onCoreLost = onCoreLost;
    this.store = store;
    /** { positions, triangles, summary, name } of the shown mesh, or null. */
    this.mesh = null;
    this.doc = L.emptyDoc();
    this.history = new History();
    this.history.clear(this.doc);
    /** The core's answer for the current document: its LayoutView, or null while invalid. */
    this.view = null;
    /** The core's verdict in words while the document is invalid, else null. */
    this.error = null;
    /** The verdict as data while the document is invalid: { message (= error), kind,
     * culprits } (protocol.js), else null. */
    this.fault = null;
    /** What the error names: { nodes, edges, patches, vertices (Sets), points }. */
    this.problem = L.problemOf(null);
    /** Mesh vertex of every node (-1 where the entry is unusable). */
    this.nodeVertex = [];
    this.pointCache = new Map();
    this.layoutName = null;
    this.storageKey = null;
    /** The autosaved layout offered for restoring ({ doc, time }), or null. */
    this.offer = null;
    /** True from an edit until the core has answered for the latest document. */
    this.checking = false;
    this.seq = 0;
    this.waiters = [];
    this.recovering = false;
  }

  /**
   * A new mesh is shown: the session starts empty on it, and offers the autosaved layout of
   * the same mesh if there is one. After a restarted core the same mesh keeps its document.
   * @param {{positions: Float32Array, triangles: Uint32Array, summary: object}} mesh
   * @param {string} name the mesh file's name
   * @param {{keep?: boolean}} [options] keep: the same mesh after repairs that keep its
   *   vertex numbering (cli.md): the document stays and is checked on it again
   */
  setMesh(mesh, name, { keep = false } = {}) {
    const key = this.store.meshKey(name, mesh.summary);
    const kept = (keep && this.mesh !== null) || (this.recovering && key === this.storageKey);
    this.recovering = false;
    this.storageKey = key;
    this.mesh = { positions: mesh.positions, triangles: mesh.triangles, summary: mesh.summary, name };
    if (kept) {
      if (keep) this.pointCache.clear(); // repairs may add vertices nearer a node's point
      this.onUpdate('mesh', { kept: true });
      this.apply(this.doc, { record: false, save: false });
      return;
    }
    this.pointCache.clear();
    this.seq++;
    this.checking = false;
    this.view = null;
    this.error = null;
    this.fault = null;
    this.problem = L.problemOf(null);
    this.doc = L.emptyDoc();
    this.nodeVertex = [];
    this.history.clear(this.doc);
    this.layoutName = `${name.replace(/\.[^.]+$/, '')}.layout.json`;
    this.skip = this.seq; // the empty document is not sent to the core
    const saved = this.store.readSaved(key);
    this.offer = saved?.doc?.nodes?.length ? saved : null;
    this.onUpdate('mesh', { kept: false });
    this.resolveWaiters();
  }

  /**
   * Opens a layout file's text as the document (an undoable step). Resolves to the
   * LayoutView when the core accepts it; rejects with the core's error otherwise (the
   * document stays, its problems named, so it can be fixed).
   * @param {{user?: boolean}} options user: a file the user chose (autosaved), not a sample
   */
  async open(text, name, { user = false } = {}) {
    if (!this.mesh) throw new Error('load a mesh before a layout');
    const doc = L.parseDoc(text);
    this.layoutName = name;
    await this.apply(doc, { label: `open ${name}`, save: user });
    if (this.fault) throw Object.assign(new Error(this.fault.message), this.fault);
    return this.view;
  }

  /**
   * Makes `doc` the current document and has the core check it. Every edit comes here.
   * Resolves once the core has answered (for this document or a later one).
   * @param {object} doc a new document (never changed afterwards)
   * @param {{label?: string, record?: boolean, save?: boolean}} o record: push to the
   *   history (false for undo/redo); save: autosave it
   */
  async apply(doc, { label = 'edit', record = true, save = true } = {}) {
    if (!this.mesh) return;
    // Kept in the file's numbering (L.inNumbering), as undo and the autosave keep it.
    doc = L.inNumbering(doc, this.mesh);
    if (record) this.history.push(doc, label);
    this.doc = doc;
    if (save) this.autosave();
    this.resolveNodes();
    // Until the core answers: no stale verdict.
    this.view = null;
    this.fault = null;
    this.problem = L.problemOf(null);
    this.seq++;
    this.lastEdit = { label, record, save };
    this.checking = true;
    this.onUpdate('edit');
    const done = this.settled();
    if (!this.inFlight) this.check();
    return done;
  }

  /**
   * Has the core check the current document. One request at a time: edits made while it is
   * away wait, and only the latest of them goes next (on a big mesh clicks come faster than
   * the core places layouts).
   */
  async check() {
    this.inFlight = true;
    let seq, doc, view, error;
    do {
      seq = this.seq;
      doc = this.doc;
      view = null;
      error = null;
      try {
        view = await this.client.setLayout(JSON.stringify(doc));
      } catch (err) {
        error = err;
      }
      if (this.skip === this.seq) {
        // A new mesh came meanwhile, and nothing was edited on it yet.
        this.inFlight = false;
        return;
      }
    } while (seq !== this.seq);
    this.inFlight = false;
    this.checking = false;
    const { label, record, save } = this.lastEdit;
    if (error?.fatal && !this.retried) {
      // The worker was thrown away (a crash, a cancelled solve): the client starts a fresh
      // one with the mesh and sends the request after it; check once more there.
      this.retried = true;
      this.apply(doc, { record: false, save: false });
      return;
    }
    this.retried = false;
    if (view) {
      this.view = view;
      this.error = null;
    } else {
      const message = error?.message || String(error);
      // A chart type set on a face that an edit has since changed no longer names a face:
      // it goes with that edit (undo brings both back).
      const stale = error?.kind === 'patch_not_a_face' ? error.culprits?.patches?.[0] ?? -1 : -1;
      if (stale >= 0 && record && !label.startsWith('chart') && doc.patches?.[stale]) {
        const fixed = L.deletePatch(doc, stale);
        this.history.undo();
        this.apply(fixed, { label, record, save });
        return;
      }
      // The worker has no mesh (it was restarted without one): load it again.
      const lost = error?.fatal || error?.kind === 'no_mesh';
      if (lost && this.onCoreLost && !this.recovering) {
        this.recovering = true;
        this.error = 'The quadlay core stopped; it restarts with this mesh and your layout…';
        this.onCoreLost();
      } else {
        this.error = lost ? `${message}. Reload the page: your layout is saved in this browser.` : message;
      }
      this.fault = { message: this.error, kind: error?.kind ?? null, culprits: error?.culprits ?? null };
      this.problem = L.problemOf(error);
    }
    this.onUpdate('checked');
    this.resolveWaiters();
  }

  /** A promise that settles once the core has checked the current document. */
  settled() {
    if (!this.checking) return Promise.resolve();
    return new Promise((resolve) => this.waiters.push(resolve));
  }

  resolveWaiters() {
    const waiters = this.waiters;
    this.waiters = [];
    for (const resolve of waiters) resolve();
  }

  /** Steps back in the history; false when there is nothing to undo. */
  undo() {
    const doc = this.history.undo();
    if (doc) this.apply(doc, { record: false });
    return Boolean(doc);
  }

  redo() {
    const doc = this.history.redo();
    if (doc) this.apply(doc, { record: false });
    return Boolean(doc);
  }

  autosave() {
    if (!this.storageKey) return;
    // Undoing back to nothing must not erase the layout that is still offered for restoring.
    if (this.offer && !this.doc.nodes?.length) return;
    this.store.writeSaved(this.storageKey, this.doc, this.history.recent(this.store.SAVED_STEPS ?? 1));
    // Once the user works on, an unanswered offer still holds the older layout in memory.
  }

  /**
   * Answers the restore offer: restore brings the saved layout back with its undo history
   * (Ctrl+Z then takes back the last edit made before, not the whole layout; resolves once
   * the core has checked it). If the user drew on this mesh meanwhile, restoring is one
   * more step instead (undo brings the drawing back). Discard forgets the saved layout
   * unless the user drew since.
   */
  async answerOffer(restore) {
    const saved = this.offer;
    this.offer = null;
    this.onUpdate('offer');
    if (!saved) return;
    if (!restore) {
      if (!this.history.canUndo) this.store.removeSaved(this.storageKey);
      return;
    }
    if (this.history.canUndo) {
      await this.apply(saved.doc, { label: 'restore' });
      return;
    }
    this.history.resume(saved.steps ?? [{ doc: saved.doc, label: 'restore' }]);
    await this.apply(saved.doc, { record: false });
  }

  /** The layout file's text (format v1). */
  text() {
    return L.toText(this.doc, this.mesh);
  }

  resolveNodes() {
    const n = this.mesh.positions.length / 3;
    this.nodeVertex = (this.doc.nodes ?? []).map((node) => this.vertexOf(node, n));
  }

  /** The mesh vertex a node or waypoint entry stands on (nearest to its point), or -1. */
  vertexOf(loc, n = this.mesh.positions.length / 3) {
    if (Number.isInteger(loc?.vertex)) return loc.vertex >= 0 && loc.vertex < n ? loc.vertex : -1;
    const p = loc?.point;
    if (Array.isArray(p) && p.length === 3 && p.every(Number.isFinite)) {
      const key = p.join(',');
      if (!this.pointCache.has(key)) this.pointCache.set(key, nearestVertex(this.mesh.positions, p));
      return this.pointCache.get(key);
    }
    return -1;
  }

  /** Mesh vertex v's position [x, y, z]. */
  position(v) {
    const p = this.mesh.positions;
    return [p[3 * v], p[3 * v + 1], p[3 * v + 2]];
  }

  /** Where a waypoint is: its vertex, or its point as given. */
  viaPosition(w) {
    if (Array.isArray(w?.point) && w.point.every(Number.isFinite)) return w.point;
    const v = this.vertexOf(w);
    return v >= 0 ? this.position(v) : null;
  }

  /** A key that changes when an edge's course can: its ends' vertices and its waypoints. */
  edgeKey(e) {
    const [a, b] = e.nodes ?? [];
    return `${this.nodeVertex[a]}|${this.nodeVertex[b]}|${JSON.stringify(e.via ?? [])}`;
  }
}
