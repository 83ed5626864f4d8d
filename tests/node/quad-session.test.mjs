// Quad models in the editing session (lib/three/session.mjs) and the app's quad opening, on the
// real WASM module and the quad sample (public/models/quad-critter.obj): the surface drawn as the
// quads' triangles, the cage as the quads' sides, drags keep the bilinear-patch volume, undo/redo,
// level changes, what quads refuse; the JS lifting steps (lib/quad-steps.mjs) against the core's
// analysis; a quad OBJ opens as quads only when it is semi-regular (web/models.js).
import { test, before } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { createMrvol } from '../../lib/node.mjs';
import { EditingSession, QUAD_SCHEME } from '../../lib/three/session.mjs';
import { quadEdgesOf, trianglesOfQuads } from '../../lib/three/edges.mjs';
import { openQuadObj, firstFaceCorners } from '../../web/models.js';
import { MODELS, rng } from './helpers.mjs';

let mrvol;
before(async () => {
  mrvol = await createMrvol();
});

const QUAD_SAMPLE = 'quad-critter';
const text = (name) => readFileSync(join(MODELS, `${name}.obj`), 'utf8');
const relative = (a, b) => Math.abs(a - b) / Math.abs(b);
const maxDiff = (a, b) => a.reduce((m, x, i) => Math.max(m, Math.abs(x - b[i])), 0);

function openCritter(options = {}) {
  const session = new EditingSession(mrvol, { tolerance: 1e-12, ...options });
  const errors = [];
  session.addEventListener('error', (e) => errors.push(e.detail.message));
  session.open(mrvol.readObjQuads(text(QUAD_SAMPLE)), { name: QUAD_SAMPLE });
  return { session, errors };
}

/** The sides of the level-e quads in cage indices, as a set of 'lo,hi' keys. */
function sidesOf(session) {
  const quads = session.model.mr.levelQuads(session.level);
  const sides = new Set();
  for (let q = 0; q < quads.length; q += 4)
    for (let k = 0; k < 4; k++) {
      const a = session.cageIndex.get(quads[q + k]), b = session.cageIndex.get(quads[q + (k + 1) % 4]);
      sides.add(`${Math.min(a, b)},${Math.max(a, b)}`);
    }
  return { sides, quadCount: quads.length / 4 };
}

test('a quad model: catmull-clark, its quads drawn as triangles, a cage of quad sides', () => {
  const { session } = openCritter();
  const { model } = session;
  assert.ok(session.quad);
  assert.equal(session.scheme, QUAD_SCHEME);
  assert.equal(model.info.levels, 3);
  // every triangle drawn lies in its quad: triangles 2q and 2q + 1 use the corners of quad q only
  const quads = model.quads;
  assert.equal(model.faces.length, 6 * quads.length / 4);
  for (let t = 0; t < model.faces.length / 3; t++) {
    const corners = new Set(quads.subarray(4 * (t >> 1), 4 * (t >> 1) + 4));
    for (let k = 0; k < 3; k++) assert.ok(corners.has(model.faces[3 * t + k]));
  }
  for (const level of [0, 1]) {
    session.setLevel(level);
    const edges = session.cageEdges();
    const { sides, quadCount } = sidesOf(session);
    // closed quad mesh: each side in two quads, so 2F sides, every cage edge one of them (no diagonal)
    assert.equal(edges.length / 2, 2 * quadCount);
    assert.equal(sides.size, edges.length / 2);
    for (let e = 0; e < edges.length; e += 2) assert.ok(sides.has(`${edges[e]},${edges[e + 1]}`), `edge ${edges[e]}-${edges[e + 1]} is not a quad side`);
    const faces = session.cageFaces();
    assert.equal(faces.corners, 4);
    assert.deepEqual(quadEdgesOf(faces.faces), edges);
  }
  session.dispose();
});

test('drags keep the bilinear-patch volume; undo and redo give the shape back', () => {
  const { session, errors } = openCritter();
  const { quads } = session.model;
  const reference = session.referenceVolume();
  const bilinear = () => mrvol.quadVolume({ positions: session.positions(), quads });
  assert.ok(relative(reference, bilinear()) < 1e-12);
  const before = session.positions();
  const r = rng(7);
  for (let drag = 0; drag < 3; drag++) {
    const h = Math.floor(r() * session.cageSize);
    const start = session.cagePositions();
    const delta = [0.3 * (r() - 0.5), 0.3 * (r() - 0.5), 0.25];
    assert.ok(session.moveHandles([h], delta), errors.join('; '));
    const cage = session.cagePositions();
    for (let k = 0; k < 3; k++) assert.ok(Math.abs(cage[3 * h + k] - start[3 * h + k] - delta[k]) < 1e-12, 'the handle is where it was dragged');
    // the volume kept is the quads' bilinear patches' (computed here independently of the editor)
    assert.ok(relative(bilinear(), reference) < 1e-9, `bilinear volume off by ${relative(bilinear(), reference)}`);
    assert.ok(relative(session.volume(), reference) < 1e-9);
  }
  const moved = session.positions();
  assert.ok(maxDiff(moved, before) > 0.1);
  // the triangles drawn enclose another volume than the patches: the editor keeps the patches'
  const triangles = mrvol.volume({ positions: moved, faces: trianglesOfQuads(quads) });
  assert.ok(relative(triangles, reference) > 1e-9);
  while (session.undo());
  assert.ok(maxDiff(session.positions(), before) < 1e-12);
  while (session.redo());
  assert.ok(maxDiff(session.positions(), moved) < 1e-12);
  assert.deepEqual(errors, []);
  session.dispose();
});

test('level changes rebuild the quad cage, keep shape and reference, and undo', () => {
  const { session } = openCritter();
  const reference = session.referenceVolume();
  session.moveHandles([3], [0, 0, 0.3]);
  const shape = session.positions();
  session.setLevel(1);
  const depths = session.model.depths;
  assert.equal(session.cageSize, depths.filter((d) => d <= 1).length);
  assert.ok(maxDiff(session.positions(), shape) < 1e-12);
  assert.equal(session.referenceVolume(), reference);
  session.moveHandles([0], [0.1, 0, 0]);
  assert.ok(relative(mrvol.quadVolume({ positions: session.positions(), quads: session.model.quads }), reference) < 1e-9);
  session.undo(); // the level-1 drag
  session.undo(); // the level change
  assert.equal(session.level, 0);
  assert.ok(maxDiff(session.positions(), shape) < 1e-12);
  // the level-l approximation of the shape: the core's analysis with the finer details zeroed
  const approx = session.approximation(1);
  assert.equal(approx.length, shape.length);
  assert.ok(maxDiff(session.approximation(3), shape) < 1e-12);
  assert.ok(maxDiff(approx, shape) > 1e-3);
  session.dispose();
});

test('what a quad model refuses, with a message; a triangle model after it goes back to loop', () => {
  const { session } = openCritter();
  assert.throws(() => session.setScheme('loop'), /quad mesh uses the catmull-clark scheme/);
  assert.throws(() => session.setSurface('limit'), /bilinear-patch volume/);
  assert.equal(session.surface, 'mesh');
  assert.ok(session.freeSetModes.includes('minus-held') && session.freeSetModes.includes('all'));
  // The bilinear patches' centre of mass is kept with the volume through a drag.
  assert.equal(session.canKeepCentroid, true);
  const before = Array.from(session.centroid());
  const volume = session.editor.volume();
  session.setKeepCentroid(true);
  assert.ok(session.moveHandles([1], [0, 0.2, 0]));
  const after = Array.from(session.centroid());
  assert.ok(Math.hypot(...after.map((x, k) => x - before[k])) < 1e-5, `${before} -> ${after}`);
  assert.ok(Math.abs(session.editor.volume() - volume) < 1e-6 * Math.abs(volume));
  session.setKeepCentroid(false);
  session.setFreeSet({ mode: 'all' });
  assert.equal(session.freeSet.mode, 'all');
  assert.ok(session.moveHandles([1], [0, 0.2, 0]));
  assert.equal(session.gradientChoice().path, 'matrix-free');
  session.open(mrvol.readObj(text('spiky-ball')), { name: 'spiky-ball' });
  assert.equal(session.quad, false);
  assert.equal(session.scheme, 'loop');
  assert.throws(() => session.setScheme(QUAD_SCHEME), /for quad meshes/);
  session.dispose();
});

test('a quad mesh on a cube\'s base opens at level 1, the lowest its analysis reaches; level 0 refused, the editor kept', () => {
  const cubeBase = { positions: Float64Array.from([0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1]),
                    quads: Uint32Array.from([0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7]) };
  const cube = mrvol.subdivide(cubeBase, { levels: 3, scheme: 'catmull-clark' });
  const cubeMesh = cube.toMesh();
  cube.delete();
  const session = new EditingSession(mrvol, { tolerance: 1e-12 });
  session.open(mrvol.readObj(text('spiky-ball')), { name: 'spiky-ball' });
  assert.equal(session.level, 0);
  const opened = session.open(cubeMesh, { name: 'cube-l3' });
  assert.equal(opened.mr.lowestLevel, 1);
  assert.equal(session.lowestLevel, 1);
  assert.equal(session.level, 1, 'level 0 is below what the analysis reaches: level 1');
  assert.equal(session.cageSize, 26);
  assert.ok(session.moveHandles([0], [0.1, 0, 0]));
  assert.ok(Math.abs(session.editor.volume() - mrvol.quadVolume(cubeMesh)) < 1e-9);
  // level 0 refused by name; the editor and its level stay
  const editor = session.editor;
  assert.throws(() => session.setLevel(0), /level 0 is outside 1\.\.3 \(this mesh's analysis stops at level 1/);
  assert.equal(session.level, 1);
  assert.equal(session.editor, editor);
  session.dispose();
});

test('the JS lifting steps of a quad level: synthesis, analysis, transposition agree with the core', () => {
  const mr = mrvol.openQuadMesh(mrvol.readObjQuads(text(QUAD_SAMPLE)));
  const positions = mr.positions();
  for (const level of [1, 2, 3]) {
    const coarse = mr.analyze(positions, { level: level - 1 }), fine = mr.analyze(positions, { level });
    const steps = mr.liftingSteps({ level });
    assert.ok(maxDiff(mr.synthesizeSteps(coarse, { level }), fine) < 1e-12);
    assert.ok(maxDiff(mr.analyzeSteps(fine, { level }), coarse) < 1e-12);
    // k phases forward then k back: the start again
    const half = Math.floor(steps.length / 2);
    const partway = mr.synthesizeSteps(coarse, { level, steps: half });
    assert.ok(maxDiff(partway, coarse) > 0);
    // the transposed steps are the adjoint: <T y, x> = <y, S x>
    const r = rng(level);
    const x = Float64Array.from(coarse, () => r() - 0.5), y = Float64Array.from(coarse, () => r() - 0.5);
    const Sx = mr.synthesizeSteps(x, { level }), Ty = mr.transposeSteps(y, { level });
    const dot = (a, b) => a.reduce((s, v, i) => s + v * b[i], 0);
    assert.ok(Math.abs(dot(Ty, x) - dot(y, Sx)) < 1e-10 * Math.abs(dot(y, Sx)) + 1e-12);
  }
  assert.throws(() => mr.synthesizeSteps(new Float64Array(3), { level: 1 }), /3 per vertex/);
  mr.delete();
});

test('the app opens a semi-regular quad OBJ as quads, anything else the triangle way', () => {
  const critter = text(QUAD_SAMPLE);
  assert.equal(firstFaceCorners(critter), 4);
  assert.equal(firstFaceCorners(new TextEncoder().encode(critter)), 4);
  const opened = openQuadObj(mrvol, { format: 'obj', text: critter }, mrvol.readObj(critter));
  assert.ok(opened);
  assert.equal(opened.mr.scheme, QUAD_SCHEME);
  assert.equal(opened.info.levels, 3);
  assert.equal(opened.info.baseVertices, 56);
  opened.mr.delete();
  // bytes as a dropped file gives them
  const bytes = new TextEncoder().encode(critter);
  const fromBytes = openQuadObj(mrvol, { format: 'obj', bytes }, mrvol.readMesh(bytes, { name: 'critter.obj' }));
  assert.equal(fromBytes.info.levels, 3);
  fromBytes.mr.delete();
  // a triangle sample is not read as quads
  const ball = text('spiky-ball');
  assert.equal(firstFaceCorners(ball), 3);
  assert.equal(openQuadObj(mrvol, { format: 'obj', text: ball }, mrvol.readObj(ball)), null);
  // a quad torus grid of 9 x 9 (81 quads: no 1-to-4 split, 81 vertices): not semi-regular, the triangle way
  const lines = [];
  for (let i = 0; i < 9; i++)
    for (let j = 0; j < 9; j++) {
      const u = 2 * Math.PI * i / 9, v = 2 * Math.PI * j / 9;
      lines.push(`v ${(2 + Math.cos(v)) * Math.cos(u)} ${(2 + Math.cos(v)) * Math.sin(u)} ${Math.sin(v)}`);
    }
  const id = (i, j) => ((i + 9) % 9) * 9 + ((j + 9) % 9) + 1;
  for (let i = 0; i < 9; i++) for (let j = 0; j < 9; j++) lines.push(`f ${id(i, j)} ${id(i + 1, j)} ${id(i + 1, j + 1)} ${id(i, j + 1)}`);
  const grid = lines.join('\n') + '\n';
  assert.equal(openQuadObj(mrvol, { format: 'obj', text: grid }, mrvol.readObj(grid)), null);
});

test('the quad sample is up to date with scripts/make-quad-models.mjs', async () => {
  const { spawnSync } = await import('node:child_process');
  const r = spawnSync(process.execPath, [join(MODELS, '../../scripts/make-quad-models.mjs'), '--check'], { encoding: 'utf8' });
  assert.equal(r.status, 0, r.stderr.slice(-2000));
  assert.match(r.stderr, /models: quad models up to date/);
});
