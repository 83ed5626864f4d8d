// The MAPS parametrisation of the remesher (collapseToTarget(..., { track: true }) in
// lib/remesh-collapse.mjs, its base -> input map in lib/remesh-param.mjs, the `parametrise`
// option of lib/remesh.mjs) on real meshes: three.js's torus and the npm bunny, with the real WASM core.
import { test, before } from 'node:test';
import assert from 'node:assert/strict';
import bunny from 'bunny';
import { TorusGeometry } from 'three';
import { createMrvol } from '../../lib/node.mjs';
import { remesh, weld } from '../../lib/remesh.mjs';
import { collapseToTarget } from '../../lib/remesh-collapse.mjs';
import { BaseParametrisation } from '../../lib/remesh-param.mjs';

let mrvol;
before(async () => {
  mrvol = await createMrvol();
});

function torusMesh() {
  const g = new TorusGeometry(1, 0.4, 24, 48);
  return weld({ positions: Float64Array.from(g.attributes.position.array), faces: Uint32Array.from(g.index.array) });
}

test('every collapsed vertex keeps barycentrics in one base triangle, and the map sends most back to themselves', () => {
  const torus = torusMesh();
  const base = collapseToTarget(torus, 80, null, { track: true });
  assert.equal(mrvol.validate(base).genus, 1);
  const { parameters } = base;
  assert.equal(parameters.length, torus.positions.length / 3);
  const faceSets = [];
  for (let t = 0; t < base.faces.length / 3; t++) faceSets.push(new Set(base.faces.slice(3 * t, 3 * t + 3)));
  let kept = 0;
  for (const { ids, weights, face } of parameters) {
    const sum = weights.reduce((s, w) => s + w, 0);
    assert.ok(Math.abs(sum - 1) < 1e-9, `weights sum to ${sum}`);
    assert.ok(weights.every((w) => w >= 0));
    if (ids.length === 1) kept++;
    else assert.ok(ids.every((id) => faceSets[face].has(id)), 'the weights are over the corners of the face given');
  }
  assert.equal(kept, base.positions.length / 3, 'the base vertices are their own parameter');
  // An input vertex's own parameter maps back onto it unless the map folds there (clamped points).
  const map = new BaseParametrisation(base, torus, parameters);
  const out = [0, 0, 0];
  let back = 0;
  for (let q = 0; q < parameters.length; q++) {
    assert.ok(map.map(parameters[q].ids, parameters[q].weights, out), `vertex ${q} maps`);
    if (Math.hypot(out[0] - torus.positions[3 * q], out[1] - torus.positions[3 * q + 1], out[2] - torus.positions[3 * q + 2]) < 1e-9) back++;
  }
  assert.ok(back >= 0.9 * parameters.length, `${back} of ${parameters.length} vertices map back onto themselves`);
});

test('parametrise: the bunny remeshed through the map, unfolded and near the input', async () => {
  const input = { positions: Float64Array.from(bunny.positions.flat()), faces: Uint32Array.from(bunny.cells.flat()) };
  const r = await remesh(mrvol, input, { levels: 2, baseFaces: 250, parametrise: true });
  assert.equal(r.flippedTriangles, 0);
  assert.equal(r.levels, 2);
  assert.ok(r.hausdorff < 0.015, `Hausdorff ${r.hausdorff}`);
  assert.ok(Math.abs(r.volumeChange) < 0.01, `volume change ${r.volumeChange}`);
});

test('fallback: above the goal the parametrised fit is tried too and the closer unfolded one kept; false turns it off', async () => {
  const input = { positions: Float64Array.from(bunny.positions.flat()), faces: Uint32Array.from(bunny.cells.flat()) };
  // A goal no fit reaches: the fallback always runs.
  const options = { levels: 1, baseFaces: 250, hausdorffGoal: 1e-9 };
  const off = await remesh(mrvol, input, { ...options, parametrise: false });
  assert.equal(off.fit, 'simplified');
  assert.equal(off.parametrisedFallback, null);
  const forced = await remesh(mrvol, input, { ...options, parametrise: true });
  assert.equal(forced.fit, 'parametrised');
  assert.equal(forced.parametrisedFallback, null);
  const auto = await remesh(mrvol, input, options);
  const fallback = auto.parametrisedFallback;
  assert.ok(fallback, 'the fallback ran');
  assert.equal(fallback.hausdorff, forced.hausdorff);
  assert.equal(fallback.kept, forced.flippedTriangles === 0 && forced.hausdorff < off.hausdorff);
  assert.equal(auto.fit, fallback.kept ? 'parametrised' : 'simplified');
  assert.equal(auto.hausdorff, fallback.kept ? forced.hausdorff : off.hausdorff);
  assert.equal(auto.flippedTriangles, 0);
  // Within the goal the default fit stands alone.
  const near = await remesh(mrvol, input, { ...options, hausdorffGoal: 1 });
  assert.equal(near.parametrisedFallback, null);
  assert.equal(near.fit, 'simplified');
});
