// The session in IndexedDB at any size: a ~20 MB OBJ opened from disk (2 more levels of Loop
// subdivision of the dragon sample, made with `mrvol subdivide`) and its edits and undo history
// survive a reload; the recent models list reopens an earlier model with its edits; a failed write
// is said in plain words and cleared once writing works again. Values are split into 32 MB chunks
// (web/chunked-store.js), so theta over Chromium's ~133 MB per-value limit is cached too.
import { after, before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { startTestServer, launchBrowser, waitReady, visibleHandles, dragHandle, settle, root, RESULTS_DIR } from './harness.mjs';

let server, scratch, bigObj;

const debug = (page, name) => page.evaluate((n) => window.mrvolDebug[n](), name);

describe('web editor: sessions in IndexedDB', { timeout: 600_000 }, () => {
  before(async () => {
    scratch = mkdtempSync(join(tmpdir(), 'mrvol-session-store-'));
    const out = join(scratch, 'dragon-fine.obj');
    execFileSync(process.execPath, [join(root, 'bin/mrvol.mjs'), 'subdivide', join(root, 'public/models/dragon-remeshed.obj'), '--levels', '2', '-o', out],
      { stdio: 'pipe', timeout: 240_000 });
    bigObj = readFileSync(out);
    server = await startTestServer();
  });

  after(async () => {
    await server?.close();
    if (scratch) rmSync(scratch, { recursive: true, force: true });
  });

  test('a ~20 MB OBJ opened from disk, its edits and undo history survive a reload', { timeout: 400_000 }, async () => {
    assert.ok(bigObj.byteLength > 14e6, `the OBJ is ${(bigObj.byteLength / 1e6).toFixed(1)} MB`);
    const browser = await launchBrowser(server.url, { viewport: { width: 1280, height: 800 } });
    try {
      const page = await browser.newPage();
      await page.goto(server.url);
      await waitReady(page);
      await page.locator('[data-testid="open-file"]').setInputFiles({ name: 'dragon-fine.obj', mimeType: 'text/plain', buffer: bigObj });
      await page.waitForFunction(() => window.mrvolDebug.modelName() === 'dragon-fine.obj' && window.mrvolDebug.ready(), null, { timeout: 240_000 });
      // theta of this mesh takes long: edit matrix-free
      if (await page.locator('[data-testid="theta-progress"]').isVisible()) await page.locator('[data-testid="theta-cancel"]').click();
      const { index } = (await visibleHandles(page))[0];
      await dragHandle(page, index, 30, -20, { steps: 3 });
      const edited = await debug(page, 'cagePositions');
      const volume = await debug(page, 'volume');
      assert.deepEqual(await debug(page, 'historySize'), { undo: 1, redo: 0 });
      // the save is written (debounced) before the reload
      await page.waitForFunction(() => document.querySelectorAll('[data-testid="recent-item"]').length >= 2, null, { timeout: 60_000 });
      await page.waitForTimeout(1500);
      assert.equal(await page.locator('[data-testid="storage-problem"]').textContent(), '');

      await page.reload();
      await page.waitForFunction(() => window.mrvolDebug.modelName() === 'dragon-fine.obj' && window.mrvolDebug.ready(), null, { timeout: 240_000 });
      if (await page.locator('[data-testid="theta-progress"]').isVisible()) await page.locator('[data-testid="theta-cancel"]').click();
      const restored = await debug(page, 'cagePositions');
      assert.equal(restored.length, edited.length);
      // the fine positions are stored exactly; the cage is analysed from them again (rounding only)
      assert.ok(restored.every((x, i) => Math.abs(x - edited[i]) <= 1e-9 * (1 + Math.abs(edited[i]))), 'the edited cage came back');
      assert.ok(Math.abs(await debug(page, 'volume') - volume) <= 1e-9 * Math.abs(volume));
      assert.deepEqual(await debug(page, 'historySize'), { undo: 1, redo: 0 }, 'the undo history came back');
      await settle(page);
      await page.screenshot({ path: join(RESULTS_DIR, 'session-store-01-big-file-reloaded.png') });
      await page.keyboard.press('Control+z');
      assert.notDeepEqual(await debug(page, 'cagePositions'), edited, 'undo goes back to before the drag');

      // The recent list reopens the spiky ball (opened first), then the file again, each with its state.
      await page.locator('[data-testid="recent-folder"]').click();
      await page.locator('[data-testid="recent-item"][data-id="sample:spiky-ball"]').click();
      await page.waitForFunction(() => window.mrvolDebug.modelName() === 'spiky-ball' && window.mrvolDebug.ready());
      await page.locator('[data-testid="recent-item"][data-id^="file:dragon-fine.obj"]').click();
      await page.waitForFunction(() => window.mrvolDebug.modelName() === 'dragon-fine.obj' && window.mrvolDebug.ready(), null, { timeout: 240_000 });
      assert.deepEqual(page.problems, []);
    } finally {
      await browser.close();
    }
  });

  test('a failed write is said in plain words and cleared when writing works again', { timeout: 120_000 }, async () => {
    const browser = await launchBrowser(server.url);
    try {
      const page = await browser.newPage();
      const cdp = await page.context().newCDPSession(page);
      const origin = new URL(server.url).origin;
      // A 0.9 MB OBJ opened as a file: its text goes into the session, over a 100 kB quota. The quota
      // is set before the page writes anything: after each quota check Chromium lets writes through
      // for up to 30 s against the space it found then (BucketContext::kBucketSpaceCacheTimeLimit),
      // so a quota lowered after the sample's first save may not be met by the file's save at once.
      await cdp.send('Storage.overrideQuotaForOrigin', { origin, quotaSize: 100_000 });
      await page.goto(server.url);
      await waitReady(page);
      await page.locator('[data-testid="open-file"]').setInputFiles(join(root, 'public/models/dragon-remeshed.obj'));
      await page.waitForFunction(() => window.mrvolDebug.modelName() === 'dragon-remeshed.obj' && window.mrvolDebug.ready());
      const problem = page.locator('[data-testid="storage-problem"]');
      await page.waitForFunction(() => document.querySelector('[data-testid="storage-problem"]').textContent !== '');
      assert.match(await problem.textContent(), /not kept: the browser's storage quota is full/);
      assert.doesNotMatch(await problem.textContent(), /DOMException|QuotaExceededError/);
      await cdp.send('Storage.overrideQuotaForOrigin', { origin });
      const { index } = (await visibleHandles(page))[0];
      await dragHandle(page, index, -20, -20);
      await page.waitForFunction(() => document.querySelector('[data-testid="storage-problem"]').textContent === '');
    } finally {
      await browser.close();
    }
  });
});
