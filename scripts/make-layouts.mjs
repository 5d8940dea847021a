// Makes the sample layouts in www/layouts/ from the recipes below, places each on its mesh
// with the core (the wasm build in Node) and prints what came out. Run it after changing a
// recipe: `node scripts/make-layouts.mjs [name ...]`; look at the result on the page
// (`npm start`, pick the sample) or with `node scripts/picture.mjs`.
//
// Nodes are written as points (the exact position of the chosen vertex), so a layout can be
// reused on another tessellation of the same shape.
import { mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = join(dirname(fileURLToPath(import.meta.url)), '..');
const { Session } = createRequire(import.meta.url)(join(root, 'target/wasm-node/quadlay.js'));

/** A mesh with the geometric queries the recipes use. */
class Shape {
  constructor(file) {
    this.file = file;
    this.session = new Session(new Uint8Array(readFileSync(join(root, '..', 'shared', 'meshes', file))), file);
    this.P = this.session.positions();
    this.T = this.session.triangles();
    this.n = this.P.length / 3;
    const [lo, hi] = this.session.summary().bounding_box;
    this.lo = lo;
    this.hi = hi;
    this.center = lo.map((l, k) => (l + hi[k]) / 2);
    this.half = lo.map((l, k) => (hi[k] - l) / 2);
  }
  p(i) {
    return [this.P[3 * i], this.P[3 * i + 1], this.P[3 * i + 2]];
  }
  /** The vertex farthest in direction `d` (in box-normalized coordinates), among those for
   * which `keep(box-normalized position)` holds. */
  extreme(d, keep = () => true) {
    let best = -Infinity, arg = 0;
    for (let i = 0; i < this.n; i++) {
      const q = this.p(i);
      if (!keep(q.map((x, k) => (x - this.center[k]) / this.half[k]))) continue;
      const s = q.reduce((acc, x, k) => acc + d[k] * (x - this.center[k]) / this.half[k], 0);
      if (s > best) [best, arg] = [s, i];
    }
    return arg;
  }
  /** The vertex nearest the point `f` given in box fractions (-1..1 per axis), among `only`. */
  nearest(f, only = null) {
    const target = f.map((x, k) => this.center[k] + x * this.half[k]);
    let best = Infinity, arg = 0;
    for (const i of only ?? this.vertices()) {
      const q = this.p(i);
      const d = q.reduce((acc, x, k) => acc + (x - target[k]) ** 2, 0);
      if (d < best) [best, arg] = [d, i];
    }
    return arg;
  }
  *vertices() {
    for (let i = 0; i < this.n; i++) yield i;
  }
  /** Vertices on the mesh boundary. */
  boundary() {
    const count = new Map();
    for (let t = 0; t < this.T.length; t += 3) {
      for (let k = 0; k < 3; k++) {
        const a = this.T[t + k], b = this.T[t + (k + 1) % 3];
        const key = a < b ? `${a},${b}` : `${b},${a}`;
        count.set(key, (count.get(key) ?? 0) + 1);
      }
    }
    const out = new Set();
    for (const [key, c] of count) if (c === 1) key.split(',').forEach((v) => out.add(Number(v)));
    return [...out];
  }
  point(i) {
    return { point: this.p(i) };
  }
}

const CUBE_CORNERS = [[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1], [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]];
const CUBE_EDGES = [[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4], [0, 4], [1, 5], [2, 6], [3, 7]];

/** A cube-like layout: the 8 vertices farthest toward the box's corners (among those `keep`
 * accepts), the cube's edges. */
function cube(shape, { align = true, keep } = {}) {
  const nodes = CUBE_CORNERS.map((d) => shape.point(shape.extreme(d, keep)));
  return { nodes, edges: CUBE_EDGES.map((e) => ({ nodes: e, ...(align ? { align: true } : {}) })) };
}

/** Mushroom: the boundary loop lies in the plane z = min; nodes on it by direction. */
function mushroomBoundary(shape, dirs) {
  const b = shape.boundary();
  return dirs.map(([x, y]) => shape.nearest([x, y, -1], b));
}

/**
 * eight.obj, genus 2: a figure eight lying in the x–z plane with its two holes along y. The
 * layout runs around the outer rim and both hole rims on the mid-plane y = 0, and splits the
 * front (y > 0) and back sheets into six faces each; the two faces between the holes carry
 * the ends of the middle edge as T-vertices. Rim edges get waypoints on the mid-plane.
 */
function eight(s) {
  const rim = ([, y]) => Math.abs(y) < 0.3;
  const at = (f) => s.nearest(f, [...s.vertices()].filter((i) => rim(s.p(i).map((x, k) => (x - s.center[k]) / s.half[k]))));
  const h = 0.512; // hole centres at z = ±0.2555 (box fraction)
  const targets = [
    [0, 0, 1], [1, 0, h], [1, 0, -h], [0, 0, -1], [-1, 0, -h], [-1, 0, h], // outer rim 0–5
    [0, 0, 0.733], [0.46, 0, h], [0, 0, 0.29], [-0.46, 0, h], // upper hole 6–9
    [0, 0, -0.29], [0.46, 0, -h], [0, 0, -0.733], [-0.46, 0, -h], // lower hole 10–13
  ];
  const ids = targets.map(at);
  const nodes = ids.map((v) => s.point(v));
  const box = (i) => s.p(ids[i]).map((x, k) => (x - s.center[k]) / s.half[k]);
  /** A waypoint on the rim between nodes a and b: out from the chord's middle (outer rim)
   * or the chord's middle itself, which lies in the hole (hole rims). */
  const rimVia = (a, b, outer) => {
    const m = box(a).map((x, k) => (x + box(b)[k]) / 2);
    const scale = outer ? 1 / Math.hypot(m[0], m[2]) : 1;
    return s.point(at([m[0] * scale, 0, m[2] * scale]));
  };
  const loops = [[[0, 1, 2, 3, 4, 5], true], [[6, 7, 8, 9], false], [[10, 11, 12, 13], false]];
  const edges = [];
  for (const [loop, outer] of loops) {
    loop.forEach((a, k) => {
      const b = loop[(k + 1) % loop.length];
      edges.push({ nodes: [a, b], via: [rimVia(a, b, outer)] });
    });
  }
  const sheet = [[0, 6, [0, 0.87]], [8, 10, [0, 0]], [12, 3, [0, -0.87]], [5, 9, [-0.73, h]], [1, 7, [0.73, h]],
    [4, 13, [-0.73, -h]], [2, 11, [0.73, -h]]];
  for (const y of [1, -1]) {
    for (const [a, b, [x, z]] of sheet) edges.push({ nodes: [a, b], via: [s.point(s.nearest([x, y, z]))] });
  }
  // The faces between the holes have six nodes: name their corners (both orientations, one
  // for the front face and one for the back).
  const patches = [[5, 9, 13, 4], [4, 13, 9, 5], [1, 7, 11, 2], [2, 11, 7, 1]].map((corners) => ({ corners }));
  return { nodes, edges, patches };
}

const RECIPES = {
  'eight-rims': {
    mesh: 'eight.obj',
    make: eight,
  },
  'fandisk-cube': {
    mesh: 'fandisk.obj',
    make: (s) => cube(s),
  },
  'bunny-cube': {
    mesh: 'bunny_28k.obj',
    // The body's corners: the ears (y up) would take the four upper nodes.
    make: (s) => cube(s, { align: false, keep: ([, y]) => y < 0.15 }),
  },
  'mushroom-4': {
    mesh: 'mushroom.obj',
    // Four nodes on the boundary: the one face is the whole disk, its sides the boundary.
    make: (s) => ({
      nodes: mushroomBoundary(s, [[1, 1], [-1, 1], [-1, -1], [1, -1]]).map((v) => s.point(v)),
      edges: [],
    }),
  },
  'mushroom-grid': {
    mesh: 'mushroom.obj',
    // 2×2 faces: corners and side midpoints on the boundary, one node on top, four edges.
    make: (s) => {
      const ring = mushroomBoundary(s, [[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1]]);
      const top = s.extreme([0, 0, 1]);
      const nodes = [...ring, top].map((v) => s.point(v));
      return { nodes, edges: [0, 2, 4, 6].map((k) => ({ nodes: [8, k], align: true })) };
    },
  },
  'mushroom-t': {
    mesh: 'mushroom.obj',
    // The 2×2 grid with one quarter split again into 2×2: its split points on the inner
    // edges are T-vertices of the two neighbouring quarters.
    make: (s) => {
      const b = s.boundary();
      const ring = mushroomBoundary(s, [[1, 0], [1, 1], [0, 1], [-1, 1], [-1, 0], [-1, -1], [0, -1], [1, -1]]);
      const top = s.extreme([0, 0, 1]);
      const mid = (i, j) => s.nearest(s.p(i).map((x, k) => (x + s.p(j)[k]) / 2 - s.center[k]).map((x, k) => x / s.half[k]));
      const A = mid(top, ring[0]);
      const B = mid(top, ring[2]);
      const D = mushroomBoundary(s, [[1, 0.45]])[0];
      const E = mushroomBoundary(s, [[0.45, 1]])[0];
      const F = mid(top, ring[1]);
      void b;
      // nodes: 0..7 ring, 8 top, 9 A, 10 B, 11 D, 12 E, 13 F
      const nodes = [...ring, top, A, B, D, E, F].map((v) => s.point(v));
      const edges = [[8, 9], [9, 0], [8, 10], [10, 2], [8, 4], [8, 6], [9, 13], [11, 13], [12, 13], [10, 13]];
      return { nodes, edges: edges.map((e) => ({ nodes: e })) };
    },
  },
};

function write(name, layout) {
  const doc = { format: 'quad-layout', version: 1, ...layout };
  const text = JSON.stringify(doc, null, 1) + '\n';
  mkdirSync(join(root, 'www/layouts'), { recursive: true });
  writeFileSync(join(root, 'www/layouts', `${name}.layout.json`), text);
  return text;
}

const wanted = process.argv.slice(2);
let failed = 0;
for (const [name, recipe] of Object.entries(RECIPES)) {
  if (wanted.length && !wanted.includes(name)) continue;
  const shape = new Shape(recipe.mesh);
  const text = write(name, recipe.make(shape));
  try {
    const view = shape.session.setLayout(text);
    const s = view.summary;
    console.log(`${name.padEnd(16)} ${recipe.mesh.padEnd(16)} ${s.nodes} nodes, ${s.edges} edges, ` +
      `${s.boundary_pieces} boundary edges, ${s.faces} faces, ${s.t_vertices} T-vertices`);
  } catch (err) {
    failed++;
    console.log(`${name.padEnd(16)} ${recipe.mesh.padEnd(16)} ERROR ${err.message}`);
  }
  shape.session.free();
}
process.exit(failed ? 1 : 0);
