// The editor's tools: `?` keyboard help, `F` frames the model, the volume chart, a PNG screenshot,
// a share link and a project file that restore the edits, links to the teaching views, the busy
// indicator while a big file opens, and handles from the keyboard (Tab selects, arrows nudge).
import { after, before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { readFile } from 'node:fs/promises';
import { join } from 'node:path';
import { createMrvol } from '../../lib/node.mjs';
import { openApp, waitReady, readouts, visibleHandles, dragHandle, settle, root } from './harness.mjs';

let browser, page;
const debug = (name) => page.evaluate((n) => window.mrvolDebug[n](), name);
const close = (a, b, tolerance) => a.length === b.length && a.every((x, i) => Math.abs(x - b[i]) <= tolerance);

describe('web editor: tools', { timeout: 400_000 }, () => {
  before(async () => ({ browser, page } = await openApp({ viewport: { width: 1280, height: 800 } })));
  after(() => browser?.close());

  test('? shows the keyboard help; F frames the model again after an orbit', async () => {
    await page.locator('#view canvas').click({ position: { x: 20, y: 20 } });
    await page.keyboard.press('?');
    const keys = page.locator('[data-testid="keys-dialog"]');
    await keys.waitFor({ state: 'visible' });
    assert.match(await keys.textContent(), /frame the model/);
    await page.keyboard.press('Escape');
    await keys.waitFor({ state: 'hidden' });

    const framed = await debug('cageScreenPositions');
    const box = await page.locator('#view canvas').boundingBox();
    await page.mouse.move(box.x + 30, box.y + 30);
    await page.mouse.down();
    await page.mouse.move(box.x + 200, box.y + 120, { steps: 6 });
    await page.mouse.up();
    await settle(page);
    assert.ok(!close(await debug('cageScreenPositions'), framed.flat(), 1), 'the orbit moved the view');
    await page.keyboard.press('f');
    await settle(page);
    const again = await debug('cageScreenPositions');
    assert.ok(close(again.flat(), framed.flat(), 0.5), 'F frames the model as at the start');
  });

  test('the volume chart follows the edits', async () => {
    const before = Number(await page.locator('[data-testid="volume-chart"]').getAttribute('data-points'));
    const { index } = (await visibleHandles(page))[0];
    await dragHandle(page, index, 30, -20, { steps: 5 });
    const after = Number(await page.locator('[data-testid="volume-chart"]').getAttribute('data-points'));
    assert.ok(after >= before + 5, `chart points ${before} -> ${after}`);
    assert.match(await page.locator('[data-testid="volume-chart"] title').textContent(), /now [\d.]+, to keep [\d.]+/);
  });

  test('a PNG screenshot downloads', async () => {
    const [download] = await Promise.all([page.waitForEvent('download'), page.locator('[data-testid="screenshot"]').click()]);
    assert.match(download.suggestedFilename(), /^spiky-ball\.png$/);
    const bytes = await readFile(await download.path());
    assert.deepEqual([...bytes.subarray(0, 8)], [0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a]);
    assert.ok(bytes.length > 5000, `${bytes.length} bytes`);
  });

  test('a share link opens the sample with its edits in a fresh page', async () => {
    const edited = await debug('cagePositions');
    await page.locator('[data-testid="share-link"]').click();
    await page.waitForFunction(() => document.querySelector('[data-testid="share-url"]').value.includes('edits='));
    const url = await page.locator('[data-testid="share-url"]').inputValue();
    const other = await browser.context.newPage();
    try {
      await other.goto(url);
      await waitReady(other);
      const shared = await other.evaluate(() => window.mrvolDebug.cagePositions());
      assert.ok(close(shared, edited, 1e-5), 'the shared cage is the edited one (float32 precision)');
      assert.doesNotMatch(other.url(), /edits=/, 'applied, the link parameters are dropped');
    } finally {
      await other.close();
    }
  });

  test('phone (390x844): the share link is scrolled into the view when the button far below it is pressed', async () => {
    // The sheet's Tools are below the readouts: the link box and its notice appeared 500-1000 px above
    // what was on screen, and the button seemed to do nothing.
    await page.setViewportSize({ width: 390, height: 844 });
    try {
      await page.evaluate(() => {
        document.getElementById('share').hidden = true;
        document.querySelector('[data-testid="share-url"]').value = '';
      });
      await page.locator('[data-testid="share-link"]').click();
      await page.waitForFunction(() => document.querySelector('[data-testid="share-url"]').value.includes('edits='));
      const field = await page.locator('[data-testid="share-url"]').boundingBox();
      assert.ok(field.y >= 0 && field.y + field.height <= 844, `the link's field at y ${field.y.toFixed(0)}..${(field.y + field.height).toFixed(0)}`);
      // Not under anything: the element at its centre is the field itself.
      const top = await page.evaluate(({ x, y }) => document.elementFromPoint(x, y)?.dataset.testid, { x: field.x + field.width / 2, y: field.y + field.height / 2 });
      assert.equal(top, 'share-url');
    } finally {
      await page.setViewportSize({ width: 1280, height: 800 });
    }
  });

  test('a project file saves and opens again with model, edits and settings', async () => {
    await page.locator('[data-testid="level"]').selectOption('1');
    await page.waitForFunction(() => window.mrvolDebug.cageSize() > 12);
    const { index } = (await visibleHandles(page))[0];
    await dragHandle(page, index, -25, 25, { steps: 4 });
    const edited = await debug('cagePositions');
    const [download] = await Promise.all([page.waitForEvent('download'), page.locator('[data-testid="save-project"]').click()]);
    assert.equal(download.suggestedFilename(), 'spiky-ball.mrvol.json');
    const text = await readFile(await download.path(), 'utf8');
    assert.equal(JSON.parse(text).format, 'mrvol-project');
    await page.locator('[data-testid="model-select"]').selectOption('torus');
    await page.waitForFunction(() => window.mrvolDebug.modelName() === 'torus' && window.mrvolDebug.ready());
    await page.locator('[data-testid="open-file"]').setInputFiles({ name: 'spiky-ball.mrvol.json', mimeType: 'application/json', buffer: Buffer.from(text) });
    await page.waitForFunction(() => window.mrvolDebug.modelName() === 'spiky-ball' && window.mrvolDebug.ready());
    assert.equal((await debug('settings')).level, 1);
    assert.ok(close(await debug('cagePositions'), edited, 1e-9));
    // a damaged project is refused in words, the model stays
    await page.locator('[data-testid="open-file"]').setInputFiles({ name: 'broken.json', mimeType: 'application/json', buffer: Buffer.from('{"format": "other"}') });
    await page.locator('[data-testid="error"]').waitFor({ state: 'visible' });
    assert.match(await page.locator('[data-testid="error-text"]').textContent(), /broken\.json is not an mrvol project/);
    await page.locator('#error-close').click();
  });

  test('Tab on the view selects handles, the arrow keys move them (volume kept, one undo step each)', async () => {
    const before = await debug('cagePositions');
    const history = await debug('historySize');
    await page.locator('#view canvas').focus();
    await page.keyboard.press('Tab');
    assert.deepEqual(await debug('selection'), [0]);
    await page.keyboard.press('Tab');
    assert.deepEqual(await debug('selection'), [1]);
    assert.match(await page.locator('#view canvas').getAttribute('aria-label'), /handle 1 selected/);
    await page.keyboard.press('Shift+ArrowRight');
    await page.keyboard.press('ArrowUp');
    const after = await debug('cagePositions');
    assert.ok(!close(after.slice(3, 6), before.slice(3, 6), 1e-9), 'handle 1 moved');
    assert.ok((await readouts(page)).error <= 1e-5);
    assert.equal((await debug('historySize')).undo, history.undo + 2);
  });

  // Each key the help lists (the drag keys: editor.test's Escape during a drag; ? and F above).
  test('every key of the help: ] [ Tab Shift+Tab, the four arrows and Shift, Esc, Ctrl+Z, Ctrl+Y, Ctrl+Shift+Z', async () => {
    const help = await page.locator('[data-testid="keys-dialog"] table').textContent();
    for (const key of ['Tab', 'Shift+Tab', ']', '[', 'arrow keys', 'Shift', 'Esc', 'Ctrl+Z', 'Ctrl+Shift+Z', 'Ctrl+Y', 'F', '?'])
      assert.ok(help.includes(key), `the help names ${key}`);
    const canvas = page.locator('#view canvas');
    await canvas.focus();
    await page.keyboard.press('Tab'); // a selection to clear (the test before may have left one)
    await page.keyboard.press('Escape');
    assert.deepEqual(await debug('selection'), [], 'Esc clears the selection');
    await page.keyboard.press(']');
    assert.deepEqual(await debug('selection'), [0]);
    await page.keyboard.press(']');
    assert.deepEqual(await debug('selection'), [1]);
    await page.keyboard.press('[');
    assert.deepEqual(await debug('selection'), [0]);
    await page.keyboard.press('Shift+Tab'); // before the first: the view lets the focus go
    assert.deepEqual(await debug('selection'), []);
    assert.equal(await canvas.evaluate((c) => document.activeElement === c), false);
    await canvas.focus();
    await page.keyboard.press('Tab');
    assert.deepEqual(await debug('selection'), [0]);
    // each arrow moves handle 0 by 2% of the radius, with Shift by 10%: the held handle goes exactly there
    const at = async () => (await debug('cagePositions')).slice(0, 3);
    const moves = [];
    for (const key of ['ArrowLeft', 'ArrowRight', 'ArrowUp', 'ArrowDown', 'Shift+ArrowLeft']) {
      const before = await at();
      await page.keyboard.press(key);
      const after = await at();
      moves.push(Math.hypot(after[0] - before[0], after[1] - before[1], after[2] - before[2]));
    }
    assert.ok(moves.slice(0, 4).every((m) => m > 0 && Math.abs(m / moves[0] - 1) < 1e-6), `the arrows move alike: ${moves}`);
    assert.ok(Math.abs(moves[4] / moves[0] - 5) < 1e-6, `Shift moves five times as far: ${moves}`);
    assert.ok((await readouts(page)).error <= 1e-5, 'the volume kept');
    const nudged = await at();
    const history = await debug('historySize');
    await page.keyboard.press('Control+z');
    assert.ok(!close(await at(), nudged, 1e-12), 'Ctrl+Z undoes the last nudge');
    assert.deepEqual(await debug('historySize'), { undo: history.undo - 1, redo: history.redo + 1 });
    await page.keyboard.press('Control+y');
    assert.ok(close(await at(), nudged, 1e-9), 'Ctrl+Y redoes it');
    await page.keyboard.press('Control+z');
    await page.keyboard.press('Control+Shift+z');
    assert.ok(close(await at(), nudged, 1e-9), 'Ctrl+Shift+Z redoes it too');
  });

  test('the teaching views are linked from the panel, and link back', async () => {
    const link = page.locator('[data-testid="learn-link-learn-levels"]');
    assert.equal(await link.getAttribute('href'), '#learn/levels');
    await link.evaluate((a) => a.click());
    await page.locator('[data-testid="learn"]').waitFor({ state: 'visible', timeout: 60_000 });
    assert.ok(await page.locator('a.learn-editor-link').count() === 1);
  });

  test('opening a big file shows the busy indicator', async () => {
    const mrvol = await createMrvol();
    const base = mrvol.readObj(await readFile(join(root, 'public/models/bunny-remeshed.obj'), 'utf8'));
    const fine = mrvol.subdivide(base, { levels: 2 });
    const obj = mrvol.writeObj(fine.toMesh());
    fine.delete();
    assert.ok(obj.length > 2_000_000);
    await page.goto(browser.url);
    await waitReady(page);
    await page.evaluate(() => {
      window.busySeen = '';
      const busy = document.querySelector('[data-testid="busy"]');
      new MutationObserver(() => { if (!busy.hidden) window.busySeen = busy.textContent; }).observe(busy, { attributes: true, subtree: true, childList: true, characterData: true });
    });
    await page.locator('[data-testid="open-file"]').setInputFiles({ name: 'bunny-fine.obj', mimeType: 'text/plain', buffer: Buffer.from(obj) });
    await page.waitForFunction(() => window.mrvolDebug.modelName() === 'bunny-fine.obj' && window.mrvolDebug.ready(), null, { timeout: 120_000 });
    assert.match(await page.evaluate(() => window.busySeen), /(Reading|Opening) bunny-fine\.obj \([\d.]+ MB\)/);
    assert.equal(await page.locator('[data-testid="busy"]').isVisible(), false);
    assert.deepEqual(page.problems, []);
  });
});
