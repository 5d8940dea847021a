// `npm run bench`: times the core natively (examples/bench.rs, release build) and as wasm
// in Node (target/wasm-node), on the shared meshes; prints a table and writes
// bench/results.json. Compare numbers from one run: a busy machine slows both.
import { execFileSync } from 'node:child_process';
import { mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { cpus } from 'node:os';
import { Worker } from 'node:worker_threads';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = join(dirname(fileURLToPath(import.meta.url)), '..');
const MESHES = ['nefertiti.obj', 'eight.obj', 'bunny_1k8.obj', 'mushroom.obj', 'fandisk.obj',
  'bunny_28k.obj', 'elephant_44k.obj', 'bunny_28k_x4.obj'];
// bunny_28k split 1-to-4 (~112k vertices), made here: the same surface, 4× the triangles.
const generated = join(root, 'target', 'bench');
mkdirSync(generated, { recursive: true });
execFileSync('cargo', ['run', '--quiet', '--release', '--example', 'bench', '--', '--subdivide',
  join(root, '..', 'shared', 'meshes', 'bunny_28k.obj'), join(generated, 'bunny_28k_x4.obj')],
{ cwd: root, stdio: ['ignore', 'inherit', 'inherit'] });
const paths = MESHES.map((m) => (m.endsWith('_x4.obj') ? join(generated, m) : join(root, '..', 'shared', 'meshes', m)));
// The sample layout timed on each mesh (www/layouts), as in the page's gallery; its nodes are
// points, so it fits the subdivided bunny too.
const LAYOUTS = { 'fandisk.obj': 'fandisk-features', 'mushroom.obj': 'mushroom-t', 'eight.obj': 'eight-rims',
  'bunny_28k.obj': 'bunny-ears', 'bunny_28k_x4.obj': 'bunny-ears' };
const layoutPath = (m) => LAYOUTS[m] && join(root, 'www', 'layouts', `${LAYOUTS[m]}.layout.json`);

console.log('bench: native (cargo run --release --example bench)');
const out = execFileSync('cargo', ['run', '--quiet', '--release', '--example', 'bench', '--',
  ...paths.map((p, i) => (LAYOUTS[MESHES[i]] ? `${p}@${layoutPath(MESHES[i])}` : p))],
  { cwd: root, encoding: 'utf8', stdio: ['ignore', 'pipe', 'inherit'] });
const native = out.trim().split('\n').map((l) => JSON.parse(l));

// Issue 22's targets for the automatic layout remeshed at about 4000 quads, each at most:
// Hausdorff (% of the bounding-box diagonal), mean angle deviation (deg), irregular vertices;
// besides, quads within 15 % of those asked, none folded, no triangle flipped in its chart (the
// report's parameterization.flipped_triangles), and bunny_28k's layout in 0.5 s.
const AUTO_TARGETS = {
  'nefertiti.obj': { hausdorff_percent: 1.35, angle_deviation_mean_deg: 2.5, irregular_vertices: 11 },
  'eight.obj': { hausdorff_percent: 0.40, angle_deviation_mean_deg: 4.9, irregular_vertices: 68 },
  'bunny_1k8.obj': { hausdorff_percent: 1.11, angle_deviation_mean_deg: 4.7, irregular_vertices: 64 },
  'mushroom.obj': { hausdorff_percent: 0.69, angle_deviation_mean_deg: 4.0, irregular_vertices: 57 },
  'fandisk.obj': { hausdorff_percent: 0.87, angle_deviation_mean_deg: 3.9, irregular_vertices: 67 },
  'bunny_28k.obj': { hausdorff_percent: 1.36, angle_deviation_mean_deg: 4.9, irregular_vertices: 74, layout_ms: 500 },
  'elephant_44k.obj': { hausdorff_percent: 1.40, angle_deviation_mean_deg: 7.0, irregular_vertices: 145 },
};
console.log('bench: automatic layout, native (cargo run --release --example bench -- --auto-layout)');
const autoOut = execFileSync('cargo', ['run', '--quiet', '--release', '--example', 'bench', '--', '--auto-layout',
  ...Object.keys(AUTO_TARGETS).map((m) => paths[MESHES.indexOf(m)])],
{ cwd: root, encoding: 'utf8', stdio: ['ignore', 'pipe', 'inherit'] });
const autoLayout = autoOut.trim().split('\n').map((l) => {
  const row = JSON.parse(l);
  const targets = { ...AUTO_TARGETS[row.mesh], quads: [0.85, 1.15].map((f) => Math.round(f * row.quads_asked)), folded_quads: 0,
    flipped_triangles: 0 };
  // Whether each measure meets its target; a refused row meets none but the layout time.
  const meets = Object.fromEntries(Object.entries(targets).map(([k, t]) => [k,
    Array.isArray(t) ? row[k] >= t[0] && row[k] <= t[1] : row[k] <= t]));
  return { mesh: row.mesh, ...row, targets, meets };
});

// The fastest of at least 3 runs and half a second: on a shared machine other work only ever
// adds time, and swings a median by a third.
function fastestMs(f) {
  let fastest = Infinity;
  const start = performance.now();
  for (let runs = 0; runs < 3 || (performance.now() - start < 500 && runs < 50); runs++) {
    const t = performance.now();
    f();
    fastest = Math.min(fastest, performance.now() - t);
  }
  return fastest;
}

console.log('bench: wasm in Node (target/wasm-node)');
const { Session, pickSuggestion } = createRequire(import.meta.url)(join(root, 'target/wasm-node/quadlay.js'));
const wasm = MESHES.map((mesh, i) => {
  const bytes = new Uint8Array(readFileSync(paths[i]));
  const row = { mesh, load_ms: Number(fastestMs(() => new Session(bytes, mesh).free()).toFixed(3)) };
  if (LAYOUTS[mesh]) {
    const text = readFileSync(layoutPath(mesh), 'utf8');
    const s = new Session(bytes, mesh);
    row.layout_ms = Number(fastestMs(() => s.setLayout(text)).toFixed(3));
    // Five warm runs of parameterization and remesh; the fastest (by their sum) is kept.
    const runs = [0, 1, 2, 3, 4].map(() => {
      const t0 = performance.now();
      s.startParam(true);
      for (let k = 0; k < 3; k++) s.stepParam();
      s.finishParam();
      const param_total_ms = Number((performance.now() - t0).toFixed(1));
      const { factorizations, ...stages } = s.paramStages();
      const param_stages_ms = Object.fromEntries(Object.entries(stages)
        .map(([stage, seconds]) => [stage, Number((seconds * 1000).toFixed(1))]));
      const t1 = performance.now();
      const report = s.remesh({});
      const mesh_and_quality_ms = Number((performance.now() - t1).toFixed(1));
      return { param_total_ms, param_stages_ms, factorizations, mesh_and_quality_ms,
        mesh_ms: Number((report.seconds.mesh * 1000).toFixed(1)), quads: report.quads.faces };
    });
    runs.sort((a, b) => (a.param_total_ms + a.mesh_and_quality_ms) - (b.param_total_ms + b.mesh_and_quality_ms));
    Object.assign(row, runs[0]);
    row.pipeline_ms = Number((row.load_ms + row.layout_ms + row.param_total_ms + row.mesh_and_quality_ms).toFixed(1));
    // The remesh alone, as a remesher without a report does it (no quality measures).
    row.pipeline_without_quality_ms = Number((row.load_ms + row.layout_ms + row.param_total_ms + row.mesh_ms).toFixed(1));
    s.free();
  }
  return row;
});

// The page's one click (issue 22): suggest a layout, place it, solve (3 iterations) and
// remesh bunny_28k in wasm; the target is native Instant Meshes' 1.1 s on this machine.
const SUGGEST_MESH = 'bunny_28k.obj';
/** The layout one suggestLayout call gave (suggestApart compares). */
let oneCallLayout;
const suggest = (() => {
  const s = new Session(new Uint8Array(readFileSync(paths[MESHES.indexOf(SUGGEST_MESH)])), SUGGEST_MESH);
  try {
    const runs = [0, 1, 2].map(() => {
      const t0 = performance.now();
      const { layout } = s.suggestLayout({});
      const t1 = performance.now();
      oneCallLayout = layout;
      const faces = s.setLayout(layout).summary.faces;
      s.startParam(true);
      for (let k = 0; k < 3; k++) s.stepParam();
      s.finishParam();
      const quads = s.remesh({}).quads.faces;
      const t2 = performance.now();
      return { suggest_ms: Number((t1 - t0).toFixed(1)), total_ms: Number((t2 - t0).toFixed(1)), faces, quads };
    });
    return { mesh: SUGGEST_MESH, ...runs.sort((a, b) => a.total_ms - b.total_ms)[0] };
  } catch (err) {
    // A proposal the core cannot finish is a result too: the bench says why.
    return { mesh: SUGGEST_MESH, error: err?.message || String(err) };
  } finally {
    s.free();
  }
})();

// The page's Suggest with more than one processor (suggest.js): the core's six tracings at once
// in SUGGEST_WORKERS workers that each load the mesh and make tracings j, j + SUGGEST_WORKERS,
// …, and the one pickSuggestion names; here in Node's worker threads. The same layout as the
// one call above.
const SUGGEST_WORKERS = 3;
const SUGGEST_WORKER = `
  const { parentPort, workerData: { wasm, bytes, name, j, workers } } = require('node:worker_threads');
  const { Session } = require(wasm);
  const s = new Session(new Uint8Array(bytes), name);
  const made = [];
  for (let k = j; ; k += workers) {
    const { layout, tracings, judged, curves } = s.suggestLayout({ tracing: k });
    if (tracings <= k) break;
    made.push({ k, layout, judged, curves });
  }
  parentPort.postMessage(made);`;
const suggestApart = await (async () => {
  const bytes = readFileSync(paths[MESHES.indexOf(SUGGEST_MESH)]);
  const wasmPath = join(root, 'target/wasm-node/quadlay.js');
  const once = async () => {
    const t0 = performance.now();
    const made = [];
    const answers = await Promise.all(Array.from({ length: SUGGEST_WORKERS }, (_, j) => new Promise((resolve, reject) => {
      const w = new Worker(SUGGEST_WORKER, { eval: true, workerData: { wasm: wasmPath, bytes, name: SUGGEST_MESH, j, workers: SUGGEST_WORKERS } });
      w.once('message', (m) => { resolve(m); w.terminate(); });
      w.once('error', reject);
    })));
    for (const m of answers.flat()) made[m.k] = m;
    const kept = pickSuggestion(made.map((m) => (m.layout == null ? null : { judged: m.judged, curves: m.curves })));
    // The page's worker has the mesh loaded already; here loading it is part of the time.
    const s = new Session(new Uint8Array(bytes), SUGGEST_MESH);
    try {
      const { layout } = s.finishSuggestion(made[kept]?.layout ?? null, made[kept]?.judged ?? null, {});
      return { suggest_ms: Number((performance.now() - t0).toFixed(1)), workers: SUGGEST_WORKERS, layout };
    } finally {
      s.free();
    }
  };
  try {
    const runs = [await once(), await once()];
    const best = runs.sort((a, b) => a.suggest_ms - b.suggest_ms)[0];
    const same = best.layout === oneCallLayout;
    return { mesh: SUGGEST_MESH, suggest_ms: best.suggest_ms, workers: best.workers, same_layout_as_one_call: same };
  } catch (err) {
    return { mesh: SUGGEST_MESH, error: err?.message || String(err) };
  }
})();

const results = {
  date: new Date().toISOString(),
  machine: { cpus: cpus().length, cpu: cpus()[0]?.model, node: process.version },
  what: 'ms, the fastest of several runs (other work on a shared machine only adds time). load: bytes to validated halfedge mesh (parse + connectivity); ' +
    'layout: placing the sample layout (curves, faces, patches); param: initial solve + 3 ' +
    'chart-optimization iterations + final solve, the fastest of 3 runs natively (with their mesh and quality), of 5 in wasm ' +
    '(by the sum with their remesh); mesh: quad extraction (native), ' +
    'quality: quality measures (native); wasm mesh_and_quality: both; pipeline: load + layout + ' +
    'param + mesh + quality; pipeline_without_quality: the same without the quality measures',
  native,
  wasm_node: wasm,
  wasm_suggest_solve_remesh: suggest,
  wasm_suggest_in_three_workers: suggestApart,
  auto_layout: {
    what: 'native, per shared mesh: layout_ms the fastest of up to 3 runs of propose_layout (layout_runs; fewer past 3 s), ' +
      'then the default parameterization and the extraction at about quads_asked quads: quads, hausdorff_percent (of the ' +
      'bounding-box diagonal), angle_deviation_mean_deg, irregular_vertices, folded_quads, flipped_triangles (in their ' +
      'charts, after the final solve); error: why the layout, ' +
      'parameterization or extraction refused instead; targets (issue 22; at most, quads a range) and whether each is met',
    rows: autoLayout,
  },
};
mkdirSync(join(root, 'bench'), { recursive: true });
writeFileSync(join(root, 'bench/results.json'), JSON.stringify(results, null, 2) + '\n');

console.log('\nparameterization stages, native (ms): mesh, assembly, symbolic, factor, solve, chart optimization; ' +
  'numeric factorizations; reference: scalar cotangent Laplacian factor+solve');
for (const n of native) {
  if (!n.param_stages_ms) continue;
  const st = n.param_stages_ms;
  console.log(`${n.mesh.padEnd(18)} ${[st.assembly, st.symbolic, st.factor, st.solve, st.chart_optimization].map((x) => x.toFixed(1).padStart(8)).join('')}` +
    `${String(n.factorizations).padStart(4)}   reference ${n.laplacian_cholesky_ms.toFixed(1)}`);
}
const cell = (x, w) => (x === undefined ? '-' : x.toFixed(2)).padStart(w);
console.log('\nmesh               triangles  load native   wasm  layout native   wasm  param native     wasm' +
  '  mesh+quality native    wasm  pipeline wasm  without quality  (ms)');
for (const [i, n] of native.entries()) {
  const mq = n.mesh_ms === undefined ? undefined : n.mesh_ms + n.quality_ms;
  console.log(`${n.mesh.padEnd(18)} ${String(n.triangles).padStart(9)}  ${cell(n.load_ms, 11)} ${cell(wasm[i].load_ms, 6)}` +
    `  ${cell(n.layout_ms, 13)} ${cell(wasm[i].layout_ms, 6)}  ${cell(n.param_total_ms, 12)} ${cell(wasm[i].param_total_ms, 8)}` +
    `  ${cell(mq, 19)} ${cell(wasm[i].mesh_and_quality_ms, 7)}  ${cell(wasm[i].pipeline_ms, 13)}` +
    ` ${cell(wasm[i].pipeline_without_quality_ms, 16)}`);
}
console.log(suggest.error
  ? `\nsuggest + solve + remesh, wasm, ${suggest.mesh}: failed: ${suggest.error}`
  : `\nsuggest + solve + remesh, wasm, ${suggest.mesh}: ${suggest.total_ms.toFixed(0)} ms (suggest ${suggest.suggest_ms.toFixed(0)} ms; ` +
    `${suggest.faces} faces, ${suggest.quads} quads; target 1100 ms)`);
console.log(suggestApart.error
  ? `suggest in three workers, wasm: failed: ${suggestApart.error}`
  : `suggest in three workers (the page's, with more than one processor), wasm: ${suggestApart.suggest_ms.toFixed(0)} ms ` +
    `(${suggestApart.same_layout_as_one_call ? 'the same layout as one call' : 'NOT the layout one call makes'})`);

console.log('\nautomatic layout, native, remeshed at about 4000 quads: each value, its target, whether it meets it');
console.log(`${'mesh'.padEnd(18)}${['layout ms', 'quads', 'Hausdorff %', 'angle °', 'irregular', 'folded', 'flipped triangles']
  .map((h) => h.padStart(22)).join('')}`);
const autoCell = (row, key, digits) => {
  const t = row.targets[key];
  if (row[key] === undefined && t === undefined) return '-'.padStart(22);
  const value = row[key] === undefined ? '-' : row[key].toFixed(digits);
  const target = t === undefined ? '' : Array.isArray(t) ? ` (${t[0]}-${t[1]})` : ` (≤${t})`;
  return `${value}${target}${t === undefined ? '' : row.meets[key] ? ' yes' : ' no'}`.padStart(22);
};
for (const row of autoLayout) {
  console.log(`${row.mesh.padEnd(18)}${autoCell(row, 'layout_ms', 0)}${autoCell(row, 'quads', 0)}` +
    `${autoCell(row, 'hausdorff_percent', 2)}${autoCell(row, 'angle_deviation_mean_deg', 1)}` +
    `${autoCell(row, 'irregular_vertices', 0)}${autoCell(row, 'folded_quads', 0)}${autoCell(row, 'flipped_triangles', 0)}`);
  if (row.error) console.log(`${''.padEnd(18)}refused: ${row.error}`);
}
console.log('\nbench: written to bench/results.json');
