// `npm start`'s set-up and build print one short line per step and keep the tools' full
// output in a log file (scripts/logged.mjs): a set-up run here (everything found), and a
// logged command that compiles and one that fails, as cargo would.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { test } from 'node:test';
import { runLogged, startLog } from '../../scripts/logged.mjs';
import { root } from './harness.mjs';

test('a set-up run says one line per step', () => {
  const out = execFileSync('node', ['scripts/setup.mjs'], { cwd: root, encoding: 'utf8' });
  const lines = out.trim().split('\n');
  assert.ok(lines.length <= 8, out);
  assert.ok(lines.every((l) => l.startsWith('setup: ') && l.length < 160), out);
  assert.match(lines.at(-1), /^setup: done/);
});

/** Runs `script` through runLogged, capturing what it prints; returns { printed, log, error }. */
async function logged(script) {
  const log = join(mkdtempSync(join(tmpdir(), 'quadlay-log-')), 'build.log');
  startLog(log, 'test');
  const printed = [];
  const { log: out, error: err } = console;
  console.log = (...a) => printed.push(a.join(' '));
  console.error = (...a) => printed.push(a.join(' '));
  let error = null;
  try {
    await runLogged('build: ', 'sh', ['-c', script], { cwd: root, log });
  } catch (e) {
    error = e;
  } finally {
    Object.assign(console, { log: out, error: err });
  }
  return { printed: printed.join('\n'), log: readFileSync(log, 'utf8'), error };
}

test('a long command prints a line when it starts and one when it ends; the rest goes to the log', async () => {
  const crates = Array.from({ length: 300 }, (_, i) => `echo "   Compiling crate${i} v0.1.0" >&2`).join('; ');
  const { printed, log, error } = await logged(`${crates}; echo "    Finished release"`);
  assert.equal(error, null);
  assert.ok(printed.split('\n').length <= 2, printed);
  assert.match(printed, /done in [\d.]+ s, 300 crates compiled/);
  assert.match(log, /Compiling crate299 v0.1.0/);
});

test('a failing command shows the end of its log and names the log file', async () => {
  const { printed, error } = await logged('for i in $(seq 1 100); do echo "line $i"; done; echo "error[E0425]: cannot find value" >&2; exit 101');
  assert.match(error.message, /failed \(exit status 101\).*build\.log/);
  assert.match(printed, /error\[E0425\]/);
  assert.doesNotMatch(printed, /line 50\b/);
});
