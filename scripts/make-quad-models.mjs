#!/usr/bin/env node
// `npm run models` (after make-models.mjs): the semi-regular quad sample models in public/models
// (Catmull-Clark hierarchies, docs/catmull-clark.md) and their part of the README, with the real
// WASM module through the public JS API. Deterministic: running it twice gives the same files byte
// for byte. Every model is checked before it is written: read back from its OBJ text as quads, its
// Catmull-Clark hierarchy detected with the intended levels and base vertices, closed, genus 0,
// positive bilinear-patch volume, no self-intersecting triangle pairs (each quad split in two),
// exact analysis-synthesis round trip. With --check nothing is written: the files on disk are
// compared with what would be generated.
//
//   node scripts/make-quad-models.mjs [--check]
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { createMrvol } from '../lib/node.mjs';
import { trianglesOfQuads } from '../lib/three/edges.mjs';
import { findSelfIntersection } from '../web/self-intersection.js';
import { finishReadme, sampleObjText, writeOrCheckModel } from './models-readme.mjs';

const root = join(dirname(fileURLToPath(import.meta.url)), '..');
const outDir = join(root, 'public/models');
const checkOnly = process.argv.includes('--check');
export const QUAD_MARKER = '<!-- Quad models: the section below is written by scripts/make-quad-models.mjs. -->';

const mrvol = await createMrvol();

/**
 * The quad base: the cube [-1, 1]^3 with each face an n x n grid of quads, every vertex then on the
 * unit sphere. Not itself a Catmull-Clark split (6 n^2 quads, n odd: not a multiple of 4), so the
 * detected base is this mesh: 8 corners of valence 3, the others of valence 4.
 */
function cubeSphereQuads(n) {
  // outward normal and (u, v) with u x v = normal: quads (i, j) (i+1, j) (i+1, j+1) (i, j+1) counter-clockwise outside
  const faces = [[[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 0, 0], [0, 0, 1], [0, 1, 0]], [[0, 1, 0], [0, 0, 1], [1, 0, 0]],
                 [[0, -1, 0], [1, 0, 0], [0, 0, 1]], [[0, 0, 1], [1, 0, 0], [0, 1, 0]], [[0, 0, -1], [0, 1, 0], [1, 0, 0]]];
  const points = [], index = new Map(), quads = [];
  const vertex = (normal, u, v, i, j) => {
    const p = [0, 1, 2].map((k) => normal[k] + (-1 + 2 * i / n) * u[k] + (-1 + 2 * j / n) * v[k]);
    const key = p.map((x) => Math.round(x * n)).join(',');
    if (!index.has(key)) {
      index.set(key, points.length);
      points.push(p);
    }
    return index.get(key);
  };
  for (const [normal, u, v] of faces)
    for (let i = 0; i < n; i++)
      for (let j = 0; j < n; j++)
        quads.push(vertex(normal, u, v, i, j), vertex(normal, u, v, i + 1, j), vertex(normal, u, v, i + 1, j + 1), vertex(normal, u, v, i, j + 1));
  const positions = points.flatMap((p) => {
    const r = Math.hypot(...p);
    return p.map((x) => x / r);
  });
  return { positions: Float64Array.from(positions), quads: Uint32Array.from(quads) };
}

// The critter's bumps: direction c (normalised), height a, width w (radians).
const BUMPS = [
  { c: [0.38, 0.15, 0.91], a: 0.75, w: 0.17, what: 'ear' },
  { c: [-0.38, 0.15, 0.91], a: 0.75, w: 0.17, what: 'ear' },
  { c: [0, 0.97, 0.25], a: 0.3, w: 0.2, what: 'nose' },
  { c: [0.5, 0.5, -0.7], a: 0.45, w: 0.18, what: 'foot' },
  { c: [-0.5, 0.5, -0.7], a: 0.45, w: 0.18, what: 'foot' },
  { c: [0.5, -0.5, -0.7], a: 0.45, w: 0.18, what: 'foot' },
  { c: [-0.5, -0.5, -0.7], a: 0.45, w: 0.18, what: 'foot' },
  { c: [0, -0.95, -0.3], a: 0.3, w: 0.16, what: 'tail' },
];
const STRETCH = [1, 1.1, 0.9]; // a slightly long, low body

/** The critter's surface point in the direction of p (any length): the bumps' radius, stretched, turned. */
function critterPoint(p) {
  const r = Math.hypot(p[0], p[1], p[2]);
  const d = [p[0] / r, p[1] / r, p[2] / r];
  let radius = 1;
  for (const { c, a, w } of BUMPS) {
    const n = Math.hypot(...c);
    const angle = Math.acos(Math.max(-1, Math.min(1, (d[0] * c[0] + d[1] * c[1] + d[2] * c[2]) / n)));
    radius += a * Math.exp(-(angle * angle) / (2 * w * w));
  }
  const q = [0, 1, 2].map((k) => radius * d[k] * STRETCH[k]);
  // turned (a rotation) to three.js's axes: up +y (the ears), front +z (the nose)
  return [-q[0], q[2], q[1]];
}

/**
 * The critter made coarse to fine, so that every level's cage lies on or near its surface: the base
 * vertices are put on the surface (they are the level-0 cage), then each level's new points (face
 * points, then edge points) get the details that put them on the surface too, and the level's
 * synthesis moves the old vertices by the vertex rule. Moving the finest vertices onto the
 * surface instead would leave the analysis to put the coarse coefficients far out (narrow bumps
 * near valence-3 corners).
 */
function critter(levels) {
  const base = cubeSphereQuads(3);
  const split = mrvol.subdivideQuads(base, { levels });
  const sphere = split.positions(), depths = split.depths();
  const x = new Float64Array(sphere.length);
  const toSurface = (v, predicted) => {
    const target = critterPoint(sphere.subarray(3 * v, 3 * v + 3));
    for (let k = 0; k < 3; k++) x[3 * v + k] = target[k] - (predicted ? predicted[3 * v + k] : 0);
  };
  for (let v = 0; v < depths.length; v++) if (depths[v] === 0) toSurface(v, null);
  for (let level = 1; level <= levels; level++) {
    const steps = split.liftingSteps({ level });
    // P_f writes the face points, P_e the edge points (reading the face points): one after the other
    for (const [k, name] of [[1, 'P_f'], [2, 'P_e']]) {
      if (steps[k - 1].name !== name) throw new Error(`level ${level}'s step ${k} is ${steps[k - 1].name}, not ${name}`);
      const predicted = split.synthesizeSteps(x, { level, steps: k });
      for (const v of steps[k - 1].targets) toSurface(v, predicted);
    }
    x.set(split.synthesizeSteps(x, { level }));
  }
  const mesh = { positions: x, quads: split.quads() };
  split.delete();
  return mesh;
}

const fmt = (x, digits) => Number(x.toPrecision(digits)).toString();

const models = [
  {
    name: 'quad-critter',
    summary: 'A four-legged critter with two ears, a semi-regular quad mesh (3 Catmull-Clark levels).',
    levels: 3,
    baseVertices: 56,
    mesh: critter(3),
    how: [
      'Base: the cube [-1, 1]³ with each face a 3 x 3 grid of quads, every vertex projected on the unit sphere:',
      '56 vertices (the 8 corners of valence 3, the others of valence 4), 54 quads (not a multiple of 4: not itself a split).',
      'The surface: in direction p (a vertex of 3 levels of Catmull-Clark subdivision of the base, `mrvol subdivide',
      '--scheme catmull-clark --levels 3`), radius 1 + Σ a_k exp(-θ_k² / (2 w_k²)) (θ_k the angle between p and c_k),',
      'scaled by (1, 1.1, 0.9) and turned so that the ears point up (+y) and the nose to +z: (x, y, z) -> (-x, z, y).',
      'Made coarse to fine so that the cages lie on the surface: the base vertices (the level-0 cage) on it, then at',
      'each level the details that put the face points and then the edge points on it; the old vertices follow the',
      'vertex rule (so the finest mesh has 3/4 of its vertices on the surface, the others near it). Bumps:',
      ...BUMPS.map(({ c, a, w, what }) => `${what}: c = (${c.join(', ')}) normalised, a = ${a}, w = ${w}`),
    ],
  },
];

// How far a cage vertex of any level may lie from the nearest fine vertex, relative to the model's
// bounding radius: far handles make the app's first framing show a small surface among them.
const CAGE_NEAR = 0.1;

/** The cage vertex of any level farthest from the fine vertices: { level, vertex, relative }. */
function farthestCageVertex(mr, positions) {
  const count = positions.length / 3, depths = mr.depths();
  const center = [0, 1, 2].map((k) => positions.reduce((sum, x, i) => (i % 3 === k ? sum + x : sum), 0) / count);
  let radius = 0;
  for (let i = 0; i < count; i++)
    radius = Math.max(radius, Math.hypot(...[0, 1, 2].map((k) => positions[3 * i + k] - center[k])));
  const farthest = { level: 0, vertex: 0, relative: 0 };
  for (let level = 0; level < mr.levels; level++) {
    const coarse = mr.analyze(positions, { level });
    for (let v = 0; v < count; v++) {
      if (depths[v] > level) continue;
      let nearest = Infinity;
      for (let i = 0; i < count; i++)
        nearest = Math.min(nearest, Math.hypot(...[0, 1, 2].map((k) => positions[3 * i + k] - coarse[3 * v + k])));
      if (nearest / radius > farthest.relative) Object.assign(farthest, { level, vertex: v, relative: nearest / radius });
    }
  }
  return farthest;
}

/** Reads the OBJ text back as quads and checks it; returns its facts. */
function checkModel(model, text) {
  const read = mrvol.readObjQuads(text);
  const mr = mrvol.openQuadMesh(read);
  try {
    const info = mr.info();
    const fail = (what) => { throw new Error(`${model.name}: ${what}`); };
    if (info.levels !== model.levels) fail(`${info.levels} levels detected, ${model.levels} intended`);
    if (info.baseVertices !== model.baseVertices) fail(`${info.baseVertices} base vertices, ${model.baseVertices} intended`);
    if (!info.closed || info.genus !== 0) fail(`not a closed genus-0 surface (closed ${info.closed}, genus ${info.genus})`);
    if (!(info.volume > 0)) fail(`volume ${info.volume} is not positive`);
    const roundtrip = mr.roundtripError({ level: mr.lowestLevel });
    if (!(roundtrip < 1e-12)) fail(`analysis-synthesis round trip error ${roundtrip}`);
    const found = findSelfIntersection(read.positions, trianglesOfQuads(read.quads));
    if (found.intersects) fail(`triangles ${found.pair[0]} and ${found.pair[1]} intersect`);
    const cageDistance = farthestCageVertex(mr, read.positions);
    if (!(cageDistance.relative <= CAGE_NEAR)) fail(`level-${cageDistance.level} cage vertex ${cageDistance.vertex} is ` +
      `${fmt(cageDistance.relative, 3)} of the model's radius from the surface (at most ${CAGE_NEAR}: the app frames the surface and its cages together)`);
    return { info, roundtrip, cageDistance, triangulatedVolume: mrvol.volume({ positions: read.positions, faces: trianglesOfQuads(read.quads) }) };
  } finally {
    mr.delete();
  }
}

const generator = 'scripts/make-quad-models.mjs';
const rows = [];
const sections = [];
let changed = 0;
for (const model of models) {
  const text = sampleObjText(model, generator, mrvol.writeObjQuads(model.mesh));
  const { info, roundtrip, cageDistance, triangulatedVolume } = checkModel(model, text);
  changed += writeOrCheckModel(join(outDir, `${model.name}.obj`), model.name, text, checkOnly);
  process.stderr.write(`models: ${model.name}.obj: ${info.vertices} vertices, ${info.faces} quads, ${info.levels} levels, ` +
                       `${info.baseVertices} base vertices, bilinear-patch volume ${fmt(info.volume, 8)}\n`);
  rows.push(`| [${model.name}.obj](${model.name}.obj) | ${info.vertices} | ${info.faces} | ${info.levels} | ${info.baseVertices} | ` +
            `${info.genus} | ${fmt(info.volume, 8)} |`);
  sections.push(`### ${model.name}.obj\n\n${model.summary}\n\n${model.how.join('\n')}\n\n` +
    `- ${info.vertices} vertices, ${info.faces} quads, ${info.levels} Catmull-Clark levels over ${info.baseVertices} base vertices ` +
    `(indices ${info.baseVertexIndices[0]}..${info.baseVertexIndices[info.baseVertices - 1]}), closed, genus ${info.genus}.\n` +
    `- Volume of the bilinear patches ${fmt(info.volume, 10)} (its triangles, each quad split along one diagonal: ${fmt(triangulatedVolume, 10)}).\n` +
    `- Checked: no self-intersections (all triangle pairs of the split quads), analysis-synthesis round trip exact to ${roundtrip === 0 ? '0 (bit for bit)' : fmt(roundtrip, 2)}; ` +
    `every cage vertex (levels 0..${info.levels - 1}) within ${fmt(cageDistance.relative, 2)} of the model's radius of a fine vertex.\n`);
}

const body = `## Quad models

Semi-regular quad meshes (Catmull-Clark 1-to-4 splits, docs/catmull-clark.md) written by
[\`${generator}\`](../../${generator}), which \`npm run models\` runs after the scripts above and which replaces
this section. The web editor opens them as quad models (the catmull-clark scheme, a cage of quads, the
bilinear-patch volume); \`mrvol info --scheme catmull-clark\` reads them. Vertex order: the hierarchy order
(base vertices, then the face points and edge points of level 1, level 2 ...); faces are quads (\`f a b c d\`),
counter-clockwise seen from outside; 17 significant digits.

| file | vertices | quads | levels | base vertices | genus | volume (bilinear) |
|---|---:|---:|---:|---:|---:|---:|
${rows.join('\n')}

${sections.join('\n')}`;

process.exitCode = finishReadme(join(outDir, 'README.md'), QUAD_MARKER, body,
  { checkOnly, changed, what: 'quad models', written: `${models.length} quad model(s) and their README part to public/models` });
