// The volume tensor theta^e (issue 3) through the real WASM module and the real CLI: the tensor
// volume equals the mesh volume for every scheme, level and sample model (also after the positions
// change: theta depends on connectivity only), full-storage counts (the paper's spiky ball), the
// entries against a direct construction in JS, theta files (round trip, damaged, future, mismatched)
// and the CLI commands `volume` and `theta`.
import { test, describe, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { writeFileSync, readFileSync, existsSync, statSync } from 'node:fs';
import { createMrvol } from '../../lib/node.mjs';
import {
  tempFolder, runCliSync, json, failsWith, usageError, model, loadModel as loadModelWith, octahedron, rng, shuffleMesh, relErr, throwsMrvol,
} from './helpers.mjs';

const SCHEMES = ['loop', 'butterfly', 'linear'];

// The theta file layout (format version 1, little-endian), as written by wasm/core/src/theta_file.cpp:
// 'MRVOLTHT', u32 version @8, u32 header size (96) @12, u8 scheme @16, u8 storage @17, u8 index
// bytes @18, u32 levels @20, u32 level @24, u32 N @28, f64 alpha @32, f64 beta @40, u64
// fingerprint @48, u64 nnzFull @56, u64 rows @64, u64 pairs @72, u64 entries @80; then rowStart,
// pairJ, pairStart (u32), k (u16 or u32), padding to 8, values (f64), u64 checksum.
function parseTheta(bytes, { headerOnly = false } = {}) {
  const dv = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  const u64 = (o) => Number(dv.getBigUint64(o, true));
  const h = {
    magic: new TextDecoder().decode(bytes.subarray(0, 8)), version: dv.getUint32(8, true), headerBytes: dv.getUint32(12, true),
    scheme: bytes[16], storage: bytes[17], indexBytes: bytes[18], levels: dv.getUint32(20, true), level: dv.getUint32(24, true),
    vertices: dv.getUint32(28, true), alpha: dv.getFloat64(32, true), beta: dv.getFloat64(40, true),
    fingerprint: dv.getBigUint64(48, true).toString(16).padStart(16, '0'), nnzFull: u64(56), rows: u64(64), pairs: u64(72),
    entries: u64(80),
  };
  if (headerOnly) return { header: h };
  let at = h.headerBytes;
  const u32s = (n) => { const a = []; for (let i = 0; i < n; ++i, at += 4) a.push(dv.getUint32(at, true)); return a; };
  const rowStart = u32s(h.rows + 1), pairJ = u32s(h.pairs), pairStart = u32s(h.pairs + 1);
  const kIndex = [];
  for (let t = 0; t < h.entries; ++t, at += h.indexBytes) kIndex.push(h.indexBytes === 2 ? dv.getUint16(at, true) : dv.getUint32(at, true));
  at = Math.ceil(at / 8) * 8;
  const entries = new Map();  // "i,j,k" -> value
  for (let i = 0; i < h.rows; ++i)
    for (let p = rowStart[i]; p < rowStart[i + 1]; ++p)
      for (let t = pairStart[p]; t < pairStart[p + 1]; ++t) entries.set(`${i},${pairJ[p]},${kIndex[t]}`, dv.getFloat64(at + 8 * t, true));
  at += 8 * h.entries;
  return { header: h, entries, end: at + 8 };
}

// theta^e built directly (method section 6): with R the synthesis operator from level e (columns
// = synthesis of unit coefficients), T_ijk = sum over fine triangles (a, b, c) of
// det[R_a; R_b; R_c] restricted to columns i < j < k, divided by 6. Vertex order of a subdivided
// mesh is the hierarchy order.
function directTensor(mr, level, scheme) {
  const n = mr.vertexCount, faces = mr.faces();
  const R = [];  // R[a][i]
  for (let a = 0; a < n; ++a) R.push(new Float64Array(n));
  for (let i = 0; i < n; ++i) {
    const c = new Float64Array(3 * n);
    c[3 * i] = 1;
    const x = mr.synthesize(c, { level, ...scheme });
    for (let a = 0; a < n; ++a) R[a][i] = x[3 * a];
  }
  // Per triangle, only triples inside the union of the three rows' supports contribute.
  const dense = new Float64Array(n * n * n);
  for (let f = 0; f < faces.length; f += 3) {
    const A = R[faces[f]], B = R[faces[f + 1]], C = R[faces[f + 2]];
    const S = [];
    for (let i = 0; i < n; ++i) if (A[i] !== 0 || B[i] !== 0 || C[i] !== 0) S.push(i);
    for (let x = 0; x < S.length; ++x)
      for (let y = x + 1; y < S.length; ++y)
        for (let z = y + 1; z < S.length; ++z) {
          const i = S[x], j = S[y], k = S[z];
          dense[(i * n + j) * n + k] +=
            A[i] * (B[j] * C[k] - B[k] * C[j]) - A[j] * (B[i] * C[k] - B[k] * C[i]) + A[k] * (B[i] * C[j] - B[j] * C[i]);
        }
  }
  const T = new Map();
  for (let i = 0; i < n; ++i)
    for (let j = i + 1; j < n; ++j)
      for (let k = j + 1; k < n; ++k) {
        const s = dense[(i * n + j) * n + k];
        if (s !== 0) T.set(`${i},${j},${k}`, s / 6);
      }
  return T;
}

const mrvolCli = (...args) => runCliSync(args, { timeout: 60000 });

let mrvol;
const file = tempFolder('mrvol-theta-test-');
const loadModel = (name) => loadModelWith(mrvol, name);
const icosahedron = () => loadModel('icosahedron');

before(async () => {
  mrvol = await createMrvol();
});

// ---- the tensor volume ---------------------------------------------------------------------------

describe('tensor volume equals the mesh volume', () => {
  // Cage storage: every scheme, every level, every sample model; then the same tensor on perturbed
  // positions (same connectivity), which checks the trilinear form itself and not one value.
  for (const name of ['icosahedron', 'spiky-ball', 'torus', 'blob'])
    test(`${name}: every scheme and level, cage storage, also after the positions change`, () => {
      const mr = mrvol.openMesh(loadModel(name));
      const original = mr.positions(), faces = mr.faces();
      const r = rng(name.length);
      const perturbed = original.map((x) => x + 0.05 * (2 * r() - 1));
      const perturbedVolume = mrvol.volume({ positions: perturbed, faces });
      const volume = mr.info().volume;
      assert.ok(relErr(perturbedVolume, volume) > 1e-4, 'the perturbation changes the volume');
      for (const scheme of SCHEMES)
        for (let level = 0; level <= mr.levels; ++level) {
          const where = `${name} ${scheme} level ${level}`;
          const theta = mr.computeTheta({ level, scheme });
          const info = theta.info();
          assert.equal(info.formatVersion, 1, where);
          assert.equal(info.scheme, scheme, where);
          assert.equal(info.levels, mr.levels, where);
          assert.equal(info.level, level, where);
          assert.equal(info.storage, 'cage', where);
          assert.equal(info.fingerprint, mr.fingerprint(), where);
          assert.match(info.fingerprint, /^[0-9a-f]{16}$/);
          assert.equal(info.vertices, mr.vertexCount, where);
          assert.equal(info.nnzFull, null, `${where}: unknown with cage storage`);
          assert.ok(info.nnzStored > 0 && info.bytes >= 8 * info.nnzStored, where);
          if (level === mr.levels) assert.equal(info.nnzStored, mr.faceCount, `${where}: one entry per fine triangle`);
          assert.ok(typeof theta.precomputeMs === 'number' && theta.precomputeMs >= 0);
          const tv = mr.thetaVolume(theta, { level, scheme });
          assert.ok(relErr(tv, volume) < 1e-10, `${where}: ${tv} vs ${volume}`);
          mr.setPositions(perturbed);
          const tp = mr.thetaVolume(theta, { level, scheme });
          assert.ok(relErr(tp, perturbedVolume) < 1e-10, `${where} (perturbed): ${tp} vs ${perturbedVolume}`);
          mr.setPositions(original);
          theta.delete();
        }
      mr.delete();
    });

  test('plain Loop weights (alpha = beta = 0) and other weights: their own tensor', () => {
    const mr = mrvol.openMesh(loadModel('blob'));
    const volume = mr.info().volume;
    for (const weights of [{ alpha: 0, beta: 0 }, { alpha: -1, beta: 0.25 }])
      for (const level of [0, 2]) {
        const theta = mr.computeTheta({ level, ...weights });
        assert.equal(theta.info().alpha, weights.alpha);
        assert.equal(theta.info().beta, weights.beta);
        assert.ok(relErr(mr.thetaVolume(theta, { level, ...weights }), volume) < 1e-10);
        throwsMrvol(() => mr.thetaVolume(theta, { level }), /^theta file was computed with Loop weights alpha = /);
        theta.delete();
      }
    mr.delete();
  });

  test('full storage on the icosahedron subdivided twice: volumes and counts', () => {
    // 6 orderings per stored entry i < j < k; the cage rows are a subset; at e = n the tensor is
    // the fine triangles. (Exact counts below e = n include round-off residues of exact zeros, so
    // they are left to the direct construction below.)
    const mr = mrvol.subdivide(icosahedron(), { levels: 2 });
    const original = mr.positions();
    const r = rng(7);
    const perturbed = original.map((x) => x * (1 + 0.1 * r()));
    const volume = mr.info().volume, perturbedVolume = mrvol.volume({ positions: perturbed, faces: mr.faces() });
    for (const scheme of SCHEMES)
      for (let level = 0; level <= 2; ++level) {
        const where = `${scheme} level ${level}`;
        const full = mr.computeTheta({ level, scheme, storage: 'full' });
        const cage = mr.computeTheta({ level, scheme });
        const info = full.info();
        assert.equal(info.storage, 'full', where);
        assert.equal(info.nnzFull, 6 * info.nnzStored, where);
        assert.ok(cage.info().nnzStored <= info.nnzStored, where);
        if (level < 2) assert.ok(cage.info().nnzStored < info.nnzStored && info.nnzStored < 162 ** 3 / 6, where);
        if (level === 2) assert.deepEqual([info.nnzFull, info.nnzStored, cage.info().nnzStored], [6 * 320, 320, 320], where);
        assert.ok(relErr(mr.thetaVolume(full, { level, scheme }), volume) < 1e-10, where);
        mr.setPositions(perturbed);
        assert.ok(relErr(mr.thetaVolume(full, { level, scheme }), perturbedVolume) < 1e-10, where);
        assert.ok(relErr(mr.thetaVolume(cage, { level, scheme }), perturbedVolume) < 1e-10, where);
        mr.setPositions(original);
        full.delete();
        cage.delete();
      }
    mr.delete();
  });

  test('spiky ball, e = 0, full storage: 42253800 non-zeros (the paper: 42E6 of N^3 = 265E6), no round-off residues', () => {
    const mr = mrvol.openMesh(loadModel('spiky-ball'));
    assert.equal(mr.vertexCount, 642);
    const theta = mr.computeTheta({ level: 0, storage: 'full' });
    const info = theta.info();
    assert.equal(info.nnzFull, 42253800);
    assert.equal(info.nnzStored, 42253800 / 6);
    assert.ok(relErr(mr.thetaVolume(theta, { level: 0 }), mr.info().volume) < 1e-10);
    theta.delete();
    mr.delete();
  });

  test('the entries equal a direct construction from the synthesis rows (JS, small meshes)', () => {
    const cases = [
      { name: 'icosahedron, 1 level', base: icosahedron, levels: 1, level: 0 },
      { name: 'octahedron, 2 levels', base: octahedron, levels: 2, level: 0 },
    ];
    for (const c of cases)
      for (const scheme of [{ scheme: 'loop' }, { scheme: 'loop', alpha: 0, beta: 0 }, { scheme: 'butterfly' }, { scheme: 'linear' }]) {
        const where = `${c.name}, level ${c.level}, ${scheme.scheme}${scheme.alpha === 0 ? ' (plain)' : ''}`;
        const mr = mrvol.subdivide(c.base(), { levels: c.levels, ...scheme });
        const direct = directTensor(mr, c.level, scheme);
        const full = mr.computeTheta({ level: c.level, ...scheme, storage: 'full' });
        const cage = mr.computeTheta({ level: c.level, ...scheme });
        const pf = parseTheta(full.bytes()), pc = parseTheta(cage.bytes());
        let scale = 0;
        for (const v of direct.values()) scale = Math.max(scale, Math.abs(v));
        const tol = 1e-12 * scale;
        for (const [key, v] of pf.entries) assert.ok(Math.abs(v - (direct.get(key) ?? 0)) <= tol, `${where}: entry ${key}: ${v} vs ${direct.get(key)}`);
        let significant = 0;
        for (const [key, v] of direct)
          if (Math.abs(v) > tol) {
            ++significant;
            assert.ok(pf.entries.has(key), `${where}: entry ${key} = ${v} is missing`);
          }
        assert.ok(pf.entries.size >= significant);
        assert.equal(pf.entries.size, full.info().nnzStored, where);
        assert.equal(pf.header.nnzFull, full.info().nnzFull, where);
        // Cage storage: the rows of the cage vertices (first index < V_e), the same values up to
        // round-off (the full tensor also keeps round-off residues of exact zeros).
        const cageSize = c.level === 0 ? c.base().positions.length / 3 : mr.depths().filter((d) => d <= c.level).length;
        assert.equal(pc.header.rows, cageSize, where);
        assert.equal(pc.entries.size, cage.info().nnzStored, where);
        for (const [key, v] of pc.entries) {
          assert.ok(Number(key.split(',')[0]) < cageSize, `${where}: cage entry ${key}`);
          assert.ok(Math.abs(v - (direct.get(key) ?? 0)) <= tol, `${where}: cage entry ${key}: ${v} vs ${direct.get(key)}`);
        }
        for (const [key, v] of pf.entries)
          if (Number(key.split(',')[0]) < cageSize && Math.abs(v) > tol) assert.ok(pc.entries.has(key), `${where}: cage lacks ${key}`);
        full.delete();
        cage.delete();
        mr.delete();
      }
  });

  test('onProgress: fractions up to 1; returning false cancels and the instance keeps working', () => {
    const mr = mrvol.subdivide(icosahedron(), { levels: 2 });
    const fractions = [];
    const theta = mr.computeTheta({ level: 0, onProgress: (f) => { fractions.push(f); } });
    assert.ok(fractions.length >= 2);
    for (let i = 1; i < fractions.length; ++i) assert.ok(fractions[i] >= fractions[i - 1]);
    assert.ok(fractions[0] >= 0 && fractions.at(-1) === 1);
    throwsMrvol(() => mr.computeTheta({ level: 0, onProgress: () => false }), 'cancelled');
    let calls = 0;
    throwsMrvol(() => mr.computeTheta({ level: 0, onProgress: () => ++calls < 3 }), 'cancelled');
    assert.equal(calls, 3);
    assert.ok(relErr(mr.thetaVolume(theta), mr.info().volume) < 1e-10);
    theta.delete();
    mr.delete();
  });

  test('errors: unknown storage, bad level, deleted theta', () => {
    const mr = mrvol.subdivide(icosahedron(), { levels: 1 });
    throwsMrvol(() => mr.computeTheta({ storage: 'dense' }), "unknown tensor storage 'dense' (expected cage or full)");
    throwsMrvol(() => mr.computeTheta({ level: 2 }), 'level 2 is out of range: this mesh has levels 0..1');
    throwsMrvol(() => mr.computeTheta({ scheme: 'cubic' }), "unknown scheme 'cubic' (expected loop, butterfly or linear)");
    const theta = mr.computeTheta();
    throwsMrvol(() => mr.thetaVolume({}), 'thetaVolume expects a Theta');
    theta.delete();
    theta.delete();
    for (const fn of [() => theta.info(), () => theta.bytes(), () => mr.thetaVolume(theta)]) throwsMrvol(fn, 'this Theta has been deleted');
    mr.delete();
  });
});

// ---- theta files ---------------------------------------------------------------------------------

describe('theta files', () => {
  let mr, theta, bytes;
  before(() => {
    mr = mrvol.subdivide(icosahedron(), { levels: 2 });
    theta = mr.computeTheta({ level: 1 });
    bytes = theta.bytes();
  });
  after(() => {
    theta.delete();
    mr.delete();
  });

  test('bytes() -> readTheta: same info, same volume, same bytes; the header as documented', () => {
    for (const [what, t] of [['cage', theta], ['full', mr.computeTheta({ level: 0, scheme: 'butterfly', storage: 'full' })],
      ['weights', mr.computeTheta({ level: 2, alpha: 0.5, beta: -0.125 })]]) {
      const b = t.bytes();
      assert.ok(b instanceof Uint8Array);
      assert.notEqual(b.buffer, t.bytes().buffer, 'a fresh copy per call');
      const back = mrvol.readTheta(b);
      assert.deepEqual(back.info(), t.info(), what);
      assert.equal(back.precomputeMs, null);
      const i = t.info(), opts = { level: i.level, scheme: i.scheme, alpha: i.alpha, beta: i.beta };
      assert.equal(mr.thetaVolume(back, opts), mr.thetaVolume(t, opts), what);
      assert.equal(Buffer.compare(back.bytes(), b), 0, `${what}: writing it again gives the same bytes`);
      const h = parseTheta(b, { headerOnly: true }).header;
      assert.equal(h.magic, 'MRVOLTHT');
      assert.equal(h.version, 1);
      assert.equal(h.headerBytes, 96);
      assert.equal(h.fingerprint, i.fingerprint);
      assert.equal(h.level, i.level);
      assert.equal(h.levels, i.levels);
      assert.equal(h.vertices, i.vertices);
      assert.equal(h.entries, i.nnzStored);
      if (what === 'weights') assert.equal(parseTheta(b).end, b.length);
      back.delete();
      if (t !== theta) t.delete();
    }
  });

  test('truncated files are refused', () => {
    throwsMrvol(() => mrvol.readTheta(bytes.subarray(0, bytes.length - 1)),
      `theta file is truncated: expected ${bytes.length} bytes, found ${bytes.length - 1}`);
    throwsMrvol(() => mrvol.readTheta(bytes.subarray(0, bytes.length >> 1)),
      `theta file is truncated: expected ${bytes.length} bytes, found ${bytes.length >> 1}`);
    throwsMrvol(() => mrvol.readTheta(bytes.subarray(0, 50)), 'theta file is truncated: 50 bytes');
    throwsMrvol(() => mrvol.readTheta(bytes.subarray(0, 10)), 'theta file is truncated: 10 bytes');
    throwsMrvol(() => mrvol.readTheta(new Uint8Array(0)), 'not a theta file (the first bytes are not the mrvol theta magic)');
    const longer = new Uint8Array(bytes.length + 1);
    longer.set(bytes);
    throwsMrvol(() => mrvol.readTheta(longer), `theta file is corrupt: expected ${bytes.length} bytes, found ${bytes.length + 1}`);
  });

  test('a flipped byte anywhere after the header fields is caught by the checksum', () => {
    const r = rng(99);
    const offsets = [96, 100, 1000, bytes.length - 9, bytes.length - 8, bytes.length - 1, 32, 48, 56];
    for (let i = 0; i < 12; ++i) offsets.push(96 + Math.floor(r() * (bytes.length - 96)));
    for (const offset of offsets)
      for (const mask of [1, 0x80]) {
        const damaged = bytes.slice();
        damaged[offset] ^= mask;
        throwsMrvol(() => mrvol.readTheta(damaged), 'theta file checksum does not match: the file is damaged');
      }
  });

  test('wrong magic, future and invalid versions', () => {
    const notTheta = bytes.slice();
    notTheta[0] = 'N'.charCodeAt(0);
    throwsMrvol(() => mrvol.readTheta(notTheta), 'not a theta file (the first bytes are not the mrvol theta magic)');
    throwsMrvol(() => mrvol.readTheta(new TextEncoder().encode('v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n')),
      'not a theta file (the first bytes are not the mrvol theta magic)');
    // Version 99: the checksum no longer matches either, but the version is checked first, which
    // is the useful message.
    const future = bytes.slice();
    new DataView(future.buffer).setUint32(8, 99, true);
    throwsMrvol(() => mrvol.readTheta(future), 'theta file format version 99 is newer than this mrvol reads (1); recompute it or update mrvol');
    const next = bytes.slice();
    new DataView(next.buffer).setUint32(8, 2, true);
    throwsMrvol(() => mrvol.readTheta(next), /^theta file format version 2 is newer than this mrvol reads \(1\)/);
    const zero = bytes.slice();
    new DataView(zero.buffer).setUint32(8, 0, true);
    throwsMrvol(() => mrvol.readTheta(zero), 'theta file has an invalid format version 0');
    // Putting version 1 back gives the original file.
    new DataView(future.buffer).setUint32(8, 1, true);
    assert.deepEqual(future, bytes);
    mrvol.readTheta(future).delete();
  });

  test('header fields out of range are refused before the arrays are read', () => {
    const patch = (offset, value, size = 1) => {
      const b = bytes.slice();
      const dv = new DataView(b.buffer);
      if (size === 1) dv.setUint8(offset, value);
      else dv.setUint32(offset, value, true);
      return b;
    };
    throwsMrvol(() => mrvol.readTheta(patch(12, 95, 4)), 'theta file header is corrupt (header size)');
    throwsMrvol(() => mrvol.readTheta(patch(16, 7)), 'theta file header is corrupt (scheme 7)');
    throwsMrvol(() => mrvol.readTheta(patch(17, 2)), 'theta file header is corrupt (storage mode 2)');
    throwsMrvol(() => mrvol.readTheta(patch(24, 3, 4)), 'theta file header is corrupt (levels)');
    throwsMrvol(() => mrvol.readTheta(patch(18, 3)), 'theta file header is corrupt (counts)');
  });

  test('a file for another mesh, scheme, level or Loop weights is refused', () => {
    const t = mrvol.readTheta(bytes);
    assert.ok(relErr(mr.thetaVolume(t, { level: 1 }), mr.info().volume) < 1e-10);
    throwsMrvol(() => mr.thetaVolume(t, { level: 0 }), 'theta file is for level 1, not level 0');
    throwsMrvol(() => mr.thetaVolume(t, { level: 2 }), 'theta file is for level 1, not level 2');
    throwsMrvol(() => mr.thetaVolume(t, { level: 1, scheme: 'butterfly' }), 'theta file was computed for the loop scheme, not butterfly');
    throwsMrvol(() => mr.thetaVolume(t, { level: 1, scheme: 'linear' }), 'theta file was computed for the loop scheme, not linear');
    throwsMrvol(() => mr.thetaVolume(t, { level: 1, alpha: 0, beta: 0 }),
      'theta file was computed with Loop weights alpha = -1.709430, beta = 0.429540, not the ones asked for');
    const otherMessage = 'theta file does not match this mesh: it was computed for another connectivity (162 vertices, 2 levels)';
    const fewer = mrvol.subdivide(icosahedron(), { levels: 1 });
    throwsMrvol(() => fewer.thetaVolume(t, { level: 1 }), otherMessage);
    fewer.delete();
    const octa = mrvol.subdivide(octahedron(), { levels: 2 });
    throwsMrvol(() => octa.thetaVolume(t, { level: 1 }), otherMessage);
    octa.delete();
    // The same mesh with its vertices in another order: same counts, other connectivity.
    const shuffled = mrvol.openMesh(shuffleMesh(mr.toMesh(), 5).mesh);
    assert.equal(shuffled.levels, 2);
    assert.notEqual(shuffled.fingerprint(), mr.fingerprint());
    throwsMrvol(() => shuffled.thetaVolume(t, { level: 1 }), otherMessage);
    shuffled.delete();
    t.delete();
  });

  test('theta depends on connectivity only: the subdivided icosahedron\'s theta serves the spiky ball', () => {
    const ico3 = mrvol.subdivide(icosahedron(), { levels: 3 });
    const spiky = mrvol.openMesh(loadModel('spiky-ball'));
    assert.equal(ico3.fingerprint(), spiky.fingerprint());
    const t = mrvol.readTheta(ico3.computeTheta({ level: 2 }).bytes());
    assert.ok(relErr(spiky.thetaVolume(t, { level: 2 }), spiky.info().volume) < 1e-10);
    assert.ok(relErr(ico3.thetaVolume(t, { level: 2 }), ico3.info().volume) < 1e-10);
    assert.ok(relErr(spiky.info().volume, ico3.info().volume) > 0.01);
    t.delete();
    ico3.delete();
    spiky.delete();
  });

  test('readTheta wants a Uint8Array', () => {
    throwsMrvol(() => mrvol.readTheta(Array.from(bytes.subarray(0, 200))), 'readTheta expects a Uint8Array');
    throwsMrvol(() => mrvol.readTheta(bytes.buffer), 'readTheta expects a Uint8Array');
    throwsMrvol(() => mrvol.readTheta(undefined), 'readTheta expects a Uint8Array');
    // A Node Buffer is a Uint8Array.
    mrvol.readTheta(Buffer.from(bytes)).delete();
  });
});

// ---- CLI: volume and theta -----------------------------------------------------------------------

describe('CLI volume and theta', () => {
  const VOLUME_KEYS = ['bytes', 'level', 'nnzFull', 'nnzStored', 'precomputeMs', 'scheme', 'source', 'storage', 'surface', 'thetaVolume', 'volume'];
  let ico2;  // the icosahedron subdivided twice (Loop)

  before(() => {
    const mr = mrvol.subdivide(icosahedron(), { levels: 2 });
    writeFileSync(file('ico2.obj'), mrvol.writeObj(mr.toMesh()));
    ico2 = { volume: mr.info().volume, fingerprint: mr.fingerprint() };
    mr.delete();
  });

  test('volume --json: exactly the documented fields; computed theta matches the API', () => {
    const r = json(mrvolCli('volume', model('spiky-ball'), '--json'));
    assert.deepEqual(Object.keys(r).sort(), VOLUME_KEYS);
    const mr = mrvol.openMesh(loadModel('spiky-ball'));
    const theta = mr.computeTheta({ level: 0 });
    assert.equal(r.volume, mr.info().volume);
    assert.ok(relErr(r.thetaVolume, r.volume) < 1e-10);
    assert.equal(r.thetaVolume, mr.thetaVolume(theta, { level: 0 }));
    assert.equal(r.scheme, 'loop');
    assert.equal(r.level, 0);
    assert.equal(r.storage, 'cage');
    assert.equal(r.nnzFull, null);
    assert.equal(r.nnzStored, theta.info().nnzStored);
    assert.equal(r.bytes, theta.info().bytes);
    assert.ok(typeof r.precomputeMs === 'number' && r.precomputeMs >= 0);
    assert.equal(r.source, 'computed');
    theta.delete();
    mr.delete();
  });

  test('volume --scheme --level --storage full', () => {
    const r = json(mrvolCli('volume', file('ico2.obj'), '--scheme', 'butterfly', '--level', '1', '--storage', 'full', '--json'));
    assert.deepEqual(Object.keys(r).sort(), VOLUME_KEYS);
    assert.equal(r.scheme, 'butterfly');
    assert.equal(r.level, 1);
    assert.equal(r.storage, 'full');
    const mr = mrvol.openMesh(mrvol.readObj(readFileSync(file('ico2.obj'), 'utf8')));
    const full = mr.computeTheta({ level: 1, scheme: 'butterfly', storage: 'full' });
    assert.deepEqual([r.nnzFull, r.nnzStored, r.bytes], [full.info().nnzFull, full.info().nnzStored, full.info().bytes]);
    assert.equal(r.nnzFull, 6 * r.nnzStored);
    full.delete();
    mr.delete();
    assert.ok(relErr(r.thetaVolume, ico2.volume) < 1e-10);
    const text = mrvolCli('volume', file('ico2.obj'), '--level', '2');
    assert.equal(text.status, 0, text.stderr);
    assert.match(text.stdout, /^theta +loop scheme, level 2, cage storage \(computed\)$/m);
  });

  test('theta -o F.theta writes the file; volume --theta F.theta uses it', () => {
    for (const [scheme, level] of [['loop', 1], ['linear', 2]]) {
      const out = file(`ico2-${scheme}-${level}.theta`);
      const r = json(mrvolCli('theta', file('ico2.obj'), '--scheme', scheme, '--level', String(level), '-o', out, '--json'));
      assert.deepEqual(Object.keys(r).sort(), [...VOLUME_KEYS, 'fileBytes', 'output'].sort());
      assert.equal(r.output, out);
      assert.equal(r.fileBytes, statSync(out).size);
      assert.equal(r.source, 'computed');
      const t = mrvol.readTheta(readFileSync(out));
      const info = t.info();
      assert.equal(info.scheme, scheme);
      assert.equal(info.level, level);
      assert.equal(info.fingerprint, ico2.fingerprint);
      assert.equal(info.nnzStored, r.nnzStored);
      t.delete();
      const v = json(mrvolCli('volume', file('ico2.obj'), '--theta', out, '--scheme', scheme, '--level', String(level), '--json'));
      assert.deepEqual(Object.keys(v).sort(), VOLUME_KEYS);
      assert.equal(v.source, 'file');
      assert.equal(v.precomputeMs, null);
      assert.equal(v.thetaVolume, r.thetaVolume);
      assert.equal(v.nnzStored, r.nnzStored);
      assert.equal(v.storage, 'cage');
    }
  });

  test('damaged or mismatched theta files: exit 1, one line naming the theta file', () => {
    const good = file('ico2-loop-1.theta');
    if (!existsSync(good)) json(mrvolCli('theta', file('ico2.obj'), '--level', '1', '-o', good, '--json'));
    const b = readFileSync(good);
    const write = (name, bytes) => (writeFileSync(file(name), bytes), file(name));
    const flipped = Buffer.from(b);
    flipped[1234] ^= 4;
    const future = Buffer.from(b);
    future.writeUInt32LE(99, 8);
    const magic = Buffer.from(b);
    magic[3] = 0;
    const cases = [
      [write('truncated.theta', b.subarray(0, b.length - 100)), ['--level', '1'], /truncated\.theta: theta file is truncated/],
      [write('flipped.theta', flipped), ['--level', '1'], /flipped\.theta: theta file checksum does not match/],
      [write('future.theta', future), ['--level', '1'], /future\.theta: theta file format version 99 is newer/],
      [write('magic.theta', magic), ['--level', '1'], /magic\.theta: not a theta file/],
      [good, ['--level', '0'], /ico2-loop-1\.theta: theta file is for level 1, not level 0/],
      [good, ['--level', '1', '--scheme', 'butterfly'], /ico2-loop-1\.theta: theta file was computed for the loop scheme, not butterfly/],
      [file('missing.theta'), ['--level', '1'], /missing\.theta: no such file/],
    ];
    for (const [theta, options, pattern] of cases) failsWith(mrvolCli('volume', file('ico2.obj'), '--theta', theta, ...options), pattern);
    // Another mesh: the spiky ball's connectivity is not ico2's.
    failsWith(mrvolCli('volume', model('spiky-ball'), '--theta', good, '--level', '1'),
      /ico2-loop-1\.theta: theta file does not match this mesh/);
  });

  test('usage errors: exit 2', () => {
    usageError(mrvolCli('theta', file('ico2.obj')), /^mrvol: error: -o FILE\.theta is required/);
    usageError(mrvolCli('volume', file('ico2.obj'), '--storage', 'dense'), /--storage must be cage or full/);
    usageError(mrvolCli('volume', file('ico2.obj'), '--theta', file('x.theta'), '--storage', 'full'),
      /--storage applies when computing, not with --theta/);
    failsWith(mrvolCli('volume', file('ico2.obj'), '--level', '3'), /level 3 is out of range/);
  });
});
