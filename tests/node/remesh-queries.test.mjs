// The remesher's checks that remember what they asked (lib/remesh.mjs's centroidsOnSurface,
// lib/remesh-nudge.mjs's patchDistancesOn) give the answers of asking anew, as vertices move, move
// back and move again; and the nudge's choice of input samples to ask again near moved faces
// (movedNear) is the set a brute-force test over every sample and every moved face gives. On the
// real WASM core's trees, the bunny (npm `bunny`) as the surface and a jittered copy as the fit.
import { test, before } from 'node:test';
import assert from 'node:assert/strict';
import bunny from 'bunny';
import { createMrvol } from '../../lib/node.mjs';
import { centroidsOnSurface, Surface } from '../../lib/remesh.mjs';
import { movedNear, patchDistancesOn } from '../../lib/remesh-nudge.mjs';
import { boundingDiagonal } from '../../lib/geometry.mjs';

let surface;
const input = { positions: Float64Array.from(bunny.positions.flat()), faces: Uint32Array.from(bunny.cells.flat()) };
const diagonal = boundingDiagonal(input.positions);
before(async () => {
  Surface.core = await createMrvol({ threads: 1 });
  surface = new Surface(input);
});
const seeded = (seed) => () => ((seed = (seed * 1103515245 + 12345) % 2147483648) / 2147483648);

/** The faces of `faces` with a corner in `vertices`, ascending. */
function facesAt(faces, vertices) {
  const out = [];
  for (let f = 0; f < faces.length / 3; f++) if (vertices.has(faces[3 * f]) || vertices.has(faces[3 * f + 1]) || vertices.has(faces[3 * f + 2])) out.push(f);
  return out;
}

test('the checks that remember give the answers of asking anew, over moves, moves undone and moves again', () => {
  const random = seeded(3);
  const positions = input.positions.map((x) => x + 0.002 * diagonal * (random() - 0.5)), faces = input.faces;
  const faceCount = faces.length / 3, vertexCount = positions.length / 3;
  const centroidsOn = centroidsOnSurface(surface, faceCount), patchDistances = patchDistancesOn(surface, faceCount);
  const BARY = [[1 / 3, 1 / 3, 1 / 3], [2 / 3, 1 / 6, 1 / 6], [1 / 6, 2 / 3, 1 / 6], [1 / 6, 1 / 6, 2 / 3]];
  let hits = 0;
  for (let trial = 0; trial < 60; trial++) {
    const moved = new Set(Array.from({ length: 1 + Math.floor(random() * 4) }, () => Math.floor(random() * vertexCount)));
    const patch = facesAt(faces, moved);
    const saved = [...moved].map((v) => positions.slice(3 * v, 3 * v + 3));
    // Before (often asked already), moved, and (every other trial) moved back.
    const states = [() => {}, () => moved.forEach((v) => { for (let k = 0; k < 3; k++) positions[3 * v + k] += 0.01 * diagonal * (random() - 0.5); }),
      () => [...moved].forEach((v, j) => trial % 2 && positions.set(saved[j], 3 * v))];
    for (const change of states) {
      change();
      const near = centroidsOn(positions, faces, patch), distances = patchDistances(positions, faces, patch);
      patch.forEach((f, q) => {
        const [a, b, c] = [0, 1, 2].map((j) => 3 * faces[3 * f + j]);
        const centroid = [0, 1, 2].map((k) => (positions[a + k] + positions[b + k] + positions[c + k]) / 3);
        const hit = surface.closest(centroid[0], centroid[1], centroid[2]);
        assert.equal(near.distances[q], hit.distance, `trial ${trial}: face ${f}'s centroid distance`);
        assert.equal(near.triangles[q], hit.faceIndex, `trial ${trial}: face ${f}'s centroid triangle`);
        const samples = [a, b, c].map((v) => [positions[v], positions[v + 1], positions[v + 2]])
          .concat(BARY.map((w) => [0, 1, 2].map((k) => w[0] * positions[a + k] + w[1] * positions[b + k] + w[2] * positions[c + k])));
        const largest = Math.max(...samples.map(([x, y, z]) => surface.closest(x, y, z).distance));
        assert.equal(distances[q], largest, `trial ${trial}: face ${f}'s samples' largest distance`);
      });
      hits += patch.length;
    }
  }
  assert.ok(hits > 300, `${hits} faces checked`);
});

test("the samples asked again near moved faces are the brute force's", () => {
  const random = seeded(11);
  const positions = input.positions.map((x) => x + 0.01 * diagonal * (random() - 0.5)), faces = input.faces;
  const faceCount = faces.length / 3;
  for (const [trial, share, far] of [[0, 0.01, 0.002], [1, 0.2, 0.05], [2, 0.001, 0.3], [3, 0.5, 0.01]]) {
    // Samples near the surface, each with a distance (a few large: the largest sets the cube).
    const n = 3000, samples = new Float64Array(3 * n), distances = new Float64Array(n);
    for (let i = 0; i < n; i++) {
      const v = Math.floor(random() * positions.length / 3);
      for (let k = 0; k < 3; k++) samples[3 * i + k] = positions[3 * v + k] + 0.02 * diagonal * (random() - 0.5);
      distances[i] = (i % 97 === 0 ? far : 0.004 * random()) * diagonal;
    }
    const faceMoved = new Uint8Array(faceCount);
    for (let f = 0; f < faceCount; f++) faceMoved[f] = random() < share ? 1 : 0;
    const asked = new Uint8Array(n);
    for (let i = 0; i < n; i += 5) asked[i] = 1;
    const expected = asked.slice();
    // The brute force: as the grid's query did it (the cube about each moved box, then the box distance).
    let farthest = 0;
    for (const d of distances) farthest = Math.max(farthest, d);
    for (let f = 0; f < faceCount; f++) {
      if (!faceMoved[f]) continue;
      const lo = [0, 0, 0], hi = [0, 0, 0];
      for (let k = 0; k < 3; k++) {
        const [a, b, c] = [0, 1, 2].map((j) => positions[3 * faces[3 * f + j] + k]);
        lo[k] = Math.min(a, b, c), hi[k] = Math.max(a, b, c);
      }
      const centre = [0, 1, 2].map((k) => (lo[k] + hi[k]) / 2), half = Math.max(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]) / 2;
      for (let i = 0; i < n; i++) {
        if (expected[i] || ![0, 1, 2].every((k) => Math.abs(samples[3 * i + k] - centre[k]) <= half + farthest)) continue;
        let squared = 0;
        for (let k = 0; k < 3; k++) {
          const x = samples[3 * i + k], gap = x < lo[k] ? lo[k] - x : x > hi[k] ? x - hi[k] : 0;
          squared += gap * gap;
        }
        if (Math.sqrt(squared) <= distances[i] * (1 + 1e-9) + 1e-12) expected[i] = 1;
      }
    }
    movedNear(samples, distances, positions, faces, faceMoved, asked);
    assert.deepEqual(asked, expected, `trial ${trial}`);
    const added = expected.reduce((s, x) => s + x, 0) - Math.ceil(n / 5);
    assert.ok(added > 0, `trial ${trial}: some samples asked again (${added})`);
  }
});
