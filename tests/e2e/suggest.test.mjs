// The automatic layout on the page, in headless Chromium: Suggest layout places a proposal
// into the editor as one edit that the page says is valid, Ctrl+Z brings the previous
// layout back, the field view draws the crosses and the singularities with their legend,
// Cancel leaves the layout as it was, and a mesh the core cannot lay out gets the reason in
// words. Screenshots go to test-output/e2e/ (suggest-*.png).
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import { tetrahedra } from '../fixtures/tetrahedra.mjs';
import { outDir, startBrowser } from './harness.mjs';

const TIMEOUT = 60_000;
let harness, baseUrl, problems;

before(async () => {
  harness = await startBrowser({ gpu: true });
  ({ baseUrl, problems } = harness);
});

after(async () => {
  await harness?.close();
});

const waitFor = (page, predicate, timeout = TIMEOUT) =>
  harness.waitFor(page, predicate, { timeout, also: (q) => ({ suggestion: q?.suggestion, editor: q?.editor?.error }) });

/** Opens the page on a mesh (and a layout, when the query names one). */
async function open(page, query) {
  await page.goto(baseUrl + query);
  if (query.includes('layout=')) await waitFor(page, (q) => (q.state === 'ready' && q.layout) || q.state === 'error');
  else await waitFor(page, (q) => q.state === 'ready' || q.state === 'error');
  assert.equal(await page.evaluate(() => window.quadlay.state), 'ready', await page.evaluate(() => window.quadlay.error));
}

test('Suggest layout places a valid layout as one edit; Ctrl+Z restores the previous one', async () => {
  const page = await harness.newPage({ timeout: TIMEOUT });
  await open(page, '?mesh=samples/mushroom.obj&layout=layouts/mushroom-grid.layout.json&view=1,0.6,0.8');
  const before = await page.evaluate(() => window.quadlay.editor.doc);
  await page.locator('#suggest-card').scrollIntoViewIfNeeded();
  assert.equal(await page.locator('#opt-feature-angle').inputValue(), '35');
  await page.click('#suggest-run');
  await waitFor(page, (q) => q.suggestion.state === 'done' || q.suggestion.state === 'error');
  const s = await page.evaluate(() => ({ suggestion: window.quadlay.suggestion, summary: window.quadlay.editor.summary, doc: window.quadlay.editor.doc, error: window.quadlay.editor.error }));
  assert.equal(s.suggestion.state, 'done', JSON.stringify(s.suggestion));
  assert.equal(s.error, null);
  assert.equal(s.summary.faces, s.suggestion.faces);
  assert.notDeepEqual(s.doc, before);
  // The page says so, under the view and in the card.
  await page.waitForFunction(() => /^Valid layout: \d+ faces/.test(document.querySelector('.editor-check')?.textContent));
  assert.match(await page.locator('#suggest-message').textContent(), /Suggested \d+ faces.*Ctrl\+Z/);
  // The tracings are made at once, each in a worker of its own, where there is more than one
  // processor.
  const cores = await page.evaluate(() => navigator.hardwareConcurrency);
  assert.equal((await page.evaluate(() => window.quadlay.suggestion)).workers, cores > 1 ? 3 : 1);
  // Every tracing's proposal was made and judged (one request makes them all where there is
  // one processor).
  assert.equal((await page.evaluate(() => window.quadlay.suggestion)).proposals, cores > 1 ? 6 : null);
  await page.screenshot({ path: join(outDir, 'suggest-layout.png') });

  // One edit: Ctrl+Z returns the sample layout, Ctrl+Shift+Z the proposal.
  await page.locator('canvas').first().click({ position: { x: 5, y: 400 } });
  await page.keyboard.press('Control+z');
  await waitFor(page, (q) => !q.editor.checking && q.editor.summary);
  assert.deepEqual(await page.evaluate(() => window.quadlay.editor.doc), before);
  await page.keyboard.press('Control+Shift+z');
  await waitFor(page, (q) => !q.editor.checking && q.editor.summary);
  assert.deepEqual(await page.evaluate(() => window.quadlay.editor.doc), s.doc);

  // Fewer patches than the field allows: the proposal says how far it got.
  const few = await page.evaluate(() => window.quadlay.suggest({ patches: 1 }));
  assert.ok(few.faces > 1);
  assert.match(await page.locator('#suggest-message').textContent(), new RegExp(`Suggested ${few.faces} faces.* s( \\(\\d workers at once\\))?\\. ${few.faces} faces where about 1 were asked: the nearest.*Ctrl\\+Z`));
  await page.evaluate(() => window.quadlay.suggest({ patches: null }));

  // The proposal is an ordinary layout: it solves.
  await page.evaluate(() => window.quadlay.run());
  const result = await page.evaluate(() => window.quadlay.result);
  assert.equal(result.layout.faces, s.summary.faces);
  assert.ok(result.quads.faces > 0);
  assert.deepEqual(problems, []);
  await page.context().close();
});

test('the field view shows the crosses and the singularities by valence, with a legend', async () => {
  const page = await harness.newPage({ timeout: TIMEOUT });
  await open(page, '?mesh=samples/bunny_1k8.obj&view=0,0.3,1');
  await page.click('#field-toggle');
  await waitFor(page, (q) => q.field);
  const field = await page.evaluate(() => window.quadlay.field);
  // A closed genus-0 surface: the indices (4 − valence)/4 add up to 2.
  const { 3: v3, 5: v5 } = field.singularities;
  assert.equal(field.singularities.other, 0, JSON.stringify(field));
  assert.equal(v3 - v5, 8, JSON.stringify(field));
  assert.ok(field.crosses > 500 && field.crosses <= field.vertices);
  assert.equal(await page.locator('#field-toggle').getAttribute('aria-pressed'), 'true');
  const legend = page.locator('#field-legend');
  assert.ok(await legend.isVisible());
  assert.match(await legend.textContent(), new RegExp(`valence 3: ${v3}.*valence 5: ${v5}.*indices sum to χ = 2`));
  await page.screenshot({ path: join(outDir, 'suggest-field.png') });
  // Beside a suggested layout.
  await page.evaluate(() => window.quadlay.suggest());
  await page.screenshot({ path: join(outDir, 'suggest-field-layout.png') });
  await page.click('#field-toggle');
  assert.equal(await legend.isVisible(), false);
  assert.equal(await page.evaluate(() => window.quadlay.field), null);
  assert.deepEqual(problems, []);
  await page.context().close();
});

test('Cancel leaves the layout as it was; a mesh without a layout says why', async () => {
  const page = await harness.newPage({ timeout: TIMEOUT });
  await open(page, '?mesh=samples/bunny_28k.obj&layout=layouts/bunny-cube.layout.json');
  const before = await page.evaluate(() => window.quadlay.editor.doc);
  await page.click('#suggest-run');
  await page.waitForSelector('#suggest-cancel:not([hidden])');
  await page.click('#suggest-cancel');
  await waitFor(page, (q) => q.suggestion.state !== 'running');
  assert.equal(await page.evaluate(() => window.quadlay.suggestion.state), 'cancelled');
  assert.deepEqual(await page.evaluate(() => window.quadlay.editor.doc), before);
  // The restarted worker still has the mesh and the layout: an edit is checked as before.
  await page.evaluate(() => window.quadlay.editor.setDoc(window.quadlay.editor.doc));
  await waitFor(page, (q) => !q.editor.checking);
  assert.ok(await page.evaluate(() => window.quadlay.editor.summary));

  // A thousand tetrahedra, too many triangles to be refined: no face of a layout has a
  // vertex inside.
  await page.evaluate((text) => window.quadlay.load(new File([text], 'tetrahedra.obj')), tetrahedra(1000));
  const err = await page.evaluate(() => window.quadlay.suggest().then(() => null, (e) => e.message));
  assert.match(err, /no valid layout could be made automatically: /);
  assert.match(await page.locator('#suggest-message').textContent(), /^No layout suggested: no valid layout could be made automatically: .+/);
  assert.equal(await page.evaluate(() => window.quadlay.suggestion.state), 'error');
  await page.screenshot({ path: join(outDir, 'suggest-error.png') });
  // The error box is the card's, not a console error.
  assert.deepEqual(problems, []);
  await page.context().close();
});
