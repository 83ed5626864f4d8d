// The self-intersection warning: none for the spiky ball as it is; a handle dragged through the
// model (preservation off) folds the surface into itself and the warning names two triangles;
// undo clears it.
import { after, before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { openApp, dragHandle, settle } from './harness.mjs';

let browser, page;
const warning = () => page.locator('[data-testid="self-intersection"]').textContent();

describe('web editor: self-intersection warning', { timeout: 180_000 }, () => {
  before(async () => ({ browser, page } = await openApp()));
  after(() => browser?.close());

  test('a handle pulled through the model warns; undo clears the warning', async () => {
    await page.waitForFunction(() => document.querySelector('[data-testid="self-intersection"]').dataset.checkedMs !== undefined);
    assert.equal(await warning(), '');
    await page.locator('[data-testid="preserve"]').uncheck();
    // past the far side: the handle farthest from the centre, pulled across the whole model
    const points = await page.evaluate(() => window.mrvolDebug.cageScreenPositions());
    const cx = points.reduce((s, p) => s + p[0], 0) / points.length, cy = points.reduce((s, p) => s + p[1], 0) / points.length;
    let far = 0;
    points.forEach((p, i) => { if (Math.hypot(p[0] - cx, p[1] - cy) > Math.hypot(points[far][0] - cx, points[far][1] - cy)) far = i; });
    const [x, y] = points[far];
    await dragHandle(page, far, 2.2 * (cx - x), 2.2 * (cy - y), { steps: 10 });
    await settle(page);
    const moved = await page.evaluate(() => window.mrvolDebug.historySize());
    assert.equal(moved.undo, 2, `the drag was recorded: ${JSON.stringify(moved)}`);
    await page.waitForFunction(() => document.querySelector('[data-testid="self-intersection"]').textContent !== '', null, { timeout: 10_000 });
    assert.match(await warning(), /The surface intersects itself \(triangles \d+ and \d+\)/);
    await page.keyboard.press('Control+z');
    await settle(page);
    await page.waitForFunction(() => document.querySelector('[data-testid="self-intersection"]').textContent === '', null, { timeout: 10_000 });
    const ms = Number(await page.evaluate(() => document.querySelector('[data-testid="self-intersection"]').dataset.checkedMs));
    assert.ok(Number.isFinite(ms) && ms >= 0, `the check reports its time: ${ms} ms`);
    assert.deepEqual(page.problems, []);
  });
});
