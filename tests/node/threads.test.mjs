// The threaded build (mrvol-node-mt: WASM pthreads, the core's big loops on a pool of threads)
// against the single-thread one: the same drags and corrections on a mesh large enough to be cut
// into blocks (the spiky ball subdivided to 40,962 and 163,842 vertices, shuffled: the renderer's
// buffers in an order of their own) give the same bits, in the renderer's buffers, the positions
// and the volumes; threads: 1 loads the single-thread build; bad thread counts are refused.
import { test, describe, before } from 'node:test';
import assert from 'node:assert/strict';
import { spawnSync } from 'node:child_process';
import { existsSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import { createMrvol, MrvolError } from '../../lib/node.mjs';
import { readFileSync } from 'node:fs';
import { loadModel, model, rng, runCliSync, shuffleMesh, tempFolder } from './helpers.mjs';

const threaded = existsSync(new URL('../../build/wasm/mrvol-node-mt.mjs', import.meta.url));

let single, multi;
before(async () => {
  single = await createMrvol({ threads: 1 });
  if (threaded) multi = await createMrvol({ threads: 3 });
});

// A subdivided spiky ball, shuffled, opened in `mrvol` (its own copy of the mesh).
function bigMesh(mrvol, levels) {
  const base = loadModel(mrvol, 'spiky-ball');
  const sub = mrvol.subdivide(base, { levels });
  const { mesh: fine } = shuffleMesh({ positions: sub.positions(), faces: sub.faces() }, 7);
  sub.delete();
  return mrvol.openMesh(fine);
}

// Seeded drags with volume preservation; everything a renderer and a caller read, after each.
function drag(mrvol, levels, level, { drags = 6, tolerance } = {}) {
  const mr = bigMesh(mrvol, levels);
  const ed = mr.createEditor({ level });
  const r = rng(level + 17), cage = ed.cageVertices(), scale = mr.positions().reduce((m, x) => Math.max(m, Math.abs(x)), 0);
  const out = [];
  for (let d = 0; d < drags; ++d) {
    // One cage vertex or four at a time; each correction moves the whole free cage (the cage basis
    // table's full pass, the polynomial's sweeps).
    const moves = d % 2 === 0
      ? [{ vertex: cage[Math.floor(r() * cage.length)], offset: [0, 1, 2].map(() => 0.03 * scale * (2 * r() - 1)) }]
      : Array.from(cage.slice(0, 4), (vertex) => ({ vertex, offset: [0, 1, 2].map(() => 0.01 * scale * (2 * r() - 1)) }));
    const report = ed.moveVertices(moves, { preserve: true, ...(tolerance ? { tolerance } : {}) });
    assert.equal(report.converged, true, report.message);
    out.push({ volume: report.volumeResult, iterations: report.iterations, normals: ed.normalsView().slice(),
               positionsView: ed.positionsView().slice(), positions: ed.positions() });
  }
  ed.delete?.();
  mr.delete();
  return out;
}

describe('threads', { skip: threaded ? false : 'the threaded build is not there (node scripts/setup.mjs)' }, () => {
  const file = tempFolder('mrvol-threads-');

  test('threads: 1 is the single-thread build; the default and threads: 3 run threads', () => {
    assert.equal(single.threads, 1);
    assert.equal(multi.threads, 3);
  });

  for (const [levels, level, tolerance] of [[3, 0], [3, 2, 1e-10], [4, 0]]) {
    test(`${levels} subdivisions, editor at level ${level}${tolerance ? ', every step corrected' : ''}: the same bits`, () => {
      const a = drag(single, levels, level, { tolerance });
      const b = drag(multi, levels, level, { tolerance });
      assert.equal(b.length, a.length);
      for (let d = 0; d < a.length; ++d) {
        assert.equal(b[d].volume, a[d].volume, `drag ${d}: volume`);
        assert.equal(b[d].iterations, a[d].iterations, `drag ${d}: iterations`);
        for (const key of ['positionsView', 'normals', 'positions'])
          assert.ok(Buffer.from(b[d][key].buffer).equals(Buffer.from(a[d][key].buffer)), `drag ${d}: ${key} differ`);
      }
    });
  }

  test('the CLI: --threads 1 and --threads 2 write the same file; a bad count is a usage error', () => {
    const outputs = [1, 2].map((threads) => {
      const out = file(`edited-${threads}.obj`);
      const r = runCliSync(['edit', model('spiky-ball'), '--move', '3:0.2,0,0.1', '--tolerance', '1e-10', '--threads', String(threads), '-o', out]);
      assert.equal(r.status, 0, r.stderr);
      return readFileSync(out, 'utf8');
    });
    assert.equal(outputs[1], outputs[0]);
    const bad = runCliSync(['volume', model('spiky-ball'), '--threads', '0']);
    assert.equal(bad.status, 2);
    assert.match(bad.stderr, /--threads must be in 1\.\.16/);
  });

  test("a threaded instance refuses to take over another instance's memory image", () => {
    const mr = single.openMesh(loadModel(single, 'spiky-ball'));
    const ed = mr.createEditor({ level: 0 });
    const transfer = single.transferable(mr, ed);
    assert.throws(() => multi.adoptTransferred(transfer),
                  (e) => e instanceof MrvolError && /adoptTransferred needs a single-thread instance/.test(e.message));
    ed.delete?.();
    mr.delete();
  });

  // Typed catch clauses under -pthread (wasm/toolchain/landing_pad_context.cpp): the bindings' catch
  // (const std::exception&) gives the message, the core's own catch (const Error&) re-validates a
  // refused mesh in the caller's numbering (its lines named); a miss would say "unknown error".
  test('core errors reach JS as the MrvolError the single-thread build gives; the pool keeps working', () => {
    const dir = new URL('../data/bad/', import.meta.url);
    const { files } = JSON.parse(readFileSync(new URL('expected.json', dir), 'utf8'));
    const messageOf = (mrvol, text) => {
      try {
        mrvol.openMesh(mrvol.readObj(text)).delete();
      } catch (e) {
        assert.ok(e instanceof MrvolError && e instanceof Error, `threw ${typeof e}: ${e}`);
        return e.message;
      }
      assert.fail('no error');
    };
    for (const name of Object.keys(files).filter((f) => f.endsWith('.obj'))) {
      const text = readFileSync(new URL(name, dir), 'utf8');
      const message = messageOf(multi, text);
      assert.equal(message, messageOf(single, text), name);
      assert.ok(message.includes(files[name].errorWithLines ?? files[name].errorNode ?? files[name].error), `${name}: ${message}`);
    }
    const [a] = drag(single, 3, 0, { drags: 1 }), [b] = drag(multi, 3, 0, { drags: 1 });
    assert.ok(Buffer.from(b.normals.buffer).equals(Buffer.from(a.normals.buffer)));
  });

  // The dispatch lock: without it, landing pads of several threads share one context and a few
  // exceptions in 10^5 land in the wrong clause (tests/wasm/typed_catch_threads.cpp).
  test('typed catches on four threads at once: every exception lands in its own clause', () => {
    const program = fileURLToPath(new URL('../../build/wasm/typed-catch-threads.js', import.meta.url));
    const r = spawnSync(process.execPath, [program], { encoding: 'utf8', timeout: 120_000 });
    assert.equal(r.stdout.trim(), 'caught by the right clause: 80000, by another or none: 0', r.stderr.slice(-500));
    assert.equal(r.status, 0);
  });

  // -fexceptions would route every call that may throw, from a function with a landing pad, through
  // a JS trampoline (invoke_*): a third of the threaded build's time in a profile of drags.
  test('both builds catch C++ exceptions in WASM: no JS invoke_ trampolines', () => {
    for (const file of ['mrvol-node.mjs', 'mrvol-node-mt.mjs']) {
      const loader = readFileSync(new URL(`../../build/wasm/${file}`, import.meta.url), 'utf8');
      assert.equal(loader.match(/\binvoke_[a-z]+\b/)?.[0], undefined, `${file} calls through JS trampolines`);
    }
  });

  test('bad thread counts are refused by name', async () => {
    for (const threads of [0, -1, 1.5, 17, '2'])
      await assert.rejects(createMrvol({ threads }), (e) => e instanceof MrvolError && /threads must be an integer/.test(e.message));
  });
});
