// The Loop limit surface's volume through the real WASM module and the real CLI: the API option
// surface: 'limit' on volume(), info() and computeTheta(), theta^e of the limit form against the
// volume computed directly, theta files that say which surface they hold, and the errors.
import { test, describe, before } from 'node:test';
import assert from 'node:assert/strict';
import { writeFileSync, readFileSync } from 'node:fs';
import { createMrvol } from '../../lib/node.mjs';
import {
  tempFolder, runCliSync, json, failsWith, usageError, model, icosahedron, openPatch, relErr, throwsMrvol,
} from './helpers.mjs';

const mrvolCli = (...args) => runCliSync(args, { timeout: 60000 });
const file = tempFolder('mrvol-limit-test-');
let mrvol;

before(async () => {
  mrvol = await createMrvol();
});

describe('limit volume (API)', () => {
  test('the limit surface of a subdivided mesh is the same surface: equal volumes', () => {
    const base = icosahedron();
    const limit = mrvol.volume(base, { surface: 'limit' });
    assert.ok(limit > 0 && limit < mrvol.volume(base), 'Loop shrinks a convex shape');
    for (const levels of [1, 2, 3]) {
      const mr = mrvol.subdivide(base, { levels });
      const info = mr.info({ surface: 'limit' });
      assert.equal(info.surface, 'limit');
      assert.ok(relErr(info.volume, limit) < 1e-12, `${levels} levels: ${info.volume} vs ${limit}`);
      assert.ok(relErr(mrvol.volume(mr.toMesh(), { surface: 'limit' }), limit) < 1e-12);
      // The mesh volumes approach it with ratio 4 per level.
      assert.equal(mr.info().surface, 'mesh');
      assert.ok(mr.info().volume > limit);
      mr.delete();
    }
    const v = [3, 4, 5].map((levels) => {
      const mr = mrvol.subdivide(base, { levels });
      const volume = mr.info().volume;
      mr.delete();
      return volume;
    });
    const ratio = (v[1] - limit) / (v[2] - limit);
    assert.ok(Math.abs(ratio - 4) < 0.05, `ratio ${ratio}`);
    // Richardson with the rates 1/4 and 1/16 on levels 3..5.
    const extrapolated = (64 * v[2] - 20 * v[1] + v[0]) / 45;
    assert.ok(relErr(extrapolated, limit) < 1e-6, `${extrapolated} vs ${limit}`);
  });

  test('computeTheta({ surface: "limit" }) gives the limit volume at every level and scheme', () => {
    const mr = mrvol.subdivide(icosahedron(), { levels: 2 });
    const p = mr.positions();
    for (let i = 0; i < p.length; i++) p[i] += 0.05 * Math.sin(7 * i);
    mr.setPositions(p);
    const limit = mr.info({ surface: 'limit' }).volume;
    for (const scheme of ['loop', 'butterfly', 'linear'])
      for (let level = 0; level <= 2; level++) {
        const theta = mr.computeTheta({ level, scheme, surface: 'limit' });
        assert.equal(theta.info().surface, 'limit');
        assert.ok(relErr(mr.thetaVolume(theta, { level, scheme }), limit) < 1e-10, `${scheme} level ${level}`);
        theta.delete();
      }
    const full = mr.computeTheta({ level: 1, storage: 'full', surface: 'limit' });
    assert.ok(relErr(mr.thetaVolume(full, { level: 1 }), limit) < 1e-10);
    // The file keeps the surface; an editor (which keeps the mesh's volume) refuses a limit theta.
    const again = mrvol.readTheta(full.bytes());
    assert.equal(again.info().surface, 'limit');
    assert.ok(relErr(mr.thetaVolume(again, { level: 1 }), limit) < 1e-10);
    const cage = mr.computeTheta({ level: 0, surface: 'limit' });
    throwsMrvol(() => mr.createEditor({ level: 0, theta: cage }), /limit surface, not of the mesh/);
    const meshTheta = mr.computeTheta({ level: 0 });
    assert.equal(meshTheta.info().surface, 'mesh');
    for (const t of [full, again, cage, meshTheta]) t.delete();
    mr.delete();
  });

  test('bad surface names and meshes with boundary: MrvolError, the module keeps working', () => {
    throwsMrvol(() => mrvol.volume(icosahedron(), { surface: 'smooth' }), /surface must be 'mesh' or 'limit'/);
    throwsMrvol(() => mrvol.volume(openPatch(), { surface: 'limit' }), /closed mesh.*boundary edges/);
    const open = mrvol.subdivide(openPatch(), { levels: 1 });
    throwsMrvol(() => open.info({ surface: 'limit' }), /closed mesh/);
    throwsMrvol(() => open.computeTheta({ level: 0, surface: 'limit' }), /closed mesh/);
    assert.ok(open.info().volume !== 0);
    open.delete();
    assert.ok(mrvol.volume(icosahedron(), { surface: 'limit' }) > 0);
  });

  test('a mesh too big for the limit form is refused at once, in words, before any of it is made', () => {
    // 1,310,720 triangles (the icosahedron at 8 levels): about 4.5 GB of form (it ran out of memory after 40 s)
    const big = mrvol.subdivide(icosahedron(), { levels: 8 });
    const triangles = big.faceCount;
    assert.equal(triangles, 1310720);
    const said = new RegExp(`the limit surface's volume of ${triangles} triangles needs about 4\\.5 GB .*keep the mesh's volume`);
    for (const call of [() => big.createEditor({ level: 0, surface: 'limit' }), () => big.info({ surface: 'limit' }),
                        () => big.computeTheta({ level: 0, surface: 'limit' }), () => mrvol.volume(big.toMesh(), { surface: 'limit' })])
      throwsMrvol(call, said);
    const editor = big.createEditor({ level: 0 });  // the mesh's volume: fine
    assert.ok(editor.volume() > 0);
    editor.delete();
    big.delete();
  });
});

describe('limit volume (CLI)', () => {
  test('volume --surface limit --json: volume directly and through theta^e agree', () => {
    const r = json(mrvolCli('volume', model('torus'), '--surface', 'limit', '--level', '1', '--json'));
    assert.equal(r.surface, 'limit');
    assert.equal(r.level, 1);
    const mesh = mrvol.readObj(readFileSync(model('torus'), 'utf8'));
    const mr = mrvol.openMesh(mesh);
    assert.equal(r.volume, mr.info({ surface: 'limit' }).volume);
    assert.ok(relErr(r.thetaVolume, r.volume) < 1e-10, `${r.thetaVolume} vs ${r.volume}`);
    assert.ok(relErr(r.volume, mr.info().volume) < 0.05 && r.volume !== mr.info().volume);
    mr.delete();
    const text = mrvolCli('volume', model('torus'), '--surface', 'limit', '--level', '1');
    assert.equal(text.status, 0, text.stderr);
    assert.match(text.stdout, /^theta +loop scheme, level 1, cage storage, limit surface \(computed\)$/m);
  });

  test('theta --surface limit writes a file that volume --theta reads for that surface only', () => {
    const obj = file('ico2.obj');
    const mr = mrvol.subdivide(icosahedron(), { levels: 2 });
    writeFileSync(obj, mrvol.writeObj(mr.toMesh()));
    mr.delete();
    const out = file('ico2-limit.theta');
    const r = json(mrvolCli('theta', obj, '--surface', 'limit', '-o', out, '--json'));
    assert.equal(r.surface, 'limit');
    const v = json(mrvolCli('volume', obj, '--theta', out, '--surface', 'limit', '--json'));
    assert.equal(v.source, 'file');
    assert.equal(v.thetaVolume, r.thetaVolume);
    assert.ok(relErr(v.thetaVolume, v.volume) < 1e-10);
    failsWith(mrvolCli('volume', obj, '--theta', out, '--json'), /ico2-limit\.theta: .*limit surface, not of the mesh surface/);
    usageError(mrvolCli('volume', obj, '--surface', 'smooth'), /--surface must be mesh or limit/);
    const open = file('open.obj');
    writeFileSync(open, mrvol.writeObj(openPatch()));
    failsWith(mrvolCli('volume', open, '--surface', 'limit', '--json'), /closed mesh/);
    // options the limit surface does not go with: usage errors (exit 2), before any reading
    usageError(mrvolCli('edit', model('torus'), '--surface', 'limit', '--keep', 'volume,centroid', '--move', '0:0.1,0,0', '-o', file('x.obj')),
      /--keep centroid keeps the mesh surface's centre of mass: not with --surface limit/);
    usageError(mrvolCli('edit', model('torus'), '--surface', 'limit', '--path', 'polynomial', '--move', '0:0.1,0,0', '-o', file('x.obj')),
      /--path polynomial sums the mesh's triangles: with --surface limit use --path auto or matrix-free/);
  });
});
