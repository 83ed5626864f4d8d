// Words in the editor: every control has a tooltip (in the teaching views too), the glossary (cage,
// level e, detail, theta, free set, tolerance) opens from the panel, and the readouts name their
// quantities in plain language with the symbol beside them.
import { after, before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { openApp, settle, RESULTS_DIR } from './harness.mjs';

let browser, page;

describe('web editor: tooltips, glossary, readout words', { timeout: 400_000 }, () => {
  before(async () => ({ browser, page } = await openApp()));
  after(() => browser?.close());

  test('every control on the page has a tooltip', async () => {
    // open every folder so that every control is on the page
    await page.evaluate(() => document.querySelectorAll('.lil-gui.closed > .lil-title, .lil-gui.closed > .title').forEach((t) => t.click()));
    const missing = await page.evaluate(() => {
      const controls = [...document.querySelectorAll('button, input, select, [role="button"], .lil-title, .title')]
        .filter((el) => el.type !== 'file' && !el.closest('dialog') && el.getClientRects().length > 0);
      return controls.filter((el) => !el.closest('[title]')?.title?.trim())
        .map((el) => `${el.tagName} ${el.dataset.testid ?? el.id ?? ''} "${el.textContent.trim().slice(0, 30)}"`);
    });
    assert.deepEqual(missing, []);
    const count = await page.evaluate(() => document.querySelectorAll('[data-testid="panel"] [title]').length);
    assert.ok(count >= 25, `${count} titled panel elements`);
  });

  test('the glossary opens from the panel and explains the terms', async () => {
    await page.locator('[data-testid="glossary"]').click();
    const dialog = page.locator('[data-testid="glossary-dialog"]');
    await dialog.waitFor({ state: 'visible' });
    const terms = await dialog.locator('dt').allTextContents();
    for (const term of ['cage', 'level e', 'detail', 'volume tensor θ', 'free set', 'tolerance'])
      assert.ok(terms.some((t) => t.replace(/\s+/g, ' ').trim() === term), `glossary term ${term} in ${terms}`);
    await settle(page);
    await page.screenshot({ path: join(RESULTS_DIR, 'words-01-glossary.png') });
    await page.locator('[data-testid="glossary-close"]').click();
    await dialog.waitFor({ state: 'hidden' });
  });

  test('readouts in plain language with their symbols', async () => {
    const labels = await page.locator('[data-testid="readouts"] th').allTextContents();
    const text = labels.join(' | ');
    for (const words of ['volume to keep V₀', 'volume now V', 'difference |V−V₀|/V₀', 'volume tensor θ', 'handles that move (free set)'])
      assert.ok(text.includes(words), `"${words}" in ${text}`);
    assert.doesNotMatch(await page.locator('[data-testid="readouts"]').textContent(), /M entries|\bit,/);
    const approx = await page.locator('[data-testid="approx-level-row"]').textContent();
    assert.match(approx, /approximation level l/);
  });
  test('every control of every teaching view has a tooltip, the nav links too; the level buttons made later as well', { timeout: 240_000 }, async () => {
    const views = ['learn/levels', 'demo/ball', 'demo/skinning', 'learn/tensor', 'demo/bunny', 'demo/balance', 'learn/lifting'];
    for (const view of views) {
      await page.goto(`${browser.url}#${view}`);
      await page.waitForFunction(() => window.mrvolLearn?.ready(), null, { timeout: 90_000 });
      await page.locator('.learn-readouts td').first().waitFor({ timeout: 60_000 });
      if (view === 'learn/levels') await page.locator('[data-testid="levels-compare"]').check(); // rebuilds the view's controls
      const missing = await page.evaluate(() => [...document.querySelectorAll('#learn button, #learn input, #learn select, #learn a')]
        .filter((el) => el.getClientRects().length > 0 && !el.closest('[title]')?.title?.trim())
        .map((el) => `${el.tagName} ${el.dataset.testid ?? ''} "${el.textContent.trim().slice(0, 30)}"`));
      assert.deepEqual(missing, [], `#${view}`);
    }
    const routes = await page.locator('[data-testid="learn-nav"] a[data-route]').evaluateAll((links) => links.map((a) => a.dataset.route));
    assert.deepEqual(routes.sort(), [...views].sort(), 'every view of the nav bar checked');
  });
});
