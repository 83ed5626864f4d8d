// web/remesh-offer.js repairWords: the app's note of what the repair did, from the real repair's
// report (lib/repair.mjs) on corpus files: only what it did, in words, counted.
import { before, test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { createMrvol } from '../../lib/node.mjs';
import { repair } from '../../lib/repair.mjs';
import { CORPUS, makeCorpus } from '../../scripts/corpus.mjs';
import { repairWords } from '../../web/remesh-offer.js';

let mrvol;
const repaired = (name) => {
  const c = CORPUS.find((x) => x.name === name);
  return repair(mrvol.readMesh(readFileSync(c.file), { name: c.file })).report;
};

before(async () => {
  mrvol = await createMrvol({ threads: 1 });
  await makeCorpus({ big: false, names: ['teapot', 'sphere-open-cap', 'flipped-patch', 'capsule', 'sphere', 'bunny'] });
});

test('what the repair did, and only that', () => {
  assert.equal(repairWords(repaired('teapot'), 0), '96 vertices welded, 3 faces dropped, 6 holes closed');
  assert.equal(repairWords(repaired('sphere-open-cap'), 0), '22 vertices welded, 1 hole closed');
  assert.equal(repairWords(repaired('flipped-patch'), 0), '40 faces turned to agree');
  assert.equal(repairWords(repaired('capsule'), 2), '40 vertices welded, 48 faces dropped, 2 pieces dropped');
  assert.equal(repairWords(repaired('sphere'), 0), '31 vertices welded');  // three's seam and poles, 1e-16 apart
  assert.equal(repairWords(repaired('bunny'), 0), 'nothing needed it');
});
