// The web editor in headless Chromium: loading, dragging with and without volume preservation,
// undo/redo, cancel, multi-selection, export, the session and theta cache across a reload, bad
// files. One server and one browser profile for the whole file; the tests run in order and build
// on each other (the reload test finds the cache the first load filled).
import { after, before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { readFile } from 'node:fs/promises';
import { join } from 'node:path';
import { createMrvol } from '../../lib/node.mjs';
import { openApp, waitReady, waitTheta, readouts, visibleHandles, dragHandle, settle, root, RESULTS_DIR } from './harness.mjs';

const SPIKY = join(root, 'public/models/spiky-ball.obj');

let browser, page, mrvol;

async function shot(name) {
  await settle(page);
  await page.screenshot({ path: join(RESULTS_DIR, `${name}.png`) });
}

const lastReport = () => page.evaluate(() => window.mrvolDebug.lastReport());

function cageDistance(a, b) {
  return Math.hypot(a[0] - b[0], a[1] - b[1]);
}

/** A closed, valid latitude-longitude sphere: a fine triangle mesh without 1-to-4 structure. */
function uvSphereObj(rings = 8, segments = 12) {
  const lines = ['# uv sphere, not semi-regular'];
  lines.push('v 0 0 1');
  for (let i = 1; i < rings; i++) {
    const t = Math.PI * i / rings;
    for (let j = 0; j < segments; j++) {
      const p = 2 * Math.PI * j / segments;
      lines.push(`v ${Math.sin(t) * Math.cos(p)} ${Math.sin(t) * Math.sin(p)} ${Math.cos(t)}`);
    }
  }
  lines.push('v 0 0 -1');
  const ring = (i, j) => 2 + (i - 1) * segments + (j % segments); // 1-based OBJ index
  const south = 2 + (rings - 1) * segments;
  for (let j = 0; j < segments; j++) lines.push(`f 1 ${ring(1, j)} ${ring(1, j + 1)}`);
  for (let i = 1; i < rings - 1; i++)
    for (let j = 0; j < segments; j++) {
      lines.push(`f ${ring(i, j)} ${ring(i + 1, j)} ${ring(i + 1, j + 1)}`);
      lines.push(`f ${ring(i, j)} ${ring(i + 1, j + 1)} ${ring(i, j + 1)}`);
    }
  for (let j = 0; j < segments; j++) lines.push(`f ${south} ${ring(rings - 1, j + 1)} ${ring(rings - 1, j)}`);
  return lines.join('\n') + '\n';
}

describe('web editor', { timeout: 240_000 }, () => {
  before(async () => {
    mrvol = await createMrvol();
    ({ browser, page } = await openApp({ goto: false }));
  });
  after(() => browser?.close());

  test('loads the default model (spiky ball) with its level-0 cage and computes theta in the worker', { timeout: 120_000 }, async () => {
    // the paper's tensor path (the app's default is the cage polynomial: files.test.mjs); kept in the stored settings
    await page.goto(`${browser.url}?gradient=tensor`);
    await waitReady(page);
    assert.equal(await page.evaluate(() => window.mrvolDebug.modelName()), 'spiky-ball');
    assert.equal(await page.evaluate(() => window.mrvolDebug.cageSize()), 12);
    const r0 = await readouts(page);
    assert.ok(Math.abs(r0.reference - 3.622788673) < 1e-8, `reference volume ${r0.reference}`);
    await waitTheta(page);
    assert.equal(await page.evaluate(() => window.mrvolDebug.thetaSource()), 'computed');
    assert.equal((await readouts(page)).thetaSource, 'computed');
    assert.equal(await page.evaluate(() => window.mrvolDebug.gradientPath()), 'tensor');
    await shot('01-loaded');
  });

  test('dragging a handle by 60 px keeps the volume (relative error <= 1e-5)', async () => {
    const handles = await visibleHandles(page);
    assert.ok(handles.length >= 2, 'at least two handles are visible on the canvas');
    const { index } = handles[0];
    const before = (await page.evaluate(() => window.mrvolDebug.cageScreenPositions()))[index];
    await dragHandle(page, index, 60, -30);
    await settle(page);
    const afterDrag = (await page.evaluate(() => window.mrvolDebug.cageScreenPositions()))[index];
    // The handle follows the pointer (it is held): about 67 px away from where it was.
    assert.ok(Math.abs(cageDistance(before, afterDrag) - Math.hypot(60, 30)) < 3,
              `handle moved ${cageDistance(before, afterDrag)} px`);
    const r = await readouts(page);
    assert.ok(r.error <= 1e-5, `relative error ${r.error}, last step ${JSON.stringify(await lastReport())}`);
    assert.ok(Math.abs(r.current - r.reference) <= 1e-5, `volume ${r.current} vs reference ${r.reference}`);
    assert.equal(Number(r.current.toPrecision(12)), Number(r.currentText));
    assert.equal(r.path, 'tensor');
    assert.ok(Number(r.iterations) >= 1);
    assert.ok(Number.isFinite(Number(r.ms)));
    assert.deepEqual(await page.evaluate(() => window.mrvolDebug.historySize()), { undo: 1, redo: 0 });
    await shot('02-dragged-preserved');
  });

  let preservedVolume, changedVolume;
  test('without preservation (panel checkbox) a drag changes the volume; Ctrl+Z and Ctrl+Shift+Z undo and redo it', async () => {
    preservedVolume = (await readouts(page)).current;
    const checkbox = page.locator('[data-testid="preserve"]');
    assert.equal(await checkbox.isChecked(), true);
    await checkbox.click();
    assert.equal(await checkbox.isChecked(), false);
    assert.equal(await page.evaluate(() => window.mrvolDebug.settings().preserve), false);

    const handles = await visibleHandles(page);
    const { index } = handles[handles.length > 1 ? 1 : 0];
    // Outwards from the centre of the screen: the volume grows.
    const [x, y] = (await page.evaluate(() => window.mrvolDebug.cageScreenPositions()))[index];
    const cx = 600, cy = 400;
    const len = Math.hypot(x - cx, y - cy);
    await dragHandle(page, index, (x - cx) / len * 60, (y - cy) / len * 60);
    await settle(page);
    const r = await readouts(page);
    changedVolume = r.current;
    assert.ok(r.error > 1e-3, `relative error after an unpreserved drag: ${r.error}`);
    assert.ok(Math.abs(r.current - preservedVolume) > 1e-3, `volume ${r.current} vs ${preservedVolume}`);
    await shot('03-dragged-not-preserved');

    await page.locator('#view canvas').focus().catch(() => {});
    await page.keyboard.press('Control+z');
    await settle(page);
    const undone = await readouts(page);
    assert.ok(Math.abs(undone.current - preservedVolume) < 1e-9, `undo: ${undone.current} vs ${preservedVolume}`);
    assert.ok(undone.error <= 1e-5);
    // the history holds the preservation toggle and the drag (tests/browser/history.test.mjs)
    assert.deepEqual(await page.evaluate(() => window.mrvolDebug.historySize()), { undo: 2, redo: 1 });

    await page.keyboard.press('Control+Shift+z');
    await settle(page);
    const redone = await readouts(page);
    assert.ok(Math.abs(redone.current - changedVolume) < 1e-9, `redo: ${redone.current} vs ${changedVolume}`);

    await checkbox.click(); // preservation back on: the editor asks what to keep
    assert.equal(await page.evaluate(() => window.mrvolDebug.settings().preserve), true);
    await page.locator('[data-testid="preserve-restore"]').click();
    assert.ok((await readouts(page)).error <= 1e-5, 'the reference volume is restored');
  });

  test('Escape during a drag puts the cage back', async () => {
    const handles = await visibleHandles(page);
    const { index } = handles[0];
    const cageBefore = await page.evaluate(() => window.mrvolDebug.cageScreenPositions());
    const volumeBefore = (await readouts(page)).current;
    const historyBefore = await page.evaluate(() => window.mrvolDebug.historySize());
    await dragHandle(page, index, -50, 40, {
      before: async () => {
        const mid = (await page.evaluate(() => window.mrvolDebug.cageScreenPositions()))[index];
        assert.ok(cageDistance(mid, cageBefore[index]) > 40, 'the handle moved during the drag');
        await page.keyboard.press('Escape');
      },
    });
    await settle(page);
    const cageAfter = await page.evaluate(() => window.mrvolDebug.cageScreenPositions());
    for (let i = 0; i < cageAfter.length; i++) assert.ok(cageDistance(cageAfter[i], cageBefore[i]) < 1e-6, `handle ${i} is back`);
    assert.ok(Math.abs((await readouts(page)).current - volumeBefore) < 1e-9);
    assert.deepEqual(await page.evaluate(() => window.mrvolDebug.historySize()), historyBefore);
  });

  test('Shift-click selects several handles and a drag moves them together', async () => {
    const handles = await visibleHandles(page);
    assert.ok(handles.length >= 2);
    const [a, b] = handles;
    // a plain click on a, then Shift-click on b
    await page.mouse.click(a.x, a.y);
    await page.keyboard.down('Shift');
    await page.mouse.click(b.x, b.y);
    await page.keyboard.up('Shift');
    assert.deepEqual((await page.evaluate(() => window.mrvolDebug.selection())).sort(), [a.index, b.index].sort());
    const before = await page.evaluate(() => window.mrvolDebug.cageScreenPositions());
    await dragHandle(page, a.index, 0, 45);
    await settle(page);
    const afterDrag = await page.evaluate(() => window.mrvolDebug.cageScreenPositions());
    assert.ok(cageDistance(afterDrag[a.index], before[a.index]) > 30, 'the dragged handle moved');
    assert.ok(cageDistance(afterDrag[b.index], before[b.index]) > 10, 'the other selected handle moved too');
    const r = await readouts(page);
    assert.ok(r.error <= 1e-5, `relative error ${r.error}, last step ${JSON.stringify(await lastReport())}`);
    await shot('04-multi-select');
  });

  test('exports the edited mesh as OBJ: same vertex order and faces, the shown volume', async () => {
    const [download] = await Promise.all([
      page.waitForEvent('download', { timeout: 30_000 }),
      page.locator('[data-testid="export"]').click(),
    ]);
    assert.equal(download.suggestedFilename(), 'spiky-ball-edited.obj');
    const text = await readFile(await download.path(), 'utf8');
    const exported = mrvol.readObj(text);
    const original = mrvol.readObj(await readFile(SPIKY, 'utf8'));
    assert.equal(exported.positions.length, original.positions.length);
    assert.deepEqual(exported.faces, original.faces);
    const shown = await page.evaluate(() => window.mrvolDebug.volume());
    assert.ok(Math.abs(mrvol.volume(exported) - shown) < 1e-9, `${mrvol.volume(exported)} vs ${shown}`);
    // edited: some vertices moved
    let moved = 0;
    for (let i = 0; i < original.positions.length; i++) moved = Math.max(moved, Math.abs(exported.positions[i] - original.positions[i]));
    assert.ok(moved > 0.01, `largest coordinate change ${moved}`);
  });

  test('a reload keeps the session (model, shape) and takes theta from IndexedDB', { timeout: 120_000 }, async () => {
    const volumeBefore = await page.evaluate(() => window.mrvolDebug.volume());
    const cageBefore = await page.evaluate(() => window.mrvolDebug.cagePositions());
    await page.waitForTimeout(300); // the session is saved 150 ms after an edit
    await page.reload();
    await waitReady(page);
    await waitTheta(page);
    assert.equal(await page.evaluate(() => window.mrvolDebug.thetaSource()), 'cache');
    assert.equal((await readouts(page)).thetaSource, 'cache');
    assert.equal(await page.evaluate(() => window.mrvolDebug.modelName()), 'spiky-ball');
    assert.ok(Math.abs(await page.evaluate(() => window.mrvolDebug.volume()) - volumeBefore) < 1e-12);
    const cageAfter = await page.evaluate(() => window.mrvolDebug.cagePositions());
    assert.equal(cageAfter.length, cageBefore.length);
    for (let i = 0; i < cageAfter.length; i++) assert.ok(Math.abs(cageAfter[i] - cageBefore[i]) < 1e-9, `cage coordinate ${i}`);
    // the cache section lists the entry
    await page.locator('[data-testid="cache-folder"]').click();
    await page.locator('[data-testid="cache-refresh"]').click();
    await page.waitForFunction(() => /spiky-ball loop e=0\s+8\.9 MB/.test(document.querySelector('[data-testid="cache-list"]').textContent));
    // and the drag still works on the cached tensor
    const { index } = (await visibleHandles(page))[0];
    await dragHandle(page, index, 30, 30);
    const r = await readouts(page);
    assert.ok(r.error <= 1e-5);
    assert.equal(r.path, 'tensor');
    await shot('05-reloaded-from-cache');
  });

  test('a corrupt cache entry is dropped and theta recomputed', { timeout: 120_000 }, async () => {
    const key = await page.evaluate(() => window.mrvolDebug.thetaKey());
    await page.evaluate((key) => new Promise((resolve, reject) => {
      const open = indexedDB.open('mrvol');
      open.onerror = () => reject(open.error);
      open.onsuccess = () => {
        const tx = open.result.transaction('theta', 'readwrite');
        const bytes = new Uint8Array(4096).fill(7);
        tx.objectStore('theta').put(bytes.buffer, `${key}#0`); // its first (only) chunk, web/chunked-store.js
        tx.oncomplete = () => { open.result.close(); resolve(); };
        tx.onerror = () => reject(tx.error);
      };
    }), key);
    await page.reload();
    await waitReady(page);
    await waitTheta(page);
    assert.equal(await page.evaluate(() => window.mrvolDebug.thetaSource()), 'computed');
    assert.match(await page.locator('[data-testid="notice"]').textContent(), /cached θ was unusable/);
    // the recomputed tensor went back into the cache (the list is refreshed after the write)
    await page.waitForFunction(() => /spiky-ball loop e=0/.test(document.querySelector('[data-testid="cache-list"]').textContent));
    await page.reload();
    await waitReady(page);
    await waitTheta(page);
    assert.equal(await page.evaluate(() => window.mrvolDebug.thetaSource()), 'cache');
  });

  test('a malformed OBJ shows an error in words and the current model stays usable', async () => {
    await page.locator('[data-testid="open-file"]').setInputFiles({
      name: 'broken.obj', mimeType: 'text/plain', buffer: Buffer.from('v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n'),
    });
    const error = page.locator('[data-testid="error"]');
    await error.waitFor({ state: 'visible', timeout: 30_000 });
    const message = await error.textContent();
    assert.match(message, /broken\.obj/);
    assert.match(message, /line 4/);
    assert.equal(await page.evaluate(() => window.mrvolDebug.modelName()), 'spiky-ball');
    assert.equal(await page.evaluate(() => window.mrvolDebug.ready()), true);
    await shot('06-bad-obj');
    const { index } = (await visibleHandles(page))[0];
    await dragHandle(page, index, -20, 20);
    const r = await readouts(page);
    assert.ok(r.error <= 1e-5, `relative error ${r.error}, last step ${JSON.stringify(await lastReport())}`);
  });

  test('a valid mesh that is not semi-regular is refused with an explanation', async () => {
    await page.locator('[data-testid="open-file"]').setInputFiles({
      name: 'uv-sphere.obj', mimeType: 'text/plain', buffer: Buffer.from(uvSphereObj()),
    });
    await page.waitForFunction(() => /uv-sphere\.obj.*not semi-regular/s.test(document.querySelector('[data-testid="error"]').textContent));
    assert.equal(await page.locator('[data-testid="error"]').isVisible(), true);
    assert.equal(await page.evaluate(() => window.mrvolDebug.modelName()), 'spiky-ball');
  });

  test('a valid OBJ file opens; level and scheme changes rebuild the editor', { timeout: 120_000 }, async () => {
    const blob = await readFile(join(root, 'public/models/blob.obj'));
    await page.locator('[data-testid="open-file"]').setInputFiles({ name: 'my-blob.obj', mimeType: 'text/plain', buffer: blob });
    await page.waitForFunction(() => window.mrvolDebug.modelName() === 'my-blob.obj');
    await waitReady(page);
    assert.equal(await page.locator('[data-testid="error"]').isVisible(), false);
    assert.equal(await page.evaluate(() => window.mrvolDebug.cageSize()), 6);
    await waitTheta(page);
    await page.locator('[data-testid="level"]').selectOption('1');
    await page.waitForFunction(() => window.mrvolDebug.cageSize() === 18);
    await page.locator('[data-testid="scheme"]').selectOption('butterfly');
    await waitTheta(page);
    assert.match(await page.evaluate(() => window.mrvolDebug.thetaKey()), /:butterfly:.*:1:v1$/);
    const { index } = (await visibleHandles(page))[0];
    await dragHandle(page, index, 40, -20);
    const r = await readouts(page);
    assert.ok(r.error <= 1e-5, `relative error ${r.error}, last step ${JSON.stringify(await lastReport())}`);
    await shot('07-blob-level1-butterfly');
  });

  test('reset forgets the edits (asked first); a sample chosen in the panel replaces the model', { timeout: 120_000 }, async () => {
    // edits to forget: the question names them; declined, nothing changes
    const undoSteps = (await page.evaluate(() => window.mrvolDebug.historySize())).undo;
    assert.ok(undoSteps > 0);
    const asked = [];
    page.once('dialog', (d) => { asked.push(d.message()); d.dismiss(); });
    await page.locator('[data-testid="reset"]').click();
    await page.waitForTimeout(300);
    assert.match(asked[0] ?? '', /^Forget the edits of my-blob\.obj \(\d+ steps? of undo history\)\? They cannot be brought back\.$/);
    assert.equal((await page.evaluate(() => window.mrvolDebug.historySize())).undo, undoSteps, 'declined: the edits stay');
    page.once('dialog', (d) => { asked.push(d.message()); d.accept(); });
    await page.locator('[data-testid="reset"]').click();
    await page.waitForFunction(() => window.mrvolDebug.ready() && window.mrvolDebug.settings().level === 0);
    const r = await readouts(page);
    assert.ok(Math.abs(r.current - 5.74817906) < 1e-6, `volume after reset ${r.current}`);
    assert.equal(r.error < 1e-12, true);
    await page.locator('[data-testid="model-select"]').selectOption('torus');
    await page.waitForFunction(() => window.mrvolDebug.modelName() === 'torus' && window.mrvolDebug.ready());
    assert.equal(await page.evaluate(() => window.mrvolDebug.cageSize()), 24);
    assert.match(page.url(), /\?model=torus$/);
    assert.deepEqual(page.problems, []);
  });
});
