// The mrvol command line (bin/mrvol.mjs) run as a child process: info, subdivide and roundtrip
// with --json, and the error contract (exit 1 with one line `mrvol: error: ...`, exit 2 on bad
// usage). Test meshes are made with the JS API and written to a fresh temporary folder.
import { test, describe, before } from 'node:test';
import assert from 'node:assert/strict';
import { writeFileSync, readFileSync, existsSync } from 'node:fs';
import { join } from 'node:path';
import { createMrvol } from '../../lib/node.mjs';
import { tempFolder, runCliSync, json, failsWith, usageError, icosahedron, rng, shuffleMesh } from './helpers.mjs';

// The CLI waits at most 30 s per run here.
const mrvolCli = (...args) => runCliSync(args, { timeout: 30000 });

let mrvol;
const file = tempFolder('mrvol-cli-test-');

before(async () => {
  mrvol = await createMrvol();
  writeFileSync(file('ico.obj'), mrvol.writeObj(icosahedron()));
});

// ---- info --------------------------------------------------------------------------------------

describe('info', () => {
  test('--json on a shuffled subdivided mesh: exact fields, base vertices in file order', () => {
    const built = mrvol.subdivide(icosahedron(), { levels: 3, scheme: 'butterfly' });
    const { mesh, perm } = shuffleMesh(built.toMesh(), 42);
    const volume = built.info().volume;
    built.delete();
    writeFileSync(file('shuffled.obj'), mrvol.writeObj(mesh));
    const r = json(mrvolCli('info', file('shuffled.obj'), '--json'));
    assert.deepEqual(Object.keys(r).sort(),
      ['baseVertexIndices', 'baseVertices', 'boundaryEdges', 'closed', 'faces', 'genus', 'levels', 'polygonTriangles',
       'polygons', 'semiRegular', 'vertices', 'volume']);
    assert.equal(r.semiRegular, true);
    assert.equal(r.polygons, 0);
    assert.equal(r.vertices, 642);
    assert.equal(r.faces, 1280);
    assert.equal(r.levels, 3);
    assert.equal(r.baseVertices, 12);
    // 0-based indices, in file order, of the vertices that were the icosahedron's.
    assert.deepEqual(r.baseVertexIndices, perm.slice(0, 12).sort((a, b) => a - b));
    const lines = readFileSync(file('shuffled.obj'), 'utf8').split('\n');
    for (const [k, i] of r.baseVertexIndices.entries()) {
      const v = perm.indexOf(i);
      assert.ok(v < 12, `file vertex ${i} (listed ${k}th) is a base vertex`);
      assert.deepEqual(lines[i].split(' ').slice(1).map(Number), Array.from(icosahedron().positions.subarray(3 * v, 3 * v + 3)));
    }
    assert.equal(r.closed, true);
    assert.equal(r.boundaryEdges, 0);
    assert.equal(r.genus, 0);
    assert.ok(Math.abs(r.volume - volume) < 1e-12 * volume);
  });

  test('plain text output and an open mesh', () => {
    // The icosahedron with one face removed: 3 boundary edges, not closed.
    const m = icosahedron();
    writeFileSync(file('open.obj'), mrvol.writeObj({ positions: m.positions, faces: m.faces.subarray(3) }));
    const r = json(mrvolCli('info', '--json', file('open.obj')));
    assert.equal(r.closed, false);
    assert.equal(r.boundaryEdges, 3);
    assert.equal(r.levels, 0);
    assert.deepEqual(r.baseVertexIndices, Array.from({ length: 12 }, (_, i) => i));
    const text = mrvolCli('info', file('ico.obj'));
    assert.equal(text.status, 0);
    assert.equal(text.stderr, '');
    assert.match(text.stdout, /^vertices\s+12$/m);
    assert.match(text.stdout, /^faces\s+20$/m);
    assert.match(text.stdout, /^levels\s+0$/m);
    assert.match(text.stdout, /^genus\s+0$/m);
  });
});

// ---- subdivide ---------------------------------------------------------------------------------

describe('subdivide', () => {
  for (const scheme of ['loop', 'butterfly', 'linear'])
    test(`${scheme}: -o OUT.obj, then info detects the levels; vertex order kept`, () => {
      const out = file(`sub-${scheme}.obj`);
      const r = json(mrvolCli('subdivide', file('ico.obj'), '--levels', '2', '--scheme', scheme, '-o', out, '--json'));
      assert.equal(r.vertices, 162);
      assert.equal(r.faces, 320);
      assert.equal(r.levels, 2);
      assert.equal(r.scheme, scheme);
      assert.equal(r.output, out);
      const info = json(mrvolCli('info', out, '--json'));
      assert.equal(info.levels, 2);
      assert.equal(info.vertices, 162);
      assert.deepEqual(info.baseVertexIndices, Array.from({ length: 12 }, (_, i) => i), 'the base comes first');
      assert.ok(Math.abs(info.volume - r.volume) < 1e-12 * Math.abs(r.volume));
      const written = mrvol.readObj(readFileSync(out, 'utf8'));
      const base = icosahedron().positions;
      if (scheme !== 'loop') assert.deepEqual(written.positions.subarray(0, 36), base, 'interpolating: base positions exactly');
      else assert.notDeepEqual(written.positions.subarray(0, 36), base, 'Loop moves the base vertices');
      // Same as the API's subdivision.
      const api = mrvol.subdivide(icosahedron(), { levels: 2, scheme });
      assert.deepEqual(written.positions, api.positions());
      assert.deepEqual(written.faces, api.faces());
      api.delete();
    });

  test('--output long form, --alpha/--beta and text output', () => {
    const out = file('sub-plain.obj');
    const r = mrvolCli('subdivide', file('ico.obj'), '--levels', '1', '--alpha', '0', '--beta', '0', '--output', out);
    assert.equal(r.status, 0, r.stderr);
    assert.match(r.stdout, /^wrote .*sub-plain\.obj: 42 vertices, 80 faces/);
    const api = mrvol.subdivide(icosahedron(), { levels: 1, alpha: 0, beta: 0 });
    assert.deepEqual(mrvol.readObj(readFileSync(out, 'utf8')).positions, api.positions());
    api.delete();
  });
});

// ---- roundtrip ---------------------------------------------------------------------------------

describe('roundtrip', () => {
  test('--json: tiny error; --scheme and --level are honoured', () => {
    // A 2-level mesh with random positions in a random vertex order: every scheme has details.
    const built = mrvol.subdivide(icosahedron(), { levels: 2 });
    const r = rng(9);
    const positions = Float64Array.from({ length: 3 * built.vertexCount }, () => 2 * r() - 1);
    const { mesh } = shuffleMesh({ positions, faces: built.faces() }, 5);
    built.delete();
    writeFileSync(file('random.obj'), mrvol.writeObj(mesh));
    const mr = mrvol.openMesh(mesh);
    for (const [scheme, level] of [['loop', 0], ['butterfly', 1], ['linear', 2]]) {
      const res = json(mrvolCli('roundtrip', file('random.obj'), '--scheme', scheme, '--level', String(level), '--json'));
      assert.deepEqual(Object.keys(res).sort(), ['level', 'maxError', 'relativeError', 'scheme']);
      assert.equal(res.scheme, scheme);
      assert.equal(res.level, level);
      assert.ok(res.maxError < 1e-12, `${scheme} level ${level}: ${res.maxError}`);
      assert.ok(res.relativeError >= res.maxError && res.relativeError <= res.maxError / 0.9);
      // The very computation of the API with these options.
      assert.equal(res.maxError, mr.roundtripError({ scheme, level }));
    }
    const def = json(mrvolCli('roundtrip', file('random.obj'), '--json'));
    assert.equal(def.scheme, 'loop');
    assert.equal(def.level, 0);
    assert.equal(def.maxError, mr.roundtripError());
    // Text output; --alpha/--beta honoured (the number printed is the JS number, exactly).
    const text = mrvolCli('roundtrip', file('random.obj'), '--alpha', '0', '--beta', '0', '--level', '1');
    assert.equal(text.status, 0, text.stderr);
    const m = text.stdout.match(/^max reconstruction error (\S+) \(relative \S+\), loop scheme, level 1\n$/);
    assert.ok(m, text.stdout);
    assert.equal(Number(m[1]), mr.roundtripError({ alpha: 0, beta: 0, level: 1 }));
    mr.delete();
  });

  test('a level beyond the mesh\'s is an error', () => {
    failsWith(mrvolCli('roundtrip', file('ico.obj'), '--level', '1'), /level 1 is out of range/);
  });
});

// ---- errors ------------------------------------------------------------------------------------

describe('errors', () => {
  test('missing file: exit 1, one line', () => {
    const missing = file('does-not-exist.obj');
    failsWith(mrvolCli('info', missing), /does-not-exist\.obj/);
    failsWith(mrvolCli('subdivide', missing, '--levels', '1', '-o', file('never.obj')), /does-not-exist\.obj/);
    assert.ok(!existsSync(file('never.obj')));
  });

  test('invalid OBJ or mesh: exit 1, one line naming the file', () => {
    writeFileSync(file('quad.obj'), 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 1\n');
    failsWith(mrvolCli('info', file('quad.obj')), /quad\.obj: line 5: polygon with 4 vertices uses vertex 1 more than once/);
    writeFileSync(file('flip.obj'), 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf 1 4 3\nf 2 3 4\n');
    failsWith(mrvolCli('info', file('flip.obj'), '--json'), /flip\.obj: inconsistent orientation/);
    failsWith(mrvolCli('subdivide', file('ico.obj'), '--levels', '13', '-o', file('big.obj')), /levels must be between 0 and 12/);
  });

  test('output that cannot be written: exit 1', () => {
    failsWith(mrvolCli('subdivide', file('ico.obj'), '--levels', '1', '-o', file(join('no', 'such', 'dir.obj'))), /cannot write/);
  });

  test('bad usage: exit 2', () => {
    usageError(mrvolCli());
    usageError(mrvolCli('frobnicate', file('ico.obj')), /^mrvol: error: unknown command 'frobnicate'/);
    usageError(mrvolCli('info'), /^mrvol: error: missing MESH\.obj/);
    usageError(mrvolCli('info', file('ico.obj'), file('ico.obj')), /^mrvol: error: unexpected argument/);
    usageError(mrvolCli('info', file('ico.obj'), '--bogus'), /^mrvol: error: .*--bogus/);
    usageError(mrvolCli('subdivide', file('ico.obj'), '-o', file('x.obj')), /^mrvol: error: --levels is required/);
    usageError(mrvolCli('subdivide', file('ico.obj'), '--levels', '1'), /-o OUT\.obj is required/);
    usageError(mrvolCli('subdivide', file('ico.obj'), '--levels', '1', '--scheme', 'cubic', '-o', file('x.obj')),
      /--scheme must be loop, butterfly or linear/);
    usageError(mrvolCli('roundtrip', file('ico.obj'), '--level', '1.5'), /--level expects an integer/);
    usageError(mrvolCli('roundtrip', file('ico.obj'), '--level'), /^mrvol: error: /);
    assert.ok(!existsSync(file('x.obj')));
  });

  test('--help: exit 0, usage on stdout', () => {
    const r = mrvolCli('--help');
    assert.equal(r.status, 0);
    assert.match(r.stdout, /^usage: mrvol <command>/);
    assert.equal(r.stderr, '');
  });
});
