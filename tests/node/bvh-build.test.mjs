// three-mesh-bvh's tree built in the core (mrvol.threeMeshBvh, wasm/core bvh_build.h) against the
// library's own build (MeshBVH, the version in package.json): the same packed nodes and the same
// reordered index, byte for byte, on every corpus model and on made meshes that reach the build's
// edge cases (a leaf of more than 10 triangles whose centres coincide, the depth limit of 40, flat
// and sliver triangles, vertices far from the origin); a Surface made on it answers as one made
// without it; bad input refused with a message, the module usable after.
import { before, test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { BufferAttribute, BufferGeometry } from 'three';
import { MeshBVH } from 'three-mesh-bvh';
import { createMrvol, MrvolError } from '../../lib/node.mjs';
import { Surface } from '../../lib/remesh.mjs';
import { CORPUS, makeCorpus } from '../../scripts/corpus.mjs';

let mrvol;
before(async () => {
  mrvol = await createMrvol({ threads: 1 });
  await makeCorpus({ big: false });
});

/** The library's build and the core's, on copies of the same float32 positions and index. */
function bothBuilds(positions, faces) {
  const pos = Float32Array.from(positions), index = Uint32Array.from(faces);
  const geometry = new BufferGeometry();
  geometry.setAttribute('position', new BufferAttribute(pos, 3));
  geometry.setIndex(new BufferAttribute(index.slice(), 1));
  const library = new MeshBVH(geometry, { verbose: false });
  const core = mrvol.threeMeshBvh(pos, index);
  return { library: { nodes: new Uint8Array(library._roots[0]), index: geometry.index.array }, core: { nodes: new Uint8Array(core.roots[0]), index: core.index } };
}

function assertSameBuild(positions, faces, what) {
  const { library, core } = bothBuilds(positions, faces);
  assert.equal(core.nodes.length, library.nodes.length, `${what}: node bytes`);
  assert.ok(Buffer.from(core.nodes).equals(Buffer.from(library.nodes)), `${what}: the packed nodes differ`);
  assert.deepEqual(core.index, library.index, `${what}: the reordered index differs`);
  return library.nodes.length / 32;
}

/** A deterministic pseudo-random generator in [0, 1). */
function random(seed) {
  let s = seed >>> 0;
  return () => ((s = (Math.imul(s, 1664525) + 1013904223) >>> 0) / 4294967296);
}

test('the same tree as three-mesh-bvh builds, on every corpus model', () => {
  let models = 0;
  for (const c of CORPUS) {
    if (c.big) continue;
    const m = mrvol.readMesh(readFileSync(c.file), { name: c.file });
    assertSameBuild(m.positions, m.faces, c.name);
    models++;
  }
  assert.ok(models >= 30, `${models} models`);
});

test('the same tree on the build\'s edge cases', () => {
  const rnd = random(3);
  // Random triangles (slivers and large ones among them) in a unit box, then moved far from the origin.
  const soup = (n, shift = 0, scale = 1) => {
    const positions = new Float64Array(9 * n), faces = new Uint32Array(3 * n);
    for (let i = 0; i < 9 * n; i++) positions[i] = shift + scale * rnd();
    for (let i = 0; i < 3 * n; i++) faces[i] = i;
    return { positions, faces };
  };
  for (const [name, m] of [['soup', soup(3000)], ['soup far away', soup(2000, 1e5, 3)], ['a few', soup(7)], ['one triangle', soup(1)]])
    assertSameBuild(m.positions, m.faces, name);
  // 40 copies of one triangle among others: their centres coincide, no split separates them (a leaf of 40).
  const copies = soup(200);
  for (let t = 100; t < 140; t++) for (let j = 0; j < 3; j++) copies.faces[3 * t + j] = copies.faces[3 * 99 + j];
  assertSameBuild(copies.positions, copies.faces, 'repeated triangles');
  // Centres at 2^-i along x: every split cuts off one triangle, past the depth limit of 40.
  const deep = { positions: new Float64Array(9 * 60), faces: new Uint32Array(3 * 60) };
  for (let t = 0; t < 60; t++) {
    const x = 2 ** -t;
    deep.positions.set([x, 0, 0, x, 1e-3, 0, x, 0, 1e-3], 9 * t);
    deep.faces.set([3 * t, 3 * t + 1, 3 * t + 2], 3 * t);
  }
  const { library } = bothBuilds(deep.positions, deep.faces);
  const leafCounts = [];
  const u16 = new Uint16Array(library.nodes.buffer);
  for (let n = 0; n < library.nodes.length / 32; n++) if (u16[16 * n + 15] === 0xffff) leafCounts.push(u16[16 * n + 14]);
  assert.ok(Math.max(...leafCounts) > 10, `the depth limit makes a leaf of more than 10 (${Math.max(...leafCounts)})`);
  assertSameBuild(deep.positions, deep.faces, 'past the depth limit');
  // A flat grid (every box flat on z, centres on a lattice: splits on ties).
  const grid = { positions: [], faces: [] };
  for (let i = 0; i <= 40; i++) for (let j = 0; j <= 40; j++) grid.positions.push(i, j, 0);
  for (let i = 0; i < 40; i++) for (let j = 0; j < 40; j++) {
    const a = 41 * i + j;
    grid.faces.push(a, a + 41, a + 1, a + 1, a + 41, a + 42);
  }
  assertSameBuild(grid.positions, grid.faces, 'flat grid');
});

test('a Surface on the core\'s tree answers as one on the library\'s', () => {
  const c = CORPUS.find((x) => x.name === 'teapot');
  const m = mrvol.readMesh(readFileSync(c.file), { name: c.file });
  const mesh = { positions: m.positions, faces: m.faces };
  const withCore = new Surface(mesh, { core: mrvol }), without = new Surface(mesh, { core: null });
  assert.deepEqual(withCore.index, without.index);
  const rnd = random(9);
  for (let q = 0; q < 500; q++) {
    const x = 4 * rnd() - 2, y = 3 * rnd() - 0.5, z = 4 * rnd() - 2;
    const a = { ...withCore.closest(x, y, z) }, b = without.closest(x, y, z);
    assert.equal(a.faceIndex, b.faceIndex, `query ${q}`);
    assert.equal(a.distance, b.distance, `query ${q}`);
  }
  withCore.dispose();
});

test('bad input is refused with a message; the module works after', () => {
  assert.throws(() => mrvol.threeMeshBvh(new Float32Array(9), new Uint32Array([0, 1, 3])), (e) => e instanceof MrvolError && /triangle 0 refers to vertex 3 but there are 3 vertices/.test(e.message));
  assert.throws(() => mrvol.threeMeshBvh(new Float32Array(9), new Uint32Array([0, 1])), (e) => e instanceof MrvolError && /3 vertex indices per triangle/.test(e.message));
  assert.throws(() => mrvol.threeMeshBvh(new Float32Array(9), new Uint32Array(0)), (e) => e instanceof MrvolError && /at least one triangle/.test(e.message));
  assert.throws(() => mrvol.threeMeshBvh(new Float64Array(9), new Uint32Array([0, 1, 2])), (e) => e instanceof MrvolError && /Float32Array/.test(e.message));
  assert.equal(mrvol.threeMeshBvh(new Float32Array([0, 0, 0, 1, 0, 0, 0, 1, 0]), new Uint32Array([0, 1, 2])).roots[0].byteLength, 32);
});
