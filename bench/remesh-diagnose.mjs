#!/usr/bin/env node
// Where and at which stage a remeshing leaves the input (issue 12's 0.5% goal): remeshes a corpus
// model as bench/remesh.mjs does (defaults, repair; `parametrise: false` unless --parametrise) with
// remesh()'s debug hook, and prints for each fit of each piece: the base's distance both ways, the
// fit's farthest vertex before and after the untangling (and how many far vertices the untangling
// moved), and for the chosen result the farthest points both ways with their positions.
//
//   node bench/remesh-diagnose.mjs NAME [--parametrise] [--scale S]
// --scale: the model scaled by S about the origin first (the poses of bench/remesh-poses.mjs).
import { readFileSync } from 'node:fs';
import { createMrvol } from '../lib/node.mjs';
import { remesh, repair, Surface } from '../lib/remesh.mjs';
import { CORPUS, makeCorpus } from '../scripts/corpus.mjs';

const args = process.argv.slice(2);
const scaleAt = args.indexOf('--scale'), scale = scaleAt >= 0 ? Number(args.splice(scaleAt, 2)[1]) : 1;
const name = args.find((a) => !a.startsWith('--'));
const c = CORPUS.find((x) => x.name === name);
if (!c) throw new Error(`not in the corpus: ${name}`);
await makeCorpus({ big: true, names: [name] });
const mrvol = await createMrvol();
const read = mrvol.readMesh(readFileSync(c.file), { name: c.file });
const input = { positions: read.positions.map((x) => x * scale), faces: read.faces };
const repaired = repair(input).mesh;
const surface = new Surface(repaired);
const diagonal = surface.diagonal;
const pct = (d) => `${(100 * d / diagonal).toFixed(3)}%`;
const centroids = (m) => {
  const out = new Float64Array(m.faces.length);
  for (let f = 0; f < m.faces.length / 3; f++)
    for (let k = 0; k < 3; k++) out[3 * f + k] = (m.positions[3 * m.faces[3 * f] + k] + m.positions[3 * m.faces[3 * f + 1] + k] + m.positions[3 * m.faces[3 * f + 2] + k]) / 3;
  return out;
};
const max = (a) => a.reduce((x, y) => Math.max(x, y), 0);
// side: whether a far input point is outside the result (a part cut off) or inside (a pocket bridged).
let sideOf = null;
const far = (points, distances, limit, shown = 6) => {
  const list = [];
  for (let i = 0; i < distances.length; i++) if (distances[i] > limit) list.push([distances[i], i]);
  list.sort((a, b) => b[0] - a[0]);
  const chosen = [];
  for (const [d, i] of list) {
    if (chosen.length >= shown) break;
    if (chosen.some(([, j]) => Math.hypot(points[3 * i] - points[3 * j], points[3 * i + 1] - points[3 * j + 1], points[3 * i + 2] - points[3 * j + 2]) < 0.02 * diagonal)) continue;
    chosen.push([d, i]);
  }
  return { count: list.length, shown: chosen.map(([d, i]) => `${pct(d)} at (${[0, 1, 2].map((k) => points[3 * i + k].toFixed(3)).join(', ')})${sideOf ? sideOf(points, i) : ''}`) };
};
const limit = 0.005 * diagonal;
let pending = null;
const debug = (event, data) => {
  if (event === 'fitted') {
    const base = new Surface(data.base, { normals: false });
    const baseFrom = max(base.distances(repaired.positions)); base.dispose();
    const baseTo = max(surface.distances(data.base.positions));
    const d = surface.distances(data.mesh.positions);
    pending = { data, d, line: `piece ${data.piece}, ${data.levels} levels, base ${data.base.faces.length / 3} faces (input→base ${pct(baseFrom)}, base vertices→input ${pct(baseTo)}); fit vertices→input max ${pct(max(d))}, ${d.filter((x) => x > limit).length} beyond 0.5%, ${data.flipped.length} flipped` };
  } else if (event === 'untangled') {
    const d = surface.distances(data.mesh.positions);
    const before = pending.d, p0 = pending.data.mesh.positions, p1 = data.mesh.positions;
    let moved = 0, farMoved = 0;
    for (let v = 0; v < d.length; v++) {
      const m = Math.hypot(p0[3 * v] - p1[3 * v], p0[3 * v + 1] - p1[3 * v + 1], p0[3 * v + 2] - p1[3 * v + 2]) > 0;
      if (m) moved++;
      if (m && d[v] > limit && before[v] <= limit) farMoved++;
    }
    const cd = surface.distances(centroids(data.mesh));
    console.log(`${pending.line}; after untangling: vertices max ${pct(max(d))} (${d.filter((x) => x > limit).length} beyond), centroids max ${pct(max(cd))}; ${moved} vertices moved, ${farMoved} of them newly beyond 0.5%; flipped left ${data.flippedTriangles}`);
  } else if (event === 'chosen') {
    const r = data.mesh, rs = new Surface(r);
    sideOf = (p, i) => {
      const h = rs.closest(p[3 * i], p[3 * i + 1], p[3 * i + 2]), n = rs.normal(h.faceIndex);
      return (p[3 * i] - h.point.x) * n[0] + (p[3 * i + 1] - h.point.y) * n[1] + (p[3 * i + 2] - h.point.z) * n[2] > 0 ? ' outside' : ' inside';
    };
    const toV = surface.distances(r.positions), toC = surface.distances(centroids(r));
    const fromV = rs.distances(repaired.positions), fromC = rs.distances(centroids(repaired));
    rs.dispose();
    console.log(`chosen before the drag: result→input ${pct(data.measured.toInput)}, input→result ${pct(data.measured.fromInput)}`);
    console.log('  result vertices far:', JSON.stringify(far(r.positions, toV, limit)));
    console.log('  result centroids far:', JSON.stringify(far(centroids(r), toC, limit)));
    const box = [0, 1, 2].map((k) => { let lo = Infinity, hi = -Infinity; for (let v = k; v < repaired.positions.length; v += 3) lo = Math.min(lo, repaired.positions[v]), hi = Math.max(hi, repaired.positions[v]); return `${lo.toFixed(1)}..${hi.toFixed(1)}`; });
    console.log(`  input box ${box.join(' x ')}`);
    console.log('  input vertices far:', JSON.stringify(far(repaired.positions, fromV, limit)));
    console.log('  input centroids far:', JSON.stringify(far(centroids(repaired), fromC, limit)));
    sideOf = null;
  }
};
const t = performance.now();
const r = await remesh(mrvol, input, { repair: true, parametrise: args.includes('--parametrise'), debug });
console.log(`result: ${pct(r.hausdorff * diagonal)} (result→input ${pct(r.hausdorffToInput * diagonal)}, input→result ${pct(r.hausdorffFromInput * diagonal)}), cage ${r.baseVertices}, ${r.vertices} vertices, untangled ${r.untangledTriangles}, ${((performance.now() - t) / 1000).toFixed(1)} s`);
console.log('fits:', JSON.stringify(r.fits));
