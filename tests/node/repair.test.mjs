// lib/repair.mjs's checks told what changed since the last pass (faces removed around some
// vertices, faces appended: what the repair's passes do) find what checking the whole mesh finds:
// the non-manifold faces, over random removals and appended faces of every kind that makes a mesh
// non-manifold (a duplicate, a reversed copy, a third face on an edge, a face joining two fans at a
// vertex, a fan closing a hole); the holes of a closed mesh with faces removed (the same fill); the
// folds of a mesh whose folds were cut out and its holes filled. Sharp corners are not folds: closed
// meshes whose faces meet at 55-70 degrees (tetrahedra, a spike) pass the repair unchanged.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import bunny from 'bunny';
import { fillHoles, foldedFaces, nonManifoldFaces, repair } from '../../lib/repair.mjs';

/** A closed sphere of rows x columns quads (split) and two poles. */
function sphere(rows, columns) {
  const positions = [0, 0, 1], faces = [];
  for (let r = 1; r < rows; r++)
    for (let c = 0; c < columns; c++) {
      const t = (Math.PI * r) / rows, q = (2 * Math.PI * c) / columns;
      positions.push(Math.sin(t) * Math.cos(q), Math.sin(t) * Math.sin(q), Math.cos(t));
    }
  const south = positions.length / 3, at = (r, c) => 1 + (r - 1) * columns + (c % columns);
  positions.push(0, 0, -1);
  for (let c = 0; c < columns; c++) faces.push(0, at(1, c), at(1, c + 1), south, at(rows - 1, c + 1), at(rows - 1, c));
  for (let r = 1; r < rows - 1; r++)
    for (let c = 0; c < columns; c++) faces.push(at(r, c), at(r + 1, c), at(r + 1, c + 1), at(r, c), at(r + 1, c + 1), at(r, c + 1));
  return { positions: Float64Array.from(positions), faces: Uint32Array.from(faces) };
}

/** The mesh without the faces of `drop` (a mask), and the mask of their corners. */
function without(mesh, drop) {
  const faces = [], touched = new Uint8Array(mesh.positions.length / 3);
  for (let f = 0; f < drop.length; f++) {
    if (!drop[f]) faces.push(mesh.faces[3 * f], mesh.faces[3 * f + 1], mesh.faces[3 * f + 2]);
    else for (let j = 0; j < 3; j++) touched[mesh.faces[3 * f + j]] = 1;
  }
  return { mesh: { positions: mesh.positions, faces: Uint32Array.from(faces) }, touched };
}

const seeded = (seed) => () => ((seed = (seed * 1103515245 + 12345) % 2147483648) / 2147483648);

test('the check of what changed finds the faces of the check of the whole mesh', () => {
  const random = seeded(11);
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

test('the fill of a closed mesh with faces removed, told where they went, fills the same holes', () => {
  const random = seeded(5), closed = sphere(24, 32), faceCount = closed.faces.length / 3;
  let filled = 0;
  for (let trial = 0; trial < 40; trial++) {
    const drop = new Uint8Array(faceCount);
    // Single faces and patches (holes of 3 to tens of edges, some joined).
    for (let r = 0, n = 1 + Math.floor(random() * 20); r < n; r++) {
      const f = Math.floor(random() * faceCount);
      drop[f] = 1;
      if (random() < 0.3) for (let g = f; g < Math.min(faceCount, f + 6); g++) drop[g] = 1;
    }
    const { mesh, touched } = without(closed, drop);
    const whole = fillHoles(mesh, 30), local = fillHoles(mesh, 30, touched);
    for (const key of ['holesFilled', 'holeEdges', 'holesLeft', 'largestLeft']) assert.equal(local[key], whole[key], `trial ${trial}: ${key}`);
    assert.deepEqual(local.mesh.faces, whole.mesh.faces, `trial ${trial}: faces`);
    assert.deepEqual(local.mesh.positions, whole.mesh.positions, `trial ${trial}: positions`);
    filled += whole.holesFilled;
  }
  assert.ok(filled > 100, `${filled} holes filled`);
});

test('the fold check told what the cut and the fill changed finds the folds of the whole mesh', () => {
  const random = seeded(9);
  let found = 0;
  for (let trial = 0; trial < 40; trial++) {
    // A sphere with vertices pushed through the surface (folds), its folds cut out and filled: the
    // fill's fans and their neighbours can fold again (a pushed vertex on the hole's rim).
    // Every other trial, noise on every vertex too: faces with one neighbour against them (not
    // folded, kept) that a fan beside them can fold.
    const mesh = sphere(16, 20), n = mesh.positions.length / 3;
    for (let r = 0, m = 1 + Math.floor(random() * 12); r < m; r++) {
      const v = Math.floor(random() * n), s = -0.6 - random();
      for (let k = 0; k < 3; k++) mesh.positions[3 * v + k] *= s;
    }
    if (trial % 2) for (let i = 0; i < mesh.positions.length; i++) mesh.positions[i] += 0.25 * (random() - 0.5);
    const first = foldedFaces(mesh);
    const cut = without(mesh, first.drop), appendedFrom = cut.mesh.faces.length / 3;
    const filled = fillHoles(cut.mesh, 1000).mesh;
    const whole = foldedFaces(filled), local = foldedFaces(filled, { touched: cut.touched, appendedFrom });
    assert.equal(local.count, whole.count, `trial ${trial}: count`);
    assert.deepEqual(local.drop, whole.drop, `trial ${trial}: the faces dropped`);
    found += whole.count;
  }
  assert.ok(found >= 5, `${found} folds found after the fills`);
});

test('sharp corners are not folds: tetrahedra and a spike pass the repair unchanged; a face turned over is found', () => {
  const mesh = (positions, faces) => ({ positions: Float64Array.from(positions), faces: Uint32Array.from(faces) });
  // Each triangle as its corners' coordinates, from its smallest corner on (orientation kept), sorted.
  const triangles = (m) => {
    const out = [];
    for (let f = 0; f < m.faces.length / 3; f++) {
      const corners = [0, 1, 2].map((j) => Array.from(m.positions.subarray(3 * m.faces[3 * f + j], 3 * m.faces[3 * f + j] + 3)).join(' '));
      const first = corners.indexOf([...corners].sort()[0]);
      out.push([0, 1, 2].map((j) => corners[(first + j) % 3]).join(' | '));
    }
    return out.sort();
  };
  const tetFaces = [0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3];
  const s = Math.sqrt(8 / 9), t = Math.sqrt(2 / 9), u = Math.sqrt(2 / 3);
  const closed = {
    // The corner of a cube cut off: the slanted face meets the other three at 54.7 degrees (its
    // normal 125 degrees from theirs), as a part's sharp corner does. The 'remesh --repair' of this
    // tetrahedron used to cut every face out ("the input has no triangle").
    'corner tetrahedron': mesh([0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1], tetFaces),
    'regular tetrahedron': mesh([0, 0, 1, s, 0, -1 / 3, -t, u, -1 / 3, -t, -u, -1 / 3], [0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2]),
    // A four-sided pyramid three times as high as wide.
    'spike': mesh([-0.5, -0.5, 0, 0.5, -0.5, 0, 0.5, 0.5, 0, -0.5, 0.5, 0, 0, 0, 3],
                  [0, 2, 1, 0, 3, 2, 0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4]),
  };
  for (const [name, m] of Object.entries(closed)) {
    assert.equal(foldedFaces(m).count, 0, `${name}: no fold`);
    const { mesh: out, report } = repair(m);
    assert.equal(report.foldedFaces, 0, `${name}: folds reported`);
    // The same oriented triangles (the weld may number the vertices its own way).
    assert.deepEqual(triangles(out), triangles(m), `${name}: the faces kept`);
  }
  // The corner tetrahedron open (its slanted face missing) is closed by the fill, not emptied.
  const open = repair(mesh([0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1], tetFaces.slice(0, 9)));
  assert.equal(open.mesh.faces.length / 3, 4);
  assert.equal(open.report.holesFilled, 1);
  // A face turned over on a smooth surface is still a fold: the sphere's north pole moved just past
  // the edge between its first two ring neighbours turns face 0 (pole, ring 0, ring 1) over, while
  // its three neighbours (two of the pole's fan, one of the next row) still face out, together.
  const ball = sphere(12, 16);
  const r0 = ball.positions.subarray(3, 6), r1 = ball.positions.subarray(6, 9);
  for (let k = 0; k < 3; k++) ball.positions[k] = (r0[k] + r1[k]) / 2 * (k < 2 ? 1.05 : 1);
  const folds = foldedFaces(ball);
  assert.equal(folds.drop[0], 1, 'the turned-over face is a fold');
  assert.equal(folds.count, 1);
  // For a simplifier's output (the remesher's bases and proxies: sharpCorners) a sharp corner's apex
  // face is cut out too: the corner tetrahedron's slanted face (against all three others), in the
  // whole-mesh check and the local one; the turned-over face as before.
  const everywhere = (m) => ({ touched: new Uint8Array(m.positions.length / 3).fill(1), appendedFrom: 0 });
  for (const since of [null, everywhere(closed['corner tetrahedron'])]) {
    const corner = foldedFaces(closed['corner tetrahedron'], since, { sharpCorners: true });
    assert.equal(corner.count, 1, `the slanted face (${since ? 'local' : 'whole'} check)`);
    assert.deepEqual(Array.from(corner.drop), [1, 1, 1, 1], 'with its neighbours');
    assert.equal(foldedFaces(closed['corner tetrahedron'], since).count, 0);
  }
  assert.equal(foldedFaces(ball, null, { sharpCorners: true }).drop[0], 1);
  // repair passes it on: the tetrahedron's fold cut out (all four faces: nothing is left to fill from).
  assert.equal(repair(closed['corner tetrahedron'], { sharpCorners: true }).report.foldedFaces, 1);
});
