// A call that runs out of WASM memory (a size the caller chose) gives MrvolError, and the module
// keeps working: nothing leaves the bindings uncaught (wasm/bindings/guard.h). In the threaded
// module an escaped exception would also keep the exception dispatch lock on the calling thread
// (wasm/toolchain/landing_pad_context.cpp) and the pool's next throw would wait for ever; so the
// threaded instance (threads: 2) then runs a batch on its pool and core errors after it.
import { test, describe, before } from 'node:test';
import assert from 'node:assert/strict';
import { existsSync } from 'node:fs';
import { createMrvol, MrvolError } from '../../lib/node.mjs';
import { loadModel, rng } from './helpers.mjs';

const threaded = existsSync(new URL('../../build/wasm/mrvol-node-mt.mjs', import.meta.url));

// 4 * (2^27 - 1) doubles for the queries' input: 4 GB less 32 bytes, a std::vector the module may
// hold (no length_error) but its 4 GB memory cannot give (std::bad_alloc; nothing is touched).
const TOO_MANY_QUERIES = 2 ** 27 - 1;

function outOfMemory(e) {
  return e instanceof MrvolError && /^out of memory: /.test(e.message);
}

let single, multi;
before(async () => {
  single = await createMrvol({ threads: 1 });
  if (threaded) multi = await createMrvol({ threads: 2 });
});

// Query points around a model's surface, enough for several blocks of the pool's batch.
function queries(positions, n) {
  const r = rng(5), scale = positions.reduce((m, x) => Math.max(m, Math.abs(x)), 0);
  return Float64Array.from({ length: 3 * n }, () => 1.5 * scale * (2 * r() - 1));
}

function runOutOfMemory(mrvol) {
  const mesh = loadModel(mrvol, 'spiky-ball');
  const tree = mrvol.closestPoints(mesh);
  // An array-like of that many points: the room for them is asked for before any is read.
  assert.throws(() => tree.closestMany({ length: 3 * TOO_MANY_QUERIES }), outOfMemory);
  assert.throws(() => tree.closestMany({ length: 3 * TOO_MANY_QUERIES }), outOfMemory, 'a second time');
  // The slot was emptied: the next error is its own, not the out-of-memory one.
  assert.throws(() => mrvol.openMesh({ positions: mesh.positions, faces: Uint32Array.of(0, 1, 99) }),
    (e) => e instanceof MrvolError && /^vertex 2 is not used by any face/.test(e.message));
  const answer = tree.closestMany(queries(mesh.positions, 20000));
  tree.dispose();
  return { mesh, answer };
}

describe('out of memory', () => {
  test('single-thread module: MrvolError, then the module answers', () => {
    const { answer } = runOutOfMemory(single);
    assert.equal(answer.distances.length, 20000);
    assert.ok(answer.distances.every((d) => Number.isFinite(d) && d >= 0));
  });

  test('threaded module: MrvolError, then its pool answers and core errors still arrive', { skip: threaded ? false : 'the threaded build is not there (node scripts/setup.mjs)' }, () => {
    assert.equal(multi.threads, 2);
    const { mesh, answer } = runOutOfMemory(multi);
    // The batch ran on the pool (20000 queries: blocks for both threads): the single module's bits.
    const reference = single.closestPoints(mesh);
    const expected = reference.closestMany(queries(mesh.positions, 20000));
    reference.dispose();
    assert.ok(Buffer.from(answer.points.buffer).equals(Buffer.from(expected.points.buffer)));
    assert.deepEqual(answer.triangles, expected.triangles);
    // A drag (its correction's sweeps on the pool), then a core error.
    const mr = multi.openMesh(subdivided(multi, mesh));
    const ed = mr.createEditor({ level: 0 });
    const report = ed.moveVertices([{ vertex: ed.cageVertices()[0], offset: [0.05, 0, 0] }], { preserve: true });
    assert.equal(report.converged, true, report.message);
    assert.throws(() => mr.createEditor({ level: 99 }), (e) => e instanceof MrvolError && !outOfMemory(e));
    ed.delete?.();
    mr.delete();
  });
});

function subdivided(mrvol, mesh) {
  const sub = mrvol.subdivide(mesh, { levels: 2 });
  const out = { positions: sub.positions(), faces: sub.faces() };
  sub.delete();
  return out;
}
