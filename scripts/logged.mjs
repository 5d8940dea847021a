// Long commands of set-up and build (cargo builds, cargo install, npm ci) with their full
// output in a log file and a short progress line on the terminal: a first `npm start` would
// otherwise print hundreds of lines of cargo output. On a terminal the line is rewritten in
// place (the crate being compiled, how many so far); elsewhere it is printed once when the
// step starts and once when it ends. When a command fails, the end of its log is shown.
import { spawn } from 'node:child_process';
import { appendFileSync, mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import { dirname, relative } from 'node:path';

/** Starts `log` afresh (a header line), creating its folder. */
export function startLog(log, title) {
  mkdirSync(dirname(log), { recursive: true });
  writeFileSync(log, `${title} — ${new Date().toISOString()}\n`);
}

/**
 * Runs `cmd args` in `cwd`, its output appended to `log`, one progress line on stdout.
 * @param {string} prefix what the line starts with ('setup: wasm-bindgen ')
 * @returns {Promise<void>} rejects with an Error naming the command and the log
 */
export function runLogged(prefix, cmd, args, { cwd, env = process.env, log }) {
  const rel = relative(process.cwd(), log);
  const shown = rel && !rel.startsWith('..') ? rel : log;
  const line = `${cmd} ${args.join(' ')}`;
  appendFileSync(log, `\n$ ${line}\n`);
  const tty = process.stdout.isTTY;
  const t0 = Date.now();
  const status = (text) => {
    if (!tty) return;
    const width = process.stdout.columns || 100;
    process.stdout.write(`\r\x1b[K${`${prefix}${text}`.slice(0, width - 1)}`);
  };
  if (!tty) console.log(`${prefix}${line} (output in ${shown})`);
  status(line);
  return new Promise((resolve, reject) => {
    const child = spawn(cmd, args, { cwd, env, stdio: ['ignore', 'pipe', 'pipe'] });
    let compiled = 0;
    let partial = '';
    const take = (chunk) => {
      const text = chunk.toString();
      appendFileSync(log, text);
      const lines = (partial + text).split('\n');
      partial = lines.pop();
      for (const l of lines) {
        const m = /^\s*(Compiling|Installing|Downloaded|Building|Finished)\s+(.*)$/.exec(l);
        if (!m) continue;
        if (m[1] === 'Compiling') compiled++;
        status(`${m[1]} ${m[2].split(' ')[0]}${compiled ? ` (${compiled} crates)` : ''}`);
      }
    };
    child.stdout.on('data', take);
    child.stderr.on('data', take);
    child.on('error', (err) => finish(err.message));
    child.on('close', (code) => finish(code === 0 ? null : `exit status ${code}`));
    let done = false;
    function finish(problem) {
      if (done) return;
      done = true;
      const seconds = ((Date.now() - t0) / 1000).toFixed(1);
      if (tty) process.stdout.write('\r\x1b[K');
      if (!problem) {
        const what = args[0] && !args[0].startsWith('-') ? `${cmd} ${args[0]}` : cmd;
        console.log(`${prefix}${what}: done in ${seconds} s${compiled ? `, ${compiled} crates compiled` : ''}`);
        resolve();
        return;
      }
      const tail = readFileSync(log, 'utf8').trimEnd().split('\n').slice(-25).join('\n');
      console.error(`${tail}\n`);
      reject(new Error(`'${line}' failed (${problem}); the last lines are above, all of it in ${shown}`));
    }
  });
}
