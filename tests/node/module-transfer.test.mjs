// A mesh and its editor made in one instance of the module and taken over by another with a copy
// of its memory (lib/api.mjs transferable / adoptTransferred, web/module-transfer.js: the web app's
// file worker makes a big mesh's editor off the page's thread). Both instances warmed up alike;
// the adopted editor is the one made there (no second build: its polynomial came along) and edits
// exactly as an editor made in place; the instance that took the copy keeps working: other meshes
// open and edit in it, the adopted objects delete cleanly.
import { test, describe, before } from 'node:test';
import assert from 'node:assert/strict';
import { createMrvol } from '../../lib/node.mjs';
import { warmUp, buildEditor } from '../../web/module-transfer.js';
import { loadModel, throwsMrvol } from './helpers.mjs';
import { EditingSession } from '../../lib/three/session.mjs';

let maker, taker, plain;
before(async () => {
  [maker, taker, plain] = await Promise.all([createMrvol({ threads: 1 }), createMrvol({ threads: 1 }), createMrvol({ threads: 1 })]);
  warmUp(maker);
  warmUp(taker);
});

// Seeded drags of two handles; the shapes and volumes after each.
function drags(editor) {
  const out = [];
  const cage = editor.cagePositions(), held = new Uint8Array(editor.cageSize);
  held[0] = held[5] = 1;
  for (let i = 0; i < 6; i++) {
    cage[0] += 0.03 * (i + 1);
    cage[16] -= 0.02;
    const report = editor.deformCage(cage, held, { tolerance: 1e-9 });
    out.push({ error: report.relativeError, volume: editor.volume(), positions: editor.positions(), view: Array.from(editor.positionsView().subarray(0, 300)) });
  }
  return out;
}

describe('a mesh and editor taken over by another instance', () => {
  test('the spiky ball subdivided four times (164k vertices) at level 0: the same edits as an editor made in place', () => {
    const spiky = loadModel(maker, 'spiky-ball');
    const fine = maker.subdivide(spiky, { levels: 4 });
    const mesh = fine.toMesh();
    fine.delete();
    const mr = maker.openMesh(mesh);
    const editor = buildEditor(maker, mr, { level: 0, scheme: 'loop' });
    assert.equal(editor.path(), 'polynomial');
    const transfer = maker.transferable(mr, editor, { scheme: 'loop' });
    assert.ok(transfer.memory.byteLength > 64 * 2 ** 20, `a memory bigger than a fresh instance's (${transfer.memory.byteLength} bytes)`);
    const taken = taker.adoptTransferred(structuredClone(transfer));
    const adopted = taken.createEditor({ level: 0, scheme: 'loop', path: 'matrix-free' });
    assert.equal(adopted.path(), 'polynomial', 'the editor made there, its polynomial with it');
    assert.equal(adopted.usePolynomial(), 'polynomial');
    assert.equal(taken.fingerprint(), mr.fingerprint());
    assert.deepEqual(taken.info(), mr.info());
    const fresh = plain.openMesh(mesh);
    const inPlace = buildEditor(plain, fresh, { level: 0, scheme: 'loop' });
    assert.deepEqual(drags(adopted), drags(inPlace));
    // a second createEditor is a new one (the made one is given once)
    const second = taken.createEditor({ level: 1 });
    assert.notEqual(second, adopted);
    assert.equal(second.level, 1);
    taken.delete();
    assert.ok(adopted.deleted, 'the mesh deleted its editors');
    // the instance goes on: another mesh opens and edits
    const bunny = loadModel(taker, 'bunny-remeshed');
    const other = taker.openMesh(bunny);
    const ed = other.createEditor({ level: 1 });
    const moved = drags(ed);
    assert.ok(moved.every((m) => m.error <= 1e-8));
    other.delete();
    for (const m of [mr, fresh]) m.delete();
  });

  test('positions set after the take-over drop the made editor: createEditor makes a new one for them', async () => {
    const [a, b] = await Promise.all([createMrvol({ threads: 1 }), createMrvol({ threads: 1 })]);
    warmUp(a);
    warmUp(b);
    const spiky = loadModel(a, 'spiky-ball');
    const mr = a.openMesh(spiky);
    const transfer = a.transferable(mr, buildEditor(a, mr, { level: 0, scheme: 'loop' }), { scheme: 'loop' });
    const taken = b.adoptTransferred(transfer);
    const moved = spiky.positions.map((x) => 1.5 * x);
    taken.setPositions(moved);
    const editor = taken.createEditor({ level: 0 });
    assert.ok(Math.abs(editor.volume() / mr.info().volume - 1.5 ** 3) < 1e-9, 'the editor of the positions set');
    taken.delete();
    mr.delete();
    throwsMrvol(() => b.adoptTransferred({ memory: new Uint8Array(4) }), /expects what transferable\(\) gave/);
  });

  test('a session swaps in an editor made elsewhere at another level: shape, reference and history kept; undo goes back', async () => {
    const [a, b] = await Promise.all([createMrvol({ threads: 1 }), createMrvol({ threads: 1 })]);
    for (const m of [a, b]) warmUp(m);
    const session = new EditingSession(a, { level: 0, path: 'auto' });
    session.open(loadModel(a, 'spiky-ball'), { name: 'spiky' });
    const reference = session.referenceVolume();
    session.moveHandles([2], [0.2, -0.1, 0.05]);
    const shape = session.positions();
    // what web/editor-worker.js does, here in instance b: the page's mesh from its hierarchy, the shape, the editor
    const { mr } = session.model;
    const other = b.openMeshWithHierarchy({ positions: mr.positions(), faces: mr.faces() }, mr.hierarchyArrays());
    other.setPositions(shape);
    const transfer = b.transferable(other, buildEditor(b, other, { level: 1, scheme: 'loop' }), { scheme: 'loop' });
    const taken = await taker.adoptTransferredInSlices(transfer);
    session.adoptRebuilt(taken, { level: 1, scheme: 'loop' });
    assert.equal(session.level, 1);
    assert.equal(session.model.mr, taken, 'the session owns the mesh handed over');
    assert.equal(session.editor.path(), 'polynomial');
    assert.ok(session.positions().every((x, i) => Math.abs(x - shape[i]) <= 1e-12), 'the shape stays');
    assert.ok(Math.abs(session.referenceVolume() - reference) <= 1e-12 * Math.abs(reference), 'the reference stays');
    assert.deepEqual(session.history.size, { undo: 2, redo: 0 }, 'the drag and the level change');
    assert.equal(session.history.peekUndo().label, 'editor');
    assert.ok(session.undo() && session.level === 0, 'undo goes back to level 0');
    assert.ok(session.positions().every((x, i) => Math.abs(x - shape[i]) <= 1e-12), 'the shape as it was');
    const original = loadModel(a, 'spiky-ball').positions;
    assert.ok(session.undo() && session.positions().every((x, i) => Math.abs(x - original[i]) <= 1e-9), 'and the drag undoes');
    assert.ok(session.redo() && session.redo() && session.level === 1, 'redone');
    // compared with the same change made in place
    const inPlace = new EditingSession(plain, { level: 0, path: 'auto' });
    inPlace.open(loadModel(plain, 'spiky-ball'), { name: 'spiky' });
    inPlace.moveHandles([2], [0.2, -0.1, 0.05]);
    inPlace.setLevel(1);
    const [mine, theirs] = [drags(session.editor), drags(inPlace.editor)];
    for (let i = 0; i < mine.length; i++) {
      assert.ok(Math.abs(mine[i].volume - theirs[i].volume) <= 1e-12 * Math.abs(theirs[i].volume), `volume after drag ${i}`);
      assert.ok(mine[i].positions.every((x, k) => Math.abs(x - theirs[i].positions[k]) <= 1e-9), `shape after drag ${i}`);
    }
    session.dispose();
    inPlace.dispose();
    throwsMrvol(() => new EditingSession(a).adoptRebuilt(taken, { level: 1, scheme: 'loop' }), /no model is open/);
  });

  // The editor worker makes the editor the session's settings call for: the limit surface, the centre of
  // mass kept, the tensor path's matrix-free editor (until theta^e comes); the session takes that one.
  for (const settings of [{ surface: 'limit' }, { keepCentroid: true }, { path: 'matrix-free' }]) {
    test(`a session swaps in an editor made elsewhere with ${JSON.stringify(settings)}: the one made there, edits as in place`, async () => {
      const [a, b] = await Promise.all([createMrvol({ threads: 1 }), createMrvol({ threads: 1 })]);
      for (const m of [a, b]) warmUp(m);
      const open = (mrvol) => {
        const s = new EditingSession(mrvol, { level: 0, path: settings.path ?? 'auto' });
        s.open(loadModel(mrvol, 'spiky-ball'), { name: 'spiky' });
        if (settings.surface) s.setSurface(settings.surface);
        if (settings.keepCentroid) s.setKeepCentroid(true);
        s.moveHandles([2], [0.2, -0.1, 0.05]);
        return s;
      };
      const session = open(a);
      const reference = session.referenceVolume(), shape = session.positions(), steps = session.history.size.undo;
      const { mr } = session.model;
      const other = b.openMeshWithHierarchy({ positions: mr.positions(), faces: mr.faces() }, mr.hierarchyArrays());
      other.setPositions(shape);
      const made = buildEditor(b, other, { level: 1, scheme: 'loop', surface: session.surface, keepCentroid: session.keepCentroid, path: session.path });
      const transfer = b.transferable(other, made, { scheme: 'loop' });
      const taken = await createMrvol({ threads: 1 }).then((c) => (warmUp(c), c.adoptTransferredInSlices(transfer)));
      session.adoptRebuilt(taken, { level: 1, scheme: 'loop' });
      assert.equal(session.editor.madeElsewhere, true, 'the editor made in the other instance, not a second one');
      assert.equal(session.editor.surface(), settings.surface ?? 'mesh');
      assert.equal(session.editor.keepsCentroid(), Boolean(settings.keepCentroid));
      assert.ok(Math.abs(session.referenceVolume() - reference) <= 1e-12 * Math.abs(reference), 'the reference stays');
      assert.deepEqual(session.history.size, { undo: steps + 1, redo: 0 }, 'the level change is one more step');
      const inPlace = open(plain);
      inPlace.setLevel(1);
      assert.equal(inPlace.editor.madeElsewhere, undefined);
      assert.equal(session.editor.path(), inPlace.editor.path(), 'the path the session picks');
      const [mine, theirs] = [drags(session.editor), drags(inPlace.editor)];
      for (let i = 0; i < mine.length; i++) {
        assert.ok(Math.abs(mine[i].volume - theirs[i].volume) <= 1e-12 * Math.abs(theirs[i].volume), `volume after drag ${i}`);
        assert.ok(mine[i].positions.every((x, k) => Math.abs(x - theirs[i].positions[k]) <= 1e-9), `shape after drag ${i}`);
      }
      if (settings.keepCentroid) {
        const [c, r] = [session.centroid(), session.referenceCentroid()];
        assert.ok(Math.hypot(c[0] - r[0], c[1] - r[1], c[2] - r[2]) < 1e-3, 'the centre of mass stays with the adopted editor');
      }
      assert.ok(session.undo() && session.level === 0, 'undo goes back to level 0');
      session.dispose();
      inPlace.dispose();
    });
  }

  test('a surface switch made elsewhere: one surface undo step, the limit volume its reference; undone with the mesh reference', async () => {
    const [a, b] = await Promise.all([createMrvol({ threads: 1 }), createMrvol({ threads: 1 })]);
    for (const m of [a, b]) warmUp(m);
    const session = new EditingSession(a, { level: 0, path: 'auto' });
    session.open(loadModel(a, 'spiky-ball'), { name: 'spiky' });
    session.setKeepCentroid(true);
    session.moveHandles([2], [0.2, -0.1, 0.05]);
    const meshReference = session.referenceVolume(), steps = session.history.size.undo;
    const { mr } = session.model;
    const other = b.openMeshWithHierarchy({ positions: mr.positions(), faces: mr.faces() }, mr.hierarchyArrays());
    other.setPositions(session.positions());
    const shaped = a.openMesh({ positions: session.positions(), faces: mr.faces() });
    const limitVolume = shaped.info({ surface: 'limit' }).volume;
    shaped.delete();
    const target = { level: 0, scheme: 'loop', surface: 'limit' };
    const made = buildEditor(b, other, { ...target, keepCentroid: session.keepCentroid, path: session.path });
    const taken = await createMrvol({ threads: 1 }).then((c) => (warmUp(c), c.adoptTransferredInSlices(b.transferable(other, made, { scheme: 'loop' }))));
    session.adoptRebuilt(taken, target);
    assert.equal(session.editor.madeElsewhere, true);
    assert.deepEqual([session.surface, session.keepCentroid, session.editor.surface()], ['limit', false, 'limit']);
    assert.ok(Math.abs(session.referenceVolume() - limitVolume) <= 1e-12 * Math.abs(limitVolume), 'the limit surface\'s volume now is its reference');
    assert.deepEqual(session.history.size, { undo: steps + 1, redo: 0 });
    assert.equal(session.history.peekUndo().label, 'surface');
    assert.ok(session.undo(), 'undone here');
    assert.deepEqual([session.surface, session.keepCentroid, session.editor.surface()], ['mesh', true, 'mesh']);
    assert.equal(session.referenceVolume(), meshReference, 'the mesh reference back');
    session.dispose();
  });

  test('taken over in slices (the page keeps drawing between them): the same mesh and editor as at once', async () => {
    const [a, b, c] = await Promise.all([createMrvol({ threads: 1 }), createMrvol({ threads: 1 }), createMrvol({ threads: 1 })]);
    for (const m of [a, b, c]) warmUp(m);
    const spiky = loadModel(a, 'spiky-ball');
    const mr = a.openMesh(spiky);
    const transfer = a.transferable(mr, buildEditor(a, mr, { level: 0, scheme: 'loop' }), { scheme: 'loop' });
    const fractions = [];
    const sliceBytes = 1 << 20;
    const sliced = await b.adoptTransferredInSlices(structuredClone(transfer), { sliceBytes, between: async (f) => { fractions.push(f); } });
    assert.equal(fractions.length, Math.ceil(transfer.memory.byteLength / sliceBytes), 'one wait per slice');
    assert.ok(fractions.every((f, i) => f > 0 && f <= 1 && (i === 0 || f > fractions[i - 1])), 'the fraction copied grows');
    assert.equal(fractions.at(-1), 1);
    const whole = c.adoptTransferred(transfer);
    const [e1, e2] = [sliced, whole].map((m) => m.createEditor({ level: 0, scheme: 'loop', path: 'matrix-free' }));
    assert.equal(e1.path(), 'polynomial');
    assert.deepEqual(drags(e1), drags(e2));
    for (const m of [sliced, whole, mr]) m.delete();
    await assert.rejects(() => b.adoptTransferredInSlices({ memory: new Uint8Array(4) }), /expects what transferable\(\) gave/);
  });

  // What web/memory-slices.js does between a worker and the page: transferable without a copy, then
  // the memory in use copied out a slice at a time (copyMemory) into one buffer used again.
  test('taken over from slices copied out of the other instance (copyMemory): the same as a whole copy; what the taker had above is cleared', async () => {
    const [a, b, c] = await Promise.all([createMrvol({ threads: 1 }), createMrvol({ threads: 1 }), createMrvol({ threads: 1 })]);
    for (const m of [a, b, c]) warmUp(m);
    // b has more in use than a will hand over: a bigger mesh opened and deleted first
    const big = b.subdivide(loadModel(b, 'spiky-ball'), { levels: 3 });
    const bigEditor = big.createEditor({ level: 0 });
    bigEditor.positionsView();
    const bInUse = b.transferable(big, bigEditor, { memory: false }).memoryBytes;
    big.delete();
    const spiky = loadModel(a, 'spiky-ball');
    const mr = a.openMesh(spiky);
    const editor = buildEditor(a, mr, { level: 0, scheme: 'loop' });
    const transfer = a.transferable(mr, editor, { scheme: 'loop', memory: false });
    assert.equal(transfer.memory, null);
    const whole = a.transferable(mr, editor, { scheme: 'loop' });
    assert.equal(whole.memory.byteLength, transfer.memoryBytes, 'the memory in use');
    assert.ok(bInUse > transfer.memoryBytes + (1 << 20), `the taker had more in use (${bInUse} > ${transfer.memoryBytes})`);
    const buffer = new Uint8Array(1 << 20);
    let slices = 0;
    async function* copied() {
      for (let at = 0; at < transfer.memoryBytes;) {
        const n = a.copyMemory(at, buffer.subarray(0, Math.min(buffer.length, transfer.memoryBytes - at)));
        at += n;
        slices++;
        yield buffer.subarray(0, n); // the taker copies it before asking for the next
      }
    }
    const fractions = [];
    const sliced = await b.adoptTransferredInSlices({ ...transfer, memory: copied() }, { between: async (f) => { fractions.push(f); } });
    assert.equal(slices, Math.ceil(transfer.memoryBytes / buffer.length));
    assert.equal(fractions.length, slices);
    assert.equal(fractions.at(-1), 1);
    const above = new Uint8Array(bInUse - transfer.memoryBytes);
    assert.equal(b.copyMemory(transfer.memoryBytes, above), above.length);
    assert.ok(above.every((x) => x === 0), 'the taker\'s own memory above the copy is cleared');
    const fromWhole = c.adoptTransferred(whole);
    const [e1, e2] = [sliced, fromWhole].map((m) => m.createEditor({ level: 0, scheme: 'loop', path: 'matrix-free' }));
    assert.equal(e1.path(), 'polynomial');
    assert.equal(e1.madeElsewhere, true);
    assert.deepEqual(drags(e1), drags(e2));
    // the taker goes on: a mesh bigger than the copy's heap opens and edits
    const again = b.subdivide(loadModel(b, 'spiky-ball'), { levels: 2 });
    assert.ok(drags(again.createEditor({ level: 0 })).every((m) => m.error <= 1e-8));
    for (const m of [sliced, fromWhole, mr, again]) m.delete();
  });

  // What web/file-open.js does while the worker makes the editor: the taker's memory grown and its
  // pages written ahead; the taker keeps working meanwhile, and then takes the copy as before.
  test('memory grown ahead (growMemoryAhead): to the bytes asked, in slices, the instance unchanged; the take-over after it the same', async () => {
    const [a, b, c] = await Promise.all([createMrvol({ threads: 1 }), createMrvol({ threads: 1 }), createMrvol({ threads: 1 })]);
    for (const m of [a, b, c]) warmUp(m);
    const mr = a.openMesh(loadModel(a, 'spiky-ball'));
    const transfer = a.transferable(mr, buildEditor(a, mr, { level: 0, scheme: 'loop' }), { scheme: 'loop' });
    // the taker has a mesh of its own, which works the same after
    const own = b.openMesh(loadModel(b, 'spiky-ball'));
    const ownBefore = drags(own.createEditor({ level: 0 }));
    own.setPositions(loadModel(b, 'spiky-ball').positions);
    const inUse = b.transferable(own, own.createEditor({ level: 0 }), { memory: false }).memoryBytes;
    const asked = inUse + 40 * 2 ** 20;
    const fractions = [];
    const size = await b.growMemoryAhead(asked, { sliceBytes: 8 * 2 ** 20, between: async (f) => { fractions.push(f); } });
    assert.ok(size >= asked, `grown to ${size} >= ${asked}`);
    assert.equal(fractions.length, 5, 'one between() per 8 MB slice of the 40 MB above what is in use');
    assert.equal(fractions.at(-1), 1);
    const above = new Uint8Array(size - inUse);
    b.copyMemory(inUse, above);
    assert.ok(above.every((x) => x === 0), 'what it wrote is zero');
    assert.deepEqual(drags(own.createEditor({ level: 0 })), ownBefore, 'the instance works as before');
    // stopped at once by an aborted signal: no slice written, no between()
    const stopped = new AbortController();
    stopped.abort();
    let calls = 0;
    await b.growMemoryAhead(size + 32 * 2 ** 20, { signal: stopped.signal, between: async () => { calls++; } });
    assert.equal(calls, 0);
    await assert.rejects(() => b.growMemoryAhead(-1), /growMemoryAhead expects a number of bytes/);
    const taken = b.adoptTransferred(transfer);
    const fromFresh = c.adoptTransferred(transfer);
    const [e1, e2] = [taken, fromFresh].map((m) => m.createEditor({ level: 0, scheme: 'loop', path: 'matrix-free' }));
    assert.deepEqual(drags(e1), drags(e2));
    for (const m of [taken, fromFresh, mr]) m.delete();
  });

  test('slices that do not add up to the memory in use, and bad copyMemory arguments, are refused by name', async () => {
    const [a, b] = await Promise.all([createMrvol({ threads: 1 }), createMrvol({ threads: 1 })]);
    for (const m of [a, b]) warmUp(m);
    const mr = a.openMesh(loadModel(a, 'spiky-ball'));
    const transfer = a.transferable(mr, buildEditor(a, mr, { level: 0, scheme: 'loop' }), { scheme: 'loop', memory: false });
    const from = (...lengths) => (async function* () { for (const n of lengths) yield new Uint8Array(n); })();
    await assert.rejects(() => b.adoptTransferredInSlices({ ...transfer, memory: from(1024) }), /the slices ended at 1024 of \d+ bytes/);
    await assert.rejects(() => b.adoptTransferredInSlices({ ...transfer, memory: from(transfer.memoryBytes, 1) }), /the slices overrun the \d+ bytes/);
    await assert.rejects(() => b.adoptTransferredInSlices({ ...transfer, memory: from(4), memoryBytes: undefined }), /expects what transferable\(\) gave/);
    throwsMrvol(() => b.adoptTransferred({ ...transfer, memory: from(4) }), /expects what transferable\(\) gave/);
    throwsMrvol(() => a.copyMemory(-1, new Uint8Array(4)), /copyMemory expects a byte offset and a Uint8Array/);
    throwsMrvol(() => a.copyMemory(0, [0, 0]), /copyMemory expects a byte offset and a Uint8Array/);
    assert.equal(a.copyMemory(2 ** 33, new Uint8Array(4)), 0, 'nothing past the end');
    mr.delete();
  });
});
