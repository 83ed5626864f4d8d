// `mrvol edit` (bin/mrvol.mjs) run as a child process: the JSON report, the written OBJ (vertex
// order and faces kept, the moved vertex where it was asked to go, the volume kept), the gradient
// paths and stored theta files, free sets, --no-preserve, and the error contract (exit 1 with one
// line `mrvol: error: ...`, exit 2 on bad usage, no output file either way). Independent runs go
// in parallel.
import { test, describe, before } from 'node:test';
import assert from 'node:assert/strict';
import { writeFileSync, existsSync } from 'node:fs';
import { createMrvol } from '../../lib/node.mjs';
import { tempFolder, runCli, json, failsWith, usageError, model, readObjFile, openPatch, relErr, maxDiff } from './helpers.mjs';

const mrvolCli = (...args) => runCli(args, { timeout: 60000 });

let mrvol;
const file = tempFolder('mrvol-edit-test-');
const readMesh = (path) => readObjFile(mrvol, path);
const EDIT_FIELDS = ['volumeReference', 'volumeTarget', 'volumeResult', 'relativeError', 'iterations', 'stepMs', 'path'];

before(async () => {
  mrvol = await createMrvol();
});

// ---- results ------------------------------------------------------------------------------------

describe('edit results', () => {
  const spiky = model('spiky-ball');
  const moves = [[3, [0.1, 0.2, -0.1]], [7, [-0.05, 0, 0.125]]];
  const moveArgs = moves.flatMap(([v, o]) => ['--move', `${v}:${o.join(',')}`]);
  let runs;

  before(async () => {
    const [tensor, matrixFree, noPreserve, text, withTensor] = await Promise.all([
      mrvolCli('edit', spiky, ...moveArgs, '-o', file('tensor.obj'), '--json'),
      mrvolCli('edit', spiky, ...moveArgs, '--path', 'matrix-free', '-o', file('mf.obj'), '--json'),
      mrvolCli('edit', spiky, ...moveArgs, '--no-preserve', '-o', file('raw.obj'), '--json'),
      mrvolCli('edit', spiky, '--move', '3:0.1,0.2,-0.1', '-o', file('text.obj')),
      mrvolCli('edit', spiky, ...moveArgs, '--path', 'tensor', '-o', file('with-tensor.obj'), '--json'),
    ]);
    runs = { tensor, matrixFree, noPreserve, text, withTensor };
  });

  test('--json report; OUT.obj keeps vertex order and faces; the volume is kept', async () => {
    const r = json(runs.tensor);
    for (const key of EDIT_FIELDS) assert.ok(Object.hasOwn(r, key), `field ${key}`);
    for (const key of EDIT_FIELDS.filter((k) => k !== 'path')) assert.equal(typeof r[key], 'number', key);
    assert.equal(r.path, 'polynomial', 'auto builds the cage polynomial, no theta');
    const input = readMesh(spiky), out = readMesh(file('tensor.obj'));
    const inputVolume = mrvol.volume(input);
    assert.ok(relErr(r.volumeReference, inputVolume) < 1e-12);
    assert.ok(r.relativeError < 1e-5);
    assert.ok(relErr(r.volumeResult, r.volumeReference) < 1e-5);
    assert.ok(relErr(r.volumeTarget, r.volumeReference) > 1e-4, 'the move alone changes the volume');
    assert.ok(r.iterations >= 1 && r.stepMs >= 0);
    assert.equal(out.positions.length, input.positions.length);
    assert.deepEqual(out.faces, input.faces, 'the same face lines');
    assert.ok(relErr(mrvol.volume(out), inputVolume) < 1e-5);
    // The moved cage vertices' level-0 coefficients moved by the offsets.
    const mr = mrvol.openMesh(input);
    const cin = mr.analyze(input.positions), cout = mr.analyze(out.positions);
    for (const [v, offset] of moves)
      for (let k = 0; k < 3; ++k) assert.ok(Math.abs(cout[3 * v + k] - (cin[3 * v + k] + offset[k])) < 1e-12, `vertex ${v}`);
    // The very edit of the API.
    const ed = mr.createEditor({ level: 0 });
    assert.equal(ed.path(), 'polynomial');
    ed.moveVertices(moves.map(([vertex, offset]) => ({ vertex, offset })));
    assert.ok(maxDiff(out.positions, ed.positions()) < 1e-12);
    mr.delete();
    // mrvol info on the result: same levels and base, the volume kept.
    const [infoIn, infoOut] = await Promise.all([mrvolCli('info', spiky, '--json'), mrvolCli('info', file('tensor.obj'), '--json')]);
    const a = json(infoIn), b = json(infoOut);
    assert.equal(b.levels, a.levels);
    assert.equal(b.vertices, a.vertices);
    assert.deepEqual(b.baseVertexIndices, a.baseVertexIndices);
    assert.ok(relErr(b.volume, a.volume) < 1e-5, `${b.volume} vs ${a.volume}`);
  });

  test('--path tensor (theta computed): the result of auto (polynomial) to 1e-10', () => {
    const r = json(runs.withTensor), auto = json(runs.tensor);
    assert.equal(r.path, 'tensor');
    assert.equal(r.iterations, auto.iterations);
    assert.ok(relErr(r.volumeResult, auto.volumeResult) < 1e-10);
    assert.ok(maxDiff(readMesh(file('with-tensor.obj')).positions, readMesh(file('tensor.obj')).positions) < 1e-10);
  });

  test('--path matrix-free: the same result', () => {
    const r = json(runs.matrixFree);
    assert.equal(r.path, 'matrix-free');
    assert.ok(r.relativeError < 1e-5);
    assert.ok(maxDiff(readMesh(file('mf.obj')).positions, readMesh(file('tensor.obj')).positions) < 1e-9);
  });

  test('--no-preserve: the volume changes', () => {
    const r = json(runs.noPreserve);
    assert.equal(r.path, 'none');
    assert.ok(relErr(r.volumeResult, r.volumeReference) > 1e-4);
    assert.ok(r.relativeError > 1e-4);
    const out = readMesh(file('raw.obj'));
    assert.ok(relErr(mrvol.volume(out), r.volumeResult) < 1e-12);
    assert.ok(relErr(mrvol.volume(out), r.volumeReference) > 1e-4);
  });

  test('text output', () => {
    const r = runs.text;
    assert.equal(r.status, 0, r.stderr);
    assert.equal(r.stderr, '');
    assert.match(r.stdout, /^reference volume +\S+$/m);
    assert.match(r.stdout, /^result volume +\S+ \(relative error \S+\)$/m);
    assert.match(r.stdout, /polynomial gradient$/m);
    assert.match(r.stdout, /^wrote +.*text\.obj$/m);
    assert.ok(existsSync(file('text.obj')));
  });

  test('at the finest level the moved vertex is exactly at input + offset', async () => {
    const offset = [0.05, -0.025, 0.0625];
    const [fine, ico, raw] = await Promise.all([
      mrvolCli('edit', spiky, '--level', '3', '--move', `100:${offset.join(',')}`, '-o', file('fine.obj'), '--json'),
      mrvolCli('edit', model('icosahedron'), '--move', `5:${offset.join(',')}`, '--move', '6:0,0,0.1', '-o', file('ico.obj'), '--json'),
      mrvolCli('edit', spiky, '--level', '3', '--move', `100:${offset.join(',')}`, '--no-preserve', '-o', file('fine-raw.obj'), '--json'),
    ]);
    for (const [r, input, output, v] of [[fine, spiky, 'fine.obj', 100], [ico, model('icosahedron'), 'ico.obj', 5], [raw, spiky, 'fine-raw.obj', 100]]) {
      const report = json(r);
      const a = readMesh(input), b = readMesh(file(output));
      for (let k = 0; k < 3; ++k) assert.equal(b.positions[3 * v + k], a.positions[3 * v + k] + offset[k], `${output} vertex ${v}`);
      assert.deepEqual(b.faces, a.faces);
      if (report.path !== 'none') assert.ok(relErr(mrvol.volume(b), mrvol.volume(a)) < 1e-5);
      else {
        // Nothing else moved.
        for (let i = 0; i < a.positions.length; ++i) if (Math.floor(i / 3) !== v) assert.equal(b.positions[i], a.positions[i]);
      }
    }
  });
});

describe('theta files and free sets', () => {
  test('--theta F.theta: the stored tensor gives the same edit; a mismatched one is refused', async () => {
    const spiky = model('spiky-ball'), theta = file('spiky-1.theta');
    json(await mrvolCli('theta', spiky, '--level', '1', '-o', theta, '--json'));
    const [withFile, computed, wrongLevel, wrongScheme] = await Promise.all([
      mrvolCli('edit', spiky, '--level', '1', '--theta', theta, '--move', '20:0.1,0.1,0', '-o', file('with-theta.obj'), '--json'),
      mrvolCli('edit', spiky, '--level', '1', '--path', 'tensor', '--move', '20:0.1,0.1,0', '-o', file('computed.obj'), '--json'),
      mrvolCli('edit', spiky, '--level', '2', '--theta', theta, '--move', '20:0.1,0.1,0', '-o', file('never1.obj')),
      mrvolCli('edit', spiky, '--level', '1', '--scheme', 'linear', '--theta', theta, '--move', '20:0.1,0.1,0', '-o', file('never2.obj')),
    ]);
    const a = json(withFile), b = json(computed);
    assert.equal(a.path, 'tensor');
    assert.ok(a.relativeError < 1e-5);
    assert.equal(a.volumeResult, b.volumeResult);
    assert.deepEqual(readMesh(file('with-theta.obj')).positions, readMesh(file('computed.obj')).positions);
    failsWith(wrongLevel, /spiky-1\.theta: theta file is for level 1, not level 2/);
    failsWith(wrongScheme, /spiky-1\.theta: theta file was computed for the loop scheme, not linear/);
    assert.ok(!existsSync(file('never1.obj')) && !existsSync(file('never2.obj')));
  });

  test('--free LIST, --free all, --free-details', async () => {
    const blob = model('blob');
    const [list, all, details] = await Promise.all([
      mrvolCli('edit', blob, '--level', '1', '--move', '2:0.1,0,0.1', '--free', '10,11,12', '-o', file('list.obj'), '--json'),
      mrvolCli('edit', blob, '--level', '1', '--move', '2:0.1,0,0.1', '--free', 'all', '-o', file('all.obj'), '--json'),
      mrvolCli('edit', blob, '--move', '2:0.1,0,0.1', '--free-details', '1', '-o', file('details.obj'), '--json'),
    ]);
    const input = readMesh(blob);
    const mr = mrvol.openMesh(input);
    const depths = mr.depths();
    const c1 = mr.analyze(input.positions, { level: 1 }), c0 = mr.analyze(input.positions, { level: 0 });
    // Only the listed cage vertices and the moved one change at level 1.
    const rl = json(list);
    assert.ok(rl.relativeError < 1e-5);
    const l1 = mr.analyze(readMesh(file('list.obj')).positions, { level: 1 });
    for (let v = 0; v < depths.length; ++v) {
      const d = Math.max(...[0, 1, 2].map((k) => Math.abs(l1[3 * v + k] - c1[3 * v + k])));
      if (v === 2 || [10, 11, 12].includes(v)) assert.ok(d > 1e-6, `vertex ${v} moved`);
      else assert.ok(d < 1e-12, `vertex ${v} (depth ${depths[v]}) stays: ${d}`);
    }
    const ra = json(all);
    assert.ok(ra.relativeError < 1e-5);
    // Details of level 1 (the vertices born at level 2) absorb the change with the cage; the other
    // levels' details stay.
    const rd = json(details);
    assert.equal(rd.path, 'matrix-free');
    assert.ok(rd.relativeError < 1e-5);
    const d0 = mr.analyze(readMesh(file('details.obj')).positions, { level: 0 });
    let changed = 0;
    for (let v = 0; v < depths.length; ++v) {
      const d = Math.max(...[0, 1, 2].map((k) => Math.abs(d0[3 * v + k] - c0[3 * v + k])));
      if (depths[v] === 2) changed = Math.max(changed, d);
      else if (depths[v] > 0) assert.ok(d < 1e-12, `detail of vertex ${v} (depth ${depths[v]}) stays: ${d}`);
    }
    assert.ok(changed > 1e-6);
    mr.delete();
  });
});

// ---- errors -------------------------------------------------------------------------------------

describe('edit errors', () => {
  before(() => {
    // The hexagon fan with an outer ring (12 boundary edges), subdivided once.
    const mr = mrvol.subdivide(openPatch(), { levels: 1 });
    writeFileSync(file('patch.obj'), mrvol.writeObj(mr.toMesh()));
    mr.delete();
  });

  // The patch's detected hierarchy (it is itself a split of a fan) decides which vertices are the
  // level-0 cage: pick a boundary one and an interior one with the API.
  function patchVertices() {
    const mesh = readMesh(file('patch.obj'));
    const mr = mrvol.openMesh(mesh);
    const ed = mr.createEditor({ level: 0 });
    const count = new Map();
    for (let f = 0; f < mesh.faces.length; f += 3)
      for (let k = 0; k < 3; ++k) {
        const a = mesh.faces[f + k], b = mesh.faces[f + (k + 1) % 3];
        const key = Math.min(a, b) + ',' + Math.max(a, b);
        count.set(key, (count.get(key) ?? 0) + 1);
      }
    const boundary = new Set();
    for (const [key, n] of count) if (n === 1) key.split(',').forEach((v) => boundary.add(Number(v)));
    const cage = Array.from(ed.cageVertices());
    mr.delete();
    return { mesh, boundary, cageBoundary: cage.find((v) => boundary.has(v)), cageInterior: cage.find((v) => !boundary.has(v)) };
  }

  test('run-time errors: exit 1, one line, no output file', async () => {
    const spiky = model('spiky-ball');
    const out = file('never.obj');
    const { cageBoundary } = patchVertices();
    assert.ok(cageBoundary !== undefined);
    const cases = [
      [['--move', '100:0.1,0,0'], /vertex 100 is not a vertex of the level-0 cage \(it is born at level 2\)/],
      [['--level', '1', '--move', '3:0,0,0.1', '--move', '641:0.1,0,0'], /vertex 641 is not a vertex of the level-1 cage \(it is born at level 3\)/],
      [['--move', '642:0.1,0,0'], /vertex 642 does not exist \(the mesh has 642 vertices\)/],
      [['--free', '4,200', '--move', '3:0.1,0,0'], /vertex 200 is not a vertex of the level-0 cage/],
      [['--free-details', '3', '--move', '3:0.1,0,0'], /free detail level 3 is out of range 0\.\.2/],
      // A move beyond the coordinates a mesh may have (it wrote a file of NaN volume that no reader took back).
      [['--move', '0:1e300,0,0'], /moves\[0\] puts vertex 0 at x = 1e\+300: coordinates must stay within \+-1e\+100/],
    ];
    const results = await Promise.all([
      ...cases.map(([args]) => mrvolCli('edit', spiky, ...args, '-o', out)),
      mrvolCli('edit', file('patch.obj'), '--move', `${cageBoundary}:0,0,0.1`, '-o', out),
    ]);
    cases.forEach(([, pattern], i) => failsWith(results[i], pattern));
    failsWith(results[cases.length], new RegExp(`vertex ${cageBoundary} is on the boundary`));
    assert.ok(!existsSync(out));
  });

  test('an open mesh: interior moves keep the cone volume, the boundary stays', async () => {
    const { mesh: a, boundary, cageInterior } = patchVertices();
    const r = json(await mrvolCli('edit', file('patch.obj'), '--move', `${cageInterior}:0,0,0.3`, '--free', 'all', '-o', file('patch-out.obj'), '--json'));
    assert.ok(r.relativeError < 1e-5);
    assert.ok(relErr(r.volumeTarget, r.volumeReference) > 1e-3);
    const b = readMesh(file('patch-out.obj'));
    // Up to the round-off of analysis and synthesis.
    for (const v of boundary) for (let k = 0; k < 3; ++k) assert.ok(Math.abs(b.positions[3 * v + k] - a.positions[3 * v + k]) < 1e-12, `boundary vertex ${v}`);
    assert.ok(relErr(mrvol.volume(b), mrvol.volume(a)) < 1e-5);
  });

  test('bad usage: exit 2, no output file', async () => {
    const spiky = model('spiky-ball');
    const out = file('never2.obj');
    const malformed = ['3:0.1,0.2', '3:a,0,0', '-1:0,0,0', '3:0.1,0.2,0.3,0.4', '3:,0,0', '3:1e400,0,0', 'x:0,0,0'];
    const others = [
      [[], /at least one --move V:dx,dy,dz is required/],
      [['--move', '3:0.1,0,0', '--tolerance', '0'], /--tolerance must be between 0 and 1/],
      [['--move', '3:0.1,0,0', '--tolerance', 'tight'], /--tolerance expects a number/],
      [['--move', '3:0.1,0,0', '--path', 'fast'], /--path must be auto, polynomial, tensor or matrix-free/],
      [['--move', '3:0.1,0,0', '--free', '1,x'], /--free expects a comma-separated list of integers/],
      [['--move', '3:0.1,0,0', '--level', '0.5'], /--level expects an integer/],
      // A moved vertex in --free was let go by the correction (it ended away from where it was put).
      [['--move', '3:0.1,0,0', '--free', '1,3,5'], /--free lists vertex 3, which --move moves: a moved vertex is held where it is put \(leave it out of --free\)/],
    ];
    const [noOutput, ...results] = await Promise.all([
      mrvolCli('edit', spiky, '--move', '3:0.1,0,0'),
      ...malformed.map((m) => mrvolCli('edit', spiky, `--move=${m}`, '-o', out)),
      ...others.map(([args]) => mrvolCli('edit', spiky, ...args, '-o', out)),
    ]);
    usageError(noOutput, /-o OUT\.obj is required/);
    malformed.forEach((m, i) => usageError(results[i], /^mrvol: error: --move expects /));
    others.forEach(([, pattern], i) => usageError(results[malformed.length + i], pattern));
    assert.ok(!existsSync(out));
  });
});
