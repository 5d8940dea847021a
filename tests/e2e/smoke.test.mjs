// Smoke test of the page in headless Chromium: it opens with the first sample and its layout
// drawn (checked on the screenshot's pixels), shows a broken file's error without losing the
// mesh, loads a small STL through the file input, places a layout file (and names the entry
// of a broken one), and logs no errors on the way.
// Screenshots go to test-output/e2e/.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import { PNG } from 'pngjs';
import { outDir, root, startBrowser } from './harness.mjs';
import { SAMPLES } from '../../www/samples.js';

const TIMEOUT = 20_000;

let harness, page, baseUrl, problems;

before(async () => {
  harness = await startBrowser();
  ({ baseUrl, problems } = harness);
  page = await harness.newPage({ timeout: TIMEOUT });
});

after(async () => {
  await harness?.close();
});

const state = () => page.evaluate(() => window.quadlay?.state);

/** Waits until `predicate(window.quadlay)` holds in the page; says where the page stood if not. */
const waitFor = (predicate) => harness.waitFor(page, predicate);

/**
 * Takes a screenshot and measures the viewport canvas on it, leaving out the controls over
 * it: the share of pixels that differ from the background (the commonest colour on the
 * canvas's border) and how many gray levels those pixels have.
 */
async function shootAndMeasure(file) {
  const path = join(outDir, file);
  await page.screenshot({ path, animations: 'disabled' });
  const box = await page.locator('#viewport canvas').boundingBox();
  assert.ok(box && box.width > 300 && box.height > 300, `viewport canvas too small: ${JSON.stringify(box)}`);
  // The controls drawn over the view are not the mesh: leave their pixels out.
  const overlays = await page.$$eval('#viewport > :not(canvas)', (els) =>
    els.filter((el) => el.checkVisibility()).map((el) => {
      const r = el.getBoundingClientRect();
      return [r.left - 2, r.top - 2, r.right + 2, r.bottom + 2];
    }));
  const covered = (x, y) => overlays.some(([l, t, r, b]) => x >= l && x < r && y >= t && y < b);
  const png = PNG.sync.read(readFileSync(path));
  const x0 = Math.ceil(box.x), y0 = Math.ceil(box.y);
  const x1 = Math.min(png.width, Math.floor(box.x + box.width));
  const y1 = Math.min(png.height, Math.floor(box.y + box.height));
  const at = (x, y) => {
    const i = (y * png.width + x) * 4;
    return [png.data[i], png.data[i + 1], png.data[i + 2]];
  };

  const counts = new Map();
  const vote = (x, y) => {
    const key = at(x, y).join(',');
    counts.set(key, (counts.get(key) || 0) + 1);
  };
  for (let x = x0 + 2; x < x1 - 2; x++) { vote(x, y0 + 2); vote(x, y1 - 3); }
  for (let y = y0 + 2; y < y1 - 2; y++) { vote(x0 + 2, y); vote(x1 - 3, y); }
  const background = [...counts.entries()].sort((a, b) => b[1] - a[1])[0][0].split(',').map(Number);

  let total = 0, differ = 0;
  const levels = new Map();
  for (let y = y0; y < y1; y++) {
    for (let x = x0; x < x1; x++) {
      if (covered(x, y)) continue;
      total++;
      const [r, g, b] = at(x, y);
      const d = Math.max(Math.abs(r - background[0]), Math.abs(g - background[1]), Math.abs(b - background[2]));
      if (d <= 12) continue;
      differ++;
      const gray = Math.round(0.299 * r + 0.587 * g + 0.114 * b);
      levels.set(gray, (levels.get(gray) || 0) + 1);
    }
  }
  // Levels that cover at least 0.2 % of the drawn pixels: shading, not antialiasing noise.
  const grays = [...levels.entries()].filter(([, n]) => n >= differ * 0.002).map(([g]) => g);
  return {
    path,
    background,
    fraction: differ / total,
    levels: grays.length,
    range: grays.length ? Math.max(...grays) - Math.min(...grays) : 0,
  };
}

const describe = (m) =>
  `${m.path}: ${(m.fraction * 100).toFixed(1)} % drawn, ${m.levels} gray levels over a range of ${m.range}`;

function assertDrawn(m, what) {
  assert.ok(m.fraction > 0.10, `${what}: only ${(m.fraction * 100).toFixed(1)} % of the viewport differs from the background ${m.background} (${m.path})`);
  assert.ok(m.levels >= 8, `${what}: only ${m.levels} gray levels on the mesh, no shading? (${m.path})`);
  assert.ok(m.range >= 40, `${what}: gray levels span only ${m.range}, no shading? (${m.path})`);
}

test('the page opens with the fandisk and its sample layout drawn', async (t) => {
  await page.goto(baseUrl);
  await waitFor((q) => (q.state === 'ready' && q.layout) || q.state === 'error');
  const layout = await page.evaluate(() => window.quadlay.layout);
  // The gallery's fandisk layout, as the file in www/layouts says.
  const sample = SAMPLES.find((s) => s.file === 'fandisk.obj');
  const doc = JSON.parse(readFileSync(join(root, 'www', sample.layout), 'utf8'));
  assert.equal(layout.edges, doc.edges.length);
  assert.ok(layout.faces >= 6, `${layout.faces} faces`);
  // The count, then (guidance, issue 20) how many faces need a node.
  assert.match(await page.locator('#layout-summary dd[data-key="faces"]').textContent(), new RegExp(`^${layout.faces}( ⚠ \\d+ Show)?$`));
  assert.equal(await state(), 'ready', await page.evaluate(() => window.quadlay.error));
  const summary = await page.evaluate(() => window.quadlay.summary);
  assert.equal(summary.vertices, 6475);
  assert.equal(summary.triangles, 12946);
  assert.equal(summary.genus, 0);
  assert.equal(summary.boundary_loops, 0);
  assert.equal(await page.locator('#summary dd[data-key="vertices"]').textContent(), '6,475');
  assert.equal(await page.locator('#summary dd[data-key="triangles"]').textContent(), '12,946');
  assert.equal(await page.locator('#summary dd[data-key="genus"]').textContent(), '0');
  assert.equal(await page.locator('[role="alert"]').isVisible(), false);

  const m = await shootAndMeasure('fandisk.png');
  t.diagnostic(describe(m));
  assertDrawn(m, 'fandisk');
});

test('a broken file shows a readable error and keeps the mesh', async (t) => {
  await page.setInputFiles('#file-input', {
    name: 'broken.obj',
    mimeType: 'text/plain',
    buffer: Buffer.from('v 0 0 0\nv 1 x 0\nv 0 1 0\nf 1 2 3\n'),
  });
  await waitFor((q) => q.state === 'error');
  const alert = page.locator('[role="alert"]');
  assert.ok(await alert.isVisible(), 'the error box is not visible');
  const text = await alert.textContent();
  assert.match(text, /broken\.obj/);
  assert.match(text, /line 2/);
  assert.match(await page.evaluate(() => window.quadlay.error), /line 2/);

  // The fandisk is still the mesh shown and summarised.
  assert.equal(await page.evaluate(() => window.quadlay.summary.vertices), 6475);
  assert.equal(await page.locator('#summary dd[data-key="vertices"]').textContent(), '6,475');
  const m = await shootAndMeasure('broken-file.png');
  t.diagnostic(describe(m));
  assertDrawn(m, 'fandisk after a broken file');
});

test('a small ASCII STL loads through the file input', async () => {
  const facet = (a, b, c) => `facet normal 0 0 0\n outer loop\n  vertex ${a}\n  vertex ${b}\n  vertex ${c}\n endloop\nendfacet\n`;
  const [A, B, C, D] = ['0 0 0', '1 0 0', '0 1 0', '0 0 1'];
  const stl = `solid tetra\n${facet(A, C, B)}${facet(A, B, D)}${facet(A, D, C)}${facet(B, C, D)}endsolid tetra\n`;
  await page.setInputFiles('#file-input', { name: 'tetra.stl', mimeType: 'model/stl', buffer: Buffer.from(stl) });
  await waitFor((q) => q.state === 'ready' && q.summary?.repairs.vertices_before_refinement === 4);
  const summary = await page.evaluate(() => window.quadlay.summary);
  assert.equal(summary.format, 'stl');
  // Refined (a coarse mesh, mesh/refine.rs); the panel shows the file's counts.
  assert.equal(summary.repairs.triangles_before_refinement, 4);
  assert.ok(summary.triangles >= 4000, `${summary.triangles}`);
  assert.equal(summary.genus, 0);
  assert.equal(await page.locator('#summary dd[data-key="vertices"]').textContent(), '4');
  assert.equal(await page.locator('#summary dd[data-key="triangles"]').textContent(), '4');
  assert.equal(await page.locator('[role="alert"]').isVisible(), false, 'the old error is still shown');
  const m = await shootAndMeasure('tetra.png');
  assert.ok(m.fraction > 0.05, `tetra: only ${(m.fraction * 100).toFixed(1)} % drawn (${m.path})`);
});

test('a layout file is placed on the mesh; a broken one names its entry', async (t) => {
  await page.evaluate(() => window.quadlay.load('samples/mushroom.obj'));
  await waitFor((q) => q.state === 'ready' && q.summary?.vertices === 2337 && !q.layout);
  assert.equal(await page.locator('#layout-card').isVisible(), false, 'a new mesh keeps the old layout');

  const bad = { format: 'quad-layout', version: 1, nodes: [{ vertex: 0 }, { vertex: 5 }], edges: [{ nodes: [0, 9] }] };
  await page.setInputFiles('#layout-input', { name: 'bad.layout.json', mimeType: 'application/json', buffer: Buffer.from(JSON.stringify(bad)) });
  await waitFor((q) => q.state === 'error');
  assert.match(await page.locator('[role="alert"]').textContent(), /edges\[0\]: node 9 does not exist/);

  const good = readFileSync(join(root, 'www/layouts/mushroom-t.layout.json'));
  await page.setInputFiles('#layout-input', { name: 'mushroom-t.layout.json', mimeType: 'application/json', buffer: good });
  await waitFor((q) => q.state === 'ready' && q.layout?.faces === 7);
  assert.equal(await page.evaluate(() => window.quadlay.layout.t_vertices), 2);
  assert.equal(await page.locator('#layout-summary dd[data-key="t_vertices"]').textContent(), '2');
  assert.equal(await page.locator('[role="alert"]').isVisible(), false);
  const m = await shootAndMeasure('mushroom-layout.png');
  t.diagnostic(describe(m));
  assertDrawn(m, 'mushroom with layout');
});

test('no page errors, console errors or failed requests', () => {
  assert.deepEqual(problems, []);
});
