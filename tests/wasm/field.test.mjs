// The cross field and the layout proposal (issue 22) through the wasm API the page's worker
// uses: the field's known answers (Poincaré–Hopf, a sphere's eight valence-3 points) and a
// proposal that the layout reader places, that solves and remeshes, on shared meshes.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { test } from 'node:test';
import { tetrahedra } from '../fixtures/tetrahedra.mjs';

const require = createRequire(import.meta.url);
const { Session, pickSuggestion } = require('../../target/wasm-node/quadlay.js');
const meshes = new URL('../../../shared/meshes/', import.meta.url);
const read = (name) => new Uint8Array(readFileSync(new URL(name, meshes)));
const obj = (text) => new TextEncoder().encode(text);

/** A cube's surface (n×n squares per side) pushed onto the unit sphere, as OBJ text. */
function sphereObj(n) {
  const index = new Map();
  const v = [];
  const f = [];
  const at = (p) => {
    const key = p.join(',');
    if (!index.has(key)) {
      const l = Math.hypot(...p);
      v.push(p.map((c) => c / l));
      index.set(key, v.length);
    }
    return index.get(key);
  };
  // Each face of [-1,1]³ as (origin, u, v) with u × v pointing outwards.
  const sides = [
    [[1, -1, -1], [0, 2, 0], [0, 0, 2]], [[-1, -1, -1], [0, 0, 2], [0, 2, 0]],
    [[-1, 1, -1], [0, 0, 2], [2, 0, 0]], [[-1, -1, -1], [2, 0, 0], [0, 0, 2]],
    [[-1, -1, 1], [2, 0, 0], [0, 2, 0]], [[-1, -1, -1], [0, 2, 0], [2, 0, 0]],
  ];
  for (const [o, u, w] of sides) {
    const p = (i, j) => at(o.map((c, k) => c + (u[k] * i + w[k] * j) / n));
    for (let i = 0; i < n; i++) {
      for (let j = 0; j < n; j++) {
        f.push([p(i, j), p(i + 1, j), p(i + 1, j + 1)], [p(i, j), p(i + 1, j + 1), p(i, j + 1)]);
      }
    }
  }
  return obj(`${v.map((p) => `v ${p.join(' ')}`).join('\n')}\n${f.map((t) => `f ${t.join(' ')}`).join('\n')}\n`);
}

test('a sphere\'s cross field has eight valence-3 singularities, unit arms tangent to it', () => {
  const s = new Session(sphereObj(10), 'sphere.obj');
  try {
    const field = s.crossField({});
    const n = s.summary().vertices;
    assert.equal(field.directions.length, 3 * n);
    const pos = s.positions();
    for (let v = 0; v < n; v++) {
      const d = field.directions.slice(3 * v, 3 * v + 3);
      assert.ok(Math.abs(Math.hypot(...d) - 1) < 1e-4, `vertex ${v}: |d| = ${Math.hypot(...d)}`);
      // On the unit sphere the normal is the position: the arm is tangent.
      const dot = d[0] * pos[3 * v] + d[1] * pos[3 * v + 1] + d[2] * pos[3 * v + 2];
      assert.ok(Math.abs(dot) < 0.05, `vertex ${v}: arm · normal = ${dot}`);
    }
    assert.deepEqual(field.singularityValences, Array(8).fill(3));
    // Each at a triangle's centroid: on the sphere, up to the chord's sag.
    const p = field.singularityPositions;
    for (let i = 0; i < 8; i++) {
      const q = [p[3 * i], p[3 * i + 1], p[3 * i + 2]];
      assert.ok(Math.abs(Math.hypot(...q) - 1) < 0.05, `${q}`);
    }
  } finally {
    s.free();
  }
});

test('Poincaré–Hopf: the singularities\' indices add up to the Euler characteristic', () => {
  for (const name of ['eight.obj', 'bunny_1k8.obj', 'fandisk.obj']) {
    const s = new Session(read(name), name);
    try {
      const chi = s.summary().components.reduce((a, c) => a + c.euler_characteristic, 0);
      const field = s.crossField({ featureAngle: 35 });
      const quarters = field.singularityValences.reduce((a, v) => a + (4 - v), 0);
      assert.equal(quarters, 4 * chi, name);
    } finally {
      s.free();
    }
  }
});

test('bad field and layout options are readable errors', () => {
  const s = new Session(read('bunny_1k8.obj'), 'bunny_1k8.obj');
  try {
    assert.throws(() => s.crossField({ feature_angle: 30 }), /unknown option `feature_angle`/);
    assert.throws(() => s.crossField({ patches: 30 }), /unknown option `patches`/);
    assert.throws(() => s.crossField({ featureAngle: -5 }), /featureAngle must be between 0 and 180/);
    assert.throws(() => s.suggestLayout({ patches: 0 }), /patches must be a whole number/);
    assert.throws(() => s.suggestLayout({ patches: 2.5 }), /patches must be a whole number/);
    assert.throws(() => s.suggestLayout({ faces: 12 }), /unknown option `faces`/);
    assert.throws(() => s.suggestLayout({ tracing: -1 }), /tracing must be a whole number/);
    assert.throws(() => s.suggestLayout({ quads: 0 }), /quads must be a number of quads, 1 or more/);
    assert.throws(() => s.suggestLayout({ quads: NaN }), /quads must be a number of quads/);
    assert.throws(() => s.crossField({ quads: 300 }), /unknown option `quads`/);
    assert.throws(() => pickSuggestion([{ judged: null }]), /candidates must be a list of/);
  } finally {
    s.free();
  }
});

// The fandisk's proposal is placed and solved; its quad mesh still folds where two sharp
// lines meet (the core's open target in issue 22), so it is not remeshed here.
for (const [name, remesh] of [['bunny_1k8.obj', true], ['mushroom.obj', true], ['fandisk.obj', false]]) {
  test(`${name}: the suggested layout is a valid layout file that solves${remesh ? ' and remeshes' : ''}`, () => {
    const s = new Session(read(name), name);
    try {
      const { layout: text, field } = s.suggestLayout({});
      // The field it was made from is the one crossField gives.
      assert.deepEqual(field, s.crossField({}));
      const doc = JSON.parse(text);
      assert.equal(doc.version, 1);
      assert.ok(doc.nodes.length >= 4 && doc.edges.length >= 4);
      const view = s.setLayout(text);
      assert.ok(view.summary.faces >= 1);
      // Every mesh vertex but the nodes lies in a face.
      assert.equal(view.vertex_face.filter((f) => f < 0).length, view.summary.nodes);
      if (name === 'fandisk.obj') assert.ok(doc.edges.some((e) => e.align), 'sharp edges are tagged');
      s.startParam({});
      s.finishParam();
      if (remesh) {
        const report = s.remesh({});
        assert.ok(report.quads.faces > 0 && report.layout.faces === view.summary.faces);
      }
      // Asking for more patches gives at least as many faces, or the reason in words.
      let more;
      try {
        more = s.suggestLayout({ patches: 2 * view.summary.faces }).layout;
      } catch (err) {
        assert.match(err.message, /^no valid layout could be made automatically: ./);
      }
      if (more) assert.ok(s.setLayout(more).summary.faces >= view.summary.faces);
    } finally {
      s.free();
    }
  });
}

// The page makes the proposals in workers of their own, one per tracing, and keeps the one
// pickSuggestion names: the same layout as one suggestLayout call makes them all.
test('proposals made apart and picked are the one suggestion', () => {
  const s = new Session(read('mushroom.obj'), 'mushroom.obj');
  try {
    const whole = s.suggestLayout({});
    const first = s.suggestLayout({ tracing: 0 });
    assert.ok(first.tracings >= 1 && first.judged.hausdorff > 0 && first.curves > 0);
    // Asked for 300 quads, the proposal is judged by 300 quads: far coarser, farther off.
    const coarse = s.suggestLayout({ tracing: 0, quads: 300 });
    assert.ok(coarse.judged.hausdorff > 2 * first.judged.hausdorff, `${coarse.judged.hausdorff} vs ${first.judged.hausdorff}`);
    const made = [first];
    for (let k = 1; k < first.tracings; k++) made.push(s.suggestLayout({ tracing: k }));
    const beyond = s.suggestLayout({ tracing: first.tracings });
    assert.equal(beyond.layout, null);
    assert.equal(beyond.error, null);
    const kept = pickSuggestion(made.map(({ judged, curves }) => ({ judged, curves })));
    // All six are made, and the one of lowest score kept (of those near the surface).
    assert.equal(first.tracings, 6);
    const lowest = Math.min(...made.filter((m) => m.judged).map((m) => m.judged.score));
    assert.ok(made[kept].judged.score <= 1.05 * lowest, `${made[kept].judged.score} vs ${lowest}`);
    const chosen = s.finishSuggestion(made[kept].layout, made[kept].judged, {});
    assert.equal(chosen.layout, whole.layout);
    assert.deepEqual(made[kept].field, whole.field);
    assert.throws(() => s.finishSuggestion(made[kept].layout, { hausdorff: 'far' }, {}), /judged must be/);
    // The session keeps the tracings of the last feature angle only: another angle is
    // another field, as a fresh session makes it.
    const fresh = new Session(read('mushroom.obj'), 'mushroom.obj');
    try {
      const sharper = s.suggestLayout({ featureAngle: 5 }).layout;
      assert.notEqual(sharper, whole.layout);
      assert.equal(sharper, fresh.suggestLayout({ featureAngle: 5 }).layout);
    } finally {
      fresh.free();
    }
    // A proposal that failed is null; none made: null, and the first one's error is what one
    // call throws (a thousand tetrahedra, too many triangles to be refined: no face of a
    // layout has a vertex inside).
    const tet = new Session(obj(tetrahedra(1000)), 'tetrahedra.obj');
    const failed = tet.suggestLayout({ tracing: 0 });
    assert.equal(failed.layout, null);
    assert.throws(() => tet.suggestLayout({}), (err) => err.message === failed.error);
    tet.free();
    assert.equal(pickSuggestion([null, { judged: null, curves: 12 }]), 1);
    assert.equal(pickSuggestion([null, null]), null);
  } finally {
    s.free();
  }
});
