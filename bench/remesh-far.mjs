#!/usr/bin/env node
// Where the input→result side of the remeshing's Hausdorff distance comes from (issue 12's goal of
// 0.5% of the diagonal): remeshes corpus models as bench/remesh.mjs does (defaults, repair), then
// lists the samples of the repaired input (its vertices, each face's centroid and three interior
// points: the measure's) farther than 0.5% of the diagonal from the result, grouped into regions
// (2% of the diagonal across), each with how sharp the input is there (the largest angle between
// the normals of two faces at a vertex: over 90° is a spike or a thin lip) and how long the
// result's edges are there (the closest result triangle's mean edge). Writes bench/RESULTS-remesh-far.md (machine, date) unless --no-write.
//
//   node bench/remesh-far.mjs [--no-write] [NAME...]   (default: teapot dragon-11k-decimated)
import { execFileSync } from 'node:child_process';
import { readFileSync, writeFileSync } from 'node:fs';
import { cpus, loadavg } from 'node:os';
import { fileURLToPath } from 'node:url';
import { createMrvol } from '../lib/node.mjs';
import { remesh, repair, Surface } from '../lib/remesh.mjs';
import { triangleNormal } from '../lib/geometry.mjs';
import { CORPUS, makeCorpus } from '../scripts/corpus.mjs';

const GOAL = 0.005, REGION = 0.02, SHOWN = 6;
const args = process.argv.slice(2);
const write = !args.includes('--no-write');
const names = args.filter((a) => !a.startsWith('--'));
const chosen = names.length ? names : ['teapot', 'dragon-11k-decimated'];
const unknown = chosen.filter((n) => !CORPUS.some((c) => c.name === n));
if (unknown.length) throw new Error(`not in the corpus (scripts/corpus.mjs): ${unknown.join(', ')}`);
const mrvol = await createMrvol();
await makeCorpus({ big: true, names: chosen });

/** Per vertex: the largest angle (degrees) between the normals of two of its faces, and its degree. */
function sharpness(mesh) {
  const { positions: p, faces: f } = mesh, n = p.length / 3, faceCount = f.length / 3;
  const normals = new Float64Array(3 * faceCount);
  for (let t = 0; t < faceCount; t++) {
    const v = triangleNormal(p, f[3 * t], f[3 * t + 1], f[3 * t + 2]), l = Math.hypot(v[0], v[1], v[2]) || 1;
    for (let k = 0; k < 3; k++) normals[3 * t + k] = v[k] / l;
  }
  const around = Array.from({ length: n }, () => []);
  for (let t = 0; t < faceCount; t++) for (let j = 0; j < 3; j++) around[f[3 * t + j]].push(t);
  const angle = new Float64Array(n);
  for (let v = 0; v < n; v++) {
    let lowest = 1;
    for (const a of around[v])
      for (const b of around[v])
        lowest = Math.min(lowest, normals[3 * a] * normals[3 * b] + normals[3 * a + 1] * normals[3 * b + 1] + normals[3 * a + 2] * normals[3 * b + 2]);
    angle[v] = (Math.acos(Math.max(-1, Math.min(1, lowest))) * 180) / Math.PI;
  }
  return { angle, degree: around.map((a) => a.length) };
}

const sections = [];
for (const name of chosen) {
  const c = CORPUS.find((k) => k.name === name);
  const read = mrvol.readMesh(readFileSync(c.file), { name: c.file });
  const input = { positions: read.positions, faces: read.faces };
  const r = await remesh(mrvol, input, { repair: true });
  // The same repair as remesh's (deterministic): the surface the distances are measured to.
  const repaired = repair(input, {}).mesh;
  const result = new Surface(r.mesh, { normals: false });
  const { angle, degree } = sharpness(repaired);
  const p = repaired.positions, rp = r.mesh.positions, rf = r.mesh.faces, diagonal = r.diagonal;
  // The measure's samples: the vertices, then each face's centroid and three interior points (a
  // face sample is as sharp as its sharpest corner, and has the degree of that corner).
  const BARY = [[1 / 3, 1 / 3, 1 / 3], [2 / 3, 1 / 6, 1 / 6], [1 / 6, 2 / 3, 1 / 6], [1 / 6, 1 / 6, 2 / 3]];
  const f = repaired.faces, vertexCount = p.length / 3, far = [];
  for (let s = 0; s < vertexCount + 4 * f.length / 3; s++) {
    let at = [p[3 * s], p[3 * s + 1], p[3 * s + 2]], vertex = s;
    if (s >= vertexCount) {
      const t = Math.floor((s - vertexCount) / 4), w = BARY[(s - vertexCount) % 4];
      at = [0, 1, 2].map((k) => w[0] * p[3 * f[3 * t] + k] + w[1] * p[3 * f[3 * t + 1] + k] + w[2] * p[3 * f[3 * t + 2] + k]);
      vertex = [f[3 * t], f[3 * t + 1], f[3 * t + 2]].reduce((a, b) => (angle[b] > angle[a] ? b : a));
    }
    const hit = result.closest(at[0], at[1], at[2]);
    if (hit.distance > GOAL * diagonal) far.push({ at, vertex, d: hit.distance / diagonal, face: hit.faceIndex });
  }
  far.sort((a, b) => b.d - a.d);
  // Regions: the farthest sample not yet in one starts one; the far samples within REGION join it.
  const regions = [];
  for (const v of far) {
    const at = (k) => v.at[k];
    const region = regions.find((g) => Math.hypot(at(0) - g.at[0], at(1) - g.at[1], at(2) - g.at[2]) < REGION * diagonal);
    if (region) {
      region.count++, region.sharpest = Math.max(region.sharpest, angle[v.vertex]);
      continue;
    }
    const corner = (j) => 3 * rf[3 * v.face + j];
    let edge = 0;
    for (let j = 0; j < 3; j++) {
      const a = corner(j), b = corner((j + 1) % 3);
      edge += Math.hypot(rp[a] - rp[b], rp[a + 1] - rp[b + 1], rp[a + 2] - rp[b + 2]) / 3;
    }
    regions.push({ at: v.at, d: v.d, count: 1, degree: degree[v.vertex], angle: angle[v.vertex], sharpest: angle[v.vertex], edge: edge / diagonal });
  }
  const spikes = far.filter((v) => angle[v.vertex] > 90).length;
  const line = `${name}: Hausdorff ${(100 * r.hausdorff).toFixed(3)}% (input→result ${(100 * r.hausdorffFromInput).toFixed(3)}%), ` +
               `${r.vertices} result vertices at ${r.levels} levels; ${far.length} of ${vertexCount + (4 * f.length) / 3} input samples beyond 0.5%, ` +
               `in ${regions.length} regions; ${spikes} of them where the input's normals turn by more than 90°`;
  process.stdout.write(line + '\n');
  sections.push([
    `### ${name}`, '', line + '.', '',
    '| region (farthest sample) | distance | far samples | degree | normals turn | sharpest in region | result edge there |',
    '|---|---:|---:|---:|---:|---:|---:|',
    ...regions.slice(0, SHOWN).map((g) => `| ${g.at.map((x) => x.toFixed(3)).join(', ')} | ${(100 * g.d).toFixed(3)}% | ${g.count} | ${g.degree} | ` +
                                          `${g.angle.toFixed(0)}° | ${g.sharpest.toFixed(0)}° | ${(100 * g.edge).toFixed(2)}% |`),
    ...(regions.length > SHOWN ? [`| (${regions.length - SHOWN} more regions) | | | | | | |`] : []),
    '',
  ].join('\n'));
}

let commit = 'unknown';
try {
  commit = execFileSync('git', ['rev-parse', '--short', 'HEAD'], { encoding: 'utf8' }).trim();
} catch {}
const text = `# Where the remeshing misses the input

Written by \`node bench/remesh-far.mjs ${names.join(' ')}\`: each model remeshed as in bench/remesh.mjs (defaults,
\`repair: true\`), then the samples of the repaired input (vertices, face centroids and three interior points per face,
as the measure takes them) farther than 0.5% of the bounding-box diagonal from
the result (the input→result side of issue 12's Hausdorff goal), grouped into regions ${100 * REGION}% of the diagonal
across, the ${SHOWN} farthest shown. "Normals turn": the largest angle between the normals of two faces at the vertex
(for a face sample: its sharpest corner; over 90°: a spike tip or a thin lip). "Result edge there": the mean edge of the result triangle closest to the
region's farthest sample. Distances and edges in % of the diagonal.

Machine: ${cpus().length} x ${cpus()[0]?.model ?? 'unknown'}, Node ${process.version}, load average ${loadavg()[0].toFixed(2)}
(shared with other jobs); sources: commit ${commit}; date: ${new Date().toISOString()}.

${sections.join('\n')}`;
if (write) writeFileSync(fileURLToPath(new URL('./RESULTS-remesh-far.md', import.meta.url)), text);
