// A hierarchy found in one instance of the module and handed to another (the web app's file
// worker detects, the page opens): MultiresMesh.hierarchyArrays() and openMeshWithHierarchy. The
// mesh opened from the arrays is the one openMesh gives (info, fingerprint, levels, faces of every
// level, vertex order, depths) and edits alike, on samples, a shuffled mesh and one with a
// boundary, in a second module instance; arrays that do not fit give a MrvolError, never a crash.
import { test, describe, before } from 'node:test';
import assert from 'node:assert/strict';
import { createMrvol } from '../../lib/node.mjs';
import { loadModel, openPatch, shuffleMesh, throwsMrvol } from './helpers.mjs';

let finder, opener;
before(async () => {
  finder = await createMrvol();
  opener = await createMrvol(); // another instance: nothing shared but the arrays
});

const fixtures = () => {
  const spiky = loadModel(finder, 'spiky-ball');
  const sub = finder.subdivide({ positions: openPatch().positions, faces: openPatch().faces }, { levels: 3 });
  const patch = sub.toMesh();
  sub.delete();
  return [
    ['spiky-ball', spiky],
    ['bunny-remeshed', loadModel(finder, 'bunny-remeshed')],
    ['spiky-ball shuffled', shuffleMesh(spiky, 7, { shuffleFaces: true }).mesh],
    ['a subdivided patch with a boundary', patch],
  ];
};

// A plain copy of the arrays, as a structured clone (postMessage) gives them.
const cloned = (arrays) => structuredClone(arrays);

function sameMesh(a, b, where) {
  assert.deepEqual({ ...b.info(), baseVertexIndices: [...b.info().baseVertexIndices] },
    { ...a.info(), baseVertexIndices: [...a.info().baseVertexIndices] }, `${where}: info`);
  assert.equal(b.fingerprint(), a.fingerprint(), `${where}: fingerprint`);
  assert.deepEqual(b.faces(), a.faces(), `${where}: faces`);
  for (let l = 0; l <= a.levels; ++l) assert.deepEqual(b.levelFaces(l), a.levelFaces(l), `${where}: level ${l} faces`);
  assert.deepEqual(b.hierarchyOrder(), a.hierarchyOrder(), `${where}: hierarchy order`);
  assert.deepEqual(b.depths(), a.depths(), `${where}: depths`);
}

describe('openMeshWithHierarchy opens what openMesh opens', () => {
  for (const [name, index] of [['spiky-ball', 0], ['bunny-remeshed', 1], ['spiky-ball shuffled', 2], ['a subdivided patch with a boundary', 3]]) {
    test(name, () => {
      const mesh = fixtures()[index][1];
      const found = finder.openMesh(mesh);
      const arrays = cloned(found.hierarchyArrays());
      const opened = opener.openMeshWithHierarchy(mesh, arrays);
      const direct = opener.openMesh(mesh);
      try {
        assert.ok(found.levels >= 1, 'a hierarchy to hand over');
        sameMesh(direct, opened, name);
        // the same edit on both gives the same shape and volume
        const level = Math.max(0, direct.levels - 3);
        const edits = [direct, opened].map((mr) => {
          const ed = mr.createEditor({ level });
          const cage = ed.cagePositions(), held = new Uint8Array(ed.cageSize);
          held[0] = 1;
          cage[0] += 0.1, cage[1] -= 0.05;
          const report = ed.deformCage(cage, held, { tolerance: 1e-9 });
          const out = { positions: ed.positions(), volume: ed.volume(), path: ed.path(), error: report.relativeError };
          ed.delete();
          return out;
        });
        assert.deepEqual(edits[1], edits[0], `${name}: the same edit`);
      } finally {
        for (const mr of [found, opened, direct]) mr.delete();
      }
    });
  }
});

describe('arrays that do not fit are refused in words', () => {
  test('each kind of damage', () => {
    const mesh = loadModel(finder, 'spiky-ball');
    const found = finder.openMesh(mesh);
    const good = found.hierarchyArrays();
    found.delete();
    const damaged = (change) => {
      const a = cloned(good);
      change(a);
      return a;
    };
    const cases = [
      [(a) => { a.inputIndex[1] = a.inputIndex[0]; }, /not a permutation/],
      [(a) => { a.inputIndex[0] = 1e9; }, /not a permutation/],
      [(a) => { a.coarseFaces[0] = good.vertexCount[good.levels]; }, /level face index .* out of range/],
      [(a) => { a.coarseFaces = a.coarseFaces.subarray(3); }, /faces of levels/],
      [(a) => { a.ends[2 * good.vertexCount[0]] = 0xffffffff; }, /end index .* out of range/],
      [(a) => { a.ends[0] = 0; }, /end index .* out of range/],
      [(a) => { a.wings[2 * good.vertexCount[good.levels] - 1] = good.vertexCount[good.levels]; }, /wing index .* out of range/],
      [(a) => { a.vertexCount = a.vertexCount.subarray(1); }, /vertex counts/],
      [(a) => { a.levels = 40; }, /levels 40/],
      [(a) => { a.boundary = new Uint8Array(3); }, /per-vertex arrays/],
      [(a) => { a.ends = Array.from(a.ends); }, /expects the arrays/],
      [(a) => { delete a.topology; }, /expects the arrays/],
    ];
    for (const [change, message] of cases) throwsMrvol(() => opener.openMeshWithHierarchy(mesh, damaged(change)), message);
    const other = loadModel(finder, 'icosahedron');
    throwsMrvol(() => opener.openMeshWithHierarchy(other, good), /for 642 vertices, the mesh has 12/);
    // faces that are not the arrays' (same vertex count): an index past the end, or a count not 4^n F0
    const faces = mesh.faces.slice();
    faces[5] = mesh.positions.length;
    throwsMrvol(() => opener.openMeshWithHierarchy({ positions: mesh.positions, faces }, good), /face index .* out of range/);
    throwsMrvol(() => opener.openMeshWithHierarchy({ positions: mesh.positions, faces: mesh.faces.subarray(3) }, good), /face count|faces of levels/);
    // the module still works
    const mr = opener.openMeshWithHierarchy(mesh, cloned(good));
    assert.equal(mr.info().vertices, 642);
    mr.delete();
  });
});
