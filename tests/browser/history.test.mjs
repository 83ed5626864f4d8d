// Undo and redo in the editor over everything that changes the shape or the reference: drags,
// level and scheme changes (the history is kept; undoing one goes back to the earlier cage),
// reference resets and preservation toggles. Turning preservation back on asks: restore the
// reference volume now, or keep the current volume as the new reference.
import { after, before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { openApp, readouts, visibleHandles, dragHandle, settle, RESULTS_DIR } from './harness.mjs';

let browser, page;
const debug = (name) => page.evaluate((n) => window.mrvolDebug[n](), name);
const relative = (a, b) => Math.abs(a - b) / Math.abs(b);

async function dragSome(dx = 40, dy = -30) {
  const { index } = (await visibleHandles(page))[0];
  await dragHandle(page, index, dx, dy);
}

describe('web editor: undo and redo over everything', { timeout: 300_000 }, () => {
  before(async () => ({ browser, page } = await openApp()));
  after(() => browser?.close());

  test('a level change keeps the history; undo walks back through it, the panel follows', { timeout: 120_000 }, async () => {
    const original = await debug('cagePositions');
    await dragSome();
    const level0 = await debug('cagePositions');
    await page.locator('[data-testid="level"]').selectOption('1');
    await page.waitForFunction(() => window.mrvolDebug.cageSize() > 12);
    await dragSome(-30, 20);
    await page.locator('[data-testid="scheme"]').selectOption('butterfly');
    await page.waitForFunction(() => window.mrvolDebug.settings().scheme === 'butterfly');
    assert.deepEqual(await debug('historySize'), { undo: 4, redo: 0 });

    await page.keyboard.press('Control+z'); // scheme
    assert.equal(await page.locator('[data-testid="scheme"]').inputValue(), 'loop');
    await page.keyboard.press('Control+z'); // level-1 drag
    await page.keyboard.press('Control+z'); // level
    assert.equal(await page.locator('[data-testid="level"]').inputValue(), '0');
    assert.equal(await debug('cageSize'), 12);
    const back = await debug('cagePositions');
    assert.ok(back.every((x, i) => Math.abs(x - level0[i]) < 1e-9), 'the level-0 edit is back');
    await page.keyboard.press('Control+z'); // level-0 drag
    const start = await debug('cagePositions');
    assert.ok(start.every((x, i) => Math.abs(x - original[i]) < 1e-9));
    for (let i = 0; i < 4; i++) await page.keyboard.press('Control+Shift+z');
    assert.equal(await page.locator('[data-testid="scheme"]').inputValue(), 'butterfly');
    assert.equal(await page.locator('[data-testid="level"]').inputValue(), '1');
    assert.deepEqual(await debug('historySize'), { undo: 4, redo: 0 });
    assert.ok((await readouts(page)).error <= 1e-5);
  });

  test('preservation back on asks; "restore" brings the reference volume back (undoable), "keep" takes the current one', { timeout: 120_000 }, async () => {
    const preserve = page.locator('[data-testid="preserve"]');
    await preserve.uncheck();
    await dragSome(50, -40);
    const changed = await readouts(page);
    assert.ok(changed.error > 1e-4, `the volume changed: ${changed.error}`);
    await preserve.check();
    const dialog = page.locator('[data-testid="preserve-dialog"]');
    await dialog.waitFor({ state: 'visible' });
    await settle(page);
    await page.screenshot({ path: join(RESULTS_DIR, 'history-01-preserve-dialog.png') });
    await page.locator('[data-testid="preserve-restore"]').click();
    await dialog.waitFor({ state: 'hidden' });
    const restored = await readouts(page);
    assert.ok(restored.error <= 1e-5, `restored: ${restored.error}`);
    assert.equal(restored.reference, changed.reference);

    await page.keyboard.press('Control+z'); // the restoring step
    assert.ok(relative(await debug('volume'), changed.current) < 1e-12);
    await page.keyboard.press('Control+z'); // preservation on
    assert.equal(await preserve.isChecked(), false);
    await page.keyboard.press('Control+Shift+z');
    assert.equal(await preserve.isChecked(), true);

    // off the reference again, then keep the current volume as the new one
    await preserve.uncheck();
    await dragSome(-40, 30);
    const grown = await debug('volume');
    await preserve.check();
    await dialog.waitFor({ state: 'visible' });
    await page.locator('[data-testid="preserve-keep"]').click();
    await dialog.waitFor({ state: 'hidden' });
    assert.equal(await debug('referenceVolume'), grown);
    await page.keyboard.press('Control+z');
    assert.equal(await debug('referenceVolume'), changed.reference, 'undo gives the old reference back');
    assert.deepEqual(page.problems, []);
  });

  test('"reference = current volume" is one undo step', { timeout: 60_000 }, async () => {
    const reference = await debug('referenceVolume');
    await page.locator('[data-testid="preserve"]').uncheck();
    await dragSome(30, 30);
    const volume = await debug('volume');
    await page.locator('[data-testid="set-reference"]').click();
    assert.equal(await debug('referenceVolume'), volume);
    await page.keyboard.press('Control+z');
    assert.equal(await debug('referenceVolume'), reference);
  });

  test('a full history says so once: the 201st step lets the oldest go', { timeout: 180_000 }, async () => {
    const noticeText = () => page.locator('[data-testid="notice"]').textContent();
    await page.evaluate(() => { document.querySelector('[data-testid="notice"]').textContent = ''; });
    const canvas = page.locator('#view canvas');
    await canvas.focus();
    await page.keyboard.press('Escape');
    await page.keyboard.press('Tab'); // handle 0, nudged by the arrow keys: one step each
    let { undo } = await debug('historySize');
    const keys = ['ArrowLeft', 'ArrowUp', 'ArrowRight', 'ArrowDown'];
    for (let k = 0; undo < 200; k++, undo++) await page.keyboard.press(keys[k % 4]);
    assert.deepEqual(await debug('historySize'), { undo: 200, redo: 0 });
    assert.doesNotMatch(await noticeText(), /Undo keeps/, 'not yet: nothing let go');
    await page.keyboard.press('ArrowLeft');
    assert.deepEqual(await debug('historySize'), { undo: 200, redo: 0 });
    assert.match(await noticeText(), /^Undo keeps the last 200 steps: from now on the oldest edit of spiky-ball cannot be undone/);
    await page.evaluate(() => { document.querySelector('[data-testid="notice"]').textContent = ''; });
    await page.keyboard.press('ArrowUp');
    assert.equal(await noticeText(), '', 'said once');
    assert.deepEqual(await debug('historySize'), { undo: 200, redo: 0 });
  });
});
