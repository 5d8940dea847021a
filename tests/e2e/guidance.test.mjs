// Guidance on a plain layout (issue 20, part 3): the bunny in a cube holds far more curvature
// in some faces than a flat chart can take. The Layout card's Faces row says how many need a node; "Show" turns the view to where a node would help (the place may be on the far
// side), its "add a node here" marker appears there, and one click on it makes the node —
// an ordinary edit that Ctrl+Z takes back.
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import { outDir, startBrowser } from './harness.mjs';

const TIMEOUT = 90_000;
let harness;

before(async () => {
  harness = await startBrowser();
});

after(async () => {
  await harness?.close();
});

const settled = (page) => page.evaluate(async () => {
  await window.quadlay.editor.settled();
  await new Promise((ok) => requestAnimationFrame(() => requestAnimationFrame(ok)));
});

test('a face that holds too much curvature is listed; Show turns to its suggestion, one click makes the node', async (t) => {
  const page = await harness.newPage({ timeout: TIMEOUT });
  await page.goto(`${harness.baseUrl}?mesh=samples/bunny_28k.obj&layout=layouts/bunny-cube.layout.json`);
  await page.waitForFunction(() => window.quadlay?.state === 'ready' && window.quadlay.editor?.summary && !window.quadlay.editor.checking);
  await settled(page);
  const guidance = await page.evaluate(() => window.quadlay.editor.guidance);
  const needy = guidance.filter((g) => g.needs_node && g.suggestion);
  t.diagnostic(needy.map((g) => `face ${g.face}: ${g.curvature_deg.toFixed(0)}°`).join(', '));
  assert.ok(needy.length >= 1, 'bunny-cube has no face that needs a node');
  // Every listed face holds more than 45° (an irregular vertex holds ±90°).
  assert.ok(needy.every((g) => Math.abs(g.curvature_deg) > 45));

  // The Faces row says how many need a node; Show turns to the most curved one first.
  const row = page.locator('#layout-summary dd[data-key="faces"]');
  assert.match(await row.textContent(), new RegExp(`⚠ ${needy.length}\\b`));
  assert.match(await row.locator('[data-key="needs-node"]').getAttribute('title'), new RegExp(`^${needy.length} of the faces needs? a node`));
  const face = needy.sort((a, b) => Math.abs(b.curvature_deg) - Math.abs(a.curvature_deg))[0].face;
  await row.locator('.guide-show').click();
  const marker = page.locator(`.guide-marker[data-face="${face}"]`);
  await marker.waitFor();
  await page.screenshot({ path: join(outDir, 'guidance-shown.png') });
  const nodes = (await page.evaluate(() => window.quadlay.editor.doc.nodes)).length;
  await marker.click();
  await settled(page);
  const doc = await page.evaluate(() => window.quadlay.editor.doc);
  const suggested = guidance.find((g) => g.face === face).suggestion.vertex;
  assert.deepEqual(doc.nodes.at(-1), { vertex: suggested });
  await page.keyboard.press('Control+z');
  await settled(page);
  assert.equal((await page.evaluate(() => window.quadlay.editor.doc.nodes)).length, nodes);
  assert.deepEqual(harness.problems, []);
  await page.close();
});
