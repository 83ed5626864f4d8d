// Shared set-up of the browser tests and the web benchmark: the dev server on a free port of its
// own (with a private dependency cache and no file watching), Debian's Chromium through
// playwright-core with a fresh profile, and small page helpers. Everything is bounded in time.
import { existsSync, mkdirSync, mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { chromium } from 'playwright-core';
import { startServer, root } from '../../scripts/serve.mjs';

export { root };
export const CHROMIUM = process.env.MRVOL_CHROMIUM ?? '/usr/bin/chromium';
export const RESULTS_DIR = join(root, 'test-results');

// The flags that work headless on these machines (shared/docs/toolchain.md): WebGL2 on SwiftShader.
const CHROMIUM_ARGS = [
  '--headless=new', '--no-sandbox', '--disable-gpu', '--enable-unsafe-swiftshader',
  '--disable-background-networking', '--disable-component-update', '--disable-sync', '--no-first-run',
];

/**
 * The server on a free port, with a private dependency cache (and, for mode 'preview', a private
 * build folder). close() stops it.
 */
export async function startTestServer({ mode = 'dev' } = {}) {
  const scratch = mkdtempSync(join(tmpdir(), 'mrvol-server-'));
  const server = await startServer({
    port: 0, watch: false, logLevel: 'warn', cacheDir: join(scratch, 'vite-cache'), mode, outDir: join(scratch, 'dist'),
  });
  return {
    url: server.url,
    async close() {
      await server.close().catch(() => {});
      rmSync(scratch, { recursive: true, force: true });
    },
  };
}

/** vite's dev server on examples/web/vite.config.mjs, on a free port with a private cache. */
export async function startExampleServer() {
  const { createServer } = await import('vite');
  const scratch = mkdtempSync(join(tmpdir(), 'mrvol-example-'));
  const server = await createServer({
    configFile: join(root, 'examples/web/vite.config.mjs'),
    logLevel: 'warn',
    clearScreen: false,
    cacheDir: join(scratch, 'vite-cache'),
    server: { port: 0, strictPort: false, watch: null, hmr: false },
  });
  await server.listen();
  const { address, port } = server.httpServer.address();
  return {
    url: `http://${address}:${port}/`,
    async close() {
      await server.close().catch(() => {});
      rmSync(scratch, { recursive: true, force: true });
    },
  };
}

/**
 * A browser with a fresh profile (IndexedDB and localStorage of its own, kept across reloads and
 * pages of this context) on a server's url; `touch`: a touch screen. close() stops it and removes the profile.
 */
export async function launchBrowser(url, { viewport = { width: 1200, height: 800 }, touch = false } = {}) {
  if (!existsSync(CHROMIUM)) throw new Error(`${CHROMIUM} is missing: apt-get install -y chromium (npm test does it)`);
  const profile = mkdtempSync(join(tmpdir(), 'mrvol-profile-'));
  let context;
  try {
    context = await chromium.launchPersistentContext(profile, {
      executablePath: CHROMIUM,
      headless: true,
      args: CHROMIUM_ARGS,
      viewport,
      hasTouch: touch,  // a touch screen: (pointer: coarse) matches, as on a phone
      acceptDownloads: true,
      timeout: 60_000,
    });
  } catch (e) {
    rmSync(profile, { recursive: true, force: true });
    throw e;
  }
  context.setDefaultTimeout(60_000);
  mkdirSync(RESULTS_DIR, { recursive: true });
  return {
    url,
    context,
    async newPage() {
      const page = context.pages().find((p) => p.url() === 'about:blank') ?? await context.newPage();
      const problems = [];
      page.on('pageerror', (e) => problems.push(`pageerror: ${e.message}`));
      page.on('console', (m) => {
        if (m.type() === 'error') problems.push(`console: ${m.text()}`);
      });
      page.problems = problems;
      return page;
    },
    async close() {
      await context.close().catch(() => {});
      rmSync(profile, { recursive: true, force: true });
    },
  };
}

/** A server and a browser on it; close() stops both. */
export async function launch(options = {}) {
  const server = await startTestServer();
  try {
    const browser = await launchBrowser(server.url, options);
    return {
      ...browser,
      async close() {
        await browser.close();
        await server.close();
      },
    };
  } catch (e) {
    await server.close();
    throw e;
  }
}

/**
 * A server, a browser on it and a page: at the app (`goto`, default true) and ready to drag
 * (`ready`, default true). For a describe()'s hooks:
 *   before(async () => ({ browser, page } = await openApp()));
 *   after(() => browser?.close());
 */
export async function openApp({ goto = true, ready = true, ...options } = {}) {
  const browser = await launch(options);
  try {
    const page = await browser.newPage();
    if (goto) await page.goto(browser.url);
    if (goto && ready) await waitReady(page);
    return { browser, page };
  } catch (e) {
    await browser.close();
    throw e;
  }
}

/** Waits until the model is loaded and the first frame is drawn (handles can be dragged). */
export async function waitReady(page, timeout = 60_000) {
  await page.waitForFunction(() => window.mrvolDebug?.ready() === true, null, { timeout });
}

/** Waits until drag steps run on their fast path (the cage polynomial, or theta in use). */
export async function waitGradient(page, timeout = 90_000) {
  await page.waitForFunction(() => window.mrvolDebug?.gradientReady() === true, null, { timeout });
}

export async function waitTheta(page, timeout = 90_000) {
  await page.waitForFunction(() => window.mrvolDebug?.thetaReady() === true, null, { timeout });
}

/** Readout values by data-testid (full precision from data-value where the page gives it). */
export async function readouts(page) {
  return page.evaluate(() => {
    const get = (id) => document.querySelector(`[data-testid="${id}"]`);
    const num = (id) => Number(get(id).dataset.value ?? get(id).textContent);
    return {
      reference: num('volume-reference'),
      current: num('volume-current'),
      error: num('volume-error'),
      referenceText: get('volume-reference').textContent,
      currentText: get('volume-current').textContent,
      errorText: get('volume-error').textContent,
      thetaSource: get('theta-source').textContent,
      iterations: get('step-iterations').textContent,
      ms: get('step-ms').textContent,
      path: get('step-path').textContent,
    };
  });
}

/**
 * Handle indices whose screen point lands on the canvas (not under the panel or the readouts),
 * with their positions, farthest from the others first.
 */
export async function visibleHandles(page) {
  return page.evaluate(() => {
    const canvas = document.querySelector('#view canvas');
    const points = window.mrvolDebug.cageScreenPositions();
    return points
      .map(([x, y], index) => ({ index, x, y }))
      .filter(({ x, y }) => document.elementFromPoint(x, y) === canvas &&
        document.elementFromPoint(x + 70, y - 40) === canvas && document.elementFromPoint(x - 70, y + 40) === canvas);
  });
}

/** Drags from a handle's screen point by (dx, dy) CSS pixels in `steps` pointer moves. */
export async function dragHandle(page, index, dx, dy, { steps = 12, modifiers = [], before } = {}) {
  const [x, y] = (await page.evaluate(() => window.mrvolDebug.cageScreenPositions()))[index];
  for (const m of modifiers) await page.keyboard.down(m);
  await page.mouse.move(x, y);
  await page.mouse.down();
  for (const m of modifiers) await page.keyboard.up(m);
  for (let i = 1; i <= steps; i++) await page.mouse.move(x + dx * i / steps, y + dy * i / steps);
  if (before) await before();
  await page.mouse.up();
  return [x, y];
}

/** Two animation frames: whatever was requested is drawn. */
export async function settle(page) {
  await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
}
