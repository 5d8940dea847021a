// Picking on the surface: a bounding volume hierarchy over the triangles, built once per
// mesh, so that a ray (a click, the pointer moving) costs a few dozen box and triangle tests
// instead of one test per triangle (three.js's Mesh.raycast tests all of them; on a
// 100k-triangle mesh that is milliseconds per pointer move).

const LEAF = 8;

/** A BVH over a triangle mesh: flat typed arrays, nodes in depth-first order. */
export class TriangleBVH {
  /**
   * @param {Float32Array} positions xyz interleaved
   * @param {Uint32Array} triangles vertex index triples
   */
  constructor(positions, triangles) {
    this.positions = positions;
    this.triangles = triangles;
    const n = triangles.length / 3;
    const centroid = new Float32Array(3 * n);
    for (let t = 0; t < n; t++) {
      for (let k = 0; k < 3; k++) {
        centroid[3 * t + k] = (positions[3 * triangles[3 * t] + k] + positions[3 * triangles[3 * t + 1] + k]
          + positions[3 * triangles[3 * t + 2] + k]) / 3;
      }
    }
    this.order = new Uint32Array(n);
    for (let t = 0; t < n; t++) this.order[t] = t;
    // At most 2n/LEAF·2 nodes; grown if needed.
    let cap = Math.max(16, Math.ceil((4 * n) / LEAF));
    this.bounds = new Float32Array(6 * cap);
    /** For inner nodes: index of the right child (the left is the next node); for leaves -1. */
    this.right = new Int32Array(cap);
    this.start = new Uint32Array(cap);
    this.count = new Uint32Array(cap);
    let used = 0;
    const stack = [[0, n, -1, false]];
    // Iterative build: [first, end, parent, isRight].
    while (stack.length) {
      const [first, end, parent, isRight] = stack.pop();
      if (used === cap) this.grow((cap *= 2));
      const node = used++;
      if (parent >= 0 && isRight) this.right[parent] = node;
      const b = this.bounds;
      let x0 = Infinity, y0 = Infinity, z0 = Infinity, x1 = -Infinity, y1 = -Infinity, z1 = -Infinity;
      let cx0 = Infinity, cy0 = Infinity, cz0 = Infinity, cx1 = -Infinity, cy1 = -Infinity, cz1 = -Infinity;
      for (let i = first; i < end; i++) {
        const t = this.order[i];
        for (let c = 0; c < 3; c++) {
          const v = 3 * triangles[3 * t + c];
          const x = positions[v], y = positions[v + 1], z = positions[v + 2];
          if (x < x0) x0 = x; if (x > x1) x1 = x;
          if (y < y0) y0 = y; if (y > y1) y1 = y;
          if (z < z0) z0 = z; if (z > z1) z1 = z;
        }
        const cx = centroid[3 * t], cy = centroid[3 * t + 1], cz = centroid[3 * t + 2];
        if (cx < cx0) cx0 = cx; if (cx > cx1) cx1 = cx;
        if (cy < cy0) cy0 = cy; if (cy > cy1) cy1 = cy;
        if (cz < cz0) cz0 = cz; if (cz > cz1) cz1 = cz;
      }
      const k6 = 6 * node;
      b[k6] = x0; b[k6 + 1] = y0; b[k6 + 2] = z0; b[k6 + 3] = x1; b[k6 + 4] = y1; b[k6 + 5] = z1;
      this.right[node] = -1;
      this.start[node] = first;
      this.count[node] = end - first;
      if (end - first <= LEAF) continue;
      // Split at the middle of the centroids' extent along its longest axis; fall back to
      // the median when everything lands on one side.
      const ext = [cx1 - cx0, cy1 - cy0, cz1 - cz0];
      const axis = ext[0] >= ext[1] && ext[0] >= ext[2] ? 0 : ext[1] >= ext[2] ? 1 : 2;
      const mid = ([cx0, cy0, cz0][axis] + [cx1, cy1, cz1][axis]) / 2;
      let i = first, j = end - 1;
      const o = this.order;
      while (i <= j) {
        if (centroid[3 * o[i] + axis] < mid) i++;
        else { const tmp = o[i]; o[i] = o[j]; o[j] = tmp; j--; }
      }
      let split = i;
      if (split === first || split === end) {
        const part = Array.from(o.subarray(first, end)).sort((a, c) => centroid[3 * a + axis] - centroid[3 * c + axis]);
        o.set(part, first);
        split = (first + end) >> 1;
      }
      this.count[node] = 0;
      // Right pushed first so the left child is built next, right after its parent.
      stack.push([split, end, node, true], [first, split, node, false]);
    }
    this.nodes = used;
  }

  grow(cap) {
    const grow = (a) => { const b = new a.constructor(cap * (a.length / this.right.length)); b.set(a); return b; };
    this.bounds = grow(this.bounds);
    this.start = grow(this.start);
    this.count = grow(this.count);
    this.right = grow(this.right);
  }

  /**
   * The nearest triangle the ray hits (both sides count).
   * @param {{x,y,z}} origin
   * @param {{x,y,z}} dir unit direction
   * @returns {{triangle: number, t: number, point: number[], bary: number[]}|null}
   */
  raycast(origin, dir) {
    const ox = origin.x, oy = origin.y, oz = origin.z;
    const dx = dir.x, dy = dir.y, dz = dir.z;
    const ix = 1 / dx, iy = 1 / dy, iz = 1 / dz;
    const { bounds: b, right, start, count, order, positions: p, triangles: tri } = this;
    let best = Infinity, bestTri = -1, bu = 0, bv = 0;
    const stack = [0];
    while (stack.length) {
      const node = stack.pop();
      const k = 6 * node;
      // Slab test.
      let t0 = ((ix >= 0 ? b[k] : b[k + 3]) - ox) * ix;
      let t1 = ((ix >= 0 ? b[k + 3] : b[k]) - ox) * ix;
      const ty0 = ((iy >= 0 ? b[k + 1] : b[k + 4]) - oy) * iy;
      const ty1 = ((iy >= 0 ? b[k + 4] : b[k + 1]) - oy) * iy;
      if (ty0 > t0) t0 = ty0;
      if (ty1 < t1) t1 = ty1;
      const tz0 = ((iz >= 0 ? b[k + 2] : b[k + 5]) - oz) * iz;
      const tz1 = ((iz >= 0 ? b[k + 5] : b[k + 2]) - oz) * iz;
      if (tz0 > t0) t0 = tz0;
      if (tz1 < t1) t1 = tz1;
      if (!(t0 <= t1) || t1 < 0 || t0 > best) continue;
      if (right[node] >= 0) {
        stack.push(right[node], node + 1);
        continue;
      }
      for (let i = start[node], e = start[node] + count[node]; i < e; i++) {
        const t = order[i];
        const a = 3 * tri[3 * t], bb = 3 * tri[3 * t + 1], c = 3 * tri[3 * t + 2];
        // Möller–Trumbore.
        const e1x = p[bb] - p[a], e1y = p[bb + 1] - p[a + 1], e1z = p[bb + 2] - p[a + 2];
        const e2x = p[c] - p[a], e2y = p[c + 1] - p[a + 1], e2z = p[c + 2] - p[a + 2];
        const px = dy * e2z - dz * e2y, py = dz * e2x - dx * e2z, pz = dx * e2y - dy * e2x;
        const det = e1x * px + e1y * py + e1z * pz;
        if (Math.abs(det) < 1e-20) continue;
        const inv = 1 / det;
        const sx = ox - p[a], sy = oy - p[a + 1], sz = oz - p[a + 2];
        const u = (sx * px + sy * py + sz * pz) * inv;
        if (u < 0 || u > 1) continue;
        const qx = sy * e1z - sz * e1y, qy = sz * e1x - sx * e1z, qz = sx * e1y - sy * e1x;
        const v = (dx * qx + dy * qy + dz * qz) * inv;
        if (v < 0 || u + v > 1) continue;
        const tt = (e2x * qx + e2y * qy + e2z * qz) * inv;
        if (tt > 0 && tt < best) { best = tt; bestTri = t; bu = u; bv = v; }
      }
    }
    if (bestTri < 0) return null;
    return {
      triangle: bestTri,
      t: best,
      point: [ox + dx * best, oy + dy * best, oz + dz * best],
      bary: [1 - bu - bv, bu, bv],
    };
  }

  /** The vertex of triangle `t` nearest to `point`. */
  nearestCorner(t, point) {
    let best = -1, bestD = Infinity;
    for (let c = 0; c < 3; c++) {
      const v = this.triangles[3 * t + c];
      const d = dist2(this.positions, v, point);
      if (d < bestD) { bestD = d; best = v; }
    }
    return best;
  }
}

/**
 * The mesh's boundary edges (those with one triangle) as vertex pairs, a, b, a, b, ...
 * @param {Uint32Array} triangles vertex index triples
 * @param {number} n the number of vertices
 */
export function boundaryEdges(triangles, n) {
  const count = new Map();
  for (let f = 0; f < triangles.length; f += 3) {
    for (let k = 0; k < 3; k++) {
      const a = triangles[f + k], b = triangles[f + ((k + 1) % 3)];
      const key = a < b ? a * n + b : b * n + a;
      count.set(key, (count.get(key) ?? 0) + 1);
    }
  }
  const out = [];
  for (const [key, c] of count) if (c === 1) out.push(Math.floor(key / n), key % n);
  return Uint32Array.from(out);
}

/**
 * The boundary vertex a point near the boundary snaps to: of the boundary edges within
 * `radius` of `point`, the nearest one's nearer end; -1 when none is that near.
 * @param {Float32Array} positions xyz interleaved
 * @param {Uint32Array} edges boundaryEdges' pairs
 */
export function nearBoundaryVertex(positions, edges, point, radius) {
  let best = -1, bestD = radius * radius;
  for (let i = 0; i < edges.length; i += 2) {
    const a = 3 * edges[i], b = 3 * edges[i + 1];
    const ex = positions[b] - positions[a], ey = positions[b + 1] - positions[a + 1], ez = positions[b + 2] - positions[a + 2];
    const px = point[0] - positions[a], py = point[1] - positions[a + 1], pz = point[2] - positions[a + 2];
    const len2 = ex * ex + ey * ey + ez * ez;
    const s = len2 > 0 ? Math.max(0, Math.min(1, (px * ex + py * ey + pz * ez) / len2)) : 0;
    const dx = px - s * ex, dy = py - s * ey, dz = pz - s * ez;
    const d = dx * dx + dy * dy + dz * dz;
    if (d < bestD) {
      bestD = d;
      best = s < 0.5 ? edges[i] : edges[i + 1];
    }
  }
  return best;
}

/** Squared distance from vertex `v` to `point`. */
export function dist2(positions, v, point) {
  const x = positions[3 * v] - point[0], y = positions[3 * v + 1] - point[1], z = positions[3 * v + 2] - point[2];
  return x * x + y * y + z * z;
}

/** The mesh vertex nearest to `point` (a scan: for clicks and loads, never per frame). */
export function nearestVertex(positions, point) {
  let best = -1, bestD = Infinity;
  for (let v = 0, n = positions.length / 3; v < n; v++) {
    const d = dist2(positions, v, point);
    if (d < bestD) { bestD = d; best = v; }
  }
  return best;
}

/** Distance from (px, py) to the segment (ax, ay)–(bx, by), and the segment parameter. */
export function segmentDistance(px, py, ax, ay, bx, by) {
  const vx = bx - ax, vy = by - ay;
  const len2 = vx * vx + vy * vy;
  let s = len2 > 0 ? ((px - ax) * vx + (py - ay) * vy) / len2 : 0;
  s = Math.max(0, Math.min(1, s));
  const x = ax + s * vx - px, y = ay + s * vy - py;
  return { d: Math.hypot(x, y), s };
}
