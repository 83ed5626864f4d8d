// The teaching views as a user sees them at 1280 x 800 and on a 390 x 844 phone: models fill their
// panels, charts have round ticks, colour maps have legends, controls come before the explanation,
// nothing runs past the page; and what students learn from: a single wavelet, the coarser levels
// ghosted, tensor entries pointed at on a mesh, the correction's multiplier plotted during a drag.
// Screenshots go to test-results/learn-design-*.png. One server and one browser for the file.
import { after, before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { launch, openApp, settle, RESULTS_DIR } from './harness.mjs';

let browser, page;
const DESKTOP = { width: 1280, height: 800 }, PHONE = { width: 390, height: 844 };

async function open(route, viewport = DESKTOP) {
  await page.setViewportSize(viewport);
  await page.goto('about:blank'); // a fresh view, even when the address was this route already
  await page.goto(`${browser.url}#${route}`);
  await page.waitForFunction((r) => window.mrvolLearn?.route() === r && window.mrvolLearn.ready(), route, { timeout: 30_000 });
  await settle(page);
}

const state = () => page.evaluate(() => window.mrvolLearn.state());
const act = (name, ...args) => page.evaluate(([n, a]) => window.mrvolLearn.act(n, ...a), [name, args]);

async function shot(name) {
  await settle(page);
  await page.screenshot({ path: join(RESULTS_DIR, `learn-design-${name}.png`) });
}

/** Fraction of the pixels of each panel cell (stage CSS pixels) that differ from the background. */
async function inkPerCell(cells) {
  await settle(page);
  return page.evaluate((cells) => {
    const canvas = document.querySelector('.learn-stage canvas');
    const scale = canvas.width / canvas.clientWidth;
    const probe = document.createElement('canvas');
    probe.width = 100;
    probe.height = 100;
    const g = probe.getContext('2d');
    return cells.map((c) => {
      g.clearRect(0, 0, 100, 100);
      g.drawImage(canvas, c.x * scale, c.y * scale, c.width * scale, c.height * scale, 0, 0, 100, 100);
      const data = g.getImageData(0, 0, 100, 100).data;
      let ink = 0;
      for (let i = 0; i < data.length; i += 4)
        if (Math.abs(data[i] - 0xf4) + Math.abs(data[i + 1] - 0xf5) + Math.abs(data[i + 2] - 0xf7) > 24) ink++;
      return ink / 10_000;
    });
  }, cells);
}

/** Round ticks: equal steps of 1, 2 or 5 x 10^k, every tick a multiple of the step. */
function assertRoundTicks(ticks, what) {
  assert.ok(ticks.length >= 3, `${what}: ${ticks.length} ticks`);
  const step = ticks[1] - ticks[0];
  const mantissa = step / 10 ** Math.floor(Math.log10(step) + 1e-9);
  assert.ok([1, 2, 5].some((m) => Math.abs(mantissa - m) < 1e-6), `${what}: step ${step}`);
  for (const [i, t] of ticks.entries()) {
    assert.ok(Math.abs(t / step - Math.round(t / step)) < 1e-6, `${what}: tick ${t} is a multiple of ${step}`);
    if (i) assert.ok(Math.abs(t - ticks[i - 1] - step) < 1e-9 * Math.max(1, Math.abs(t)), `${what}: equal steps`);
  }
}

/** Nothing wider than the viewport; the panel's boxes stay inside the page. */
async function assertFits(viewport, what) {
  const overflow = await page.evaluate(() => {
    const wide = [];
    for (const e of document.querySelectorAll('#learn *')) {
      const r = e.getBoundingClientRect();
      if (r.width > 0 && r.right > window.innerWidth + 1 && !e.closest('.learn-nav')) wide.push(`${e.tagName}.${e.className} ${e.dataset.testid ?? ''} right ${Math.round(r.right)}`);
    }
    return { wide: wide.slice(0, 5), scroll: document.scrollingElement.scrollWidth };
  });
  assert.deepEqual(overflow.wide, [], `${what} at ${viewport.width} px: nothing runs past the page`);
  assert.ok(overflow.scroll <= viewport.width, `${what}: no sideways scrolling (${overflow.scroll})`);
}

/** The first control is above the first paragraph of explanation. */
async function assertControlsFirst(what) {
  const [controls, text] = await page.evaluate(() => [
    document.querySelector('[data-testid="learn-controls"]').getBoundingClientRect().top,
    document.querySelector('[data-testid="learn-text"] p').getBoundingClientRect().top,
  ]);
  assert.ok(controls < text, `${what}: controls (${controls}) above the explanation (${text})`);
}

describe('teaching views on a touch phone', { timeout: 180_000 }, () => {
  let touchBrowser;
  before(async () => (touchBrowser = await launch({ viewport: PHONE, touch: true })));
  after(() => touchBrowser?.close());

  test('every control of every view is a target of 24 px or more (a checkbox: its row); links in the text excepted', async () => {
    const touchPage = await touchBrowser.newPage();
    const small = [];
    for (const route of ['learn/levels', 'learn/lifting', 'learn/tensor', 'demo/ball', 'demo/bunny', 'demo/skinning', 'demo/balance']) {
      await touchPage.goto('about:blank');
      await touchPage.goto(`${touchBrowser.url}#${route}`);
      await touchPage.waitForFunction((r) => window.mrvolLearn?.route() === r && window.mrvolLearn.ready(), route, { timeout: 30_000 });
      small.push(...await touchPage.evaluate((r) => {
        const out = [];
        for (const e of document.querySelectorAll('#learn button, #learn a[href], #learn input, #learn select')) {
          if (e.closest('p')) continue; // a link inside a sentence (WCAG's inline exception)
          const target = e.type === 'checkbox' ? e.closest('label') ?? e : e;
          const box = target.getBoundingClientRect();
          if (box.width === 0 || getComputedStyle(e).visibility === 'hidden') continue;
          if (box.width < 24 || box.height < 24) out.push(`${r}: ${e.tagName} ${e.dataset.testid ?? e.textContent.trim().slice(0, 20)} ${Math.round(box.width)}x${Math.round(box.height)}`);
        }
        return out;
      }, route));
    }
    assert.equal(await touchPage.evaluate(() => matchMedia('(pointer: coarse)').matches), true);
    assert.deepEqual(small, []);
    assert.deepEqual(touchPage.problems, []);
  });
});

describe('teaching views: design, at 1280 x 800 and on a phone', { timeout: 180_000 }, () => {
  before(async () => ({ browser, page } = await openApp({ goto: false, viewport: DESKTOP })));
  after(() => browser?.close());

  test('#learn/levels: schemes fill their panels, legend on the colour map, the finest level says it keeps every detail', async () => {
    await open('learn/levels');
    await assertControlsFirst('levels');
    await page.selectOption('[data-testid="levels-details"]', 'colour');
    assert.equal(await page.isVisible('[data-testid="levels-colorbar"]'), true, 'the colour map has a legend');
    assert.match(await page.textContent('[data-testid="levels-colorbar"]'), /\|d\|.*0.*\d\.\d+/s);
    await page.check('[data-testid="levels-compare"]');
    let s = await state();
    assert.equal(s.panels.length, 3);
    const ink = await inkPerCell(s.cells);
    for (const [i, f] of ink.entries()) assert.ok(f > 0.2, `panel ${s.panels[i]} is filled by its model (${f.toFixed(2)} of its pixels)`);
    await shot('levels-compare');
    await act('setLevel', 3);
    s = await state();
    assert.equal(s.zeroedText, 'none: the finest level keeps every detail');
    await act('setLevel', 2);
    assert.match((await state()).zeroedText, /^\d+ vertices: d²$/);
    await act('setLevel', 0);
    assert.match((await state()).zeroedText, /^630 vertices: d⁰ … d²$/);
    assert.deepEqual(page.problems, []);
  });

  test('#learn/levels: a single wavelet (one coefficient 1, all others 0) and the coarser levels ghosted', async () => {
    await open('learn/levels');
    await act('setLevel', 2);
    let s = await state();
    assert.equal(s.ghosts, 2, 'M⁰ and M¹ ghosted behind M²');
    await page.uncheck('[data-testid="levels-ghosts"]');
    assert.equal((await state()).ghosts, 0);
    await page.check('[data-testid="levels-ghosts"]');
    await act('setLevel', 1);
    await page.click('[data-testid="levels-wavelet"]');
    s = await state();
    assert.equal(s.wavelets.length, 1);
    const [w] = s.wavelets;
    assert.equal(w.nonZero, 1, 'one coefficient is 1, all others 0');
    assert.equal(w.depth, 2, 'at level 1 the wavelet is a detail of d¹, a vertex born at level 2');
    assert.ok(Math.abs(w.atVertex) > 0.1, `the basis function is large at its own vertex (${w.atVertex})`);
    assert.ok(w.support > 1 && w.support < 642 / 2, `local support: ${w.support} of 642 vertices`);
    assert.equal(await page.isVisible('[data-testid="levels-colorbar"]'), true, 'its colour map has a legend');
    assert.match(await page.textContent('[data-testid="levels-colorbar"]'), /wavelet ψ/);
    await shot('levels-wavelet');
    await page.click('[data-testid="levels-wavelet-next"]');
    const next = (await state()).wavelets[0];
    assert.notEqual(next.vertex, w.vertex, 'next wavelet: another vertex');
    assert.equal(next.depth, 2);
    // Schemes side by side: the interpolating linear wavelet is narrower than the Loop one.
    await page.check('[data-testid="levels-compare"]');
    s = await state();
    assert.equal(s.wavelets.length, 3);
    const [loop, , linear] = s.wavelets;
    assert.ok(linear.support < loop.support, `linear support ${linear.support} < loop ${loop.support}`);
    await shot('levels-wavelet-compare');
    await page.click('[data-testid="levels-wavelet"]');
    assert.equal((await state()).wavelets.length, 0, 'the button turns it off');
    assert.deepEqual(page.problems, []);
  });

  test('#learn/levels: a play reads stop while it runs and stops there; a level chosen by hand stops it', async () => {
    await open('learn/levels');
    const analysis = '[data-testid="levels-play-analysis"]';
    await page.click(analysis);
    assert.equal(await page.textContent(analysis), '■ stop');
    await page.click('[data-testid="bank-1"]');
    assert.equal(await page.textContent(analysis), '▶ analysis (n → 0)', 'stopped by the choice');
    await page.waitForTimeout(2000); // two ticks of the play, had it gone on
    assert.equal((await state()).level, 1, 'the level chosen stays');
    await page.click(analysis);
    await page.click(analysis);
    assert.equal(await page.textContent(analysis), '▶ analysis (n → 0)', 'its own button stops it');
    const level = (await state()).level;
    await page.waitForTimeout(2000);
    assert.equal((await state()).level, level);
  });

  test('#learn/levels and #learn/lifting keep their settings in the address: a reload comes back to them', async () => {
    await open('learn/levels');
    await page.click('[data-testid="bank-2"]');
    await page.selectOption('[data-testid="levels-details"]', 'colour');
    assert.match(page.url(), /#learn\/levels\?.*l=2.*details=colour/);
    await page.reload();
    await page.waitForFunction(() => window.mrvolLearn?.ready());
    let s = await state();
    assert.deepEqual([s.level, s.details], [2, 'colour']);
    assert.equal(await page.inputValue('[data-testid="levels-details"]'), 'colour');
    await open('learn/lifting');
    await page.fill('[data-testid="lifting-vertex"]', '12');
    await page.press('[data-testid="lifting-vertex"]', 'Enter');
    await page.click('[data-testid="lifting-step"]');
    assert.match(page.url(), /#learn\/lifting\?.*vertex=12.*phase=1/);
    await page.reload();
    await page.waitForFunction(() => window.mrvolLearn?.ready());
    s = await state();
    assert.deepEqual([s.vertex, s.phase], [12, 1]);
    // Nonsense in the address is ignored, not obeyed.
    await page.goto('about:blank');
    await page.goto(`${browser.url}#learn/lifting?vertex=99999&phase=x&mode=evil`);
    await page.waitForFunction(() => window.mrvolLearn?.ready());
    s = await state();
    assert.deepEqual([s.vertex, s.phase], [0, 0]);
    assert.deepEqual(page.problems, []);
  });

  test('#learn/tensor: a new mesh says it is computing before the tensors are made', async () => {
    await open('learn/tensor');
    const seen = page.waitForFunction(() => /^Computing θ at \d+ levels for /.test(document.querySelector('[data-testid="learn-status"]').textContent));
    const options = await page.$$eval('select[data-testid="tensor-mesh"] option', (o) => o.map((x) => x.value));
    await page.selectOption('select[data-testid="tensor-mesh"]', options.at(-1));
    await seen;
    await page.waitForFunction(() => document.querySelector('[data-testid="learn-status"]').textContent === '');
  });

  test('#learn/lifting at 1280 x 800: the controls fit the sidebar and come before the text; the point colours have a legend', async () => {
    await open('learn/lifting');
    await assertControlsFirst('lifting');
    await page.selectOption('[data-testid="lifting-mode"]', 'transposed');
    const [select, aside] = await page.evaluate(() => [
      document.querySelector('[data-testid="lifting-mode"]').getBoundingClientRect().right,
      document.querySelector('.learn-aside').getBoundingClientRect().right,
    ]);
    assert.ok(select <= aside, `the direction select (right ${select}) stays in the sidebar (${aside})`);
    const stepTop = await page.evaluate(() => document.querySelector('[data-testid="lifting-step"]').getBoundingClientRect().bottom);
    assert.ok(stepTop < 800, `the step button is on screen without scrolling (${stepTop})`);
    assert.match(await page.textContent('[data-testid="lifting-legend"]'), /picked.*written.*read.*reached/);
    await assertFits(DESKTOP, 'lifting');
    await shot('lifting');
    assert.deepEqual(page.problems, []);
  });

  test('#learn/tensor: a mesh beside the pictures; pointing at an entry lights its three vertices', async () => {
    await open('learn/tensor');
    assert.doesNotMatch(await page.textContent('[data-testid="learn-text"]'), /mesh below/);
    let s = await state();
    assert.ok(s.meshFrames > 0, 'the mesh is drawn');
    assert.equal(s.markerCount, 0);
    const faces = new Set();
    for (let f = 0; f < s.faces.length; f += 3) faces.add(s.faces.slice(f, f + 3).sort((a, b) => a - b).join(','));
    // theta^n (n = 2): every non-zero entry is a triangle of the fine mesh, +-1/6.
    for (const g of [0, 1, 2]) {
      const cell = await act('nonZeroCell', 2, g);
      if (!cell) continue;
      const [x, y] = await act('cellCenter', 2, g, ...cell);
      await page.mouse.move(x, y);
      s = await state();
      assert.equal(s.hover.level, 2);
      assert.deepEqual([s.hover.i, s.hover.j], cell);
      assert.ok(faces.has([...s.hover.vertices].sort((a, b) => a - b).join(',')), `θ² entry at ${s.hover.vertices} is a face`);
      assert.ok(Math.abs(Math.abs(s.hover.value) - 1 / 6) < 1e-12, `±1/6: ${s.hover.value}`);
      assert.equal(s.markerCount, 3, 'its three vertices light up');
    }
    assert.match(await page.textContent('[data-testid="tensor-hover"]'), /θ²\[\d+, \d+, \d+\] = -?0\.1667/);
    // At level 0 the masks have spread the entries: the coarse triangle of hierarchy vertices 0, 2 (and a third
    // coarse one) is no longer +-1/6, and its vertices are the octahedron's.
    const [x, y] = await act('cellCenter', 0, 0, 0, 2);
    await page.mouse.move(x, y);
    s = await state();
    assert.equal(s.hover.level, 0);
    assert.ok(s.hover.k < 6, 'k among the six coarse vertices');
    assert.ok(Math.abs(s.hover.value) > 1e-3 && Math.abs(Math.abs(s.hover.value) - 1 / 6) > 1e-3, `a spread entry: ${s.hover.value}`);
    assert.equal(await page.locator('.tensor-slabs figure [data-testid="tensor-cursor"]').count(), 1, 'a ring marks the cell');
    // The keyboard: Tab to a picture, the arrows walk its cells and read them out as the pointer does.
    await page.focus('canvas[data-testid="tensor-slab-0-0"]');
    await page.keyboard.press('Home');
    s = await state();
    assert.deepEqual([s.hover.level, s.hover.i, s.hover.j], [0, 0, 0]);
    await page.keyboard.press('ArrowRight');
    await page.keyboard.press('ArrowRight');
    await page.keyboard.press('ArrowDown');
    s = await state();
    assert.deepEqual([s.hover.level, s.hover.i, s.hover.j], [0, 1, 2], 'arrows move the read-out cell');
    await page.keyboard.press('ArrowUp');
    await page.keyboard.press('ArrowUp');
    s = await state();
    assert.deepEqual([s.hover.i, s.hover.j], [0, 2], 'held at the edge');
    await shot('tensor');
    assert.deepEqual(page.problems, []);
  });

  test('#demo/ball: one floor per ball, inside its panel (no V where two grids meet); round chart ticks', async () => {
    await open('demo/ball');
    // at the start both volumes are the reference: a range of 1e-6 around 1, labelled without repeats
    const first = await page.evaluate(() => JSON.parse(document.querySelector('[data-testid="volume-chart"]').dataset.tickLabels ?? '[]'));
    assert.ok(first.length >= 3 && new Set(first).size === first.length, `tick labels at the start: ${first}`);
    await page.click('[data-testid="demo-play"]');
    await act('runUntilSquashed', 0.2, 1 / 120);
    for (const [p, f] of (await act('floorScreen')).entries())
      assert.ok(f.min > f.cellLeft + 4 && f.max < f.cellRight - 4, `panel ${p}: floor ${f.min}..${f.max} inside ${f.cellLeft}..${f.cellRight}`);
    const s = await state();
    assertRoundTicks(s.ticks, 'volume chart');
    const labels = await page.evaluate(() => JSON.parse(document.querySelector('[data-testid="volume-chart"]').dataset.ticks));
    assert.deepEqual(labels, s.ticks);
    assert.match(s.labels[0], /^volume free: \d+\.\d %$/);
    assert.match(s.labels[1], /^volume preserved: 100\.0 %$/);
    await shot('ball');
    assert.deepEqual(page.problems, []);
  });

  test('#demo/skinning: free and preserved tubes in the chart\'s colours, each with the other ghosted', async () => {
    await open('demo/skinning');
    await page.click('[data-testid="demo-play"]');
    await act('run', 45, 1 / 30);
    const s = await state();
    const [free, kept] = s.colors.map((c) => [(c >> 16) & 255, (c >> 8) & 255, c & 255]);
    assert.ok(free[0] > free[1] + 60, `the free tube is red-orange (${free})`);
    assert.ok(kept[1] > kept[0] + 60, `the preserved tube is green (${kept})`);
    assert.equal(s.ghosts, 2);
    assert.ok(s.minRatio < 0.97);
    assertRoundTicks(s.ticks, 'skinning chart');
    await shot('skinning');
    assert.deepEqual(page.problems, []);
  });

  test('#demo/bunny: dragging a control vertex plots the multiplier and the volumes live', async () => {
    await open('demo/bunny');
    let s = await state();
    assert.equal(s.playing, true);
    // The ear's handle in the preserved panel, dragged outwards (away from the panel's centre) in 10 moves.
    const ear = await page.evaluate(() => window.mrvolLearn.state().ears);
    assert.equal(ear.length, 2);
    await page.click('[data-testid="demo-restart"]');
    await act('pause');
    const handles = await page.evaluate(() => {
      const out = [];
      for (let c = 0; c < 50; c++) out.push(window.mrvolLearn.act('screenOfCage', c, 1));
      return out;
    });
    const rect = await page.evaluate(() => document.querySelector('.learn-stage canvas').getBoundingClientRect().toJSON());
    // A handle well inside the right half (the preserved panel), the one farthest up.
    const inside = handles.map(([x, y], c) => ({ c, x, y })).filter(({ x, y }) => x > rect.left + rect.width / 2 + 30 && x < rect.right - 30 && y > rect.top + 30 && y < rect.bottom - 30);
    assert.ok(inside.length > 0, 'a handle is on screen');
    const { x, y } = inside.sort((a, b) => a.y - b.y)[0];
    await page.mouse.move(x, y);
    await page.mouse.down();
    for (let i = 1; i <= 10; i++) await page.mouse.move(x, y - 6 * i);
    s = await state();
    assert.equal(s.dragging, true);
    assert.equal(s.playing, false, 'the animation paused for the drag');
    await page.mouse.up();
    s = await state();
    assert.equal(s.dragging, false);
    assert.ok(s.dragSamples >= 8, `the drag charts got a point per move (${s.dragSamples})`);
    assert.ok(s.lambdas.length === s.dragSamples && s.lambdas.every((l) => Number.isFinite(l)));
    assert.ok(Math.abs(s.lambdas.at(-1)) > 0, 'the correction moved the free vertices');
    const [freeV, keptV] = s.dragVolumes;
    assert.ok(Math.abs(freeV.at(-1) - 1) > 1e-3, `the free volume changed (${freeV.at(-1)})`);
    assert.ok(keptV.every((v) => Math.abs(v - 1) <= 1.01e-5), 'the preserved one did not');
    assert.ok(s.maxError <= 1.01e-5);
    assertRoundTicks(s.lambdaTicks, 'multiplier chart');
    // The time chart followed the drag too (paused, nothing else draws it): its axis spans the dragged volume.
    assert.equal(s.chartLast[0], freeV.at(-1));
    assert.ok(s.ticks[0] <= freeV.at(-1) && freeV.at(-1) <= s.ticks.at(-1), `time chart ticks ${s.ticks} span ${freeV.at(-1)}`);
    await shot('bunny-drag');
    // Restart while paused: the shapes, the charts, the extremes and the view of the start, drawn.
    const picture = () => page.evaluate(() => document.querySelector('.learn-stage canvas').toDataURL());
    await settle(page);
    const dragged = await picture();
    await page.mouse.move(rect.left + 20, rect.top + rect.height / 2);  // an orbit off the handles
    await page.mouse.down();
    await page.mouse.move(rect.left + 120, rect.top + rect.height / 2 - 30, { steps: 5 });
    await page.mouse.up();
    const turned = (await state()).camera;
    await page.click('[data-testid="demo-restart"]');
    await settle(page);
    s = await state();
    assert.equal(s.playing, false, 'still paused');
    assert.ok(Math.abs(s.free / s.reference - 1) < 1e-9, `the free volume back to the reference (${s.free / s.reference})`);
    assert.equal(s.chartPoints, 1, 'the time chart starts again');
    assert.ok(Math.abs(s.minRatio - 1) < 1e-9 && Math.abs(s.maxRatio - 1) < 1e-9, `the free range starts again (${s.minRatio}, ${s.maxRatio})`);
    assert.deepEqual([s.dragSamples, s.lambdas.length], [0, 0], 'the drag charts start empty');
    assert.ok(s.maxError < 1e-9, `the error over the run starts again (${s.maxError})`);
    assert.notDeepEqual(s.camera, turned, 'the view back home');
    assert.notEqual(await picture(), dragged, 'the picture drawn again');
    assert.deepEqual(page.problems, []);
  });

  test('charts are drawn again at their new width when a paused demo\'s page is resized', async () => {
    await open('demo/bunny', PHONE);
    await act('pause');
    // On the phone a drag's charts come right under the stage, the λ chart whole in sight.
    const tops = await page.evaluate(() => Object.fromEntries(['drag-lambda-chart', 'drag-volume-chart', 'volume-chart'].map((id) => {
      const r = document.querySelector(`[data-testid="${id}"]`).getBoundingClientRect();
      return [id, [r.top, r.bottom]];
    })));
    assert.ok(tops['drag-lambda-chart'][0] < tops['volume-chart'][0] && tops['drag-volume-chart'][0] < tops['volume-chart'][0], JSON.stringify(tops));
    assert.ok(tops['drag-lambda-chart'][1] <= PHONE.height, `the λ chart in sight: ${tops['drag-lambda-chart']}`);
    await page.setViewportSize({ width: PHONE.height, height: PHONE.width });
    await settle(page);
    const widths = await page.evaluate(() => [...document.querySelectorAll('canvas.learn-chart')].map((c) => [c.width, c.clientWidth]));
    assert.ok(widths.length === 3, JSON.stringify(widths));
    for (const [buffer, shown] of widths) assert.equal(buffer, shown, `a chart's buffer (${buffer}) is its width on the page (${shown})`);
    await page.setViewportSize(DESKTOP);
  });

  test('on a 390 x 844 phone: every view stacks stage and panel, nothing runs past the page', async () => {
    for (const route of ['learn/levels', 'learn/lifting', 'learn/tensor', 'demo/ball', 'demo/bunny', 'demo/skinning']) {
      await open(route, PHONE);
      await assertFits(PHONE, route);
      await assertControlsFirst(route);
      const box = await page.evaluate(() => {
        const stage = document.querySelector('[data-testid="learn-stage"]').getBoundingClientRect();
        const aside = document.querySelector('.learn-aside').getBoundingClientRect();
        return { stageHeight: stage.height, stageWidth: stage.width, asideTop: aside.top, stageBottom: stage.bottom };
      });
      assert.ok(box.stageWidth >= 380, `${route}: the stage spans the phone (${box.stageWidth})`);
      assert.ok(box.stageHeight >= 250, `${route}: the stage is tall enough (${box.stageHeight})`);
      assert.ok(box.asideTop >= box.stageBottom - 1, `${route}: the panel is below the stage`);
      if (route === 'learn/levels') {
        await page.check('[data-testid="levels-compare"]');
        const s = await state();
        assert.ok(s.grid.columns < 3, 'schemes not squeezed side by side on a narrow stage');
      }
      await shot(`phone-${route.replace('/', '-')}`);
    }
    await page.setViewportSize(DESKTOP);
    assert.deepEqual(page.problems, []);
  });
});
