// The layout editor's session (www/layout-session.js) in Node, against the wasm core the page
// uses: edits checked by the core, undo and redo, the latest of quick edits checked, the
// autosave offered and restored on the same mesh, the culprits of the core's error, a chart
// type on a face an edit removed dropped with that edit, and a core that lost its mesh.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { test } from 'node:test';
import * as L from '../../www/layout-doc.js';
import { LayoutSession } from '../../www/layout-session.js';

const require = createRequire(import.meta.url);
const { Session } = require('../../target/wasm-node/quadlay.js');
const bytes = new Uint8Array(readFileSync(new URL('../../../shared/meshes/mushroom.obj', import.meta.url)));

/** The mushroom's four boundary corners and its top (see tests/e2e/editor.test.mjs). */
const CORNERS = [147, 151, 139, 143];
const TOP = 16;

/** The browser's localStorage, as far as autosave.js uses it. */
class MemoryStorage {
  constructor() { this.items = new Map(); }
  getItem(key) { return this.items.has(key) ? this.items.get(key) : null; }
  setItem(key, value) { this.items.set(key, String(value)); }
  removeItem(key) { this.items.delete(key); }
}

/** The core as the worker holds it, answering like client.js (a promise per request). */
function core() {
  const session = new Session(bytes, 'mushroom.obj');
  const mesh = { positions: session.positions(), triangles: session.triangles(), summary: session.summary() };
  const client = {
    requests: 0,
    async setLayout(text) {
      this.requests++;
      await new Promise((ok) => setTimeout(ok, 1));
      return session.setLayout(text);
    },
  };
  return { mesh, client };
}

/** A session on the mushroom; `updates` lists what it reported. */
function open({ client, mesh } = core(), options = {}) {
  const updates = [];
  const s = new LayoutSession({ client, onUpdate: (what) => updates.push(what), ...options });
  s.setMesh(mesh, 'mushroom.obj');
  return { s, updates, client, mesh };
}

const fourCorners = () => CORNERS.reduce((doc, v) => L.addNode(doc, v)[0], L.emptyDoc());
/** Two faces: the corners, the top, and edges from two opposite corners to the top. */
function twoFaces(doc = fourCorners()) {
  let top;
  [doc, top] = L.addNode(doc, TOP);
  doc = L.addEdge(doc, 0, top)[0];
  return L.addEdge(doc, top, 2)[0];
}

test('edits are checked by the core; undo and redo walk them', async () => {
  globalThis.localStorage = new MemoryStorage();
  const { s, updates } = open();
  assert.equal(s.layoutName, 'mushroom.layout.json');
  assert.equal(s.offer, null);

  let doc = fourCorners();
  await s.apply(doc, { label: 'add node' });
  assert.equal(s.checking, false);
  assert.equal(s.error, null);
  assert.equal(s.view.summary.faces, 1);
  assert.deepEqual(s.nodeVertex, CORNERS);

  // A node inside the face, joined to nothing: the core names it.
  [doc] = L.addNode(doc, TOP);
  const pending = s.apply(doc, { label: 'add node' });
  assert.equal(s.checking, true);
  assert.equal(s.view, null, 'the old verdict is dropped at once');
  await pending;
  assert.equal(s.view, null);
  assert.match(s.error, /nodes\[4\]/);
  assert.equal(s.fault.kind, 'node_on_no_edge');
  assert.deepEqual([...s.problem.nodes], [4]);
  assert.equal(s.problem.edges.size + s.problem.vertices.size + s.problem.points.length, 0);

  assert.equal(s.history.undoLabel, 'add node');
  assert.ok(s.undo());
  await s.settled();
  assert.equal(s.doc.nodes.length, 4);
  assert.equal(s.view.summary.faces, 1);
  assert.equal(s.problem.nodes.size, 0);
  assert.ok(s.redo());
  await s.settled();
  assert.equal(s.doc, doc);
  assert.deepEqual([...s.problem.nodes], [4]);
  assert.equal(s.redo(), false);
  assert.deepEqual(updates.filter((u) => u !== 'edit'), ['mesh', 'checked', 'checked', 'checked', 'checked']);
});

test('edits made while the core is busy: only the latest is checked next', async () => {
  globalThis.localStorage = new MemoryStorage();
  const { s, client } = open();
  let doc = L.emptyDoc();
  const done = [];
  for (const v of CORNERS) {
    [doc] = L.addNode(doc, v);
    done.push(s.apply(doc, { label: 'add node' }));
  }
  await Promise.all(done);
  // The first edit went at once; the three made meanwhile wait, and only the last goes.
  assert.equal(client.requests, 2);
  assert.equal(s.view.summary.faces, 1);
  assert.equal(s.history.states.length, 5, 'every edit is a step of the history');
});

test('the autosaved layout is offered on the same mesh, restored with its undo history', async () => {
  globalThis.localStorage = new MemoryStorage();
  const c = core();
  const first = open(c).s;
  const corners = fourCorners();
  const doc = twoFaces(corners);
  await first.apply(corners, { label: 'add node' });
  await first.apply(doc, { label: 'add edge' });
  // A reload: a new session on the same mesh.
  const { s, updates } = open(c);
  assert.deepEqual(s.offer.doc, doc);
  assert.ok(Number.isFinite(s.offer.time));
  assert.deepEqual(s.doc, L.emptyDoc());
  await s.answerOffer(true);
  assert.equal(s.offer, null);
  assert.ok(updates.includes('offer'));
  assert.deepEqual(s.doc, doc);
  assert.equal(s.view.summary.faces, 2);
  // The first undo takes back the last edit before the reload, not the whole layout.
  assert.equal(s.history.undoLabel, 'add edge');
  s.undo();
  await s.settled();
  assert.deepEqual(s.doc, corners);
  assert.equal(s.view.summary.faces, 1);
  s.redo();
  await s.settled();
  assert.deepEqual(s.doc, doc);

  // Something drawn before restoring: the restore is one step, undo brings the drawing back.
  const drew = open(c).s;
  const mine = L.addNode(L.emptyDoc(), TOP)[0];
  await drew.apply(mine, { label: 'add node' });
  await drew.answerOffer(true);
  assert.deepEqual(drew.doc, doc);
  assert.equal(drew.history.undoLabel, 'restore');
  drew.undo();
  await drew.settled();
  assert.deepEqual(drew.doc, mine);
  await drew.apply(doc); // the saved layout as before, for what follows

  // Discarded with nothing drawn: the saved layout is forgotten.
  const again = open(c).s;
  assert.ok(again.offer);
  again.answerOffer(false);
  assert.equal(open(c).s.offer, null);
  // Another mesh (another name) has its own.
  const other = new LayoutSession({ client: c.client });
  other.setMesh(c.mesh, 'other.obj');
  assert.equal(other.offer, null);
});

test("the core's culprits are what the session marks, whatever the message says", async () => {
  globalThis.localStorage = new MemoryStorage();
  const c = core();
  const working = c.client.setLayout;
  // The core's answer reworded: the marks come from `culprits`, not from the words.
  c.client.setLayout = async (text) => {
    try {
      return await working.call(c.client, text);
    } catch (err) {
      throw Object.assign(new Error('something else entirely'), { kind: err.kind, culprits: err.culprits });
    }
  };
  const { s } = open(c);
  // Both diagonals cross in the middle.
  let doc = L.addEdge(fourCorners(), 0, 2)[0];
  doc = L.addEdge(doc, 1, 3)[0];
  await s.apply(doc);
  assert.equal(s.error, 'something else entirely');
  assert.equal(s.fault.kind, 'curves_meet');
  assert.deepEqual([...s.problem.edges].sort(), [0, 1]);
  assert.equal(s.problem.points.length, 1);
  // A file error inside an edge: that edge.
  await s.apply(L.addEdge(fourCorners(), 0, 0)[0]);
  assert.equal(s.fault.kind, 'self_loop');
  assert.deepEqual([...s.problem.edges], [0]);
  await s.open(L.toText(fourCorners()), 'four.layout.json');
  assert.equal(s.fault, null);
  assert.equal(s.problem.edges.size, 0);
  // Opening a file the core refuses rejects with the core's kind and culprits.
  await assert.rejects(s.open(L.toText(L.addNode(fourCorners(), TOP)[0]), 'five.layout.json'),
    (err) => err.kind === 'node_on_no_edge' && err.culprits.nodes[0] === 4);
});

test('a chart type on a face an edit removed goes with that edit', async () => {
  globalThis.localStorage = new MemoryStorage();
  const { s } = open();
  await s.apply(fourCorners());
  const corners = s.view.summary.face_list[0].corners;
  await s.apply(L.setChart(s.doc, corners, 'rect'), { label: 'chart rect' });
  assert.deepEqual(s.view.summary.charts, [0, 1, 0]);
  // Splitting the face in two: the patches entry names no face any more.
  await s.apply(twoFaces(s.doc), { label: 'add edge' });
  assert.equal(s.error, null);
  assert.equal(s.doc.patches, undefined);
  assert.equal(s.view.summary.faces, 2);
  assert.equal(s.history.undoLabel, 'add edge');
  s.undo();
  await s.settled();
  assert.equal(s.doc.patches.length, 1, 'undo brings the chart type back with the face');
});

test('a core that lost the mesh: the session asks for it again and keeps the document', async () => {
  globalThis.localStorage = new MemoryStorage();
  const c = core();
  let lost = 0;
  const { s } = open(c, { onCoreLost: () => lost++ });
  await s.apply(fourCorners());
  const doc = s.doc;
  // The worker restarted without a mesh: it refuses layouts.
  const working = c.client.setLayout;
  c.client.setLayout = async () => {
    throw Object.assign(new Error('load a mesh before a layout'), { kind: 'no_mesh' });
  };
  await s.apply(twoFaces(doc), { label: 'add edge' });
  assert.equal(lost, 1);
  assert.match(s.error, /restarts/);
  // The page loads the mesh again: the session places its document once more.
  c.client.setLayout = working;
  const edited = s.doc;
  s.setMesh(c.mesh, 'mushroom.obj');
  await s.settled();
  assert.equal(s.doc, edited);
  assert.equal(s.error, null);
  assert.equal(s.view.summary.faces, 2);
  assert.equal(s.history.undoLabel, 'add edge');
});

test("on a refined mesh the documents stay in the file's numbering: a node on an added vertex is its point", async () => {
  globalThis.localStorage = new MemoryStorage();
  // eight.obj has 634 triangles: the core refines it (mesh/refine.rs).
  const session = new Session(new Uint8Array(readFileSync(new URL('../../../shared/meshes/eight.obj', import.meta.url))), 'eight.obj');
  const mesh = { positions: session.positions(), triangles: session.triangles(), summary: session.summary() };
  const client = { async setLayout(text) { return session.setLayout(text); } };
  const file = L.numberedCounts(mesh.summary);
  assert.deepEqual(file, { vertices: 315, triangles: 634 });
  assert.ok(mesh.positions.length / 3 > file.vertices);
  const s = new LayoutSession({ client, onUpdate: () => {} });
  s.setMesh(mesh, 'eight.obj');
  // Vertex 0 is the file's; the last one the refinement's.
  const added = mesh.positions.length / 3 - 1;
  let doc = L.addNode(L.emptyDoc(), 0)[0];
  doc = L.addNode(doc, added)[0];
  await s.apply(doc, { label: 'add nodes' });
  assert.deepEqual(s.doc.nodes[0], { vertex: 0 });
  assert.deepEqual(s.doc.nodes[1].point, Array.from(mesh.positions.subarray(3 * added, 3 * added + 3)));
  assert.deepEqual(s.nodeVertex, [0, added]);
  // The file says so too, with the file's counts; the core places it on the same vertices.
  const text = s.text();
  assert.deepEqual(JSON.parse(text).mesh, file);
  // (Two nodes and no edge make no layout; the core's objection is that, not the vertices.)
  assert.throws(() => session.setLayout(text), /no edge or boundary reaches this node/);
  // The autosave is keyed by the file's counts and offers the same document on a reload.
  const again = new LayoutSession({ client, onUpdate: () => {} });
  again.setMesh(mesh, 'eight.obj');
  assert.deepEqual(again.offer.doc, s.doc);
  // The core refuses the added vertex by index, as a file naming it would be.
  assert.throws(() => session.setLayout(JSON.stringify(doc)), /vertex \d+ does not exist \(the mesh has 315 vertices\)/);
  session.free();
});
