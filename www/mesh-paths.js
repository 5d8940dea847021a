// Shortest paths along mesh edges, for drawing an edge the core has not traced yet (while
// the layout is invalid the core returns no curves): A* over the vertex graph, edge lengths
// as weights, the straight-line distance as the (admissible) estimate. The core's geodesic
// crosses triangles and is shorter; this path follows the surface closely enough to show
// where the edge will run.

/** The mesh's vertex graph in compressed rows: neighbours of v are adj[start[v]..start[v+1]). */
export function meshGraph(positions, triangles) {
  const n = positions.length / 3;
  const degree = new Uint32Array(n + 1);
  for (let f = 0; f < triangles.length; f += 3) {
    for (let k = 0; k < 3; k++) degree[triangles[f + k]] += 2;
  }
  const start = new Uint32Array(n + 1);
  for (let v = 0; v < n; v++) start[v + 1] = start[v] + degree[v];
  const fill = start.slice(0, n);
  const adj = new Uint32Array(start[n]);
  for (let f = 0; f < triangles.length; f += 3) {
    for (let k = 0; k < 3; k++) {
      const a = triangles[f + k], b = triangles[f + ((k + 1) % 3)];
      // Each interior edge is listed twice (once per triangle); harmless for the search.
      adj[fill[a]++] = b;
      adj[fill[b]++] = a;
    }
  }
  return { n, start, adj, positions };
}

/**
 * The shortest path along mesh edges through `stops` (vertex indices) in order, as xyz
 * interleaved positions, or null when some stop cannot be reached.
 */
export function pathThrough(graph, stops) {
  const out = [];
  for (let i = 0; i + 1 < stops.length; i++) {
    const part = shortestPath(graph, stops[i], stops[i + 1]);
    if (!part) return null;
    for (let k = i === 0 ? 0 : 1; k < part.length; k++) {
      const v = part[k];
      out.push(graph.positions[3 * v], graph.positions[3 * v + 1], graph.positions[3 * v + 2]);
    }
  }
  return out;
}

/** Vertices of a shortest path from `from` to `to` along mesh edges (A*), or null. */
export function shortestPath(graph, from, to) {
  const { start, adj, positions: p } = graph;
  const dist = new Map([[from, 0]]);
  const prev = new Map();
  const done = new Set();
  const tx = p[3 * to], ty = p[3 * to + 1], tz = p[3 * to + 2];
  const h = (v) => Math.hypot(p[3 * v] - tx, p[3 * v + 1] - ty, p[3 * v + 2] - tz);
  const heap = new MinHeap();
  heap.push(h(from), from);
  while (heap.size) {
    const v = heap.pop();
    if (done.has(v)) continue;
    if (v === to) break;
    done.add(v);
    const dv = dist.get(v);
    for (let k = start[v]; k < start[v + 1]; k++) {
      const w = adj[k];
      if (done.has(w)) continue;
      const d = dv + Math.hypot(p[3 * v] - p[3 * w], p[3 * v + 1] - p[3 * w + 1], p[3 * v + 2] - p[3 * w + 2]);
      if (d < (dist.get(w) ?? Infinity)) {
        dist.set(w, d);
        prev.set(w, v);
        heap.push(d + h(w), w);
      }
    }
  }
  if (!dist.has(to)) return null;
  const path = [to];
  while (path[path.length - 1] !== from) path.push(prev.get(path[path.length - 1]));
  return path.reverse();
}

/** A binary min-heap of (key, value) pairs. */
class MinHeap {
  constructor() {
    this.keys = [];
    this.values = [];
  }

  get size() {
    return this.keys.length;
  }

  push(key, value) {
    const { keys, values } = this;
    let i = keys.length;
    keys.push(key);
    values.push(value);
    while (i > 0) {
      const parent = (i - 1) >> 1;
      if (keys[parent] <= key) break;
      keys[i] = keys[parent];
      values[i] = values[parent];
      i = parent;
    }
    keys[i] = key;
    values[i] = value;
  }

  pop() {
    const { keys, values } = this;
    const top = values[0];
    const lastKey = keys.pop();
    const lastValue = values.pop();
    if (keys.length) {
      let i = 0;
      for (;;) {
        const l = 2 * i + 1;
        if (l >= keys.length) break;
        const c = l + 1 < keys.length && keys[l + 1] < keys[l] ? l + 1 : l;
        if (keys[c] >= lastKey) break;
        keys[i] = keys[c];
        values[i] = values[c];
        i = c;
      }
      keys[i] = lastKey;
      values[i] = lastValue;
    }
    return top;
  }
}
