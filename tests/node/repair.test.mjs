// lib/repair.mjs's non-manifold check told what changed since a mesh had no non-manifold face
// (faces removed around some vertices, faces appended: what the repair's passes do) finds the same
// faces as checking the whole mesh: over random removals and appended faces of every kind that
// makes a mesh non-manifold (a duplicate, a reversed copy, a third face on an edge, a face joining
// two fans at a vertex, a fan closing a hole).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import bunny from 'bunny';
import { nonManifoldFaces } from '../../lib/repair.mjs';

test('the check of what changed finds the faces of the check of the whole mesh', () => {
  let seed = 11;
  const random = () => ((seed = (seed * 1103515245 + 12345) % 2147483648) / 2147483648);
  const pick = (n) => Math.floor(random() * n);
  const vertexCount = bunny.positions.length;
  // The bunny without its non-manifold faces (none: checked) is the clean mesh.
  const clean = Uint32Array.from(bunny.cells.flat());
  assert.equal(nonManifoldFaces(clean, vertexCount).count, 0);
  let found = 0;
  for (let trial = 0; trial < 60; trial++) {
    const faceCount = clean.length / 3;
    // Faces removed (their corners touched).
    const removed = new Uint8Array(faceCount), touched = new Uint8Array(vertexCount + 1);
    for (let r = 0, n = pick(40); r < n; r++) {
      const f = pick(faceCount);
      removed[f] = 1;
      for (let j = 0; j < 3; j++) touched[clean[3 * f + j]] = 1;
    }
    const faces = [];
    for (let f = 0; f < faceCount; f++) if (!removed[f]) faces.push(clean[3 * f], clean[3 * f + 1], clean[3 * f + 2]);
    const appendedFrom = faces.length / 3;
    // Faces appended, of every kind.
    for (let a = 0, n = 1 + pick(12); a < n; a++) {
      const f = 3 * pick(appendedFrom), [x, y, z] = [faces[f], faces[f + 1], faces[f + 2]];
      const g = 3 * pick(appendedFrom);
      switch (pick(5)) {
        case 0: faces.push(x, y, z); break;                  // a duplicate
        case 1: faces.push(x, z, y); break;                  // reversed
        case 2: faces.push(y, x, faces[g]); break;           // a third face on edge x-y (or a fold)
        case 3: faces.push(x, faces[g], faces[g + 1]); break;  // a face joining x to a far edge
        default:                                             // a fan on a new vertex, around a face's edges
          faces.push(y, x, vertexCount, z, y, vertexCount, x, z, vertexCount);
      }
    }
    const all = Uint32Array.from(faces), n = vertexCount + 1;
    const whole = nonManifoldFaces(all, n), local = nonManifoldFaces(all, n, { touched, appendedFrom });
    assert.equal(local.count, whole.count, `trial ${trial}: count`);
    assert.deepEqual(local.drop, whole.drop, `trial ${trial}: the faces dropped`);
    found += whole.count;
  }
  // The trials made non-manifold faces to find.
  assert.ok(found > 100, `${found} non-manifold faces found`);
});
