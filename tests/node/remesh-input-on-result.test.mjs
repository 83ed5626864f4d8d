// The input's closest points on a moving fit asked again only where they can matter
// (lib/remesh-input-on-result.mjs), on the real WASM core's trees: after rounds of vertex moves
// (a few vertices, a patch, every vertex, moves undone), every point beyond the limit has exactly
// the answer of asking every point (distance, closest point, the corners of its triangle), and
// every other point's entry is an upper bound of its distance that is within the limit.
import { test, before } from 'node:test';
import assert from 'node:assert/strict';
import bunny from 'bunny';
import { createMrvol } from '../../lib/node.mjs';
import { Surface } from '../../lib/remesh.mjs';
import { InputOnResult } from '../../lib/remesh-input-on-result.mjs';
import { boundingDiagonal } from '../../lib/geometry.mjs';

before(async () => {
  Surface.core = await createMrvol({ threads: 1 });
});

const fit = { positions: Float64Array.from(bunny.positions.flat()), faces: Uint32Array.from(bunny.cells.flat()) };

/** Every point asked on the fit as it is: { distances, points, corners }. */
function askAll(input, positions, faces) {
  const surface = new Surface({ positions, faces }, { normals: false });
  const answers = surface.closestMany(input), index = surface.index;
  surface.dispose();
  const corners = new Uint32Array(answers.triangles.length * 3);
  answers.triangles.forEach((t, i) => corners.set(index.subarray(3 * t, 3 * t + 3), 3 * i));
  return { ...answers, corners };
}

test('beyond the limit the answers of asking every point; within it upper bounds', () => {
  let seed = 7;
  const random = () => ((seed = (seed * 1103515245 + 12345) % 2147483648) / 2147483648);
  const diagonal = boundingDiagonal(fit.positions), limit = 0.002 * diagonal;
  const vertexCount = fit.positions.length / 3;
  // The input: points near the surface (most within the limit) and a few farther out.
  const input = new Float64Array(3 * 4000);
  for (let s = 0; s < 4000; s++) {
    const v = Math.floor(random() * vertexCount), r = (s % 10 ? 0.003 : 0.05) * diagonal;
    for (let k = 0; k < 3; k++) input[3 * s + k] = fit.positions[3 * v + k] + r * (random() - 0.5);
  }
  const positions = fit.positions.slice(), start = positions.slice();
  const closest = new InputOnResult(input, limit);
  const moves = [
    () => {},  // nothing moved
    () => { for (let t = 0; t < 20; t++) { const v = Math.floor(random() * vertexCount); for (let k = 0; k < 3; k++) positions[3 * v + k] += 0.01 * diagonal * (random() - 0.5); } },
    () => { const c = Math.floor(random() * vertexCount); for (let v = 0; v < vertexCount; v++) if (Math.hypot(positions[3 * v] - positions[3 * c], positions[3 * v + 1] - positions[3 * c + 1], positions[3 * v + 2] - positions[3 * c + 2]) < 0.1 * diagonal) positions[3 * v + 1] += 0.02 * diagonal; },
    () => { for (let i = 0; i < positions.length; i++) positions[i] *= 1.001; },
    () => positions.set(start),  // undone
    () => {},
  ];
  let asked = 0, skipped = 0;
  for (let round = 0; round < 3 * moves.length; round++) {
    moves[round % moves.length]();
    closest.update(positions, fit.faces);
    const all = askAll(input, positions, fit.faces);
    for (let i = 0; i < input.length / 3; i++) {
      if (all.distances[i] > limit || closest.distances[i] > limit) {
        asked++;
        assert.equal(closest.distances[i], all.distances[i], `round ${round}, point ${i}: distance`);
        for (let k = 0; k < 3; k++) {
          assert.equal(closest.points[3 * i + k], all.points[3 * i + k], `round ${round}, point ${i}: closest point`);
          assert.equal(closest.corners[3 * i + k], all.corners[3 * i + k], `round ${round}, point ${i}: triangle`);
        }
      } else {
        if (closest.distances[i] !== all.distances[i]) skipped++;
        assert.ok(closest.distances[i] >= all.distances[i], `round ${round}, point ${i}: an upper bound`);
      }
    }
  }
  // Both kinds were met: far points, and near ones left as they were while the fit moved.
  assert.ok(asked > 1000, `${asked} far answers checked`);
  assert.ok(skipped > 0, `${skipped} entries left as upper bounds`);
});
