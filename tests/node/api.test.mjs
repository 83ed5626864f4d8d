// The public JS API over the real WASM module (lib/node.mjs): OBJ in and out, validation, volume,
// subdivision and hierarchy detection, perfect reconstruction of every scheme, typed arrays that
// are copies, errors as MrvolError with the core's message, and an instance that survives them.
import { test, describe, before } from 'node:test';
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { createMrvol, MrvolError } from '../../lib/node.mjs';
import {
  ROOT, mesh, icosahedron, octahedron, openPatch, rng, shuffleMesh, maxAbs, maxDiff, throwsMrvol as throwsMrvolError,
} from './helpers.mjs';

// ---- fixtures (the same models as tests/native/fixtures.h; the shared ones in helpers.mjs) -------

// Unit right tetrahedron, outward: volume 1/6.
const unitTetrahedron = () => mesh([0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1], [0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3]);

function torus(u = 6, v = 4, R = 2, r = 0.7) {
  const p = [], f = [];
  for (let i = 0; i < u; ++i)
    for (let j = 0; j < v; ++j) {
      const a = 2 * Math.PI * i / u, b = 2 * Math.PI * j / v;
      p.push((R + r * Math.cos(b)) * Math.cos(a), (R + r * Math.cos(b)) * Math.sin(a), r * Math.sin(b));
    }
  const id = (i, j) => ((i + u) % u) * v + (j + v) % v;
  for (let i = 0; i < u; ++i)
    for (let j = 0; j < v; ++j) {
      const a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      f.push(a, b, c, a, c, d);
    }
  return mesh(p, f);
}

const SCHEMES = [
  { scheme: 'loop' },
  { scheme: 'loop', alpha: 0, beta: 0 },
  { scheme: 'butterfly' },
  { scheme: 'linear' },
];
const label = (s) => s.scheme + (s.alpha === 0 ? ' (plain)' : '');

function randomPositions(n, seed, scale = 1) {
  const r = rng(seed);
  return Float64Array.from({ length: 3 * n }, () => (2 * r() - 1) * scale);
}

// Errors of the API are MrvolErrors, Errors named 'MrvolError'.
const throwsMrvol = (fn, message) => throwsMrvolError(fn, message, { named: true });

// ---- tests -------------------------------------------------------------------------------------

let mrvol;
before(async () => {
  mrvol = await createMrvol();
});

describe('OBJ text', () => {
  test('readObj parses triangles into typed arrays, 0-based', () => {
    const m = mrvol.readObj('# square\nv 0 0 0\nv 1 0 0\r\nv 1 1 0 1\nvn 0 0 1\nv 0 1 0\nf 1/1/1 2//1 3\nf -4 -2 -1\n');
    assert.ok(m.positions instanceof Float64Array);
    assert.ok(m.faces instanceof Uint32Array);
    assert.deepEqual(Array.from(m.positions), [0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0]);
    assert.deepEqual(Array.from(m.faces), [0, 1, 2, 0, 2, 3]);
  });

  test('writeObj -> readObj keeps vertex order and exact coordinates', () => {
    const m = shuffleMesh(torus(), 3, { shuffleFaces: true }).mesh;
    const r = rng(5);
    for (let i = 0; i < m.positions.length; ++i) m.positions[i] = m.positions[i] / 3 + (r() - 0.5) * 1e-9;
    m.positions[0] = 1e-300;
    m.positions[1] = -1e100;
    m.positions[2] = 5e-324;
    m.positions[3] = 0.1 + 0.2;
    const text = mrvol.writeObj(m);
    assert.equal(typeof text, 'string');
    const lines = text.trimEnd().split('\n');
    assert.equal(lines.length, m.positions.length / 3 + m.faces.length / 3);
    assert.match(lines[0], /^v \S+ \S+ \S+$/);
    assert.equal(lines.at(-1), `f ${m.faces.at(-3) + 1} ${m.faces.at(-2) + 1} ${m.faces.at(-1) + 1}`);
    const back = mrvol.readObj(text);
    assert.deepEqual(back.positions, m.positions);
    assert.deepEqual(back.faces, m.faces);
    assert.equal(mrvol.writeObj(back), text);
  });

  test('readObj errors carry the line', () => {
    throwsMrvol(() => mrvol.readObj('v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 1 3\n'), /^line 4: polygon with 4 vertices uses vertex 1 more than once/);
    throwsMrvol(() => mrvol.readObj('v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n'),
      'line 4: face refers to vertex 9 but the file has 3 vertices');
    throwsMrvol(() => mrvol.readObj(''), 'empty input: no vertices and no faces');
  });
});

describe('validate and volume', () => {
  test('topology of the fixtures', () => {
    assert.deepEqual(mrvol.validate(icosahedron()), { edges: 30, boundaryEdges: 0, components: 1, closed: true, genus: 0 });
    assert.deepEqual(mrvol.validate(torus()), { edges: 72, boundaryEdges: 0, components: 1, closed: true, genus: 1 });
    assert.deepEqual(mrvol.validate(openPatch()), { edges: 42, boundaryEdges: 12, components: 1, closed: false, genus: 0 });
    const a = unitTetrahedron();
    const two = mesh([...a.positions, ...a.positions.map((x, i) => (i % 3 === 0 ? x + 5 : x))],
      [...a.faces, ...a.faces.map((i) => i + 4)]);
    assert.deepEqual(mrvol.validate(two), { edges: 12, boundaryEdges: 0, components: 2, closed: true, genus: 0 });
  });

  test('validation errors', () => {
    const m = icosahedron();
    [m.faces[1], m.faces[2]] = [m.faces[2], m.faces[1]];
    throwsMrvol(() => mrvol.validate(m), /^inconsistent orientation at edge/);
    throwsMrvol(() => mrvol.volume(m), /^inconsistent orientation at edge/);
  });

  test('volumes: tetrahedron, octahedron, icosahedron, translation, orientation', () => {
    assert.ok(Math.abs(mrvol.volume(unitTetrahedron()) - 1 / 6) < 1e-15);
    assert.ok(Math.abs(mrvol.volume(octahedron()) - 4 / 3) < 1e-14);
    const ico = icosahedron(), v = mrvol.volume(ico);
    assert.ok(Math.abs(v - 5 / 12 * (3 + Math.sqrt(5)) * 8) < 1e-12);
    const moved = { positions: ico.positions.map((x) => x + 1e6), faces: ico.faces };
    assert.ok(Math.abs(mrvol.volume(moved) - v) < 1e-9 * v);
    const flipped = { positions: ico.positions, faces: ico.faces.slice() };
    for (let f = 0; f < 20; ++f) [flipped.faces[3 * f + 1], flipped.faces[3 * f + 2]] = [flipped.faces[3 * f + 2], flipped.faces[3 * f + 1]];
    assert.ok(Math.abs(mrvol.volume(flipped) + v) < 1e-13 * v);
  });
});

describe('subdivide and openMesh', () => {
  const cases = [
    { name: 'icosahedron', base: icosahedron, V: [12, 42, 162, 642], F: [20, 80, 320, 1280], closed: true, genus: 0 },
    { name: 'octahedron', base: octahedron, V: [6, 18, 66, 258], F: [8, 32, 128, 512], closed: true, genus: 0 },
    { name: 'torus', base: torus, V: [24, 96, 384], F: [48, 192, 768], closed: true, genus: 1 },
    { name: 'open patch', base: openPatch, V: [19, 61, 217], F: [24, 96, 384], closed: false, genus: 0 },
  ];

  test('every scheme gives the expected counts', () => {
    for (const c of cases)
      for (const s of SCHEMES)
        for (let levels = 0; levels < c.V.length; ++levels) {
          const mr = mrvol.subdivide(c.base(), { levels, ...s });
          const where = `${c.name} ${label(s)} levels ${levels}`;
          assert.equal(mr.levels, levels, where);
          assert.equal(mr.vertexCount, c.V[levels], where);
          assert.equal(mr.faceCount, c.F[levels], where);
          const info = mr.info();
          assert.equal(info.vertices, c.V[levels], where);
          assert.equal(info.faces, c.F[levels], where);
          assert.equal(info.levels, levels, where);
          assert.equal(info.baseVertices, c.V[0], where);
          assert.deepEqual(Array.from(info.baseVertexIndices), Array.from({ length: c.V[0] }, (_, i) => i), where);
          assert.equal(info.closed, c.closed, where);
          assert.equal(info.genus, c.genus, where);
          assert.equal(info.components, 1, where);
          assert.equal(mr.positions().length, 3 * c.V[levels], where);
          assert.equal(mr.faces().length, 3 * c.F[levels], where);
          const depths = mr.depths();
          assert.ok(depths instanceof Uint8Array, where);
          for (let l = 0; l <= levels; ++l)
            for (let v = l ? c.V[l - 1] : 0; v < c.V[l]; ++v) assert.equal(depths[v], l, `${where} vertex ${v}`);
          mr.delete();
        }
  });

  test('subdivision with the interpolating schemes keeps the base positions', () => {
    for (const scheme of ['butterfly', 'linear']) {
      const base = icosahedron();
      const mr = mrvol.subdivide(base, { levels: 2, scheme });
      assert.deepEqual(mr.positions().subarray(0, 36), base.positions);
      mr.delete();
    }
  });

  test('openMesh detects the levels of a shuffled subdivided mesh', () => {
    for (const c of cases) {
      if (c.name === 'open patch') continue;  // the patch is itself a split of a fan: one level more
      const levels = c.V.length - 1;
      const built = mrvol.subdivide(c.base(), { levels });
      for (const seed of [1, 2]) {
        const { mesh: m, perm } = shuffleMesh(built.toMesh(), seed, { shuffleFaces: true });
        const mr = mrvol.openMesh(m);
        assert.equal(mr.levels, levels, c.name);
        assert.equal(mr.vertexCount, c.V[levels]);
        const info = mr.info();
        assert.equal(info.levels, levels);
        assert.equal(info.baseVertices, c.V[0]);
        assert.deepEqual(mr.positions(), m.positions, 'positions stay in the caller\'s order');
        assert.deepEqual(mr.faces(), m.faces, 'faces stay in the caller\'s order');
        // Depth counts per level; for a base with a unique tiling, the very same vertices.
        const depths = mr.depths();
        for (let l = 0; l <= levels; ++l)
          assert.equal(depths.filter((d) => d === l).length, c.V[l] - (l ? c.V[l - 1] : 0));
        if (c.name !== 'torus') {
          const expectedBase = perm.slice(0, c.V[0]).sort((a, b) => a - b);
          assert.deepEqual(Array.from(info.baseVertexIndices), expectedBase);
          assert.deepEqual(Array.from(mr.baseVertexIndices), expectedBase);
          const builtDepths = built.depths();
          for (let v = 0; v < perm.length; ++v) assert.equal(depths[perm[v]], builtDepths[v]);
        }
        assert.ok(Math.abs(info.volume - built.info().volume) < 1e-12 * Math.abs(info.volume));
        mr.delete();
      }
      built.delete();
    }
  });

  test('openMesh honours maxLevels; a base mesh has 0 levels', () => {
    const built = mrvol.subdivide(icosahedron(), { levels: 3 });
    const m = shuffleMesh(built.toMesh(), 4, { shuffleFaces: true }).mesh;
    for (let maxLevels = 0; maxLevels <= 4; ++maxLevels) {
      const mr = mrvol.openMesh(m, { maxLevels });
      assert.equal(mr.levels, Math.min(3, maxLevels));
      mr.delete();
    }
    built.delete();
    const base = mrvol.openMesh(icosahedron());
    assert.equal(base.levels, 0);
    assert.deepEqual(Array.from(base.depths()), new Array(12).fill(0));
    base.delete();
  });
});

describe('wavelet transforms', () => {
  test('analyze/synthesize reconstruct random positions for every scheme and level', () => {
    for (const [name, base, levels] of [['icosahedron', icosahedron, 3], ['torus', torus, 2], ['open patch', openPatch, 2]]) {
      const built = mrvol.subdivide(base(), { levels });
      const { mesh: m } = shuffleMesh({ positions: randomPositions(built.vertexCount, 11), faces: built.faces() }, 7,
        { shuffleFaces: true });
      built.delete();
      const mr = mrvol.openMesh(m, { maxLevels: levels });
      assert.equal(mr.levels, levels);
      const x = m.positions, scale = maxAbs(x);
      for (const s of SCHEMES)
        for (let level = 0; level <= levels; ++level) {
          const where = `${name} ${label(s)} level ${level}`;
          const c = mr.analyze(x, { level, ...s });
          assert.ok(c instanceof Float64Array, where);
          assert.equal(c.length, x.length, where);
          const back = mr.synthesize(c, { level, ...s });
          assert.ok(maxDiff(back, x) < 1e-12 * scale, `${where}: error ${maxDiff(back, x)}`);
          if (level === levels) assert.deepEqual(c, x, `${where}: analysis to the finest level is the identity`);
        }
      // roundtripError works on the current positions.
      mr.setPositions(x);
      for (const s of SCHEMES) assert.ok(mr.roundtripError({ level: 0, ...s }) < 1e-12 * scale);
      mr.delete();
    }
  });

  test('zero-detail synthesis analyses to zero details and the base positions', () => {
    for (const [name, base] of [['icosahedron', icosahedron], ['octahedron', octahedron], ['open patch', openPatch]])
      for (const s of SCHEMES) {
        const where = `${name} ${label(s)}`;
        const b = base();
        const mr = mrvol.subdivide(b, { levels: 2, ...s });
        const x = mr.positions(), depths = mr.depths(), scale = maxAbs(b.positions);
        const c = mr.analyze(x, { level: 0, ...s });
        for (let v = 0; v < depths.length; ++v)
          for (let k = 0; k < 3; ++k) {
            const expected = depths[v] === 0 ? b.positions[3 * v + k] : 0;
            assert.ok(Math.abs(c[3 * v + k] - expected) < 1e-12 * scale, `${where} vertex ${v} depth ${depths[v]}: ${c[3 * v + k]}`);
          }
        // At level 1, details of depth 2 still vanish.
        const c1 = mr.analyze(x, { level: 1, ...s });
        for (let v = 0; v < depths.length; ++v)
          if (depths[v] === 2) for (let k = 0; k < 3; ++k) assert.ok(Math.abs(c1[3 * v + k]) < 1e-12 * scale, where);
        // Another scheme sees details (the schemes differ), except linear/butterfly both interpolate
        // the base: just check that Loop subdivision is not zero-detail for the linear scheme.
        if (s.scheme === 'loop' && s.alpha === undefined) {
          const other = mr.analyze(x, { level: 0, scheme: 'linear' });
          let m = 0;
          for (let v = 0; v < depths.length; ++v) if (depths[v] > 0) m = Math.max(m, Math.abs(other[3 * v]), Math.abs(other[3 * v + 1]), Math.abs(other[3 * v + 2]));
          assert.ok(m > 1e-3, `${where}: the linear analysis of a Loop surface has details`);
        }
        mr.delete();
      }
  });

  test('default options are Loop at level 0', () => {
    const mr = mrvol.subdivide(icosahedron(), { levels: 2 });
    const x = mr.positions();
    assert.deepEqual(mr.analyze(x), mr.analyze(x, { scheme: 'loop', alpha: -1.70943, beta: 0.42954, level: 0 }));
    assert.notDeepEqual(mr.analyze(x), mr.analyze(x, { scheme: 'loop', alpha: 0, beta: 0 }));
    mr.delete();
  });
});

describe('typed arrays', () => {
  test('outputs are copies: mutating them does not affect the module', () => {
    const base = icosahedron();
    const mr = mrvol.subdivide(base, { levels: 1, scheme: 'butterfly' });
    const p = mr.positions(), f = mr.faces(), d = mr.depths(), info = mr.info(), mesh1 = mr.toMesh();
    const p0 = p.slice(), f0 = f.slice(), d0 = d.slice(), b0 = info.baseVertexIndices.slice();
    p.fill(42); f.fill(7); d.fill(9); info.baseVertexIndices.fill(3); mesh1.positions.fill(1); mesh1.faces.fill(1);
    mr.baseVertexIndices.fill(5);
    assert.deepEqual(mr.positions(), p0);
    assert.deepEqual(mr.faces(), f0);
    assert.deepEqual(mr.depths(), d0);
    assert.deepEqual(mr.info().baseVertexIndices, b0);
    assert.notEqual(mr.positions(), mr.positions(), 'a fresh array per call');
    assert.ok(mr.positions().buffer !== mr.positions().buffer);
    // Results of analysis are independent arrays too, and analysis does not modify its input.
    const x = mr.positions(), xCopy = x.slice();
    const c = mr.analyze(x, { level: 0 });
    assert.deepEqual(x, xCopy);
    c.fill(0);
    assert.deepEqual(mr.analyze(x, { level: 0 }).subarray(0, 3).length, 3);
    assert.ok(maxAbs(mr.analyze(x, { level: 0 })) > 0);
    // Inputs are copied in: changing them after the call changes nothing.
    const q = randomPositions(mr.vertexCount, 3);
    mr.setPositions(q);
    const q0 = q.slice();
    q.fill(0);
    assert.deepEqual(mr.positions(), q0);
    // readObj's arrays are the caller's to keep.
    const m = mrvol.readObj('v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n');
    const m2 = mrvol.readObj('v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n');
    m.positions.fill(5);
    assert.deepEqual(Array.from(m2.positions), [0, 0, 0, 1, 0, 0, 0, 1, 0]);
    mr.delete();
  });
});

describe('errors', () => {
  test('bad levels', () => {
    const mr = mrvol.subdivide(icosahedron(), { levels: 2 });
    const x = mr.positions();
    for (const level of [3, 7, -1])
      for (const fn of [() => mr.analyze(x, { level }), () => mr.synthesize(x, { level }), () => mr.roundtripError({ level })])
        throwsMrvol(fn, `level ${level} is out of range: this mesh has levels 0..2`);
    throwsMrvol(() => mr.analyze(x, { level: 1.5 }), 'level must be an integer, got 1.5');
    throwsMrvol(() => mr.analyze(x, { level: NaN }), 'level must be an integer, got NaN');
    throwsMrvol(() => mr.analyze(x, { level: '1' }), /^level must be an integer/);
    throwsMrvol(() => mrvol.subdivide(icosahedron(), { levels: -1 }), 'levels must be between 0 and 12, got -1');
    throwsMrvol(() => mrvol.subdivide(icosahedron(), { levels: 13 }), 'levels must be between 0 and 12, got 13');
    // A result that cannot fit is refused at once, naming the result (not "the input is too large"
    // after 16 s and 3.4 GB).
    throwsMrvol(() => mrvol.subdivide(icosahedron(), { levels: 11 }),
                '11 levels on 20 faces make 83,886,080 faces, too many for this WebAssembly module: ask fewer levels');
    throwsMrvol(() => mrvol.subdivide(icosahedron(), { levels: 0.5 }), 'levels must be an integer, got 0.5');
    mr.delete();
  });

  // Integers beyond 32 bits would wrap in the embind int conversion: the JS layer refuses them.
  test('levels beyond 32 bits are refused', () => {
    const mr = mrvol.subdivide(icosahedron(), { levels: 1 });
    const x = mr.positions();
    try {
      throwsMrvol(() => mr.analyze(x, { level: 2 ** 32 }), /level/);
      throwsMrvol(() => mr.synthesize(x, { level: 2 ** 32 + 1 }), /level/);
      throwsMrvol(() => mr.analyze(x, { level: 2 ** 31 }), 'level 2147483648 is out of range');
      throwsMrvol(() => mr.analyze(x, { level: -(2 ** 31) - 1 }), 'level -2147483649 is out of range');
      throwsMrvol(() => mr.analyze(x, { level: 2 ** 31 - 1 }), 'level 2147483647 is out of range: this mesh has levels 0..1');
      throwsMrvol(() => mrvol.subdivide(icosahedron(), { levels: 2 ** 32 }), /levels/);
    } finally {
      mr.delete();
    }
  });

  test('bad maxLevels are refused', () => {
    const built = mrvol.subdivide(icosahedron(), { levels: 1 });
    const m = built.toMesh();
    built.delete();
    for (const maxLevels of ['x', -1, 2 ** 32, 1.5]) throwsMrvol(() => mrvol.openMesh(m, { maxLevels }).delete(), /maxLevels/);
  });

  test('wrong array lengths', () => {
    const mr = mrvol.subdivide(icosahedron(), { levels: 1 });
    const n = 3 * mr.vertexCount;
    throwsMrvol(() => mr.analyze(new Float64Array(5)), `expected ${n} coordinates, got 5`);
    throwsMrvol(() => mr.analyze(new Float64Array(n + 3)), `expected ${n} coordinates, got ${n + 3}`);
    throwsMrvol(() => mr.synthesize(new Float64Array(6)), `expected ${n} coefficients, got 6`);
    throwsMrvol(() => mr.setPositions(new Float64Array(0)), `expected ${n} coordinates (3 per vertex), got 0`);
    throwsMrvol(() => mrvol.validate({ positions: new Float64Array(7), faces: new Uint32Array([0, 1, 2]) }),
      'positions must hold 3 numbers per vertex');
    throwsMrvol(() => mrvol.validate({ positions: new Float64Array(9), faces: new Uint32Array([0, 1, 2, 0]) }),
      'faces must hold 3 vertex indices per triangle');
    mr.delete();
  });

  test('wrong types', () => {
    const mr = mrvol.subdivide(icosahedron(), { levels: 1 });
    const x = mr.positions();
    throwsMrvol(() => mr.analyze(Array.from(x)), 'positions must be a Float64Array');
    throwsMrvol(() => mr.analyze(Float32Array.from(x)), 'positions must be a Float64Array');
    throwsMrvol(() => mr.synthesize(null), 'coefficients must be a Float64Array');
    throwsMrvol(() => mr.setPositions(undefined), 'positions must be a Float64Array');
    throwsMrvol(() => mr.analyze(x, { scheme: 3 }), 'scheme must be a string (loop, butterfly or linear)');
    throwsMrvol(() => mr.analyze(x, { alpha: NaN }), 'alpha and beta must be finite numbers');
    throwsMrvol(() => mr.analyze(x, { beta: '1' }), 'alpha and beta must be finite numbers');
    throwsMrvol(() => mrvol.readObj(42), 'readObj expects the OBJ file as a Uint8Array or a string');
    throwsMrvol(() => mrvol.readObj([118, 32, 48]), 'readObj expects the OBJ file as a Uint8Array or a string');
    throwsMrvol(() => mrvol.readObj(new Uint8Array(3)), 'line 1: binary data (byte 0 at column 1): this is not an OBJ text file');
    const ico = icosahedron();
    for (const fn of [mrvol.writeObj, mrvol.validate, mrvol.volume, mrvol.openMesh, mrvol.subdivide]) {
      throwsMrvol(() => fn(null), 'expected a mesh { positions, faces }');
      throwsMrvol(() => fn('mesh'), 'expected a mesh { positions, faces }');
      throwsMrvol(() => fn({ positions: Array.from(ico.positions), faces: ico.faces }), 'mesh.positions must be a Float64Array');
      throwsMrvol(() => fn({ positions: ico.positions, faces: Int32Array.from(ico.faces) }), 'mesh.faces must be a Uint32Array');
      throwsMrvol(() => fn({ positions: ico.positions, faces: Array.from(ico.faces) }), 'mesh.faces must be a Uint32Array');
    }
    mr.delete();
  });

  test('unknown scheme', () => {
    const mr = mrvol.subdivide(icosahedron(), { levels: 1 });
    const x = mr.positions();
    const message = "unknown scheme 'foo' (expected loop, butterfly or linear)";
    throwsMrvol(() => mr.analyze(x, { scheme: 'foo' }), message);
    throwsMrvol(() => mr.synthesize(x, { scheme: 'foo' }), message);
    throwsMrvol(() => mr.roundtripError({ scheme: 'foo' }), message);
    throwsMrvol(() => mrvol.subdivide(icosahedron(), { levels: 1, scheme: 'foo' }), message);
    throwsMrvol(() => mr.analyze(x, { scheme: 'Loop' }), "unknown scheme 'Loop' (expected loop, butterfly or linear)");
    mr.delete();
  });

  test('invalid meshes are refused with the core\'s message', () => {
    throwsMrvol(() => mrvol.openMesh({ positions: new Float64Array(9), faces: new Uint32Array([0, 1, 5]) }),
      'face 0 refers to vertex 5 but there are 3 vertices');
    throwsMrvol(() => mrvol.subdivide({ positions: new Float64Array(9), faces: new Uint32Array([0, 1, 1]) }, { levels: 1 }),
      'face 0 is degenerate: it uses vertex 1 twice');
    const p = new Float64Array(9);
    p[4] = Infinity;
    throwsMrvol(() => mrvol.validate({ positions: p, faces: new Uint32Array([0, 1, 2]) }), 'vertex 1 has a non-finite coordinate');
  });

  test('delete() then use throws MrvolError; delete() twice is harmless', () => {
    const mr = mrvol.subdivide(icosahedron(), { levels: 1 });
    const x = mr.positions();
    mr.delete();
    const message = 'this MultiresMesh has been deleted';
    for (const fn of [() => mr.info(), () => mr.positions(), () => mr.faces(), () => mr.depths(), () => mr.toMesh(),
      () => mr.setPositions(x), () => mr.analyze(x), () => mr.synthesize(x), () => mr.roundtripError()])
      throwsMrvol(fn, message);
    mr.delete();
    throwsMrvol(() => mr.info(), message);
  });

  test('the instance keeps working after errors', () => {
    const mr = mrvol.subdivide(icosahedron(), { levels: 2 });
    const x = mr.positions();
    const good = mr.analyze(x, { level: 1 });
    for (let i = 0; i < 3; ++i) {
      throwsMrvol(() => mr.analyze(x, { level: 9 }));
      throwsMrvol(() => mr.synthesize(new Float64Array(3)));
      throwsMrvol(() => mrvol.readObj('v 1 2 3\nf 1 2 3\n'));
      throwsMrvol(() => mrvol.subdivide(icosahedron(), { scheme: 'nope' }));
      throwsMrvol(() => mrvol.openMesh({ positions: new Float64Array(9), faces: new Uint32Array([0, 1, 1]) }));
      // A failed call leaves no error behind for the next one.
      assert.deepEqual(mr.analyze(x, { level: 1 }), good);
      assert.equal(mr.info().levels, 2);
      assert.ok(Math.abs(mrvol.volume(unitTetrahedron()) - 1 / 6) < 1e-15);
    }
    const other = mrvol.subdivide(octahedron(), { levels: 1 });
    assert.equal(other.vertexCount, 18);
    other.delete();
    mr.delete();
  });

  test('the core entry points load no three.js, three-mesh-bvh or meshoptimizer; mrvol/remesh is apart', () => {
    // A child process whose module resolver refuses those packages, then loads and uses the core.
    const refuse = `export async function resolve(s, c, next) {
      if (/^(three|three-mesh-bvh|meshoptimizer)(\\/|$)/.test(s)) throw new Error('the core loaded ' + s);
      return next(s, c);
    }`;
    const script = `
      import { register } from 'node:module';
      register('data:text/javascript,' + encodeURIComponent(${JSON.stringify(refuse)}));
      const node = await import(${JSON.stringify(new URL('../../lib/node.mjs', import.meta.url).href)});
      const api = await import(${JSON.stringify(new URL('../../lib/api.mjs', import.meta.url).href)});
      const mrvol = await node.createMrvol();
      console.log(JSON.stringify({ volume: mrvol.volume(mrvol.readObj('v 0 0 0\\nv 1 0 0\\nv 0 1 0\\nv 0 0 1\\nf 1 3 2\\nf 1 2 4\\nf 1 4 3\\nf 2 3 4\\n')),
        nodeExports: Object.keys(node).sort(), apiExports: Object.keys(api).sort() }));
      let refused = null;
      try { await import('three'); } catch (e) { refused = e.message; }
      console.log(JSON.stringify({ refused }));`;
    const r = spawnSync(process.execPath, ['--input-type=module', '-e', script], { encoding: 'utf8', cwd: ROOT });
    assert.equal(r.status, 0, r.stderr);
    const [used, check] = r.stdout.trim().split('\n').map((l) => JSON.parse(l));
    assert.ok(Math.abs(used.volume - 1 / 6) < 1e-15);
    assert.deepEqual(used.nodeExports, ['DEFAULT_SCHEME', 'MrvolError', 'canUseThreads', 'chooseGradientPath', 'createMrvol', 'readObjFile', 'wrapModule']);
    assert.deepEqual(used.apiExports, ['DEFAULT_SCHEME', 'MrvolError', 'chooseGradientPath', 'wrapModule']);
    assert.match(check.refused, /the core loaded three/, 'the resolver hook is in force');
  });

  test('mrvol/remesh (lib/remesh.mjs) exports the remesher and the repair stage', async () => {
    const m = await import('../../lib/remesh.mjs');
    for (const name of ['remesh', 'repair', 'weld', 'defaultBaseFaces']) assert.equal(typeof m[name], 'function', name);
  });

  test('MrvolError is exported by both entry points', async () => {
    const api = await import('../../lib/api.mjs');
    assert.equal(api.MrvolError, MrvolError);
    assert.equal(mrvol.MrvolError, MrvolError);
    const e = new MrvolError('x');
    assert.ok(e instanceof Error);
    assert.equal(e.name, 'MrvolError');
    assert.equal(e.message, 'x');
  });
});
