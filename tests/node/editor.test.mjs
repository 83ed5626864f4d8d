// The volume-preserving editor (issue 4) through the real WASM module: seeded random drags on the
// sample models for every scheme and several levels, on both gradient paths (tensor and
// matrix-free, which must agree), with the invariants of an edit checked after every drag: volume
// kept, held vertices exactly at their target, details untouched. Then free sets, localized parts,
// no-preserve moves, correct(), the gradient itself, index mapping of shuffled meshes, open
// meshes, and the errors and life cycle of editors.
import { test, describe, before } from 'node:test';
import assert from 'node:assert/strict';
import { createMrvol } from '../../lib/node.mjs';
import { loadModel, openPatch, rng, shuffleMesh, relErr, maxDiff, maxAbs, throwsMrvol } from './helpers.mjs';

// Bitwise equality of two Float64Arrays (faster than deepEqual, and -0 !== 0 counts).
function sameBits(a, b) {
  if (a.length !== b.length) return false;
  return Buffer.compare(Buffer.from(a.buffer, a.byteOffset, a.byteLength), Buffer.from(b.buffer, b.byteOffset, b.byteLength)) === 0;
}

let mrvol;
const meshes = {};
before(async () => {
  mrvol = await createMrvol();
  for (const name of ['icosahedron', 'spiky-ball', 'torus', 'blob'])
    meshes[name] = loadModel(mrvol, name);
});

// Random moves of 1 to 3 distinct cage vertices, offsets up to `size` per coordinate.
function randomMoves(r, cage, size) {
  const count = 1 + Math.floor(r() * 3), moves = [], used = new Set();
  while (moves.length < count) {
    const vertex = cage[Math.floor(r() * cage.length)];
    if (used.has(vertex)) continue;
    used.add(vertex);
    moves.push({ vertex, offset: [0, 1, 2].map(() => size * (2 * r() - 1)) });
  }
  return moves;
}

// Applies one drag and checks what every preserving drag with the default free set must give.
function dragAndCheck(ed, faces, moves, where, { path, details }) {
  const before = ed.cagePositions();
  const report = ed.moveVertices(moves);
  assert.equal(report.converged, true, `${where}: ${report.message}`);
  assert.equal(report.message, '', where);
  assert.equal(report.path, path, where);
  const ref = ed.referenceVolume(), volume = ed.volume();
  assert.equal(report.volumeReference, ref, where);
  assert.ok(report.relativeError < 1e-5, `${where}: relative error ${report.relativeError}`);
  assert.ok(relErr(volume, ref) < 1e-5, `${where}: volume ${volume} vs reference ${ref}`);
  assert.ok(relErr(report.volumeResult, volume) < 1e-12, `${where}: reported ${report.volumeResult}, volume() ${volume}`);
  const positions = ed.positions();
  assert.ok(relErr(mrvol.volume({ positions, faces }), volume) < 1e-12, `${where}: volume() is the mesh's volume`);
  const after = ed.cagePositions();
  const held = new Set();
  for (const { vertex, offset } of moves) {
    const c = ed.cageIndexOf(vertex);
    held.add(c);
    for (let k = 0; k < 3; ++k)
      assert.equal(after[3 * c + k], before[3 * c + k] + offset[k], `${where}: held vertex ${vertex} is exactly at its target`);
  }
  // The free (not held) cage vertices absorbed the change when there was one.
  if (relErr(report.volumeTarget, ref) > 1e-5) {
    let moved = false;
    for (let c = 0; c < ed.cageSize && !moved; ++c) if (!held.has(c)) moved = after[3 * c] !== before[3 * c] || after[3 * c + 1] !== before[3 * c + 1] || after[3 * c + 2] !== before[3 * c + 2];
    assert.ok(moved, `${where}: some free vertex moved`);
  }
  assert.ok(sameBits(ed.coefficients().subarray(3 * ed.cageSize), details), `${where}: details unchanged, bit for bit`);
  return report;
}

// ---- random drags ---------------------------------------------------------------------------------

describe('random drags keep the volume; tensor, polynomial and matrix-free paths agree', () => {
  // [model, scheme, level]: every model and scheme, levels from the coarsest to the finest (e = n:
  // the cage is every vertex).
  const CASES = [
    ['icosahedron', 'loop', 0],
    ['spiky-ball', 'loop', 0], ['spiky-ball', 'loop', 1], ['spiky-ball', 'butterfly', 2], ['spiky-ball', 'linear', 3],
    ['torus', 'loop', 2], ['torus', 'butterfly', 2], ['torus', 'linear', 0],
    ['blob', 'loop', 1], ['blob', 'butterfly', 3], ['blob', 'linear', 2], ['blob', 'loop', 4],
  ];
  const DRAGS = 16;

  for (const [name, scheme, level] of CASES)
    test(`${name}, ${scheme}, level ${level}: ${DRAGS} drags on each path`, () => {
      const mr = mrvol.openMesh(meshes[name]);
      const faces = mr.faces();
      const theta = mr.computeTheta({ level, scheme });
      const tensor = mr.createEditor({ level, scheme, theta });
      const free = mr.createEditor({ level, scheme, path: 'matrix-free' });
      const poly = mr.createEditor({ level, scheme, path: 'polynomial' });  // the polynomial built from the mesh
      assert.equal(tensor.path(), 'tensor');
      assert.equal(free.path(), 'matrix-free');
      assert.equal(poly.path(), 'polynomial');
      assert.ok(relErr(poly.referenceVolume(), tensor.referenceVolume()) < 1e-14);
      const details = free.coefficients().subarray(3 * free.cageSize);
      assert.ok(sameBits(tensor.coefficients().subarray(3 * tensor.cageSize), details));
      const cage = Array.from(free.cageVertices());
      const r = rng(1000 * level + name.length + scheme.length);
      const size = 0.12;  // the models are about unit size
      let substeps = 0;
      for (let d = 0; d < DRAGS; ++d) {
        const moves = randomMoves(r, cage, d === DRAGS - 1 ? 4 * size : size);
        const where = `${name} ${scheme} e=${level} drag ${d}`;
        const a = dragAndCheck(tensor, faces, moves, `${where} (tensor)`, { path: 'tensor', details });
        dragAndCheck(free, faces, moves, `${where} (matrix-free)`, { path: 'matrix-free', details });
        const p = dragAndCheck(poly, faces, moves, `${where} (polynomial)`, { path: 'polynomial', details });
        substeps = Math.max(substeps, a.substeps);
        const diff = maxDiff(tensor.positions(), free.positions());
        assert.ok(diff < 1e-9, `${where}: the two paths differ by ${diff}`);
        const polyDiff = maxDiff(tensor.positions(), poly.positions());
        assert.ok(polyDiff < 1e-10, `${where}: polynomial and tensor differ by ${polyDiff}`);
        assert.equal(p.iterations, a.iterations, `${where}: the same steps`);
        if (d % 4 === 3) {
          // Theta_tau on the cage: the tensor polynomial against the adjoint of synthesis (the
          // cage comes first in hierarchy order).
          const gt = tensor.gradient('tensor'), gm = tensor.gradient('matrix-free');
          assert.equal(gt.length, 3 * tensor.cageSize);
          assert.equal(gm.length, 3 * mr.vertexCount);
          const scale = maxAbs(gm.subarray(0, gt.length));
          assert.ok(maxDiff(gt, gm.subarray(0, gt.length)) <= 1e-10 * scale, `${where}: gradients differ by ${maxDiff(gt, gm.subarray(0, gt.length))}`);
          const gp = poly.gradient('polynomial');
          assert.ok(maxDiff(gp, gt) <= 1e-10 * scale, `${where}: polynomial gradient differs by ${maxDiff(gp, gt)}`);
        }
      }
      theta.delete();
      mr.delete();
      assert.ok(tensor.deleted && free.deleted && poly.deleted);
    });

  test('large drags are split into sub-steps and still keep the volume', () => {
    const mr = mrvol.openMesh(meshes['spiky-ball']);
    const theta = mr.computeTheta({ level: 0 });
    for (const ed of [mr.createEditor({ level: 0 }), mr.createEditor({ level: 0, theta })]) {
      const details = ed.coefficients().subarray(3 * ed.cageSize);
      const cp = ed.cagePositions();
      // Pull four base vertices out to 1.8 times their distance: the raw volume nearly doubles.
      const moves = [0, 1, 2, 3].map((v) => ({ vertex: v, offset: [0.8 * cp[3 * v], 0.8 * cp[3 * v + 1], 0.8 * cp[3 * v + 2]] }));
      const report = dragAndCheck(ed, mr.faces(), moves, `big drag (${ed.path()})`, { path: ed.path(), details });
      assert.ok(report.volumeTarget > 1.5 * report.volumeReference);
      assert.ok(report.substeps > 1, `substeps ${report.substeps}`);
    }
    theta.delete();
    mr.delete();
  });
});

// ---- the gradient -------------------------------------------------------------------------------

describe('gradient', () => {
  test('the matrix-free gradient is the derivative of the volume (central differences on the cage)', () => {
    const mr = mrvol.openMesh(meshes.blob);
    const ed = mr.createEditor({ level: 1, scheme: 'butterfly' });
    const g = ed.gradient('matrix-free');
    const base = ed.cagePositions(), none = new Uint8Array(ed.cageSize);
    const h = 1e-4, r = rng(3);
    for (let t = 0; t < 8; ++t) {
      const i = Math.floor(r() * base.length);
      const at = (s) => {
        const target = base.slice();
        target[i] += s;
        ed.deformCage(target, none, { preserve: false });
        return ed.volume();
      };
      const fd = (at(h) - at(-h)) / (2 * h);
      assert.ok(Math.abs(fd - g[i]) < 1e-6 * maxAbs(g), `coordinate ${i}: ${fd} vs ${g[i]}`);
    }
    mr.delete();
  });

  test('gradient paths and their errors', () => {
    const mr = mrvol.openMesh(meshes['spiky-ball']);
    const ed = mr.createEditor({ level: 1, path: 'matrix-free' });
    throwsMrvol(() => ed.gradient('tensor'), 'no tensor is in use');
    throwsMrvol(() => ed.gradient('adjoint'), "unknown gradient path 'adjoint' (tensor, polynomial or matrix-free)");
    assert.equal(ed.gradient().length, 3 * 642, 'matrix-free by default');
    const theta = mr.computeTheta({ level: 1 });
    ed.useTheta(theta);
    // Deleting the Theta does not take the editor's tensor away: it keeps its own polynomial.
    theta.delete();
    assert.equal(ed.path(), 'tensor');
    assert.ok(maxDiff(ed.gradient('tensor'), ed.gradient().subarray(0, 3 * 42)) < 1e-12);
    const report = ed.moveVertices([{ vertex: 5, offset: [0.1, -0.05, 0.02] }]);
    assert.equal(report.path, 'tensor');
    assert.ok(report.relativeError < 1e-5);
    ed.useMatrixFree();
    assert.equal(ed.path(), 'matrix-free');
    throwsMrvol(() => ed.gradient('tensor'), 'no tensor is in use');
    mr.delete();
  });
});

// ---- free sets, no-preserve, correct --------------------------------------------------------------

describe('free sets', () => {
  let mr;
  before(() => { mr = mrvol.openMesh(meshes['spiky-ball']); });

  test("'all': the held vertex may give too; 'cage' is 'minus-held'", () => {
    const ed = mr.createEditor({ level: 1, path: 'polynomial' });
    ed.setFreeSet({ cage: 'all' });
    const before = ed.cagePositions();
    const report = ed.moveVertices([{ vertex: 7, offset: [0.2, 0.1, 0] }]);
    assert.ok(report.converged && report.relativeError < 1e-5 && relErr(ed.volume(), ed.referenceVolume()) < 1e-5);
    const c = ed.cageIndexOf(7), after = ed.cagePositions();
    assert.ok([0, 1, 2].some((k) => after[3 * c + k] !== before[3 * c + k] + [0.2, 0.1, 0][k]), 'the moved vertex absorbed part of the change');
    assert.ok(maxDiff([0, 1, 2].map((k) => after[3 * c + k]), [0, 1, 2].map((k) => before[3 * c + k] + [0.2, 0.1, 0][k])) < 0.05);
    ed.setFreeSet({ cage: 'cage' });
    const details = ed.coefficients().subarray(3 * ed.cageSize);
    dragAndCheck(ed, mr.faces(), [{ vertex: 7, offset: [-0.1, 0, 0.1] }], "'cage'", { path: 'polynomial', details });
  });

  test('a list: only the listed vertices (and the moved one) change', () => {
    const ed = mr.createEditor({ level: 1 });
    const list = [20, 21, 30];
    ed.setFreeSet({ cage: list });
    const before = ed.cagePositions();
    const report = ed.moveVertices([{ vertex: 2, offset: [0, 0.15, 0.1] }]);
    assert.ok(report.converged && report.relativeError < 1e-5 && relErr(ed.volume(), ed.referenceVolume()) < 1e-5);
    const after = ed.cagePositions();
    const listed = new Set(list.map((v) => ed.cageIndexOf(v)));
    for (let c = 0; c < ed.cageSize; ++c) {
      const same = [0, 1, 2].every((k) => after[3 * c + k] === before[3 * c + k]);
      if (c === ed.cageIndexOf(2)) assert.deepEqual([0, 1, 2].map((k) => after[3 * c + k]), [0, 1, 2].map((k) => before[3 * c + k] + [0, 0.15, 0.1][k]));
      else if (listed.has(c)) assert.ok(!same, `listed vertex ${c} moved`);
      else assert.ok(same, `unlisted vertex ${c} stays, bit for bit`);
    }
  });

  test('detail levels: the chosen levels\' details change, the others do not; matrix-free path', () => {
    const theta = mr.computeTheta({ level: 0 });
    const ed = mr.createEditor({ level: 0, theta });
    ed.setFreeSet({ detailLevels: [1] });  // d^1: the vertices born at level 2, hierarchy 42..161
    const before = ed.coefficients();
    const report = ed.moveVertices([{ vertex: 4, offset: [0.1, 0.1, -0.1] }]);
    assert.equal(report.path, 'matrix-free');
    assert.ok(report.converged && report.relativeError < 1e-5 && relErr(ed.volume(), ed.referenceVolume()) < 1e-5);
    const after = ed.coefficients();
    assert.ok(sameBits(after.subarray(3 * 12, 3 * 42), before.subarray(3 * 12, 3 * 42)), 'details born at level 1 unchanged');
    assert.ok(sameBits(after.subarray(3 * 162), before.subarray(3 * 162)), 'details born at level 3 unchanged');
    assert.ok(!sameBits(after.subarray(3 * 42, 3 * 162), before.subarray(3 * 42, 3 * 162)), 'details born at level 2 changed');
    ed.setFreeSet({ cage: [], detailLevels: [0, 2] });
    const r2 = ed.moveVertices([{ vertex: 4, offset: [-0.1, 0, 0] }]);
    assert.ok(r2.converged && r2.relativeError < 1e-5);
    const last = ed.coefficients();
    assert.ok(sameBits(last.subarray(0, 3 * 4), after.subarray(0, 3 * 4)) && sameBits(last.subarray(15, 36), after.subarray(15, 36)),
      'no cage vertex but the moved one changes');
    assert.ok(sameBits(last.subarray(3 * 42, 3 * 162), after.subarray(3 * 42, 3 * 162)), 'level-1 details stay');
    theta.delete();
  });

  test('no theta: free details run matrix-free, then the polynomial follows the moved details', () => {
    const ed = mr.createEditor({ level: 0 });
    assert.equal(ed.path(), 'polynomial');
    const reference = ed.referenceVolume();
    ed.setFreeSet({ detailLevels: [1] });
    const r1 = ed.moveVertices([{ vertex: 4, offset: [0.1, 0.1, -0.1] }]);
    assert.equal(r1.path, 'matrix-free');
    assert.ok(r1.converged && relErr(ed.volume(), reference) < 1e-5);
    ed.setFreeSet({});
    const r2 = ed.moveVertices([{ vertex: 4, offset: [-0.15, 0, 0.05] }]);
    assert.equal(r2.path, 'polynomial');
    assert.ok(r2.converged && r2.relativeError < 1e-5);
    assert.ok(relErr(ed.volume(), reference) < 1e-5, 'the rebuilt polynomial keeps the fine volume');
    ed.useMatrixFree();
    assert.equal(ed.path(), 'matrix-free');
    assert.equal(ed.usePolynomial(), 'polynomial');
    throwsMrvol(() => mr.createEditor({ level: 0, path: 'tensor' }), "createEditor path must be auto, polynomial or matrix-free (tensor with a theta), got 'tensor'");
    throwsMrvol(() => mr.createEditor({ level: 0, path: 'fast' }), /got 'fast'/);
    ed.delete();
  });

  test('an empty free list: converged false, with a message; the move is applied', () => {
    const ed = mr.createEditor({ level: 1 });
    ed.setFreeSet({ cage: [] });
    const report = ed.moveVertices([{ vertex: 3, offset: [0.2, 0, 0] }]);
    assert.equal(report.converged, false);
    assert.equal(report.message, 'the free set is empty: nothing can absorb the volume change');
    assert.ok(report.relativeError > 1e-4);
    assert.ok(relErr(report.volumeResult, report.volumeTarget) < 1e-12);
  });

  test('free-set errors', () => {
    const ed = mr.createEditor({ level: 1 });
    throwsMrvol(() => ed.setFreeSet({ cage: 'some' }), "unknown free set 'some' (minus-held, all or a list of vertices)");
    throwsMrvol(() => ed.setFreeSet({ cage: [3, 100] }), 'vertex 100 is not a vertex of the level-1 cage (it is born at level 2)');
    throwsMrvol(() => ed.setFreeSet({ detailLevels: [0] }), 'free detail level 0 is out of range 1..2');
    throwsMrvol(() => ed.setFreeSet({ detailLevels: [3] }), 'free detail level 3 is out of range 1..2');
    throwsMrvol(() => ed.setFreeSet({ detailLevels: [-1] }), 'free detail level -1 is out of range 1..2');
  });
});

describe('no-preserve moves, correct(), reference volume', () => {
  test('preserve: false applies the move only: the volume changes', () => {
    const mr = mrvol.openMesh(meshes.torus);
    const ed = mr.createEditor({ level: 1, scheme: 'butterfly' });
    const before = ed.cagePositions(), ref = ed.referenceVolume();
    const report = ed.moveVertices([{ vertex: 10, offset: [0.15, 0.1, 0.2] }], { preserve: false });
    assert.equal(report.iterations, 0);
    assert.ok(relErr(ed.volume(), ref) > 1e-4, 'the volume changed');
    assert.ok(relErr(report.volumeResult, ed.volume()) < 1e-12);
    assert.equal(report.volumeResult, report.volumeTarget);
    assert.ok(Math.abs(report.relativeError - relErr(ed.volume(), ref)) < 1e-12);
    const after = ed.cagePositions(), c = ed.cageIndexOf(10);
    for (let i = 0; i < after.length; ++i)
      assert.equal(after[i], Math.floor(i / 3) === c ? before[i] + [0.15, 0.1, 0.2][i % 3] : before[i]);
    assert.equal(ed.referenceVolume(), ref, 'the reference stays');
    // correct() then restores it, holding the moved vertex.
    const held = new Uint8Array(ed.cageSize);
    held[c] = 1;
    const fixed = ed.correct(held);
    assert.ok(fixed.converged && fixed.relativeError < 1e-5 && relErr(ed.volume(), ref) < 1e-5);
    assert.deepEqual(ed.cagePositions().subarray(3 * c, 3 * c + 3), after.subarray(3 * c, 3 * c + 3));
    mr.delete();
  });

  test('preserve: false puts the moved vertex exactly at its target', () => {
    const mr = mrvol.openMesh(meshes['spiky-ball']);
    const ed = mr.createEditor({ level: 3 });
    const p = ed.cagePositions();
    ed.moveVertices([{ vertex: 0, position: [1e-20, p[1], p[2]] }], { preserve: false });
    try {
      assert.equal(ed.cagePositions()[0], 1e-20);
    } finally {
      mr.delete();
    }
  });

  test('setReferenceVolume + correct(): another volume is reached', () => {
    const mr = mrvol.openMesh(meshes.blob);
    const ed = mr.createEditor({ level: 2, scheme: 'linear' });
    const v0 = ed.volume();
    ed.setReferenceVolume(1.03 * v0);
    assert.equal(ed.referenceVolume(), 1.03 * v0);
    const report = ed.correct();
    assert.ok(report.converged && report.relativeError < 1e-5);
    assert.ok(relErr(ed.volume(), 1.03 * v0) < 1e-5);
    throwsMrvol(() => ed.setReferenceVolume(NaN), 'the reference volume must be a finite number');
    throwsMrvol(() => ed.setReferenceVolume(Infinity), 'the reference volume must be a finite number');
    mr.delete();
  });
});

// ---- localized preservation ---------------------------------------------------------------------

describe('parts', () => {
  test('each part keeps its own volume', () => {
    const mr = mrvol.openMesh(meshes['spiky-ball']);
    const ed = mr.createEditor({ level: 1 });
    const cage = ed.cageVertices(), cp = ed.cagePositions();
    // Three slabs along x.
    const parts = [[], [], []];
    cage.forEach((v, c) => parts[cp[3 * c] < -0.3 ? 0 : cp[3 * c] > 0.3 ? 2 : 1].push(v));
    assert.ok(parts.every((p) => p.length >= 5));
    ed.setParts(parts);
    const refs = ed.partVolumes();
    assert.equal(refs.length, 3);
    const sum = refs.reduce((a, b) => a + b, 0);
    assert.ok(relErr(sum, ed.volume()) < 1e-12, 'parts covering the cage split the whole volume');
    // Without preservation a drag in part 0 changes its volume ...
    const probe = mr.createEditor({ level: 1 });
    probe.setParts(parts);
    const r = rng(11);
    const drags = Array.from({ length: 6 }, () => {
      const vertex = parts[0][Math.floor(r() * parts[0].length)];
      return [{ vertex, offset: [-0.15 * r(), 0.1 * (r() - 0.5), 0.1 * (r() - 0.5)] }];
    });
    probe.moveVertices(drags[0], { preserve: false });
    assert.ok(relErr(probe.partVolumes()[0], refs[0]) > 1e-3);
    // ... with preservation every part keeps its own.
    for (const [d, moves] of drags.entries()) {
      const report = ed.moveVertices(moves);
      assert.ok(report.converged, report.message);
      assert.equal(report.path, 'matrix-free');
      assert.deepEqual(Array.from(report.partReferences), Array.from(refs));
      const now = ed.partVolumes();
      for (let p = 0; p < 3; ++p) assert.ok(relErr(now[p], refs[p]) < 1e-5, `drag ${d} part ${p}: ${now[p]} vs ${refs[p]}`);
      assert.ok(maxDiff(report.partVolumes, now) < 1e-12);
      assert.ok(relErr(ed.volume(), sum) < 3e-5, 'so the total too');
    }
    // Explicit references.
    const wanted = [refs[0] * 1.02, refs[1], refs[2] * 0.99];
    ed.setParts(parts, wanted);
    const report = ed.correct();
    assert.ok(report.converged, report.message);
    const now = ed.partVolumes();
    for (let p = 0; p < 3; ++p) assert.ok(relErr(now[p], wanted[p]) < 1e-5, `part ${p}`);
    // No parts: back to one global constraint.
    ed.setParts([]);
    assert.equal(ed.partVolumes().length, 0);
    mr.delete();
  });

  test('part errors', () => {
    const mr = mrvol.openMesh(meshes['spiky-ball']);
    const ed = mr.createEditor({ level: 1 });
    throwsMrvol(() => ed.setParts([[0, 1, 2], [2, 3]]), 'cage vertex 2 is in two parts');
    throwsMrvol(() => ed.setParts([[0, 1], [2, 3]], [1]), 'give one reference volume per part (2)');
    throwsMrvol(() => ed.setParts([[0, 100]]), 'vertex 100 is not a vertex of the level-1 cage (it is born at level 2)');
    mr.delete();
  });
});

// ---- vertex order, open meshes --------------------------------------------------------------------

describe('vertex order and boundaries', () => {
  test('a shuffled mesh: caller indices in and out, the same edit as the unshuffled one', () => {
    const { mesh, perm } = shuffleMesh(meshes['spiky-ball'], 21);
    const a = mrvol.openMesh(meshes['spiky-ball']), b = mrvol.openMesh(mesh);
    const thetaB = b.computeTheta({ level: 1 });
    const ea = a.createEditor({ level: 1 }), eb = b.createEditor({ level: 1, theta: thetaB });
    const cageA = Array.from(ea.cageVertices()), cageB = Array.from(eb.cageVertices());
    assert.deepEqual(cageB.slice().sort((x, y) => x - y), cageA.map((v) => perm[v]).sort((x, y) => x - y));
    for (const v of cageA) {
      const cb = eb.cageIndexOf(perm[v]);
      assert.equal(cageB[cb], perm[v]);
      const ca = ea.cageIndexOf(v);
      assert.ok(maxDiff(eb.cagePositions().subarray(3 * cb, 3 * cb + 3), ea.cagePositions().subarray(3 * ca, 3 * ca + 3)) < 1e-14,
        'the same coefficients up to the order of summation');
    }
    const r = rng(8);
    for (let d = 0; d < 5; ++d) {
      const moves = randomMoves(r, cageA, 0.1);
      ea.moveVertices(moves);
      eb.moveVertices(moves.map((m) => ({ vertex: perm[m.vertex], offset: m.offset })));
    }
    const pa = ea.positions(), pb = eb.positions();
    let diff = 0;
    for (let v = 0; v < perm.length; ++v) for (let k = 0; k < 3; ++k) diff = Math.max(diff, Math.abs(pa[3 * v + k] - pb[3 * perm[v] + k]));
    assert.ok(diff < 1e-9, `positions differ by ${diff}`);
    assert.ok(relErr(eb.volume(), ea.referenceVolume()) < 1e-5);
    thetaB.delete();
    a.delete();
    b.delete();
  });

  test('an open mesh: boundary vertices cannot move and never absorb the correction', () => {
    const mr = mrvol.subdivide(openPatch(), { levels: 2 });
    const theta = mr.computeTheta({ level: 0 });
    assert.ok(relErr(mr.thetaVolume(theta), mr.info().volume) < 1e-10);
    for (const ed of [mr.createEditor({ level: 0 }), mr.createEditor({ level: 0, theta })]) {
      throwsMrvol(() => ed.moveVertices([{ vertex: 8, offset: [0, 0, 0.1] }]),
        'vertex 8 is on the boundary: boundary vertices stay fixed so that the volume stays meaningful');
      ed.setFreeSet({ cage: 'all' });
      const before = ed.cagePositions();
      const report = ed.moveVertices([{ vertex: 0, offset: [0, 0, 0.3] }]);
      assert.ok(report.converged && report.relativeError < 1e-5 && relErr(ed.volume(), ed.referenceVolume()) < 1e-5);
      const after = ed.cagePositions();
      assert.ok(sameBits(after.subarray(3 * 7), before.subarray(3 * 7)), 'the outer ring (vertices 7..18) stays');
      assert.ok(!sameBits(after.subarray(3, 3 * 7), before.subarray(3, 3 * 7)), 'the inner ring absorbed the change');
    }
    theta.delete();
    mr.delete();
  });
});

// ---- errors and life cycle ------------------------------------------------------------------------

describe('errors and life cycle', () => {
  test('moving a vertex that is not a cage vertex throws and changes nothing', () => {
    const mr = mrvol.openMesh(meshes['spiky-ball']);
    const ed = mr.createEditor({ level: 1 });
    const before = ed.coefficients();
    throwsMrvol(() => ed.moveVertices([{ vertex: 5, offset: [0.1, 0, 0] }, { vertex: 100, offset: [0.1, 0, 0] }]),
      'vertex 100 is not a vertex of the level-1 cage (it is born at level 2)');
    throwsMrvol(() => ed.moveVertices([{ vertex: 641, offset: [0, 0, 0.1] }]), 'vertex 641 is not a vertex of the level-1 cage (it is born at level 3)');
    throwsMrvol(() => ed.moveVertices([{ vertex: 642, offset: [0, 0, 0.1] }]), 'vertex 642 does not exist (the mesh has 642 vertices)');
    throwsMrvol(() => ed.moveVertices([{ vertex: -1, offset: [0, 0, 0.1] }]), 'vertex index must be a non-negative integer');
    throwsMrvol(() => ed.moveVertices([{ vertex: 1.5, offset: [0, 0, 0.1] }]), 'vertex index must be a non-negative integer');
    throwsMrvol(() => ed.cageIndexOf(200), 'vertex 200 is not a vertex of the level-1 cage (it is born at level 3)');
    assert.ok(sameBits(ed.coefficients(), before));
    assert.equal(ed.cageIndexOf(41), 41);
    mr.delete();
  });

  test('bad targets and options', () => {
    const mr = mrvol.openMesh(meshes['spiky-ball']);
    const ed = mr.createEditor({ level: 0 });
    const t = ed.cagePositions(), none = new Uint8Array(12);
    throwsMrvol(() => ed.deformCage(Array.from(t), none), 'target must be a Float64Array');
    throwsMrvol(() => ed.deformCage(t.subarray(3), none), 'the cage target needs 36 coordinates, got 33');
    const bad = t.slice();
    bad[4] = NaN;
    throwsMrvol(() => ed.deformCage(bad, none), 'the cage target has a non-finite coordinate');
    bad[4] = 1e101;
    throwsMrvol(() => ed.deformCage(bad, none), 'target: cage vertex 1 has y = 1e+101: coordinates must stay within +-1e+100');
    // Moves that are not { vertex, position } or { vertex, offset } with 3 finite numbers, or that
    // put a vertex beyond the coordinates a mesh may have (the readers' limit): named, not read as
    // zero moves or padded (the CLI's edit wrote a file of NaN volume that no reader took back).
    const refused = [
      [{ vertex: 0 }, 'moves must be an array of { vertex, position: [x, y, z] } or { vertex, offset: [dx, dy, dz] }'],
      [[{ vertex: 0 }], 'moves[0] must give either position: [x, y, z] or offset: [dx, dy, dz]'],
      [[{ vertex: 0, offset: [0, 0, 0], position: [0, 0, 0] }], 'moves[0] must give either position: [x, y, z] or offset: [dx, dy, dz], not both'],
      [[{ vertex: 0, offset: [0.1] }], 'moves[0].offset must be 3 finite numbers, got [0.1] (1 values)'],
      [[{ vertex: 0, offset: [0, 0, 0, 0] }], 'moves[0].offset must be 3 finite numbers, got [0, 0, 0, 0] (4 values)'],
      [[{ vertex: 0, position: ['1', 0, 0] }], 'moves[0].position must be 3 finite numbers, got [1, 0, 0] (3 values)'],
      [[{ vertex: 0, offset: [0, NaN, 0] }], 'moves[0].offset must be 3 finite numbers, got [0, NaN, 0] (3 values)'],
      [[{ vertex: 1, offset: [0.1, 0, 0] }, null], 'moves[1] must be { vertex, position: [x, y, z] } or { vertex, offset: [dx, dy, dz] }'],
      [[{ vertex: 0, offset: [1e300, 0, 0] }], 'moves[0] puts vertex 0 at x = 1e+300: coordinates must stay within +-1e+100'],
    ];
    for (const [moves, message] of refused) throwsMrvol(() => ed.moveVertices(moves), message);
    for (const tolerance of [0, 1, -1e-5, NaN])
      throwsMrvol(() => ed.moveVertices([{ vertex: 0, offset: [0.1, 0, 0] }], { tolerance }), 'tolerance must be between 0 and 1');
    throwsMrvol(() => ed.moveVertices([{ vertex: 0, offset: [0.1, 0, 0] }], { maxIterations: 0 }),
      'tolerance must be positive and iteration limits at least 1');
    assert.ok(sameBits(ed.cagePositions(), t), 'refused calls change nothing');
    // A looser tolerance is honoured.
    const loose = ed.moveVertices([{ vertex: 0, offset: [0.2, 0, 0] }], { tolerance: 1e-2 });
    assert.ok(loose.converged && loose.relativeError < 1e-2);
    mr.delete();
  });

  test('useTheta refuses a tensor of another level, scheme, weights, mesh or storage', () => {
    const mr = mrvol.openMesh(meshes['spiky-ball']);
    const torus = mrvol.openMesh(meshes.torus);
    const ed = mr.createEditor({ level: 1, path: 'polynomial' });
    const thetas = {
      level2: mr.computeTheta({ level: 2 }),
      linear: mr.computeTheta({ level: 1, scheme: 'linear' }),
      plain: mr.computeTheta({ level: 1, alpha: 0, beta: 0 }),
      torus: torus.computeTheta({ level: 1, scheme: 'linear' }),
      full: mr.computeTheta({ level: 1, scheme: 'linear', storage: 'full' }),
    };
    throwsMrvol(() => ed.useTheta(thetas.level2), 'theta file is for level 2, not level 1');
    throwsMrvol(() => ed.useTheta(thetas.linear), 'theta file was computed for the linear scheme, not loop');
    throwsMrvol(() => ed.useTheta(thetas.plain), /^theta file was computed with Loop weights alpha = 0\.000000, beta = 0\.000000/);
    throwsMrvol(() => ed.useTheta(thetas.torus), /^theta file does not match this mesh/);
    const linear = mr.createEditor({ level: 1, scheme: 'linear', path: 'polynomial' });
    throwsMrvol(() => linear.useTheta(thetas.full), 'the tensor is not theta^1 with cage storage for this mesh');
    throwsMrvol(() => linear.useTheta({}), 'useTheta expects a Theta');
    throwsMrvol(() => mr.createEditor({ level: 2, theta: thetas.linear }), /^theta file was computed for the linear scheme/);
    assert.equal(ed.path(), 'polynomial');
    assert.equal(linear.path(), 'polynomial');
    linear.useTheta(thetas.linear);
    assert.equal(linear.path(), 'tensor');
    for (const t of Object.values(thetas)) t.delete();
    throwsMrvol(() => ed.useTheta(thetas.level2), 'this Theta has been deleted');
    torus.delete();
    mr.delete();
  });

  test('createEditor: level range, initial state', () => {
    const mr = mrvol.openMesh(meshes.blob);
    throwsMrvol(() => mr.createEditor({ level: 5 }), 'level 5 is out of range: this mesh has levels 0..4');
    throwsMrvol(() => mr.createEditor({ scheme: 'cubic' }), "unknown scheme 'cubic' (expected loop, butterfly or linear)");
    const ed = mr.createEditor({ level: 2, scheme: 'butterfly' });
    assert.equal(ed.level, 2);
    assert.equal(ed.cageSize, 66);
    assert.deepEqual(Array.from(ed.cageVertices()), Array.from({ length: 66 }, (_, i) => i));
    // auto: the polynomial built from the mesh on a cage at least 3 levels coarse, else matrix-free.
    assert.equal(ed.path(), 'matrix-free', 'e = n - 2: matrix-free');
    const coarse = mr.createEditor({ level: 1, scheme: 'butterfly' });
    assert.equal(coarse.path(), 'polynomial', 'e = n - 3: the polynomial built from the mesh');
    coarse.delete();
    assert.ok(relErr(ed.volume(), mr.info().volume) < 1e-12);
    assert.equal(ed.referenceVolume(), ed.volume());
    assert.ok(maxDiff(ed.positions(), mr.positions()) < 1e-14);
    // The blob's file order is the hierarchy order: coefficients() is analyze() at that level.
    assert.ok(sameBits(ed.coefficients(), mr.analyze(mr.positions(), { level: 2, scheme: 'butterfly' })));
    assert.ok(sameBits(ed.cagePositions(), ed.coefficients().subarray(0, 3 * 66)));
    // The editor has its own copy of the positions.
    mr.setPositions(mr.positions().map((x) => 2 * x));
    assert.ok(relErr(ed.volume(), mr.info().volume / 8) < 1e-12);
    mr.delete();
  });

  test('deleting the MultiresMesh deletes its editors; an editor can go alone', () => {
    const mr = mrvol.openMesh(meshes['spiky-ball']);
    const a = mr.createEditor({ level: 0 }), b = mr.createEditor({ level: 2, scheme: 'linear' }), c = mr.createEditor({ level: 1 });
    c.delete();
    assert.equal(c.deleted, true);
    assert.equal(a.deleted, false);
    assert.ok(a.moveVertices([{ vertex: 0, offset: [0.1, 0, 0] }]).converged, 'the others keep working');
    mr.delete();
    for (const ed of [a, b, c]) {
      assert.equal(ed.deleted, true);
      const message = 'this VolumeEditor has been deleted';
      for (const fn of [() => ed.volume(), () => ed.positions(), () => ed.coefficients(), () => ed.cageVertices(), () => ed.cagePositions(),
        () => ed.cageIndexOf(0), () => ed.referenceVolume(), () => ed.setReferenceVolume(1), () => ed.path(), () => ed.useMatrixFree(),
        () => ed.setFreeSet({ cage: 'all' }), () => ed.partVolumes(), () => ed.gradient(), () => ed.correct(),
        () => ed.moveVertices([{ vertex: 0, offset: [0.1, 0, 0] }]), () => ed.deformCage(new Float64Array(3 * ed.cageSize), new Uint8Array(ed.cageSize))])
        throwsMrvol(fn, message);
      ed.delete();  // harmless
    }
    throwsMrvol(() => mr.createEditor(), 'this MultiresMesh has been deleted');
  });
});
