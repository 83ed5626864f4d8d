// The renderer's buffers (issue 14): editor.positionsView() and normalsView(), float32 views of
// WASM memory rewritten in place after each edit. Checked after many seeded drags on every
// gradient path and on the paths the fine positions take (stencils for a few moved cage vertices,
// zero-detail synthesis of a whole-cage move, full resynthesis every so often): the positions equal
// a fresh synthesis of the editor's coefficients, the normals equal area-weighted normals computed
// here in JS from the editor's double positions, in the caller's vertex order (shuffled meshes too).
import { test, describe, before } from 'node:test';
import assert from 'node:assert/strict';
import { createMrvol } from '../../lib/node.mjs';
import { loadModel, openPatch, rng, shuffleMesh, throwsMrvol } from './helpers.mjs';

let mrvol;
before(async () => {
  mrvol = await createMrvol();
});

// The fine positions from the editor's coefficients by one full synthesis (caller's order).
function freshSynthesis(mr, ed) {
  const coefficients = ed.coefficients(), order = mr.hierarchyOrder();
  const caller = new Float64Array(coefficients.length);
  for (let h = 0; h < order.length; ++h) for (let k = 0; k < 3; ++k) caller[3 * order[h] + k] = coefficients[3 * h + k];
  return mr.synthesize(caller, { level: ed.level });
}

// Area-weighted unit vertex normals (sum of face cross products, normalized), in doubles.
function referenceNormals(positions, faces) {
  const n = new Float64Array(positions.length);
  for (let t = 0; t < faces.length; t += 3) {
    const [a, b, c] = [faces[t], faces[t + 1], faces[t + 2]].map((v) => 3 * v);
    const u = [0, 1, 2].map((k) => positions[b + k] - positions[a + k]);
    const v = [0, 1, 2].map((k) => positions[c + k] - positions[a + k]);
    const x = u[1] * v[2] - u[2] * v[1], y = u[2] * v[0] - u[0] * v[2], z = u[0] * v[1] - u[1] * v[0];
    for (const p of [a, b, c]) n[p] += x, n[p + 1] += y, n[p + 2] += z;
  }
  for (let i = 0; i < n.length; i += 3) {
    const length = Math.hypot(n[i], n[i + 1], n[i + 2]);
    if (length > 0) n[i] /= length, n[i + 1] /= length, n[i + 2] /= length;
  }
  return n;
}

// Largest |a - b| over the arrays, relative to the largest |b| (the mesh's size) for positions.
function maxError(a, b, scale = 1) {
  assert.equal(a.length, b.length);
  let e = 0;
  for (let i = 0; i < a.length; ++i) e = Math.max(e, Math.abs(a[i] - b[i]));
  return e / scale;
}
const size = (p) => p.reduce((m, x) => Math.max(m, Math.abs(x)), 0);

// normalsFirst: as the app asks (normalsView() first: positions and normals in one pass).
function checkBuffers(mr, ed, faces, where, normalsFirst = false) {
  if (normalsFirst) ed.normalsView();
  const positions = ed.positionsView();
  assert.ok(positions instanceof Float32Array, where);
  const fresh = freshSynthesis(mr, ed);
  const e = maxError(positions, fresh, size(fresh));
  assert.ok(e < 1e-6, `${where}: positions differ from a fresh synthesis by ${e} (relative)`);
  const normals = ed.normalsView();
  assert.ok(normals instanceof Float32Array, where);
  const en = maxError(normals, referenceNormals(ed.positions(), faces));
  assert.ok(en < 1e-5, `${where}: normals differ from the reference by ${en}`);
}

// Seeded drags of one cage vertex (held), the buffers checked every `every` drags; more than the
// 64 incremental updates after which the fine positions are synthesized afresh.
function dragMany(mr, ed, faces, { drags = 80, every = 10, seed = 1, preserve = true, where }) {
  const r = rng(seed), cage = ed.cageVertices(), scale = size(mr.positions());
  let version = ed.surfaceVersion;
  for (let d = 1; d <= drags; ++d) {
    const vertex = cage[Math.floor(r() * cage.length)];
    const report = ed.moveVertices([{ vertex, offset: [0, 1, 2].map(() => 0.02 * scale * (2 * r() - 1)) }], { preserve });
    assert.equal(report.converged, true, `${where}: ${report.message}`);
    if (d % every === 0 || d === drags) {
      checkBuffers(mr, ed, faces, `${where}, drag ${d}`, (d / every) % 2 === 1);
      assert.notEqual(ed.surfaceVersion, version, `${where}: the version changes with the positions`);
      version = ed.surfaceVersion;
    }
  }
}

describe('positionsView and normalsView follow the edits', () => {
  for (const [name, level, path] of [['spiky-ball', 0, 'polynomial'], ['spiky-ball', 2, 'matrix-free'], ['torus', 1, 'polynomial'],
                                     ['blob', 0, 'matrix-free']]) {
    test(`${name}, level ${level}, ${path}: equal to a fresh synthesis and to JS normals after many drags`, () => {
      const mesh = loadModel(mrvol, name);
      const mr = mrvol.openMesh(mesh);
      const ed = mr.createEditor({ level, path });
      assert.equal(ed.path(), path);
      checkBuffers(mr, ed, mesh.faces, `${name} before any drag`);
      dragMany(mr, ed, mesh.faces, { where: `${name} e=${level} ${path}` });
      mr.delete();
    });
  }

  test('moves without preservation (the stencils of a few cage vertices) and with it, alternating', () => {
    const mesh = loadModel(mrvol, 'spiky-ball');
    const mr = mrvol.openMesh(mesh);
    const ed = mr.createEditor({ level: 1 });
    dragMany(mr, ed, mesh.faces, { drags: 70, every: 7, seed: 2, preserve: false, where: 'no preserve' });
    dragMany(mr, ed, mesh.faces, { drags: 20, every: 5, seed: 3, where: 'preserve after' });
    mr.delete();
  });

  test('a cage of 642 over the subdivided spiky ball: single moves (the table\'s columns) and corrections (its full pass)', () => {
    const mr = mrvol.subdivide(loadModel(mrvol, 'spiky-ball'), { levels: 1 });
    const faces = mr.faces();
    const ed = mr.createEditor({ level: mr.levels - 1, path: 'polynomial' });
    assert.equal(ed.cageSize, 642);
    checkBuffers(mr, ed, faces, 'e=3 before');
    dragMany(mr, ed, faces, { drags: 24, every: 3, seed: 5, preserve: false, where: 'e=3 no preserve' });
    dragMany(mr, ed, faces, { drags: 24, every: 3, seed: 6, where: 'e=3 preserve' });
    mr.delete();
  });

  test('a shuffled mesh (caller order unlike the hierarchy order) and an open mesh', () => {
    const { mesh } = shuffleMesh(loadModel(mrvol, 'torus'), 7, { shuffleFaces: true });
    const mr = mrvol.openMesh(mesh);
    const ed = mr.createEditor({ level: 1 });
    dragMany(mr, ed, mesh.faces, { drags: 30, where: 'shuffled torus' });
    mr.delete();
    const patch = mrvol.subdivide(openPatch(), { levels: 2 });
    const pe = patch.createEditor({ level: 0 });
    const interior = [...pe.cageVertices()].filter((v) => {
      try {
        return pe.moveVertices([{ vertex: v, offset: [0, 0, 0.01] }]).converged;
      } catch {
        return false;  // a boundary vertex
      }
    });
    assert.ok(interior.length > 0);
    checkBuffers(patch, pe, patch.faces(), 'open patch');
    patch.delete();
  });
});

describe('updates of a few vertices', () => {
  test('moves of one vertex of a fine cage rewrite only its stencil and the normals around it; the ranges cover every change', () => {
    const mr = mrvol.subdivide(loadModel(mrvol, 'spiky-ball'), { levels: 1 });
    const faces = mr.faces(), n = faces.length / 6 + 2;  // closed: V = F / 2 + 2
    const ed = mr.createEditor({ level: mr.levels - 1 });
    checkBuffers(mr, ed, faces, 'before');
    const r = rng(11), cage = ed.cageVertices();
    for (let d = 0; d < 12; ++d) {
      const positions = ed.positionsView().slice(), normals = ed.normalsView().slice();
      const vertex = cage[Math.floor(r() * cage.length)];
      ed.moveVertices([{ vertex, offset: [0.01, -0.02, 0.015] }], { preserve: d % 4 === 3 });
      checkBuffers(mr, ed, faces, `move ${d}`);
      const ranges = ed.updatedRanges();
      for (const [name, before, after] of [['positions', positions, ed.positionsView()], ['normals', normals, ed.normalsView()]]) {
        const { first, count } = ranges[name];
        let changed = 0;
        for (let i = 0; i < after.length; ++i) {
          if (after[i] === before[i]) continue;
          ++changed;
          const v = Math.floor(i / 3);
          assert.ok(v >= first && v < first + count, `move ${d}: ${name} of vertex ${v} changed outside [${first}, ${first + count})`);
        }
        assert.ok(changed > 0, `move ${d}: ${name} changed`);
        if (d % 4 !== 3) assert.ok(changed < after.length / 4, `move ${d}: a few ${name} rewritten (${changed / 3} of ${n} vertices)`);
      }
    }
    mr.delete();
  });
});

describe('views and versions', () => {
  test('the view is rewritten in place; the version changes only when the positions do', () => {
    const mesh = loadModel(mrvol, 'spiky-ball');
    const mr = mrvol.openMesh(mesh);
    const ed = mr.createEditor({ level: 0 });
    const first = ed.positionsView(), v0 = ed.surfaceVersion;
    const copy = first.slice();
    assert.equal(ed.positionsView().byteOffset, first.byteOffset, 'the same memory');
    assert.equal(ed.surfaceVersion, v0, 'no edit: the same version');
    ed.moveVertices([{ vertex: ed.cageVertices()[0], offset: [0.1, 0, 0] }]);
    const second = ed.positionsView();
    assert.equal(second.byteOffset, first.byteOffset, 'written in place');
    assert.notEqual(ed.surfaceVersion, v0);
    if (first.length > 0) assert.ok(maxError(first, copy) > 0, 'the old view (memory not grown) shows the new values');
    assert.equal(second.length, 3 * (mesh.positions.length / 3));
    ed.delete();
    throwsMrvol(() => ed.positionsView(), /deleted/);
    throwsMrvol(() => ed.normalsView(), /deleted/);
    mr.delete();
  });
});
