// Hostile and malformed OBJ files (tests/data/bad) through the WASM module and the CLI: each fails
// with the message tests/data/bad/expected.json expects, as a MrvolError, and the module instance
// keeps working after every error. The CLI prints exactly one line `mrvol: error: FILE: ...` and
// exits with status 1; usage errors exit with status 2.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync, readdirSync } from 'node:fs';
import { availableParallelism } from 'node:os';
import { join } from 'node:path';
import { createMrvol, MrvolError } from '../../lib/node.mjs';
import { ROOT as root, runCli } from './helpers.mjs';

const badDir = 'tests/data/bad';
const goodDir = 'tests/data/good';

const manifest = JSON.parse(readFileSync(join(root, badDir, 'expected.json'), 'utf8')).files;
const badFiles = Object.keys(manifest).sort();
// Under Node the file arrives as a UTF-8-decoded string: see `errorNode` in the manifest.
const expectedError = (name) => manifest[name].errorNode ?? manifest[name].error;
// A mesh from readObj carries the OBJ lines of its vertices and faces: validation names them.
const expectedFromObj = (name) => manifest[name].errorWithLines ?? expectedError(name);
// The CLI hands the file's bytes to the core as they are: no U+FFFD, so `error`, not `errorNode`.
const expectedFromCli = (name) => manifest[name].errorWithLines ?? manifest[name].error;
const objFiles = (dir) => readdirSync(join(root, dir)).filter((f) => f.endsWith('.obj')).sort();
const readText = (dir, name) => readFileSync(join(root, dir, name), 'utf8');

// One module instance for the whole file: errors must leave it usable.
const mrvol = await createMrvol();
const octahedronText = readText(goodDir, 'octahedron.obj');

function assertStillWorks(after) {
  const mr = mrvol.openMesh(mrvol.readObj(octahedronText));
  try {
    const info = mr.info();
    assert.equal(info.vertices, 6, `after ${after}`);
    assert.equal(info.faces, 8, `after ${after}`);
    assert.equal(info.closed, true, `after ${after}`);
    assert.ok(Math.abs(info.volume - 4 / 3) < 1e-15, `after ${after}: volume ${info.volume}`);
  } finally {
    mr.delete();
  }
}

// The MrvolError `fn` throws (fails when it throws nothing or something else).
function errorOf(fn, what) {
  try {
    fn();
  } catch (e) {
    assert.ok(e instanceof MrvolError, `${what} threw ${e?.name}: ${e?.message}`);
    assert.equal(e.name, 'MrvolError');
    assert.match(e.message, /^[\x20-\x7e]+$/, `${what}: the message should be one line of printable ASCII`);
    return e.message;
  }
  assert.fail(`${what} threw nothing`);
}

test('the manifest lists every bad file, and only files that exist', () => {
  const files = objFiles(badDir);
  assert.ok(badFiles.length >= 32, `only ${badFiles.length} files in expected.json`);
  for (const f of files) assert.ok(Object.hasOwn(manifest, f), `${f} is in ${badDir} but not in expected.json`);
  for (const f of badFiles) {
    assert.ok(files.includes(f), `${f} is in expected.json but not in ${badDir}`);
    assert.ok(['read', 'validate'].includes(manifest[f].stage), `${f}: stage ${manifest[f].stage}`);
    assert.ok(typeof manifest[f].error === 'string' && manifest[f].error.length > 0, `${f}: no expected error`);
  }
});

test('every bad file fails as a MrvolError with its expected message; the instance keeps working', async (t) => {
  for (const name of badFiles) {
    await t.test(name, () => {
      const { stage } = manifest[name];
      const expected = expectedError(name);
      const text = readText(badDir, name);
      if (stage === 'read') {
        const message = errorOf(() => mrvol.readObj(text), 'readObj');
        assert.ok(message.includes(expected), `got:      ${message}\nexpected: ${expected}`);
      } else {
        let mesh;
        assert.doesNotThrow(() => { mesh = mrvol.readObj(text); }, 'the file should read and fail validation');
        const message = errorOf(() => mrvol.openMesh(mesh), 'openMesh');
        const withLines = expectedFromObj(name);
        assert.ok(message.includes(withLines), `got:      ${message}\nexpected: ${withLines}`);
        assert.equal(errorOf(() => mrvol.validate(mesh), 'validate'), message);
        assert.equal(errorOf(() => mrvol.volume(mesh), 'volume'), message);
        // The same arrays without their lines (or with lines that no longer fit): indices only.
        const bare = errorOf(() => mrvol.openMesh({ positions: mesh.positions, faces: mesh.faces }), 'openMesh (arrays)');
        assert.ok(bare.includes(expected) && !bare.includes('(line '), `got:      ${bare}\nexpected: ${expected}`);
        const stale = { ...mesh, lines: { vertex: mesh.lines.vertex.subarray(1), face: mesh.lines.face } };
        assert.equal(errorOf(() => mrvol.validate(stale), 'validate (stale lines)'), bare);
      }
      assertStillWorks(name);
    });
  }
});

test('accepted-but-odd files read exactly like the plain octahedron', () => {
  const reference = mrvol.readObj(octahedronText);
  const files = objFiles(goodDir);
  assert.ok(files.length >= 8);
  for (const name of files) {
    const mesh = mrvol.readObj(readText(goodDir, name));
    // Equal as numbers (-0 written as "-0" reads as -0, which is 0).
    assert.deepEqual(Array.from(mesh.positions, (x) => x + 0), Array.from(reference.positions, (x) => x + 0), name);
    assert.deepEqual(Array.from(mesh.faces), Array.from(reference.faces), name);
    const mr = mrvol.openMesh(mesh);
    assert.ok(Math.abs(mr.info().volume - 4 / 3) < 1e-15, name);
    mr.delete();
  }
});

// ---- the command line ---------------------------------------------------------------------------

// Runs from the repository root: the paths below are relative to it.
const mrvolCli = (args) => runCli(args, { cwd: root });

// Runs every job, `limit` at a time, keeping the order of the results.
async function inParallel(items, limit, job) {
  const results = new Array(items.length);
  let next = 0;
  const worker = async () => {
    while (next < items.length) {
      const i = next++;
      results[i] = await job(items[i]);
    }
  };
  await Promise.all(Array.from({ length: Math.min(limit, items.length) }, worker));
  return results;
}

test('mrvol info FILE --json: exit status 1, nothing on stdout, one line on stderr', async (t) => {
  const paths = badFiles.map((name) => `${badDir}/${name}`);
  const results = await inParallel(paths, Math.max(2, availableParallelism()), (path) => mrvolCli(['info', path, '--json']));
  for (const [i, name] of badFiles.entries()) {
    await t.test(name, () => {
      const { status, signal, stdout, stderr } = results[i];
      const path = paths[i];
      assert.equal(signal, null);
      assert.equal(status, 1, `exit status (stderr: ${stderr})`);
      assert.equal(stdout, '');
      assert.ok(stderr.endsWith('\n'), `stderr should end with a newline: ${JSON.stringify(stderr)}`);
      const lines = stderr.slice(0, -1).split('\n');
      assert.equal(lines.length, 1, `stderr should be one line: ${JSON.stringify(stderr)}`);
      assert.ok(lines[0].startsWith(`mrvol: error: ${path}: `), lines[0]);
      assert.ok(lines[0].includes(expectedFromCli(name)), `got:      ${lines[0]}\nexpected: ${expectedFromCli(name)}`);
      assert.doesNotMatch(lines[0], /[\r\x00]/);
    });
  }
});

test('mrvol usage errors exit with status 2', async (t) => {
  const good = `${goodDir}/octahedron.obj`;
  const cases = [
    { args: ['frobnicate', good], stderr: "mrvol: error: unknown command 'frobnicate'" },
    { args: ['info'], stderr: 'mrvol: error: missing MESH.obj' },
    { args: [], stderr: 'usage: mrvol' },
    { args: ['info', good, 'extra.obj'], stderr: "mrvol: error: unexpected argument 'extra.obj'" },
    { args: ['info', good, '--bogus'], stderr: 'mrvol: error: unknown option --bogus (mrvol help info lists the options)' },
    { args: ['roundtrip', good, '--level', 'abc'], stderr: "mrvol: error: --level expects an integer, got 'abc'" },
    { args: ['roundtrip', good, '--level', '1.5'], stderr: "mrvol: error: --level expects an integer, got '1.5'" },
    { args: ['roundtrip', good, '--level='], stderr: "mrvol: error: --level expects an integer, got ''" },
    { args: ['roundtrip', good, '--level'], stderr: 'mrvol: error: --level needs a value (mrvol help roundtrip)' },
  ];
  const results = await inParallel(cases, Math.max(2, availableParallelism()), (c) => mrvolCli(c.args));
  for (const [i, c] of cases.entries()) {
    await t.test(`mrvol ${c.args.join(' ')}`, () => {
      const { status, stdout, stderr } = results[i];
      assert.equal(status, 2, `exit status (stderr: ${stderr})`);
      assert.equal(stdout, '');
      assert.ok(stderr.startsWith(c.stderr), `got: ${stderr}\nexpected the start: ${c.stderr}`);
    });
  }
});

test('mrvol run-time errors that are not about usage exit with status 1', async () => {
  const [missing, level] = await Promise.all([
    mrvolCli(['info', `${badDir}/no-such-file.obj`]),
    mrvolCli(['roundtrip', `${goodDir}/octahedron.obj`, '--level', '99']),
  ]);
  assert.equal(missing.status, 1);
  assert.equal(missing.stdout, '');
  assert.equal(missing.stderr, `mrvol: error: cannot read ${badDir}/no-such-file.obj: no such file\n`);
  assert.equal(level.status, 1);
  assert.equal(level.stdout, '');
  assert.equal(level.stderr, 'mrvol: error: level 99 is out of range: this mesh has levels 0..0\n');
});
