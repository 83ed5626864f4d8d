// web/share.js under Node: the project file (a Blob of parts) and its base64url, against Node's own
// base64url and through readProject, bit for bit.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { base64UrlBytes, fromBase64Url, projectBlob, readProject } from '../../web/share.js';

const ascii = (bytes) => new TextDecoder().decode(bytes);
function randomBytes(n, seed) {
  const out = new Uint8Array(n);
  let s = seed >>> 0;
  for (let i = 0; i < n; i++) {
    s = (Math.imul(s, 1664525) + 1013904223) >>> 0;
    out[i] = s >>> 24;
  }
  return out;
}

test('base64UrlBytes spells every length as Node does, and fromBase64Url reads it back', () => {
  for (let n = 0; n < 70; n++) {
    const bytes = randomBytes(n, n + 1);
    const spelt = ascii(base64UrlBytes(bytes));
    assert.equal(spelt, Buffer.from(bytes).toString('base64url'), `length ${n}`);
    assert.deepEqual(fromBase64Url(spelt), bytes, `length ${n}`);
    // base64's own spelling, padded, reads the same
    assert.deepEqual(fromBase64Url(Buffer.from(bytes).toString('base64')), bytes, `length ${n}, base64`);
  }
  const big = randomBytes(3_000_001, 7); // every byte value, the tail of 1 byte
  const spelt = ascii(base64UrlBytes(big));
  assert.equal(spelt, Buffer.from(big).toString('base64url'));
  assert.deepEqual(fromBase64Url(spelt), big);
});

test('fromBase64Url names what is wrong and where', () => {
  assert.throws(() => fromBase64Url('AAAA*AAA', 'p.json: "positions"'), /^Error: p\.json: "positions" is not base64: character 5 is "\*"$/);
  assert.throws(() => fromBase64Url('AAAAA'), /is not base64 \(its length, 5, is one more than a multiple of 4\)/);
  assert.throws(() => fromBase64Url('AAé'), /character 3 is "é"/);
  assert.throws(() => fromBase64Url('AA\u0100A'), /character 3/); // above 255: not read as its low byte
  assert.throws(() => fromBase64Url('A A'), /character 2 is " "/);
});

test('a project file reads back: positions bit for bit, the file bytes, an OBJ text, settings and reference', async () => {
  const positions = new Float64Array(3000).map((_, i) => Math.sin(i) * 1e3 + (i % 7 === 0 ? -0 : 0));
  positions[5] = Number.MIN_VALUE;
  positions[6] = -Number.MAX_VALUE;
  const settings = { level: 2, scheme: 'butterfly', keepBalance: true, surface: 'limit' };
  const bytes = randomBytes(100_003, 3);
  const fromFile = readProject(await projectBlob({ model: { name: 'part "7".glb', kind: 'file', format: 'glb', bytes },
                                                   positions, reference: 1.25, settings }).text(), 'p.json');
  assert.deepEqual(new Uint8Array(fromFile.positions.buffer), new Uint8Array(positions.buffer));
  assert.deepEqual(fromFile.model, { name: 'part "7".glb', kind: 'file', bytes, format: 'glb' });
  assert.deepEqual(fromFile.settings, settings);
  assert.equal(fromFile.reference, 1.25);
  // an OBJ's text with what JSON must escape
  const text = 'v 0 0 0\r\nv 1 0 0\nv 0 1 0\n# "quoted" \\ \t ünïcødé \u2028\nf 1 2 3\n';
  const fromText = readProject(await projectBlob({ model: { name: 'tri', kind: 'sample', text }, positions, reference: null, settings: {} }).text(), 'q.json');
  assert.deepEqual(fromText.model, { name: 'tri', kind: 'file', text });
  assert.equal(fromText.reference, null);
  assert.equal(JSON.parse(await projectBlob({ model: { name: 'tri', kind: 'sample', text }, positions, reference: 2, settings }).text()).format, 'mrvol-project');
});

test('a damaged project is refused in words', async () => {
  const good = JSON.parse(await projectBlob({ model: { name: 'm', kind: 'file', format: 'ply', bytes: new Uint8Array([1, 2, 3]) },
                                             positions: new Float64Array([1, 2, 3]), reference: 1, settings: {} }).text());
  assert.throws(() => readProject('{"format": "mrvol-project", "vers', 'a.json'), /^Error: a\.json is not a project file/);
  assert.throws(() => readProject(JSON.stringify({ ...good, positions: 'AAA!AAAA' }), 'b.json'), /b\.json: "positions" is not base64: character 4 is "!"/);
  assert.throws(() => readProject(JSON.stringify({ ...good, positions: 'AAAA' }), 'c.json'), /c\.json: "positions" is not a list of float64 numbers/);
  assert.throws(() => readProject(JSON.stringify({ ...good, model: { ...good.model, bytes: 'A~' } }), 'd.json'), /d\.json: "model\.bytes" is not base64: character 2 is "~"/);
  assert.throws(() => readProject(JSON.stringify({ ...good, version: 9 }), 'e.json'), /e\.json is a version 9 project/);
});
