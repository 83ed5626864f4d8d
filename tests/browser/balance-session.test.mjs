// "Keep balance" and the surface switch (web/balance.js) as part of the editing session, in real
// Chromium: both are undo steps (Ctrl+Z / Ctrl+Shift+Z walk through them with the drags, the
// switches follow, a surface change brings its own reference volume back), both come back after a
// reload with the undo history (IndexedDB), and both travel in a share link and a project file.
import { after, before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { readFile } from 'node:fs/promises';
import { openApp, waitReady, settle, visibleHandles, dragHandle, readouts } from './harness.mjs';

let browser, page;
const debug = (p, name) => p.evaluate((n) => window.mrvolDebug[n](), name);
const switches = (p) => p.evaluate(() => ({
  keep: document.querySelector('[data-testid="keep-balance"]').checked,
  surface: document.querySelector('[data-testid="surface-select"]').value,
}));
/** Keys go to the page, not to the select that was just used. */
const key = async (combo) => {
  await page.evaluate(() => document.activeElement?.blur());
  await page.keyboard.press(combo);
  await settle(page);
};
async function dragOne(dx = 40, dy = -30) {
  const { index } = (await visibleHandles(page))[0];
  await dragHandle(page, index, dx, dy, { steps: 5 });
  await settle(page);
}
/** Waits until the stored session (IndexedDB) holds what the page shows: the save runs 150 ms after a change. */
const saved = () => page.waitForTimeout(600);

describe('keep balance and surface: undo, stored session, share link, project file', { timeout: 400_000 }, () => {
  before(async () => ({ browser, page } = await openApp({ viewport: { width: 1280, height: 800 } })));
  after(() => browser?.close());

  test('both switches are undo steps among the drags; the panel and settings follow', async () => {
    const meshReference = (await readouts(page)).reference;
    await page.check('[data-testid="keep-balance"]');
    await dragOne();
    await page.selectOption('[data-testid="surface-select"]', 'limit');
    await page.waitForFunction(() => document.querySelector('[data-testid="keep-balance"]').disabled); // switched
    await settle(page);
    const limitReference = (await readouts(page)).reference;
    assert.ok(Math.abs(limitReference - meshReference) > 1e-4 * meshReference, 'the limit surface has its own volume');
    await dragOne(-30, 20);
    assert.deepEqual(await debug(page, 'historySize'), { undo: 4, redo: 0 });

    await key('Control+z'); // the limit drag
    await key('Control+z'); // back to the mesh surface, balance on again
    assert.deepEqual(await switches(page), { keep: true, surface: 'mesh' });
    assert.equal((await readouts(page)).reference, meshReference, "the mesh's reference volume is back");
    assert.equal((await debug(page, 'settings')).surface, 'mesh');
    await key('Control+z'); // the drag with balance kept
    await key('Control+z'); // balance off
    assert.deepEqual(await switches(page), { keep: false, surface: 'mesh' });
    assert.equal((await debug(page, 'settings')).keepBalance, false);

    for (let i = 0; i < 4; i++) await key('Control+Shift+z');
    assert.deepEqual(await switches(page), { keep: false, surface: 'limit' });
    const r = await readouts(page);
    assert.equal(r.reference, limitReference);
    assert.ok(r.error < 1e-5, `the limit volume is kept (${r.error})`);
    assert.deepEqual(await debug(page, 'settings'), { ...(await debug(page, 'settings')), surface: 'limit', keepBalance: false });
    assert.deepEqual(page.problems, []);
  });

  test('a reload brings the surface, the balance switch and their undo steps back', async () => {
    const { reference } = await readouts(page);
    const cage = await debug(page, 'cagePositions');
    await saved();
    await page.reload();
    await waitReady(page);
    assert.deepEqual(await switches(page), { keep: false, surface: 'limit' });
    assert.equal((await readouts(page)).reference, reference);
    const again = await debug(page, 'cagePositions');
    assert.ok(again.length === cage.length && again.every((x, i) => Math.abs(x - cage[i]) < 1e-9), 'the edited cage is back (found again from the fine positions)');
    await key('Control+z'); // the limit drag
    await key('Control+z'); // the surface change
    assert.deepEqual(await switches(page), { keep: true, surface: 'mesh' });
    await saved();
    await page.reload();
    await waitReady(page);
    assert.deepEqual(await switches(page), { keep: true, surface: 'mesh' });
    assert.deepEqual(page.problems, []);
  });

  test('a share link carries balance and surface', async () => {
    for (const expected of [{ keep: true, surface: 'mesh' }, { keep: false, surface: 'limit' }]) {
      if (expected.surface === 'limit') {
        await page.selectOption('[data-testid="surface-select"]', 'limit');
        // the switch is async (the limit surface's editor is made): done when balance is switched off with it
        await page.waitForFunction(() => document.querySelector('[data-testid="keep-balance"]').disabled);
      }
      await settle(page);
      const { reference } = await readouts(page);
      await page.locator('[data-testid="share-link"]').click();
      await page.waitForFunction(() => document.querySelector('[data-testid="share-url"]').value.includes('edits='));
      const url = await page.locator('[data-testid="share-url"]').inputValue();
      assert.equal(new URL(url).searchParams.get('balance'), expected.keep ? '1' : null);
      await page.locator('#share-close').click();
      const other = await browser.context.newPage();
      try {
        await other.goto(url);
        await waitReady(other);
        assert.deepEqual(await switches(other), expected);
        assert.equal(Number(await other.locator('[data-testid="volume-reference"]').getAttribute('data-value') ??
          await other.locator('[data-testid="volume-reference"]').textContent()), reference);
        assert.doesNotMatch(other.url(), /balance=|surface=/, 'applied, the link parameters are dropped');
      } finally {
        await other.close();
      }
    }
  });

  test('a project file carries balance and surface', async () => {
    await page.selectOption('[data-testid="surface-select"]', 'mesh');
    await page.check('[data-testid="keep-balance"]');
    await settle(page);
    const [download] = await Promise.all([page.waitForEvent('download'), page.locator('[data-testid="save-project"]').click()]);
    const text = await readFile(await download.path(), 'utf8');
    assert.deepEqual([JSON.parse(text).settings.keepBalance, JSON.parse(text).settings.surface], [true, 'mesh']);
    await page.uncheck('[data-testid="keep-balance"]');
    await page.locator('[data-testid="model-select"]').selectOption('torus');
    await page.waitForFunction(() => window.mrvolDebug.modelName() === 'torus' && window.mrvolDebug.ready());
    await page.locator('[data-testid="open-file"]').setInputFiles({ name: 'ball.mrvol.json', mimeType: 'application/json', buffer: Buffer.from(text) });
    await page.waitForFunction(() => window.mrvolDebug.modelName() === 'spiky-ball' && window.mrvolDebug.ready());
    assert.deepEqual(await switches(page), { keep: true, surface: 'mesh' });
    assert.deepEqual(page.problems, []);
  });
});
