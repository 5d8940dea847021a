// `npm run bench`: times the core natively (examples/bench.rs, release build) and as wasm
// in Node (target/wasm-node), on the shared meshes; prints a table and writes
// bench/results.json. Compare numbers from one run: a busy machine slows both.
import { execFileSync } from 'node:child_process';
import { mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { cpus } from 'node:os';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = join(dirname(fileURLToPath(import.meta.url)), '..');
const MESHES = ['nefertiti.obj', 'eight.obj', 'bunny_1k8.obj', 'mushroom.obj', 'fandisk.obj',
  'bunny_28k.obj', 'elephant_44k.obj'];
const paths = MESHES.map((m) => join(root, '..', 'shared', 'meshes', m));

console.log('bench: native (cargo run --release --example bench)');
const out = execFileSync('cargo', ['run', '--quiet', '--release', '--example', 'bench', '--', ...paths],
  { cwd: root, encoding: 'utf8', stdio: ['ignore', 'pipe', 'inherit'] });
const native = out.trim().split('\n').map((l) => JSON.parse(l));

function medianMs(f) {
  const times = [];
  const start = performance.now();
  while (times.length < 3 || (performance.now() - start < 500 && times.length < 50)) {
    const t = performance.now();
    f();
    times.push(performance.now() - t);
  }
  times.sort((a, b) => a - b);
  return times[times.length >> 1];
}

console.log('bench: wasm in Node (target/wasm-node)');
const { Session } = createRequire(import.meta.url)(join(root, 'target/wasm-node/quadlay.js'));
const wasm = MESHES.map((mesh, i) => {
  const bytes = new Uint8Array(readFileSync(paths[i]));
  return { mesh, load_ms: Number(medianMs(() => new Session(bytes, mesh).free()).toFixed(3)) };
});

const results = {
  date: new Date().toISOString(),
  machine: { cpus: cpus().length, cpu: cpus()[0]?.model, node: process.version },
  what: 'load_ms: bytes to validated halfedge mesh (parse + connectivity), median',
  native,
  wasm_node: wasm,
};
mkdirSync(join(root, 'bench'), { recursive: true });
writeFileSync(join(root, 'bench/results.json'), JSON.stringify(results, null, 2) + '\n');

console.log('\nmesh               triangles  native load  wasm load   topology  cot weights (ms)');
for (const [i, n] of native.entries()) {
  console.log(`${n.mesh.padEnd(18)} ${String(n.triangles).padStart(9)}  ${n.load_ms.toFixed(2).padStart(11)}` +
    `  ${wasm[i].load_ms.toFixed(2).padStart(9)}  ${n.topology_ms.toFixed(2).padStart(9)}` +
    `  ${n.cotangent_weights_ms.toFixed(2).padStart(11)}`);
}
console.log('\nbench: written to bench/results.json');
