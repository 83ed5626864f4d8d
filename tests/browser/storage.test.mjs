// The editor when things go wrong around it: IndexedDB over quota or missing, a theta computation
// cancelled, a model named in the URL that does not exist, an open mesh whose boundary stays fixed;
// and opening a file by drag and drop.
// One server; a fresh browser profile per test.
import { after, before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { readFile } from 'node:fs/promises';
import { join } from 'node:path';
import { createMrvol } from '../../lib/node.mjs';
import { startTestServer, launchBrowser, waitReady, waitTheta, readouts, visibleHandles, dragHandle, settle, root, RESULTS_DIR } from './harness.mjs';

let server, mrvol;

async function withBrowser(fn) {
  const browser = await launchBrowser(server.url);
  try {
    const page = await browser.newPage();
    await fn(page, browser);
  } finally {
    await browser.close();
  }
}

async function dragAndCheck(page) {
  const { index } = (await visibleHandles(page))[0];
  await dragHandle(page, index, 40, -30);
  const r = await readouts(page);
  assert.ok(r.error <= 1e-5, `relative error ${r.error}`);
  return r;
}

describe('web editor: storage, cancel, drop, open meshes', { timeout: 240_000 }, () => {
  before(async () => {
    mrvol = await createMrvol();
    server = await startTestServer();
  });

  after(async () => {
    await server?.close();
  });

  test('over the storage quota theta is not cached, editing goes on, the next load computes it again', { timeout: 120_000 }, async () => {
    await withBrowser(async (page) => {
      const cdp = await page.context().newCDPSession(page);
      await cdp.send('Storage.overrideQuotaForOrigin', { origin: new URL(server.url).origin, quotaSize: 200_000 });
      await page.goto(`${server.url}?gradient=tensor`);
      await waitReady(page);
      await waitTheta(page);
      assert.equal(await page.evaluate(() => window.mrvolDebug.thetaSource()), 'computed');
      const notice = page.locator('[data-testid="notice"]');
      await page.waitForFunction(() => /not cached/.test(document.querySelector('[data-testid="notice"]').textContent));
      assert.match(await notice.textContent(), /θ is not cached: .*quota/i);
      await dragAndCheck(page);
      await page.waitForTimeout(300);
      await page.reload();
      await waitReady(page);
      await waitTheta(page);
      assert.equal(await page.evaluate(() => window.mrvolDebug.thetaSource()), 'computed');
      assert.deepEqual(page.problems, []);
    });
  });

  test('without IndexedDB the editor computes theta and says there is no cache', { timeout: 120_000 }, async () => {
    await withBrowser(async (page) => {
      await page.addInitScript(() => {
        Object.defineProperty(window, 'indexedDB', {
          configurable: true,
          get() { throw new DOMException('The user denied permission to access the database.', 'SecurityError'); },
        });
      });
      await page.goto(`${server.url}?gradient=tensor`);
      await waitReady(page);
      await waitTheta(page);
      assert.equal(await page.evaluate(() => window.mrvolDebug.thetaSource()), 'computed');
      assert.match(await page.locator('[data-testid="cache-status"]').textContent(), /none: the browser does not allow storage on this page/);
      assert.match(await page.locator('[data-testid="cache-list"]').textContent(), /IndexedDB unavailable/);
      await dragAndCheck(page);
      assert.deepEqual(page.problems, []);
    });
  });

  test('a long theta computation shows progress, can be cancelled (matrix-free editing) and recomputed', { timeout: 150_000 }, async () => {
    // 4 levels of Loop subdivision of the icosahedron: 2562 vertices, theta^0 takes a few seconds.
    const base = mrvol.readObj(await readFile(join(root, 'public/models/icosahedron.obj'), 'utf8'));
    const fine = mrvol.subdivide(base, { levels: 4 });
    const obj = mrvol.writeObj(fine.toMesh());
    fine.delete();
    await withBrowser(async (page) => {
      await page.goto(`${server.url}?gradient=tensor`);
      await waitReady(page);
      await page.locator('[data-testid="open-file"]').setInputFiles({ name: 'ball-4.obj', mimeType: 'text/plain', buffer: Buffer.from(obj) });
      await page.waitForFunction(() => window.mrvolDebug.modelName() === 'ball-4.obj' && window.mrvolDebug.ready());
      const progress = page.locator('[data-testid="theta-progress"]');
      await progress.waitFor({ state: 'visible', timeout: 30_000 });
      // the page answers while the worker computes
      const started = Date.now();
      assert.equal(await page.evaluate(() => window.mrvolDebug.cageSize()), 12);
      assert.ok(Date.now() - started < 2000, 'the page stays responsive');
      await page.screenshot({ path: join(RESULTS_DIR, 'storage-01-theta-progress.png') });
      await page.locator('[data-testid="theta-cancel"]').click();
      await progress.waitFor({ state: 'hidden' });
      assert.match(await page.locator('[data-testid="theta-status"]').textContent(), /cancelled/);
      assert.equal(await page.evaluate(() => window.mrvolDebug.thetaSource()), null);
      assert.equal(await page.locator('[data-testid="theta-source"]').textContent(), 'none');
      assert.equal(await page.evaluate(() => window.mrvolDebug.gradientPath()), 'matrix-free');
      const r = await dragAndCheck(page);
      assert.equal(r.path, 'matrix-free');

      await page.locator('[data-testid="theta-recompute"]').click();
      await waitTheta(page, 120_000);
      assert.equal(await page.evaluate(() => window.mrvolDebug.thetaSource()), 'computed');
      const r2 = await dragAndCheck(page);
      assert.equal(r2.path, 'tensor');
      assert.deepEqual(page.problems, []);
    });
  });

  test('an open mesh: its boundary handles stay fixed (said in words), its interior ones keep the volume', { timeout: 120_000 }, async () => {
    // An open pyramid (no bottom), 3 levels of Loop subdivision: apex inside, the base ring on the boundary.
    const base = { positions: new Float64Array([0, 0, 1, 1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1, 0]),
                   faces: new Uint32Array([0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1]) };
    const fine = mrvol.subdivide(base, { levels: 3 });
    const obj = mrvol.writeObj(fine.toMesh());
    fine.delete();
    await withBrowser(async (page) => {
      await page.goto(server.url);
      await waitReady(page);
      await page.locator('[data-testid="open-file"]').setInputFiles({ name: 'open-pyramid.obj', mimeType: 'text/plain', buffer: Buffer.from(obj) });
      await page.waitForFunction(() => window.mrvolDebug.modelName() === 'open-pyramid.obj' && window.mrvolDebug.ready());
      assert.match(await page.locator('[data-testid="model-info"]').textContent(), /open: the volume is that of the cone/);
      const cage = await page.evaluate(() => window.mrvolDebug.cagePositions());
      // handle 1 is base vertex 1, on the boundary: the drag is refused and the cage stays
      await dragHandle(page, 1, 30, 30);
      await page.locator('[data-testid="error"]').waitFor({ state: 'visible' });
      assert.match(await page.locator('[data-testid="error"]').textContent(), /not possible: vertex 1 is on the boundary/);
      assert.deepEqual(await page.evaluate(() => window.mrvolDebug.cagePositions()), cage);
      // level 1: the apex (handle 0) moves, the other interior handles absorb the volume change
      await page.locator('[data-testid="level"]').selectOption('1');
      await page.waitForFunction(() => window.mrvolDebug.cageSize() === 13);
      await dragHandle(page, 0, 25, -25);
      const r = await readouts(page);
      assert.ok(r.error <= 1e-5, `relative error ${r.error}`);
      assert.ok(Math.abs(r.reference - mrvol.volume(mrvol.readObj(obj))) < 1e-12);
      await page.screenshot({ path: join(RESULTS_DIR, 'storage-03-open-pyramid.png') });
    });
  });

  test('an unknown model in the URL is reported and the default model opens; a dropped OBJ file opens', { timeout: 120_000 }, async () => {
    await withBrowser(async (page) => {
      await page.goto(`${server.url}?model=no-such-model`);
      await waitReady(page);
      assert.equal(await page.evaluate(() => window.mrvolDebug.modelName()), 'spiky-ball');
      assert.match(await page.locator('[data-testid="error"]').textContent(), /no-such-model.*there is no sample model/);

      const torus = await readFile(join(root, 'public/models/torus.obj'), 'utf8');
      await page.evaluate((text) => {
        const data = new DataTransfer();
        data.items.add(new File([text], 'dropped-torus.obj', { type: 'text/plain' }));
        const target = document.querySelector('#view canvas');
        for (const type of ['dragenter', 'dragover', 'drop'])
          target.dispatchEvent(new DragEvent(type, { dataTransfer: data, bubbles: true, cancelable: true }));
      }, torus);
      await page.waitForFunction(() => window.mrvolDebug.modelName() === 'dropped-torus.obj' && window.mrvolDebug.ready());
      assert.equal(await page.evaluate(() => window.mrvolDebug.cageSize()), 24);
      assert.equal(await page.locator('[data-testid="error"]').isVisible(), false);
      assert.equal(await page.locator('#drop-hint').isVisible(), false);
      await settle(page);
      await page.screenshot({ path: join(RESULTS_DIR, 'storage-02-dropped-torus.png') });
      // the dropped file is the session's model after a reload
      await page.waitForTimeout(300);
      await page.goto(server.url);
      await waitReady(page);
      assert.equal(await page.evaluate(() => window.mrvolDebug.modelName()), 'dropped-torus.obj');
    });
  });
});
