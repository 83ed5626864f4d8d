// examples/web/minimal.html (the mrvol/three component in a scene of its own) in headless
// Chromium: a real mouse drag and a real touch drag of handles keep the volume, undo gives the cage
// back, a press off the handles orbits instead, dispose() frees it.
import { after, before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { join } from 'node:path';
import { launchBrowser, settle, startExampleServer, RESULTS_DIR } from './harness.mjs';

let server, browser, page;

const state = () => page.evaluate(() => {
  const editor = window.minimalEditor;
  const label = document.querySelector('[data-testid="volume"]');
  return {
    volume: editor.volume(), reference: editor.referenceVolume(), cage: Array.from(editor.cagePositions()),
    shown: Number(label.dataset.value), report: editor.lastReport,
  };
});

/** A handle well inside the canvas, in page coordinates, with the handle index. */
async function handleOnScreen(index = null) {
  return page.evaluate((wanted) => {
    const editor = window.minimalEditor;
    const rect = editor.domElement.getBoundingClientRect();
    const screen = editor.handleScreenPositions();
    const inside = (i) => screen[2 * i] > 100 && screen[2 * i] < rect.width - 100 && screen[2 * i + 1] > 100 && screen[2 * i + 1] < rect.height - 100;
    const i = wanted ?? [...Array(screen.length / 2).keys()].find(inside);
    return { index: i, x: rect.left + screen[2 * i], y: rect.top + screen[2 * i + 1] };
  }, index);
}

describe('examples/web/minimal.html', { timeout: 180_000 }, () => {
  before(async () => {
    server = await startExampleServer();
    browser = await launchBrowser(server.url, { viewport: { width: 900, height: 700 } });
    page = await browser.newPage();
    await page.goto(`${server.url}minimal.html`);
    await page.waitForFunction(() => window.minimalEditor !== undefined, null, { timeout: 60_000 });
  });
  after(async () => {
    await browser?.close();
    await server?.close();
  });

  test('a mouse drag of a handle moves it and keeps the volume', async () => {
    const start = await state();
    const handle = await handleOnScreen();
    assert.ok(handle.index >= 0, 'a handle inside the canvas');
    await page.mouse.move(handle.x, handle.y);
    await page.mouse.down();
    for (let i = 1; i <= 10; i++) await page.mouse.move(handle.x + 6 * i, handle.y - 4 * i);
    await page.mouse.up();
    await settle(page);
    const end = await state();
    const moved = Math.hypot(...[0, 1, 2].map((k) => end.cage[3 * handle.index + k] - start.cage[3 * handle.index + k]));
    assert.ok(moved > 0.05, `the handle moved (${moved})`);
    assert.ok(end.report && end.report.converged, 'the last step converged');
    assert.equal(end.reference, start.reference);
    assert.ok(Math.abs(end.volume - end.reference) / end.reference < 1e-5, `volume ${end.volume} vs ${end.reference}`);
    assert.equal(end.shown, end.volume, 'the page shows the volume on change');
    await page.screenshot({ path: join(RESULTS_DIR, 'example-minimal-drag.png') });
    assert.deepEqual(page.problems, []);
  });

  test('undo gives the cage back; a press off the handles orbits the camera, not the cage', async () => {
    await page.keyboard.press('Control+z');
    const start = await state();
    const fresh = await page.evaluate(() => window.minimalEditor.session.history.size);
    assert.deepEqual(fresh, { undo: 0, redo: 1 });
    const camera = () => page.evaluate(() => window.minimalEditor.camera.position.toArray());
    const before = await camera();
    await page.mouse.move(820, 640);
    await page.mouse.down();
    await page.mouse.move(700, 600, { steps: 5 });
    await page.mouse.up();
    await settle(page);
    assert.notDeepEqual(await camera(), before, 'the camera orbited');
    assert.deepEqual((await state()).cage, start.cage, 'the cage stayed');
  });

  test('a touch drag moves a handle with the volume kept', async () => {
    const start = await state();
    const handle = await handleOnScreen();
    const cdp = await page.context().newCDPSession(page);
    const touch = (type, x, y) => cdp.send('Input.dispatchTouchEvent', {
      type, touchPoints: type === 'touchEnd' ? [] : [{ x, y, id: 1, radiusX: 2, radiusY: 2, force: 1 }],
    });
    await touch('touchStart', handle.x, handle.y);
    for (let i = 1; i <= 8; i++) await touch('touchMove', handle.x - 5 * i, handle.y + 5 * i);
    await touch('touchEnd');
    await settle(page);
    const end = await state();
    const moved = Math.hypot(...[0, 1, 2].map((k) => end.cage[3 * handle.index + k] - start.cage[3 * handle.index + k]));
    assert.ok(moved > 0.05, `the handle moved under the finger (${moved})`);
    assert.ok(Math.abs(end.volume - end.reference) / end.reference < 1e-5);
    await cdp.detach();
  });

  test('moveHandles from code: the volume kept, the picture redrawn, change (move) sent, one undo step', async () => {
    // (Driving the session directly moved the shape but left the surface and the cage drawn as before.)
    const result = await page.evaluate(() => {
      const editor = window.minimalEditor;
      const events = [];
      const listen = (e) => events.push(e.reason);
      editor.addEventListener('change', listen);
      const drawn = () => Array.from(editor.surface.geometry.getAttribute('position').array.slice(0, 30));
      const drawnCage = () => Array.from(editor.cage.positions.slice(0, 3));
      const before = { surface: drawn(), cage: drawnCage(), positions: Array.from(editor.positions().slice(0, 30)), undo: editor.session.history.size.undo };
      const report = editor.moveHandles([0], [0.2, 0, 0]);
      const after = { surface: drawn(), cage: drawnCage(), positions: Array.from(editor.positions().slice(0, 30)), undo: editor.session.history.size.undo };
      const volume = editor.volume(), reference = editor.referenceVolume();
      editor.removeEventListener('change', listen);
      editor.undo();
      return { before, after, events, converged: report?.converged, volume, reference, back: Array.from(editor.cagePositions().slice(0, 3)) };
    });
    assert.ok(result.converged);
    assert.ok(Math.abs(result.volume - result.reference) / result.reference < 1e-5);
    assert.notDeepEqual(result.after.positions, result.before.positions, 'the shape moved');
    // The drawn surface is float32: it follows the shape to float32.
    assert.ok(result.after.surface.every((x, i) => Math.abs(x - result.after.positions[i]) < 1e-5), 'the surface drawn is the new shape');
    assert.notDeepEqual(result.after.cage, result.before.cage, 'the cage drawn moved');
    assert.deepEqual(result.events, ['move']);
    assert.equal(result.after.undo, result.before.undo + 1, 'one undo step');
    assert.ok(result.back.every((x, i) => Math.abs(x - result.before.cage[i]) < 1e-6), 'undo gave the handle back');
  });

  test('a 163k-vertex mesh: the cage polynomial by default, the surface from the editor\'s float32 buffers, the rewritten range uploaded', async () => {
    // (It was matrix-free, a pass over the mesh at every step, and the whole surface copied, its
    // normals and bounding sphere computed in JS at every move.)
    const result = await page.evaluate(() => {
      const editor = window.minimalEditor;
      const { mrvol, model } = editor.session;
      const Controls = editor.constructor;
      const fine = mrvol.subdivide({ positions: model.mr.positions(), faces: model.faces }, { levels: 4 });
      const mesh = fine.toMesh();
      fine.delete();
      const out = { vertices: mesh.positions.length / 3 };
      for (const flat of [true, false]) {
        const big = new Controls(mrvol, editor.camera, editor.domElement, mesh, { level: 0, flat });
        const geometry = big.surface.geometry;
        const worstDrawn = () => {
          const drawn = geometry.getAttribute('position').array, positions = big.positions();
          let worst = 0;
          for (let i = 0; i < positions.length; i++) worst = Math.max(worst, Math.abs(drawn[i] - positions[i]));
          return worst;
        };
        // without the correction one handle's move changes its stencil's vertices only
        big.preserve = false;
        big.moveHandles([0], [0.05, 0.02, 0]);
        const ranges = geometry.getAttribute('position').updateRanges.map((r) => r.count / 3);
        const normals = geometry.getAttribute('normal');
        const normalRanges = normals ? normals.updateRanges.map((r) => r.count / 3) : [];
        const worstUnpreserved = worstDrawn();
        big.preserve = true;
        const report = big.moveHandles([1], [0.05, 0.02, 0]);
        out[flat ? 'flat' : 'smooth'] = { path: big.session.editor.path(), converged: report.converged, worst: Math.max(worstUnpreserved, worstDrawn()),
          ranges, normalRanges, sphere: geometry.boundingSphere, culled: big.surface.frustumCulled };
        big.dispose();
      }
      const forced = new Controls(mrvol, editor.camera, editor.domElement, model.mr, { level: 0, theta: 'matrix-free' });
      out.forced = forced.session.editor.path();
      forced.dispose();
      return out;
    });
    assert.equal(result.vertices, 163842);
    for (const shading of ['flat', 'smooth']) {
      const r = result[shading];
      assert.equal(r.path, 'polynomial', shading);
      assert.ok(r.converged);
      assert.ok(r.worst < 1e-5, `${shading}: the surface drawn is the editor's (to float32): ${r.worst}`);
      // the range the core rewrote, marked for upload (one handle's stencil: its first to last vertex)
      assert.equal(r.ranges.length, 1);
      assert.ok(r.ranges[0] > 0 && r.ranges[0] <= result.vertices, `${shading}: ${r.ranges[0]} of ${result.vertices} vertices copied`);
      assert.equal(r.sphere, null, 'no bounding sphere computed per move');
      assert.equal(r.culled, false);
    }
    assert.deepEqual(result.flat.normalRanges, [], 'flat: no normals copied');
    assert.equal(result.smooth.normalRanges.length, 1, 'smooth: the normals the core wrote, copied');
    assert.equal(result.forced, 'matrix-free');
    assert.deepEqual(page.problems, []);
  });

  test('after dispose() every call says the editor was disposed; a second dispose() does nothing', async () => {
    // (setLevel threw a TypeError from inside, volume() gave null, undo() false.)
    const result = await page.evaluate(() => {
      const editor = window.minimalEditor;
      const { mrvol, model } = editor.session;
      const second = new editor.constructor(mrvol, editor.camera, editor.domElement, model.mr, { level: 0 });
      second.dispose();
      second.dispose();
      const calls = { setLevel: () => second.setLevel(1), volume: () => second.volume(), undo: () => second.undo(),
                      redo: () => second.redo(), positions: () => second.positions(), handleCount: () => second.handleCount,
                      handleScreenPositions: () => second.handleScreenPositions() };
      const out = {};
      for (const [name, call] of Object.entries(calls)) {
        try {
          out[name] = `returned ${JSON.stringify(call())?.slice(0, 40)}`;
        } catch (e) {
          out[name] = `${e instanceof mrvol.MrvolError ? 'MrvolError' : e.name}: ${e.message}`;
        }
      }
      out.firstStillEdits = editor.volume() > 0 && editor.handleCount === 12;
      return out;
    });
    const { firstStillEdits, ...calls } = result;
    for (const [name, outcome] of Object.entries(calls)) assert.equal(outcome, 'MrvolError: this VolumeEditControls was disposed', name);
    assert.equal(firstStillEdits, true, 'the page\'s own editor (sharing the mesh) still works');
  });

  test("two editors on one canvas: touch-action is none while either listens, the canvas's own back after both, in either order", async () => {
    const result = await page.evaluate(() => {
      const editor = window.minimalEditor;
      const { mrvol, model } = editor.session;
      const canvas = document.createElement('canvas');
      canvas.style.touchAction = 'pan-y';
      const make = () => new editor.constructor(mrvol, editor.camera, canvas, model.mr, { level: 0 });
      const out = [];
      for (const firstDisposed of [0, 1]) {
        const pair = [make(), make()];
        out.push(canvas.style.touchAction);
        pair[firstDisposed].dispose();
        out.push(canvas.style.touchAction);
        pair[1 - firstDisposed].dispose();
        out.push(canvas.style.touchAction);
      }
      return out;
    });
    assert.deepEqual(result, ['none', 'none', 'pan-y', 'none', 'none', 'pan-y']);
  });

  test("theta: 'auto' edits through the tensor; a tensor of another level is refused, nothing left behind", async () => {
    const result = await page.evaluate(() => {
      const editor = window.minimalEditor;
      const { mrvol, model } = editor.session;
      const Controls = editor.constructor;
      const second = new Controls(mrvol, editor.camera, editor.domElement, model.mr, { theta: 'auto', level: 0 });
      const path = second.session.editor.path();
      const handles = second.handleCount;
      second.dispose();
      const foreign = model.mr.computeTheta({ level: 1 });
      let message = null;
      try {
        new Controls(mrvol, editor.camera, editor.domElement, model.mr, { theta: foreign, level: 0 });
      } catch (e) {
        message = `${e.name}: ${e.message}`;
      }
      foreign.delete();
      return { path, handles, message, firstStillWorks: Number.isFinite(editor.volume()) };
    });
    assert.equal(result.path, 'tensor');
    assert.equal(result.handles, 12);
    assert.match(result.message, /^MrvolError: this theta does not fit the mesh: /);
    assert.ok(result.firstStillWorks, 'the page\'s editor (owner of the mesh) is untouched');
    assert.deepEqual(page.problems, []);
  });

  test('a quad mesh: triangles drawn, a cage of quad sides, a drag keeps the bilinear-patch volume', async () => {
    await page.goto(`${server.url}minimal.html?model=quad-critter`);
    await page.waitForFunction(() => window.minimalEditor?.session.model?.name === 'mesh', null, { timeout: 60_000 });
    const drawn = await page.evaluate(() => {
      const editor = window.minimalEditor;
      const quads = editor.session.model.quads;
      return {
        quad: editor.session.quad, scheme: editor.session.scheme, quads: quads.length / 4,
        triangles: editor.surface.geometry.index.count / 3, handles: editor.handleCount,
        cageEdges: editor.cage.lines.geometry.index.count / 2, baseQuads: editor.session.model.mr.levelQuads(0).length / 4,
      };
    });
    assert.deepEqual(drawn, { quad: true, scheme: 'catmull-clark', quads: 3456, triangles: 6912, handles: 56, cageEdges: 108, baseQuads: 54 });
    const start = await state();
    const handle = await handleOnScreen();
    await page.mouse.move(handle.x, handle.y);
    await page.mouse.down();
    for (let i = 1; i <= 10; i++) await page.mouse.move(handle.x + 5 * i, handle.y + 3 * i);
    await page.mouse.up();
    await settle(page);
    const end = await state();
    const moved = Math.hypot(...[0, 1, 2].map((k) => end.cage[3 * handle.index + k] - start.cage[3 * handle.index + k]));
    assert.ok(moved > 0.05, `the handle moved (${moved})`);
    // the volume kept is the bilinear patches' of the quads (computed here from the edited positions)
    const bilinear = await page.evaluate(() => {
      const editor = window.minimalEditor;
      return editor.session.mrvol.quadVolume({ positions: editor.positions(), quads: editor.session.model.quads });
    });
    assert.ok(Math.abs(bilinear - start.reference) / start.reference < 1e-6, `bilinear volume ${bilinear} vs ${start.reference}`);
    assert.ok(Math.abs(end.volume - bilinear) <= 1e-12 * bilinear, 'the editor\'s volume is the bilinear patches\'');
    await page.screenshot({ path: join(RESULTS_DIR, 'example-minimal-quad.png') });
    assert.deepEqual(page.problems, []);
  });

  test('dispose() removes the object and its listeners', async () => {
    const result = await page.evaluate(() => {
      const editor = window.minimalEditor;
      const parent = editor.object.parent;
      editor.dispose();
      let threw = false;
      try {
        editor.volume();
      } catch {
        threw = true;
      }
      return { removed: parent.children.indexOf(editor.object) < 0, threw, volume: threw ? null : editor.volume() };
    });
    assert.ok(result.removed, 'the object left the scene');
    // The session's editor is gone: volume() reads null (nothing left in WASM memory to read).
    assert.equal(result.volume, null);
    const handle = { x: 450, y: 350 };
    await page.mouse.move(handle.x, handle.y);
    await page.mouse.down();
    await page.mouse.move(handle.x + 30, handle.y);
    await page.mouse.up();
    assert.deepEqual(page.problems, [], 'no listener left acting on a freed editor');
  });
});
