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

let maker, taker, plain;
before(async () => {
  [maker, taker, plain] = await Promise.all([createMrvol(), createMrvol(), createMrvol()]);
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
    const [a, b] = await Promise.all([createMrvol(), createMrvol()]);
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
});
