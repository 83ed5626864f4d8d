// The threaded WASM module in Chromium. The app's server sends COOP/COEP, so the page is
// cross-origin isolated and its core instance is the threaded build (mrvol-web-mt: a pool of
// workers, their script from a blob: URL of lib/browser.mjs's): a real drag there keeps the volume, and lib/browser.mjs's
// threaded and single-thread instances give the same bits for the same edits of a mesh large enough
// to be cut into blocks. Without isolation (the examples' server sends no such headers)
// lib/browser.mjs loads the single-thread build, whatever threads are asked for, and edits.
import { after, before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dragHandle, launchBrowser, openApp, root, settle, waitGradient } from './harness.mjs';

// In the page: the spiky ball subdivided 3 times (40,962 vertices), an editor at level 0, a few
// corrected drags; the volumes and the renderer's buffers after each (as plain arrays of bits).
async function editInPage(page, options) {
  return page.evaluate(async ({ entry, options }) => {
    const { createMrvol } = await import(entry);
    const mrvol = await createMrvol(options);
    const text = await (await fetch('/models/spiky-ball.obj')).text();
    const sub = mrvol.subdivide(mrvol.readObj(text), { levels: 3 });
    const ed = sub.createEditor({ level: 0 });
    const out = { threads: mrvol.threads, isolated: globalThis.crossOriginIsolated, steps: [] };
    const hash = (array) => {
      const words = new Uint32Array(array.buffer.slice(array.byteOffset, array.byteOffset + array.byteLength));
      let h = 2166136261;
      for (const w of words) h = Math.imul(h ^ w, 16777619) >>> 0;
      return h;
    };
    for (let s = 0; s < 4; ++s) {
      const report = ed.moveVertices([{ vertex: ed.cageVertices()[s], offset: [0.05, -0.03, 0.02] }], { tolerance: 1e-10 });
      out.steps.push({ converged: report.converged, error: report.relativeError, volume: report.volumeResult,
                       normals: hash(ed.normalsView()), positions: hash(ed.positionsView()) });
    }
    ed.delete();
    sub.delete();
    return out;
  }, { entry: `/@fs${root}/lib/browser.mjs`, options });
}

// In the page: createMrvol({ threads: 2 }) with the real module but a pool worker that is `worker`
// ('a model file': not a script; 'silent': a script that never answers), raced against 30 s;
// { settled: 'resolved' | 'ErrorName: message' | 'still pending', ms }.
async function threadedStart(page, worker, threadStartTimeout, threads = 2) {
  return page.evaluate(async ({ entry, worker, threadStartTimeout, threads }) => {
    const { createMrvol, MrvolError } = await import(entry);
    const base = new URL(entry, location.href);
    const urls = {
      factory: new URL('../build/wasm/mrvol-web-mt.mjs', base).href,
      wasm: new URL('../build/wasm/mrvol-web-mt.wasm', base).href,
      worker: worker === 'silent' ? URL.createObjectURL(new Blob(['// a pool worker that never reports'], { type: 'text/javascript' }))
        : new URL('/models/spiky-ball.obj', location.href).href,
    };
    const started = performance.now();
    const pending = new Promise((resolve) => setTimeout(() => resolve('still pending'), 30_000));
    const settled = await Promise.race([
      createMrvol({ ...(threads ? { threads } : {}), threadedUrls: urls, ...(threadStartTimeout ? { threadStartTimeout } : {}) })
        .then((m) => `resolved (${m.threads} thread${m.threads > 1 ? 's' : ''})`, (e) => `${e instanceof MrvolError ? 'MrvolError' : e?.name}: ${e?.message}`),
      pending,
    ]);
    return { settled, ms: performance.now() - started, worker: urls.worker };
  }, { entry: `/@fs${root}/lib/browser.mjs`, worker, threadStartTimeout, threads });
}

describe('the app on its cross-origin isolated server', { timeout: 240_000 }, () => {
  let browser, page;
  before(async () => ({ browser, page } = await openApp()));
  after(() => browser?.close());

  test('the page is isolated and its core runs threads; a drag keeps the volume', async () => {
    assert.equal(await page.evaluate(() => globalThis.crossOriginIsolated), true);
    const threads = await page.evaluate(() => window.mrvolDebug.coreThreads());
    const cores = await page.evaluate(() => navigator.hardwareConcurrency);
    assert.equal(threads, Math.max(1, Math.min(8, cores)), 'the threaded core on the cores');
    await waitGradient(page);
    const before = await page.evaluate(() => window.mrvolDebug.referenceVolume());
    await dragHandle(page, 0, 60, -40);
    await settle(page);
    const after = await page.evaluate(() => ({ volume: window.mrvolDebug.volume(), report: window.mrvolDebug.lastReport() }));
    assert.ok(after.report, 'a drag step ran');
    assert.ok(Math.abs(after.volume - before) / Math.abs(before) < 1e-5, `volume kept: ${after.volume} vs ${before}`);
    assert.deepEqual(page.problems, []);
  });

  test('lib/browser.mjs: threaded and single-thread instances edit to the same bits', async () => {
    const threaded = await editInPage(page, { threads: 2 });
    const single = await editInPage(page, { threads: 1 });
    assert.equal(threaded.isolated, true);
    assert.equal(threaded.threads, 2);
    assert.equal(single.threads, 1);
    for (const step of threaded.steps) assert.ok(step.converged && step.error < 1e-10, JSON.stringify(step));
    assert.deepEqual(threaded.steps, single.steps);
  });

  test('lib/browser.mjs: a pool worker that cannot start rejects with a MrvolError naming it (it never settled)', async () => {
    // The worker's script as a bundler's dev server may hand it out: here a file that is not one at all.
    const outcome = await threadedStart(page, 'a model file');
    assert.match(outcome.settled, /^MrvolError: the threaded module's worker .*spiky-ball\.obj could not start \(.*\): serve it as a classic script, untransformed .*or use createMrvol\(\{ threads: 1 \}\)$/);
  });

  test('lib/browser.mjs: a pool worker that starts but never reports (its import of the module failed in it) rejects after threadStartTimeout', async () => {
    // A build that did not emit the module's file: the worker's import fails inside it, which only the
    // worker sees. Here a worker that runs and never answers.
    const outcome = await threadedStart(page, 'silent', 2000);
    assert.match(outcome.settled, /^MrvolError: the threaded module's workers did not start within 2 s \(blob:.* importing .*mrvol-web-mt\.mjs\): serve both as they are .*or use createMrvol\(\{ threads: 1 \}\)$/);
    assert.ok(outcome.ms < 20_000, `settled after ${outcome.ms} ms`);
    // Its pool's worker is stopped, not left running in the page.
    const running = () => page.workers().filter((w) => w.url() === outcome.worker).length;
    for (let t = 0; t < 50 && running() > 0; ++t) await new Promise((r) => setTimeout(r, 100));
    assert.equal(running(), 0, 'the failed pool\'s worker is terminated');
  });
});

describe('lib/browser.mjs: threads not asked for', { timeout: 120_000 }, () => {
  let browser, page;
  before(async () => ({ browser, page } = await openApp()));
  after(() => browser?.close());

  test('a pool that cannot start gives way to the single-thread build, a console warning saying why', async () => {
    const warnings = [];
    page.on('console', (m) => m.type() === 'warning' && warnings.push(m.text()));
    const outcome = await threadedStart(page, 'a model file', undefined, null);
    assert.equal(outcome.settled, 'resolved (1 thread)');
    assert.ok(warnings.some((w) => /^mrvol: running on one thread: the threaded module's worker .*spiky-ball\.obj could not start/.test(w)),
              warnings.join('\n'));
  });
});

describe('lib/browser.mjs without cross-origin isolation', { timeout: 180_000 }, () => {
  let server, browser, page, scratch;
  before(async () => {
    // The examples' server: no COOP/COEP headers.
    const { createServer } = await import('vite');
    scratch = mkdtempSync(join(tmpdir(), 'mrvol-threads-'));
    server = await createServer({
      configFile: join(root, 'examples/web/vite.config.mjs'), logLevel: 'warn', clearScreen: false,
      cacheDir: join(scratch, 'vite-cache'), server: { port: 0, strictPort: false, watch: null, hmr: false },
    });
    await server.listen();
    const { address, port } = server.httpServer.address();
    browser = await launchBrowser(`http://${address}:${port}/`);
    page = await browser.newPage();
    await page.goto(`http://${address}:${port}/minimal.html`);
  });
  after(async () => {
    await browser?.close();
    await server?.close();
    if (scratch) rmSync(scratch, { recursive: true, force: true });
  });

  test('loads the single-thread build even when threads are asked for, and edits', async () => {
    const result = await editInPage(page, { threads: 4 });
    assert.equal(result.isolated, false);
    assert.equal(result.threads, 1);
    for (const step of result.steps) assert.ok(step.converged && step.error < 1e-10, JSON.stringify(step));
  });
});
