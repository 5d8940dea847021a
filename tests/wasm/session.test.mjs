// The wasm build, run in Node: the same readers and checks as natively, through the
// JavaScript API the page uses (target/wasm-node, built by scripts/build.mjs).
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { test } from 'node:test';

const require = createRequire(import.meta.url);
const { Session } = require('../../target/wasm-node/quadlay.js');
const meshes = new URL('../../../shared/meshes/', import.meta.url);
const read = (name) => new Uint8Array(readFileSync(new URL(name, meshes)));

// From shared/meshes/SOURCES.md.
const EXPECTED = {
  'nefertiti.obj': [299, 562, 0, 1],
  'eight.obj': [315, 634, 2, 0],
  'bunny_1k8.obj': [1839, 3674, 0, 0],
  'mushroom.obj': [2337, 4608, 0, 1],
  'fandisk.obj': [6475, 12946, 0, 0],
  'bunny_28k.obj': [28088, 56172, 0, 0],
  'elephant_44k.obj': [44460, 88928, 3, 0],
};

for (const [name, [v, f, genus, loops]] of Object.entries(EXPECTED)) {
  test(`${name}: counts and topology as SOURCES.md gives them`, () => {
    const s = new Session(read(name), name);
    try {
      const sum = s.summary();
      assert.deepEqual(
        [sum.vertices, sum.triangles, sum.genus, sum.boundary_loops, sum.components.length],
        [v, f, genus, loops, 1],
      );
      const pos = s.positions();
      const tri = s.triangles();
      assert.ok(pos instanceof Float32Array && pos.length === 3 * v);
      assert.ok(tri instanceof Uint32Array && tri.length === 3 * f);
      assert.ok(tri.every((i) => i < v));
      assert.ok(pos.every(Number.isFinite));
    } finally {
      s.free();
    }
  });
}

test('bad input becomes a readable JS error naming the place, not a crash', () => {
  const enc = new TextEncoder();
  const cases = [
    ['bad.obj', 'v 0 0 0\nv 1 zz 0\n', /bad\.obj: OBJ line 2: 'zz' is not a number/],
    ['tri.obj', 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n', /refers to vertex 8.*line 4/],
    ['empty.ply', 'ply\nformat ascii 1.0\nend_header\n', /no 'vertex' element/],
    ['x.stl', 'hello', /neither an ASCII STL/],
    ['x.glb', 'glTF garbage', /glTF/],
    ['x.dae', '<xml/>', /cannot tell the format/],
  ];
  for (const [name, text, pattern] of cases) {
    assert.throws(() => new Session(enc.encode(text), name), pattern, name);
  }
  // The module survives errors: a good file still loads afterwards.
  const ok = new Session(read('nefertiti.obj'), 'nefertiti.obj');
  assert.equal(ok.summary().vertices, 299);
  ok.free();
});

test('layout and parameterization through the wasm API, one iteration per call', () => {
  const s = new Session(read('mushroom.obj'), 'mushroom.obj');
  try {
    const layout = readFileSync(new URL('../../www/layouts/mushroom-grid.layout.json', import.meta.url), 'utf8');
    const view = s.setLayout(layout);
    assert.equal(view.summary.faces, 4);
    assert.equal(view.curves.length, 4 + 8);
    assert.equal(view.vertex_face.length, 2337);
    const first = s.startParam(true);
    assert.equal(first.iteration, 0);
    const steps = [1, 2, 3].map(() => s.stepParam());
    assert.deepEqual(steps.map((x) => x.iteration), [1, 2, 3]);
    assert.ok(steps[2].distortion.mean < first.distortion.mean, `${steps[2].distortion.mean} vs ${first.distortion.mean}`);
    const fin = s.finishParam();
    assert.equal(fin.flipped, 0);
    assert.ok(Number.isFinite(fin.mean));
    assert.throws(() => s.setLayout('{"format":"quad-layout","version":1,"nodes":[],"edges":[{"nodes":[0,1]}]}'), /edges\[0\]: node 0 does not exist/);
    assert.throws(() => s.stepParam(), /start the parameterization first/);
  } finally {
    s.free();
  }
});
