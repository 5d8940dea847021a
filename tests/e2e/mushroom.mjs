// The mushroom sample as the editor tests need it (www/samples/mushroom.obj, copied there by
// scripts/build.mjs).
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { root } from './harness.mjs';

/**
 * The mushroom's vertices, its boundary vertices, the four boundary vertices nearest the
 * corners of its square rim and its top, read here as the page's core reads them.
 */
export function mushroom() {
  const v = [];
  const f = [];
  for (const line of readFileSync(join(root, 'www/samples/mushroom.obj'), 'utf8').split('\n')) {
    const p = line.trim().split(/\s+/);
    if (p[0] === 'v') v.push(p.slice(1, 4).map(Number));
    if (p[0] === 'f') f.push(p.slice(1, 4).map((s) => parseInt(s, 10) - 1));
  }
  const count = new Map();
  for (const t of f) {
    for (let k = 0; k < 3; k++) {
      const a = t[k], b = t[(k + 1) % 3];
      const key = `${Math.min(a, b)},${Math.max(a, b)}`;
      count.set(key, (count.get(key) ?? 0) + 1);
    }
  }
  const boundary = new Set();
  for (const [key, c] of count) if (c === 1) key.split(',').forEach((s) => boundary.add(Number(s)));
  const nearest = (x, y, among) => [...among].sort((a, b) =>
    (v[a][0] - x) ** 2 + (v[a][1] - y) ** 2 - (v[b][0] - x) ** 2 - (v[b][1] - y) ** 2)[0];
  const corners = [[1, 1], [-1, 1], [-1, -1], [1, -1]].map(([x, y]) => nearest(x, y, boundary));
  const top = v.reduce((best, p, i) => (p[2] > v[best][2] ? i : best), 0);
  return { v, corners, top, boundary };
}
