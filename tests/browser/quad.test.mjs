// Quad models in the web app and the teaching views (issue 16): the quad sample opens as quads
// (catmull-clark, a cage drawn with the quads' sides, the bilinear-patch volume), a drag keeps the
// volume, level changes and undo, the OBJ export writes quads; a semi-regular quad OBJ made by
// `mrvol subdivide --scheme catmull-clark` opens directly, a quad OBJ that is not semi-regular goes
// the triangle way (remesh offer); the levels and lifting views show quads. Screenshots at 1280x800
// and 390x844 go to test-results/quad-*.png.
import { after, before, describe, test } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { readFile } from 'node:fs/promises';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { createMrvol } from '../../lib/node.mjs';
import { openApp, waitReady, visibleHandles, dragHandle, settle, readouts, root, RESULTS_DIR } from './harness.mjs';

const SAMPLE = 'quad-critter';
const SAMPLE_PATH = join(root, `public/models/${SAMPLE}.obj`);
let browser, page, mrvol, scratch;

const debug = (fn, arg) => page.evaluate(fn, arg);
const shot = async (name) => {
  await settle(page);
  await page.screenshot({ path: join(RESULTS_DIR, `quad-${name}.png`) });
};

async function openSample(name) {
  await page.goto(`${browser.url}?model=${name}`);
  await waitReady(page);
  await page.waitForFunction((n) => window.mrvolDebug.modelName() === n, name);
}

async function openFile(name, buffer) {
  await page.locator('[data-testid="open-file"]').setInputFiles({ name, mimeType: 'application/octet-stream', buffer });
}

async function download(testid) {
  const [file] = await Promise.all([page.waitForEvent('download', { timeout: 30_000 }), page.locator(`[data-testid="${testid}"]`).click()]);
  return { name: file.suggestedFilename(), text: await readFile(await file.path(), 'utf8') };
}

/** The sides of the level-0 quads of the sample, as 'lo,hi' keys of vertex indices. */
function baseQuadSides(mr) {
  const quads = mr.levelQuads(0), sides = new Set();
  for (let q = 0; q < quads.length; q += 4)
    for (let k = 0; k < 4; k++) {
      const a = quads[q + k], b = quads[q + (k + 1) % 4];
      sides.add(`${Math.min(a, b)},${Math.max(a, b)}`);
    }
  return { sides, quads: quads.length / 4 };
}

/** An OBJ torus of nu x nv quads. */
function torusGrid(nu, nv) {
  const lines = [];
  for (let i = 0; i < nu; i++)
    for (let j = 0; j < nv; j++) {
      const u = 2 * Math.PI * i / nu, v = 2 * Math.PI * j / nv;
      lines.push(`v ${(2 + Math.cos(v)) * Math.cos(u)} ${(2 + Math.cos(v)) * Math.sin(u)} ${Math.sin(v)}`);
    }
  const id = (i, j) => ((i + nu) % nu) * nv + ((j + nv) % nv) + 1;
  for (let i = 0; i < nu; i++) for (let j = 0; j < nv; j++) lines.push(`f ${id(i, j)} ${id(i + 1, j)} ${id(i + 1, j + 1)} ${id(i, j + 1)}`);
  return lines.join('\n') + '\n';
}

/** The first base vertex of the quad sample with 4 quads around it. */
function valence4BaseVertex() {
  const mr = mrvol.openQuadMesh(mrvol.readObjQuads(readFileSync(SAMPLE_PATH, 'utf8')));
  const quads = mr.levelQuads(0);
  mr.delete();
  const count = new Map();
  for (const v of quads) count.set(v, (count.get(v) ?? 0) + 1);
  return [...count].filter(([, n]) => n === 4).map(([v]) => v).sort((a, b) => a - b)[0];
}

describe('quad models in the app', { timeout: 240_000 }, () => {
  before(async () => {
    mrvol = await createMrvol();
    scratch = mkdtempSync(join(tmpdir(), 'mrvol-quad-browser-'));
    ({ browser, page } = await openApp({ goto: false, viewport: { width: 1280, height: 800 } }));
  });
  after(async () => {
    await browser?.close();
    if (scratch) rmSync(scratch, { recursive: true, force: true });
  });

  test('the quad sample opens as quads: catmull-clark, a cage of quad sides, bilinear-patch volume', async () => {
    await openSample(SAMPLE);
    const settings = await debug(() => window.mrvolDebug.settings());
    assert.equal(settings.scheme, 'catmull-clark');
    assert.equal(settings.level, 0);
    const schemes = await page.locator('[data-testid="scheme"] option').allTextContents();
    assert.deepEqual(schemes, ['catmull-clark']);
    // the quad editor's free sets (painted regions and parts are for triangle models) and their pointer tools
    assert.deepEqual(await page.locator('[data-testid="free-set"] option').allTextContents(), ['cage minus held', 'all cage', 'painted region']);
    assert.deepEqual(await page.locator('[data-testid="tool"] option').allTextContents(), ['drag handles', 'paint free set']);
    assert.match(await page.textContent('#model-info'), /3458 vertices, 3456 quads, 3 levels \(Catmull-Clark\), cage 56 vertices/);
    assert.equal(await page.textContent('[data-testid="volume-kind"]'), '(bilinear patches)');
    // the cage drawn: the base quads' sides (54 quads, 108 sides), no diagonal
    const text = readFileSync(SAMPLE_PATH, 'utf8');
    const mr = mrvol.openQuadMesh(mrvol.readObjQuads(text));
    const { sides, quads } = baseQuadSides(mr);
    const bilinear = mr.info().volume;
    mr.delete();
    const edges = await debug(() => window.mrvolDebug.cageEdges());
    const vertexOf = await debug(() => window.mrvolDebug.cageVertices());
    assert.equal(edges.length / 2, 2 * quads);
    for (let e = 0; e < edges.length; e += 2) {
      const a = vertexOf[edges[e]], b = vertexOf[edges[e + 1]];
      assert.ok(sides.has(`${Math.min(a, b)},${Math.max(a, b)}`), `drawn edge ${a}-${b} is not a quad side`);
    }
    const r = await readouts(page);
    assert.ok(Math.abs(r.reference - bilinear) <= 1e-12 * bilinear, `the volume kept is the bilinear patches' (${r.reference} vs ${bilinear})`);
    await shot('app-1280');
    assert.deepEqual(page.problems, []);
  });

  test('a drag keeps the volume to 1e-9; level change, undo, export of quads', async () => {
    await page.selectOption('[data-testid="tolerance"]', { label: '1e-8' });
    const reference = await debug(() => window.mrvolDebug.referenceVolume());
    const handles = await visibleHandles(page);
    assert.ok(handles.length > 3, 'handles on the canvas');
    const before = await debug(() => window.mrvolDebug.cagePositions());
    await dragHandle(page, handles[0].index, 40, -35);
    const after = await debug(() => window.mrvolDebug.cagePositions());
    assert.ok(Math.hypot(...[0, 1, 2].map((k) => after[3 * handles[0].index + k] - before[3 * handles[0].index + k])) > 0.05, 'the handle moved');
    const volume = await debug(() => window.mrvolDebug.volume());
    assert.ok(Math.abs(volume - reference) <= 1e-9 * reference, `relative volume error ${Math.abs(volume - reference) / reference}`);
    const report = await debug(() => window.mrvolDebug.lastReport());
    assert.equal(report.path, 'polynomial'); // the app edits on the cage polynomial by default, quads too
    // the export writes quads, the edited positions
    const exported = await download('export');
    assert.equal(exported.name, `${SAMPLE}-edited.obj`);
    const faceLines = exported.text.split('\n').filter((l) => l.startsWith('f '));
    assert.equal(faceLines.length, 3456);
    assert.ok(faceLines.every((l) => l.trim().split(/\s+/).length === 5), 'every face a quad');
    const mesh = mrvol.readObjQuads(exported.text);
    assert.ok(Math.abs(mrvol.quadVolume(mesh) - reference) <= 1e-9 * reference, 'the exported quads keep the volume');
    const cageFile = await download('export-cage');
    assert.equal(cageFile.text.split('\n').filter((l) => /^f( \d+){4}\s*$/.test(l)).length, 54);
    // level 1: the cage of the level-1 quads (56 + 54 face points + 108 edge points)
    await page.selectOption('[data-testid="level"]', '1');
    await page.waitForFunction(() => window.mrvolDebug.cageSize() === 218);
    assert.equal((await debug(() => window.mrvolDebug.cageEdges())).length / 2, 2 * 216);
    await page.keyboard.press('Control+z'); // the level change
    await page.waitForFunction(() => window.mrvolDebug.cageSize() === 56);
    await page.keyboard.press('Control+z'); // the drag
    await page.waitForFunction((b) => window.mrvolDebug.cagePositions().every((v, i) => Math.abs(v - b[i]) < 1e-12), before);
    assert.deepEqual(page.problems, []);
  });

  test('phone layout: the quad sample and its cage; a triangle sample after it gets its schemes back', async () => {
    await page.setViewportSize({ width: 390, height: 844 });
    await openSample(SAMPLE);
    await shot('app-390');
    await page.setViewportSize({ width: 1280, height: 800 });
    await openSample('spiky-ball');
    assert.equal((await debug(() => window.mrvolDebug.settings())).scheme, 'loop');
    assert.deepEqual(await page.locator('[data-testid="scheme"] option').allTextContents(), ['loop', 'butterfly', 'linear']);
    assert.equal(await page.locator('[data-testid="free-set"] option').count(), 4);
    assert.equal(await page.locator('[data-testid="tool"] option').count(), 3);
    assert.equal(await page.textContent('[data-testid="volume-kind"]'), '');
    assert.deepEqual(page.problems, []);
  });

  test('a quad OBJ made by `mrvol subdivide --scheme catmull-clark` opens directly; a non-semi-regular one goes the triangle way', async () => {
    // base: a torus of 3 x 3 quads (9 vertices of valence 4, 18 edges), 2 levels by the command line
    const base = join(scratch, 'torus3.obj'), out = join(scratch, 'torus3-cc.obj');
    writeFileSync(base, torusGrid(3, 3));
    execFileSync(process.execPath, [join(root, 'bin/mrvol.mjs'), 'subdivide', base, '--scheme', 'catmull-clark', '--levels', '2', '-o', out]);
    await openFile('torus3-cc.obj', readFileSync(out));
    await page.waitForFunction(() => window.mrvolDebug.modelName() === 'torus3-cc.obj' && window.mrvolDebug.ready());
    assert.equal((await debug(() => window.mrvolDebug.settings())).scheme, 'catmull-clark');
    assert.equal(await debug(() => window.mrvolDebug.cageSize()), 9);
    assert.equal((await debug(() => window.mrvolDebug.cageEdges())).length / 2, 18);
    await shot('file-torus');
    const { index } = (await visibleHandles(page))[0];
    await dragHandle(page, index, 30, 25);
    const r = await readouts(page);
    assert.ok(r.error <= 1e-8, `relative error ${r.error}`);
    // a 25 x 11 quad torus: 275 quads, no Catmull-Clark split: not semi-regular, the triangle way, which
    // offers remeshing, into quads for a file of quads (lib/remesh-quad.mjs), and opens the result as quads
    await openFile('grid-torus.obj', Buffer.from(torusGrid(25, 11)));
    await page.locator('[data-testid="remesh-offer"]').waitFor({ state: 'visible' });
    assert.match(await page.locator('[data-testid="error-text"]').textContent(), /grid-torus\.obj.*not semi-regular/s);
    assert.equal(await page.locator('[data-testid="remesh-into"]').inputValue(), 'quads');
    await page.waitForFunction(() => window.mrvolDebug.modelName() === 'grid-torus-remeshed' && window.mrvolDebug.ready(), null, { timeout: 120_000 });
    assert.match(await page.locator('[data-testid="notice"]').textContent(), /^Remeshed into quads in [\d.]+ s: 2 Catmull-Clark levels/);
    assert.equal((await debug(() => window.mrvolDebug.settings())).scheme, 'catmull-clark');
    const cage = await debug(() => ({ size: window.mrvolDebug.cageSize(), edges: window.mrvolDebug.cageEdges().length / 2 }));
    assert.ok(cage.size > 8 && cage.edges === 2 * cage.size, `a genus-1 quad cage: E = 2V (${JSON.stringify(cage)})`);
    await shot('remeshed-quads');
  });

  test('a quad OBJ on a cube\'s base opens at level 1 (analysis stops there), its level select from 1; it drags', async () => {
    const base = join(scratch, 'cube.obj'), out = join(scratch, 'cube-cc.obj');
    writeFileSync(base, 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n' +
                        'f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n');
    execFileSync(process.execPath, [join(root, 'bin/mrvol.mjs'), 'subdivide', base, '--scheme', 'catmull-clark', '--levels', '3', '-o', out]);
    await openSample('spiky-ball');
    assert.equal((await debug(() => window.mrvolDebug.settings())).level, 0, 'a triangle model at level 0 first');
    await openFile('cube-cc.obj', readFileSync(out));
    await page.waitForFunction(() => window.mrvolDebug.modelName() === 'cube-cc.obj' && window.mrvolDebug.ready(), null, { timeout: 30_000 });
    assert.equal(await page.locator('[data-testid="error-text"]').isVisible(), false, 'no error');
    const settings = await debug(() => window.mrvolDebug.settings());
    assert.deepEqual([settings.scheme, settings.level], ['catmull-clark', 1]);
    assert.equal(await debug(() => window.mrvolDebug.cageSize()), 26);
    const levels = await page.$$eval('[data-testid="level"] option', (o) => o.map((x) => x.textContent.trim()));
    assert.deepEqual(levels, ['1', '2', '3'], 'level 0 is not offered');
    const { index } = (await visibleHandles(page))[0];
    await dragHandle(page, index, 30, 25);
    const r = await readouts(page);
    assert.ok(r.error <= 1e-8, `relative error ${r.error}`);
    await shot('file-cube');
  });

  test('#learn/levels shows the quad levels; #learn/lifting the Catmull-Clark steps', async () => {
    await page.goto(`${browser.url}#learn/levels`);
    await page.waitForFunction(() => window.mrvolLearn?.route() === 'learn/levels' && window.mrvolLearn.ready(), null, { timeout: 30_000 });
    await page.selectOption('[data-testid="levels-model"]', SAMPLE);
    await page.waitForFunction((n) => window.mrvolLearn.state().model === n, SAMPLE);
    let s = await debug(() => window.mrvolLearn.state());
    assert.equal(s.quad, true);
    assert.equal(s.scheme, 'catmull-clark');
    assert.equal(s.levels, 3);
    assert.deepEqual(await page.locator('[data-testid="levels-scheme"] option').allTextContents(), ['catmull-clark']);
    await page.fill('[data-testid="levels-level"]', '1');
    await page.dispatchEvent('[data-testid="levels-level"]', 'input');
    s = await debug(() => window.mrvolLearn.state());
    // M^1: 216 quads, 218 vertices, their 432 sides (no diagonals)
    assert.deepEqual([s.cageFaces, s.cageVertices, s.cageEdges], [216, 218, 432]);
    // the finest level's approximation is the model: its bilinear volume
    assert.ok(Math.abs(s.volumes['catmull-clark'][3] - s.fineVolume) <= 1e-9 * s.fineVolume);
    assert.match(await page.textContent('[data-testid="levels-volume-fine"]'), /bilinear patches/);
    await shot('levels');

    await page.goto(`${browser.url}#learn/lifting`);
    await page.waitForFunction(() => window.mrvolLearn?.route() === 'learn/lifting' && window.mrvolLearn.ready(), null, { timeout: 30_000 });
    await page.selectOption('[data-testid="lifting-model"]', SAMPLE);
    await page.waitForFunction((n) => window.mrvolLearn.state().model === n, SAMPLE);
    s = await debug(() => window.mrvolLearn.state());
    assert.equal(s.quad, true);
    assert.equal(s.scheme, 'catmull-clark');
    // level 1 of a base with valence-3 corners: face points, edge points, the valence-3 layer, the vertex rule
    assert.deepEqual(s.phases, ['P_f', 'P_e', 'N_31', 'P_31', 'N_v', 'P_v']);
    // a face point: P_f writes it from its quad's four corners (1/4 each)
    const facePoint = 56; // hierarchy order: the 56 base vertices, then level 1's face points
    await page.fill('[data-testid="lifting-vertex"]', String(facePoint));
    await page.dispatchEvent('[data-testid="lifting-vertex"]', 'change');
    await page.click('[data-testid="lifting-step"]');
    s = await debug(() => window.mrvolLearn.state());
    assert.equal(s.kind, 'face point, odd');
    assert.equal(s.phaseName, 'P_f');
    const own = s.weights.filter((w) => w.target === facePoint);
    assert.equal(own.length, 4);
    assert.ok(own.every((w) => w.weight === 0.25));
    assert.match(await page.textContent('[data-testid="lifting-phase"]'), /face points/);
    // an old vertex of valence 4 after the vertex rule: 4 edge points at 4/16, 4 face points at -1/16
    const old = valence4BaseVertex();
    await page.fill('[data-testid="lifting-vertex"]', String(old));
    await page.dispatchEvent('[data-testid="lifting-vertex"]', 'change');
    await page.evaluate(() => window.mrvolLearn.act('setPhase', 6));
    s = await debug(() => window.mrvolLearn.state());
    assert.equal(s.phaseName, 'P_v');
    assert.equal(s.kind, 'old vertex, even');
    const rule = s.weights.filter((w) => w.target === old).map((w) => w.weight).sort((a, b) => a - b);
    assert.deepEqual(rule, [-1 / 16, -1 / 16, -1 / 16, -1 / 16, 0.25, 0.25, 0.25, 0.25]);
    await shot('lifting');
    await page.setViewportSize({ width: 390, height: 844 });
    await shot('lifting-390');
    await page.setViewportSize({ width: 1280, height: 800 });
    assert.deepEqual(page.problems, []);
  });
});
