// The layout editor's document edits (www/layout-doc.js) and picking (www/picking.js), run in
// Node against the wasm core the page uses: every edit gives a document the core reads, the
// editor reads the entries the core's errors name, and the BVH finds what a brute-force ray
// test finds.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { test } from 'node:test';
import * as L from '../../www/layout-doc.js';
import { History } from '../../www/history.js';
import { meshGraph, pathThrough, shortestPath } from '../../www/mesh-paths.js';
import { TriangleBVH, nearestVertex } from '../../www/picking.js';

const require = createRequire(import.meta.url);
const { Session } = require('../../target/wasm-node/quadlay.js');
const bytes = new Uint8Array(readFileSync(new URL('../../../shared/meshes/mushroom.obj', import.meta.url)));

/** The mushroom's four boundary corners and its top (see tests/e2e/editor.test.mjs). */
const CORNERS = [147, 151, 139, 143];
const TOP = 16;

function place(session, doc) {
  try {
    return { view: session.setLayout(L.toText(doc)) };
  } catch (err) {
    return { error: err.message, fault: err };
  }
}

test('a layout drawn edit by edit: the core follows every step', () => {
  const s = new Session(bytes, 'mushroom.obj');
  let doc = L.emptyDoc();
  for (const v of CORNERS) doc = L.addNode(doc, v)[0];
  assert.equal(place(s, doc).view.summary.faces, 1);

  let top;
  [doc, top] = L.addNode(doc, TOP);
  let r = place(s, doc);
  assert.match(r.error, /^nodes\[4\]: /);
  assert.deepEqual([...L.problemOf(r.fault).nodes], [top]);

  doc = L.addEdge(doc, 0, top)[0];
  r = place(s, doc);
  assert.match(r.error, /^edges\[0\]: the same face lies on both sides/);
  assert.deepEqual([...L.problemOf(r.fault).edges], [0]);

  doc = L.addEdge(doc, top, 2)[0];
  r = place(s, doc);
  assert.equal(r.view.summary.faces, 2);
  assert.equal(L.findEdge(doc, 2, top), 1);

  // Tagging, a T-vertex, chart types.
  doc = L.toggleAlign(doc, 0);
  assert.equal(place(s, doc).view.summary.aligned_edges, 1);
  const [split, t] = L.splitEdge(doc, 1, 1200);
  assert.deepEqual(split.edges.map((e) => e.nodes), [[0, 4], [4, t], [t, 2]]);
  r = place(s, split);
  assert.equal(r.view.summary.faces, 2, r.error);
  assert.ok(r.view.summary.t_vertices >= 1);
  const corners = r.view.summary.face_list[0].corners;
  let charted = L.setChart(split, corners, 'rect');
  assert.equal(L.chartOf(charted, corners), 'rect');
  // The same corners rotated name the same face.
  assert.equal(L.chartOf(charted, [...corners.slice(1), corners[0]]), 'rect');
  r = place(s, charted);
  assert.deepEqual(r.view.summary.charts, [1, 1, 0]);
  charted = L.setChart(charted, corners, 'quad');
  assert.equal(charted.patches, undefined, 'a face back at the default chart keeps an entry');

  // Deleting a node renumbers the others and drops its edges and patches.
  const withPatch = L.setChart(split, corners, 'unit');
  const fewer = L.deleteNode(withPatch, 0);
  assert.equal(fewer.nodes.length, 5);
  assert.deepEqual(fewer.edges.map((e) => e.nodes), [[3, t - 1], [t - 1, 1]]);
  assert.equal(fewer.patches, undefined, 'a patch with the deleted node as corner stays');
  const other = L.deleteNode(withPatch, corners.includes(1) ? 99 : 1);
  if (!corners.includes(1)) assert.deepEqual(other.patches[0].corners, corners.map((n) => (n > 1 ? n - 1 : n)));
});

test('waypoints: inserted, moved, deleted; the file text round-trips', () => {
  const s = new Session(bytes, 'mushroom.obj');
  let doc = L.emptyDoc();
  for (const v of [...CORNERS, TOP]) doc = L.addNode(doc, v)[0];
  doc = L.addEdge(doc, 0, 4)[0];
  doc = L.addEdge(doc, 4, 2)[0];
  // A waypoint a little beside the middle of the first curve.
  const curve = place(s, doc).view.curves.find((c) => c.source.edge === 0).points;
  const m = 3 * Math.floor(curve.length / 6);
  const near = nearestVertex(s.positions(), [curve[m] + 0.03, curve[m + 1] - 0.03, curve[m + 2]]);
  const bent = L.insertVia(doc, 0, 0, near);
  assert.deepEqual(bent.edges[0].via, [{ vertex: near }]);
  const r = place(s, bent);
  assert.equal(r.view?.summary.faces, 2, r.error);
  const moved = L.moveVia(bent, 0, 0, 1310);
  assert.deepEqual(moved.edges[0].via, [{ vertex: 1310 }]);
  assert.equal(L.deleteVia(moved, 0, 0).edges[0].via, undefined);
  assert.deepEqual(doc.edges[0].via, undefined, 'an edit changed its input');

  const text = L.toText({ ...moved, defaults: { chart: 'rect' } });
  assert.deepEqual(L.parseDoc(text), { ...moved, defaults: { chart: 'rect' } });
  assert.equal(text.split('\n')[0], '{');
  assert.match(text, /^ "format": "quad-layout",$/m);
  assert.throws(() => L.parseDoc('{'), /not valid JSON/);
  assert.throws(() => L.parseDoc('{"nodes": 3}'), /'nodes' must be a list/);
});

test('undo and redo walk the documents; a new edit drops what could be redone', () => {
  const h = new History();
  const a = L.emptyDoc();
  const b = L.addNode(a, 1)[0];
  const c = L.addNode(b, 2)[0];
  h.clear(a);
  h.push(b, 'add node');
  h.push(c, 'add node');
  assert.equal(h.undo(), b);
  assert.equal(h.undo(), a);
  assert.equal(h.undo(), null);
  assert.equal(h.redo(), b);
  const d = L.addNode(b, 3)[0];
  h.push(d, 'add node');
  assert.equal(h.canRedo, false);
  assert.equal(h.current, d);
});

test('the BVH hits what every triangle tested one by one hits', () => {
  const s = new Session(bytes, 'mushroom.obj');
  const P = s.positions();
  const T = s.triangles();
  const bvh = new TriangleBVH(P, T);
  let state = 7;
  const rand = () => ((state = (state * 1103515245 + 12345) % 2147483648) / 2147483648);
  let hits = 0;
  for (let i = 0; i < 200; i++) {
    // Towards the centroid of a triangle, so no ray grazes an edge or a vertex.
    const v = Math.floor(rand() * (T.length / 3));
    const c = [0, 1, 2].map((k) => (P[3 * T[3 * v] + k] + P[3 * T[3 * v + 1] + k] + P[3 * T[3 * v + 2] + k]) / 3);
    const o = { x: (rand() - 0.5) * 4, y: (rand() - 0.5) * 4, z: (rand() - 0.5) * 4 };
    const d = { x: c[0] - o.x, y: c[1] - o.y, z: c[2] - o.z };
    const n = Math.hypot(d.x, d.y, d.z);
    Object.assign(d, { x: d.x / n, y: d.y / n, z: d.z / n });
    const hit = bvh.raycast(o, d);
    // Brute force: the nearest hit over all triangles, the same test.
    let best = Infinity;
    for (let t = 0; t < T.length / 3; t++) {
      const one = new TriangleBVH(P, T.subarray(3 * t, 3 * t + 3)).raycast(o, d);
      if (one && one.t < best) best = one.t;
    }
    if (best < Infinity) hits++;
    assert.ok(hit, `ray ${i} towards triangle ${v} missed`);
    assert.ok(Math.abs(hit.t - best) < 1e-9, `ray ${i}: ${hit.t} vs ${best}`);
  }
  assert.equal(hits, 200);
  assert.equal(nearestVertex(P, [P[30], P[31], P[32]]), 10);
});

test('paths along mesh edges (drawn for edges not traced yet) are connected and short', () => {
  const s = new Session(bytes, 'mushroom.obj');
  const P = s.positions();
  const T = s.triangles();
  const g = meshGraph(P, T);
  const edges = new Set();
  for (let f = 0; f < T.length; f += 3) {
    for (let k = 0; k < 3; k++) edges.add(`${T[f + k]},${T[f + ((k + 1) % 3)]}`);
  }
  const len = (a, b) => Math.hypot(P[3 * a] - P[3 * b], P[3 * a + 1] - P[3 * b + 1], P[3 * a + 2] - P[3 * b + 2]);
  const path = shortestPath(g, CORNERS[0], TOP);
  assert.equal(path[0], CORNERS[0]);
  assert.equal(path.at(-1), TOP);
  let total = 0;
  for (let i = 1; i < path.length; i++) {
    assert.ok(edges.has(`${path[i - 1]},${path[i]}`) || edges.has(`${path[i]},${path[i - 1]}`), `step ${i} is not a mesh edge`);
    total += len(path[i - 1], path[i]);
  }
  assert.ok(total >= len(CORNERS[0], TOP));
  // Through a waypoint: the two halves, joined once.
  const through = pathThrough(g, [CORNERS[0], TOP, CORNERS[2]]);
  const a = shortestPath(g, CORNERS[0], TOP).length, b = shortestPath(g, TOP, CORNERS[2]).length;
  assert.equal(through.length / 3, a + b - 1);
});
