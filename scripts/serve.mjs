// Serves the page on 127.0.0.1: www/ at /, three.js from node_modules at /vendor/three/.
// PORT sets the port (default 8080; the next free one is taken if it is busy).
// Exported for the tests: startServer(port) resolves to { server, url }.
import { createReadStream, statSync } from 'node:fs';
import { createServer } from 'node:http';
import { dirname, extname, join, normalize, sep } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = join(dirname(fileURLToPath(import.meta.url)), '..');
const MOUNTS = [
  ['/vendor/three/', join(root, 'node_modules/three')],
  ['/', join(root, 'www')],
];
const TYPES = {
  '.html': 'text/html; charset=utf-8',
  '.js': 'text/javascript; charset=utf-8',
  '.mjs': 'text/javascript; charset=utf-8',
  '.css': 'text/css; charset=utf-8',
  '.json': 'application/json',
  '.wasm': 'application/wasm',
  '.png': 'image/png',
  '.svg': 'image/svg+xml',
};

function resolve(urlPath) {
  for (const [prefix, dir] of MOUNTS) {
    if (!urlPath.startsWith(prefix)) continue;
    const rel = normalize(decodeURIComponent(urlPath.slice(prefix.length)) || 'index.html');
    if (rel.startsWith('..') || rel.includes(`${sep}..${sep}`)) return null;
    const file = join(dir, rel);
    try {
      const st = statSync(file);
      return st.isDirectory() ? join(file, 'index.html') : file;
    } catch {
      return null;
    }
  }
  return null;
}

export function startServer(port = 0) {
  const server = createServer((req, res) => {
    const file = resolve(new URL(req.url, 'http://x').pathname);
    if (!file) {
      res.writeHead(404, { 'content-type': 'text/plain' }).end('not found\n');
      return;
    }
    res.writeHead(200, {
      'content-type': TYPES[extname(file)] || 'application/octet-stream',
      'cache-control': 'no-cache',
    });
    createReadStream(file).on('error', () => res.end()).pipe(res);
  });
  return new Promise((ok, fail) => {
    server.once('error', fail);
    server.listen(port, '127.0.0.1', () => {
      ok({ server, url: `http://127.0.0.1:${server.address().port}/` });
    });
  });
}

if (process.argv[1] === fileURLToPath(import.meta.url)) {
  let port = Number(process.env.PORT || 8080);
  for (;;) {
    try {
      const { url } = await startServer(port);
      console.log(`quadlay is served at ${url}  (Ctrl-C stops it)`);
      break;
    } catch (e) {
      if (e.code !== 'EADDRINUSE' || port > 8100) throw e;
      port++;
    }
  }
}
