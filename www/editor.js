// The layout editor: draw a coarse quad layout on the shown mesh. Nodes snap to mesh
// vertices, edges are traced as geodesics by the core (every edit sends the whole layout
// document to the worker's `setLayout`, which returns the curves or the rule that fails),
// waypoints bend edges, a node dropped on an edge splits it at a T-vertex, edges are tagged
// for alignment, faces get chart types. An incomplete layout is normal while drawing: the
// core's error is shown in words and on the mesh (the nodes and edges it names in red), and
// the drawing stays visible (curves of unchanged edges; new ones dashed, along the shortest
// path over mesh edges, mesh-paths.js).
//
// Undo/redo over whole documents (history.js), autosave per mesh (autosave.js), picking
// through a BVH (picking.js): pointer moves cost the layout's size, not the mesh's.
// After every check the window gets a `quadlay-layout` event, detail { summary, error }
// (summary null while the layout is invalid), for other parts of the page.
import * as THREE from 'three';
import { Line2 } from 'three/addons/lines/Line2.js';
import { LineGeometry } from 'three/addons/lines/LineGeometry.js';
import { LineMaterial } from 'three/addons/lines/LineMaterial.js';
import { LineSegments2 } from 'three/addons/lines/LineSegments2.js';
import { LineSegmentsGeometry } from 'three/addons/lines/LineSegmentsGeometry.js';
import * as autosave from './autosave.js';
import { History } from './history.js';
import * as L from './layout-doc.js';
import { faceColors } from './layout-view.js';
import { meshGraph, pathThrough } from './mesh-paths.js';
import { TriangleBVH, dist2, nearestVertex, segmentDistance } from './picking.js';

/** The tools; `key` is the keyboard shortcut. */
export const MODES = {
  view: { key: 'v', label: 'View', hint: 'Drag to orbit, right-drag to pan, scroll to zoom. Pick a tool to edit the layout.' },
  node: { key: 'n', label: 'Node', hint: 'Click the surface to add a node (it snaps to the nearest vertex). Click an edge to split it at a new node (T-vertex).' },
  edge: { key: 'e', label: 'Edge', hint: 'Click a node, then another to connect them. Clicking the surface (or an edge: a T-vertex) adds a node and connects it. Esc ends the chain.' },
  bend: { key: 'b', label: 'Bend', hint: 'Drag an edge to bend it through a waypoint; drag a waypoint (cyan) to move it.' },
  align: { key: 'a', label: 'Align', hint: 'Click an edge to tag it for alignment (thick orange) or untag it (thin blue).' },
  chart: { key: 'c', label: 'Chart', hint: 'Click a face to change its chart type: quad → rect → unit.' },
  delete: { key: 'd', label: 'Delete', hint: 'Click a node, an edge or a waypoint to delete it (Delete key: the one under the pointer).' },
};

const COLOR = {
  free: 0x4fa8ff,
  aligned: 0xff9d2e,
  boundary: 0xe9ecf2,
  error: 0xff2e3a,
  hover: 0xffffff,
  node: 0xf4f6fa,
  tvertex: 0xffd43b,
  pending: 0x4fd08a,
  via: 0x6fe3ff,
  ghost: 0xffffff,
};
/** Pick radii in CSS pixels. */
const PICK = { node: 11, via: 10, edge: 8 };
/** Pointer travel (px) below which a press and release is a click, not an orbit. */
const CLICK_SLOP = 5;

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
    this.onCoreLost = onCoreLost;
    this.viewer = viewer;
    this.client = client;
    this.viewport = viewport;
    this.onChange = onChange;
    this.canvas = viewer.renderer.domElement;

    this.mesh = null;
    this.bvh = null;
    this.doc = L.emptyDoc();
    this.history = new History();
    this.history.clear(this.doc);
    this.mode = 'view';
    /** The core's answer for the current document: its LayoutView, or null while invalid. */
    this.view = null;
    this.error = null;
    this.problem = L.problemOf(null);
    /** Curves already traced, by edge key (its ends' vertices and waypoints). */
    this.curveCache = new Map();
    /** Paths along mesh edges for edges the core has not traced, by edge key. */
    this.pathCache = new Map();
    this.pointCache = new Map();
    this.nodeVertex = [];
    this.edgePoints = [];
    this.layoutName = null;
    this.storageKey = null;
    this.offer = null;
    this.seq = 0;
    this.checking = false;
    this.waiters = [];
    this.pending = null; // edge mode: the node the next edge starts at
    this.hover = null;
    this.drag = null;
    this.down = null;
    this.lastPointer = null;
    this.hoverQueued = false;
    this.notice = null;

    this.layer = new THREE.Group();
    this.layer.name = 'layout-editor';
    viewer.scene.add(this.layer);
    this.transient = new THREE.Group(); // ghost dot and rubber band, moved without a redraw
    viewer.scene.add(this.transient);
    this.materials = new Map();

    this.createUi();
    this.listen();
    this.setMode('view');
  }

  // ---- mesh and documents ------------------------------------------------------------------

  /**
   * A new mesh is shown: the editor starts empty on it, and offers the autosaved layout of
   * the same mesh if there is one.
   * @param {{positions: Float32Array, triangles: Uint32Array, summary: object}} mesh
   * @param {string} name the mesh file's name
   */
  setMesh(mesh, name) {
    const key = autosave.meshKey(name, mesh.summary);
    if (this.recovering && key === this.storageKey) {
      // The same mesh again after the worker was restarted: keep the layout and its history.
      this.recovering = false;
      this.mesh = { positions: mesh.positions, triangles: mesh.triangles, summary: mesh.summary, name };
      this.bvh = null;
      this.boundary = null;
      this.graph = null;
      this.apply(this.doc, { record: false, save: false });
      return;
    }
    this.recovering = false;
    this.mesh = { positions: mesh.positions, triangles: mesh.triangles, summary: mesh.summary, name };
    this.bvh = null;
    this.boundary = null;
    this.curveCache.clear();
    this.pathCache.clear();
    this.graph = null;
    this.pointCache.clear();
    this.seq++;
    this.checking = false;
    this.pending = null;
    this.hover = null;
    this.view = null;
    this.error = null;
    this.problem = L.problemOf(null);
    this.doc = L.emptyDoc();
    this.nodeVertex = [];
    this.history.clear(this.doc);
    this.layoutName = `${name.replace(/\.[^.]+$/, '')}.layout.json`;
    this.storageKey = key;
    this.skip = this.seq; // the empty document is not sent to the core
    this.radius = this.viewer.radius;
    // Built when the browser is idle, before the first pointer move needs it.
    const build = () => this.ensureBvh();
    if (window.requestIdleCallback) requestIdleCallback(build, { timeout: 1500 });
    else setTimeout(build, 200);
    const saved = autosave.readSaved(this.storageKey);
    this.showOffer(saved?.doc?.nodes?.length ? saved : null);
    this.draw();
    this.updateUi();
    this.resolveWaiters();
  }

  ensureBvh() {
    if (!this.bvh && this.mesh) this.bvh = new TriangleBVH(this.mesh.positions, this.mesh.triangles);
    return this.bvh;
  }

  /**
   * Opens a layout file's text as the document (an undoable step). Resolves to the
   * LayoutView when the core accepts it; rejects with the core's error otherwise (the
   * document stays in the editor, its problems drawn, so it can be fixed).
   * @param {{user?: boolean}} options user: a file the user chose (autosaved), not a sample
   */
  async open(text, name, { user = false } = {}) {
    if (!this.mesh) throw new Error('load a mesh before a layout');
    const doc = L.parseDoc(text);
    this.layoutName = name;
    await this.apply(doc, { label: `open ${name}`, save: user });
    if (this.error) throw new Error(this.error);
    return this.view;
  }

  /**
   * Makes `doc` the current document and has the core check it. Every edit comes here.
   * @param {object} doc a new document (never changed afterwards)
   * @param {{label?: string, record?: boolean, save?: boolean}} o record: push to the
   *   history (false for undo/redo); save: autosave it
   */
  async apply(doc, { label = 'edit', record = true, save = true } = {}) {
    if (!this.mesh) return;
    if (record) this.history.push(doc, label);
    this.doc = doc;
    if (save) this.autosave();
    this.resolveNodes();
    // Until the core answers: the old curves where edges are unchanged, no stale highlights.
    this.view = null;
    this.problem = L.problemOf(null);
    if (this.pending != null && !(this.pending < (doc.nodes?.length ?? 0))) this.pending = null;
    this.hover = null;
    this.draw();
    this.seq++;
    this.lastEdit = { label, record, save };
    this.checking = true;
    this.updateUi();
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
      view.curves.forEach((c) => {
        const i = edgeIndex(c.source);
        if (i >= 0 && doc.edges?.[i]) this.curveCache.set(this.edgeKey(doc.edges[i]), c.points);
      });
      this.viewer.setSurfaceColors(faceColors(view.vertex_face));
    } else {
      const message = error?.message || String(error);
      // A chart type set on a face that an edit has since changed no longer names a face:
      // it goes with that edit (undo brings both back).
      const stale = /^patches\[(\d+)\]: /.exec(message);
      if (stale && record && !label.startsWith('chart') && doc.patches?.[Number(stale[1])]) {
        const fixed = L.deletePatch(doc, Number(stale[1]));
        this.history.undo();
        this.apply(fixed, { label, record, save });
        return;
      }
      // The worker has no mesh (it was restarted without one): load it again.
      const lost = error?.fatal || /^load a mesh/.test(message);
      if (lost && this.onCoreLost && !this.recovering) {
        this.recovering = true;
        this.error = 'The quadlay core stopped; it restarts with this mesh and your layout…';
        this.onCoreLost();
      } else {
        this.error = lost ? `${message}. Reload the page: your layout is saved in this browser.` : message;
      }
      this.problem = L.problemOf(message, doc);
      this.viewer.setSurfaceColors(null);
    }
    this.hover = null;
    this.draw();
    this.updatePointer();
    this.updateUi();
    this.onChange(this.view?.summary ?? null, this.error);
    window.dispatchEvent(new CustomEvent('quadlay-layout', { detail: { summary: this.view?.summary ?? null, error: this.error } }));
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
    autosave.writeSaved(this.storageKey, this.doc);
    // Once the user works on, an unanswered offer still holds the older layout in memory.
  }

  /** The layout file's text (format v1). */
  text() {
    return L.toText(this.doc);
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

  /** Mesh vertex of every node (-1 where the entry is unusable). */
  resolveNodes() {
    const n = this.mesh.positions.length / 3;
    this.nodeVertex = (this.doc.nodes ?? []).map((node) => this.vertexOf(node, n));
  }

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

  edgeKey(e) {
    const [a, b] = e.nodes ?? [];
    return `${this.nodeVertex[a]}|${this.nodeVertex[b]}|${JSON.stringify(e.via ?? [])}`;
  }

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

  /**
   * Where an edge the core has not traced yet runs: the shortest path along mesh edges
   * through its stops (cached), or null if a stop is unusable.
   */
  provisionalPath(e) {
    const key = this.edgeKey(e);
    if (this.pathCache.has(key)) return this.pathCache.get(key);
    const [a, b] = e.nodes ?? [];
    const stops = [this.nodeVertex[a], ...(e.via ?? []).map((w) => this.vertexOf(w)), this.nodeVertex[b]];
    let path = null;
    if (stops.every((v) => v >= 0)) {
      this.graph ??= meshGraph(this.mesh.positions, this.mesh.triangles);
      path = pathThrough(this.graph, stops);
    }
    this.pathCache.set(key, path);
    return path;
  }

  /** Straight segments through an edge's stops (drawn until the core traces it), or null. */
  straight(e) {
    const [a, b] = e.nodes ?? [];
    const va = this.nodeVertex[a], vb = this.nodeVertex[b];
    if (!(va >= 0) || !(vb >= 0)) return null;
    const stops = [this.position(va), ...(e.via ?? []).map((w) => this.viaPosition(w)).filter(Boolean), this.position(vb)];
    return stops.flat();
  }

  // ---- drawing -----------------------------------------------------------------------------

  material(kind, { dashed = false, width, through = dashed } = {}) {
    const key = `${kind}:${dashed}:${width}:${through}`;
    let m = this.materials.get(key);
    if (!m) {
      const widths = { free: 2.5, aligned: 5, boundary: 2.5, error: 6, hover: 6, rubber: 2 };
      m = new LineMaterial({
        color: kind === 'rubber' ? COLOR.pending : COLOR[kind],
        linewidth: width ?? widths[kind] ?? 3,
        resolution: this.viewer.resolution,
        worldUnits: false,
        dashed,
        dashSize: this.radius * 0.025,
        gapSize: this.radius * 0.018,
        transparent: dashed,
        opacity: dashed ? 0.9 : 1,
        // Straight stand-ins cut through the surface: drawn over it.
        depthTest: !through,
      });
      this.materials.set(key, m);
    }
    return m;
  }

  /** Rebuilds the layer from the document, the core's answer and the pointer's state. */
  draw() {
    disposeChildren(this.layer);
    if (!this.mesh) {
      this.viewer.requestRender();
      return;
    }
    // Material sizes depend on the mesh.
    if (this.materialsRadius !== this.radius) {
      for (const m of this.materials.values()) m.dispose();
      this.materials.clear();
      this.materialsRadius = this.radius;
    }
    const r = this.radius;
    const doc = this.doc;
    const problem = this.problem;
    const hover = this.hover;

    // The mesh's boundary is part of every layout.
    const boundary = this.boundarySegments();
    if (boundary.length) {
      const g = new LineSegmentsGeometry();
      g.setPositions(boundary);
      this.layer.add(new LineSegments2(g, this.material('boundary')));
    }

    const traced = new Map();
    for (const c of this.view?.curves ?? []) {
      const i = edgeIndex(c.source);
      if (i >= 0) traced.set(i, c.points);
    }
    this.edgePoints = [];
    (doc.edges ?? []).forEach((e, i) => {
      let points = traced.get(i) ?? this.curveCache.get(this.edgeKey(e));
      const provisional = !points;
      let through = false;
      if (!points) points = this.provisionalPath(e);
      if (!points) {
        points = this.straight(e);
        through = true;
      }
      if (!points) return;
      this.edgePoints[i] = points;
      let kind = e.align ? 'aligned' : 'free';
      if (problem.edges.has(i)) kind = 'error';
      const hovered = hover?.kind === 'edge' && hover.index === i;
      if (hovered && this.mode === 'delete') kind = 'error';
      const width = hovered ? (kind === 'aligned' || kind === 'error' ? 8 : 5) : undefined;
      const g = new LineGeometry();
      g.setPositions(points);
      const line = new Line2(g, this.material(kind, { dashed: provisional, width, through }));
      if (provisional) line.computeLineDistances();
      line.renderOrder = provisional ? 3 : 2;
      line.userData.edge = i;
      this.layer.add(line);
    });

    // Nodes: dots, coloured by role; error halos drawn through the surface.
    const tVertices = new Set((this.view?.summary.face_list ?? []).flatMap((f) => f.t_vertices));
    const dot = new THREE.SphereGeometry(r * 0.015, 14, 10);
    const nodes = this.nodeVertex.map((v, n) => [v, n]).filter(([v]) => v >= 0);
    if (nodes.length) {
      const mesh = new THREE.InstancedMesh(dot, new THREE.MeshBasicMaterial(), nodes.length);
      const m = new THREE.Matrix4();
      const c = new THREE.Color();
      nodes.forEach(([v, n], k) => {
        const [x, y, z] = this.position(v);
        const big = (hover?.kind === 'node' && hover.index === n) || this.pending === n ? 1.5 : 1;
        mesh.setMatrixAt(k, m.makeScale(big, big, big).setPosition(x, y, z));
        let color = tVertices.has(n) ? COLOR.tvertex : COLOR.node;
        if (this.pending === n) color = COLOR.pending;
        if (hover?.kind === 'node' && hover.index === n) color = this.mode === 'delete' ? COLOR.error : 0x9fd0ff;
        if (problem.nodes.has(n)) color = COLOR.error;
        mesh.setColorAt(k, c.setHex(color));
      });
      mesh.renderOrder = 4;
      this.layer.add(mesh);
    }

    // Waypoints, where they can be moved or deleted.
    if (this.mode === 'bend' || this.mode === 'delete') {
      const handles = [];
      (doc.edges ?? []).forEach((e, i) => (e.via ?? []).forEach((w, k) => {
        const p = this.viaPosition(w);
        if (p) handles.push([p, i, k]);
      }));
      if (handles.length) {
        const mesh = new THREE.InstancedMesh(new THREE.SphereGeometry(r * 0.014, 12, 8), new THREE.MeshBasicMaterial(), handles.length);
        const m = new THREE.Matrix4();
        const c = new THREE.Color();
        handles.forEach(([p, i, k], j) => {
          const on = hover?.kind === 'via' && hover.index === i && hover.via === k;
          const s = on ? 1.5 : 1;
          mesh.setMatrixAt(j, m.makeScale(s, s, s).setPosition(p[0], p[1], p[2]));
          mesh.setColorAt(j, c.setHex(on && this.mode === 'delete' ? COLOR.error : on ? 0xffffff : COLOR.via));
        });
        mesh.renderOrder = 4;
        this.layer.add(mesh);
      }
    }

    // What the error names but is not a node or an edge: vertices, a crossing point.
    const halos = [];
    for (const n of problem.nodes) if (this.nodeVertex[n] >= 0) halos.push(this.position(this.nodeVertex[n]));
    for (const v of problem.vertices) if (v >= 0 && v < this.mesh.positions.length / 3) halos.push(this.position(v));
    halos.push(...problem.points);
    if (halos.length) {
      const halo = new THREE.InstancedMesh(
        new THREE.SphereGeometry(r * 0.03, 20, 14),
        new THREE.MeshBasicMaterial({ color: COLOR.error, transparent: true, opacity: 0.5, depthTest: false, depthWrite: false }),
        halos.length,
      );
      const m = new THREE.Matrix4();
      halos.forEach((p, k) => halo.setMatrixAt(k, m.makeTranslation(p[0], p[1], p[2])));
      halo.renderOrder = 5;
      this.layer.add(halo);
    }
    this.updateLabels({ now: true });
    this.viewer.requestRender();
  }

  /** The mesh's boundary edges as segment end points (found once per mesh). */
  boundarySegments() {
    if (this.boundary) return this.boundary;
    const t = this.mesh.triangles;
    const n = this.mesh.positions.length / 3;
    const count = new Map();
    for (let f = 0; f < t.length; f += 3) {
      for (let k = 0; k < 3; k++) {
        const a = t[f + k], b = t[f + ((k + 1) % 3)];
        const key = a < b ? a * n + b : b * n + a;
        count.set(key, (count.get(key) ?? 0) + 1);
      }
    }
    const out = [];
    for (const [key, c] of count) {
      if (c !== 1) continue;
      const a = Math.floor(key / n), b = key % n;
      out.push(...this.position(a), ...this.position(b));
    }
    this.boundary = out;
    return out;
  }

  /** The ghost dot (where a click would put a node) and the rubber band of edge mode. */
  drawTransient(target, { ghost = true } = {}) {
    // Nothing shown and nothing to show: no frame to draw.
    if (!target && !this.drag?.target && !this.transient.children.length) return;
    disposeChildren(this.transient);
    if (target && ghost) {
      const dot = new THREE.Mesh(
        new THREE.SphereGeometry(this.radius * 0.011, 12, 8),
        new THREE.MeshBasicMaterial({ color: COLOR.ghost, transparent: true, opacity: 0.55, depthTest: false }),
      );
      dot.position.set(...target);
      dot.renderOrder = 6;
      this.transient.add(dot);
    }
    const from = this.drag ? null : this.pending != null ? this.nodeVertex[this.pending] : -1;
    if (this.mode === 'edge' && from >= 0 && target) {
      const g = new LineGeometry();
      g.setPositions([...this.position(from), ...target]);
      const line = new Line2(g, this.material('rubber', { dashed: true }));
      line.computeLineDistances();
      line.renderOrder = 6;
      this.transient.add(line);
    }
    if (this.drag?.curve) {
      // The core's curve through the waypoint where it is now.
      const g = new LineGeometry();
      g.setPositions(this.drag.curve);
      const line = new Line2(g, this.material('hover', { width: 4 }));
      line.renderOrder = 6;
      this.transient.add(line);
    } else if (this.drag?.target) {
      const { edge, k, insert } = this.drag;
      const e = this.doc.edges[edge];
      const via = (e.via ?? []).map((w) => this.viaPosition(w));
      const before = k === 0 ? this.position(this.nodeVertex[e.nodes[0]]) : via[k - 1];
      const afterIndex = insert ? k : k + 1;
      const after = afterIndex < via.length ? via[afterIndex] : this.position(this.nodeVertex[e.nodes[1]]);
      const g = new LineGeometry();
      g.setPositions([...before, ...this.drag.target, ...after]);
      const line = new Line2(g, this.material('rubber', { dashed: true }));
      line.computeLineDistances();
      line.renderOrder = 6;
      this.transient.add(line);
    }
    this.viewer.requestRender();
  }

  // ---- picking -----------------------------------------------------------------------------

  /** Page pixels of a mesh vertex (or an [x, y, z] point), null when behind the camera. */
  screenOf(target) {
    const p = Array.isArray(target) ? target : this.position(target);
    const v = new THREE.Vector3(...p).project(this.viewer.camera);
    if (v.z > 1 || v.z < -1) return null;
    const rect = this.canvas.getBoundingClientRect();
    return { x: rect.left + ((v.x + 1) / 2) * rect.width, y: rect.top + ((1 - v.y) / 2) * rect.height };
  }

  ray(x, y) {
    const rect = this.canvas.getBoundingClientRect();
    const ndc = new THREE.Vector2(((x - rect.left) / rect.width) * 2 - 1, -((y - rect.top) / rect.height) * 2 + 1);
    const caster = new THREE.Raycaster();
    caster.setFromCamera(ndc, this.viewer.camera);
    return caster.ray;
  }

  /** The surface under page pixel (x, y): { triangle, point, vertex } or null. */
  surfaceAt(x, y) {
    const bvh = this.ensureBvh();
    if (!bvh) return null;
    const { origin, direction } = this.ray(x, y);
    const hit = bvh.raycast(origin, direction);
    if (!hit) return null;
    return { ...hit, vertex: bvh.nearestCorner(hit.triangle, hit.point) };
  }

  /** Whether point p is in front of the surface as the camera sees it. */
  visible(p) {
    const cam = this.viewer.camera.position;
    const d = new THREE.Vector3(...p).sub(cam);
    const len = d.length();
    const hit = this.ensureBvh().raycast(cam, d.normalize());
    return !hit || hit.t >= len - this.radius * 0.02;
  }

  /**
   * What is under page pixel (x, y): a waypoint, a node, an edge (with the curve point
   * nearest to the pointer), or the surface; null over the background.
   */
  pick(x, y) {
    if (!this.mesh) return null;
    const candidates = [];
    if (this.mode === 'bend' || this.mode === 'delete') {
      (this.doc.edges ?? []).forEach((e, i) => (e.via ?? []).forEach((w, k) => {
        const p = this.viaPosition(w);
        const s = p && this.screenOf(p);
        const d = s && Math.hypot(s.x - x, s.y - y);
        if (d <= PICK.via) candidates.push({ kind: 'via', index: i, via: k, d: d - 2, point: p });
      }));
    }
    this.nodeVertex.forEach((v, n) => {
      if (v < 0) return;
      const p = this.position(v);
      const s = this.screenOf(p);
      const d = s && Math.hypot(s.x - x, s.y - y);
      if (d <= PICK.node) candidates.push({ kind: 'node', index: n, d: d - 1, point: p });
    });
    const screen = this.projectedCurves();
    this.edgePoints.forEach((pts, i) => {
      if (!pts) return;
      const q = screen[i];
      let best = null;
      for (let j = 1; j < q.length / 2; j++) {
        const ax = q[2 * j - 2], ay = q[2 * j - 1], bx = q[2 * j], by = q[2 * j + 1];
        if (Number.isNaN(ax) || Number.isNaN(bx)) continue;
        // Cheap rejection before the exact distance.
        if ((ax < x - PICK.edge && bx < x - PICK.edge) || (ax > x + PICK.edge && bx > x + PICK.edge)
          || (ay < y - PICK.edge && by < y - PICK.edge) || (ay > y + PICK.edge && by > y + PICK.edge)) continue;
        const { d, s: t } = segmentDistance(x, y, ax, ay, bx, by);
        if (d <= PICK.edge && (!best || d < best.d)) best = { d, segment: j - 1, t };
      }
      if (best) {
        const a = pts.slice(3 * best.segment, 3 * best.segment + 3);
        const b = pts.slice(3 * best.segment + 3, 3 * best.segment + 6);
        const point = a.map((c, k) => c + (b[k] - c) * best.t);
        candidates.push({ kind: 'edge', index: i, d: best.d + 1, point, segment: best.segment });
      }
    });
    candidates.sort((a, b) => a.d - b.d);
    for (const c of candidates) if (this.visible(c.point)) return c;
    const hit = this.surfaceAt(x, y);
    return hit ? { kind: 'surface', ...hit } : null;
  }

  /**
   * The drawn curves in page pixels (x, y per point; NaN behind the camera), kept until the
   * camera, the canvas or the curves change: pointer moves then cost no projections.
   */
  projectedCurves() {
    const cam = this.viewer.camera;
    const rect = this.canvas.getBoundingClientRect();
    const key = `${cam.matrixWorld.elements.join()}|${cam.projectionMatrix.elements.join()}|${rect.left},${rect.top},${rect.width},${rect.height}`;
    if (this.projection?.key === key && this.projection.curves === this.edgePoints) return this.projection.screen;
    const m = new THREE.Matrix4().multiplyMatrices(cam.projectionMatrix, cam.matrixWorldInverse).elements;
    const screen = this.edgePoints.map((pts) => {
      if (!pts) return null;
      const q = new Float32Array((pts.length / 3) * 2);
      for (let j = 0; j < pts.length / 3; j++) {
        const px = pts[3 * j], py = pts[3 * j + 1], pz = pts[3 * j + 2];
        const w = m[3] * px + m[7] * py + m[11] * pz + m[15];
        if (w <= 0) {
          q[2 * j] = q[2 * j + 1] = NaN;
          continue;
        }
        const nx = (m[0] * px + m[4] * py + m[8] * pz + m[12]) / w;
        const ny = (m[1] * px + m[5] * py + m[9] * pz + m[13]) / w;
        q[2 * j] = rect.left + ((nx + 1) / 2) * rect.width;
        q[2 * j + 1] = rect.top + ((1 - ny) / 2) * rect.height;
      }
      return q;
    });
    this.projection = { key, curves: this.edgePoints, screen };
    return screen;
  }

  // ---- pointer and keys --------------------------------------------------------------------

  listen() {
    // Capture on the viewport: runs before OrbitControls' own listener on the canvas, so a
    // waypoint drag can switch the orbit off before it starts.
    this.viewport.addEventListener('pointerdown', (e) => this.onDown(e), true);
    this.viewport.addEventListener('pointermove', (e) => this.onMove(e), true);
    this.viewport.addEventListener('pointerup', (e) => this.onUp(e), true);
    this.canvas.addEventListener('pointerleave', () => {
      if (this.drag) return;
      this.setHover(null);
      this.drawTransient(null);
      this.hoverHint = null;
      this.updateUi();
    });
    this.viewer.controls.addEventListener('change', () => this.updateLabels());
    window.addEventListener('keydown', (e) => this.onKey(e));
  }

  onDown(event) {
    if (event.target !== this.canvas || event.button !== 0 || !this.mesh) return;
    this.down = { x: event.clientX, y: event.clientY };
    if (this.mode !== 'bend') return;
    const hit = this.pick(event.clientX, event.clientY);
    if (hit?.kind === 'via') {
      this.drag = { edge: hit.index, k: hit.via, insert: false, target: null };
    } else if (hit?.kind === 'edge') {
      this.drag = { edge: hit.index, k: this.viaInsertIndex(hit.index, hit.segment), insert: true, target: null };
    } else {
      return;
    }
    this.viewer.controls.enabled = false;
    this.canvas.setPointerCapture(event.pointerId);
  }

  onMove(event) {
    if (!this.mesh) return;
    this.lastPointer = { x: event.clientX, y: event.clientY, onCanvas: event.target === this.canvas };
    if (this.hoverQueued) return;
    this.hoverQueued = true;
    // At most one pick per frame, however fast the pointer moves.
    requestAnimationFrame(() => {
      this.hoverQueued = false;
      this.updatePointer(event.buttons);
    });
  }

  /** Hover highlight, ghost dot and rubber band for the pointer's last position. */
  updatePointer(buttons = 0) {
    const p = this.lastPointer;
    if (!p || !this.mesh) return;
    {
      if (this.drag) {
        const hit = this.surfaceAt(p.x, p.y);
        if (hit && hit.vertex !== this.drag.vertex) {
          this.drag.vertex = hit.vertex;
          this.drag.target = this.position(hit.vertex);
          this.previewDrag();
        }
        this.drawTransient(this.drag.target);
        return;
      }
      if (!p.onCanvas || this.mode === 'view' || (buttons & 1 && this.down)) {
        this.setHover(null);
        this.drawTransient(null);
        if (this.hoverHint) {
          this.hoverHint = null;
          this.updateUi();
        }
        return;
      }
      const hit = this.pick(p.x, p.y);
      this.setHover(hit && hit.kind !== 'surface' ? hit : null);
      const ghost = (this.mode === 'node' || this.mode === 'edge') && hit?.kind === 'surface' ? this.position(hit.vertex) : null;
      const target = hit?.kind === 'node' ? hit.point : ghost;
      this.drawTransient(target, { ghost: Boolean(ghost) });
      this.canvas.style.cursor = hit && hit.kind !== 'surface' ? 'pointer' : this.mode === 'view' ? '' : 'crosshair';
      const hint = this.describe(hit);
      if (hint !== this.hoverHint) {
        this.hoverHint = hint;
        this.updateUi();
      }
    }
  }

  onUp(event) {
    if (event.button !== 0 || !this.down) return;
    const moved = Math.hypot(event.clientX - this.down.x, event.clientY - this.down.y);
    this.down = null;
    if (this.drag) {
      const drag = this.endDrag(event.pointerId);
      if (drag.vertex >= 0 && moved > CLICK_SLOP) {
        this.apply(this.dragDoc(drag), { label: drag.insert ? 'bend edge' : 'move waypoint' });
      } else if (drag.previewed) {
        this.apply(this.doc, { record: false, save: false }); // the worker holds a preview
      }
      return;
    }
    if (moved > CLICK_SLOP || event.target !== this.canvas) return;
    this.click(event.clientX, event.clientY);
  }

  /** The document with the dragged waypoint where the pointer is. */
  dragDoc(drag) {
    return drag.insert
      ? L.insertVia(this.doc, drag.edge, drag.k, drag.vertex)
      : L.moveVia(this.doc, drag.edge, drag.k, drag.vertex);
  }

  /**
   * Has the core trace the dragged edge through the waypoint's current place, one request
   * at a time (the latest place wins), so the curve follows the pointer.
   */
  async previewDrag() {
    const drag = this.drag;
    if (!drag || !(drag.vertex >= 0)) return;
    if (drag.inFlight) {
      drag.stale = true;
      return;
    }
    drag.inFlight = true;
    drag.stale = false;
    drag.previewed = true;
    let curve = null;
    try {
      const view = await this.client.setLayout(JSON.stringify(this.dragDoc(drag)));
      curve = view.curves.find((c) => c.source === `edges[${drag.edge}]`)?.points ?? null;
    } catch {
      // an invalid place: the dashed lines show it until the next one
    }
    drag.inFlight = false;
    if (this.drag !== drag) return;
    drag.curve = curve;
    this.drawTransient(drag.target);
    if (drag.stale) this.previewDrag();
  }

  /** Stops a waypoint drag; returns it. */
  endDrag(pointerId) {
    const drag = this.drag;
    this.drag = null;
    this.viewer.controls.enabled = true;
    if (pointerId != null && this.canvas.hasPointerCapture(pointerId)) this.canvas.releasePointerCapture(pointerId);
    this.drawTransient(null);
    return drag;
  }

  /** A click at page pixel (x, y) in the current mode. */
  click(x, y) {
    let hit = this.pick(x, y);
    if (hit?.kind === 'surface' && this.nodeVertex.includes(hit.vertex)) {
      const n = this.nodeVertex.indexOf(hit.vertex);
      hit = { kind: 'node', index: n, point: this.position(hit.vertex) };
    }
    const doc = this.doc;
    switch (this.mode) {
      case 'node': {
        if (!hit) return;
        if (hit.kind === 'edge') return this.splitAt(hit);
        if (hit.kind === 'node') return this.say(`nodes[${hit.index}] is already here`);
        if (hit.kind !== 'surface') return;
        return this.apply(L.addNode(doc, hit.vertex)[0], { label: 'add node' });
      }
      case 'edge': {
        if (!hit) {
          this.pending = null;
          return this.draw();
        }
        if (hit.kind === 'node') {
          const n = hit.index;
          if (this.pending == null || this.pending === n) {
            this.pending = this.pending === n ? null : n;
            this.draw();
            return this.updateUi();
          }
          const a = this.pending;
          this.pending = n;
          if (L.findEdge(doc, a, n) >= 0) {
            this.draw();
            return this.say(`nodes[${a}] and nodes[${n}] are connected already`);
          }
          return this.apply(L.addEdge(doc, a, n)[0], { label: 'add edge' });
        }
        let next, n;
        if (hit.kind === 'edge') {
          const split = this.splitDoc(hit);
          if (!split) return;
          [next, n] = split;
        } else if (hit.kind === 'surface') {
          [next, n] = L.addNode(doc, hit.vertex);
        } else {
          return;
        }
        if (this.pending != null) next = L.addEdge(next, this.pending, n)[0];
        this.pending = n;
        return this.apply(next, { label: 'add edge' });
      }
      case 'align':
        if (hit?.kind === 'edge') return this.apply(L.toggleAlign(doc, hit.index), { label: 'tag edge' });
        return;
      case 'chart':
        return this.cycleChart(hit);
      case 'delete':
        return this.deleteHit(hit);
      default:
    }
  }

  deleteHit(hit) {
    if (hit?.kind === 'via') return this.apply(L.deleteVia(this.doc, hit.index, hit.via), { label: 'delete waypoint' });
    if (hit?.kind === 'node') {
      if (this.pending === hit.index) this.pending = null;
      else if (this.pending > hit.index) this.pending--;
      return this.apply(L.deleteNode(this.doc, hit.index), { label: 'delete node' });
    }
    if (hit?.kind === 'edge') return this.apply(L.deleteEdge(this.doc, hit.index), { label: 'delete edge' });
  }

  /** Index in edge i's `via` at which a waypoint at curve segment `segment` belongs. */
  viaInsertIndex(i, segment) {
    const pts = this.edgePoints[i];
    const via = this.doc.edges[i].via ?? [];
    let k = 0;
    for (const w of via) {
      const p = this.viaPosition(w);
      if (p && nearestPointIndex(pts, p) <= segment) k++;
    }
    return k;
  }

  /** [doc, new node] with edge hit.index split at the mesh vertex nearest the picked point. */
  splitDoc(hit) {
    const through = this.surfaceAt(...Object.values(this.screenOf(hit.point)));
    let vertex = through ? this.ensureBvh().nearestCorner(through.triangle, hit.point) : nearestVertex(this.mesh.positions, hit.point);
    if (through && dist2(this.mesh.positions, vertex, hit.point) > (this.radius * 0.05) ** 2) {
      vertex = nearestVertex(this.mesh.positions, hit.point);
    }
    const at = this.nodeVertex.indexOf(vertex);
    if (at >= 0) {
      this.say(`nodes[${at}] is on that vertex already`);
      return null;
    }
    return L.splitEdge(this.doc, hit.index, vertex, this.viaInsertIndex(hit.index, hit.segment));
  }

  splitAt(hit) {
    const split = this.splitDoc(hit);
    if (split) this.apply(split[0], { label: 'split edge' });
  }

  /** The face under a surface hit (index into the summary's face_list), or -1. */
  faceAt(hit) {
    if (hit?.kind !== 'surface' || !this.view) return -1;
    const t = this.mesh.triangles;
    const corners = [0, 1, 2].map((k) => t[3 * hit.triangle + k])
      .sort((a, b) => dist2(this.mesh.positions, a, hit.point) - dist2(this.mesh.positions, b, hit.point));
    for (const v of corners) if (this.view.vertex_face[v] >= 0) return this.view.vertex_face[v];
    return -1;
  }

  cycleChart(hit) {
    if (!this.view) return this.say('chart types can be set once the layout is valid');
    const f = this.faceAt(hit);
    if (f < 0) return;
    const corners = this.view.summary.face_list[f].corners;
    const now = L.chartOf(this.doc, corners);
    const next = L.CHARTS[(L.CHARTS.indexOf(now) + 1) % L.CHARTS.length];
    this.say(`face ${f}: ${next} chart`);
    return this.apply(L.setChart(this.doc, corners, next), { label: `chart ${next}` });
  }

  /** What a click on `hit` would do now, for the hint line; null: the tool's own hint. */
  describe(hit) {
    if (!hit) return null;
    const edges = (n) => (this.doc.edges ?? []).filter((e) => e.nodes?.includes(n)).length;
    const what = hit.kind === 'edge' ? `edges[${hit.index}]` : hit.kind === 'node' ? `nodes[${hit.index}]` : null;
    switch (this.mode) {
      case 'node':
        if (hit.kind === 'edge') return `Click: split ${what} at a new node (T-vertex).`;
        if (hit.kind === 'node') return `${what} is here.`;
        return null;
      case 'edge':
        if (hit.kind === 'node') {
          if (this.pending == null) return `Click: start an edge at ${what}.`;
          if (this.pending === hit.index) return `Click: end the chain at ${what}.`;
          return `Click: connect nodes[${this.pending}] to ${what}.`;
        }
        if (hit.kind === 'edge') return `Click: a new node on ${what} (T-vertex)${this.pending != null ? `, connected to nodes[${this.pending}]` : ''}.`;
        return null;
      case 'bend':
        if (hit.kind === 'via') return `Drag: move waypoint ${hit.via} of edges[${hit.index}].`;
        if (hit.kind === 'edge') return `Drag: bend ${what} through a new waypoint.`;
        return null;
      case 'align':
        if (hit.kind === 'edge') return `Click: ${this.doc.edges[hit.index].align ? 'untag' : 'tag'} ${what} ${this.doc.edges[hit.index].align ? '(thin blue)' : 'for alignment (thick orange)'}.`;
        return null;
      case 'chart': {
        const f = this.faceAt(hit);
        if (f < 0) return null;
        const face = this.view.summary.face_list[f];
        const next = L.CHARTS[(L.CHARTS.indexOf(face.chart) + 1) % 3];
        return `Face ${f} (corners ${face.corners.join(', ')}): ${face.chart} chart. Click: ${next}.`;
      }
      case 'delete':
        if (hit.kind === 'via') return `Click: delete waypoint ${hit.via} of edges[${hit.index}].`;
        if (hit.kind === 'node') {
          const k = edges(hit.index);
          return `Click: delete ${what}${k ? ` and its ${k} edge${k === 1 ? '' : 's'}` : ''}.`;
        }
        if (hit.kind === 'edge') return `Click: delete ${what}.`;
        return null;
      default:
        return null;
    }
  }

  setHover(hit) {
    const same = (a, b) => (a == null && b == null) || (a && b && a.kind === b.kind && a.index === b.index && a.via === b.via);
    if (same(hit, this.hover)) return;
    this.hover = hit;
    this.draw();
  }

  onKey(event) {
    if (event.target.closest?.('input, textarea, select, [contenteditable]') || !this.mesh) return;
    const key = event.key.toLowerCase();
    if (event.ctrlKey || event.metaKey) {
      if (this.drag) return;
      if (key === 'z' && !event.shiftKey) this.undo();
      else if ((key === 'z' && event.shiftKey) || key === 'y') this.redo();
      else if (key === 's') this.save();
      else return;
      event.preventDefault();
      return;
    }
    if (event.altKey) return;
    if (key === 'escape') {
      if (this.drag) {
        const drag = this.endDrag();
        this.down = null;
        if (drag.previewed) this.apply(this.doc, { record: false, save: false });
      } else if (this.pending != null) {
        this.pending = null;
        this.draw();
        this.drawTransient(null);
        this.updateUi();
      } else {
        this.setMode('view');
      }
      return;
    }
    if ((key === 'delete' || key === 'backspace') && this.hover) {
      event.preventDefault();
      this.deleteHit(this.hover);
      return;
    }
    const mode = Object.keys(MODES).find((m) => MODES[m].key === key);
    if (mode) this.setMode(mode);
  }

  setMode(mode) {
    if (!MODES[mode]) throw new Error(`unknown mode '${mode}' (${Object.keys(MODES).join(', ')})`);
    this.mode = mode;
    this.hoverHint = null;
    if (mode !== 'edge') this.pending = null;
    this.hover = null;
    this.canvas.style.cursor = mode === 'view' ? '' : 'crosshair';
    this.drawTransient(null);
    this.draw();
    this.updatePointer();
    this.updateUi();
  }

  // ---- the page around the view ------------------------------------------------------------

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
      b.addEventListener('click', () => this.setMode(mode));
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
    this.undoButton = action('layout-undo', 'Undo', 'Undo (Ctrl+Z)', () => this.undo(), '^Z');
    this.redoButton = action('layout-redo', 'Redo', 'Redo (Ctrl+Shift+Z, Ctrl+Y)', () => this.redo(), '^Y');
    this.saveButton = action('layout-save', 'Save', 'Download the layout file (Ctrl+S)', () => this.save(), '^S');
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
    const restore = action('restore-yes', 'Restore', 'Bring back the layout saved in this browser', () => this.answerOffer(true));
    restore.classList.add('primary');
    const discard = action('restore-no', 'Discard', 'Forget the saved layout', () => this.answerOffer(false));
    this.offerBox.append(this.offerText, restore, discard);
    this.offerBox.hidden = true;

    this.labels = el('div', 'chart-labels');
    this.viewport.append(bar, status, this.offerBox, this.labels);
    // The old help line says the same as the View tool's hint.
    this.viewport.querySelector('.view-help')?.remove();
  }

  /** Shows a short message in the hint line for a moment. */
  say(text) {
    this.notice = text;
    this.updateUi();
    clearTimeout(this.noticeTimer);
    this.noticeTimer = setTimeout(() => {
      this.notice = null;
      this.updateUi();
    }, 2500);
  }

  updateUi() {
    for (const b of this.modeButtons) b.setAttribute('aria-checked', String(b.dataset.mode === this.mode));
    this.undoButton.disabled = !this.history.canUndo;
    this.redoButton.disabled = !this.history.canRedo;
    this.undoButton.title = `Undo ${this.history.undoLabel ?? ''} (Ctrl+Z)`;
    this.redoButton.title = `Redo ${this.history.redoLabel ?? ''} (Ctrl+Shift+Z)`;
    const has = (this.doc.nodes?.length ?? 0) + (this.doc.edges?.length ?? 0) > 0;
    this.saveButton.disabled = !has;

    let hint = MODES[this.mode].hint;
    if (this.mode === 'edge' && this.pending != null) hint = `From nodes[${this.pending}]: click a node to connect it, or the surface for a new node. Esc ends the chain.`;
    this.hintText.textContent = this.notice ?? this.hoverHint ?? hint;

    const check = this.checkText;
    if (!this.mesh) {
      check.dataset.state = 'empty';
      check.textContent = '';
    } else if (this.checking) {
      check.dataset.state = 'checking';
      check.textContent = 'Checking the layout…';
    } else if (this.error) {
      check.dataset.state = 'error';
      check.textContent = has || !/no nodes/.test(this.error) ? this.error : 'No layout yet: add nodes.';
      if (!has) check.dataset.state = 'empty';
    } else if (this.view) {
      const s = this.view.summary;
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
    document.getElementById('layout-name').textContent = this.layoutName ?? '';
    const dl = document.getElementById('layout-summary');
    const s = this.view?.summary;
    const edges = this.doc.edges ?? [];
    const rows = [
      ['nodes', 'Nodes', s?.nodes ?? this.doc.nodes?.length ?? 0],
      ['edges', 'Edges', `${edges.length} (${edges.filter((e) => e.align).length} tagged)`],
      ['boundary_pieces', 'Boundary edges', s?.boundary_pieces ?? '—'],
      ['faces', 'Faces', s?.faces ?? '—'],
      ['t_vertices', 'T-vertices', s?.t_vertices ?? '—'],
      ['charts', 'Charts', s ? `${s.charts[0]} quad · ${s.charts[1]} rect · ${s.charts[2]} unit` : '—'],
    ];
    dl.replaceChildren(...rows.flatMap(([key, label, value]) => {
      const dt = document.createElement('dt');
      const dd = document.createElement('dd');
      dt.textContent = label;
      dd.textContent = typeof value === 'number' ? value.toLocaleString('en-US') : String(value);
      dd.dataset.key = key;
      return [dt, dd];
    }));
    problem.hidden = !this.error || this.checking;
    problem.textContent = this.error ?? '';
  }

  showOffer(saved) {
    this.offer = saved;
    this.offerBox.hidden = !saved;
    if (saved) {
      const n = saved.doc.nodes.length, m = saved.doc.edges?.length ?? 0;
      this.offerText.textContent = `Restore your layout from ${autosave.formatTime(saved.time)}? (${n} node${n === 1 ? '' : 's'}, ${m} edge${m === 1 ? '' : 's'})`;
    }
  }

  answerOffer(restore) {
    const saved = this.offer;
    this.showOffer(null);
    if (!saved) return;
    if (restore) this.apply(saved.doc, { label: 'restore' });
    else if (!this.history.canUndo) autosave.removeSaved(this.storageKey);
  }

  /**
   * Chart-type labels on the faces, in Chart mode: each at the visible vertex of its face
   * nearest to the face's middle on screen. Placed once the camera rests (the labels hide
   * while it moves), at a cost of the layout's size.
   */
  updateLabels({ now = false } = {}) {
    clearTimeout(this.labelTimer);
    const show = this.mode === 'chart' && this.view && this.mesh;
    if (!show || !now) {
      if (this.labels.childElementCount) this.labels.replaceChildren();
      if (show) this.labelTimer = setTimeout(() => this.updateLabels({ now: true }), 120);
      return;
    }
    if (this.labelView !== this.view) {
      this.labelView = this.view;
      this.faceSamples = faceSamples(this.view.vertex_face, this.view.summary.faces, 48);
    }
    const rect = this.viewport.getBoundingClientRect();
    const items = this.view.summary.face_list.map((face, f) => {
      const seen = this.faceSamples[f].map((v) => [v, this.screenOf(v)]).filter(([, s]) => s);
      if (!seen.length) return null;
      const mx = seen.reduce((a, [, s]) => a + s.x, 0) / seen.length;
      const my = seen.reduce((a, [, s]) => a + s.y, 0) / seen.length;
      seen.sort((a, b) => Math.hypot(a[1].x - mx, a[1].y - my) - Math.hypot(b[1].x - mx, b[1].y - my));
      const at = seen.find(([v]) => this.visible(this.position(v)));
      if (!at) return null;
      const tag = document.createElement('span');
      tag.className = `chart-label chart-${face.chart}`;
      tag.textContent = face.chart;
      tag.style.left = `${at[1].x - rect.left}px`;
      tag.style.top = `${at[1].y - rect.top}px`;
      return tag;
    }).filter(Boolean);
    this.labels.replaceChildren(...items);
  }

  /** What scripts and tests see as `window.quadlay.editor` (documented in main.js). */
  get api() {
    const ed = this;
    return {
      get doc() { return structuredClone(ed.doc); },
      get mode() { return ed.mode; },
      setMode: (m) => ed.setMode(m),
      get error() { return ed.error; },
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
      get offer() { return ed.offer ? { time: ed.offer.time, doc: structuredClone(ed.offer.doc) } : null; },
      get layoutName() { return ed.layoutName; },
      /** Stops the worker as a crash would (for tests): the next edit finds it restarted. */
      stopCore: () => ed.client.terminate('the quadlay core was stopped (test)'),
      /** Restarts the worker as after a crash (the client sends the mesh again; for tests). */
      restartCore: () => ed.client.restart?.('the quadlay core was restarted (test)'),
      undo: () => ed.undo(),
      redo: () => ed.redo(),
      settled: () => ed.settled(),
      setDoc: (doc) => ed.apply(structuredClone(doc), { label: 'script' }),
      text: () => ed.text(),
      save: () => ed.save(),
      screenOf: (target) => ed.screenOf(target),
      /** Edge i as drawn (its curve, or straight segments until traced): [[x, y, z], ...]. */
      edgePoints: (i) => {
        const p = ed.edgePoints[i] ?? [];
        return Array.from({ length: p.length / 3 }, (_, k) => [p[3 * k], p[3 * k + 1], p[3 * k + 2]]);
      },
      pick: (x, y) => {
        const hit = ed.pick(x, y);
        return hit && { kind: hit.kind, index: hit.index, via: hit.via, vertex: hit.vertex, point: hit.point };
      },
      /** The layout face (index into summary.face_list) under page pixel (x, y), or -1. */
      faceAt: (x, y) => ed.faceAt(ed.surfaceAt(x, y) && { kind: 'surface', ...ed.surfaceAt(x, y) }),
      /** The mesh vertex a node placed at page pixel (x, y) would snap to, or -1. */
      vertexAt: (x, y) => ed.surfaceAt(x, y)?.vertex ?? -1,
    };
  }
}

/** `edges[3]` → 3; anything else (a boundary piece) → -1. */
function edgeIndex(source) {
  const m = /^edges\[(\d+)\]$/.exec(source);
  return m ? Number(m[1]) : -1;
}

/** Index of the polyline point nearest to p. */
function nearestPointIndex(pts, p) {
  let best = 0, bestD = Infinity;
  for (let j = 0; j < pts.length; j += 3) {
    const d = (pts[j] - p[0]) ** 2 + (pts[j + 1] - p[1]) ** 2 + (pts[j + 2] - p[2]) ** 2;
    if (d < bestD) { bestD = d; best = j / 3; }
  }
  return best;
}

/** Per face, up to `count` of its vertices, evenly spread over the face's vertex list. */
function faceSamples(vertexFace, faces, count) {
  const lists = Array.from({ length: faces }, () => []);
  vertexFace.forEach((f, v) => {
    if (f >= 0) lists[f].push(v);
  });
  return lists.map((l) => {
    if (l.length <= count) return l;
    const step = l.length / count;
    return Array.from({ length: count }, (_, k) => l[Math.floor(k * step)]);
  });
}

function disposeChildren(group) {
  for (const child of [...group.children]) {
    group.remove(child);
    child.traverse((o) => o.geometry?.dispose());
    if (child.isInstancedMesh || (child.isMesh && child.material && !child.material.isLineMaterial)) child.material.dispose?.();
  }
}
