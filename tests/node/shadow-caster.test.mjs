// web/shadow-caster.js: a big mesh's floor shadow from a coarser level of its hierarchy (the core's
// levelFaces), on the fine mesh's vertices. Real hierarchies (the API's subdivide, then openMesh on the
// mesh with its vertices shuffled): the coarse faces are a closed, consistently oriented surface on the
// vertices of that level, each 1/4 as many per level, with nearly the fine volume; a mesh within the
// bound keeps its own faces.
import { test, before } from 'node:test';
import assert from 'node:assert/strict';
import { createMrvol } from '../../lib/node.mjs';
import { shadowFaces, shadowLevel } from '../../web/shadow-caster.js';
import { icosahedron, shuffleMesh } from './helpers.mjs';

let mrvol;
before(async () => { mrvol = await createMrvol(); });

function volume(positions, faces) {
  let v = 0;
  for (let f = 0; f < faces.length; f += 3) {
    const [a, b, c] = [faces[f], faces[f + 1], faces[f + 2]].map((i) => [positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]]);
    v += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
  }
  return v / 6;
}

/** Each directed edge once and its opposite present: closed and consistently oriented. */
function closedOriented(faces) {
  const edges = new Set();
  for (let f = 0; f < faces.length; f += 3)
    for (let k = 0; k < 3; k++) {
      const key = `${faces[f + k]},${faces[f + (k + 1) % 3]}`;
      if (edges.has(key)) return false;
      edges.add(key);
    }
  return [...edges].every((e) => edges.has(e.split(',').reverse().join(',')));
}

test('coarser levels of a shuffled subdivision hierarchy: closed, oriented, a quarter per level, the volume kept', () => {
  const fine = mrvol.subdivide(icosahedron(), { levels: 4 });
  const shuffled = shuffleMesh(fine.toMesh(), 7, { shuffleFaces: true }).mesh;
  fine.delete();
  const mr = mrvol.openMesh(shuffled);
  const faces = mr.faces(), depths = mr.depths(), positions = mr.positions(), levels = mr.info().levels;
  const maxDepth = depths.reduce((a, b) => Math.max(a, b), 0);
  const fineVolume = volume(positions, faces);
  try {
    assert.equal(shadowFaces(mr, levels, faces.length / 3, faces.length / 3), null, 'within the bound: its own faces');
    for (const [maxTriangles, levelsUp] of [[faces.length / 3 - 1, 1], [faces.length / 12 - 1, 2]]) {
      const coarse = shadowFaces(mr, levels, faces.length / 3, maxTriangles);
      assert.equal(coarse.length, faces.length / 4 ** levelsUp, `${levelsUp} levels up`);
      assert.ok(closedOriented(coarse));
      // only the vertices of that level
      assert.ok(coarse.every((v) => depths[v] <= maxDepth - levelsUp));
      assert.ok(Math.abs(volume(positions, coarse) - fineVolume) < 0.05 * fineVolume, `volume ${volume(positions, coarse)} vs ${fineVolume}`);
    }
  } finally {
    mr.delete();
  }
});

test('the level for a bound: a quarter of the triangles per level up, never below level 0', () => {
  assert.equal(shadowLevel(1_310_720, 5, 200_000), 3);
  assert.equal(shadowLevel(200_000, 5, 200_000), 5);
  assert.equal(shadowLevel(1_310_720, 1, 200_000), 0);
});
