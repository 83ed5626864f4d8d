// web/models.js openParsed: what the editor makes of a mesh read from a file, and what it offers when
// the mesh does not open: remeshing (closed, not semi-regular) or repair first (holes, not manifold).
// Corpus files (scripts/corpus.mjs, made as a user's files: a scan with holes, an STL sphere with its
// cap cut off, the npm bunny), read by the real core.
import { before, test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { createMrvol } from '../../lib/node.mjs';
import { CORPUS, makeCorpus } from '../../scripts/corpus.mjs';
import { openParsed } from '../../web/models.js';

let mrvol;
const read = (name) => {
  const c = CORPUS.find((x) => x.name === name);
  return mrvol.readMesh(readFileSync(c.file), { name: c.file });
};
const refusal = (mesh) => {
  try {
    openParsed(mrvol, mesh).mr.delete();
  } catch (e) {
    return e;
  }
  assert.fail('the mesh opened');
};

before(async () => {
  mrvol = await createMrvol({ threads: 1 });
  await makeCorpus({ big: false, names: ['bunny', 'bunny-holes', 'sphere-open-cap', 'l-bracket', 'duplicated-faces'] });
});

test('a mesh with holes is offered repair, and the message counts its boundary edges', () => {
  for (const name of ['bunny-holes', 'sphere-open-cap']) {
    const mesh = read(name), opened = mrvol.openMesh(mesh), edges = opened.info().boundaryEdges;
    opened.delete();
    assert.ok(edges > 0, name);
    const e = refusal(mesh);
    assert.equal(e.offer, 'repair', name);
    assert.match(e.message, new RegExp(`^this mesh has holes \\(${edges} boundary edges\\), so it encloses no volume to keep`), name);
  }
  // a small one too (it would otherwise open flat, every vertex a handle): a cube with a face cut out
  const cube = read('l-bracket');
  const open = { positions: cube.positions, faces: cube.faces.slice(3) };
  assert.equal(refusal(open).offer, 'repair');
});

test('a closed mesh that is not semi-regular is offered remeshing; a non-manifold one repair; a small closed one opens', () => {
  const bunny = refusal(read('bunny'));
  assert.equal(bunny.offer, 'remesh');
  assert.match(bunny.message, /^this mesh is not semi-regular/);
  assert.equal(refusal(read('duplicated-faces')).offer, 'repair');
  const { mr, info } = openParsed(mrvol, read('l-bracket'));
  assert.equal(info.levels, 0);
  assert.equal(info.closed, true);
  mr.delete();
});

test('a closed mesh that encloses no volume is refused with nothing offered: all at one point, or flat', () => {
  const tetrahedron = (positions) => ({ positions: Float64Array.from(positions), faces: Uint32Array.of(0, 1, 2, 0, 3, 1, 1, 3, 2, 2, 3, 0) });
  const point = refusal(tetrahedron([1, 2, 3, 1, 2, 3, 1, 2, 3, 1, 2, 3]));
  assert.equal(point.offer, null);
  assert.equal(point.message, 'all 4 vertices of this mesh are at one point (1, 2, 3): it has no shape to show or edit');
  const flat = refusal(tetrahedron([0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 2, 0]));
  assert.equal(flat.offer, null);
  assert.match(flat.message, /^this mesh encloses no volume \(0\): its surface lies flat/);
  // the same tetrahedron with its fourth corner lifted opens
  const lifted = openParsed(mrvol, tetrahedron([0, 0, 0, 1, 0, 0, 0, 1, 0, 0.2, 0.2, 1]));
  assert.ok(Math.abs(lifted.info.volume) > 0.1);
  lifted.mr.delete();
});
