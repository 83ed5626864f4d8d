// The editor's looks in real Chromium: a physically based surface lit by the room light, and a
// soft shadow of the model on a floor under it (web/floor-shadow.js) in both themes; the shadow is
// drawn again after a drag and goes with the mesh layer. Screenshots: test-results/looks-*.png.
import { after, before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { openApp, waitReady, settle, visibleHandles, dragHandle, RESULTS_DIR } from './harness.mjs';

let browser, page;
const shadow = () => page.evaluate(() => window.mrvolDebug.floorShadow());

describe('web editor: material, environment light and floor shadow', { timeout: 300_000 }, () => {
  before(async () => ({ browser, page } = await openApp({ viewport: { width: 1280, height: 800 } })));
  after(() => browser?.close());

  for (const scheme of ['light', 'dark']) {
    test(`${scheme} theme: the room lights the surface and the shadow darkens the floor under the model`, async () => {
      await page.emulateMedia({ colorScheme: scheme });
      await page.reload();
      await waitReady(page);
      await settle(page);
      const room = await page.evaluate(() => window.mrvolDebug.roomLight());
      assert.ok(room.intensity > 0 && room.brightened > 0.2, `the room light brightens ${(100 * room.brightened).toFixed(2)}% of the view`);
      const s = await shadow();
      assert.equal(s.visible, true);
      assert.ok(s.updates >= 1, 'the shadow map was drawn');
      assert.ok(s.darkened > 0.01, `the shadow darkens ${(100 * s.darkened).toFixed(2)}% of the view`);
      await page.screenshot({ path: join(RESULTS_DIR, `looks-${scheme}.png`) });
      assert.deepEqual(page.problems, []);
    });
  }

  test('a drag draws the shadow again; hiding the mesh hides its shadow', async () => {
    const before = (await shadow()).updates;
    const { index } = (await visibleHandles(page))[0];
    await dragHandle(page, index, 50, 40, { steps: 4 });
    await settle(page);
    assert.ok((await shadow()).updates > before, 'the shadow follows the edit');
    await page.locator('[data-testid="show-mesh"]').uncheck();
    await settle(page);
    const hidden = await shadow();
    assert.equal(hidden.visible, false);
    assert.ok(hidden.darkened < 1e-4, `no shadow without the mesh (${hidden.darkened})`);
    await page.locator('[data-testid="show-mesh"]').check();
    assert.deepEqual(page.problems, []);
  });
});
