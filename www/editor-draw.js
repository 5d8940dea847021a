// The layout editor's drawing (three.js): the layout's curves, nodes and waypoints over the
// surface, the culprits of the core's error in red, the ghost dot and rubber band that
// follow the pointer, and the chart-type labels. It reads the editor's state (the session's
// document and verdict, the tool, hover and pending node) and changes none of it.
//
// Edges the core has not traced yet are drawn dashed along the shortest path over mesh edges
// (mesh-paths.js), or straight through the surface until that is known; the curves of
// unchanged edges are kept from the last valid layout.
import * as THREE from 'three';
import { Line2 } from 'three/addons/lines/Line2.js';
import { LineGeometry } from 'three/addons/lines/LineGeometry.js';
import { LineMaterial } from 'three/addons/lines/LineMaterial.js';
import { LineSegments2 } from 'three/addons/lines/LineSegments2.js';
import { LineSegmentsGeometry } from 'three/addons/lines/LineSegmentsGeometry.js';
import { edgeIndex } from './layout-doc.js';
import { meshGraph, pathThrough } from './mesh-paths.js';

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

export class EditorDrawing {
  /**
   * @param {import('./editor.js').Editor} ed the editor whose state is drawn
   * @param {HTMLElement} viewport where the chart labels go
   */
  constructor(ed, viewport) {
    this.ed = ed;
    this.viewer = ed.viewer;
    this.viewport = viewport;
    this.layer = new THREE.Group();
    this.layer.name = 'layout-editor';
    this.viewer.scene.add(this.layer);
    this.transient = new THREE.Group(); // ghost dot and rubber band, moved without a redraw
    this.viewer.scene.add(this.transient);
    this.materials = new Map();
    /** Curves already traced, by edge key (its ends' vertices and waypoints). */
    this.curveCache = new Map();
    /** Paths along mesh edges for edges the core has not traced, by edge key. */
    this.pathCache = new Map();
    /** Every edge as drawn (xyz interleaved), by edge index. */
    this.edgePoints = [];
    this.labels = document.createElement('div');
    this.labels.className = 'chart-labels';
    viewport.append(this.labels);
  }

  /** Forgets what belongs to the mesh (all of it for a new mesh, else its geometry only). */
  resetMesh({ kept }) {
    this.boundary = null;
    this.graph = null;
    if (kept) return;
    this.curveCache.clear();
    this.pathCache.clear();
    this.ed.radius = this.viewer.radius;
  }

  /** Keeps the curves the core traced for the current document. */
  keepCurves(view) {
    const { doc } = this.ed.session;
    for (const c of view.curves) {
      const i = edgeIndex(c.source);
      if (i >= 0 && doc.edges?.[i]) this.curveCache.set(this.ed.session.edgeKey(doc.edges[i]), c.points);
    }
  }

  /**
   * Where an edge the core has not traced yet runs: the shortest path along mesh edges
   * through its stops (cached), or null if a stop is unusable.
   */
  provisionalPath(e) {
    const key = this.ed.session.edgeKey(e);
    if (this.pathCache.has(key)) return this.pathCache.get(key);
    const [a, b] = e.nodes ?? [];
    const stops = [this.ed.nodeVertex[a], ...(e.via ?? []).map((w) => this.ed.session.vertexOf(w)), this.ed.nodeVertex[b]];
    let path = null;
    if (stops.every((v) => v >= 0)) {
      this.graph ??= meshGraph(this.ed.mesh.positions, this.ed.mesh.triangles);
      path = pathThrough(this.graph, stops);
    }
    this.pathCache.set(key, path);
    return path;
  }

  /** Straight segments through an edge's stops (drawn until the core traces it), or null. */
  straight(e) {
    const [a, b] = e.nodes ?? [];
    const va = this.ed.nodeVertex[a], vb = this.ed.nodeVertex[b];
    if (!(va >= 0) || !(vb >= 0)) return null;
    const stops = [this.ed.session.position(va), ...(e.via ?? []).map((w) => this.ed.session.viaPosition(w)).filter(Boolean), this.ed.session.position(vb)];
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
        dashSize: this.ed.radius * 0.025,
        gapSize: this.ed.radius * 0.018,
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
    if (!this.ed.mesh) {
      this.viewer.requestRender();
      return;
    }
    // Material sizes depend on the mesh.
    if (this.materialsRadius !== this.ed.radius) {
      for (const m of this.materials.values()) m.dispose();
      this.materials.clear();
      this.materialsRadius = this.ed.radius;
    }
    const r = this.ed.radius;
    const doc = this.ed.doc;
    const problem = this.ed.problem;
    const hover = this.ed.hover;

    // The mesh's boundary is part of every layout.
    const boundary = this.boundarySegments();
    if (boundary.length) {
      const g = new LineSegmentsGeometry();
      g.setPositions(boundary);
      this.layer.add(new LineSegments2(g, this.material('boundary')));
    }

    const traced = new Map();
    for (const c of this.ed.view?.curves ?? []) {
      const i = edgeIndex(c.source);
      if (i >= 0) traced.set(i, c.points);
    }
    this.edgePoints = [];
    (doc.edges ?? []).forEach((e, i) => {
      let points = traced.get(i) ?? this.curveCache.get(this.ed.session.edgeKey(e));
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
      if (hovered && this.ed.mode === 'delete') kind = 'error';
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
    const tVertices = new Set((this.ed.view?.summary.face_list ?? []).flatMap((f) => f.t_vertices));
    const dot = new THREE.SphereGeometry(r * 0.015, 14, 10);
    const nodes = this.ed.nodeVertex.map((v, n) => [v, n]).filter(([v]) => v >= 0);
    if (nodes.length) {
      const mesh = new THREE.InstancedMesh(dot, new THREE.MeshBasicMaterial(), nodes.length);
      const m = new THREE.Matrix4();
      const c = new THREE.Color();
      nodes.forEach(([v, n], k) => {
        const [x, y, z] = this.ed.session.position(v);
        const big = (hover?.kind === 'node' && hover.index === n) || this.ed.pending === n ? 1.5 : 1;
        mesh.setMatrixAt(k, m.makeScale(big, big, big).setPosition(x, y, z));
        let color = tVertices.has(n) ? COLOR.tvertex : COLOR.node;
        if (this.ed.pending === n) color = COLOR.pending;
        if (hover?.kind === 'node' && hover.index === n) color = this.ed.mode === 'delete' ? COLOR.error : 0x9fd0ff;
        if (problem.nodes.has(n)) color = COLOR.error;
        mesh.setColorAt(k, c.setHex(color));
      });
      mesh.renderOrder = 4;
      this.layer.add(mesh);
    }

    // Waypoints, where they can be moved or deleted.
    if (this.ed.mode === 'bend' || this.ed.mode === 'delete') {
      const handles = [];
      (doc.edges ?? []).forEach((e, i) => (e.via ?? []).forEach((w, k) => {
        const p = this.ed.session.viaPosition(w);
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
          mesh.setColorAt(j, c.setHex(on && this.ed.mode === 'delete' ? COLOR.error : on ? 0xffffff : COLOR.via));
        });
        mesh.renderOrder = 4;
        this.layer.add(mesh);
      }
    }

    // What the error names but is not a node or an edge: vertices, a crossing point.
    const halos = [];
    for (const n of problem.nodes) if (this.ed.nodeVertex[n] >= 0) halos.push(this.ed.session.position(this.ed.nodeVertex[n]));
    for (const v of problem.vertices) if (v >= 0 && v < this.ed.mesh.positions.length / 3) halos.push(this.ed.session.position(v));
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
    const out = [];
    for (const v of this.ed.picker.boundaryEdges()) out.push(...this.ed.session.position(v));
    this.boundary = out;
    return out;
  }

  /** The ghost dot (where a click would put a node) and the rubber band of edge mode. */
  drawTransient(target, { ghost = true } = {}) {
    // Nothing shown and nothing to show: no frame to draw.
    if (!target && !this.ed.input.drag?.target && !this.transient.children.length) return;
    disposeChildren(this.transient);
    if (target && ghost) {
      const dot = new THREE.Mesh(
        new THREE.SphereGeometry(this.ed.radius * 0.011, 12, 8),
        new THREE.MeshBasicMaterial({ color: COLOR.ghost, transparent: true, opacity: 0.55, depthTest: false }),
      );
      dot.position.set(...target);
      dot.renderOrder = 6;
      this.transient.add(dot);
    }
    const from = this.ed.input.drag ? null : this.ed.pending != null ? this.ed.nodeVertex[this.ed.pending] : -1;
    if (this.ed.mode === 'edge' && from >= 0 && target) {
      const g = new LineGeometry();
      g.setPositions([...this.ed.session.position(from), ...target]);
      const line = new Line2(g, this.material('rubber', { dashed: true }));
      line.computeLineDistances();
      line.renderOrder = 6;
      this.transient.add(line);
    }
    const drag = this.ed.input.drag;
    if (drag?.curves) {
      // The core's curves through the dragged waypoint or node where it is now.
      for (const points of drag.curves) {
        const g = new LineGeometry();
        g.setPositions(points);
        const line = new Line2(g, this.material('hover', { width: 4 }));
        line.renderOrder = 6;
        this.transient.add(line);
      }
    } else if (drag?.target) {
      for (const [before, after] of this.dragNeighbours(drag)) {
        const g = new LineGeometry();
        g.setPositions([...before, ...drag.target, ...(after ?? [])]);
        const line = new Line2(g, this.material('rubber', { dashed: true }));
        line.computeLineDistances();
        line.renderOrder = 6;
        this.transient.add(line);
      }
    }
    this.viewer.requestRender();
  }

  /**
   * The stops next to a dragged waypoint or node, for its rubber band: [before, after] for a
   * waypoint, [neighbour] for each edge of a node.
   */
  dragNeighbours(drag) {
    const S = this.ed.session;
    const stops = (e) => [S.position(this.ed.nodeVertex[e.nodes[0]]), ...(e.via ?? []).map((w) => S.viaPosition(w)), S.position(this.ed.nodeVertex[e.nodes[1]])];
    if (drag.node != null) {
      return this.ed.input.incidentEdges(drag.node).flatMap((i) => {
        const e = this.ed.doc.edges[i];
        const s = stops(e);
        const next = e.nodes[0] === drag.node ? s[1] : s.at(-2);
        return this.ed.nodeVertex[e.nodes[0]] >= 0 && this.ed.nodeVertex[e.nodes[1]] >= 0 && next ? [[next]] : [];
      });
    }
    const e = this.ed.doc.edges[drag.edge];
    const s = stops(e);
    // Stop k is before waypoint k (s[0] is the first node); a moved waypoint is s[k + 1].
    return [[s[drag.k], s[drag.insert ? drag.k + 1 : drag.k + 2]]];
  }

  /**
   * Chart-type labels on the faces, in Chart mode: each at the visible vertex of its face
   * nearest to the face's middle on screen. Placed once the camera rests (the labels hide
   * while it moves), at a cost of the layout's size.
   */
  updateLabels({ now = false } = {}) {
    clearTimeout(this.labelTimer);
    const show = this.ed.mode === 'chart' && this.ed.view && this.ed.mesh;
    if (!show || !now) {
      if (this.labels.childElementCount) this.labels.replaceChildren();
      if (show) this.labelTimer = setTimeout(() => this.updateLabels({ now: true }), 120);
      return;
    }
    if (this.labelView !== this.ed.view) {
      this.labelView = this.ed.view;
      this.faceSamples = faceSamples(this.ed.view.vertex_face, this.ed.view.summary.faces, 48);
    }
    const rect = this.viewport.getBoundingClientRect();
    const items = this.ed.view.summary.face_list.map((face, f) => {
      const seen = this.faceSamples[f].map((v) => [v, this.ed.picker.screenOf(v)]).filter(([, s]) => s);
      if (!seen.length) return null;
      const mx = seen.reduce((a, [, s]) => a + s.x, 0) / seen.length;
      const my = seen.reduce((a, [, s]) => a + s.y, 0) / seen.length;
      seen.sort((a, b) => Math.hypot(a[1].x - mx, a[1].y - my) - Math.hypot(b[1].x - mx, b[1].y - my));
      const at = seen.find(([v]) => this.ed.picker.visible(this.ed.session.position(v)));
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
