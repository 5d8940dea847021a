// The layout document the editor changes (format v1, shared/spec/layout-format.md): pure
// functions from a document to a new one, never changing their input, and what the core's
// errors name in it. Keys the editor does not know are kept.

/** An empty layout. */
export function emptyDoc() {
  return { format: 'quad-layout', version: 1, nodes: [], edges: [] };
}

const clone = (doc) => structuredClone(doc);

/**
 * The document from a layout file's text, or an error naming what is wrong with it as a
 * document the editor can hold (the core judges everything else).
 */
export function parseDoc(text) {
  let doc;
  try {
    doc = JSON.parse(text);
  } catch (err) {
    throw new Error(`not valid JSON: ${err.message}`);
  }
  if (!doc || typeof doc !== 'object' || Array.isArray(doc)) throw new Error('a layout file is a JSON object');
  if (!Array.isArray(doc.nodes ?? [])) throw new Error("'nodes' must be a list");
  if (!Array.isArray(doc.edges ?? [])) throw new Error("'edges' must be a list");
  if (doc.patches !== undefined && !Array.isArray(doc.patches)) throw new Error("'patches' must be a list");
  return doc;
}

/**
 * The counts of the vertex numbering layout files use on a mesh the core loaded, from its
 * `summary`: the mesh's own, or where the core refined a coarse mesh (the summary's repairs
 * say), the mesh's before that: the file's, which stay the same whatever the refinement.
 */
export function numberedCounts(summary) {
  const { repairs, vertices, triangles } = summary;
  return repairs?.refinements > 0
    ? { vertices: repairs.vertices_before_refinement, triangles: repairs.triangles_before_refinement }
    : { vertices, triangles };
}

/**
 * `doc` as a file gives it on `mesh` (`{ positions, summary }`): a node or waypoint on a vertex
 * past the file's numbering (one the core's refinement added) by its point, which the core
 * snaps back to the same vertex. The core refuses such an index, as the file format does;
 * and the documents the editor keeps (undo, autosave) stay valid on the mesh refined anew
 * after a repair, which numbers the refinement's vertices differently.
 */
export function inNumbering(doc, mesh) {
  if (!(mesh?.summary?.repairs?.refinements > 0)) return doc;
  const numbered = numberedCounts(mesh.summary).vertices;
  const n = mesh.positions.length / 3;
  const named = (loc) => (Number.isInteger(loc?.vertex) && loc.vertex >= numbered && loc.vertex < n
    ? { point: Array.from(mesh.positions.subarray(3 * loc.vertex, 3 * loc.vertex + 3)) }
    : loc);
  const next = { ...doc };
  if (doc.nodes) next.nodes = doc.nodes.map(named);
  if (doc.edges) next.edges = doc.edges.map((e) => (e.via ? { ...e, via: e.via.map(named) } : e));
  return next;
}

/**
 * The layout file's text: format v1, one node, edge or patch per line. With `mesh` (`{
 * positions, summary }` of the mesh it is drawn on), the document as a file gives it there
 * ([`inNumbering`]) and the counts of its numbering as the file's `mesh` entry, unless the
 * document has one already (a layout loaded for another mesh keeps saying so).
 */
export function toText(doc, mesh = null) {
  const counts = mesh ? { mesh: numberedCounts(mesh.summary) } : {};
  const { format = 'quad-layout', version = 1, nodes = [], edges = [], ...rest } = { ...counts, ...inNumbering(doc, mesh) };
  const list = (items) => (items.length ? `[\n${items.map((x) => `  ${JSON.stringify(x)}`).join(',\n')}\n ]` : '[]');
  const lines = [
    ` "format": ${JSON.stringify(format)}`,
    ` "version": ${JSON.stringify(version)}`,
    ` "nodes": ${list(nodes)}`,
    ` "edges": ${list(edges)}`,
  ];
  for (const [key, value] of Object.entries(rest)) {
    lines.push(` ${JSON.stringify(key)}: ${Array.isArray(value) ? list(value) : JSON.stringify(value)}`);
  }
  return `{\n${lines.join(',\n')}\n}\n`;
}

/** Adds a node on mesh vertex `vertex`; returns [doc, its index]. */
export function addNode(doc, vertex) {
  const next = clone(doc);
  next.nodes = [...(next.nodes ?? []), { vertex }];
  return [next, next.nodes.length - 1];
}

/** Moves node `n` to mesh vertex `vertex` (its edges follow; other keys of the entry stay). */
export function moveNode(doc, n, vertex) {
  const next = clone(doc);
  const { point: _, ...rest } = next.nodes[n];
  next.nodes[n] = { ...rest, vertex };
  return next;
}

/** Adds the edge a–b (untagged, no waypoints); returns [doc, its index]. */
export function addEdge(doc, a, b) {
  const next = clone(doc);
  next.edges = [...(next.edges ?? []), { nodes: [a, b] }];
  return [next, next.edges.length - 1];
}

/** Index of an edge a–b (either way round) without waypoints, or -1. */
export function findEdge(doc, a, b) {
  return (doc.edges ?? []).findIndex((e) =>
    !(e.via?.length) && ((e.nodes?.[0] === a && e.nodes?.[1] === b) || (e.nodes?.[0] === b && e.nodes?.[1] === a)));
}

/** Removes edge `i`. */
export function deleteEdge(doc, i) {
  const next = clone(doc);
  next.edges = next.edges.filter((_, k) => k !== i);
  return next;
}

/** Removes node `n`, its edges and the patches it is a corner of; later nodes move down. */
export function deleteNode(doc, n) {
  const next = clone(doc);
  const renumber = (m) => (m > n ? m - 1 : m);
  next.nodes = next.nodes.filter((_, k) => k !== n);
  next.edges = (next.edges ?? [])
    .filter((e) => !e.nodes?.includes(n))
    .map((e) => ({ ...e, nodes: e.nodes.map(renumber) }));
  if (next.patches) {
    next.patches = next.patches
      .filter((p) => !p.corners?.includes(n))
      .map((p) => ({ ...p, corners: p.corners.map(renumber) }));
    if (!next.patches.length) delete next.patches;
  }
  return next;
}

/** Tags edge `i` for alignment, or untags it. */
export function toggleAlign(doc, i) {
  const next = clone(doc);
  const e = next.edges[i];
  if (e.align) delete e.align;
  else e.align = true;
  return next;
}

/**
 * Splits edge `i` at a new node on `vertex` (a T-vertex where the faces beside it have four
 * corners elsewhere): a–b becomes a–new (index i) and new–b (appended), both keeping the tag;
 * the waypoints before `viaSplit` stay with the first half, the others go to the second.
 * Returns [doc, the new node's index].
 */
export function splitEdge(doc, i, vertex, viaSplit = 0) {
  let [next, n] = addNode(doc, vertex);
  const e = next.edges[i];
  const [a, b] = e.nodes;
  const via = e.via ?? [];
  const first = { ...e, nodes: [a, n] };
  const second = { ...e, nodes: [n, b] };
  delete first.via;
  delete second.via;
  if (via.slice(0, viaSplit).length) first.via = via.slice(0, viaSplit);
  if (via.slice(viaSplit).length) second.via = via.slice(viaSplit);
  next.edges[i] = first;
  next.edges.push(second);
  return [next, n];
}

/** Inserts waypoint `{vertex}` into edge `i` at position `k` of its `via`. */
export function insertVia(doc, i, k, vertex) {
  const next = clone(doc);
  const e = next.edges[i];
  e.via = [...(e.via ?? [])];
  e.via.splice(k, 0, { vertex });
  return next;
}

/** Moves waypoint `k` of edge `i` to mesh vertex `vertex`. */
export function moveVia(doc, i, k, vertex) {
  const next = clone(doc);
  next.edges[i].via[k] = { vertex };
  return next;
}

/** Removes waypoint `k` of edge `i`. */
export function deleteVia(doc, i, k) {
  const next = clone(doc);
  const e = next.edges[i];
  e.via = e.via.filter((_, j) => j !== k);
  if (!e.via.length) delete e.via;
  return next;
}

export const CHARTS = ['quad', 'rect', 'unit'];

/** True when `a` and `b` list the same corners in the same cyclic order. */
function sameCycle(a, b) {
  if (a.length !== b.length) return false;
  const s = b.indexOf(a[0]);
  return s >= 0 && a.every((x, k) => b[(s + k) % b.length] === x);
}

/** The chart type of the face with corners `corners` (from the layout's summary). */
export function chartOf(doc, corners) {
  const entry = (doc.patches ?? []).find((p) => Array.isArray(p.corners) && sameCycle(p.corners, corners));
  return entry?.chart ?? doc.defaults?.chart ?? 'quad';
}

/**
 * Sets the chart type of the face with corners `corners` (counter-clockwise, as the core
 * reports them). A face whose type is the default needs no `patches` entry: it is removed.
 */
export function setChart(doc, corners, chart) {
  const next = clone(doc);
  const patches = (next.patches ?? []).filter((p) => !(Array.isArray(p.corners) && sameCycle(p.corners, corners)));
  const old = (doc.patches ?? []).find((p) => Array.isArray(p.corners) && sameCycle(p.corners, corners));
  const fallback = next.defaults?.chart ?? 'quad';
  if (chart !== fallback || (old && Object.keys(old).some((k) => k !== 'corners' && k !== 'chart'))) {
    patches.push({ ...old, corners: [...corners], chart });
  }
  if (patches.length) next.patches = patches;
  else delete next.patches;
  return next;
}

/** Removes `patches[k]`. */
export function deletePatch(doc, k) {
  const next = clone(doc);
  next.patches = next.patches.filter((_, j) => j !== k);
  if (!next.patches.length) delete next.patches;
  return next;
}

/** The edge index of a curve's source (`{ edge: 3 }` → 3); a boundary piece → -1. */
export function edgeIndex(source) {
  return Number.isInteger(source?.edge) ? source.edge : -1;
}

/**
 * What the core's error names, for drawing it on the mesh: { nodes, edges, patches,
 * vertices } (Sets of indices) and points ([x, y, z] each), read from the error's
 * `culprits`, which the core sends as data (protocol.js); nothing for any other error.
 */
export function problemOf(error) {
  const out = { nodes: new Set(), edges: new Set(), patches: new Set(), vertices: new Set(), points: [] };
  const culprits = error?.culprits;
  if (!culprits) return out;
  for (const key of ['nodes', 'edges', 'patches', 'vertices']) {
    for (const i of culprits[key] ?? []) out[key].add(i);
  }
  if (culprits.point) out.points.push(culprits.point);
  return out;
}
