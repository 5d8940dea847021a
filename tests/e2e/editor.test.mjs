// The layout editor in headless Chromium, driven by real mouse clicks on the canvas (click
// pixels come from projecting mesh vertices with the page's camera, `quadlay.editor.screenOf`):
// nodes on the mushroom's boundary and top, edges between them, live validation (the core's
// error in words and in red on the mesh), an edge tagged, a T-vertex, a chart type, a bent
// edge, undo/redo, the saved file, the autosave offered again after a reload, a worker
// crash survived, a node deleted with its edges.
// Screenshots of each state go to test-output/e2e/editor-*.png.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { after, before, test } from 'node:test';
import { PNG } from 'pngjs';
import { outDir, startBrowser } from './harness.mjs';
import { mushroom } from './mushroom.mjs';

const TIMEOUT = 20_000;
const PAGE = '?mesh=samples/mushroom.obj&view=0.2,0.3,-1';

let harness, page, baseUrl, problems;

const M = mushroom();

before(async () => {
  harness = await startBrowser();
  ({ baseUrl, problems } = harness);
  page = await harness.newPage({ timeout: TIMEOUT });
});

after(async () => {
  await harness?.close();
});

const waitFor = (predicate) => harness.waitFor(page, predicate, { also: (q) => q?.editor?.error });

const editor = (fn, arg) => page.evaluate(([f, a]) => new Function('ed', 'arg', `return (${f})(ed, arg)`)(window.quadlay.editor, a), [fn.toString(), arg]);
/** Waits until the core has checked the last edit and a frame shows it. */
async function settled() {
  await page.evaluate(async () => {
    await window.quadlay.editor.settled();
    await new Promise((ok) => requestAnimationFrame(() => requestAnimationFrame(ok)));
  });
}
const doc = () => editor((ed) => ed.doc);

/**
 * Clicks mesh vertex `v`: at its projection, or the nearest pixel to it (within 5 px) where
 * a node would snap to `v` (a vertex on the rim has half its surroundings beside the mesh).
 */
async function clickVertex(v) {
  const p = await editor((ed, v) => {
    const s = ed.screenOf(v);
    const tries = [];
    for (let dy = -5; dy <= 5; dy++) for (let dx = -5; dx <= 5; dx++) tries.push([dx, dy]);
    tries.sort((a, b) => Math.hypot(...a) - Math.hypot(...b));
    for (const [dx, dy] of tries) {
      if (ed.vertexAt(s.x + dx, s.y + dy) === v) return { x: s.x + dx, y: s.y + dy };
    }
    return null;
  }, v);
  assert.ok(p, `no pixel near vertex ${v} snaps to it`);
  await page.mouse.click(p.x, p.y);
  await settled();
}

/** A pixel on edge `i` where a click hits that edge: near the middle of its curve if it can. */
async function pixelOnEdge(i) {
  const p = await editor((ed, i) => {
    const pts = ed.edgePoints(i);
    // Its points from the middle outwards (the middle may be hidden behind the surface).
    const order = pts.map((_, k) => k).sort((a, b) => Math.abs(a / (pts.length - 1) - 0.5) - Math.abs(b / (pts.length - 1) - 0.5));
    for (const k of order.filter((k) => k > 0 && k < pts.length - 1)) {
      const s = ed.screenOf(pts[k]);
      const hit = s && ed.pick(s.x, s.y);
      if (hit?.kind === 'edge' && hit.index === i) return s;
    }
    return null;
  }, i);
  assert.ok(p, `no visible pixel on edge ${i}`);
  return p;
}

/** Clicks edge `i`. */
async function clickEdge(i) {
  const p = await pixelOnEdge(i);
  await page.mouse.click(p.x, p.y);
  await settled();
}

async function key(k) {
  await page.keyboard.press(k);
  await settled();
}

/** Screenshot; returns how many pixels of the view are the error red. */
async function shoot(name) {
  const path = join(outDir, `editor-${name}.png`);
  await page.screenshot({ path });
  const png = PNG.sync.read(readFileSync(path));
  const box = await page.locator('#viewport canvas').boundingBox();
  const overlays = await page.$$eval('#viewport > :not(canvas, .editor-status), #viewport .editor-status > *', (els) =>
    els.filter((el) => el.checkVisibility()).map((el) => {
      const r = el.getBoundingClientRect();
      return [r.left, r.top, r.right, r.bottom];
    }));
  let red = 0;
  for (let y = Math.ceil(box.y); y < box.y + box.height; y++) {
    for (let x = Math.ceil(box.x); x < box.x + box.width; x++) {
      if (overlays.some(([l, t, r, b]) => x >= l && x < r && y >= t && y < b)) continue;
      const i = (y * png.width + x) * 4;
      const [r, g, b] = [png.data[i], png.data[i + 1], png.data[i + 2]];
      if (r > 200 && g < 90 && b < 100) red++;
    }
  }
  return { path, red };
}

test('nodes placed by clicks on the mushroom make a valid one-face layout', async (t) => {
  await page.goto(baseUrl + PAGE);
  await waitFor((q) => q.state === 'ready' && q.summary?.vertices === 2337);
  assert.equal(await editor((ed) => ed.offer), null, 'a fresh browser has nothing to restore');
  assert.equal(await editor((ed) => ed.mode), 'view');
  await key('n');
  assert.equal(await editor((ed) => ed.mode), 'node');
  assert.match(await page.locator('#layout-hint').textContent(), /Click the surface to add a node/);

  for (const v of M.corners) await clickVertex(v);
  const d = await doc();
  assert.deepEqual(d.nodes, M.corners.map((vertex) => ({ vertex })));
  assert.equal(await editor((ed) => ed.error), null);
  assert.equal(await editor((ed) => ed.summary?.faces), 1);
  assert.match(await page.locator('#layout-check').textContent(), /Valid layout: 1 face/);
  assert.equal(await page.locator('#layout-summary dd[data-key="faces"]').textContent(), '1');
  const s = await shoot('1-four-nodes');
  t.diagnostic(s.path);
});

test('a lone node and a dangling edge are shown as errors, in words and in red on the mesh', async (t) => {
  await clickVertex(M.top);
  let error = await editor((ed) => ed.error);
  assert.match(error, /^nodes\[4\]: no edge or boundary reaches this node/);
  assert.deepEqual((await editor((ed) => ed.problem)).nodes, [4]);
  assert.match(await page.locator('#layout-check').textContent(), /nodes\[4\]/);
  assert.equal(await page.locator('#layout-check').getAttribute('data-state'), 'error');
  assert.match(await page.locator('#layout-problem').textContent(), /nodes\[4\]/);
  let s = await shoot('2-lone-node');
  assert.ok(s.red > 30, `no red highlight on the mesh (${s.red} red pixels, ${s.path})`);

  // Edge mode: corner 0 → top dangles.
  await key('e');
  await clickVertex(M.corners[0]);
  assert.equal(await editor((ed) => ed.pending), 0);
  await clickVertex(M.top);
  assert.deepEqual((await doc()).edges, [{ nodes: [0, 4] }]);
  error = await editor((ed) => ed.error);
  assert.match(error, /^edges\[0\]: the same face lies on both sides/);
  assert.deepEqual((await editor((ed) => ed.problem)).edges, [0]);
  s = await shoot('3-dangling-edge');
  t.diagnostic(`${s.path}: ${s.red} red pixels`);
  assert.ok(s.red > 100, `the dangling edge is not red (${s.red} red pixels, ${s.path})`);
});

test('connecting the top to the opposite corner makes two faces', async (t) => {
  // The chain goes on from the top (pending after the last edge).
  assert.equal(await editor((ed) => ed.pending), 4);
  await clickVertex(M.corners[2]);
  const d = await doc();
  assert.deepEqual(d.edges, [{ nodes: [0, 4] }, { nodes: [4, 2] }]);
  assert.equal(await editor((ed) => ed.error), null);
  assert.equal(await editor((ed) => ed.summary.faces), 2);
  await key('Escape');
  assert.equal(await editor((ed) => ed.pending), null);
  const s = await shoot('4-two-faces');
  assert.equal(s.red, 0, `red pixels on a valid layout (${s.path})`);
  t.diagnostic(s.path);
});

test('tagging an edge for alignment, undo and redo', async () => {
  await key('a');
  await clickEdge(0);
  assert.equal((await doc()).edges[0].align, true);
  assert.equal(await editor((ed) => ed.summary.aligned_edges), 1);
  await shoot('5-tagged');

  await key('Control+z');
  assert.equal((await doc()).edges[0].align, undefined);
  assert.equal(await editor((ed) => ed.summary.aligned_edges), 0);
  await key('Control+Shift+z');
  assert.equal((await doc()).edges[0].align, true);
  await key('Control+z');
  await key('Control+y');
  assert.equal((await doc()).edges[0].align, true);
  // The buttons do the same.
  await page.click('#layout-undo');
  await settled();
  assert.equal((await doc()).edges[0].align, undefined);
  await page.click('#layout-redo');
  await settled();
  assert.equal((await doc()).edges[0].align, true);
  assert.equal(await editor((ed) => ed.summary.aligned_edges), 1);
  // Edits faster than the core: only the last document counts, and its check is shown.
  await editor((ed) => { ed.undo(); ed.undo(); ed.undo(); ed.redo(); ed.redo(); ed.redo(); });
  await settled();
  assert.equal((await doc()).edges[0].align, true);
  assert.equal(await editor((ed) => ed.summary?.aligned_edges), 1);
  assert.equal(await editor((ed) => ed.error), null);
});

test('a node dropped on an edge splits it at a T-vertex', async () => {
  await key('n');
  const over = await pixelOnEdge(1);
  await page.mouse.move(over.x, over.y);
  await page.waitForFunction(() => /split edges\[1\]/.test(document.getElementById('layout-hint').textContent));
  await clickEdge(1);
  const d = await doc();
  assert.equal(d.nodes.length, 6);
  assert.deepEqual(d.edges.map((e) => e.nodes), [[0, 4], [4, 5], [5, 2]]);
  assert.equal(await editor((ed) => ed.error), null);
  const summary = await editor((ed) => ed.summary);
  assert.equal(summary.faces, 2);
  assert.ok(summary.t_vertices >= 1, `no T-vertex: ${JSON.stringify(summary)}`);
  await shoot('6-t-vertex');
});

test('crossing curves are named and drawn red; undo takes the edge back', async (t) => {
  await key('e');
  await clickVertex(M.corners[1]);
  await clickVertex(M.corners[3]);
  const error = await editor((ed) => ed.error);
  assert.ok(error, 'an edge across the others is accepted');
  t.diagnostic(error);
  const problem = await editor((ed) => ed.problem);
  assert.ok(problem.edges.length + problem.nodes.length > 0, `nothing highlighted for: ${error}`);
  assert.equal(await page.locator('#layout-check').textContent(), error);
  const s = await shoot('7-crossing');
  assert.ok(s.red > 100, `the crossing is not red (${s.red} red pixels, ${s.path})`);
  await key('Escape');
  await key('Control+z');
  assert.equal((await doc()).edges.length, 3);
  assert.equal(await editor((ed) => ed.error), null);
});

test('a face gets a rect chart; an edge bends through a dragged waypoint', async () => {
  await key('c');
  // A pixel on face 0, between its first corner and the middle of the view.
  const p = await editor((ed) => {
    const corners = ed.summary.face_list[0].corners.map((n) => ed.screenOf(ed.nodeVertices[n]));
    const c = corners.reduce((a, b) => ({ x: a.x + b.x / 4, y: a.y + b.y / 4 }), { x: 0, y: 0 });
    for (const s of [0.5, 0.4, 0.6, 0.3, 0.7, 0.2, 0.8]) {
      for (const k of [0, 1, 2, 3]) {
        const q = { x: corners[k].x + (c.x - corners[k].x) * s, y: corners[k].y + (c.y - corners[k].y) * s };
        if (ed.faceAt(q.x, q.y) === 0 && ed.pick(q.x, q.y)?.kind === 'surface') return q;
      }
    }
    return null;
  });
  assert.ok(p, 'no pixel on face 0');
  await page.mouse.click(p.x, p.y);
  await settled();
  const d = await doc();
  assert.equal(d.patches?.length, 1, JSON.stringify(d.patches));
  assert.equal(d.patches[0].chart, 'rect');
  assert.equal(await editor((ed) => ed.summary.charts[1]), 1);
  assert.ok(await page.locator('.chart-label.chart-rect').count() >= 1, 'no rect label on the face');
  await shoot('8-chart');

  await key('b');
  const from = await pixelOnEdge(0);
  await page.mouse.move(from.x, from.y);
  await page.mouse.down();
  await page.mouse.move(from.x + 20, from.y - 10, { steps: 5 });
  await page.mouse.move(from.x + 40, from.y - 25, { steps: 5 });
  // While dragging, the core's curve through the waypoint follows the pointer.
  await page.waitForFunction(() => !window.quadlay.editor.checking);
  await page.waitForTimeout(300);
  await shoot('9-bending');
  await page.mouse.up();
  await settled();
  const bent = await doc();
  assert.equal(bent.edges[0].via?.length, 1, JSON.stringify(bent.edges[0]));
  assert.equal(await editor((ed) => ed.error), null, 'the bent edge broke the layout');
  await shoot('9-bent');
});

let saved;
test('the layout is saved as NAME.layout.json, format v1', async () => {
  const [download] = await Promise.all([page.waitForEvent('download'), page.click('#layout-save')]);
  assert.equal(download.suggestedFilename(), 'mushroom.layout.json');
  const text = readFileSync(await download.path(), 'utf8');
  const file = JSON.parse(text);
  assert.equal(file.format, 'quad-layout');
  assert.equal(file.version, 1);
  // The file also names the mesh it was drawn on (layout-format.md, `mesh`); the rest is
  // the document as drawn.
  const { mesh, ...drawn } = file;
  assert.deepEqual(mesh, { vertices: 2337, triangles: 4608 });
  saved = drawn;
  assert.deepEqual(saved, await doc());
  assert.equal(saved.nodes.length, 6);
  assert.equal(saved.edges.length, 3);
  assert.equal(saved.edges[0].align, true);
  assert.equal(saved.patches[0].chart, 'rect');
});

test('after a reload the autosaved layout is offered and restored', async (t) => {
  await page.reload();
  await waitFor((q) => q.state === 'ready' && q.summary?.vertices === 2337);
  const offer = page.locator('#restore-offer');
  assert.ok(await offer.isVisible(), 'no restore offer after a reload');
  assert.match(await offer.textContent(), /Restore your layout from \d\d:\d\d\?/);
  const s = await shoot('10-offer');
  t.diagnostic(s.path);
  await page.click('#restore-yes');
  await settled();
  assert.equal(await offer.isVisible(), false);
  assert.deepEqual(await doc(), saved);
  assert.equal(await editor((ed) => ed.error), null);
  assert.equal(await editor((ed) => ed.summary.faces), 2);
  await shoot('11-restored');
});

test('a crashed worker loses nothing: the mesh is loaded again and the layout placed', async () => {
  await editor((ed) => ed.stopCore());
  await key('a');
  await clickEdge(1);
  await waitFor((q) => !q.editor.checking && q.editor.summary && q.editor.doc.edges[1].align);
  assert.equal(await editor((ed) => ed.error), null);
  assert.equal(await editor((ed) => ed.summary.aligned_edges), 2);
  await key('Control+z');
  assert.deepEqual(await doc(), saved);
  assert.equal(await editor((ed) => ed.summary.aligned_edges), 1);

  // A restart while an edit is being checked (a crash, a cancelled solve): checked again.
  await editor((ed) => { ed.redo(); ed.restartCore(); });
  await waitFor((q) => !q.editor.checking);
  assert.equal(await editor((ed) => ed.error), null);
  assert.equal(await editor((ed) => ed.summary.aligned_edges), 2);
  await key('Control+z');
  assert.equal(await editor((ed) => ed.summary.aligned_edges), 1);
});

test('deleting a node takes its edges with it', async () => {
  await key('d');
  const at = await editor((ed) => ed.screenOf(ed.nodeVertices[4]));
  await page.mouse.click(at.x, at.y);
  await settled();
  const d = await doc();
  assert.equal(d.nodes.length, 5);
  assert.deepEqual(d.edges.map((e) => e.nodes), [[4, 2]]);
  await key('Control+z');
  assert.deepEqual(await doc(), saved);
});

test('no page errors, console errors or failed requests', () => {
  assert.deepEqual(problems, []);
});
