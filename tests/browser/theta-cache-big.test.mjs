// The largest sample's volume tensor from the cache after a reload (issue 13): the dragon's θ⁰
// (hundreds of MB, over Chromium's ~133 MB limit for one IndexedDB value) is computed once in the
// worker, stored in 32 MB chunks (web/chunked-store.js) and read back after a reload instead of
// being computed again; no storage problem is shown at any point.
import { after, before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { startTestServer, launchBrowser, waitReady, waitTheta, visibleHandles, dragHandle, settle, RESULTS_DIR } from './harness.mjs';

let server;

describe('web editor: the largest sample\'s θ in the cache', { timeout: 1_200_000 }, () => {
  before(async () => {
    server = await startTestServer();
  });

  after(async () => {
    await server?.close();
  });

  test('the dragon\'s θ⁰ (over 133 MB) is cached in chunks and comes from the cache after a reload', { timeout: 1_100_000 }, async () => {
    const browser = await launchBrowser(server.url, { viewport: { width: 1280, height: 800 } });
    try {
      const page = await browser.newPage();
      const url = `${server.url}?model=dragon-remeshed&gradient=tensor`;
      await page.goto(url);
      await waitReady(page, 240_000);
      assert.equal(await page.evaluate(() => window.mrvolDebug.settings().level), 0);
      await waitTheta(page, 900_000);
      assert.equal(await page.evaluate(() => window.mrvolDebug.thetaSource()), 'computed');
      const key = await page.evaluate(() => window.mrvolDebug.thetaKey());
      // written: the panel's cache list shows the entry with its size
      await page.waitForFunction(() => /dragon-remeshed loop e=0 +[\d.]+ MB/.test(document.querySelector('[data-testid="cache-list"]').textContent), null, { timeout: 300_000 });
      const listed = await page.locator('[data-testid="cache-list"]').textContent();
      const mb = Number(/dragon-remeshed loop e=0 +([\d.]+) MB/.exec(listed)[1]);
      assert.ok(mb > 133, `θ⁰ of the dragon is ${mb} MB: more than one IndexedDB value takes`);
      assert.equal(await page.locator('[data-testid="notice"]').textContent(), '', 'no storage notice');
      assert.equal(await page.locator('[data-testid="storage-problem"]').textContent(), '');

      await page.goto(url);
      await waitReady(page, 240_000);
      await waitTheta(page, 600_000);
      assert.equal(await page.evaluate(() => window.mrvolDebug.thetaSource()), 'cache', 'read back, not computed again');
      assert.equal(await page.evaluate(() => window.mrvolDebug.thetaKey()), key);
      const { index } = (await visibleHandles(page))[0];
      await dragHandle(page, index, 30, -20, { steps: 4 });
      const report = await page.evaluate(() => window.mrvolDebug.lastReport());
      assert.equal(report.path, 'tensor');
      assert.ok(report.relativeError <= 1e-5, `volume kept with the cached θ: ${report.relativeError}`);
      await settle(page);
      await page.screenshot({ path: join(RESULTS_DIR, 'theta-cache-big-dragon.png') });
      assert.equal(await page.locator('[data-testid="notice"]').textContent(), '');
      assert.deepEqual(page.problems, []);
    } finally {
      await browser.close();
    }
  });
});
