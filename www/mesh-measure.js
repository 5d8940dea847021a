// Measures of the shown mesh that the page needs itself: its surface area (a target quad
// count's edge length, √(area / quads), for the checkerboard before the core has remeshed)
// and the sizes of its boundary loops (the default of the fill-holes repair).
import { boundaryEdges } from './picking.js';

/** The total area of the triangles. */
export function surfaceArea(positions, triangles) {
  let sum = 0;
  for (let t = 0; t < triangles.length; t += 3) {
    const a = 3 * triangles[t], b = 3 * triangles[t + 1], c = 3 * triangles[t + 2];
    const ux = positions[b] - positions[a], uy = positions[b + 1] - positions[a + 1], uz = positions[b + 2] - positions[a + 2];
    const vx = positions[c] - positions[a], vy = positions[c + 1] - positions[a + 1], vz = positions[c + 2] - positions[a + 2];
    sum += Math.hypot(uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx) / 2;
  }
  return sum;
}

/**
 * The number of edges of every boundary loop, longest first. Loops are followed through
 * boundary vertices; a vertex where several loops touch is walked through once per visit.
 */
export function boundaryLoopSizes(triangles, n) {
  const edges = boundaryEdges(triangles, n);
  const next = new Map();
  for (let i = 0; i < edges.length; i += 2) {
    for (const [a, b] of [[edges[i], edges[i + 1]], [edges[i + 1], edges[i]]]) {
      if (!next.has(a)) next.set(a, []);
      next.get(a).push(b);
    }
  }
  const used = new Set();
  const key = (a, b) => (a < b ? a * n + b : b * n + a);
  const sizes = [];
  for (let i = 0; i < edges.length; i += 2) {
    if (used.has(key(edges[i], edges[i + 1]))) continue;
    let at = edges[i + 1];
    used.add(key(edges[i], at));
    let size = 1;
    for (;;) {
      const on = next.get(at).find((v) => !used.has(key(at, v)));
      if (on === undefined) break;
      used.add(key(at, on));
      size++;
      at = on;
    }
    sizes.push(size);
  }
  return sizes.sort((a, b) => b - a);
}
