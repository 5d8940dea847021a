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
      // A coarse mesh is refined (mesh/refine.rs): the file's counts are the repairs'.
      const refined = sum.repairs.refinements > 0;
      assert.equal(refined, f < 4000);
      const file = refined ? [sum.repairs.vertices_before_refinement, sum.repairs.triangles_before_refinement] : [sum.vertices, sum.triangles];
      assert.deepEqual(
        [...file, sum.genus, sum.boundary_loops, sum.components.length],
        [v, f, genus, loops, 1],
      );
      assert.equal(sum.triangles, f * 4 ** sum.repairs.refinements);
      const pos = s.positions();
      const tri = s.triangles();
      assert.ok(pos instanceof Float32Array && pos.length === 3 * sum.vertices);
      assert.ok(tri instanceof Uint32Array && tri.length === 3 * sum.triangles);
      assert.ok(tri.every((i) => i < sum.vertices));
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
  assert.equal(ok.summary().repairs.vertices_before_refinement, 299);
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

test('a run with chosen chart types, its refined mesh, uv, distortion, charts and OBJ', () => {
  const s = new Session(read('mushroom.obj'), 'mushroom.obj');
  try {
    const layout = readFileSync(new URL('../../www/layouts/mushroom-grid.layout.json', import.meta.url), 'utf8');
    s.setLayout(layout);
    const runs = {};
    for (const chart of ['unit', 'rect', 'quad']) {
      const first = s.startParam({ chart, align: true });
      assert.equal(first.iteration, 0);
      for (let k = 0; k < 3; k++) s.stepParam();
      const fin = s.finishParam();
      const charts = s.paramCharts();
      assert.equal(charts.length, 4);
      assert.ok(charts.every((c) => c.kind === chart), JSON.stringify(charts.map((c) => c.kind)));
      for (const c of charts) {
        assert.deepEqual(c.corners[0], [0, 0]);
        // Counter-clockwise: positive area.
        const [p0, p1, p2, p3] = c.corners;
        const area = ((p1[0] - p0[0]) * (p2[1] - p0[1]) - (p2[0] - p0[0]) * (p1[1] - p0[1]))
          + ((p2[0] - p0[0]) * (p3[1] - p0[1]) - (p3[0] - p0[0]) * (p2[1] - p0[1]));
        assert.ok(area > 0);
      }
      const pos = s.cutPositions();
      const tri = s.cutTriangles();
      const uv = s.cornerUv();
      const face = s.triangleFace();
      const dist = s.triangleDistortion();
      const n = tri.length / 3;
      assert.ok(pos instanceof Float32Array && pos.length >= 3 * 2337);
      assert.ok(tri instanceof Uint32Array && n >= 4608);
      assert.ok(tri.every((i) => i < pos.length / 3));
      assert.ok(uv instanceof Float32Array && uv.length === 6 * n && uv.every(Number.isFinite));
      assert.ok(face instanceof Uint32Array && face.length === n && face.every((f) => f < 4));
      assert.ok(dist instanceof Float32Array && dist.length === n && dist.every((d) => d >= 0));
      assert.ok(Math.abs(Math.max(...dist) - fin.max) <= 1e-4 * Math.max(1, fin.max), `${Math.max(...dist)} vs ${fin.max}`);
      const history = s.paramHistory();
      assert.deepEqual(history.map((h) => h.iteration), [0, 1, 2, 3]);
      runs[chart] = fin;
      s.keepParam(chart);
      assert.throws(() => s.cornerUv(), /start the parameterization first/);
    }
    // Paper Figs. 2 and 8: free quadrilaterals fit at least as well as rectangles, which fit
    // better than unit squares.
    assert.ok(runs.quad.mean <= runs.rect.mean * 1.001 && runs.rect.mean < runs.unit.mean,
      JSON.stringify(runs));
    assert.equal(s.useParam('rect'), true);
    assert.ok(s.paramCharts().every((c) => c.kind === 'rect'));
    assert.equal(s.useParam('unit', 'rect'), true);
    assert.equal(s.useParam('rect', 'unit'), true);
    assert.equal(s.useParam('nothing'), false);

    // The refined mesh with its uv; the input mesh with its uv (as --param-out).
    const obj = new TextDecoder().decode(s.cutObj());
    const lines = obj.split('\n');
    const nv = lines.filter((l) => l.startsWith('v ')).length;
    const nvt = lines.filter((l) => l.startsWith('vt ')).length;
    const faces = lines.filter((l) => l.startsWith('f '));
    assert.equal(nvt, 3 * faces.length);
    assert.equal(nv, s.cutPositions().length / 3);
    assert.equal(faces.length, s.cutTriangles().length / 3);
    const input = new TextDecoder().decode(s.paramObj()).split('\n');
    assert.equal(input.filter((l) => l.startsWith('v ')).length, 2337);
    assert.equal(input.filter((l) => l.startsWith('f ')).length, 4608);
    assert.match(faces[0], /^f \d+\/1 \d+\/2 \d+\/3$/);
    const sec = s.seconds();
    assert.ok(sec.load >= 0 && sec.layout >= 0);

    assert.throws(() => s.startParam({ chart: 'hex' }), /unknown chart type 'hex'/);
    // A misspelled option is named, not ignored.
    assert.throws(() => s.startParam({ charts: 'rect' }), /solve options: unknown option `charts` \(known: iterations, align, chart, accelerate, anderson_depth, blow_up, guard_flips, step_shares, grow_after, final_anchors\)/);
  } finally {
    s.free();
  }
});

test('a layout whose patches name a chart keeps it when the run asks for another default', () => {
  const s = new Session(read('eight.obj'), 'eight.obj');
  try {
    const layout = JSON.parse(readFileSync(new URL('../../www/layouts/eight-rims.layout.json', import.meta.url), 'utf8'));
    layout.patches[1].chart = 'unit';
    s.setLayout(JSON.stringify(layout));
    s.startParam({ chart: 'rect' });
    for (let k = 0; k < 3; k++) s.stepParam();
    s.finishParam();
    const kinds = s.paramCharts().map((c) => c.kind);
    assert.equal(kinds.filter((k) => k === 'unit').length, 1, kinds.join());
    assert.equal(kinds.filter((k) => k === 'rect').length, kinds.length - 1, kinds.join());
    s.startParam(null);
    for (let k = 0; k < 3; k++) s.stepParam();
    s.finishParam();
    const asFiled = s.paramCharts().map((c) => c.kind);
    assert.equal(asFiled.filter((k) => k === 'unit').length, 1, asFiled.join());
    assert.equal(asFiled.filter((k) => k === 'quad').length, kinds.length - 1, asFiled.join());
  } finally {
    s.free();
  }
});

test('remesh: the quad mesh of the active run, its report (cli.md) and files', () => {
  const s = new Session(read('mushroom.obj'), 'mushroom.obj');
  try {
    s.setLayout(readFileSync(new URL('../../www/layouts/mushroom-grid.layout.json', import.meta.url), 'utf8'));
    assert.throws(() => s.remesh({}), /start the parameterization first/);
    s.startParam({ chart: 'quad' });
    for (let k = 0; k < 3; k++) s.stepParam();
    s.finishParam();
    assert.throws(() => s.quadPositions(), /remesh first/);
    const report = s.remesh({ edge_length: 0.02 });
    for (const [group, fields] of Object.entries({
      input: ['vertices', 'triangles'],
      layout: ['nodes', 'edges', 'faces', 't_vertices'],
      parameterization: ['distortion_mean', 'distortion_max', 'flipped_triangles'],
      quads: ['vertices', 'faces', 'irregular_vertices'],
      seconds: ['load', 'layout', 'parameterize', 'mesh', 'total'],
    })) {
      for (const f of fields) assert.equal(typeof report[group][f], 'number', `${group}.${f}`);
    }
    assert.deepEqual(report.iterations.map((i) => i.iteration), [0, 1, 2, 3]);
    assert.deepEqual([report.input.vertices, report.input.triangles, report.layout.faces], [2337, 4608, 4]);
    assert.ok(report.seconds.parameterize > 0 && report.seconds.total >= report.seconds.parameterize);
    const pos = s.quadPositions();
    const quads = s.quadIndices();
    assert.ok(pos instanceof Float32Array && pos.length === 3 * report.quads.vertices);
    assert.ok(quads instanceof Uint32Array && quads.length === 4 * report.quads.faces);
    assert.ok(quads.every((i) => i < report.quads.vertices));
    assert.deepEqual(s.quadReport(), report);
    // A failed extraction says why and leaves no quad mesh.
    assert.throws(() => s.remesh({ edge_length: -1 }), /edge length/);
    assert.throws(() => s.remesh({ edgeLength: 0.05 }), /remesh options: unknown option `edgeLength` \(known: edge_length, quads\)/);
    assert.throws(() => s.quadPositions(), /remesh first/);
    // A coarser edge length gives fewer quads.
    const coarse = s.remesh({ edge_length: 0.05 });
    assert.ok(coarse.quads.faces < report.quads.faces);

    const text = (b) => new TextDecoder().decode(b);
    const obj = text(s.quadFile('obj')).split('\n');
    assert.equal(obj.filter((l) => l.startsWith('v ')).length, coarse.quads.vertices);
    const f = obj.filter((l) => l.startsWith('f '));
    assert.equal(f.length, coarse.quads.faces);
    assert.ok(f.every((l) => /^f \d+ \d+ \d+ \d+$/.test(l)));
    assert.match(text(s.quadFile('ply').subarray(0, 200)), new RegExp(`element face ${coarse.quads.faces}`));
    assert.equal(text(s.quadFile('glb').subarray(0, 4)), 'glTF');
    assert.throws(() => s.quadFile('stl'), /unknown quad mesh format 'stl'/);
    const cut = text(s.cutObj()).split('\n');
    assert.equal(cut.filter((l) => l.startsWith('vt ')).length, 3 * cut.filter((l) => l.startsWith('f ')).length);
    const param = text(s.paramObj()).split('\n');
    assert.equal(param.filter((l) => l.startsWith('f ')).length, 4608);
    assert.equal(param.filter((l) => l.startsWith('vt ')).length, 3 * 4608);

    // A new run drops the quad mesh; each kept run keeps its own.
    s.keepParam('quad');
    s.startParam({ chart: 'rect' });
    s.finishParam();
    assert.throws(() => s.quadPositions(), /remesh first/);
    s.useParam('quad', 'rect');
    assert.equal(s.quadIndices().length, 4 * coarse.quads.faces);
  } finally {
    s.free();
  }
});
