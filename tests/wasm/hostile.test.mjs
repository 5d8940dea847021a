// Hostile input in the wasm build (issue 21): the cases that trapped `unreachable` (an
// allocation beyond wasm32's memory, or a count that wrapped in its 32-bit usize) are JS
// errors now, with the same message as the command line's `error:` line.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { existsSync, mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, test } from 'node:test';
import { fileURLToPath } from 'node:url';

const require = createRequire(import.meta.url);
const { Session } = require('../../target/wasm-node/quadlay.js');
const root = fileURLToPath(new URL('../../', import.meta.url));

// The command line as `cargo test` (run before these tests by `npm test`) or a release
// build left it.
const cli = ['debug', 'release'].map((p) => join(root, 'target', p, 'quadlay')).find(existsSync);
const dir = mkdtempSync(join(tmpdir(), 'quadlay-hostile-'));
after(() => rmSync(dir, { recursive: true, force: true }));

// The unit square as an n × n grid of squares, two triangles each: its four sides have
// length exactly 1 (sums of 1/8), so an edge length of 2^-16 asks for exactly 2^16 segments
// a side and 2^32 quads, which is 0 in a 32-bit usize.
const N = 8;
function gridObj() {
  let s = '';
  for (let j = 0; j <= N; j++) for (let i = 0; i <= N; i++) s += `v ${i / N} ${j / N} 0\n`;
  const id = (i, j) => j * (N + 1) + i + 1;
  for (let j = 0; j < N; j++) {
    for (let i = 0; i < N; i++) s += `f ${id(i, j)} ${id(i + 1, j)} ${id(i + 1, j + 1)}\nf ${id(i, j)} ${id(i + 1, j + 1)} ${id(i, j + 1)}\n`;
  }
  return s;
}
const corners = [0, N, (N + 1) * (N + 1) - 1, N * (N + 1)];
const layoutOf = (nodes) => JSON.stringify({ format: 'quad-layout', version: 1, nodes, edges: [] });
const squareLayout = layoutOf(corners.map((vertex) => ({ vertex })));

const meshPath = join(dir, 'square.obj');
writeFileSync(meshPath, gridObj());

/** The command line's error for `args`: exit status 2 and one line, returned without
 * `error: FILE: ` (the page names no file). */
function cliError(args, file) {
  let out;
  try {
    execFileSync(cli, args, { stdio: ['ignore', 'pipe', 'pipe'] });
    assert.fail(`quadlay ${args.join(' ')} succeeded`);
  } catch (e) {
    out = e;
  }
  assert.equal(out.status, 2, String(out.stderr));
  const lines = String(out.stderr).split('\n').filter((l) => l !== '');
  assert.equal(lines.length, 1, String(out.stderr));
  const prefix = `error: ${file}: `;
  assert.ok(lines[0].startsWith(prefix), lines[0]);
  return lines[0].slice(prefix.length);
}

/** `f()` throws a JS Error (not a trapped `RuntimeError: unreachable`); its message. */
function jsError(f) {
  try {
    f();
  } catch (e) {
    assert.ok(!(e instanceof WebAssembly.RuntimeError), `trapped: ${e}`);
    return e.message;
  }
  assert.fail('no error');
}

test('edge lengths that trapped or wrapped are refused with the command line message', { skip: !cli && 'no quadlay binary' }, () => {
  const layoutPath = join(dir, 'square.layout.json');
  writeFileSync(layoutPath, squareLayout);
  const s = new Session(new TextEncoder().encode(gridObj()), 'square.obj');
  try {
    s.setLayout(squareLayout);
    s.startParam({});
    s.finishParam();
    // 2^-16: 2^32 quads, 0 in wasm32's usize (it ran 25 s and trapped); 3e-4: 11 M quads,
    // under the old cap, beyond wasm32's memory (trapped); 1e-320: infinite counts (taken
    // as one: the coarsest mesh); 1e-300: a count past any integer.
    for (const edge of [2 ** -16, 3e-4, 1e-320, 1e-300]) {
      const message = jsError(() => s.remesh({ edge_length: edge }));
      const expected = cliError(['remesh', meshPath, '--layout', layoutPath, '--edge-length', String(edge)], layoutPath);
      assert.equal(message, expected, `edge length ${edge}`);
      assert.match(message, /^the edge length asks for (about \d|more quads than can be counted)/);
    }
    // The session is still usable: a sane edge length meshes.
    const report = s.remesh({ edge_length: 0.25 });
    assert.equal(report.quads.faces, 16);
  } finally {
    s.free();
  }
});

test('layout errors quote input cut short and name the real vertex count, as the command line does', { skip: !cli && 'no quadlay binary' }, () => {
  const s = new Session(new TextEncoder().encode(gridObj()), 'square.obj');
  try {
    const cases = [
      layoutOf([{ vertex: 4294967296 }]),
      layoutOf([{ vertex: 0, ['k'.repeat(100000) + '\u001b[31m']: 1 }]),
    ];
    for (const [k, text] of cases.entries()) {
      const layoutPath = join(dir, `bad-${k}.layout.json`);
      writeFileSync(layoutPath, text);
      const message = jsError(() => s.setLayout(text));
      assert.equal(message, cliError(['check', meshPath, '--layout', layoutPath], layoutPath));
      assert.ok(message.length < 300 && !/[\u0000-\u001f]/.test(message), message);
    }
  } finally {
    s.free();
  }
});
