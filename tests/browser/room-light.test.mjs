// The room light's coefficients (web/room-light.js) against the room measured now in Chromium from
// the three.js in node_modules (web/room-light-measure.js): a three.js update that changes its
// RoomEnvironment fails here, with the coefficients to keep.
import { after, before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { launch } from './harness.mjs';
import { ROOM_LIGHT_SH } from '../../web/room-light.js';

let browser, page;

describe('the room light', { timeout: 120_000 }, () => {
  before(async () => {
    browser = await launch();
    page = await browser.newPage();
    await page.goto(browser.url);
  });
  after(() => browser?.close());

  test('its spherical harmonics are the room three.js draws (within 0.02 of each)', async () => {
    // the dev server resolves the module's imports (three) as it does the app's
    const measured = await page.evaluate(async () => (await import('/room-light-measure.js')).measureRoomLight());
    assert.equal(measured.length, ROOM_LIGHT_SH.length);
    const far = measured.flatMap((rgb, i) => rgb.map((x, k) => ({ i, k, x })).filter(({ x }) => !(Math.abs(x - ROOM_LIGHT_SH[i]) <= 0.02)));
    assert.deepEqual(far, [], `the room measured now: ${JSON.stringify(measured.map((rgb) => +rgb[0].toFixed(6)))} (grey: ${measured.every(([r, g, b]) => r === g && g === b)}); web/room-light.js keeps ${JSON.stringify(ROOM_LIGHT_SH)}`);
    assert.deepEqual(page.problems, []);
  });
});
