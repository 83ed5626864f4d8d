#!/usr/bin/env node
// What the editor keeps (issue 15): one drag step keeping the volume (1 constraint) against the
// volume and the centre of mass (4 constraints), and keeping the Loop limit surface's volume, on
// the paper's sizes (the spiky ball, N = 642, and the bunny, N = 2002; the dragon sample) and on the spiky ball subdivided to
// N = 10k ... 163,842, through the JS API on the WASM module (lib/node.mjs), as the CLI and the
// app run it. A step: one handle moved by 2 % of the bounding-box diagonal (alternately out and
// back), the correction to tolerance 1e-5; the median over the steps, in CPU ms (the machine may
// be shared: CPU time is the fair measure; wall time counts the other processes' turns too).
// Writes bench/RESULTS-keep.md (machine, date) unless --no-write.
//
//   node bench/keep.mjs [--no-write] [--quick]     (--quick: up to 40k, fewer steps)
import { readFileSync, writeFileSync } from 'node:fs';
import { cpus, loadavg, totalmem } from 'node:os';
import { fileURLToPath } from 'node:url';
import { parseArgs } from 'node:util';
import { createMrvol } from '../lib/node.mjs';

const { values: opts } = parseArgs({ options: { 'no-write': { type: 'boolean' }, quick: { type: 'boolean' } } });
const quick = Boolean(opts.quick);
const mrvol = await createMrvol();
const models = fileURLToPath(new URL('../public/models/', import.meta.url));
const read = (name) => mrvol.readObj(readFileSync(`${models}${name}.obj`, 'utf8'));

// The meshes: [label, mesh, levels of the cages to edit at].
const ball = read('spiky-ball');  // 642 vertices
const CASES = [['spiky ball (paper)', ball, [0]], ['bunny (paper)', read('bunny-remeshed'), [0, 1]], ['dragon sample', read('dragon-remeshed'), [0, 1]]];
for (const levels of quick ? [2, 3] : [2, 3, 4]) {
  const mr = mrvol.subdivide(ball, { levels });
  CASES.push([`spiky ball x${levels}`, mr.toMesh(), [0, 2]]);
  mr.delete();
}

const cpuMs = (a, b) => (b.user - a.user + b.system - a.system) / 1000;
const median = (v) => [...v].sort((a, b) => a - b)[Math.floor(v.length / 2)];

function diagonalOf(p) {
  const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i < p.length; i += 3) for (let k = 0; k < 3; k++) lo[k] = Math.min(lo[k], p[i + k]), hi[k] = Math.max(hi[k], p[i + k]);
  return Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
}

// Drag steps on a fresh editor: { ms (median CPU), wall, iterations (median), setupMs, path }.
function steps(mr, options, count, diagonal) {
  const t0 = process.cpuUsage();
  const editor = mr.createEditor(options);
  const setupMs = cpuMs(t0, process.cpuUsage());
  const cage = editor.cageVertices();
  const ms = [], wall = [], iterations = [];
  let path = null;
  for (let s = 0; s < count; s++) {
    const vertex = cage[(7 * s) % cage.length];
    const sign = s % 2 ? -1 : 1;
    const offset = [0.02 * diagonal * sign, 0.012 * diagonal * sign, -0.008 * diagonal * sign];
    const c0 = process.cpuUsage(), w0 = performance.now();
    const report = editor.moveVertices([{ vertex, offset }], { tolerance: 1e-5 });
    wall.push(performance.now() - w0);
    ms.push(cpuMs(c0, process.cpuUsage()));
    if (!report.converged) throw new Error(`${JSON.stringify(options)}: ${report.message}`);
    iterations.push(report.iterations);
    path = report.path;
  }
  editor.delete();
  return { ms: median(ms), wall: median(wall), iterations: median(iterations), setupMs, path };
}

const rows = [];
for (const [label, mesh, levels] of CASES) {
  const mr = mrvol.openMesh(mesh);
  const n = mesh.positions.length / 3, diagonal = diagonalOf(mesh.positions);
  const count = quick ? 5 : n > 100000 ? 7 : 15;
  for (const level of levels) {
    if (level > mr.levels) continue;
    const cells = {
      volume: steps(mr, { level, path: 'matrix-free' }, count, diagonal),
      auto: steps(mr, { level }, count, diagonal),
      centroid: steps(mr, { level, keep: ['volume', 'centroid'] }, count, diagonal),
      limit: steps(mr, { level, surface: 'limit' }, count, diagonal),
    };
    const f = (x) => (x < 10 ? x.toFixed(2) : x.toFixed(1));
    rows.push(`| ${label} | ${n} | ${level} | ${mr.info().baseVertices ?? ''} | ${f(cells.volume.ms)} (${cells.volume.iterations}) | ` +
      `${f(cells.auto.ms)} (${cells.auto.iterations}, ${cells.auto.path}) | ${f(cells.centroid.ms)} (${cells.centroid.iterations}) | ` +
      `${(cells.centroid.ms / cells.volume.ms).toFixed(2)} | ${f(cells.limit.ms)} (${cells.limit.iterations}) | ${f(cells.limit.setupMs)} |`);
    process.stderr.write(`${rows.at(-1)}\n`);
  }
  mr.delete();
}

const text = [
  '# What the editor keeps: the drag step with 4 constraints against 1, and the limit volume',
  '',
  `Machine: ${cpus()[0]?.model ?? 'unknown CPU'} x ${cpus().length}, ${(totalmem() / 2 ** 30).toFixed(0)} GB; ` +
    `Node ${process.version}; ${new Date().toISOString().slice(0, 10)}; load average at the end ${loadavg()[0].toFixed(1)} ` +
    '(the machine was shared with other jobs: CPU times, medians). Rerun: `node bench/keep.mjs`.',
  '',
  'One drag step through the JS API on the WASM module: one level-e handle moved by 2 % of the bounding-box diagonal',
  '(out and back alternately), then the correction to 1e-5. Median CPU ms per step, (median iterations). Columns:',
  'volume: 1 constraint, matrix-free (adjoint of synthesis); auto: 1 constraint on the path `createEditor` picks',
  '(the cage polynomial on coarse cages); volume + centroid: 4 constraints (volume and the three first moments,',
  'delta = J^T (J J^T)^-1 r), matrix-free; ratio: 4 rows against 1 (both matrix-free); limit: the Loop limit',
  "surface's volume, matrix-free (the limit form's gradient through the adjoint), and its set-up (building the form",
  'and the editor).',
  '',
  '| mesh | N | e | base | volume, ms (it.) | auto, ms (it., path) | volume + centroid, ms (it.) | 4 : 1 | limit, ms (it.) | limit set-up, ms |',
  '|---|---|---|---|---|---|---|---|---|---|',
  ...rows,
  '',
].join('\n');
if (!opts['no-write']) writeFileSync(fileURLToPath(new URL('RESULTS-keep.md', import.meta.url)), text);
process.stderr.write(opts['no-write'] ? text : 'bench: wrote bench/RESULTS-keep.md\n');
