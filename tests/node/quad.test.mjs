// Quad meshes and the catmull-clark scheme through the real WASM module and the command line:
// subdivision against a textbook Catmull-Clark written here, detection in any vertex order, round
// trip, theta^e of the bilinear volume, volume-preserving edits, quad OBJ in and out, errors.
import { test, describe, before } from 'node:test';
import assert from 'node:assert/strict';
import { writeFileSync, readFileSync } from 'node:fs';
import { createMrvol } from '../../lib/node.mjs';
import { remeshQuads } from '../../lib/remesh-quad.mjs';
import { selfIntersections } from '../../lib/self-intersection.mjs';
import { CORPUS, makeCorpus } from '../../scripts/corpus.mjs';
import { tempFolder, runCliSync, json, failsWith, usageError, rng, relErr, maxDiff, throwsMrvol, model } from './helpers.mjs';

let mrvol;
const file = tempFolder('mrvol-quad-test-');
const cli = (...args) => runCliSync(args, { timeout: 60000 });

// ---- meshes and a textbook Catmull-Clark ---------------------------------------------------------

// The cube [-1, 1]^3 (valence 3 everywhere).
function cube() {
  const p = [];
  for (let i = 0; i < 8; ++i) p.push(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1);
  return { positions: Float64Array.from(p), faces: [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]] };
}
// A pyramid over a pentagon: apex valence 5, a pentagon face.
function pyramid5() {
  const p = [];
  for (let i = 0; i < 5; ++i) p.push(Math.cos(2 * Math.PI * i / 5), Math.sin(2 * Math.PI * i / 5), 0);
  p.push(0.1, -0.05, 1.4);
  const faces = [[4, 3, 2, 1, 0]];
  for (let i = 0; i < 5; ++i) faces.push([i, (i + 1) % 5, 5]);
  return { positions: Float64Array.from(p), faces };
}

// One Catmull-Clark step (Catmull and Clark 1978; closed polygon meshes): face point = centroid,
// edge point = mean of ends and face points, vertex (Q + 2R + (n - 3) S) / n. Numbering as mrvol's
// contract: old vertices, face points in face order, edge points in order of first use; child
// quads per face (v_i, e_i, f, e_{i-1}).
function textbookCC({ positions, faces }) {
  const V = positions.length / 3, P = (v) => [0, 1, 2].map((k) => positions[3 * v + k]);
  const add = (a, b, w) => { for (let k = 0; k < 3; ++k) a[k] += w * b[k]; };
  const fp = faces.map((f) => { const c = [0, 0, 0]; for (const v of f) add(c, P(v), 1 / f.length); return c; });
  const key = (a, b) => (a < b ? `${a},${b}` : `${b},${a}`);
  const edges = new Map(); const order = [];
  faces.forEach((f, fi) => f.forEach((a, i) => {
    const b = f[(i + 1) % f.length], k = key(a, b);
    if (!edges.has(k)) { edges.set(k, { a, b, faces: [] }); order.push(k); }
    edges.get(k).faces.push(fi);
  }));
  const out = [];
  for (let v = 0; v < V; ++v) out.push(null);
  const facePoint = fp.map((c) => (out.push(c), out.length - 1));
  const edgePoint = new Map();
  for (const k of order) {
    const e = edges.get(k), c = [0, 0, 0];
    add(c, P(e.a), 0.25); add(c, P(e.b), 0.25); add(c, fp[e.faces[0]], 0.25); add(c, fp[e.faces[1]], 0.25);
    edgePoint.set(k, out.length); out.push(c);
  }
  for (let v = 0; v < V; ++v) {
    const around = faces.map((f, i) => (f.includes(v) ? i : -1)).filter((i) => i >= 0);
    const nbrs = order.map((k) => edges.get(k)).filter((e) => e.a === v || e.b === v).map((e) => (e.a === v ? e.b : e.a));
    const n = nbrs.length, Q = [0, 0, 0], R = [0, 0, 0], c = [0, 0, 0];
    for (const f of around) add(Q, fp[f], 1 / around.length);
    for (const w of nbrs) { add(R, P(v), 0.5 / n); add(R, P(w), 0.5 / n); }
    add(c, Q, 1 / n); add(c, R, 2 / n); add(c, P(v), (n - 3) / n);
    out[v] = c;
  }
  const quads = [];
  faces.forEach((f, fi) => f.forEach((v, i) => {
    const next = f[(i + 1) % f.length], prev = f[(i + f.length - 1) % f.length];
    quads.push([v, edgePoint.get(key(v, next)), facePoint[fi], edgePoint.get(key(prev, v))]);
  }));
  return { positions: Float64Array.from(out.flat()), faces: quads };
}
const toQuadMesh = (m) => ({ positions: m.positions, quads: Uint32Array.from(m.faces.flat()) });

// A subdivided quad mesh with details, its vertices shuffled.
function noisyShuffled(built, seed) {
  const r = rng(seed), m = built.toMesh(), nv = m.positions.length / 3;
  const perm = Array.from({ length: nv }, (_, i) => i);
  for (let i = nv - 1; i > 0; --i) { const j = Math.floor(r() * (i + 1)); [perm[i], perm[j]] = [perm[j], perm[i]]; }
  const positions = new Float64Array(m.positions.length);
  for (let v = 0; v < nv; ++v) for (let k = 0; k < 3; ++k) positions[3 * perm[v] + k] = m.positions[3 * v + k] + 0.02 * (r() - 0.5);
  return { positions, quads: m.quads.map((v) => perm[v]) };
}

before(async () => {
  mrvol = await createMrvol();
});

// ---- the API ---------------------------------------------------------------------------------------

describe('catmull-clark API', () => {
  test('one split of the cube puts the corner (1, 1, 1) at (5/9, 5/9, 5/9)', () => {
    const mr = mrvol.subdivide(toQuadMesh(cube()), { levels: 1, scheme: 'catmull-clark' });
    const p = mr.positions();
    for (let k = 0; k < 3; ++k) assert.ok(Math.abs(p[21 + k] - 5 / 9) < 1e-15, `${p[21 + k]}`);
    assert.equal(mr.lowestLevel, 1);
    mr.delete();
  });

  test('subdivision equals a textbook Catmull-Clark (valences 3, 4, 5)', () => {
    const base = textbookCC(pyramid5());  // quads: apex 5, pentagon centre 5, triangle centres 3
    const expected = textbookCC(textbookCC(base));
    const mr = mrvol.subdivide(toQuadMesh(base), { levels: 2, scheme: 'catmull-clark' });
    assert.ok(maxDiff(mr.positions(), expected.positions) < 1e-14);
    assert.deepEqual(Array.from(mr.quads()), expected.faces.flat());
    mr.delete();
  });

  test('detection in any vertex order, round trip, theta and edits keep the bilinear volume', () => {
    const built = mrvol.subdivide(toQuadMesh(textbookCC(pyramid5())), { levels: 2 });
    const mesh = noisyShuffled(built, 7);
    built.delete();
    const mr = mrvol.openMesh(mesh);
    assert.equal(mr.levels, 2);
    assert.equal(mr.scheme, 'catmull-clark');
    const volume = mrvol.quadVolume(mesh);
    assert.equal(mr.info().volume, volume);
    for (const level of [0, 1, 2]) assert.ok(mr.roundtripError({ level }) < 1e-12);
    const theta = mr.computeTheta({ level: 0 });
    assert.equal(theta.info().scheme, 'catmull-clark');
    assert.ok(relErr(mr.thetaVolume(theta), volume) < 1e-12);
    for (const path of ['matrix-free', 'tensor']) {
      const editor = mr.createEditor({ level: 0, ...(path === 'tensor' ? { theta } : {}) });
      assert.equal(editor.path(), path);
      const cage = editor.cagePositions(), cageVertices = editor.cageVertices();
      let top = 0;
      for (let c = 1; c < editor.cageSize; ++c) if (cage[3 * c + 2] > cage[3 * top + 2]) top = c;
      const apex = cageVertices[top];
      const report = editor.moveVertices([{ vertex: apex, offset: [0, 0, 0.6] }]);
      assert.ok(report.converged);
      assert.ok(Math.abs(report.volumeTarget - volume) / volume > 1e-2, 'the move changes the volume');
      assert.ok(relErr(mrvol.quadVolume({ positions: editor.positions(), quads: mesh.quads }), volume) < 1e-5);
      // A new reference: the next correction reaches it.
      editor.setReferenceVolume(1.05 * volume);
      assert.ok(editor.correct().converged);
      assert.ok(relErr(mrvol.quadVolume({ positions: editor.positions(), quads: mesh.quads }), 1.05 * volume) < 1e-5);
      editor.delete();
    }
    theta.delete();
    mr.delete();
  });

  test('the lifting steps, applied here one by one, are the synthesis of a level', () => {
    // The cube's level-1 mesh as base: its valence-3 vertices take the layer steps N_31, P_31.
    const built = mrvol.subdivide(toQuadMesh(cube()), { levels: 3 });
    const mr = mrvol.openMesh(noisyShuffled(built, 3));
    built.delete();
    const c = mr.analyze(undefined, { level: 1 });
    const steps = mr.liftingSteps({ level: 2 });
    assert.deepEqual(steps.map((s) => s.name), ['P_f', 'P_e', 'N_31', 'P_31', 'N_v', 'P_v']);
    const x = c.slice();
    for (const st of steps) {
      st.targets.forEach((t, r) => {
        for (let k = 0; k < 3; ++k) {
          if (st.scaling) { x[3 * t + k] *= st.weights[r]; continue; }
          let acc = 0;
          for (let e = st.offsets[r]; e < st.offsets[r + 1]; ++e) acc += st.weights[e] * x[3 * st.sources[e] + k];
          x[3 * t + k] += acc;
        }
      });
    }
    assert.ok(maxDiff(x, mr.analyze(undefined, { level: 2 })) < 1e-12);
    throwsMrvol(() => mr.liftingSteps({ level: 0 }), /level 0 has no lifting steps/);
    mr.delete();
  });

  test('quad OBJ in and out; errors name what is wrong', () => {
    const m = toQuadMesh(cube());
    const text = mrvol.writeObjQuads(m);
    assert.match(text, /^f 1 3 4 2$/m);
    const back = mrvol.readObjQuads(text);
    assert.deepEqual(back.quads, m.quads);
    assert.deepEqual(back.positions, m.positions);
    throwsMrvol(() => mrvol.readObjQuads(text + 'f 1 2 3\n'), /^line 15: a face with 3 corners/);
    throwsMrvol(() => mrvol.openMesh({ positions: m.positions, faces: new Uint32Array(3) }, { scheme: 'catmull-clark' }),
      /mesh.quads must be a Uint32Array/);
    throwsMrvol(() => mrvol.openMesh({ positions: m.positions, quads: Uint32Array.from([0, 1, 2, 2]) }), /quad 0 is degenerate/);
    const cubeMesh = mrvol.subdivide(m, { levels: 1 });
    throwsMrvol(() => cubeMesh.createEditor({ level: 0 }), /cannot reach level 0/);
    cubeMesh.delete();
  });
});

// ---- the command line ----------------------------------------------------------------------------

describe('mrvol --scheme catmull-clark', () => {
  test('subdivide writes quads; info, roundtrip, volume, theta and edit on them', () => {
    writeFileSync(file('pyr.obj'), mrvol.writeObjQuads(toQuadMesh(textbookCC(pyramid5()))));
    const s = json(cli('subdivide', file('pyr.obj'), '--scheme', 'catmull-clark', '--levels', '2', '-o', file('pyr2.obj'), '--json'));
    assert.equal(s.scheme, 'catmull-clark');
    const written = readFileSync(file('pyr2.obj'), 'utf8');
    const faceLines = written.split('\n').filter((l) => l.startsWith('f '));
    assert.equal(faceLines.length, s.faces);
    assert.ok(faceLines.every((l) => l.split(/\s+/).length === 5), 'every face is a quad');
    const info = json(cli('info', file('pyr2.obj'), '--scheme', 'catmull-clark', '--json'));
    assert.equal(info.levels, 2);
    // Without --scheme the file's quads are split into triangles, which have no 1-to-4 splits: the
    // report names the quads' levels and the flag (it sent the user to the remesher).
    const asTriangles = json(cli('info', file('pyr2.obj'), '--json'));
    assert.equal(asTriangles.levels, 0);
    assert.equal(asTriangles.catmullClarkLevels, 2);
    assert.match(cli('info', file('pyr2.obj')).stdout,
                 /semi-regular {3}no \(as triangles; its quads have 2 Catmull-Clark levels: mrvol info .*pyr2\.obj --scheme catmull-clark\)/);
    assert.equal(info.baseVertices, textbookCC(pyramid5()).positions.length / 3);
    assert.equal(info.volume, mrvol.quadVolume(mrvol.readObjQuads(written)));
    const rt = json(cli('roundtrip', file('pyr2.obj'), '--scheme', 'catmull-clark', '--json'));
    assert.ok(rt.maxError < 1e-12);
    const vol = json(cli('volume', file('pyr2.obj'), '--scheme', 'catmull-clark', '--level', '1', '--json'));
    assert.ok(relErr(vol.thetaVolume, vol.volume) < 1e-12);
    const th = json(cli('theta', file('pyr2.obj'), '--scheme', 'catmull-clark', '-o', file('pyr2.theta'), '--json'));
    assert.equal(th.output, file('pyr2.theta'));
    const ed = json(cli('edit', file('pyr2.obj'), '--scheme', 'catmull-clark', '--move', '5:0,0,0.5',
      '--theta', file('pyr2.theta'), '-o', file('pyr2-edit.obj'), '--json'));
    assert.equal(ed.path, 'tensor');
    const edited = mrvol.readObjQuads(readFileSync(file('pyr2-edit.obj')));
    assert.ok(relErr(mrvol.quadVolume(edited), info.volume) < 1e-5);
    assert.ok(relErr(ed.volumeTarget, info.volume) > 1e-2);
    const mf = json(cli('edit', file('pyr2.obj'), '--scheme', 'catmull-clark', '--move', '5:0,0,0.5', '-o', file('pyr2-mf.obj'), '--json'));
    assert.equal(mf.path, 'matrix-free');
    assert.ok(relErr(mrvol.quadVolume(mrvol.readObjQuads(readFileSync(file('pyr2-mf.obj')))), info.volume) < 1e-5);
  });

  test('a subdivided cube: level 1 is the lowest; errors', () => {
    writeFileSync(file('cube.obj'), mrvol.writeObjQuads(toQuadMesh(cube())));
    json(cli('subdivide', file('cube.obj'), '--scheme', 'catmull-clark', '--levels', '2', '-o', file('cube2.obj'), '--json'));
    const info = json(cli('info', file('cube2.obj'), '--scheme', 'catmull-clark', '--json'));
    assert.equal(info.levels, 2);
    assert.equal(info.lowestLevel, 1);
    assert.ok(json(cli('roundtrip', file('cube2.obj'), '--scheme', 'catmull-clark', '--json')).maxError < 1e-12);
    failsWith(cli('roundtrip', file('cube2.obj'), '--scheme', 'catmull-clark', '--level', '0', '--json'), /cube/);
    writeFileSync(file('tri.obj'), 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n');
    failsWith(cli('info', file('tri.obj'), '--scheme', 'catmull-clark'), /line 5: a face with 3 corners: the catmull-clark scheme needs a mesh made of quads only \(mrvol remesh .*tri\.obj --scheme catmull-clark -o OUT\.obj makes one of it\)/);
    usageError(cli('remesh', file('tri.obj'), '--scheme', 'catmull-clark', '-o', file('x.stl')), /\.obj/);
    usageError(cli('subdivide', file('cube.obj'), '--scheme', 'catmull-clark', '--levels', '1', '-o', file('x.stl')), /\.obj/);
  });
});

// Each quad as two triangles (its 0-2 diagonal).
const quadTriangles = (quads) => {
  const t = new Uint32Array(quads.length * 3 / 2);
  for (let q = 0, i = 0; q < quads.length; q += 4) t.set([quads[q], quads[q + 1], quads[q + 2], quads[q], quads[q + 2], quads[q + 3]], (i++) * 6);
  return t;
};

describe('remeshQuads (lib/remesh-quad.mjs) on CAD parts', () => {
  // The quads placed through the triangle fit's parametrisation: a pipe's inner and outer walls stay
  // apart (moving CC positions to the nearest surface crossed them: -14% of the volume), a prism's and a
  // box grid's edges stay sharp (exact: their volume to round-off).
  before(() => makeCorpus({ big: false, names: ['pipe', 'prism-48gon-caps', 'cube-grid'] }));
  for (const [name, volumeTolerance] of [['pipe', 0.01], ['prism-48gon-caps', 1e-9], ['cube-grid', 1e-9]]) {
    test(name, async () => {
      const c = CORPUS.find((x) => x.name === name);
      const input = mrvol.readMesh(readFileSync(c.file), { name: c.file });
      const r = await remeshQuads(mrvol, { positions: input.positions, faces: input.faces }, { levels: 2 });
      assert.ok(Math.abs(r.volumeChange) < volumeTolerance, `volume change ${r.volumeChange}`);
      assert.ok(r.distanceToInput < 1e-6, `distance ${r.distanceToInput}`);
      const opened = mrvol.openQuadMesh(r.mesh);
      const info = opened.info();
      // as the editor has it (analysed and synthesised: round-off on the flat faces), still not crossing itself
      const editor = opened.createEditor({ level: 0 });
      const edited = editor.positions();
      editor.delete?.();
      opened.delete();
      assert.equal(info.levels, 2);
      assert.equal(info.closed, true);
      for (const positions of [r.mesh.positions, edited])
        assert.equal(selfIntersections(positions, quadTriangles(r.mesh.quads)).withinPieces, 0);
    });
  }
});

describe('mrvol remesh --scheme catmull-clark', () => {
  test('a closed triangle mesh becomes a semi-regular quad mesh near it', () => {
    // two levels: the default cage of the triangle remesher is coarse (50-500 handles)
    const r = json(cli('remesh', model('blob'), '--scheme', 'catmull-clark', '--levels', '2', '-o', file('blob-quads.obj'), '--json'));
    assert.equal(r.levels, 2);
    assert.ok(Math.abs(r.volumeChange) < 0.01, `volume change ${r.volumeChange}`);
    assert.ok(r.distanceToInput < 0.01, `distance ${r.distanceToInput}`);
    const written = mrvol.readObjQuads(readFileSync(file('blob-quads.obj')));
    assert.equal(written.quads.length / 4, r.faces);
    const info = json(cli('info', file('blob-quads.obj'), '--scheme', 'catmull-clark', '--json'));
    assert.equal(info.levels, 2);
    assert.equal(info.baseVertices, r.baseVertices);
    assert.equal(info.closed, true);
    assert.equal(info.genus, 0);
    const input = mrvol.readObj(readFileSync(model('blob')));
    assert.ok(relErr(info.volume, mrvol.volume(input)) < 0.01);
  });
});
