// Intersecting triangle pairs (lib/self-intersection.mjs): none on closed surfaces that do not
// cross themselves (made and from a package), the known pairs on made ones, pieces told apart.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import bunny from 'bunny';
import { selfIntersections } from '../../lib/self-intersection.mjs';

const mesh = (points, triangles) => ({ positions: Float64Array.from(points.flat()), faces: Uint32Array.from(triangles.flat()) });

// An octahedron around `c` of radius r: 6 vertices, 8 outward triangles.
function octahedron([x, y, z], r, first = 0) {
  const points = [[x + r, y, z], [x - r, y, z], [x, y + r, z], [x, y - r, z], [x, y, z + r], [x, y, z - r]];
  const triangles = [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]]
    .map((t) => t.map((i) => i + first));
  return { points, triangles };
}

test('a closed octahedron and the npm bunny do not intersect themselves', () => {
  const o = octahedron([0, 0, 0], 1);
  assert.deepEqual(selfIntersections(...Object.values(mesh(o.points, o.triangles))),
                   { withinPieces: 0, betweenPieces: 0, first: null, firstWithin: null, firstBetween: null, complete: true });
  const b = mesh(bunny.positions, bunny.cells);
  const found = selfIntersections(b.positions, b.faces);
  assert.equal(found.withinPieces + found.betweenPieces, 0);
});

test('two overlapping octahedra: pairs between pieces only', () => {
  const a = octahedron([0, 0, 0], 1), b = octahedron([0.5, 0.1, 0.2], 1, 6);
  const m = mesh([...a.points, ...b.points], [...a.triangles, ...b.triangles]);
  const found = selfIntersections(m.positions, m.faces);
  assert.equal(found.withinPieces, 0);
  assert.ok(found.betweenPieces > 0);
  // the first pair: a face of each octahedron
  assert.ok(found.first[0] < 8 !== found.first[1] < 8, `pair ${found.first}`);
});

test('a strip whose far triangle pierces its first, and a piece crossing it: one pair within, one between', () => {
  const points = [
    [0, 0, 0], [2, 0, 0], [0, 2, 0],          // A (0, 1, 2) in the plane z = 0
    [-1, 3, 2],                               // C (2, 3, 4) joins A to B through shared vertices
    [0.5, 0.5, 1], [0.5, 0.5, -1], [0.6, 0.3, 0.5],  // B (4, 5, 6): its edge 4-5 pierces A at (0.5, 0.5, 0)
    [1, 0.2, -1], [1, 0.2, 1], [1, 0.8, 0],   // E (7, 8, 9), another piece: crosses A along x = 1
    [10, 10, 10], [11, 10, 10], [10, 11, 10], // D, far away
  ];
  const triangles = [[0, 1, 2], [2, 3, 4], [4, 5, 6], [7, 8, 9], [10, 11, 12]];
  const m = mesh(points, triangles);
  const found = selfIntersections(m.positions, m.faces);
  assert.equal(found.withinPieces, 1);
  assert.equal(found.betweenPieces, 1);
  assert.equal(found.complete, true);
  const pair = [...found.first].sort();
  assert.ok(String(pair) === '0,2' || String(pair) === '0,3', `first pair ${found.first}`);
  // stopped at the first pair
  const one = selfIntersections(m.positions, m.faces, { limit: 1 });
  assert.equal(one.withinPieces + one.betweenPieces, 1);
  assert.equal(one.complete, false);
  // stopped at the first pair within a piece; the first pair of two pieces named apart
  const within = selfIntersections(m.positions, m.faces, { limitWithin: 1 });
  assert.equal(within.withinPieces, 1);
  assert.deepEqual([...within.firstWithin].sort(), [0, 2]);
  assert.ok(within.firstBetween === null || String([...within.firstBetween].sort()) === '0,3', `${within.firstBetween}`);
  assert.equal(within.complete, false);
  // two pieces passing through each other and nothing else: named, not a fold, the whole mesh walked
  const apart = mesh(points, [[0, 1, 2], [7, 8, 9], [10, 11, 12]]);
  const between = selfIntersections(apart.positions, apart.faces, { limitWithin: 1 });
  assert.equal(between.firstWithin, null);
  assert.deepEqual([...between.firstBetween].sort(), [0, 1]);
  assert.equal(between.complete, true);
  // the same pair found by its faces in another order (the BVH reorders them; the answer names the caller's faces)
  const reversed = mesh(points, [...triangles].reverse());
  const again = selfIntersections(reversed.positions, reversed.faces);
  assert.equal(again.withinPieces, 1);
  assert.ok([...again.first].sort().every((f) => [4, 2, 1].includes(f)), `first pair ${again.first}`);
});

test('pairs that only touch do not cross: a point twice in the file, flat neighbours with round-off', () => {
  // two triangles meeting at one point given as two vertices (an unwelded pole): touching, not crossing
  const touching = mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 0], [-1, 0, 0.2], [0, -1, -0.3]], [[0, 1, 2], [3, 4, 5]]);
  assert.equal(selfIntersections(touching.positions, touching.faces).withinPieces + selfIntersections(touching.positions, touching.faces).betweenPieces, 0);
  // a hinge: two triangles along a seam given twice (its two copies 1e-16 apart, as three's sphere writes it)
  const hinge = mesh([[0, 0, 0], [1, 0, 0], [0.5, 1, -0.3], [0, 0, 1e-16], [1, 0, -1e-16], [0.5, -1, 0.4]], [[0, 1, 2], [4, 3, 5]]);
  assert.equal(selfIntersections(hinge.positions, hinge.faces).withinPieces + selfIntersections(hinge.positions, hinge.faces).betweenPieces, 0);
  // a flat 20 x 20 grid whose z is round-off (what synthesis leaves on a CAD part's face): three's
  // float32 test took 1,076 such pairs on a quad pipe's end for crossings
  let seed = 7;
  const random = () => ((seed = (seed * 16807) % 2147483647) / 2147483647 - 0.5);
  const points = [], triangles = [];
  for (let j = 0; j <= 20; j++) for (let i = 0; i <= 20; i++) points.push([i / 20 + 1e-3 * random(), j / 20 + 1e-3 * random(), 1e-16 * random()]);
  for (let j = 0; j < 20; j++)
    for (let i = 0; i < 20; i++) {
      const v = j * 21 + i;
      triangles.push([v, v + 1, v + 22], [v, v + 22, v + 21]);
    }
  const flat = mesh(points, triangles);
  assert.equal(selfIntersections(flat.positions, flat.faces).withinPieces, 0);
  // one of its triangles folded back over its neighbours, in the plane: that overlap is a crossing
  const folded = Float64Array.from(flat.positions);
  folded[3 * (10 * 21 + 10)] += 0.12;  // a vertex pulled past its ring
  assert.ok(selfIntersections(folded, flat.faces).withinPieces > 0);
  // and a real crossing through the plane
  const pierced = mesh([...points, [0.52, 0.52, -1], [0.53, 0.52, 1], [0.6, 0.7, 1]], [...triangles, [441, 442, 443]]);
  assert.ok(selfIntersections(pierced.positions, pierced.faces).betweenPieces > 0);
});
