// A big model's editor is made off the page's thread whatever the settings (issue 13: "no long
// computation or hand-off on the main thread"): with "keep balance" (the centre of mass kept), the
// limit surface or the tensor path, a level change (and its undo) and a change of the gradient path
// are made in the editor worker and swapped in with the undo history kept, progress shown; the
// editor in use is the worker's, keeping what the settings say. The session's first save hands the
// file to the store's worker as the File it was opened from (read there, not copied on the page).
// The model: the spiky ball subdivided four more times (164k vertices, over the 100k-vertex rule).
import { after, before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { openApp, visibleHandles, dragHandle, settle, root, RESULTS_DIR } from './harness.mjs';

let browser, page, scratch, bigObj;
const debug = (name) => page.evaluate((n) => window.mrvolDebug[n](), name);

/** Runs `change` and waits for the editor it makes in the worker: progress shown, stages on their threads. */
async function rebuiltInWorker(change, what) {
  await page.evaluate(() => {
    window.busyTexts = [];
    window.busyObserver = new MutationObserver(() => {
      const text = document.querySelector('#busy-text').textContent;
      if (!document.querySelector('#busy').hidden && window.busyTexts.at(-1) !== text) window.busyTexts.push(text);
    });
    window.busyObserver.observe(document.querySelector('#busy'), { subtree: true, childList: true, characterData: true, attributes: true });
  });
  await change();
  await page.waitForFunction((what) => {
    const s = window.mrvolDebug.openStages();
    return window.busyTexts.some((t) => t.startsWith('Making the level')) && s.what === what &&
      s.stages.some((x) => x.stage === 'editor swapped in (cage, view)') && window.mrvolDebug.ready() && document.querySelector('#busy').hidden;
  }, what, { timeout: 300_000 });
  const texts = await page.evaluate(() => (window.busyObserver.disconnect(), window.busyTexts));
  assert.ok(texts.some((t) => /^Making the level \d editor of spiky-164k\.obj/.test(t)), `progress shown: ${JSON.stringify(texts)}`);
  const { stages } = await debug('openStages');
  for (const [name, thread] of [['editor made', 'worker'], ['memory copied for the page', 'worker'], ['memory taken over (in slices)', 'page']])
    assert.ok(stages.some((s) => s.stage === name && s.thread === thread), `"${name}" in the ${thread}: ${JSON.stringify(stages)}`);
  assert.ok(!stages.some((s) => s.stage === 'editor made' && s.thread === 'page'));
  const editor = await debug('editorSettings');
  assert.equal(editor.madeElsewhere, true, 'the editor in use is the one the worker made');
  return editor;
}

describe('web editor: a big model\'s editor made in the worker with any settings', { timeout: 900_000 }, () => {
  before(async () => {
    scratch = mkdtempSync(join(tmpdir(), 'mrvol-rebuild-settings-'));
    const out = join(scratch, 'spiky-164k.obj');
    execFileSync(process.execPath, [join(root, 'bin/mrvol.mjs'), 'subdivide', join(root, 'public/models/spiky-ball.obj'), '--levels', '4', '-o', out],
      { stdio: 'pipe', timeout: 240_000 });
    bigObj = readFileSync(out);
    ({ browser, page } = await openApp({ viewport: { width: 1280, height: 800 } }));
  });

  after(async () => {
    await browser?.close();
    if (scratch) rmSync(scratch, { recursive: true, force: true });
  });

  test('the first save reads the file in the store\'s worker (its File), not on the page', { timeout: 400_000 }, async () => {
    await page.locator('[data-testid="open-file"]').setInputFiles({ name: 'spiky-164k.obj', mimeType: 'text/plain', buffer: bigObj });
    await page.waitForFunction(() => window.mrvolDebug.modelName() === 'spiky-164k.obj' && window.mrvolDebug.ready(), null, { timeout: 300_000 });
    assert.ok((await debug('modelFile')).vertices >= 100_000);
    await page.waitForFunction(() => window.mrvolDebug.openStages().stages.some((s) => s.stage === 'session saved: written to IndexedDB'), null, { timeout: 120_000 });
    const { what, stages } = await debug('openStages');
    assert.equal(what, 'opening spiky-164k.obj');
    const read = stages.filter((s) => s.stage === 'session saved: the file read from disk for IndexedDB');
    assert.equal(read.length, 1, JSON.stringify(stages));
    assert.equal(read[0].thread, 'worker');
    assert.equal(read[0].bytes, bigObj.byteLength, 'the whole file');
    assert.ok(stages.some((s) => s.stage === 'session saved: the page\'s part' && s.thread === 'page'));
    assert.equal(await page.locator('[data-testid="storage-problem"]').textContent(), '');
  });

  test('keep balance: a level change and its undo made in the worker, the centre of mass still kept', { timeout: 400_000 }, async () => {
    await page.check('[data-testid="keep-balance"]');
    const history = await debug('historySize');
    const level = (await debug('settings')).level, to = level === 0 ? 1 : 0;
    const made = await rebuiltInWorker(() => page.locator('[data-testid="level"]').selectOption(String(to)), `editor at level ${to}, loop`);
    assert.deepEqual({ surface: made.surface, keepsCentroid: made.keepsCentroid, level: made.level }, { surface: 'mesh', keepsCentroid: true, level: to });
    assert.deepEqual(await debug('historySize'), { undo: history.undo + 1, redo: 0 }, 'the level change is one more undo step');
    // a drag keeps the centre of mass with this editor
    const { index } = (await visibleHandles(page))[0];
    await dragHandle(page, index, 40, -25, { steps: 4 });
    await settle(page);
    await page.waitForFunction(() => document.querySelector('[data-testid="balance"]').dataset.drift !== undefined);
    const drift = Number(await page.locator('[data-testid="balance"]').getAttribute('data-drift'));
    assert.ok(drift < 1e-4, `the centre of mass stayed (moved ${drift} of the size)`);
    assert.ok((await debug('lastReport')).relativeError <= 1e-5);
    await page.screenshot({ path: join(RESULTS_DIR, 'rebuild-settings-balance.png') });
    // undo the drag here, then the level change: that editor made in the worker again
    await page.evaluate(() => document.activeElement?.blur());
    await page.keyboard.press('Control+z');
    const back = await rebuiltInWorker(() => page.keyboard.press('Control+z'), `editor at level ${level}, loop`);
    assert.equal(back.keepsCentroid, true);
    assert.deepEqual(await debug('historySize'), { undo: history.undo, redo: 2 });
    await page.uncheck('[data-testid="keep-balance"]');
  });

  test('the limit surface: the switch, a level change and the switch\'s undo made in the worker', { timeout: 600_000 }, async () => {
    const meshReference = await debug('referenceVolume'), history = await debug('historySize');
    const level0 = (await debug('settings')).level;
    const switched = await rebuiltInWorker(() => page.selectOption('[data-testid="surface-select"]', 'limit'), `editor at level ${level0}, loop`);
    assert.deepEqual({ surface: switched.surface, level: switched.level }, { surface: 'limit', level: level0 });
    assert.deepEqual(await debug('historySize'), { undo: history.undo + 1, redo: 0 }, 'the switch is one undo step');
    assert.equal(await page.locator('[data-testid="surface-select"]').inputValue(), 'limit');
    const reference = await debug('referenceVolume');
    assert.notEqual(reference, meshReference, 'the limit surface\'s own volume is its reference');
    const level = (await debug('settings')).level, to = level === 0 ? 1 : 0;
    const made = await rebuiltInWorker(() => page.locator('[data-testid="level"]').selectOption(String(to)), `editor at level ${to}, loop`);
    assert.deepEqual({ surface: made.surface, keepsCentroid: made.keepsCentroid, path: made.path }, { surface: 'limit', keepsCentroid: false, path: 'matrix-free' });
    assert.equal(await debug('referenceVolume'), reference, 'the limit surface\'s reference stays');
    const { index } = (await visibleHandles(page))[0];
    await dragHandle(page, index, -30, 20, { steps: 4 });
    const volume = await debug('volume');
    assert.ok(Math.abs(volume - reference) <= 1e-5 * Math.abs(reference), `the limit volume kept: ${volume} vs ${reference}`);
    // undo the drag and the level change, then the switch: the mesh editor made in the worker, its reference back
    await page.evaluate(() => document.activeElement?.blur());
    await page.keyboard.press('Control+z');
    await rebuiltInWorker(() => page.keyboard.press('Control+z'), `editor at level ${level0}, loop`);
    const back = await rebuiltInWorker(() => page.keyboard.press('Control+z'), `editor at level ${level0}, loop`);
    assert.equal(back.surface, 'mesh');
    assert.equal(await debug('referenceVolume'), meshReference, 'the mesh reference back');
    assert.equal(await page.locator('[data-testid="surface-select"]').inputValue(), 'mesh', 'the switch follows');
    assert.deepEqual(await debug('historySize'), { undo: history.undo, redo: 3 });
  });

  test('the gradient from θ (tensor path): the editor rebuilt on it in the worker', { timeout: 400_000 }, async () => {
    const history = await debug('historySize');
    const level = (await debug('settings')).level;
    const made = await rebuiltInWorker(() => page.selectOption('[data-testid="gradient"]', { label: 'volume tensor θ (the paper\'s)' }), `editor at level ${level}, loop`);
    assert.equal(made.level, level);
    assert.ok(['matrix-free', 'tensor'].includes(made.path), `matrix-free until θ comes: ${made.path}`);
    assert.deepEqual(await debug('historySize'), history, 'no undo step for the path');
    if (await page.locator('[data-testid="theta-progress"]').isVisible()) await page.locator('[data-testid="theta-cancel"]').click();
    const back = await rebuiltInWorker(() => page.selectOption('[data-testid="gradient"]', { label: 'cage polynomial' }), `editor at level ${level}, loop`);
    assert.equal(back.path, 'polynomial');
    assert.deepEqual(page.problems, []);
  });
  test('reopened after a reload with the limit surface stored: the file\'s worker makes that editor', { timeout: 600_000 }, async () => {
    if (await debug('modelName') !== 'spiky-164k.obj') {
      await page.locator('[data-testid="open-file"]').setInputFiles({ name: 'spiky-164k.obj', mimeType: 'text/plain', buffer: bigObj });
      await page.waitForFunction(() => window.mrvolDebug.modelName() === 'spiky-164k.obj' && window.mrvolDebug.ready(), null, { timeout: 300_000 });
    }
    const level = (await debug('settings')).level;
    if ((await debug('editorSettings')).surface !== 'limit')
      await rebuiltInWorker(() => page.selectOption('[data-testid="surface-select"]', 'limit'), `editor at level ${level}, loop`);
    const reference = await debug('referenceVolume');
    await page.waitForTimeout(1500); // the save (debounced) is written
    await page.reload();
    await page.waitForFunction(() => window.mrvolDebug.modelName() === 'spiky-164k.obj' && window.mrvolDebug.ready(), null, { timeout: 300_000 });
    assert.equal((await debug('modelFile')).editorFrom, 'worker', 'the editor taken from the file\'s worker');
    const editor = await debug('editorSettings');
    assert.deepEqual({ surface: editor.surface, madeElsewhere: editor.madeElsewhere, level: editor.level }, { surface: 'limit', madeElsewhere: true, level });
    assert.ok(Math.abs(await debug('referenceVolume') - reference) <= 1e-12 * Math.abs(reference), 'the limit surface\'s reference back');
    assert.equal(await page.locator('[data-testid="surface-select"]').inputValue(), 'limit');
    assert.deepEqual(page.problems, []);
  });
});
