// The repairs of a raw scan from the mesh summary (issue 20, part 5), in headless Chromium: a
// mesh with a speck beside it and two small holes (the coarse bunny with two triangles taken
// out and a tetrahedron added) offers "Keep largest" and "Fill holes"; one click each loads
// it again repaired, the summary lists the repair, and the layout being drawn stays.
// Screenshot: test-output/e2e/repairs-*.png.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import { outDir, root, startBrowser } from './harness.mjs';

const TIMEOUT = 30_000;
let harness, baseUrl, problems;

before(async () => {
  harness = await startBrowser();
  ({ baseUrl, problems } = harness);
});

after(async () => {
  await harness?.close();
});

/** bunny_1k8 without two triangles far apart (two holes of 3 edges) and with a speck. */
function scan() {
  const lines = readFileSync(join(root, 'www/samples/bunny_1k8.obj'), 'utf8').split('\n');
  const faces = lines.filter((l) => l.startsWith('f '));
  const vertices = lines.filter((l) => l.startsWith('v ')).length;
  const drop = new Set([faces[10], faces[Math.floor(faces.length / 2)]]);
  const n = vertices;
  const speck = ['v 5 5 5', 'v 5.1 5 5', 'v 5 5.1 5', 'v 5 5 5.1',
    `f ${n + 1} ${n + 3} ${n + 2}`, `f ${n + 1} ${n + 2} ${n + 4}`, `f ${n + 1} ${n + 4} ${n + 3}`, `f ${n + 2} ${n + 3} ${n + 4}`];
  return [...lines.filter((l) => !drop.has(l)), ...speck].join('\n');
}

test('a speck and two holes: one click each repairs them, the layout stays', async (t) => {
  const page = await harness.newPage({ timeout: TIMEOUT });
  await page.route('**/scan.obj', (route) => route.fulfill({ contentType: 'text/plain', body: scan() }));
  await page.goto(`${baseUrl}?mesh=scan.obj`);
  await harness.waitFor(page, (q) => q.state === 'ready');
  let s = await page.evaluate(() => window.quadlay.summary);
  t.diagnostic(`as read: ${s.components.length} components, ${s.boundary_loops} boundary loops`);
  assert.equal(s.components.length, 2);
  assert.equal(s.boundary_loops, 2);
  assert.equal(await page.locator('#summary-details').evaluate((el) => el.open), true);
  assert.match(await page.locator('#repair-fill-holes').textContent(), /Fill holes ≤ 3 edges/);
  // A node drawn before the repairs stays through them.
  const doc = { format: 'quad-layout', version: 1, nodes: [{ vertex: 5 }], edges: [] };
  await page.evaluate((d) => window.quadlay.editor.setDoc(d), doc);
  await page.evaluate(() => window.quadlay.editor.settled());
  await page.screenshot({ path: join(outDir, 'repairs-offered.png') });

  await page.click('#repair-keep-largest');
  await harness.waitFor(page, (q) => q.state === 'ready' && q.summary.components.length === 1);
  s = await page.evaluate(() => window.quadlay.summary);
  assert.equal(s.boundary_loops, 2);
  assert.equal(await page.locator('#repair-keep-largest').count(), 0);
  assert.deepEqual(await page.evaluate(() => window.quadlay.editor.doc), doc);

  await page.click('#repair-fill-holes');
  await harness.waitFor(page, (q) => q.state === 'ready' && q.summary.boundary_loops === 0);
  s = await page.evaluate(() => window.quadlay.summary);
  t.diagnostic(`repaired: ${s.components.length} component, ${s.boundary_loops} boundary loops, repairs ${JSON.stringify(s.repairs)}`);
  assert.equal(s.components.length, 1);
  assert.equal(s.genus, 0);
  assert.deepEqual(await page.evaluate(() => window.quadlay.editor.doc), doc);
  assert.match(await page.locator('#summary-line').textContent(), /closed/);
  await page.screenshot({ path: join(outDir, 'repairs-done.png') });
  await page.close();
});

test('no page errors, console errors or failed requests', () => {
  assert.deepEqual(problems, []);
});
