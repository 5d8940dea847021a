// The core's errors as the page gets them: JS `Error`s whose `kind` (a stable name) and
// `culprits` (the layout entries and mesh vertices they name, as numbers) say what the
// message says in words, so the page never reads the message (www/protocol.js).
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { test } from 'node:test';

const require = createRequire(import.meta.url);
const { Session } = require('../../target/wasm-node/quadlay.js');
const bytes = new Uint8Array(readFileSync(new URL('../../../shared/meshes/mushroom.obj', import.meta.url)));

/** The mushroom's four boundary corners and its top (see tests/e2e/editor.test.mjs). */
const CORNERS = [147, 151, 139, 143];
const TOP = 16;
const NOTHING = { nodes: [], edges: [], patches: [], vertices: [], point: null };

/** The error `setLayout` throws for a layout of these nodes (mesh vertices) and edges. */
function layoutError(session, { nodes, edges = [], ...rest }) {
  const text = JSON.stringify({ format: 'quad-layout', version: 1, nodes: nodes.map((v) => (typeof v === 'number' ? { vertex: v } : v)), edges, ...rest });
  try {
    session.setLayout(text);
  } catch (err) {
    assert.ok(err instanceof Error, 'not an Error');
    assert.equal(typeof err.message, 'string');
    return { kind: err.kind, culprits: err.culprits, message: err.message };
  }
  assert.fail(`no error for ${text}`);
}

const sorted = (xs) => [...xs].sort((a, b) => a - b);

test('layout errors name their nodes, edges, patches, vertices and points', () => {
  const s = new Session(bytes, 'mushroom.obj');
  try {
    // A node that no edge reaches.
    let e = layoutError(s, { nodes: [...CORNERS, TOP] });
    assert.equal(e.kind, 'node_on_no_edge');
    assert.deepEqual(e.culprits, { ...NOTHING, nodes: [4] });

    // A dangling edge.
    e = layoutError(s, { nodes: [...CORNERS, TOP], edges: [{ nodes: [0, 4] }] });
    assert.equal(e.kind, 'same_face_both_sides');
    assert.deepEqual(e.culprits, { ...NOTHING, edges: [0] });

    // A diagonal: two faces of three nodes; the diagonal is a side of both.
    e = layoutError(s, { nodes: CORNERS, edges: [{ nodes: [0, 2] }] });
    assert.equal(e.kind, 'face_too_few_nodes');
    assert.equal(e.culprits.nodes.length, 3);
    assert.ok(e.culprits.nodes.includes(0) && e.culprits.nodes.includes(2));
    assert.deepEqual(e.culprits.edges, [0]);

    // Both diagonals: they cross in the middle, away from the nodes.
    e = layoutError(s, { nodes: CORNERS, edges: [{ nodes: [0, 2] }, { nodes: [1, 3] }] });
    assert.equal(e.kind, 'curves_meet');
    assert.deepEqual(sorted(e.culprits.edges), [0, 1]);
    assert.equal(e.culprits.point.length, 3);
    assert.ok(e.culprits.point.every(Number.isFinite));
    assert.ok(Math.hypot(e.culprits.point[0], e.culprits.point[1]) < 0.5, `${e.culprits.point} is not near the middle`);

    // One node on the boundary loop: the loop is named by one of its vertices.
    e = layoutError(s, { nodes: [CORNERS[0]] });
    assert.equal(e.kind, 'boundary_loop_nodes');
    assert.equal(e.culprits.vertices.length, 1);
    assert.deepEqual({ ...e.culprits, vertices: [] }, NOTHING);

    // A chart type for corners that are not a face's: the patch and its corners.
    const twoFaces = { nodes: [...CORNERS, TOP], edges: [{ nodes: [0, 4] }, { nodes: [4, 2] }] };
    e = layoutError(s, { ...twoFaces, patches: [{ corners: [0, 1, 2, 3], chart: 'rect' }] });
    assert.equal(e.kind, 'patch_not_a_face');
    assert.deepEqual(e.culprits.patches, [0]);
    assert.deepEqual(sorted(e.culprits.nodes), [0, 1, 2, 3]);

    // A waypoint on another node.
    e = layoutError(s, { nodes: [...CORNERS, TOP], edges: [{ nodes: [0, 4], via: [{ vertex: CORNERS[2] }] }] });
    assert.equal(e.kind, 'no_path');
    assert.deepEqual(e.culprits, { ...NOTHING, edges: [0] });
  } finally {
    s.free();
  }
});

test("the layout file's errors name the entry they are in", () => {
  const s = new Session(bytes, 'mushroom.obj');
  try {
    let e = layoutError(s, { nodes: [...CORNERS, CORNERS[1]] });
    assert.equal(e.kind, 'same_vertex');
    assert.deepEqual(e.culprits, { ...NOTHING, nodes: [4, 1], vertices: [CORNERS[1]] });

    e = layoutError(s, { nodes: CORNERS, edges: [{ nodes: [0, 1] }, { nodes: [2, 9] }] });
    assert.equal(e.kind, 'no_such_node');
    assert.deepEqual(e.culprits, { ...NOTHING, edges: [1] });

    e = layoutError(s, { nodes: [...CORNERS, { vertex: 1e6 }] });
    assert.equal(e.kind, 'no_such_vertex');
    assert.deepEqual(e.culprits, { ...NOTHING, nodes: [4] });

    e = layoutError(s, { nodes: CORNERS, patches: [{ corners: [0, 1, 1, 2] }] });
    assert.equal(e.kind, 'repeated_corner');
    assert.deepEqual(e.culprits, { ...NOTHING, patches: [0] });

    e = layoutError(s, { nodes: CORNERS, colour: 'red' });
    assert.equal(e.kind, 'unknown_key');
    assert.deepEqual(e.culprits, NOTHING);

    assert.throws(() => s.setLayout('{'), (err) => err.kind === 'not_json' && err.culprits.nodes.length === 0);
  } finally {
    s.free();
  }
});

test('mesh files and calls out of order: a kind, nothing to point at', () => {
  const enc = new TextEncoder();
  assert.throws(() => new Session(enc.encode('v 0 0 0\nv 1 zz 0\n'), 'bad.obj'),
    (err) => err.kind === 'read_syntax' && /line 2/.test(err.message) && err.culprits.vertices.length === 0);
  assert.throws(() => new Session(enc.encode('<xml/>'), 'x.dae'), (err) => err.kind === 'unknown_format');
  const s = new Session(bytes, 'mushroom.obj');
  try {
    assert.throws(() => s.startParam({}), (err) => err.kind === 'no_layout');
    assert.throws(() => s.remesh({}), (err) => err.kind === 'no_param');
    s.setLayout(JSON.stringify({ format: 'quad-layout', version: 1, nodes: CORNERS.map((vertex) => ({ vertex })), edges: [] }));
    assert.throws(() => s.startParam({ charts: 'rect' }), (err) => err.kind === 'bad_options');
    s.startParam({});
    assert.throws(() => s.remesh({ edge_length: -1 }), (err) => err.kind === 'edge_length');
  } finally {
    s.free();
  }
});
