// What the pointer is over in the layout editor: page pixels of points on the mesh, the
// surface under a pixel (a ray through picking.js's BVH), and the waypoint, node or edge a
// click there hits. Drawn curves are projected once per camera position, so pointer moves
// cost the layout's size, not the mesh's.
import * as THREE from 'three';
import { TriangleBVH, boundaryEdges, dist2, nearBoundaryVertex, segmentDistance } from './picking.js';

/** Pick radii in CSS pixels. */
const PICK = { node: 11, via: 10, edge: 8 };
/** A click this near the mesh's boundary (CSS pixels) snaps to a boundary vertex. */
const BOUNDARY_SNAP = 8;

export class EditorPicker {
  /** @param {import('./editor.js').Editor} ed the editor whose layout is picked */
  constructor(ed) {
    this.ed = ed;
    this.viewer = ed.viewer;
    this.canvas = ed.canvas;
    this.bvh = null;
    this.boundary = null;
  }

  /** Forgets what belongs to the shown mesh. */
  resetMesh() {
    this.bvh = null;
    this.boundary = null;
  }

  /** The mesh's boundary edges as vertex pairs (found once per mesh). */
  boundaryEdges() {
    if (!this.boundary && this.ed.mesh) this.boundary = boundaryEdges(this.ed.mesh.triangles, this.ed.mesh.positions.length / 3);
    return this.boundary ?? new Uint32Array(0);
  }

  /** The BVH of the shown mesh, built on first use. */
  ensureBvh() {
    if (!this.bvh && this.ed.mesh) this.bvh = new TriangleBVH(this.ed.mesh.positions, this.ed.mesh.triangles);
    return this.bvh;
  }


  /** Page pixels of a mesh vertex (or an [x, y, z] point), null when behind the camera. */
  screenOf(target) {
    const p = Array.isArray(target) ? target : this.ed.session.position(target);
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

  /**
   * The surface under page pixel (x, y): { triangle, point, vertex } or null. `vertex` is
   * where a node placed there goes: the hit triangle's nearest corner, or within a few
   * pixels of the mesh's boundary a boundary vertex (a node meant for the rim must not land
   * one vertex inside it).
   */
  surfaceAt(x, y) {
    const bvh = this.ensureBvh();
    if (!bvh) return null;
    const { origin, direction } = this.ray(x, y);
    const hit = bvh.raycast(origin, direction);
    if (!hit) return null;
    const pixel = (2 * hit.t * Math.tan(THREE.MathUtils.degToRad(this.viewer.camera.fov) / 2)) / this.canvas.getBoundingClientRect().height;
    const rim = nearBoundaryVertex(this.ed.mesh.positions, this.boundaryEdges(), hit.point, BOUNDARY_SNAP * pixel);
    return { ...hit, vertex: rim >= 0 ? rim : bvh.nearestCorner(hit.triangle, hit.point) };
  }

  /** Whether point p is in front of the surface as the camera sees it. */
  visible(p) {
    const cam = this.viewer.camera.position;
    const d = new THREE.Vector3(...p).sub(cam);
    const len = d.length();
    const hit = this.ensureBvh().raycast(cam, d.normalize());
    return !hit || hit.t >= len - this.ed.radius * 0.02;
  }

  /**
   * What is under page pixel (x, y): a waypoint, a node, an edge (with the curve point
   * nearest to the pointer), or the surface; null over the background.
   */
  pick(x, y) {
    if (!this.ed.mesh) return null;
    const candidates = [];
    if (this.ed.mode === 'bend' || this.ed.mode === 'delete') {
      (this.ed.doc.edges ?? []).forEach((e, i) => (e.via ?? []).forEach((w, k) => {
        const p = this.ed.session.viaPosition(w);
        const s = p && this.screenOf(p);
        const d = s && Math.hypot(s.x - x, s.y - y);
        if (d <= PICK.via) candidates.push({ kind: 'via', index: i, via: k, d: d - 2, point: p });
      }));
    }
    this.ed.nodeVertex.forEach((v, n) => {
      if (v < 0) return;
      const p = this.ed.session.position(v);
      const s = this.screenOf(p);
      const d = s && Math.hypot(s.x - x, s.y - y);
      if (d <= PICK.node) candidates.push({ kind: 'node', index: n, d: d - 1, point: p });
    });
    const screen = this.projectedCurves();
    this.ed.drawing.edgePoints.forEach((pts, i) => {
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
    if (this.projection?.key === key && this.projection.curves === this.ed.drawing.edgePoints) return this.projection.screen;
    const m = new THREE.Matrix4().multiplyMatrices(cam.projectionMatrix, cam.matrixWorldInverse).elements;
    const screen = this.ed.drawing.edgePoints.map((pts) => {
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
    this.projection = { key, curves: this.ed.drawing.edgePoints, screen };
    return screen;
  }

  /** The face under a surface hit (index into the summary's face_list), or -1. */
  faceAt(hit) {
    if (hit?.kind !== 'surface' || !this.ed.view) return -1;
    const t = this.ed.mesh.triangles;
    const corners = [0, 1, 2].map((k) => t[3 * hit.triangle + k])
      .sort((a, b) => dist2(this.ed.mesh.positions, a, hit.point) - dist2(this.ed.mesh.positions, b, hit.point));
    for (const v of corners) if (this.ed.view.vertex_face[v] >= 0) return this.ed.view.vertex_face[v];
    return -1;
  }

}
