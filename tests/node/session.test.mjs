// The editing session (lib/three/session.mjs) on the real WASM module: open a sample, drag steps
// keep the volume, undo/redo give the cage back, free sets and parts, level and scheme changes keep
// the shape and the reference volume, refused edits roll back; and MultiresMesh.approximation.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { createMrvol } from '../../lib/node.mjs';
import { chooseGradientPath, DEFAULT_SCHEME } from '../../lib/api.mjs';
import { EditingSession, FREE_SET_MODES } from '../../lib/three/session.mjs';
import { MODELS } from './helpers.mjs';

let mrvol;
before(async () => {
  mrvol = await createMrvol();
});

const sample = (name) => mrvol.readObj(readFileSync(join(MODELS, `${name}.obj`), 'utf8'));
const relative = (a, b) => Math.abs(a - b) / Math.abs(b);

/** A session on the spiky ball at level 0, with the events it emitted. */
function openBall(options = {}) {
  const session = new EditingSession(mrvol, { tolerance: 1e-8, ...options });
  const events = [];
  for (const type of ['model', 'editor', 'step', 'change', 'theta', 'error', 'dragend'])
    session.addEventListener(type, (e) => events.push({ type, detail: e.detail }));
  session.open(sample('spiky-ball'), { name: 'spiky-ball' });
  return { session, events };
}

/** The direction out of the ball at handle h (its position from the cage's centroid). */
function outward(session, h, length) {
  const cage = session.cagePositions();
  const n = cage.length / 3;
  const centroid = [0, 1, 2].map((k) => cage.reduce((s, v, i) => (i % 3 === k ? s + v : s), 0) / n);
  const d = [0, 1, 2].map((k) => cage[3 * h + k] - centroid[k]);
  const norm = Math.hypot(...d);
  return d.map((x) => x / norm * length);
}

test('opening a sample emits model, editor and change; the cage is the level-0 base', () => {
  const { session, events } = openBall();
  const types = events.map((e) => e.type);
  assert.ok(types.includes('model') && types.includes('editor') && types.includes('change'));
  assert.equal(session.model.name, 'spiky-ball');
  assert.equal(session.cageSize, session.model.info.baseVertices);
  assert.equal(session.cageVertices.length, session.cageSize);
  const edges = session.cageEdges();
  // A closed triangle mesh: E = 3F/2 with F = 2V - 4 (genus 0).
  assert.equal(edges.length / 2, 3 * (2 * session.cageSize - 4) / 2);
  assert.ok(edges.every((i) => i < session.cageSize));
  assert.equal(session.editor.path(), 'matrix-free', 'the app runs matrix-free until theta arrives');
  session.dispose();
  assert.equal(session.editor, null);
});

test('drag steps keep the volume; the step event carries the report', () => {
  const { session, events } = openBall();
  const reference = session.referenceVolume();
  session.beginDrag([0]);
  const start = session.cagePositions();
  const direction = outward(session, 0, 1);
  for (let step = 1; step <= 5; step++) {
    const report = session.dragBy(direction.map((x) => x * 0.08 * step));
    assert.ok(report.converged, `step ${step} converged`);
    assert.ok(relative(session.volume(), reference) < 1e-7, `step ${step}: volume ${session.volume()} vs ${reference}`);
  }
  session.endDrag();
  // The dragged handle is where the drag put it.
  const moved = session.cagePositions();
  for (let k = 0; k < 3; k++) assert.ok(Math.abs(moved[k] - (start[k] + direction[k] * 0.4)) < 1e-12);
  const steps = events.filter((e) => e.type === 'step');
  assert.equal(steps.length, 5);
  assert.ok(steps.every((e) => e.detail.report.volumeReference === reference && e.detail.ms >= 0));
  assert.deepEqual(session.history.size, { undo: 1, redo: 0 });
  session.dispose();
});

test('without preservation the volume changes; with it, other handles move', () => {
  const { session } = openBall({ preserve: false });
  const reference = session.referenceVolume();
  const before = session.cagePositions();
  session.moveHandles([0], outward(session, 0, 0.5));
  assert.ok(relative(session.volume(), reference) > 1e-3);
  const after = session.cagePositions();
  assert.ok(after.slice(3).every((v, i) => v === before[3 + i]), 'only handle 0 moved');
  session.preserve = true;
  session.moveHandles([1], outward(session, 1, 0.3));
  assert.ok(relative(session.volume(), reference) < 1e-7);
  session.dispose();
});

test('undo and redo give the cage and the volume back', () => {
  const { session } = openBall();
  const original = session.cagePositions();
  session.moveHandles([2], outward(session, 2, 0.4));
  const edited = session.cagePositions();
  session.moveHandles([5, 6], [0.1, -0.2, 0.05]);
  const twice = session.cagePositions();
  assert.deepEqual(session.history.size, { undo: 2, redo: 0 });
  assert.ok(session.undo());
  assert.deepEqual(session.cagePositions(), edited);
  assert.ok(session.undo());
  assert.deepEqual(session.cagePositions(), original);
  assert.equal(session.undo(), false);
  assert.ok(session.redo());
  assert.deepEqual(session.cagePositions(), edited);
  assert.ok(session.redo());
  assert.deepEqual(session.cagePositions(), twice);
  assert.ok(relative(session.volume(), session.referenceVolume()) < 1e-7);
  session.dispose();
});

test('a full history lets its oldest step go and says so (history-full), once per step let go', () => {
  const { session } = openBall({ historyLimit: 3 });
  const full = [];
  session.addEventListener('history-full', (e) => full.push(e.detail));
  const cages = [session.cagePositions()];
  for (let k = 0; k < 3; k++) {
    session.moveHandles([k], [0.01, 0, 0]);
    cages.push(session.cagePositions());
  }
  assert.deepEqual(full, [], 'three steps fit');
  session.moveHandles([3], [0.01, 0, 0]);
  assert.deepEqual(full, [{ limit: 3 }]);
  assert.deepEqual(session.history.size, { undo: 3, redo: 0 });
  for (let k = 0; k < 3; k++) assert.ok(session.undo());
  assert.equal(session.undo(), false);
  assert.deepEqual(session.cagePositions(), cages[1], 'undo stops at the oldest step kept');
  session.dispose();
});

test('volumeNow: during a drag the step\'s own volume (no pass over the mesh), the mesh\'s after it', () => {
  const { session } = openBall();
  const before = session.volumeNow();
  assert.equal(before, session.volume());
  session.beginDrag([4]);
  assert.equal(session.volumeNow(), before, 'no step yet: the volume as it was');
  const report = session.dragBy(outward(session, 4, 0.3));
  assert.equal(session.volumeNow(), report.volumeResult);
  assert.ok(relative(session.volumeNow(), session.volume()) < 1e-12, 'the step\'s volume is the mesh\'s to round-off');
  session.endDrag();
  assert.equal(session.volumeNow(), session.volume(), 'after the drag: the mesh\'s own');
  // without preservation the step's volume is the moved shape's
  session.setPreserve(false);
  session.beginDrag([4]);
  session.dragBy([0.2, 0, 0]);
  assert.ok(relative(session.volumeNow(), session.volume()) < 1e-12);
  session.endDrag();
  session.dispose();
});

test('the centre of mass is asked of the core once per shape: not again for a free set, a keep toggle or preservation', () => {
  const { session } = openBall();
  let asked = 0;
  const count = (editor) => {
    const centroid = editor.centroid.bind(editor);
    editor.centroid = () => (asked++, centroid());
  };
  count(session.editor);
  const first = session.centroid();
  assert.deepEqual(session.centroid(), first);
  session.setFreeSet({ mode: 'all' });
  session.setPreserve(false);
  session.setPreserve(true);
  assert.deepEqual(session.centroid(), first);
  assert.equal(asked, 1);
  session.moveHandles([3], [0.2, 0, 0]);
  const moved = session.centroid();
  assert.equal(asked, 2, 'a new shape: asked again');
  assert.notDeepEqual(moved, first);
  session.undo();
  const near = (a, b) => a.every((x, k) => Math.abs(x - b[k]) < 1e-12);
  assert.ok(near(session.centroid(), first), 'undo: the first shape\'s centre (to round-off)');
  assert.equal(asked, 3);
  const again = session.centroid();
  session.setKeepCentroid(true); // (the editor keeps it now: the same shape, the same centre)
  assert.deepEqual(session.centroid(), again);
  assert.equal(asked, 3);
  session.dispose();
});

test('gradientChoice: theta^e\'s estimate asked once per model, level, scheme and surface', () => {
  const { session } = openBall({ path: 'auto' });
  let asked = 0;
  const { mr } = session.model;
  const estimate = mr.estimateTheta.bind(mr);
  mr.estimateTheta = (options) => (asked++, estimate(options));
  session.setLevel(2);  // a fine cage: the estimate decides between the tensor and matrix-free
  const first = session.gradientChoice();
  assert.deepEqual(session.gradientChoice(), first);
  assert.ok(first.estimate, 'an estimate was made');
  assert.equal(asked, 1, 'once for the editor and the later asks');
  session.setLevel(1);
  session.gradientChoice();
  const afterOne = asked;
  session.setLevel(2);
  assert.deepEqual(session.gradientChoice(), first);
  assert.equal(asked, afterOne, 'level 2 again: kept');
  session.dispose();
});

test('a cancelled drag puts the cage back and records nothing', () => {
  const { session } = openBall();
  const before = session.cagePositions();
  session.beginDrag([3]);
  session.dragBy([0.3, 0.2, 0.1]);
  session.cancelDrag();
  assert.deepEqual(session.cagePositions(), before);
  assert.deepEqual(session.history.size, { undo: 0, redo: 0 });
  session.dispose();
});

test('free sets: all cage moves the held handle too; a painted region confines the correction', () => {
  assert.deepEqual([...FREE_SET_MODES], ['minus-held', 'all', 'painted', 'parts']);
  const { session } = openBall();
  const reference = session.referenceVolume();
  const v = session.cageVertices;
  // Painted: only handles 1..4 may move for the correction.
  session.setFreeSet({ mode: 'painted', painted: [v[1], v[2], v[3], v[4], 99999, -1] });
  assert.deepEqual(session.freeSet.painted, [v[1], v[2], v[3], v[4]], 'vertices outside the cage are dropped');
  const before = session.cagePositions();
  session.moveHandles([0], outward(session, 0, 0.3));
  assert.ok(relative(session.volume(), reference) < 1e-7);
  const after = session.cagePositions();
  for (let h = 5; h < session.cageSize; h++)
    for (let k = 0; k < 3; k++) assert.equal(after[3 * h + k], before[3 * h + k], `handle ${h} is not painted: it stays`);
  assert.ok([1, 2, 3, 4].some((h) => after[3 * h] !== before[3 * h]), 'painted handles took the correction');
  // All cage: the held handle is corrected too (it does not stay exactly where it was put).
  session.setFreeSet({ mode: 'all' });
  const target = session.cagePositions();
  const delta = outward(session, 7, 0.3);
  session.moveHandles([7], delta);
  const moved = session.cagePositions();
  assert.ok([0, 1, 2].some((k) => Math.abs(moved[21 + k] - (target[21 + k] + delta[k])) > 1e-9));
  assert.ok(relative(session.volume(), reference) < 1e-7);
  // An unknown mode falls back to minus-held.
  session.setFreeSet({ mode: 'nonsense' });
  assert.equal(session.freeSet.mode, 'minus-held');
  session.dispose();
});

test('parts keep their own volumes; a vertex is in one part at most', () => {
  const { session } = openBall();
  const v = session.cageVertices;
  const parts = [[v[0], v[1], v[2], v[3]], [v[3], v[8], v[9], v[10]]];
  session.setFreeSet({ mode: 'parts', parts });
  assert.deepEqual(session.freeSet.parts[1], [v[8], v[9], v[10]], 'v[3] stays in part 1');
  assert.deepEqual(session.parts, [1, 2]);
  const references = session.partReferences;
  assert.equal(references.length, 2);
  session.moveHandles([0], outward(session, 0, 0.3));
  const volumes = session.partVolumes();
  volumes.forEach((volume, p) => {
    if (references[p] !== 0) assert.ok(relative(volume, references[p]) < 1e-5, `part ${p + 1}: ${volume} vs ${references[p]}`);
  });
  session.setFreeSet({ mode: 'minus-held' });
  assert.deepEqual(session.parts, []);
  assert.equal(session.partVolumes(), null);
  session.dispose();
});

test('level and scheme changes keep the shape and the reference volume; the free set follows the cage', () => {
  const { session, events } = openBall();
  const reference = session.referenceVolume();
  session.moveHandles([0], outward(session, 0, 0.4));
  const shape = session.positions();
  session.setFreeSet({ mode: 'painted', painted: [session.cageVertices[1]] });
  events.length = 0;
  session.setLevel(1);
  assert.ok(events.some((e) => e.type === 'editor' && e.detail.level === 1));
  assert.ok(session.cageSize > session.model.info.baseVertices);
  assert.equal(session.referenceVolume(), reference);
  assert.ok(session.positions().every((x, i) => Math.abs(x - shape[i]) < 1e-12), 'the shape is the same at another level');
  assert.deepEqual(session.history.size, { undo: 2, redo: 0 }, 'the drag and the level change are kept');
  assert.equal(session.freeSet.painted.length, 1, 'a level-0 vertex is in the level-1 cage too');
  session.setScheme('butterfly');
  const after = session.positions();
  assert.ok(after.every((x, i) => Math.abs(x - shape[i]) < 1e-9), 'the scheme changes the cage, not the shape');
  session.setFreeSet({ mode: 'minus-held' });
  session.moveHandles([session.cageSize - 1], [0.05, 0.05, 0]);
  assert.ok(relative(session.volume(), reference) < 1e-7);
  assert.throws(() => session.setLevel(99), /level 99 is outside 0\.\.\d/);
  assert.throws(() => session.setLevel(0.5), /level must be an integer/);
  session.dispose();
});

test('setCage drives the whole cage: two sessions on one mesh, one free and one preserving', () => {
  const mr = mrvol.openMesh(sample('spiky-ball'));
  const free = new EditingSession(mrvol, { preserve: false });
  const kept = new EditingSession(mrvol, { preserve: true, tolerance: 1e-8 });
  free.open(mr, { name: 'free' });
  kept.open(mr, { name: 'kept' });
  const reference = kept.referenceVolume();
  // Squash the cage along y by 30 %, the lowest handle held.
  const target = kept.cagePositions();
  for (let i = 1; i < target.length; i += 3) target[i] *= 0.7;
  const held = new Uint8Array(kept.cageSize);
  held[0] = 1;
  free.setCage(target, new Uint8Array(free.cageSize));
  const report = kept.setCage(target, held);
  assert.ok(report.converged);
  assert.ok(free.volume() < 0.8 * reference, `squashed without preservation: ${free.volume()} vs ${reference}`);
  assert.ok(relative(kept.volume(), reference) < 1e-7);
  assert.deepEqual(free.cagePositions(), target, 'without preservation the cage is the target');
  free.dispose();
  kept.dispose();
  assert.ok(mr.info().vertices > 0, 'the mesh stays the caller\'s');
  mr.delete();
});

test('a refused edit emits error, cancels the drag and restores the cage', () => {
  const { session, events } = openBall();
  const before = session.cagePositions();
  session.beginDrag([0]);
  assert.equal(session.dragBy([NaN, 0, 0]), null);
  const error = events.find((e) => e.type === 'error');
  assert.ok(error, 'an error event');
  assert.match(error.detail.message, /^This edit is not possible: /);
  assert.equal(session.dragging, false);
  assert.deepEqual(session.cagePositions(), before);
  assert.throws(() => session.beginDrag([session.cageSize]), /is not a cage index/);
  session.dispose();
});

test('theta: computed and used here, kept per level, dropped with the model', () => {
  const { session, events } = openBall();
  assert.equal(session.gradientChoice().path, 'tensor', 'theta^0 of the spiky ball fits');
  assert.ok(session.computeTheta().ok);
  assert.equal(session.editor.path(), 'tensor');
  assert.equal(session.thetaSource, 'computed');
  assert.ok(events.some((e) => e.type === 'theta' && e.detail.path === 'tensor'));
  const reference = session.referenceVolume();
  session.moveHandles([0], outward(session, 0, 0.3));
  assert.equal(session.lastReport.path, 'tensor');
  assert.ok(relative(session.volume(), reference) < 1e-7);
  session.setLevel(1);
  assert.equal(session.editor.path(), 'matrix-free');
  session.setLevel(0);
  assert.equal(session.editor.path(), 'tensor', 'the level-0 tensor was kept');
  // Another mesh's tensor is refused.
  const other = mrvol.openMesh(sample('icosahedron'));
  const foreign = other.computeTheta({ level: 0 });
  const used = session.useTheta(foreign);
  assert.equal(used.ok, false);
  assert.match(used.reason, /./);
  foreign.delete();
  other.delete();
  session.forgetTheta();
  assert.equal(session.editor.path(), 'matrix-free');
  session.dispose();
});

test('a restored shape opens with its reference volume; a bad mesh leaves the current model', () => {
  const { session } = openBall();
  session.moveHandles([0], outward(session, 0, 0.4));
  const restore = { positions: session.positions(), reference: session.referenceVolume() * 1.01 };
  const again = new EditingSession(mrvol);
  again.open(sample('spiky-ball'), { name: 'again', restore });
  assert.ok(again.positions().every((x, i) => Math.abs(x - restore.positions[i]) < 1e-12), 'the stored shape');
  assert.equal(again.referenceVolume(), restore.reference);
  const bad = { positions: new Float64Array(9), faces: Uint32Array.of(0, 1, 5) };
  assert.throws(() => again.open(bad), mrvol.MrvolError);
  assert.equal(again.model.name, 'again');
  again.dispose();
  session.dispose();
});

test('an opened MultiresMesh stays the caller\'s unless owned', () => {
  const mr = mrvol.openMesh(sample('icosahedron'));
  const session = new EditingSession(mrvol);
  session.open(mr, { name: 'ico' });
  session.dispose();
  assert.ok(mr.info().vertices > 0, 'still open');
  session.open(mr, { name: 'ico', own: true });
  session.dispose();
  assert.throws(() => mr.info(), /deleted/);
});

test('chooseGradientPath: one rule for the CLI and the editor', () => {
  const mr = mrvol.openMesh(sample('spiky-ball'));
  assert.deepEqual(chooseGradientPath(mr, { level: 0 }), { path: 'polynomial', estimate: null }, 'no theta needed');
  const background = chooseGradientPath(mr, { level: 0, thetaInBackground: true });
  assert.equal(background.path, background.estimate.fits ? 'tensor' : 'polynomial');
  assert.equal(background.path, 'tensor', 'theta^0 of the spiky ball fits');
  assert.deepEqual(chooseGradientPath(mr, { level: 0, path: 'polynomial' }), { path: 'polynomial', estimate: null });
  assert.deepEqual(chooseGradientPath(mr, { level: 0, path: 'matrix-free' }), { path: 'matrix-free', estimate: null });
  assert.deepEqual(chooseGradientPath(mr, { level: 0, path: 'tensor' }), { path: 'tensor', estimate: null });
  assert.equal(chooseGradientPath(mr, { level: 0, detailLevels: [1] }).path, 'matrix-free', 'free details need the matrix-free path');
  assert.equal(chooseGradientPath(mr, { level: 0, detailLevels: [1], thetaInBackground: true }).path, 'matrix-free');
  assert.throws(() => chooseGradientPath(mr, { path: 'fast' }), /gradient path must be auto, polynomial, tensor or matrix-free, got 'fast'/);
  assert.deepEqual({ ...DEFAULT_SCHEME }, { scheme: 'loop', alpha: -1.70943, beta: 0.42954 });
  mr.delete();
});

test('approximation: level n gives the shape back, level 0 the smooth base, through the API', () => {
  const mr = mrvol.openMesh(sample('spiky-ball'));
  const x = mr.positions();
  const n = mr.levels;
  const full = mr.approximation(x, { level: n });
  assert.ok(full.every((v, i) => Math.abs(v - x[i]) < 1e-9));
  // Level l: the analysis at l and its synthesis without details = the approximation of level l.
  const depths = mr.depths();
  for (let l = 0; l < n; l++) {
    const approx = mr.approximation(x, { level: l });
    const c = mr.analyze(x, { level: l });
    const a = mr.analyze(approx, { level: l });
    for (let i = 0; i < depths.length; i++)
      for (let k = 0; k < 3; k++) {
        const expected = depths[i] > l ? 0 : c[3 * i + k];
        assert.ok(Math.abs(a[3 * i + k] - expected) < 1e-9, `level ${l}, vertex ${i}`);
      }
  }
  // The spiky ball's spikes are details: its level-0 approximation encloses less.
  const mesh = { positions: mr.approximation(x, { level: 0 }), faces: mr.faces() };
  assert.notEqual(mrvol.volume(mesh), mrvol.volume({ positions: x, faces: mr.faces() }));
  assert.throws(() => mr.approximation(x, { level: n + 1 }), /level \d+ is outside 0\.\.\d+/);
  assert.throws(() => mr.approximation([1, 2, 3], { level: 0 }), /positions must be a Float64Array/);
  mr.delete();
});

after(() => {});

test('undo and redo cross level and scheme changes, reference resets and preservation toggles', () => {
  const { session } = openBall();
  const original = session.cagePositions();
  const reference = session.referenceVolume();
  session.moveHandles([0], outward(session, 0, 0.3));
  const level0Edit = session.positions();
  session.setLevel(1);
  session.moveHandles([session.cageSize - 1], [0.05, 0.02, 0]);
  const level1Edit = session.positions();
  session.setScheme('butterfly');
  session.setPreserve(false);
  session.moveHandles([1], outward(session, 1, 0.4));
  const grown = session.volume();
  assert.ok(relative(grown, reference) > 1e-3);
  session.setReferenceVolume();
  assert.equal(session.referenceVolume(), grown);
  assert.deepEqual(session.history.size, { undo: 7, redo: 0 });

  assert.ok(session.undo()); // the reference
  assert.equal(session.referenceVolume(), reference);
  assert.ok(session.undo()); // the unpreserved drag
  assert.ok(relative(session.volume(), reference) < 1e-7);
  assert.ok(session.undo()); // preservation back on
  assert.equal(session.preserve, true);
  assert.ok(session.undo()); // back to loop
  assert.equal(session.scheme, 'loop');
  assert.ok(session.positions().every((x, i) => Math.abs(x - level1Edit[i]) < 1e-9));
  assert.ok(session.undo()); // the level-1 drag
  assert.ok(session.positions().every((x, i) => Math.abs(x - level0Edit[i]) < 1e-9));
  assert.ok(session.undo()); // back to level 0
  assert.equal(session.level, 0);
  assert.ok(session.undo()); // the level-0 drag
  assert.ok(session.cagePositions().every((x, i) => Math.abs(x - original[i]) < 1e-9));
  assert.equal(session.undo(), false);
  for (let i = 0; i < 7; i++) assert.ok(session.redo());
  assert.equal(session.level, 1);
  assert.equal(session.scheme, 'butterfly');
  assert.equal(session.preserve, false);
  assert.equal(session.referenceVolume(), grown);
  session.dispose();
});

test('restoring the reference volume after preservation was off: one undoable step', () => {
  const { session } = openBall({ preserve: false });
  const reference = session.referenceVolume();
  session.moveHandles([0], outward(session, 0, 0.5));
  const changed = session.cagePositions();
  assert.ok(relative(session.volume(), reference) > 1e-3);
  session.setPreserve(true);
  const report = session.restoreReferenceVolume();
  assert.ok(report.converged);
  assert.ok(relative(session.volume(), reference) < 1e-7);
  assert.ok(session.undo());
  assert.deepEqual(session.cagePositions(), changed);
  session.dispose();
});

test("path 'auto' (the web app's): the cage polynomial wherever the rule takes it or theta^e, no tensor wanted", () => {
  const { session } = openBall({ path: 'auto' });
  assert.equal(session.editor.path(), 'polynomial', 'spiky ball, e = 0 (3 levels of details)');
  assert.equal(session.gradientChoice().path, 'polynomial');
  // e = 1: the rule's coarse path is matrix-free; theta^1 fits, so the polynomial stands in for it
  const background = chooseGradientPath(session.model.mr, { level: 1, thetaInBackground: true, ...DEFAULT_SCHEME });
  assert.equal(background.path, 'tensor');
  session.setLevel(1);
  assert.equal(session.editor.path(), 'polynomial');
  const h = 0;
  const report = session.moveHandles([h], outward(session, h, 0.2));
  assert.equal(report.path, 'polynomial');
  assert.ok(relative(session.volume(), session.referenceVolume()) <= 1e-8);
  session.forgetTheta();
  assert.equal(session.editor.path(), 'polynomial', 'forgetting theta keeps the polynomial');
  // the default stays matrix-free until a tensor is handed over (the component, the demos)
  const plain = openBall().session;
  assert.equal(plain.editor.path(), 'matrix-free');
  plain.dispose();
  session.dispose();
});

test('keep balance and the surface are undo steps; undoing a surface change brings its reference volume back', () => {
  const { session } = openBall();
  const meshReference = session.referenceVolume();
  session.setKeepCentroid(true);
  const kept = session.referenceCentroid();
  session.moveHandles([0], outward(session, 0, 0.3));
  const centroid = session.centroid();
  assert.ok(Math.hypot(...centroid.map((c, k) => c - kept[k])) < 1e-7, 'the centre of mass stayed');
  session.setKeepCentroid(true); // no change, no step
  session.setSurface('limit');
  assert.equal(session.keepCentroid, false, 'the limit surface does not keep the centre of mass');
  const limitReference = session.referenceVolume();
  assert.notEqual(limitReference, meshReference);
  session.moveHandles([2], outward(session, 2, 0.2));
  assert.ok(relative(session.volume(), limitReference) < 1e-6);
  assert.deepEqual(session.history.size, { undo: 4, redo: 0 });

  assert.ok(session.undo()); // the limit drag
  assert.ok(session.undo()); // back to the mesh surface
  assert.equal(session.surface, 'mesh');
  assert.equal(session.keepCentroid, true);
  assert.equal(session.editor.surface(), 'mesh');
  assert.equal(session.referenceVolume(), meshReference);
  assert.ok(session.undo()); // the drag with balance kept
  assert.ok(session.undo()); // balance off again
  assert.equal(session.keepCentroid, false);
  assert.equal(session.undo(), false);

  for (let i = 0; i < 4; i++) assert.ok(session.redo());
  assert.equal(session.surface, 'limit');
  assert.equal(session.keepCentroid, false);
  assert.equal(session.referenceVolume(), limitReference);
  assert.ok(relative(session.volume(), limitReference) < 1e-6);
  session.dispose();
});

test('a stored limit surface on a mesh without a limit volume opens on the mesh surface', () => {
  // an open mesh (semi-regular still): the spiky ball with its first face dropped
  const mesh = sample('spiky-ball');
  const open = { positions: mesh.positions, faces: mesh.faces.slice(3) };
  const session = new EditingSession(mrvol);
  session.surface = 'limit';
  session.keepCentroid = true;
  session.open(open, { name: 'open' });
  assert.throws(() => session.setSurface('limit'), /closed mesh/);
  assert.equal(session.surface, 'mesh');
  assert.equal(session.keepCentroid, false);
  assert.equal(session.editor.surface(), 'mesh');
  assert.deepEqual(session.history.size, { undo: 0, redo: 0 }, 'a refused surface change is no step');
  session.dispose();
});
