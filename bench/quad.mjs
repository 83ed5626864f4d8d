#!/usr/bin/env node
// Catmull-Clark quad multiresolution (issue 16, docs/catmull-clark.md) through the JS API and the
// WASM module, beside Loop on triangle meshes of about the same size: a full analysis to level 0
// plus synthesis (roundtripError), theta^e with cage storage, the cage polynomial built from the
// fine mesh, and one drag step (a cage vertex moved, the volume restored to 1e-5) on the
// matrix-free, tensor and polynomial paths; and, on the largest quad mesh, the drag step per
// level on the matrix-free and polynomial paths (where 'auto' switches).
// Quad meshes: the Catmull-Clark split of an octahedron (26 vertices, valences 3 and 4; the cube's
// split, so detection finds the cube as level 0 and analysis stops at level 1) subdivided;
// triangle meshes: the icosahedron subdivided n times (Loop). Median (minimum) in ms.
// Writes bench/RESULTS-quad.md unless --no-write.
//
//   node bench/quad.mjs [--no-write]
import { execFileSync } from 'node:child_process';
import { writeFileSync } from 'node:fs';
import { cpus, loadavg, totalmem } from 'node:os';
import { createMrvol } from '../lib/node.mjs';

const mrvol = await createMrvol();
const write = !process.argv.includes('--no-write');

function time(fn, { min = 5, ms = 300 } = {}) {
  for (let i = 0; i < 2; ++i) fn();  // warm-up
  const t = [];
  const start = performance.now();
  while (t.length < min || performance.now() - start < ms) {
    const t0 = performance.now();
    fn();
    t.push(performance.now() - t0);
  }
  t.sort((a, b) => a - b);
  return { median: t[t.length >> 1], min: t[0], runs: t.length };
}
const cell = (r) => `${r.median.toFixed(2)} (${r.min.toFixed(2)})`;

// The quad base: Catmull-Clark topology of the octahedron, vertices on the unit sphere.
function quadSphereBase() {
  const oct = [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]];
  const tris = [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]];
  const p = oct.map((v) => v.slice()), key = (a, b) => (a < b ? `${a},${b}` : `${b},${a}`), edge = new Map();
  const norm = (v) => { const l = Math.hypot(...v); return v.map((x) => x / l); };
  const facePoint = tris.map((t) => (p.push(norm([0, 1, 2].map((k) => t.reduce((s, v) => s + oct[v][k], 0)))), p.length - 1));
  const quads = [];
  const edgePoint = (a, b) => {
    const k = key(a, b);
    if (!edge.has(k)) { p.push(norm([0, 1, 2].map((c) => oct[a][c] + oct[b][c]))); edge.set(k, p.length - 1); }
    return edge.get(k);
  };
  tris.forEach((t, f) => t.forEach((v, i) => quads.push(v, edgePoint(v, t[(i + 1) % 3]), facePoint[f], edgePoint(t[(i + 2) % 3], v))));
  return { positions: Float64Array.from(p.flat()), quads: Uint32Array.from(quads) };
}
const icosahedron = () => {
  const t = (1 + Math.sqrt(5)) / 2;
  return {
    positions: Float64Array.from([-1, t, 0, 1, t, 0, -1, -t, 0, 1, -t, 0, 0, -1, t, 0, 1, t, 0, -1, -t, 0, 1, -t, t, 0, -1, t, 0, 1, -t, 0, -1, -t, 0, 1]),
    faces: Uint32Array.from([0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4, 11, 10, 2, 10, 7, 6, 7, 1, 8,
      3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8, 3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8, 1]),
  };
};

// One drag step: a cage vertex moved by 0.01 (back and forth), the volume restored to 1e-5.
function dragStep(editor) {
  const vertex = editor.cageVertices()[0];
  let sign = 1;
  return time(() => {
    const r = editor.moveVertices([{ vertex, offset: [0.01 * sign, 0, 0] }]);
    if (!r.converged || r.relativeError > 1e-5) throw new Error('drag step did not converge');
    sign = -sign;
  }, { min: 9, ms: 300 });
}

// The drag step at every level analysis reaches, matrix-free against the polynomial.
function perLevel(levels) {
  const built = mrvol.subdivide(quadSphereBase(), { levels, scheme: 'catmull-clark' });
  const mr = mrvol.openMesh(built.toMesh());
  built.delete();
  const out = [];
  for (let level = mr.lowestLevel; level < mr.levels; ++level) {
    const row = { levels: mr.levels, vertices: mr.vertexCount, level };
    for (const path of ['matrix-free', 'polynomial']) {
      const editor = mr.createEditor({ level, path });
      row.cage = editor.cageSize;
      row[path] = dragStep(editor);
      editor.delete();
    }
    out.push(row);
    process.stdout.write(JSON.stringify(row) + '\n');
  }
  mr.delete();
  return out;
}

function measure(kind, levels) {
  const built = kind === 'quad' ? mrvol.subdivide(quadSphereBase(), { levels, scheme: 'catmull-clark' })
    : mrvol.subdivide(icosahedron(), { levels });
  const mesh = built.toMesh();
  built.delete();
  const mr = mrvol.openMesh(mesh);
  // The quad base is the cube's split: detection finds the cube below it, whose first split cannot be
  // analysed (docs/catmull-clark.md): the transform stops at level 1 there.
  const lowest = mr.lowestLevel ?? 0;
  const row = { kind, levels: mr.levels, vertices: mr.vertexCount, lowest };
  row.transform = time(() => mr.roundtripError({ level: lowest }));
  const thetaLevel = Math.max(lowest, mr.levels - 2);
  row.thetaLevel = thetaLevel;
  const t0 = performance.now();
  const theta = mr.computeTheta({ level: thetaLevel });
  row.thetaMs = performance.now() - t0;
  row.thetaEntries = theta.info().nnzStored;
  for (const path of ['matrix-free', 'tensor', 'polynomial']) {
    const t1 = performance.now();
    const editor = mr.createEditor({ level: thetaLevel, ...(path === 'tensor' ? { theta } : { path }) });
    if (path === 'polynomial') row.polynomialMs = performance.now() - t1;
    row[path] = dragStep(editor);
    editor.delete();
  }
  theta.delete();
  mr.delete();
  return row;
}

const rows = [];
for (const levels of [3, 4, 5]) {
  for (const kind of ['quad', 'loop']) {
    const r = measure(kind, kind === 'quad' ? levels - 1 : levels);  // the quad base is already one split
    rows.push(r);
    process.stdout.write(JSON.stringify(r) + '\n');
  }
}

const levelRows = perLevel(5);

if (write) {
  let commit = 'unknown';
  try { commit = execFileSync('git', ['rev-parse', '--short', 'HEAD'], { encoding: 'utf8' }).trim(); } catch {}
  const lines = [
    '# Catmull-Clark quad multiresolution: benchmark',
    '',
    'Written by `node bench/quad.mjs` (rerun to refresh). JS API over the Node WASM module (`lib/node.mjs`).',
    'Quad meshes: the Catmull-Clark split of an octahedron (26 vertices, valences 3 and 4) subdivided (`subdivide',
    '--scheme catmull-clark`); it is the cube\'s split, so detection finds n levels over the 8-vertex cube and',
    'analysis stops at level 1 (the cube\'s first split is not invertible, docs/catmull-clark.md). Triangle meshes:',
    'the icosahedron subdivided n times, Loop scheme, for comparison. Cells: median (minimum) in ms.',
    '*transform*: `roundtripError` to the lowest level (0; 1 for the quads: analysis there and synthesis back, with',
    'the API\'s copies); *theta*: theta^e with cage storage, e = n - 2, computed once; *drag*: one `moveVertices`',
    'of a cage vertex by 0.01 with the volume restored to 1e-5 at level e = n - 2; *polynomial build*: the cage',
    'polynomial built from the fine mesh (`createEditor({ path: \'polynomial\' })`, no theta) at that level.',
    '',
    `- Machine: ${cpus().length} CPUs (${cpus()[0]?.model ?? '?'}), ${(totalmem() / 2 ** 30).toFixed(1)} GiB, Node ${process.version}`,
    `- Date: ${new Date().toISOString()}, commit ${commit}; load average (1 min) at the end: ${loadavg()[0].toFixed(2)}`,
    '- The machine was shared with other jobs (parallel helpers building and testing): minima are the better estimate.',
    '',
    '| scheme | n | vertices | transform | theta^e (e) | theta entries | polynomial build | drag matrix-free | drag tensor | drag polynomial |',
    '| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |',
    ...rows.map((r) => `| ${r.kind === 'quad' ? 'catmull-clark' : 'loop'} | ${r.levels} | ${r.vertices} | ${cell(r.transform)} | ` +
      `${r.thetaMs.toFixed(1)} (${r.thetaLevel}) | ${r.thetaEntries} | ${r.polynomialMs.toFixed(1)} | ${cell(r['matrix-free'])} | ` +
      `${cell(r.tensor)} | ${cell(r.polynomial)} |`),
    '',
    `Drag step per cage level on the largest quad mesh (n = ${levelRows[0]?.levels}, ${levelRows[0]?.vertices} vertices): the`,
    'matrix-free pass over the fine quads against the cage polynomial. `createEditor` under \'auto\' takes the polynomial',
    'from n - e = 3 levels of details on (`quadGradientPath` in lib/quad.mjs).',
    '',
    '| e | cage vertices | n - e | drag matrix-free | drag polynomial |',
    '| --- | --- | --- | --- | --- |',
    ...levelRows.map((r) => `| ${r.level} | ${r.cage} | ${r.levels - r.level} | ${cell(r['matrix-free'])} | ${cell(r.polynomial)} |`),
    '',
  ];
  writeFileSync(new URL('RESULTS-quad.md', import.meta.url), lines.join('\n'));
}
