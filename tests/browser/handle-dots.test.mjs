// Handle dots on a dense cage (issue 12): sized to the cage's spacing on the screen ('auto', the
// default; a number stays fixed) and drawn faint through the surface, the selected ones not.
// The app at phone size with the 599-handle dragon sample, and the mrvol/three component
// (examples/web/minimal.html): the size it reports and draws, the pixels of a dot in front and
// one behind the surface, and touch drags of small dots that keep the volume.
import { after, before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { launchBrowser, openApp, readouts, settle, startExampleServer, visibleHandles, RESULTS_DIR } from './harness.mjs';

const PHONE = { width: 390, height: 844 };
const MIN = 6, MAX = 13;

/** A touch drag by CDP from (x, y) by (dx, dy) in `steps` moves. */
async function touchDrag(page, x, y, dx, dy, steps = 8) {
  const cdp = await page.context().newCDPSession(page);
  const touch = (type, points) => cdp.send('Input.dispatchTouchEvent', {
    type, touchPoints: points.map(([px, py], id) => ({ x: px, y: py, id, radiusX: 2, radiusY: 2, force: 1 })),
  });
  await touch('touchStart', [[x, y]]);
  for (let i = 1; i <= steps; i++) await touch('touchMove', [[x + dx * i / steps, y + dy * i / steps]]);
  await touch('touchEnd', []);
  await cdp.detach();
}

describe('the app at phone size with a dense cage', { timeout: 240_000 }, () => {
  let browser, page;
  before(async () => {
    ({ browser, page } = await openApp({ goto: false, viewport: PHONE }));
    await page.goto(`${browser.url}?model=dragon-remeshed`);
    await page.waitForFunction(() => window.mrvolDebug?.ready() === true && window.mrvolDebug.modelName() === 'dragon-remeshed', null, { timeout: 90_000 });
    await settle(page);
  });
  after(() => browser?.close());

  const dots = () => page.evaluate(() => window.mrvolDebug.handleDots());

  test('599 handles seen whole: dots smaller than 13 px, not below the minimum, the size drawn', async () => {
    assert.equal(await page.evaluate(() => window.mrvolDebug.cageSize()), 599);
    const d = await dots();
    assert.equal(d.setting, 'auto');
    assert.ok(d.size < MAX && d.size > MIN, `size ${d.size}`);
    assert.equal(d.drawn, d.size, 'the frame drawn used it');
    await page.screenshot({ path: join(RESULTS_DIR, 'handle-dots-phone.png') });
  });

  test('zooming in raises the size back to 13 px; framing again brings it back', async () => {
    const start = (await dots()).drawn;
    const box = await page.locator('#view canvas').boundingBox();
    await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
    const sizes = [];
    for (let i = 0; i < 8; i++) {
      await page.mouse.wheel(0, -300);
      await settle(page);
      sizes.push((await dots()).drawn);
    }
    for (let i = 1; i < sizes.length; i++) assert.ok(sizes[i] >= sizes[i - 1], `never smaller while zooming in: ${sizes}`);
    assert.ok(sizes[0] > start, `one zoom step grew the dots: ${start} -> ${sizes[0]}`);
    assert.equal(sizes.at(-1), MAX, `zoomed in: ${sizes}`);
    await page.keyboard.press('f');
    await settle(page);
    assert.ok(Math.abs((await dots()).drawn - start) <= 0.5, 'framed again: the size of the whole cage');
  });

  test('handles behind the surface are faint; a touched (selected) one is not', async () => {
    const box = await page.locator('#view canvas').boundingBox();
    await page.mouse.move(box.x + 3, box.y + 3);  // no handle hovered
    const d = await dots();
    assert.ok(d.alphaBehind.every((a) => a > 0 && a < 0.5), 'every handle faint through the surface');
    // a small dot, apart from the others by a few pixels, pressed with a finger at its place
    const screen = await page.evaluate(() => window.mrvolDebug.cageScreenPositions());
    const apart = (await visibleHandles(page)).filter(({ index, x, y }) =>
      screen.every(([sx, sy], j) => j === index || Math.hypot(sx - x, sy - y) > 4));
    assert.ok(apart.length > 10, 'dots to press');
    const { index, x, y } = apart[Math.floor(apart.length / 2)];
    const start = await page.evaluate(() => window.mrvolDebug.cagePositions());
    await touchDrag(page, x, y, 24, -30);
    await page.mouse.move(box.x + 3, box.y + 3);
    await settle(page);
    const end = await page.evaluate(() => window.mrvolDebug.cagePositions());
    const moved = (i) => Math.hypot(...[0, 1, 2].map((k) => end[3 * i + k] - start[3 * i + k]));
    assert.ok(moved(index) > 0, 'the pressed handle moved under the finger');
    const held = [...Array(599).keys()].filter((i) => i !== index && moved(i) > moved(index));
    assert.deepEqual(held, [], 'the pressed handle moved most (the nearest was picked)');
    const r = await readouts(page);
    assert.ok(r.error <= 1e-5, `relative volume error ${r.error}`);
    const after = await dots();
    assert.equal(after.alphaBehind[index], 1, 'the selected handle at full strength through the surface');
    assert.ok(after.alphaBehind.filter((a) => a === 1).length === 1, 'only it');
    await page.screenshot({ path: join(RESULTS_DIR, 'handle-dots-phone-dragged.png') });
    assert.deepEqual(page.problems, []);
  });
});

describe('the mrvol/three component (examples/web/minimal.html)', { timeout: 240_000 }, () => {
  let server, browser, page;
  before(async () => {
    server = await startExampleServer();
    browser = await launchBrowser(server.url, { viewport: { width: 900, height: 700 } });
    page = await browser.newPage();
  });
  after(async () => {
    await browser?.close();
    await server?.close();
  });

  async function open(model, viewport) {
    await page.setViewportSize(viewport);
    await page.goto(`${server.url}minimal.html?model=${model}`);
    await page.waitForFunction(() => window.minimalEditor !== undefined, null, { timeout: 60_000 });
    await settle(page);
  }

  test('a dot in front of the surface at full strength, one behind it faint', async () => {
    await open('spiky-ball', { width: 900, height: 700 });
    const seen = await page.evaluate(() => {
      const editor = window.minimalEditor;
      const cage = editor.cagePositions(), screen = editor.handleScreenPositions();
      const eye = editor.camera.position;
      const distance = (i) => Math.hypot(cage[3 * i] - eye.x, cage[3 * i + 1] - eye.y, cage[3 * i + 2] - eye.z);
      const order = [...Array(editor.handleCount).keys()].sort((a, b) => distance(a) - distance(b));
      editor.dispatchEvent({ type: 'change', reason: 'test' });  // the page renders on change: read this frame
      const canvas = editor.domElement;
      const copy = document.createElement('canvas');
      copy.width = canvas.width;
      copy.height = canvas.height;
      const g = copy.getContext('2d');
      g.drawImage(canvas, 0, 0);
      const scale = canvas.width / canvas.getBoundingClientRect().width;
      const pixel = (i) => Array.from(g.getImageData(Math.round(screen[2 * i] * scale), Math.round(screen[2 * i + 1] * scale), 1, 1).data).slice(0, 3);
      const front = order[0], back = order.at(-1);
      return { front: pixel(front), back: pixel(back), size: editor.handlePixelSize, setting: editor.handleSize,
        apart: Math.hypot(screen[2 * front] - screen[2 * back], screen[2 * front + 1] - screen[2 * back + 1]) };
    });
    await page.screenshot({ path: join(RESULTS_DIR, 'handle-dots-component.png') });
    assert.equal(seen.setting, 'auto');
    assert.equal(seen.size, MAX, '12 handles: full size');
    assert.ok(seen.apart > 2 * MAX, 'the two dots apart on the screen');
    const handle = [31, 111, 235];  // CAGE_COLOR
    const off = (rgb) => Math.hypot(...rgb.map((c, k) => c - handle[k]));
    assert.ok(off(seen.front) < 30, `the front dot in the handle colour: ${seen.front}`);
    assert.ok(off(seen.back) > 50, `the dot behind the surface faint: ${seen.back}`);
    assert.ok(seen.back[2] - seen.back[0] > 15, `but still drawn (bluish): ${seen.back}`);
  });

  test('a fixed handleSize stays fixed when the camera comes nearer', async () => {
    const sizes = await page.evaluate(() => {
      const editor = window.minimalEditor;
      const { mrvol, model } = editor.session;
      const fixed = new editor.constructor(mrvol, editor.camera, editor.domElement, model.mr, { handleSize: 9 });
      const before = [fixed.handleSize, fixed.handlePixelSize, fixed.cage.materials.handles.size];
      const position = editor.camera.position.clone();
      editor.camera.position.multiplyScalar(0.3);
      const after = [fixed.handlePixelSize, fixed.cage.materials.handles.size];
      editor.camera.position.copy(position);
      fixed.dispose();
      return { before, after };
    });
    assert.deepEqual(sizes, { before: [9, 9, 9], after: [9, 9] });
  });

  test('599 handles at phone size: smaller dots, bigger when nearer; a touch drag of one keeps the volume', async () => {
    await open('dragon-remeshed', PHONE);
    const sizes = await page.evaluate(() => {
      const editor = window.minimalEditor;
      const far = editor.handlePixelSize;
      const position = editor.camera.position.clone();
      // halfway and more to the cage's centre
      const p = editor.cagePositions(), centre = position.clone().set(0, 0, 0);
      for (let i = 0; i < p.length; i += 3) centre.set(centre.x + p[i], centre.y + p[i + 1], centre.z + p[i + 2]);
      editor.camera.position.lerp(centre.multiplyScalar(3 / p.length), 0.6);
      const near = editor.handlePixelSize;
      editor.camera.position.copy(position);
      return { handles: editor.handleCount, far, near, again: editor.handlePixelSize };
    });
    assert.equal(sizes.handles, 599);
    assert.ok(sizes.far < MAX && sizes.far > MIN, `seen whole: ${sizes.far}`);
    assert.ok(sizes.near > sizes.far, `nearer: ${sizes.near} > ${sizes.far}`);
    assert.equal(sizes.again, sizes.far);
    const start = await page.evaluate(() => ({ cage: Array.from(window.minimalEditor.cagePositions()), screen: window.minimalEditor.handleScreenPositions() }));
    const rect = await page.evaluate(() => window.minimalEditor.domElement.getBoundingClientRect().toJSON());
    // a handle well inside the view, with no other within 4 px
    const n = start.screen.length / 2;
    const index = [...Array(n).keys()].find((i) => {
      const x = start.screen[2 * i], y = start.screen[2 * i + 1];
      return x > 80 && x < rect.width - 80 && y > 200 && y < rect.height - 200 &&
        [...Array(n).keys()].every((j) => j === i || Math.hypot(start.screen[2 * j] - x, start.screen[2 * j + 1] - y) > 4);
    });
    assert.ok(index >= 0, 'a handle to press');
    await touchDrag(page, rect.left + start.screen[2 * index], rect.top + start.screen[2 * index + 1], -20, 25);
    await settle(page);
    const end = await page.evaluate(() => ({ cage: Array.from(window.minimalEditor.cagePositions()), volume: window.minimalEditor.volume(),
      reference: window.minimalEditor.referenceVolume() }));
    const moved = (i) => Math.hypot(...[0, 1, 2].map((k) => end.cage[3 * i + k] - start.cage[3 * i + k]));
    assert.ok(moved(index) > 0, 'the pressed handle moved');
    assert.deepEqual([...Array(n).keys()].filter((i) => i !== index && moved(i) > moved(index)), [], 'it moved most');
    assert.ok(Math.abs(end.volume - end.reference) / end.reference < 1e-5, `volume ${end.volume} vs ${end.reference}`);
    await page.screenshot({ path: join(RESULTS_DIR, 'handle-dots-component-phone.png') });
    assert.deepEqual(page.problems, []);
  });
});
