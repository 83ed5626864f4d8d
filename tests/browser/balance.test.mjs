// Keep balance and the surface switch in the editor (web/balance.js), and the #demo/balance view
// (web/learn/balance.js), in real Chromium: the switches reach the core (the centre of mass stays
// put over a drag with balance kept, and moves without; the limit surface's volume is what the
// readouts keep), the marker is drawn, and the demo's kept centre stays put while the other one
// drifts. Screenshots go to test-results/balance-*.png at 1280x800 and 390x844.
import { after, before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { openApp, settle, waitReady, visibleHandles, dragHandle, readouts, RESULTS_DIR } from './harness.mjs';

let browser, page;

const balance = () => page.evaluate(() => {
  const box = document.querySelector('[data-testid="balance"]');
  return {
    keep: document.querySelector('[data-testid="keep-balance"]').checked,
    keepDisabled: document.querySelector('[data-testid="keep-balance"]').disabled,
    surface: document.querySelector('[data-testid="surface-select"]').value,
    readout: document.querySelector('[data-testid="centroid-readout"]').textContent,
    centroid: box.dataset.centroid ? JSON.parse(box.dataset.centroid) : null,
    baseline: box.dataset.baseline ? JSON.parse(box.dataset.baseline) : null,
    drift: Number(box.dataset.drift),
  };
});
const distance = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);

async function dragSomeHandle() {
  const handles = await visibleHandles(page);
  assert.ok(handles.length > 0, 'a handle is visible');
  await dragHandle(page, handles[0].index, 60, -45);
  await settle(page);
  await settle(page);
}

describe('keep balance and surface in the editor', { timeout: 240_000 }, () => {
  before(async () => ({ browser, page } = await openApp({ viewport: { width: 1280, height: 800 } })));
  after(() => browser?.close());

  test('keep balance: the centre of mass stays put over a drag; without it it moves', async () => {
    let b = await balance();
    assert.equal(b.keep, false);
    assert.equal(b.surface, 'mesh');
    assert.ok(b.centroid, 'the centre of mass is drawn');
    await page.check('[data-testid="keep-balance"]');
    await settle(page);
    b = await balance();
    assert.equal(b.keep, true);
    const start = b.centroid;
    await dragSomeHandle();
    b = await balance();
    const r = await readouts(page);
    assert.ok(r.error < 1e-5, `volume kept (${r.error})`);
    assert.ok(b.drift < 1e-5, `kept: moved ${b.drift} of the size`);
    assert.ok(distance(b.centroid, start) < 1e-5, 'the marker stayed');
    assert.match(b.readout, /kept/);
    await page.screenshot({ path: join(RESULTS_DIR, 'balance-editor-kept.png') });
    // Without it the same kind of drag moves the centre.
    await page.uncheck('[data-testid="keep-balance"]');
    await dragSomeHandle();
    b = await balance();
    assert.ok(b.drift > 1e-4, `free: moved ${b.drift} of the size`);
    assert.match(b.readout, /free/);
    assert.deepEqual(page.problems, []);
  });

  test('surface limit: the readouts keep the limit surface volume; balance is off for it', async () => {
    await page.check('[data-testid="keep-balance"]');
    const meshVolume = (await readouts(page)).current;
    await page.selectOption('[data-testid="surface-select"]', 'limit');
    await settle(page);
    let b = await balance();
    assert.equal(b.surface, 'limit');
    assert.equal(b.keep, false, 'balance is for the mesh surface only');
    assert.equal(b.keepDisabled, true);
    let r = await readouts(page);
    const reference = r.reference;
    await dragSomeHandle();
    r = await readouts(page);
    assert.ok(r.error < 1e-5, `limit volume kept (${r.error})`);
    assert.equal(r.reference, reference);
    // The reference is the limit surface's volume of the shape, not the mesh's: they differ.
    assert.ok(Math.abs(reference - meshVolume) > 1e-3 * meshVolume, `limit ${reference} vs mesh ${meshVolume}`);
    await page.screenshot({ path: join(RESULTS_DIR, 'balance-editor-limit.png') });
    await page.selectOption('[data-testid="surface-select"]', 'mesh');
    await settle(page);
    b = await balance();
    assert.equal(b.surface, 'mesh');
    assert.equal(b.keepDisabled, false);
    assert.deepEqual(page.problems, []);
  });

  test('phone layout: the switches are reachable', async () => {
    await page.setViewportSize({ width: 390, height: 844 });
    await page.reload();
    await waitReady(page);
    await page.locator('[data-testid="keep-balance"]').scrollIntoViewIfNeeded();
    assert.ok(await page.isVisible('[data-testid="keep-balance"]'));
    await page.screenshot({ path: join(RESULTS_DIR, 'balance-editor-phone.png') });
    await page.setViewportSize({ width: 1280, height: 800 });
  });
});

describe('#demo/balance', { timeout: 240_000 }, () => {
  before(async () => ({ browser, page } = await openApp({ goto: false, viewport: { width: 1280, height: 800 } })));
  after(() => browser?.close());

  test('the ears pulled: the kept centre stays, the other drifts; the chart shows both', async () => {
    await page.goto(`${browser.url}#demo/balance`);
    await page.waitForFunction(() => window.mrvolLearn?.route() === 'demo/balance' && window.mrvolLearn.ready(), null, { timeout: 60_000 });
    await page.evaluate(() => window.mrvolLearn.act('pause'));
    await page.evaluate(() => window.mrvolLearn.act('restart'));
    await page.evaluate(() => window.mrvolLearn.act('run', 63, 1 / 30));  // out to the widest pull (t = 2.1 s)
    await settle(page);
    const s = await page.evaluate(() => window.mrvolLearn.state());
    assert.equal(s.model, 'bunny-remeshed');
    assert.deepEqual(s.keeps, [false, true]);
    assert.equal(s.failures, 0);
    assert.ok(s.volumeError < 1e-5, `both keep the volume (${s.volumeError})`);
    assert.ok(s.maxDrift[1] < 2e-6, `kept: ${s.maxDrift[1]} (each coordinate to 1e-6 of the diagonal)`);
    assert.ok(s.maxDrift[0] > 1e-3, `free: ${s.maxDrift[0]}`);
    assert.ok(await page.isVisible('[data-testid="balance-chart"]'));
    await page.screenshot({ path: join(RESULTS_DIR, 'balance-demo.png') });
    await page.setViewportSize({ width: 390, height: 844 });
    await settle(page);
    await page.screenshot({ path: join(RESULTS_DIR, 'balance-demo-phone.png') });
    assert.deepEqual(page.problems, []);
  });
});
