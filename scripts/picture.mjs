// Renders a mesh with a layout to a PNG through the page in headless Chromium:
//   node scripts/picture.mjs MESH_URL LAYOUT_URL OUT.png [x,y,z ...]
// URLs are relative to www/ (e.g. samples/fandisk.obj layouts/fandisk-cube.layout.json).
// With several view directions, OUT.png gets one picture per view, side by side is left to
// the viewer: files are named OUT-1.png, OUT-2.png, ...
import { chromium } from 'playwright-core';
import { startServer } from './serve.mjs';

const [mesh, layout, out, ...views] = process.argv.slice(2);
if (!out) {
  console.error('usage: node scripts/picture.mjs MESH_URL LAYOUT_URL OUT.png [x,y,z ...]');
  process.exit(2);
}
const { server, url } = await startServer(0);
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
    '--disable-background-networking', '--disable-component-update', '--disable-sync'],
});
try {
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  const list = views.length ? views : [null];
  for (const [i, v] of list.entries()) {
    const q = new URLSearchParams({ mesh, layout });
    if (v) q.set('view', v);
    await page.goto(`${url}?${q}`);
    await page.waitForFunction(() => window.quadlay?.layout || window.quadlay?.state === 'error', null, { timeout: 60000 });
    const q2 = await page.evaluate(() => ({ error: window.quadlay.error, layout: window.quadlay.layout }));
    if (q2.error) console.error(`error: ${q2.error}`);
    const file = list.length > 1 ? out.replace(/\.png$/, `-${i + 1}.png`) : out;
    await page.screenshot({ path: file });
    console.log(`${file}: ${q2.layout ? `${q2.layout.faces} faces` : 'no layout'}`);
  }
} finally {
  await browser.close();
  server.close();
}
