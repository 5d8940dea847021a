// The rough edges a new user hit (issue 20, part 4), in headless Chromium: the first paint
// says the sample layout is being placed (not "No layout yet"); the default view keeps the
// mesh clear of the tool palette and the Solve button is on screen in a 900-pixel-high
// window; a click a few pixels inside the rim snaps to the rim; a dragged node takes its
// curves along in one undoable edit; after restoring an autosaved layout Ctrl+Z takes back
// the last edit only; options from a link stay when another mesh is loaded; and
// `window.quadlay.result` is set once per run, complete. Screenshots: test-output/e2e/fixes-*.png.
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import { outDir, startBrowser } from './harness.mjs';
import { mushroom } from './mushroom.mjs';

const TIMEOUT = 30_000;
const M = mushroom();
let harness, baseUrl, problems;

before(async () => {
  harness = await startBrowser();
  ({ baseUrl, problems } = harness);
});

after(async () => {
  await harness?.close();
});

const editor = (page, fn, arg) => page.evaluate(([f, a]) => new Function('ed', 'arg', `return (${f})(ed, arg)`)(window.quadlay.editor, a), [fn.toString(), arg]);
const settled = (page) => page.evaluate(async () => {
  await window.quadlay.editor.settled();
  await new Promise((ok) => requestAnimationFrame(() => requestAnimationFrame(ok)));
});

test('the first paint says the sample layout is coming; the view and the Solve card fit a 1280×900 window', async (t) => {
  const page = await harness.newPage({ timeout: TIMEOUT });
  await page.setViewportSize({ width: 1280, height: 900 });
  // Every text the check line shows, from the first paint on.
  await page.addInitScript(() => {
    window.__checks = [];
    new MutationObserver(() => {
      const el = document.getElementById('layout-check');
      if (el && window.__checks.at(-1) !== el.textContent) window.__checks.push(el.textContent);
    }).observe(document, { subtree: true, childList: true, characterData: true });
  });
  await page.goto(baseUrl);
  await harness.waitFor(page, (q) => q.state === 'ready' && q.layout);
  await settled(page);
  const checks = (await page.evaluate(() => window.__checks)).filter(Boolean);
  t.diagnostic(`check line: ${checks.join(' → ')}`);
  assert.ok(!checks.some((c) => /No layout yet/.test(c)), checks.join(' | '));
  assert.match(checks[0], /^Placing .*\.layout\.json…$/);
  assert.match(checks.at(-1), /^Valid layout/);

  await page.screenshot({ path: join(outDir, 'fixes-default-view.png') });
  // No vertex of the mesh is drawn under the tool palette or the status lines.
  const covered = await page.evaluate(() => {
    const ed = window.quadlay.editor;
    const boxes = ['.editor-bar', '.editor-status'].map((s) => document.querySelector(s).getBoundingClientRect());
    const n = window.quadlay.summary.vertices;
    let under = 0, seen = 0;
    for (let v = 0; v < n; v += 7) {
      const s = ed.screenOf(v);
      if (!s) continue;
      seen++;
      if (boxes.some((b) => s.x >= b.left && s.x <= b.right && s.y >= b.top && s.y <= b.bottom)) under++;
    }
    return { under, seen };
  });
  t.diagnostic(`vertices under the palette or status: ${covered.under} of ${covered.seen}`);
  assert.ok(covered.seen > 500);
  assert.equal(covered.under, 0);
  // The Solve button is in the window, above the status line, without scrolling the panel.
  const run = await page.locator('#solve-run').boundingBox();
  const status = await page.locator('#status').boundingBox();
  assert.ok(run && run.y + run.height <= status.y, `Solve is at y = ${run?.y}, the status line at ${status.y}`);
  assert.equal(await page.locator('.panel').evaluate((el) => el.scrollTop), 0);
  await page.close();
});

test('a click a few pixels inside the rim puts the node on the rim', async (t) => {
  const page = await harness.newPage({ timeout: TIMEOUT });
  await page.goto(`${baseUrl}?mesh=samples/mushroom.obj&view=0.2,0.3,-1`);
  await harness.waitFor(page, (q) => q.state === 'ready');
  await page.keyboard.press('n');
  // For every rim vertex: a pixel 6 px from it towards the middle of the mesh (for a few of
  // them the hit triangle's nearest corner there is an interior vertex: 4 of 64 here).
  const tries = await editor(page, (ed, rim) => {
    const out = [];
    const centre = ed.screenOf(rim.centre);
    for (const v of rim.vertices) {
      const s = ed.screenOf(v);
      if (!s) continue;
      const dx = centre.x - s.x, dy = centre.y - s.y, l = Math.hypot(dx, dy);
      const p = { x: s.x + (6 * dx) / l, y: s.y + (6 * dy) / l };
      out.push({ v, p, snapped: ed.vertexAt(p.x, p.y) });
    }
    return out;
  }, { vertices: [...M.boundary], centre: M.top });
  const onMesh = tries.filter((r) => r.snapped >= 0);
  const onRim = onMesh.filter((r) => M.boundary.has(r.snapped));
  t.diagnostic(`${onRim.length} of ${onMesh.length} clicks 6 px inside the rim snap to the rim`);
  assert.ok(onMesh.length >= 10);
  assert.equal(onRim.length, onMesh.length, JSON.stringify(onMesh.filter((r) => !M.boundary.has(r.snapped)).slice(0, 3)));
  // A real click there adds a node on the rim.
  const { p } = onMesh[0];
  await page.mouse.click(p.x, p.y);
  await settled(page);
  const node = (await editor(page, (ed) => ed.doc)).nodes[0];
  assert.ok(M.boundary.has(node.vertex), JSON.stringify(node));
  // Well inside, it snaps to the nearest vertex as before (not to the rim).
  const inside = await editor(page, (ed, top) => { const s = ed.screenOf(top); return ed.vertexAt(s.x, s.y); }, M.top);
  assert.equal(inside, M.top);
  await page.close();
});

/** The mushroom with its four rim corners, its top and edges from two corners to the top. */
async function twoFaces(page) {
  const doc = {
    format: 'quad-layout',
    version: 1,
    nodes: [...M.corners, M.top].map((vertex) => ({ vertex })),
    edges: [{ nodes: [0, 4] }, { nodes: [4, 2] }],
  };
  await editor(page, (ed, d) => ed.setDoc(d), doc);
  await settled(page);
  assert.equal(await editor(page, (ed) => ed.summary?.faces), 2);
  return doc;
}

test('a node dragged to another vertex takes its curves along, in one undoable edit', async (t) => {
  const page = await harness.newPage({ timeout: TIMEOUT });
  await page.goto(`${baseUrl}?mesh=samples/mushroom.obj&view=0.2,0.3,-1`);
  await harness.waitFor(page, (q) => q.state === 'ready');
  const before = await twoFaces(page);
  await page.keyboard.press('n');
  const from = await editor(page, (ed, v) => ed.screenOf(v), M.top);
  await page.mouse.move(from.x, from.y);
  await page.waitForFunction(() => /Drag: move nodes\[4\]/.test(document.getElementById('layout-hint').textContent));
  await page.mouse.down();
  await page.mouse.move(from.x + 25, from.y + 10, { steps: 4 });
  await page.mouse.move(from.x + 50, from.y + 20, { steps: 4 });
  await page.waitForTimeout(400); // the core traces the curves to the new place meanwhile
  await page.screenshot({ path: join(outDir, 'fixes-node-dragging.png') });
  const target = await editor(page, (ed, p) => ed.vertexAt(p.x, p.y), { x: from.x + 50, y: from.y + 20 });
  await page.mouse.up();
  await settled(page);
  const moved = await editor(page, (ed) => ed.doc);
  t.diagnostic(`nodes[4]: vertex ${M.top} → ${moved.nodes[4].vertex}`);
  assert.equal(moved.nodes[4].vertex, target);
  assert.notEqual(target, M.top);
  assert.deepEqual(moved.edges, before.edges);
  assert.equal(await editor(page, (ed) => ed.error), null);
  // The curves end at the new place.
  const ends = await editor(page, (ed) => [0, 1].map((i) => { const p = ed.edgePoints(i); return [p[0], p.at(-1)]; }));
  const at = M.v[target];
  const near = (p) => Math.hypot(p[0] - at[0], p[1] - at[1], p[2] - at[2]) < 1e-4;
  assert.ok(ends.every(([a, b]) => near(a) || near(b)), JSON.stringify(ends));
  await page.screenshot({ path: join(outDir, 'fixes-node-moved.png') });
  // One edit: one undo brings the node back.
  await page.keyboard.press('Control+z');
  await settled(page);
  assert.deepEqual(await editor(page, (ed) => ed.doc), before);
  await page.close();
});

test('after restoring an autosaved layout, Ctrl+Z takes back the last edit, not the layout', async () => {
  const page = await harness.newPage({ timeout: TIMEOUT });
  await page.goto(`${baseUrl}?mesh=samples/mushroom.obj&view=0.2,0.3,-1`);
  await harness.waitFor(page, (q) => q.state === 'ready');
  const doc = await twoFaces(page);
  const tagged = structuredClone(doc);
  tagged.edges[0].align = true;
  await editor(page, (ed, d) => ed.setDoc(d), tagged);
  await settled(page);
  await page.reload();
  await harness.waitFor(page, (q) => q.state === 'ready' && q.editor.offer);
  await page.click('#restore-yes');
  await settled(page);
  assert.deepEqual(await editor(page, (ed) => ed.doc), tagged);
  await page.keyboard.press('Control+z');
  await settled(page);
  assert.deepEqual(await editor(page, (ed) => ed.doc), doc, 'the first undo took more than the last edit');
  assert.equal(await editor(page, (ed) => ed.summary?.faces), 2);
  await page.keyboard.press('Control+Shift+z');
  await settled(page);
  assert.deepEqual(await editor(page, (ed) => ed.doc), tagged);
  await page.close();
});

test('options from a link stay when another mesh is loaded', async () => {
  const page = await harness.newPage({ timeout: TIMEOUT });
  await page.goto(`${baseUrl}?mesh=samples/mushroom.obj&layout=layouts/mushroom-grid.layout.json&chart=rect&iterations=2&quads=900`);
  await harness.waitFor(page, (q) => q.state === 'ready' && q.layout);
  await page.waitForFunction(() => document.getElementById('opt-chart').value === 'rect');
  await page.click('.sample[data-file="fandisk.obj"]');
  await harness.waitFor(page, (q) => q.state === 'ready' && q.name === 'fandisk.obj' && q.layout);
  assert.equal(await page.locator('#opt-chart').inputValue(), 'rect');
  assert.equal(await page.locator('#opt-iterations').inputValue(), '2');
  assert.equal(await page.locator('#opt-quads').inputValue(), '900');
  await page.close();
});

test('window.quadlay.result is set once per run, when the run is complete', async (t) => {
  const page = await harness.newPage({ timeout: 90_000 });
  await page.goto(`${baseUrl}?mesh=samples/mushroom.obj&layout=layouts/mushroom-grid.layout.json`);
  await harness.waitFor(page, (q) => q.state === 'ready' && q.layout);
  // Every value given to `result` from here on.
  await page.evaluate(() => {
    let value = window.quadlay.result;
    window.__results = [];
    Object.defineProperty(window.quadlay, 'result', {
      get: () => value,
      set: (v) => { value = v; window.__results.push(v === null ? null : v.quads ? 'complete' : 'partial'); },
    });
  });
  await page.click('#solve-run');
  await harness.waitFor(page, (q) => q.solve.state === 'done' || q.solve.state === 'error', { timeout: 90_000 });
  const seen = await page.evaluate(() => window.__results);
  t.diagnostic(`result was set to: ${seen.join(', ')}`);
  assert.deepEqual(seen.filter((v) => v !== null), ['complete']);
  assert.equal(seen.at(-1), 'complete');
  const partial = await page.evaluate(() => window.quadlay.paramReport);
  assert.equal(partial.quads, null);
  assert.ok(partial.parameterization.distortion_mean > 0);
  await page.close();
});

test('no page errors, console errors or failed requests', () => {
  assert.deepEqual(problems, []);
});
