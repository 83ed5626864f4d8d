// The editor's layout at a desktop size (1280x800) and a phone size (390x844): nothing that takes
// pointer events lies over the canvas where handles are (every handle of every sample, framed as it
// opens, can be grabbed), the phone's sheet leaves the model most of the screen and folds away,
// touch drags a handle and pinch zooms, and the remesh offer's parts do not overlap.
// Screenshots go to test-results/layout-*.png.
import { after, before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { readdirSync } from 'node:fs';
import { startTestServer, launchBrowser, waitReady, readouts, settle, root, RESULTS_DIR } from './harness.mjs';

const SIZES = { desktop: { width: 1280, height: 800 }, phone: { width: 390, height: 844 } };
// every sample the app offers (public/models/*.obj), framed as it opens
const MODELS = readdirSync(join(root, 'public/models')).filter((f) => f.endsWith('.obj')).map((f) => f.slice(0, -4)).sort();

let server;

async function withBrowser(viewport, fn, options = {}) {
  const browser = await launchBrowser(server.url, { viewport, ...options });
  try {
    await fn(await browser.newPage());
  } finally {
    await browser.close();
  }
}

/** Handles whose screen point is not the canvas (covered, or outside the view), with what is there. */
function unreachableHandles(page) {
  return page.evaluate(() => {
    const canvas = document.querySelector('#view canvas');
    return window.mrvolDebug.cageScreenPositions().flatMap(([x, y], index) => {
      const hit = document.elementFromPoint(x, y);
      return hit === canvas ? [] : [{ index, x: Math.round(x), y: Math.round(y), hit: hit ? `${hit.tagName}#${hit.id}.${hit.className}` : null }];
    });
  });
}

/** A closed latitude-longitude sphere: valid, not semi-regular (the remesh offer opens). */
function uvSphereObj(rings = 8, segments = 12) {
  const lines = ['v 0 0 1'];
  for (let i = 1; i < rings; i++) {
    const t = Math.PI * i / rings;
    for (let j = 0; j < segments; j++) {
      const p = 2 * Math.PI * j / segments;
      lines.push(`v ${Math.sin(t) * Math.cos(p)} ${Math.sin(t) * Math.sin(p)} ${Math.cos(t)}`);
    }
  }
  lines.push('v 0 0 -1');
  const ring = (i, j) => 2 + (i - 1) * segments + (j % segments);
  const south = 2 + (rings - 1) * segments;
  for (let j = 0; j < segments; j++) lines.push(`f 1 ${ring(1, j)} ${ring(1, j + 1)}`);
  for (let i = 1; i < rings - 1; i++)
    for (let j = 0; j < segments; j++)
      lines.push(`f ${ring(i, j)} ${ring(i + 1, j)} ${ring(i + 1, j + 1)}`, `f ${ring(i, j)} ${ring(i + 1, j + 1)} ${ring(i, j + 1)}`);
  for (let j = 0; j < segments; j++) lines.push(`f ${south} ${ring(rings - 1, j + 1)} ${ring(rings - 1, j)}`);
  return lines.join('\n') + '\n';
}

function overlaps(a, b) {
  return a.left < b.right && b.left < a.right && a.top < b.bottom && b.top < a.bottom;
}

describe('web editor layout at desktop and phone sizes', { timeout: 1_200_000 }, () => {
  before(async () => {
    server = await startTestServer();
  });
  after(async () => {
    await server?.close();
  });

  for (const [sizeName, viewport] of Object.entries(SIZES)) {
    test(`${sizeName} ${viewport.width}x${viewport.height}: every handle of every sample is on the canvas, uncovered, as it opens`, { timeout: 480_000 }, async () => {
      await withBrowser(viewport, async (page) => {
        for (const model of MODELS) {
          await page.goto(`${server.url}?model=${model}`);
          await waitReady(page);
          await settle(page);
          const size = await page.evaluate(() => window.mrvolDebug.cageSize());
          assert.ok(size > 0, `${model}: ${size} handles`);
          assert.deepEqual(await unreachableHandles(page), [], `${model} at ${sizeName}: handles not on the canvas`);
          await page.screenshot({ path: join(RESULTS_DIR, `layout-${sizeName}-${model}.png`) });
        }
        // The view is most of the screen; the readouts are beside or below it, not over it.
        const boxes = await page.evaluate(() => {
          const rect = (sel) => document.querySelector(sel).getBoundingClientRect().toJSON();
          return { canvas: rect('#view canvas'), readouts: rect('[data-testid="readouts"]'), panel: rect('[data-testid="panel"]') };
        });
        assert.ok(!overlaps(boxes.canvas, boxes.readouts), 'readouts over the canvas');
        assert.ok(!overlaps(boxes.canvas, boxes.panel), 'panel over the canvas');
        const share = boxes.canvas.width * boxes.canvas.height / (viewport.width * viewport.height);
        assert.ok(share >= 0.6, `the view is ${(100 * share).toFixed(0)}% of the screen`);
        assert.deepEqual(page.problems, []);
      });
    });
  }

  test('phone with a touch screen: every control in sight or in the panel is a target of 24 px or more', { timeout: 120_000 }, async () => {
    // (lil-gui's lists were their native 19 px in its 28 px rows, the recent files and the teaching
    // views' links 15-17 px.) A checkbox's target is its label, the whole row.
    await withBrowser(SIZES.phone, async (page) => {
      await page.goto(server.url);
      await waitReady(page);
      const small = await page.evaluate(() => {
        for (const folder of document.querySelectorAll('.lil-gui.lil-closed')) folder.classList.remove('lil-closed');
        const out = [];
        for (const el of document.querySelectorAll('button, a[href], input, select')) {
          const target = el.type === 'checkbox' ? el.closest('label') ?? el : el;
          const r = target.getBoundingClientRect();
          if (r.width === 0 || getComputedStyle(el).visibility === 'hidden') continue;
          if (r.height < 24 || r.width < 24) out.push(`${el.tagName} "${(el.textContent || el.getAttribute('aria-label') || el.closest('label')?.textContent || '').trim().slice(0, 30)}" ${Math.round(r.width)}x${Math.round(r.height)}`);
        }
        return { coarse: matchMedia('(pointer: coarse)').matches, out };
      });
      assert.equal(small.coarse, true, 'the page sees a touch screen');
      assert.deepEqual(small.out, []);
      // The keep-balance box itself, not only its row, large enough to see under a finger (it was 13 px).
      const check = await page.locator('[data-testid="keep-balance"]').boundingBox();
      assert.ok(check.width >= 20 && check.height >= 20, `the keep-balance box is ${check.width}x${check.height}`);
      await page.screenshot({ path: join(RESULTS_DIR, 'layout-phone-touch-panel.png'), fullPage: true });
    }, { touch: true });
  });

  test('phone: the sheet folds away and back; touch drags a handle (volume kept) and pinch zooms', { timeout: 120_000 }, async () => {
    await withBrowser(SIZES.phone, async (page) => {
      await page.goto(server.url);
      await waitReady(page);
      const canvasHeight = () => page.evaluate(() => document.querySelector('#view canvas').getBoundingClientRect().height);
      const open = await canvasHeight();
      await page.locator('[data-testid="sheet-toggle"]').click();
      await page.waitForFunction((h) => document.querySelector('#view canvas').getBoundingClientRect().height > h + 100, open);
      assert.equal(await page.locator('[data-testid="sheet-toggle"]').getAttribute('aria-expanded'), 'false');
      await settle(page);
      assert.deepEqual(await unreachableHandles(page), []);
      await page.screenshot({ path: join(RESULTS_DIR, 'layout-phone-folded.png') });
      const folded = await canvasHeight();
      await page.locator('[data-testid="sheet-toggle"]').click();
      await page.waitForFunction((h) => document.querySelector('#view canvas').getBoundingClientRect().height < h - 100, folded);
      assert.ok(await canvasHeight() >= 0.6 * 844, 'the unfolded sheet leaves the view 60% of the height');

      const cdp = await page.context().newCDPSession(page);
      await cdp.send('Emulation.setTouchEmulationEnabled', { enabled: true, maxTouchPoints: 5 });
      const touch = (type, points) => cdp.send('Input.dispatchTouchEvent', { type, touchPoints: points.map(([x, y], id) => ({ x, y, id })) });
      await settle(page);
      const before = await page.evaluate(() => window.mrvolDebug.cagePositions());
      const [x, y] = (await page.evaluate(() => window.mrvolDebug.cageScreenPositions()))[0];
      await touch('touchStart', [[x, y]]);
      for (let i = 1; i <= 8; i++) await touch('touchMove', [[x + 3 * i, y - 3 * i]]);
      await touch('touchEnd', []);
      const after = await page.evaluate(() => window.mrvolDebug.cagePositions());
      assert.notDeepEqual(after.slice(0, 3), before.slice(0, 3), 'the touched handle moved');
      const r = await readouts(page);
      assert.ok(r.error <= 1e-5, `relative error ${r.error}`);

      // Pinch: two fingers apart from the middle of the view zoom in (handles spread on screen).
      const spread = async () => {
        const points = await page.evaluate(() => window.mrvolDebug.cageScreenPositions());
        const xs = points.map((p) => p[0]);
        return Math.max(...xs) - Math.min(...xs);
      };
      const wide = await spread();
      const middle = await page.evaluate(() => {
        const r = document.querySelector('#view canvas').getBoundingClientRect();
        return [r.left + r.width / 2, r.top + r.height / 2];
      });
      // away from every handle, so the two touches orbit/zoom rather than grab
      const [cx, cy] = middle;
      await touch('touchStart', [[cx - 20, cy + 150], [cx + 20, cy + 150]]);
      for (let i = 1; i <= 10; i++) await touch('touchMove', [[cx - 20 - 8 * i, cy + 150], [cx + 20 + 8 * i, cy + 150]]);
      await touch('touchEnd', []);
      await settle(page);
      assert.ok(await spread() > wide * 1.1, `pinch did not zoom: ${wide} -> ${await spread()}`);
      await page.screenshot({ path: join(RESULTS_DIR, 'layout-phone-after-touch.png') });
      assert.deepEqual(page.problems, []);
    });
  });

  for (const [sizeName, viewport] of Object.entries({ ...SIZES, wide: { width: 1920, height: 1080 } })) {
    test(`${sizeName} ${viewport.width}x${viewport.height}: no empty strip above the view; progress shows above it, not over it`, { timeout: 120_000 }, async () => {
      await withBrowser(viewport, async (page) => {
        await page.goto(server.url);
        await waitReady(page);
        const layout = () => page.evaluate(() => ({
          strip: document.querySelector('.status-strip').getBoundingClientRect().height,
          stageTop: document.querySelector('.stage').getBoundingClientRect().top,
          canvas: document.querySelector('#view canvas').getBoundingClientRect().toJSON(),
        }));
        const idle = await layout();
        assert.equal(idle.strip, 0, 'an empty status strip');
        assert.equal(idle.canvas.top, idle.stageTop, 'the view starts at the top');
        await page.screenshot({ path: join(RESULTS_DIR, `layout-${sizeName}-no-strip.png`) });
        // θ's progress as the app shows it (web/readouts.js unhides the box): the strip comes, above the view
        await page.evaluate(() => { document.getElementById('theta-progress').hidden = false; });
        await settle(page);
        const busy = await layout();
        assert.ok(busy.strip >= 30, `the progress strip is ${busy.strip}px`);
        assert.ok(busy.canvas.top >= busy.stageTop + busy.strip - 0.5, 'the progress is above the canvas, not over it');
        assert.deepEqual(await unreachableHandles(page), []);
        await page.evaluate(() => { document.getElementById('theta-progress').hidden = true; });
        await settle(page);
        assert.equal((await layout()).strip, 0, 'the strip goes with the progress');
        assert.deepEqual(page.problems, []);
      });
    });
  }

  for (const [sizeName, viewport] of Object.entries(SIZES)) {
    test(`${sizeName}: the remesh offer's text, fields, button and close button do not overlap`, { timeout: 120_000 }, async () => {
      await withBrowser(viewport, async (page) => {
        await page.goto(server.url);
        await waitReady(page);
        await page.locator('[data-testid="open-file"]').setInputFiles({ name: 'uv.obj', mimeType: 'text/plain', buffer: Buffer.from(uvSphereObj()) });
        await page.locator('[data-testid="remesh-offer"]').waitFor({ state: 'visible' });
        const rects = await page.evaluate(() => {
          const rect = (sel) => document.querySelector(sel).getBoundingClientRect().toJSON();
          const label = document.querySelector('[data-testid="remesh-repair"]').closest('label');
          return {
            text: rect('#error-text'), why: rect('#remesh-why'), close: rect('#error-close'), go: rect('#remesh-go'),
            repair: rect('[data-testid="remesh-repair"]'), repairLabel: label.getBoundingClientRect().toJSON(),
            fields: [...document.querySelectorAll('.remesh-fields label')].map((l) => l.getBoundingClientRect().toJSON()),
          };
        });
        for (const [a, b] of [['go', 'text'], ['go', 'why'], ['go', 'close'], ['close', 'why']])
          assert.ok(!overlaps(rects[a], rects[b]), `${a} overlaps ${b}`);
        for (const field of rects.fields) assert.ok(!overlaps(rects.go, field), 'the button overlaps a field');
        assert.ok(rects.repairLabel.width < 110, `the repair checkbox is ${rects.repairLabel.width}px from its word`);
        assert.ok(rects.repair.width < 30);
        await page.screenshot({ path: join(RESULTS_DIR, `layout-${sizeName}-remesh-offer.png`) });
      });
    });
  }

  test('phone: what a remesh did is said in sight, under the model\'s name, without scrolling the sheet', { timeout: 120_000 }, async () => {
    await withBrowser(SIZES.phone, async (page) => {
      await page.goto(server.url);
      await waitReady(page);
      await page.locator('[data-testid="open-file"]').setInputFiles({ name: 'uv.obj', mimeType: 'text/plain', buffer: Buffer.from(uvSphereObj()) });
      await page.waitForFunction(() => window.mrvolDebug.modelName() === 'uv-remeshed' && window.mrvolDebug.ready(), null, { timeout: 60_000 });
      const at = await page.evaluate(() => {
        const rect = (sel) => document.querySelector(sel).getBoundingClientRect().toJSON();
        return { notice: rect('[data-testid="notice"]'), name: rect('[data-testid="model-name"]'), table: rect('.readouts table'),
                 sheetTop: document.querySelector('#side-content').scrollTop, text: document.querySelector('[data-testid="notice"]').textContent };
      });
      assert.match(at.text, /^Remeshed in /);
      assert.equal(at.sheetTop, 0);
      assert.ok(at.notice.top >= at.name.bottom - 0.5 && at.notice.bottom <= at.table.top + 0.5, 'the notice between the name and the table');
      assert.ok(at.notice.bottom <= SIZES.phone.height, `the notice ends at ${at.notice.bottom}px of ${SIZES.phone.height}`);
      await page.screenshot({ path: join(RESULTS_DIR, 'layout-phone-remesh-notice.png') });
    });
  });
});
