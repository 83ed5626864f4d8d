// The teaching views and the paper's demos (web/learn/): each view opens from its URL, renders
// (a non-blank canvas), responds to its controls, and shows numbers from the core. Screenshots of
// every view go to test-results/learn-*.png. One server and one browser for the file.
import { after, before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { launch, settle, RESULTS_DIR } from './harness.mjs';

let browser, page;

async function open(route) {
  await page.goto(`${browser.url}#${route}`);
  await page.waitForFunction((r) => window.mrvolLearn?.route() === r && window.mrvolLearn.ready(), route, { timeout: 30_000 });
  await settle(page);
}

const state = () => page.evaluate(() => window.mrvolLearn.state());

async function shot(name) {
  await settle(page);
  await page.screenshot({ path: join(RESULTS_DIR, `learn-${name}.png`) });
}

/** Fraction of sampled canvas pixels that differ from the background colour. */
async function inkFraction() {
  await settle(page);
  return page.evaluate(() => {
    const canvas = document.querySelector('.learn-stage canvas');
    const probe = document.createElement('canvas');
    probe.width = 200;
    probe.height = 120;
    const g = probe.getContext('2d');
    g.drawImage(canvas, 0, 0, 200, 120);
    const data = g.getImageData(0, 0, 200, 120).data;
    let ink = 0;
    for (let i = 0; i < data.length; i += 4)
      if (Math.abs(data[i] - 0xf4) + Math.abs(data[i + 1] - 0xf5) + Math.abs(data[i + 2] - 0xf7) > 24) ink++;
    return ink / (data.length / 4);
  });
}

describe('teaching views', { timeout: 120_000 }, () => {
  before(async () => {
    browser = await launch();
    page = await browser.newPage();
  });
  after(async () => {
    await browser?.close();
  });

  test('#learn/levels: every level of the spiky ball, details, three schemes side by side', async () => {
    await open('learn/levels');
    let s = await state();
    assert.equal(s.model, 'spiky-ball');
    assert.equal(s.levels, 3);
    assert.ok(await inkFraction() > 0.05, 'the canvas shows the mesh');
    assert.match(await page.textContent('[data-testid="learn-text"]'), /section 2/);
    // Level 3 is the fine mesh: its approximation keeps every detail and the fine volume.
    await page.fill('[data-testid="levels-level"]', '3');
    await page.dispatchEvent('[data-testid="levels-level"]', 'input');
    s = await state();
    assert.equal(s.level, 3);
    assert.ok(Math.abs(s.volumes.loop[3] - s.fineVolume) < 1e-9 * s.fineVolume);
    // Zeroing the spikes' details leaves the round ball: the level-0 approximation is near the unit sphere's volume.
    assert.ok(Math.abs(s.volumes.loop[0] - 4 * Math.PI / 3) < 0.05, `volume at level 0 ${s.volumes.loop[0]}`);
    await page.click('[data-testid="bank-1"]');
    assert.equal((await state()).level, 1);
    assert.equal(await page.textContent('[data-testid="levels-cage-size"]'), '42');
    await shot('levels');
    await page.selectOption('[data-testid="levels-details"]', 'colour');
    await page.check('[data-testid="levels-compare"]');
    s = await state();
    assert.deepEqual(s.panels, ['loop: level 1', 'butterfly: level 1', 'linear: level 1']);
    assert.equal(s.volumes.butterfly.length, 4);
    assert.ok(await inkFraction() > 0.02);
    await shot('levels-compare');
    assert.deepEqual(page.problems, []);
  });

  test('#demo/ball: the squashed ball loses volume without preservation and keeps it with', async () => {
    await open('demo/ball');
    assert.match(await page.textContent('[data-testid="learn-text"]'), /Figure 6.*section 5/s);
    await page.click('[data-testid="demo-play"]'); // pause: the test drives the clock
    const before = await state();
    await page.evaluate(() => window.mrvolLearn.act('run', 150, 1 / 60)); // 2.5 s: the first impact
    const s = await state();
    assert.ok(s.steps >= before.steps + 150, `steps ${s.steps}`);
    assert.equal(s.failures, 0);
    assert.ok(s.minRatio < 0.9, `the free volume drops at the impact (min ratio ${s.minRatio})`);
    assert.ok(s.maxError <= 1.01e-5, `preserved volume within 1e-5 (worst ${s.maxError})`);
    assert.ok(await inkFraction() > 0.05);
    const chartInk = await page.evaluate(() => document.querySelector('[data-testid="volume-chart"]').width > 100);
    assert.ok(chartInk);
    await page.evaluate(() => window.mrvolLearn.act('runUntilSquashed', 0.25, 1 / 120));
    const squashed = await state();
    assert.ok(squashed.free < 0.8 * squashed.reference, 'stopped during an impact');
    assert.ok(Math.abs(squashed.preserved - squashed.reference) <= 1.01e-5 * squashed.reference);
    await shot('ball');
    assert.deepEqual(page.problems, []);
  });

  test('#demo/skinning: a skeleton drives the cage; linear blend skinning loses volume, the correction keeps it', async () => {
    await open('demo/skinning');
    assert.match(await page.textContent('[data-testid="learn-text"]'), /Figure 8.*section 5/s);
    await page.click('[data-testid="demo-play"]');
    let s = await state();
    assert.equal(s.vertices, 674);
    assert.equal(s.cageSize, 44);
    await page.evaluate(() => window.mrvolLearn.act('run', 75, 1 / 30)); // 2.5 s of animation
    s = await state();
    assert.equal(s.failures, 0);
    assert.ok(s.minRatio < 0.97, `skinning alone changes the volume (min ratio ${s.minRatio})`);
    assert.ok(s.maxError <= 1.01e-5, `preserved within 1e-5 (worst ${s.maxError})`);
    assert.ok(await inkFraction() > 0.03);
    await shot('skinning');
    assert.deepEqual(page.problems, []);
  });

  test('#learn/tensor: theta^l for l = n..0 read from the live tensors, blocks by depth and coarse count', async () => {
    await open('learn/tensor');
    assert.match(await page.textContent('[data-testid="learn-text"]'), /Figure 4.*section 3\.1/s);
    let s = await state();
    assert.equal(s.n, 2);
    assert.equal(s.N, 66);
    assert.deepEqual(s.levels.map((x) => x.level), [2, 1, 0]);
    for (const level of s.levels) {
      assert.equal(level.stored, level.nnzStored, 'every stored entry is read back from the file');
      assert.equal(6 * level.stored, level.nnzFull, 'alternating: six orderings per stored entry');
    }
    assert.deepEqual(s.levels[0].classCounts.slice(0, 3), [0, 0, 0], 'at the fine level every index is coarse');
    assert.ok(s.levels[2].classCounts[0] > 0 && s.levels[2].stored > s.levels[0].stored, 'theta^0 fills in, with detail-only entries');
    assert.equal(await page.locator('canvas[data-testid^="tensor-slab-"]').count(), 9);
    await shot('tensor');
    await page.selectOption('[data-testid="tensor-scheme"]', 'linear');
    await page.waitForFunction(() => window.mrvolLearn.state()?.scheme === 'linear');
    s = await state();
    assert.equal(6 * s.levels[2].stored, s.levels[2].nnzFull);
    assert.deepEqual(page.problems, []);
  });

  test('#demo/bunny: pulling two ears grows the free mesh, the preserved one keeps its volume; level e changes', async () => {
    await open('demo/bunny');
    assert.match(await page.textContent('[data-testid="learn-text"]'), /Figure 7.*section 5/s);
    await page.click('[data-testid="demo-play"]');
    let s = await state();
    assert.equal(s.ears.length, 2);
    await page.evaluate(() => window.mrvolLearn.act('run', 60, 1 / 30)); // 2 s: pulled out
    s = await state();
    assert.equal(s.failures, 0);
    assert.ok(s.maxRatio > 1.01, `the ears add volume (max ratio ${s.maxRatio})`);
    assert.ok(s.maxError <= 1.01e-5, `preserved within 1e-5 (worst ${s.maxError})`);
    await shot('bunny');
    await page.selectOption('[data-testid="bunny-level"]', '1');
    s = await state();
    assert.equal(s.level, 1);
    assert.ok(await inkFraction() > 0.03);
    assert.deepEqual(page.problems, []);
  });

  test('#learn/lifting: what one coefficient writes in a synthesis step and what reads a vertex in analysis', async () => {
    await open('learn/lifting');
    assert.match(await page.textContent('[data-testid="learn-text"]'), /Figure 3.*section 2/s);
    let s = await state();
    assert.equal(s.level, 1);
    assert.equal(s.vertex, 0);
    assert.equal(s.odd, false);
    assert.ok(s.touched > 1, `an even coefficient writes several vertices (${s.touched})`);
    assert.ok(s.weights.some((w) => w.vertex === 0), 'including itself');
    // An odd vertex, by clicking it on the canvas.
    await page.click('[data-testid="lifting-next-odd"]');
    s = await state();
    assert.equal(s.odd, true);
    const oddVertex = s.vertex;
    await page.click('[data-testid="lifting-next-even"]');
    assert.equal((await state()).odd, false);
    await page.evaluate((v) => window.mrvolLearn.act('pick', v), oddVertex); // the camera faces it
    await page.evaluate(() => window.mrvolLearn.act('pick', 0, false)); // another one picked, the camera stays
    assert.equal((await state()).vertex, 0);
    const [x, y] = await page.evaluate((v) => window.mrvolLearn.act('screenOf', v), oddVertex);
    await settle(page);
    await page.mouse.click(x, y);
    s = await state();
    assert.equal(s.vertex, oddVertex, 'a click picks the vertex under the pointer');
    // A detail writes its own vertex (P_o) and, through U and P_e, even vertices around it.
    assert.ok(s.weights.some((w) => w.vertex === oddVertex), 'the odd vertex itself');
    assert.ok(s.weights.some((w) => !w.odd), `even vertices too: ${JSON.stringify(s.weights.slice(0, 4))}`);
    await page.selectOption('[data-testid="lifting-mode"]', 'analysis');
    s = await state();
    assert.equal(s.mode, 'analysis');
    assert.ok(s.touched > 1);
    await shot('lifting');
    assert.deepEqual(page.problems, []);
  });

  test('navigation: the bar switches views, a learn URL in the editor opens it, the editor link goes back', async () => {
    await open('learn/tensor');
    await page.click('[data-testid="nav-demo-skinning"]');
    await page.waitForFunction(() => window.mrvolLearn.route() === 'demo/skinning' && window.mrvolLearn.ready());
    assert.equal(await page.locator('.learn-stage canvas').count(), 1, 'the previous view is gone');
    await page.goto(`${browser.url}#learn/nothing`);
    await page.waitForFunction(() => window.mrvolLearn?.ready());
    assert.match(await page.textContent('[data-testid="learn-text"]'), /no view 'learn\/nothing'/);
    await page.click('.learn-editor-link');
    await page.waitForFunction(() => window.mrvolDebug?.ready() === true, null, { timeout: 30_000 });
    assert.equal(await page.isVisible('[data-testid="readouts"]'), true, 'the editor is back');
    await page.evaluate(() => { location.hash = '#learn/levels'; });
    await page.waitForFunction(() => window.mrvolLearn?.route() === 'learn/levels' && window.mrvolLearn.ready(), null, { timeout: 30_000 });
    assert.equal(await page.isVisible('[data-testid="readouts"]'), false, 'the editor is hidden');
    assert.deepEqual(page.problems, []);
  });
});
