// What every end-to-end test file needs: the page's server, headless Debian Chromium, pages
// that record what goes wrong in them (uncaught errors, console errors, failed requests), and
// a wait on `window.quadlay` that says where the page stood when it times out.
// Screenshots go to test-output/e2e/.
import { mkdirSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';
import { startServer } from '../../scripts/serve.mjs';

export const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
export const outDir = join(root, 'test-output', 'e2e');

const QUIET = ['--no-sandbox', '--disable-quic', '--no-first-run', '--disable-background-networking',
  '--disable-component-update', '--disable-sync'];

/**
 * Starts the server and the browser.
 * `gpu: true` runs GL through SwiftShader in the GPU process and composites there, as a
 * browser with a GPU does. (With --disable-gpu the compositor reads every WebGL frame back on
 * the page's thread, which blocks it for as long as the software rasterizer takes to draw
 * the frame: most of a second for the 60k-triangle bunny on a 2-core machine.)
 */
export async function startBrowser({ gpu = false } = {}) {
  mkdirSync(outDir, { recursive: true });
  const { server, url: baseUrl } = await startServer(0);
  const browser = await chromium.launch({
    executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
    headless: true,
    args: [...QUIET, ...(gpu ? ['--use-angle=swiftshader', '--enable-unsafe-swiftshader'] : ['--disable-gpu'])],
  });
  /** Everything that went wrong in the pages. */
  const problems = [];

  /** A fresh page (in its own context) that reports its problems into `problems`. */
  async function newPage({ timeout = 20_000 } = {}) {
    const context = await browser.newContext({ viewport: { width: 1280, height: 800 }, deviceScaleFactor: 1, acceptDownloads: true });
    const page = await context.newPage();
    page.setDefaultTimeout(timeout);
    page.on('pageerror', (err) => problems.push(`page error: ${err.message}`));
    page.on('console', (msg) => {
      if (msg.type() === 'error') problems.push(`console error: ${msg.text()}`);
    });
    page.on('requestfailed', (req) => problems.push(`request failed: ${req.url()} ${req.failure()?.errorText}`));
    page.on('response', (res) => {
      if (res.status() >= 400) problems.push(`HTTP ${res.status()}: ${res.url()}`);
    });
    return page;
  }

  /**
   * Waits until `predicate(window.quadlay)` holds in `page`; on timeout says where the page
   * stood: its state, error, and `also(window.quadlay)` when given.
   */
  async function waitFor(page, predicate, { timeout, also } = {}) {
    try {
      await page.waitForFunction(`window.quadlay && (${predicate})(window.quadlay)`, null, timeout ? { timeout } : {});
    } catch (err) {
      const q = await page.evaluate((extra) => {
        const quadlay = window.quadlay;
        const more = extra ? new Function('q', `return (${extra})(q)`)(quadlay) : undefined;
        return { state: quadlay?.state, error: quadlay?.error, more };
      }, also?.toString());
      throw new Error(`${err.message}\nwindow.quadlay: ${JSON.stringify(q)}\nproblems: ${problems.join('\n')}`);
    }
  }

  async function close() {
    await browser.close();
    server.closeAllConnections();
    await new Promise((ok) => server.close(ok));
  }

  return { browser, baseUrl, problems, newPage, waitFor, close };
}
