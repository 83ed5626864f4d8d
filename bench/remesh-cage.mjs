#!/usr/bin/env node
// Where a remeshing's cage size comes from: remeshes a corpus model as bench/remesh.mjs does and
// prints, for each fit, its pieces' base sizes (faces, vertices, genus), the simplifier's retries
// and the chosen result's cage.
//
//   node bench/remesh-cage.mjs NAME
import { readFileSync } from 'node:fs';
import { createMrvol } from '../lib/node.mjs';
import { remesh } from '../lib/remesh.mjs';
import { CORPUS, makeCorpus } from '../scripts/corpus.mjs';

const name = process.argv[2];
const c = CORPUS.find((x) => x.name === name);
if (!c) throw new Error(`not in the corpus: ${name}`);
await makeCorpus({ big: true, names: [name] });
const mrvol = await createMrvol();
const read = mrvol.readMesh(readFileSync(c.file), { name: c.file });
const debug = (event, data) => {
  if (event === 'untangled') console.log(`  piece ${data.piece}: ${data.flippedTriangles} flipped left after untangling`);
  if (event !== 'fitted') return;
  const v = mrvol.validate(data.base);
  console.log(`piece ${data.piece}: base ${data.base.faces.length / 3} faces, ${data.base.positions.length / 3} vertices, genus ${v.genus}; ${data.levels} levels; ${data.flipped.length} flipped before untangling`);
};
const t = performance.now();
const r = await remesh(mrvol, { positions: read.positions, faces: read.faces }, { repair: true, debug });
console.log(`result ${(100 * r.hausdorff).toFixed(3)}%, cage ${r.baseVertices} (${r.baseFaces} faces), ${r.vertices} vertices, levels ${r.levels}, genus changed in ${r.genusChangedPieces} pieces, ${((performance.now() - t) / 1000).toFixed(1)} s`);
console.log('fits:', JSON.stringify(r.fits));
console.log('simplifier retries:', JSON.stringify(r.simplifierRetries));
