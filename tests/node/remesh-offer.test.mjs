// web/remesh-offer.js repairWords: the app's note of what the repair did, from the real repair's
// report (lib/repair.mjs) on corpus files: only what it did, in words, counted; remeshFailureWords:
// the remesher's real failures in the app's words (its repair box, not the CLI's flags).
import { before, test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { createMrvol } from '../../lib/node.mjs';
import { repair } from '../../lib/repair.mjs';
import { CORPUS, makeCorpus } from '../../scripts/corpus.mjs';
import { remesh } from '../../lib/remesh.mjs';
import { remeshFailureWords, repairWords } from '../../web/remesh-offer.js';

let mrvol;
const repaired = (name) => {
  const c = CORPUS.find((x) => x.name === name);
  return repair(mrvol.readMesh(readFileSync(c.file), { name: c.file })).report;
};

before(async () => {
  mrvol = await createMrvol({ threads: 1 });
  await makeCorpus({ big: false, names: ['teapot', 'sphere-open-cap', 'flipped-patch', 'capsule', 'sphere', 'bunny', 'boxes-sharing-an-edge'] });
});

test('what the repair did, and only that', () => {
  assert.equal(repairWords(repaired('teapot'), 0), '96 vertices welded, 3 faces dropped, 6 holes closed');
  assert.equal(repairWords(repaired('sphere-open-cap'), 0), '22 vertices welded, 1 hole closed');
  assert.equal(repairWords(repaired('flipped-patch'), 0), '40 faces turned to agree');
  assert.equal(repairWords(repaired('capsule'), 2), '40 vertices welded, 48 faces dropped, 2 pieces dropped');
  assert.equal(repairWords(repaired('sphere'), 0), '31 vertices welded');  // three's seam and poles, 1e-16 apart
  assert.equal(repairWords(repaired('bunny'), 0), 'nothing needed it');
  // A vertex no face uses (a stray point): dropped, and said (it read "nothing needed it").
  const tetrahedron = { positions: Float64Array.of(0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 5, 5, 5), faces: Uint32Array.of(0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2) };
  const report = repair(tetrahedron).report;
  assert.equal(report.unusedVertices, 1);
  assert.equal(repairWords(report, 0), '1 unused vertex dropped');
});

test('the remesher\'s failures name the app\'s repair box, not the CLI\'s flags', async () => {
  const failure = async (mesh, options) => {
    try {
      await remesh(mrvol, mesh, options);
    } catch (e) {
      return e.message;
    }
    assert.fail('remeshed');
  };
  const read = (name) => {
    const c = CORPUS.find((x) => x.name === name);
    return mrvol.readMesh(readFileSync(c.file), { name: c.file });
  };
  const open = read('sphere-open-cap');
  const holes = await failure({ positions: open.positions, faces: open.faces }, {});
  assert.match(holes, /--repair/);
  assert.match(remeshFailureWords(holes), /^the input has holes \(\d+ boundary edges\); remeshing needs a closed surface: close the holes first, or tick repair \(it closes holes of up to 100 edges\)$/);
  const large = await failure({ positions: open.positions, faces: open.faces }, { repair: true, maxHoleEdges: 3 });
  assert.match(large, /--max-hole/);
  assert.match(remeshFailureWords(large), /the repair closes holes of up to 100 edges, and these are larger: close them in a modelling tool, or use the CLI's --max-hole$/);
  // Inside out: the sphere's faces turned.
  const sphere = read('bunny'), turned = sphere.faces.slice();
  for (let f = 0; f < turned.length; f += 3) [turned[f + 1], turned[f + 2]] = [turned[f + 2], turned[f + 1]];
  const inside = await failure({ positions: sphere.positions, faces: turned }, {});
  assert.match(remeshFailureWords(inside), /is it inside out\? \(tick repair: it turns it outward\)$/);
  const fan = read('boxes-sharing-an-edge');
  const nonManifold = await failure({ positions: fan.positions, faces: fan.faces }, {});
  assert.match(remeshFailureWords(nonManifold), /^the input is not a manifold triangle mesh: .* \(tick repair: it drops such faces and closes the holes\)$/);
  for (const m of [holes, large, inside, nonManifold]) assert.doesNotMatch(remeshFailureWords(m).replace("the CLI's --max-hole", ''), /--|maxHoleEdges/);
});
