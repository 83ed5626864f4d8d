// One level's lifting phases through the JS API on the real WASM module (lib/node.mjs), over the
// sample models (shuffled too): the step data in caller indices, applied here as documented, gives
// the phases synthesizeSteps runs; all phases are one level of synthesis, zero phases nothing;
// analysis phase by phase is the exact reverse. Theta entries with hierarchyOrder() give the
// volume. Bad arguments are MrvolErrors, and the module keeps working after them.
import { test, describe, before } from 'node:test';
import assert from 'node:assert/strict';
import { createMrvol, MrvolError } from '../../lib/node.mjs';
import { loadModel, octahedron, openPatch, shuffleMesh, maxAbs, maxDiff, throwsMrvol as throwsMrvolError } from './helpers.mjs';

const throwsMrvol = (fn, message) => throwsMrvolError(fn, message, { named: true });

const SCHEMES = [{ scheme: 'loop' }, { scheme: 'butterfly' }, { scheme: 'linear' }];
const NAMES = { loop: ['U', 'P_o', 'N', 'P_e'], butterfly: ['U', 'P'], linear: ['U', 'P'] };

// x_t += W x_s | x_t *= f, on 3 doubles per vertex: the documented meaning of a step's data.
function applyStep(step, x) {
  for (let r = 0; r < step.targets.length; r++) {
    const t = step.targets[r];
    for (let d = 0; d < 3; d++) {
      if (step.scaling) {
        x[3 * t + d] *= step.weights[r];
        continue;
      }
      let sum = 0;
      for (let s = step.offsets[r]; s < step.offsets[r + 1]; s++) sum += step.weights[s] * x[3 * step.sources[s] + d];
      x[3 * t + d] += sum;
    }
  }
}

let mrvol;
const cases = []; // { name, mr, positions }

before(async () => {
  mrvol = await createMrvol();
  for (const name of ['spiky-ball', 'blob', 'torus']) {
    const m = loadModel(mrvol, name);
    cases.push({ name, mr: mrvol.openMesh(m), positions: m.positions });
    const shuffled = shuffleMesh(m, 17, { shuffleFaces: true }).mesh;
    cases.push({ name: `${name} (shuffled)`, mr: mrvol.openMesh(shuffled), positions: shuffled.positions });
  }
  const open = mrvol.subdivide(openPatch(), { levels: 2 });
  const shuffledOpen = shuffleMesh(open.toMesh(), 5).mesh;
  open.delete();
  cases.push({ name: 'open patch (shuffled)', mr: mrvol.openMesh(shuffledOpen), positions: shuffledOpen.positions });
});

describe('lifting steps', () => {
  test('the steps of every level: names, typed arrays, vertices of M^l, caller indices', () => {
    for (const { name, mr } of cases) {
      const depths = mr.depths();
      for (const options of SCHEMES)
        for (let level = 1; level <= mr.levels; level++) {
          const steps = mr.liftingSteps({ level, ...options });
          assert.deepEqual(steps.map((s) => s.name), NAMES[options.scheme], `${name} ${options.scheme} l=${level}`);
          for (const step of steps) {
            assert.ok(step.targets instanceof Uint32Array && step.sources instanceof Uint32Array && step.offsets instanceof Uint32Array);
            assert.ok(step.weights instanceof Float64Array);
            assert.ok(step.targets.length > 0);
            if (step.scaling) {
              assert.equal(step.weights.length, step.targets.length);
              assert.equal(step.sources.length, 0);
            } else {
              assert.equal(step.offsets.length, step.targets.length + 1);
              assert.equal(step.offsets.at(-1), step.sources.length);
              assert.equal(step.weights.length, step.sources.length);
            }
            for (const v of [...step.targets, ...step.sources]) assert.ok(depths[v] <= level, `${name} ${step.name}: vertex ${v} is in M^${level}`);
          }
          if (options.scheme === 'loop') {
            const [U, Po, N, Pe] = steps;
            assert.ok(U.readsOnlyDetails && !Po.readsOnlyDetails && N.scaling && !Pe.scaling);
            for (const t of Po.targets) assert.equal(depths[t], level, 'P_o writes the odd vertices');
            for (const t of [...U.targets, ...N.targets, ...Pe.targets]) assert.ok(depths[t] < level, 'U, N, P_e write the even ones');
          }
        }
    }
  });

  test('the step data applied as documented is the phase synthesizeSteps runs; all phases are synthesis', () => {
    for (const { name, mr, positions } of cases)
      for (const options of SCHEMES) {
        const scale = maxAbs(positions);
        const coarse = mr.analyze(positions, { level: 0, ...options });
        let x = coarse;
        for (let level = 1; level <= mr.levels; level++) {
          const steps = mr.liftingSteps({ level, ...options });
          const mine = Float64Array.from(x);
          steps.forEach((step, k) => {
            applyStep(step, mine);
            const theirs = mr.synthesizeSteps(x, { level, ...options, steps: k + 1 });
            assert.ok(maxDiff(mine, theirs) < 1e-12 * scale, `${name} ${options.scheme} l=${level} ${step.name}`);
          });
          x = mr.synthesizeSteps(x, { level, ...options }); // default: every step
        }
        assert.ok(maxDiff(x, positions) < 1e-11 * scale, `${name} ${options.scheme}: synthesis from level 0 gives the mesh`);
        assert.deepEqual(x, mr.synthesize(coarse, { level: 0, ...options }));
        // And analysis level by level, every step undone, is analyze.
        let y = positions;
        for (let level = mr.levels; level >= 1; level--) y = mr.analyzeSteps(y, { level, ...options });
        assert.deepEqual(y, coarse);
      }
  });

  test('steps: 0 changes nothing; analysis phase by phase retraces synthesis in reverse', () => {
    for (const { name, mr, positions } of cases)
      for (const options of SCHEMES) {
        const scale = maxAbs(positions);
        for (let level = 1; level <= mr.levels; level++) {
          assert.deepEqual(mr.synthesizeSteps(positions, { level, ...options, steps: 0 }), positions);
          assert.deepEqual(mr.analyzeSteps(positions, { level, ...options, steps: 0 }), positions);
          const count = NAMES[options.scheme].length;
          const start = mr.analyze(positions, { level: level - 1, ...options });
          const end = mr.synthesizeSteps(start, { level, ...options, steps: count });
          for (let k = 0; k <= count; k++) {
            const forward = mr.synthesizeSteps(start, { level, ...options, steps: k });
            const backward = mr.analyzeSteps(end, { level, ...options, steps: count - k });
            assert.ok(maxDiff(forward, backward) < 1e-12 * scale, `${name} ${options.scheme} l=${level} k=${k}`);
          }
        }
      }
  });

  test('a unit coefficient spreads phase by phase only through what each phase writes', () => {
    const { mr } = cases[0]; // the spiky ball, level 1, Loop
    const depths = mr.depths();
    const even = mr.baseVertexIndices[0];
    const unit = new Float64Array(3 * mr.vertexCount);
    unit[3 * even] = 1;
    const steps = mr.liftingSteps({ level: 1 });
    const support = (x) => { const s = new Set(); for (let v = 0; v < mr.vertexCount; v++) if (x[3 * v] !== 0) s.add(v); return s; };
    let before = support(unit);
    assert.equal(before.size, 1);
    steps.forEach((step, k) => {
      const now = support(mr.synthesizeSteps(unit, { level: 1, steps: k + 1 }));
      const targets = new Set(step.targets);
      for (const v of now) if (!before.has(v)) assert.ok(targets.has(v), `${step.name} wrote ${v}, one of its targets`);
      before = now;
    });
    // U reads details only: the even coefficient is untouched by it; P_o then reaches the odd ring.
    assert.equal(support(mr.synthesizeSteps(unit, { level: 1, steps: 1 })).size, 1);
    const afterPo = support(mr.synthesizeSteps(unit, { level: 1, steps: 2 }));
    assert.ok([...afterPo].some((v) => depths[v] === 1), 'P_o writes odd vertices next to it');
  });
});

describe('theta entries', () => {
  test('the stored entries (i < j < k, hierarchy order) give the volume; a read-back theta lists the same', () => {
    for (const m of [octahedron(), loadModel(mrvol, 'icosahedron')]) {
      const built = mrvol.subdivide(m, { levels: 2 });
      const shuffled = shuffleMesh(built.toMesh(), 3, { shuffleFaces: true }).mesh;
      built.delete();
      const mr = mrvol.openMesh(shuffled);
      const order = mr.hierarchyOrder();
      assert.ok(order instanceof Uint32Array && order.length === mr.vertexCount);
      assert.deepEqual([...order].sort((a, b) => a - b), [...order.keys()], 'a permutation');
      const depths = mr.depths();
      for (let h = 1; h < order.length; h++) assert.ok(depths[order[h - 1]] <= depths[order[h]], 'by depth');
      for (const level of [0, 1, 2]) {
        const theta = mr.computeTheta({ level, storage: 'full' });
        const e = theta.entries();
        assert.ok(e.i instanceof Uint32Array && e.k instanceof Uint32Array && e.values instanceof Float64Array);
        assert.equal(e.values.length, theta.info().nnzStored);
        const c = mr.analyze(shuffled.positions, { level });
        let volume = 0;
        for (let t = 0; t < e.values.length; t++) {
          assert.ok(e.i[t] < e.j[t] && e.j[t] < e.k[t]);
          const [a, b, d] = [e.i[t], e.j[t], e.k[t]].map((h) => c.subarray(3 * order[h], 3 * order[h] + 3));
          volume += e.values[t] * (a[0] * (b[1] * d[2] - b[2] * d[1]) - a[1] * (b[0] * d[2] - b[2] * d[0]) + a[2] * (b[0] * d[1] - b[1] * d[0]));
        }
        const expected = mrvol.volume(shuffled);
        assert.ok(Math.abs(volume - expected) < 1e-10 * expected, `level ${level}: ${volume} vs ${expected}`);
        const again = mrvol.readTheta(theta.bytes());
        assert.deepEqual(again.entries(), e);
        again.delete();
        theta.delete();
      }
      mr.delete();
    }
  });

  test('cage storage lists only rows of cage vertices; a deleted theta refuses', () => {
    const { mr } = cases[0];
    const theta = mr.computeTheta({ level: 0 });
    const e = theta.entries();
    assert.equal(e.values.length, theta.info().nnzStored);
    const cage = mr.info().baseVertices;
    assert.ok(e.i.every((i) => i < cage));
    theta.delete();
    throwsMrvol(() => theta.entries(), 'this Theta has been deleted');
  });
});

describe('bad arguments', () => {
  test('transposed phases (Figure 5) are the adjoint of the last phases, and apply the step data outwards', () => {
    const dot = (u, v) => u.reduce((sum, x, i) => sum + x * v[i], 0);
    for (const { name, mr, positions } of cases)
      for (const options of SCHEMES)
        for (let level = 1; level <= mr.levels; level++) {
          const count = NAMES[options.scheme].length;
          const a = mr.analyze(positions, { level: level - 1, ...options });
          const b = Float64Array.from(positions, (x, i) => Math.sin(7 * i + 1));
          const whole = dot(mr.synthesizeSteps(a, { level, ...options }), b);
          for (let k = 0; k <= count; k++) {
            const split = dot(mr.synthesizeSteps(a, { level, ...options, steps: count - k }), mr.transposeSteps(b, { level, ...options, steps: k }));
            assert.ok(Math.abs(split - whole) < 1e-10 * (Math.abs(whole) + 1), `${name} ${options.scheme} l=${level} k=${k}`);
          }
          // One phase outwards: x_s += w x_t over the last step's rows (x_t *= f for a scaling).
          const last = mr.liftingSteps({ level, ...options }).at(-1);
          const expected = Float64Array.from(b);
          for (let r = 0; r < last.targets.length; r++)
            for (let d = 0; d < 3; d++) {
              const t = 3 * last.targets[r] + d;
              if (last.scaling) expected[t] *= last.weights[r];
              else for (let q = last.offsets[r]; q < last.offsets[r + 1]; q++) expected[3 * last.sources[q] + d] += last.weights[q] * b[t];
            }
          assert.ok(maxDiff(mr.transposeSteps(b, { level, ...options, steps: 1 }), expected) < 1e-12 * maxAbs(b), `${name} ${options.scheme} l=${level}`);
        }
    throwsMrvol(() => cases[0].mr.transposeSteps([1, 2, 3], { level: 1 }), 'covector must be a Float64Array');
  });

  test('every bad argument is a MrvolError saying why; the module keeps working', () => {
    const { mr, positions } = cases[0];
    const n = mr.levels;
    throwsMrvol(() => mr.liftingSteps(), 'level is required: level l (1..n) builds M^l from M^(l-1)');
    throwsMrvol(() => mr.liftingSteps({ level: 0 }), `level 0 is out of range for lifting steps: level l builds M^l from M^(l-1), l = 1..${n}`);
    throwsMrvol(() => mr.liftingSteps({ level: n + 1 }), new RegExp(`^level ${n + 1} is out of range for lifting steps`));
    throwsMrvol(() => mr.liftingSteps({ level: 1.5 }), 'level must be an integer, got 1.5');
    throwsMrvol(() => mr.liftingSteps({ level: 1, scheme: 'cubic' }), /unknown scheme/);
    throwsMrvol(() => mr.synthesizeSteps(positions, { steps: 1 }), /level is required/);
    throwsMrvol(() => mr.synthesizeSteps(positions, { level: 1, steps: 5 }), 'steps 5 is out of range: the loop scheme has 4 lifting steps per level (0..4)');
    throwsMrvol(() => mr.analyzeSteps(positions, { level: 1, steps: -1 }), 'steps -1 is out of range: the loop scheme has 4 lifting steps per level (0..4)');
    throwsMrvol(() => mr.analyzeSteps(positions, { level: 1, scheme: 'linear', steps: 3 }), 'steps 3 is out of range: the linear scheme has 2 lifting steps per level (0..2)');
    throwsMrvol(() => mr.synthesizeSteps(positions, { level: 1, steps: 2.5 }), 'steps must be an integer, got 2.5');
    throwsMrvol(() => mr.synthesizeSteps(positions, { level: 1, steps: 2 ** 40 }), `steps ${2 ** 40} is out of range`);
    throwsMrvol(() => mr.synthesizeSteps(Float32Array.from(positions), { level: 1 }), 'coefficients must be a Float64Array');
    throwsMrvol(() => mr.analyzeSteps(positions.subarray(3), { level: 1 }), `expected ${positions.length} coefficients, got ${positions.length - 3}`);
    const flat = mrvol.openMesh(loadModel(mrvol, 'icosahedron'));
    throwsMrvol(() => flat.liftingSteps({ level: 1 }), 'this mesh has no subdivision level, so no lifting steps');
    throwsMrvol(() => flat.synthesizeSteps(flat.positions(), { level: 1, steps: 0 }), 'this mesh has no subdivision level, so no lifting steps');
    flat.delete();
    throwsMrvol(() => flat.liftingSteps({ level: 1 }), 'this MultiresMesh has been deleted');
    throwsMrvol(() => flat.hierarchyOrder(), 'this MultiresMesh has been deleted');
    // Still working: the same calls with good arguments.
    assert.equal(mr.liftingSteps({ level: n }).length, 4);
    assert.deepEqual(mr.synthesizeSteps(positions, { level: 1, steps: 0 }), positions);
    assert.ok(mrvol.readObj('v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n').faces.length === 3);
    assert.ok(new MrvolError('x') instanceof Error);
  });
});
