// Issue 20 through the wasm API the page uses: the quad count asked for, the verdict and the
// faces' guidance in the report, guidance before and after solving, the layout's `mesh`
// identity, and a text file named .obj that is not OBJ.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { test } from 'node:test';

const require = createRequire(import.meta.url);
const { Session } = require('../../target/wasm-node/quadlay.js');
const meshes = new URL('../../../shared/meshes/', import.meta.url);
const read = (name) => new Uint8Array(readFileSync(new URL(name, meshes)));
const layout = (name) => readFileSync(new URL(`../../www/layouts/${name}.layout.json`, import.meta.url), 'utf8');

function solved(mesh, layoutName) {
  const s = new Session(read(mesh), mesh);
  const view = s.setLayout(layout(layoutName));
  s.startParam();
  for (let k = 0; k < 3; k++) s.stepParam();
  s.finishParam();
  return [s, view];
}

test('remesh { quads } gives about that many quads; with edge_length too it is an error', () => {
  const [s] = solved('mushroom.obj', 'mushroom-grid');
  try {
    for (const asked of [500, 2500]) {
      const got = s.remesh({ quads: asked }).quads.faces;
      assert.ok(Math.abs(got / asked - 1) < 0.1, `asked ${asked}, got ${got}`);
    }
    assert.throws(() => s.remesh({ quads: 100, edge_length: 0.05 }), /edge_length or quads, not both/);
    assert.throws(() => s.remesh({ quads: 0 }), /quads must be at least 1/);
  } finally {
    s.free();
  }
});

test('a clean result has no warnings; its faces carry curvature, distortion and length error', () => {
  const [s, view] = solved('mushroom.obj', 'mushroom-grid');
  try {
    // Before solving: area and curvature per face from setLayout.
    assert.equal(view.faces.length, 4);
    for (const f of view.faces) {
      assert.equal(typeof f.curvature_deg, 'number');
      assert.ok(f.area > 0 && f.distortion === undefined);
    }
    const report = s.remesh();
    assert.deepEqual(report.warnings, []);
    assert.ok(report.quads.hausdorff > 0 && report.quads.hausdorff < 0.05, `${report.quads.hausdorff}`);
    assert.equal(report.quads.hausdorff_at.length, 3);
    assert.ok(report.parameterization.length_error > 0);
    assert.equal(report.faces.length, 4);
    for (const f of report.faces) assert.ok(f.length_error >= 0 && f.distortion >= 0, JSON.stringify(f));
    const guidance = s.faceGuidance();
    assert.deepEqual(guidance.map((f) => f.curvature_deg), report.faces.map((f) => f.curvature_deg));
  } finally {
    s.free();
  }
});

test('the bunny in a cube misses the surface, says where, and suggests nodes', () => {
  const [s, view] = solved('bunny_28k.obj', 'bunny-cube');
  try {
    const report = s.remesh();
    const missed = report.warnings.find((w) => w.kind === 'surface_missed');
    assert.ok(missed, JSON.stringify(report.warnings));
    assert.equal(missed.at.length, 3);
    assert.match(missed.message, /miss the surface by up to \d+\.\d %/);
    const suggested = view.faces.filter((f) => f.suggestion);
    assert.ok(suggested.length >= 3, JSON.stringify(view.faces));
    for (const f of suggested) {
      assert.ok(f.needs_node && Math.abs(f.curvature_deg) > 45);
      assert.equal(f.suggestion.reason, 'curvature');
      assert.ok(Number.isInteger(f.suggestion.vertex) && f.suggestion.vertex < 28088);
    }
  } finally {
    s.free();
  }
});

test('a layout made for another mesh is refused, naming mesh and both counts', () => {
  const s = new Session(read('nefertiti.obj'), 'nefertiti.obj');
  try {
    const text = JSON.stringify({
      format: 'quad-layout', version: 1,
      nodes: [0, 1, 2, 3].map((vertex) => ({ vertex })), edges: [],
      mesh: { vertices: 2337, triangles: 4608 },
    });
    assert.throws(() => s.setLayout(text), /^Error: mesh: .*2337 vertices and 4608 triangles.*299 vertices and 562 triangles/);
  } finally {
    s.free();
  }
});

test('a text file named .obj without OBJ statements says it is not an OBJ file', () => {
  const text = new TextEncoder().encode('name,x,y\nA,1,2\n');
  assert.throws(() => new Session(text, 'table.obj'), /table\.obj: OBJ: not an OBJ file/);
});
