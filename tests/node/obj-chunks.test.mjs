// OBJ read in chunks (createObjReader, readObjFile, and readObj of a large file, which feeds the
// heap in chunks): the same mesh, lines and extras as one readObj of the whole text wherever the
// chunks split it (mid-number, mid-CRLF, inside the byte order mark, mid-line), and the same
// error with the same line for a bad file.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync, writeFileSync } from 'node:fs';
import { createMrvol, MrvolError, readObjFile } from '../../lib/node.mjs';
import { tempFolder, model } from './helpers.mjs';

const mrvol = await createMrvol();
const file = tempFolder('mrvol-obj-chunks-test-');
const encode = (text) => new TextEncoder().encode(text);

// Every form readObj takes: BOM, CRLF, comments, colours, w, vt / vn, negative indices, polygons.
const FORMS = '\ufeff# forms\r\nv -0.47085295474687316 0.76185608448375686 1.7308149509183618e-17 \r\n' +
  'v 1 0 0 0.5 0.25 0.125\r\nv\t+1.5e+0 1 0 1 1 1\nv 0 1 0 0 0 1   \nvt 0 0\nvt 1 0 0\nvn 0 0 1\n' +
  'o thing\ng group\nusemtl m\nf 1/1/1 2/2/1 3//1\r\nf -4 -2 -1 # after\nf 2 4 3 1\nf 1 2 4';

function readInPieces(bytes, cuts, size = bytes.length) {
  const reader = mrvol.createObjReader({ size });
  let at = 0;
  for (const cut of [...cuts, bytes.length]) reader.push(bytes.subarray(at, cut)), (at = cut);
  return reader.finish();
}

function outcome(read) {
  try {
    return read();
  } catch (e) {
    if (!(e instanceof MrvolError)) throw e;
    return { error: e.message };
  }
}

test('createObjReader: every split of a file with every form equals readObj of the whole', () => {
  const bytes = encode(FORMS);
  const whole = mrvol.readObj(bytes);
  assert.ok(whole.polygons > 0 && whole.texCoords && whole.cornerNormals && whole.lines.vertex.length === 4);
  for (let cut = 0; cut <= bytes.length; ++cut) {
    assert.deepEqual(readInPieces(bytes, [cut]), whole, `cut at ${cut}`);
    if (cut > 0 && cut < bytes.length) assert.deepEqual(readInPieces(bytes, [cut - 1, cut], 0), whole, `cuts at ${cut - 1}, ${cut}`);
  }
  const everyByte = Array.from({ length: bytes.length - 1 }, (_, i) => i + 1);
  assert.deepEqual(readInPieces(bytes, everyByte), whole, 'one byte at a time');
});

test('createObjReader: a bad file gives the same error, with the same line, wherever it is split', () => {
  for (const text of ['v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nv 1.5x 0 0\n', 'v 0 0 0\r\nv 1 0 0\rv 0 1 0\r\nf 1 2 3\r\n',
                      'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n', 'v 0 0 0\nv 1 0 0\nv 0 1 0\n', '']) {
    const bytes = encode(text);
    const whole = outcome(() => mrvol.readObj(bytes));
    assert.ok(whole.error, text);
    for (let cut = 0; cut <= bytes.length; ++cut)
      assert.deepEqual(outcome(() => readInPieces(bytes, [cut])), whole, `${JSON.stringify(text)} cut at ${cut}`);
  }
});

test('createObjReader: a spent reader refuses more, and chunks must be bytes', () => {
  const reader = mrvol.createObjReader();
  assert.throws(() => reader.push('v 0 0 0\n'), MrvolError);
  reader.push(encode('v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n'));
  assert.equal(reader.finish().faces.length, 3);
  assert.throws(() => reader.push(encode('v 0 0 0\n')), /finished/);
  const failed = mrvol.createObjReader();
  assert.throws(() => failed.push(encode('v 0 0 zero\n')), /line 1: coordinate 'zero' is not a number/);
  assert.throws(() => failed.finish(), /finished \(or failed\)/);
});

test('readObjFile: a file read in small chunks equals readObj of its bytes; a missing file is named', async () => {
  const bytes = readFileSync(model('spiky-ball'));
  const path = file('forms.obj');
  writeFileSync(path, FORMS);
  assert.deepEqual(await readObjFile(mrvol, model('spiky-ball'), { chunkBytes: 1000 }), mrvol.readObj(bytes));
  const fractions = [];
  assert.deepEqual(await readObjFile(mrvol, path, { chunkBytes: 7, onProgress: (f) => fractions.push(f) }), mrvol.readObj(FORMS));
  assert.equal(fractions.length, Math.ceil(encode(FORMS).length / 7));
  assert.equal(fractions.at(-1), 1);
  await assert.rejects(readObjFile(mrvol, file('missing.obj')), /cannot read .*missing\.obj: no such file/);
});

test('readObj: a file larger than one chunk (16 MB) is read in chunks, every line in place', () => {
  // 1.1M vertices "v i 0.5 -0.25" then triangles over them: about 20 MB.
  const n = 1_100_000;
  const parts = [];
  for (let i = 0; i < n; ++i) parts.push(`v ${i} 0.5 -0.25\n`);
  for (let i = 1; i + 2 <= n; i += 100_000) parts.push(`f ${i} ${i + 1} ${i + 2}\r\n`);
  const bytes = encode(parts.join(''));
  assert.ok(bytes.length > 16 << 20);
  const mesh = mrvol.readObj(bytes);
  assert.equal(mesh.positions.length, 3 * n);
  for (const i of [0, 1, 777_777, n - 1]) {
    assert.deepEqual([...mesh.positions.subarray(3 * i, 3 * i + 3)], [i, 0.5, -0.25]);
    assert.equal(mesh.lines.vertex[i], i + 1);
  }
  assert.equal(mesh.faces.length, 3 * 11);
  assert.deepEqual([...mesh.faces.subarray(3, 6)], [100_000, 100_001, 100_002]);
  assert.equal(mesh.lines.face[1], n + 2);
});
