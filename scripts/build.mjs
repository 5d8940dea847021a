// Builds the wasm core for the page (www/pkg, ES module) and for Node (target/wasm-node,
// used by tests and benchmarks), and copies the sample meshes into www/samples. One line per
// step; the compilers' full output goes to target/build.log.
import { copyFileSync, existsSync, mkdirSync, writeFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { SAMPLES } from '../www/samples.js';
import { runLogged, startLog } from './logged.mjs';

const root = join(dirname(fileURLToPath(import.meta.url)), '..');
const log = join(root, 'target', 'build.log');
startLog(log, 'quadlay build');
const run = async (cmd, args, env = process.env) => {
  try {
    await runLogged('build: ', cmd, args, { cwd: root, env, log });
  } catch (err) {
    console.error(`build: ${err.message}`);
    process.exit(1);
  }
};

const t0 = Date.now();
const cargoArgs = ['build', '--release', '--lib', '--target', 'wasm32-unknown-unknown'];
if (process.env.QUADLAY_BUILD_STD) {
  // No prebuilt wasm32 std (no rustup): compile it from source, README "Without rustup".
  await run('cargo', [...cargoArgs, '-Zbuild-std=std,panic_abort'], { ...process.env, RUSTC_BOOTSTRAP: '1' });
} else {
  await run('cargo', cargoArgs);
}
const wasm = join(root, 'target/wasm32-unknown-unknown/release/quadlay.wasm');
await run('wasm-bindgen', ['--target', 'web', '--out-dir', 'www/pkg', wasm]);
await run('wasm-bindgen', ['--target', 'nodejs', '--out-dir', 'target/wasm-node', wasm]);
// The Node build is CommonJS; our package.json says "module" for everything below it.
writeFileSync(join(root, 'target/wasm-node/package.json'), '{ "type": "commonjs" }\n');

// The meshes live beside the project in shared/meshes (see README); the page serves copies.
const meshes = join(root, '..', 'shared', 'meshes');
mkdirSync(join(root, 'www/samples'), { recursive: true });
let copied = 0;
for (const s of SAMPLES) {
  const from = join(meshes, s.file);
  if (existsSync(from)) {
    copyFileSync(from, join(root, 'www/samples', s.file));
    copied++;
  } else {
    console.warn(`build: sample ${s.file} not found in ${meshes}; the gallery will lack it`);
  }
}
writeFileSync(join(root, 'www/pkg/.built'), new Date().toISOString() + '\n');
console.log(`build: done in ${((Date.now() - t0) / 1000).toFixed(1)} s, ${copied} sample meshes`);
