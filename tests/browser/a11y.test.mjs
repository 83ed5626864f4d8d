// Accessibility and looks: an axe-core audit (no serious or critical violations) of the editor at a
// desktop and a phone size, in the light and the dark theme (prefers-color-scheme), with the
// dialogs open too; every control reachable by keyboard (Tab order reaches the panel's controls
// and the view); the view labelled; the dark theme really dark.
import { after, before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { createRequire } from 'node:module';
import { join } from 'node:path';
import { startTestServer, launchBrowser, waitReady, settle, RESULTS_DIR } from './harness.mjs';

const AXE = createRequire(import.meta.url).resolve('axe-core/axe.min.js');
const SIZES = { desktop: { width: 1280, height: 800 }, phone: { width: 390, height: 844 } };

let server;

async function audit(page, label) {
  await page.addScriptTag({ path: AXE });
  const result = await page.evaluate(() => window.axe.run(document, { resultTypes: ['violations'] }));
  const bad = result.violations.filter((v) => v.impact === 'serious' || v.impact === 'critical');
  assert.deepEqual(bad.map((v) => `${label}: ${v.id} (${v.impact}): ${v.help} — ${v.nodes.slice(0, 3).map((n) => n.target.join(' ')).join(' | ')}`), []);
}

describe('web editor: accessibility and themes', { timeout: 400_000 }, () => {
  before(async () => {
    server = await startTestServer();
  });
  after(async () => {
    await server?.close();
  });

  for (const [sizeName, viewport] of Object.entries(SIZES)) {
    for (const scheme of ['light', 'dark']) {
      test(`axe: ${sizeName}, ${scheme} theme: no serious or critical violations`, { timeout: 120_000 }, async () => {
        const browser = await launchBrowser(server.url, { viewport });
        try {
          const page = await browser.newPage();
          await page.emulateMedia({ colorScheme: scheme });
          await page.goto(server.url);
          await waitReady(page);
          await settle(page);
          await page.screenshot({ path: join(RESULTS_DIR, `a11y-${sizeName}-${scheme}.png`) });
          await audit(page, `${sizeName} ${scheme}`);
          const background = await page.evaluate(() => getComputedStyle(document.body).backgroundColor);
          const [r, g, b] = background.match(/\d+/g).map(Number);
          if (scheme === 'dark') assert.ok(r + g + b < 150, `dark background ${background}`);
          else assert.ok(r + g + b > 600, `light background ${background}`);
          // the dialogs pass too
          await page.locator('#view canvas').focus();
          await page.keyboard.press('?');
          await page.locator('[data-testid="keys-dialog"]').waitFor({ state: 'visible' });
          await audit(page, `${sizeName} ${scheme} keys dialog`);
          await page.keyboard.press('Escape');
          await page.evaluate(() => document.getElementById('glossary').showModal());
          await audit(page, `${sizeName} ${scheme} glossary`);
          await page.keyboard.press('Escape');
          // the teaching views too (drawn light in either theme: readable text on their white)
          for (const view of ['learn/levels', 'learn/tensor', 'learn/lifting', 'demo/bunny']) {
            await page.goto(`${server.url}#${view}`);
            await page.locator('[data-testid="learn"]').waitFor({ state: 'visible', timeout: 60_000 });
            await page.locator('.learn-readouts td').first().waitFor({ timeout: 60_000 });
            await settle(page);
            if (view === 'learn/levels') await page.screenshot({ path: join(RESULTS_DIR, `a11y-${sizeName}-${scheme}-learn-levels.png`) });
            await audit(page, `${sizeName} ${scheme} #${view}`);
          }
          assert.deepEqual(page.problems, []);
        } finally {
          await browser.close();
        }
      });
    }
  }

  test('every control is reachable with Tab, the view among them, and labelled', { timeout: 120_000 }, async () => {
    const browser = await launchBrowser(server.url, { viewport: SIZES.desktop });
    try {
      const page = await browser.newPage();
      await page.goto(server.url);
      await waitReady(page);
      const label = await page.locator('#view canvas').getAttribute('aria-label');
      assert.match(label, /3D view of spiky-ball: 12 handles/);
      await page.evaluate(() => document.querySelectorAll('.lil-gui.closed > .lil-title, .lil-gui.closed > .title').forEach((t) => t.click()));
      // Tab through the page (Tab on the view selects handles, so leave it with Tab past the last one)
      const reached = new Set();
      await page.locator('body').focus();
      for (let i = 0; i < 200; i++) {
        await page.keyboard.press('Tab');
        const id = await page.evaluate(() => {
          const el = document.activeElement;
          return el?.dataset.testid || el?.id || el?.tagName;
        });
        reached.add(id);
      }
      const controls = await page.evaluate(() => [...document.querySelectorAll('[data-testid]')]
        .filter((el) => el.matches('button, input, select') && el.type !== 'file' && !el.closest('dialog') && el.getClientRects().length > 0 && !el.disabled)
        .map((el) => el.dataset.testid));
      const missing = controls.filter((id) => !reached.has(id));
      assert.deepEqual(missing, [], 'controls Tab never reached');
      assert.ok(reached.has('CANVAS'), 'the view takes focus');
    } finally {
      await browser.close();
    }
  });
});
