// Sets up what building and testing quadlay needs, and only what is missing; a second run
// finds everything and takes seconds. Each step prints one line: what it found or did. The
// full output of what it runs (cargo install, npm ci, apt-get) goes to target/setup.log.
// Where a step cannot work here it stops with a message saying what to do (see README,
// "Set-up").
//
//   node scripts/setup.mjs            Rust + wasm32 target + wasm-bindgen CLI + npm packages
//   node scripts/setup.mjs --browser  also Chromium for the end-to-end tests
import { spawnSync } from 'node:child_process';
import { existsSync, readFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { runLogged, startLog } from './logged.mjs';

const root = join(dirname(fileURLToPath(import.meta.url)), '..');
const wantBrowser = process.argv.includes('--browser');
const log = join(root, 'target', 'setup.log');
let logStarted = false;

function say(step, text) {
  console.log(`setup: ${step.padEnd(13)} ${text}`);
}

function fail(step, text) {
  console.error(`setup: ${step}: ${text}`);
  process.exit(1);
}

/** Output of a command, or null when it cannot run. */
function output(cmd, args) {
  const r = spawnSync(cmd, args, { cwd: root, encoding: 'utf8' });
  return r.status === 0 ? r.stdout.trim() : null;
}

async function run(step, cmd, args) {
  if (!logStarted) startLog(log, 'quadlay set-up');
  logStarted = true;
  try {
    await runLogged(`setup: ${step.padEnd(13)} `, cmd, args, { cwd: root, log });
  } catch (err) {
    fail(step, err.message);
  }
}

// 1. Rust
const cargo = output('cargo', ['--version']);
if (!cargo) {
  fail('rust', 'cargo is not on PATH. Install Rust with rustup (https://rustup.rs), then run this again.');
}
say('rust', cargo);

// 2. The wasm32 target
const target = 'wasm32-unknown-unknown';
const rustup = output('rustup', ['--version']);

// Clippy: `npm test` runs it as a gate (no warnings).
const clippy = output('cargo', ['clippy', '--version']);
if (clippy) {
  say('clippy', clippy);
} else if (rustup !== null) {
  run('clippy', 'rustup', ['component', 'add', 'clippy']);
} else {
  fail('clippy', 'cargo clippy is missing and there is no rustup to add it; install your toolchain\'s clippy ' +
    '(Debian: apt-get install rust-clippy), then run this again.');
}
if (rustup === null && process.env.QUADLAY_BUILD_STD) {
  say('wasm32', 'QUADLAY_BUILD_STD is set: the build compiles std for wasm32 from source');
} else if (rustup === null) {
  const sysroot = output('rustc', ['--print', 'sysroot']);
  if (!sysroot || !existsSync(join(sysroot, 'lib', 'rustlib', target))) {
    fail('wasm32', `no rustup to add the ${target} target. Install rustup, or build std for wasm32 ` +
      'from source: set QUADLAY_BUILD_STD=1 as README.md describes ("Without rustup").');
  }
  say('wasm32', `found in ${sysroot}`);
} else if ((output('rustup', ['target', 'list', '--installed']) || '').split('\n').includes(target)) {
  say('wasm32', `found ${target}`);
} else {
  await run('wasm32', 'rustup', ['target', 'add', target]);
}

// 3. wasm-bindgen CLI at exactly the crate's version (their protocol must match)
const lock = readFileSync(join(root, 'Cargo.lock'), 'utf8');
const m = lock.match(/name = "wasm-bindgen"\nversion = "([^"]+)"/);
if (!m) fail('wasm-bindgen', 'Cargo.lock names no wasm-bindgen version');
const want = m[1];
const have = (output('wasm-bindgen', ['--version']) || '').split(' ')[1];
if (have === want) {
  say('wasm-bindgen', `found ${want}`);
} else {
  say('wasm-bindgen', have ? `found ${have}, need ${want}` : `not found, need ${want} (about 5 minutes, once)`);
  // Without --locked: the CLI's own lock file pins a crate version the registry no longer serves.
  await run('wasm-bindgen', 'cargo', ['install', 'wasm-bindgen-cli', '--version', `=${want}`]);
}

// 4. npm packages
const pkg = JSON.parse(readFileSync(join(root, 'package.json'), 'utf8'));
const needed = Object.keys({ ...pkg.dependencies, ...pkg.devDependencies });
const missing = needed.filter((n) => !existsSync(join(root, 'node_modules', n, 'package.json')));
if (missing.length === 0) {
  say('npm', `found ${needed.join(', ')}`);
} else {
  const npm = process.platform === 'win32' ? 'npm.cmd' : 'npm';
  await run('npm', npm, existsSync(join(root, 'package-lock.json')) ? ['ci', '--no-audit', '--no-fund'] : ['install']);
}

// 5. Chromium for the end-to-end tests: Debian's package, never a browser download
if (wantBrowser) {
  const chromium = process.env.CHROMIUM || '/usr/bin/chromium';
  if (existsSync(chromium)) {
    say('chromium', `found ${chromium}`);
  } else if (process.getuid && process.getuid() === 0 && output('apt-get', ['--version'])) {
    await run('chromium', 'apt-get', ['update', '-q']);
    await run('chromium', 'apt-get', ['install', '-y', '-q', 'chromium']);
  } else {
    fail('chromium', `${chromium} not found. Install Debian's 'chromium' package ` +
      '(sudo apt-get install chromium), or set CHROMIUM to a Chromium binary.');
  }
}
say('done', 'everything needed is here');
