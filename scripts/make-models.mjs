#!/usr/bin/env node
// `npm run models`: (re)generates the sample models in public/models and their README, with the
// real WASM module through the public JS API (lib/node.mjs). Deterministic: no randomness, fixed
// parameters; running it twice gives the same files byte for byte.
//
//   node scripts/make-models.mjs [--check]    (--check also runs make-remeshed-models.mjs --check)
//
// Every model is checked before it is written: it is read back from its OBJ text, its hierarchy is
// detected with the intended number of levels and base vertices, it is closed with the intended
// genus, its volume is positive, it has no self-intersections (exhaustive triangle-pair test) and
// its Loop/Butterfly/linear analysis-synthesis round trip is exact to rounding. With --check
// nothing is written: the files on disk are compared with what would be generated.
import { spawnSync } from 'node:child_process';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { createMrvol } from '../lib/node.mjs';
import { finishReadme, sampleObjText, writeOrCheckModel } from './models-readme.mjs';

const root = join(dirname(fileURLToPath(import.meta.url)), '..');
const outDir = join(root, 'public/models');
const checkOnly = process.argv.includes('--check');

const mrvol = await createMrvol();

// ---- small vector helpers ---------------------------------------------------------------------

const PHI = (1 + Math.sqrt(5)) / 2;

function mesh(positions, faces) {
  return { positions: Float64Array.from(positions), faces: Uint32Array.from(faces) };
}

/** Scales every vertex to length `radius` (centred at the origin). */
function projectToSphere(positions, radius = 1) {
  const out = new Float64Array(positions.length);
  for (let i = 0; i < positions.length; i += 3) {
    const x = positions[i], y = positions[i + 1], z = positions[i + 2];
    const s = radius / Math.hypot(x, y, z);
    out[i] = x * s, out[i + 1] = y * s, out[i + 2] = z * s;
  }
  return out;
}

// ---- base meshes --------------------------------------------------------------------------------

/**
 * The regular icosahedron with unit circumradius: the standard vertices (0, ±1, ±phi) and their
 * cyclic permutations, divided by sqrt(1 + phi^2). Faces counter-clockwise seen from outside.
 */
function icosahedron() {
  const raw = [-1, PHI, 0, 1, PHI, 0, -1, -PHI, 0, 1, -PHI, 0, 0, -1, PHI, 0, 1, PHI,
               0, -1, -PHI, 0, 1, -PHI, PHI, 0, -1, PHI, 0, 1, -PHI, 0, -1, -PHI, 0, 1];
  const faces = [0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4, 11, 10, 2, 10, 7, 6, 7, 1, 8,
                 3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8, 3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8, 1];
  return mesh(projectToSphere(raw), faces);
}

/** The regular octahedron with unit circumradius (vertices ±e_i). */
function octahedron() {
  return mesh([1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1],
              [0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5]);
}

/** Torus point at angles u (around the z axis) and v (around the tube). */
function torusPoint(R, r, u, v) {
  return [(R + r * Math.cos(v)) * Math.cos(u), (R + r * Math.cos(v)) * Math.sin(u), r * Math.sin(v)];
}

/**
 * A coarse torus: nu x nv grid of quads (nu, nv even), split along alternating diagonals like a
 * checkerboard, so that its vertices have valence 8 and 4. (With one diagonal direction everywhere
 * every vertex has valence 6, the subdivided torus is translation-invariant and hierarchy detection
 * may pick any of the 64 translated copies of the base vertex set.)
 */
function gridTorus(nu, nv, place) {
  const positions = [], faces = [];
  for (let i = 0; i < nu; ++i)
    for (let j = 0; j < nv; ++j) positions.push(...place((2 * Math.PI * i) / nu, (2 * Math.PI * j) / nv));
  const id = (i, j) => ((i + nu) % nu) * nv + ((j + nv) % nv);
  for (let i = 0; i < nu; ++i)
    for (let j = 0; j < nv; ++j) {
      const a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      if ((i + j) % 2 === 0) faces.push(a, b, c, a, c, d);
      else faces.push(a, b, d, b, c, d);
    }
  return mesh(positions, faces);
}

// ---- checks ---------------------------------------------------------------------------------------

const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];

// Does the open segment p-q cross triangle (a, b, c)? (Moeller-Trumbore, with a small tolerance
// that counts touching as crossing.)
function segmentHitsTriangle(p, q, a, b, c) {
  const d = sub(q, p), e1 = sub(b, a), e2 = sub(c, a);
  const h = cross(d, e2), det = dot(e1, h);
  const scale = Math.sqrt(dot(e1, e1) * dot(e2, e2) * dot(d, d));
  if (Math.abs(det) <= 1e-12 * scale) return false;  // parallel: no transversal crossing
  const s = sub(p, a), u = dot(s, h) / det;
  if (u < -1e-9 || u > 1 + 1e-9) return false;
  const qv = cross(s, e1), v = dot(d, qv) / det;
  if (v < -1e-9 || u + v > 1 + 1e-9) return false;
  const t = dot(e2, qv) / det;
  return t > 1e-9 && t < 1 - 1e-9;
}

/**
 * Exhaustive self-intersection test over all triangle pairs (bounding boxes first). Pairs without
 * a shared vertex: any edge of one crossing the other. Pairs sharing one vertex: the edge opposite
 * the shared vertex crossing the other triangle. Pairs sharing an edge: folded onto each other
 * (dihedral angle below 10 degrees). Returns the number of intersecting pairs.
 */
function selfIntersections({ positions, faces }) {
  const nf = faces.length / 3;
  const P = (i) => [positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]];
  const box = new Float64Array(6 * nf);
  for (let f = 0; f < nf; ++f)
    for (let k = 0; k < 3; ++k) {
      const lo = Math.min(positions[3 * faces[3 * f] + k], positions[3 * faces[3 * f + 1] + k], positions[3 * faces[3 * f + 2] + k]);
      const hi = Math.max(positions[3 * faces[3 * f] + k], positions[3 * faces[3 * f + 1] + k], positions[3 * faces[3 * f + 2] + k]);
      box[6 * f + k] = lo, box[6 * f + 3 + k] = hi;
    }
  let count = 0;
  for (let f = 0; f < nf; ++f)
    for (let g = f + 1; g < nf; ++g) {
      if (box[6 * f] > box[6 * g + 3] || box[6 * g] > box[6 * f + 3] || box[6 * f + 1] > box[6 * g + 4] ||
          box[6 * g + 1] > box[6 * f + 4] || box[6 * f + 2] > box[6 * g + 5] || box[6 * g + 2] > box[6 * f + 5]) continue;
      const A = [faces[3 * f], faces[3 * f + 1], faces[3 * f + 2]], B = [faces[3 * g], faces[3 * g + 1], faces[3 * g + 2]];
      const shared = A.filter((v) => B.includes(v));
      const pa = A.map(P), pb = B.map(P);
      let hit = false;
      if (shared.length === 0) {
        for (let k = 0; k < 3 && !hit; ++k)
          hit = segmentHitsTriangle(pa[k], pa[(k + 1) % 3], ...pb) || segmentHitsTriangle(pb[k], pb[(k + 1) % 3], ...pa);
      } else if (shared.length === 1) {
        const ka = A.indexOf(shared[0]), kb = B.indexOf(shared[0]);
        hit = segmentHitsTriangle(pa[(ka + 1) % 3], pa[(ka + 2) % 3], ...pb) ||
              segmentHitsTriangle(pb[(kb + 1) % 3], pb[(kb + 2) % 3], ...pa);
      } else {
        const na = cross(sub(pa[1], pa[0]), sub(pa[2], pa[0])), nb = cross(sub(pb[1], pb[0]), sub(pb[2], pb[0]));
        hit = dot(na, nb) < -Math.cos((10 * Math.PI) / 180) * Math.sqrt(dot(na, na) * dot(nb, nb));
      }
      if (hit) ++count;
    }
  return count;
}

/** Smallest and largest edge length, smallest triangle angle (degrees). */
function shapeStats({ positions, faces }) {
  let minEdge = Infinity, maxEdge = 0, minAngle = 180;
  const P = (i) => [positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]];
  for (let f = 0; f < faces.length; f += 3) {
    const p = [P(faces[f]), P(faces[f + 1]), P(faces[f + 2])];
    for (let k = 0; k < 3; ++k) {
      const e1 = sub(p[(k + 1) % 3], p[k]), e2 = sub(p[(k + 2) % 3], p[k]);
      const l = Math.sqrt(dot(e1, e1));
      minEdge = Math.min(minEdge, l), maxEdge = Math.max(maxEdge, l);
      const cos = dot(e1, e2) / Math.sqrt(dot(e1, e1) * dot(e2, e2));
      minAngle = Math.min(minAngle, (Math.acos(Math.max(-1, Math.min(1, cos))) * 180) / Math.PI);
    }
  }
  return { minEdge, maxEdge, minAngle };
}

function radiusRange({ positions }) {
  let lo = Infinity, hi = 0;
  for (let i = 0; i < positions.length; i += 3) {
    const r = Math.hypot(positions[i], positions[i + 1], positions[i + 2]);
    lo = Math.min(lo, r), hi = Math.max(hi, r);
  }
  return [lo, hi];
}

// ---- the models -------------------------------------------------------------------------------

// Each model: name, description lines for the OBJ header and the README, the mesh (hierarchy order
// as the API gives it: base vertices first), and the intended levels / base vertices / genus.
const models = [];

// 1. The icosahedron itself: a base mesh (0 levels).
{
  const m = icosahedron();
  models.push({
    name: 'icosahedron', mesh: m, levels: 0, baseVertices: 12, genus: 0,
    summary: 'Regular icosahedron, unit circumradius.',
    how: ['The 12 vertices (0, ±1, ±φ) and their cyclic permutations (φ = (1 + √5) / 2), divided by √(1 + φ²)',
          'so that every vertex lies on the unit sphere (circumradius 1, edge length 1.0514622).',
          'The base mesh of the other sphere-like models; 0 levels (no 1-to-4 split).'],
  });
}

// 2. The spiky ball: icosahedron base, n = 3, spikes as Loop wavelet details of a round ball.
// One spike over the centre of each of the 20 icosahedron faces: outward radial details on the 3
// depth-3 vertices nearest the face centre (5.2 degrees from it) and on the 3 depth-2 vertices
// around them (10.3 degrees). Spikes need sparse details: the lifted Loop wavelets have (nearly)
// vanishing moments, so the same radial detail on every vertex of a level (for example all 30
// depth-1 vertices) mostly cancels out.
const SPIKES = [{ depth: 3, maxAngle: 8, length: 0.6 }, { depth: 2, maxAngle: 12, length: 0.4 }];
{
  const ico = icosahedron();
  const sphere = mrvol.subdivide(ico, { levels: 3, scheme: 'loop' });
  const ball = projectToSphere(sphere.positions());  // the round ball: Loop icosphere on the unit sphere
  const depths = sphere.depths();
  const centres = [];
  for (let f = 0; f < ico.faces.length; f += 3) {
    const c = [0, 1, 2].map((k) => ico.positions[3 * ico.faces[f]+ k] + ico.positions[3 * ico.faces[f + 1] + k] +
                                   ico.positions[3 * ico.faces[f + 2] + k]);
    centres.push([...projectToSphere(c)]);
  }
  const coeffs = sphere.analyze(ball, { level: 0, scheme: 'loop' });
  const counts = SPIKES.map(() => 0);
  for (let v = 0; v < depths.length; ++v) {
    const p = [ball[3 * v], ball[3 * v + 1], ball[3 * v + 2]];
    const angle = (Math.acos(Math.min(1, Math.max(...centres.map((c) => dot(c, p))))) * 180) / Math.PI;
    const k = SPIKES.findIndex((s) => s.depth === depths[v] && angle < s.maxAngle);
    if (k < 0) continue;
    // Added to the small details the round ball already has.
    for (let d = 0; d < 3; ++d) coeffs[3 * v + d] += SPIKES[k].length * p[d];
    ++counts[k];
  }
  const positions = sphere.synthesize(coeffs, { level: 0, scheme: 'loop' });
  const m = { positions, faces: sphere.faces() };
  sphere.delete();
  models.push({
    name: 'spiky-ball', mesh: m, levels: 3, baseVertices: 12, genus: 0, starShaped: true,
    summary: `Bouncing ball with ${centres.length} spikes that are Loop wavelet details on a round ball.`,
    how: ['Round ball: 3 levels of Loop subdivision of icosahedron.obj, every vertex then projected on the unit sphere.',
          'Loop analysis of the ball to level 0 (default weights α = -1.70943, β = 0.42954): base vertices hold',
          'the coarse coefficients, all other vertices details.',
          `Spikes, one over the centre of each of the ${centres.length} icosahedron faces: an outward radial vector added to the`,
          'detail coefficients of',
          ...SPIKES.map((s, k) => `- the ${counts[k]} depth-${s.depth} vertices less than ${s.maxAngle}° from a face centre (${counts[k] / centres.length} per face): length ${s.length}`),
          'then Loop synthesis back to level 3. The coarse mesh (base coefficients) is the round ball\'s; the',
          'update step of the Loop wavelets lowers the surface a little around each spike.',
          'Why not the 30 depth-1 vertices: the lifted Loop wavelets have (nearly) vanishing moments, so one',
          'radial detail on every vertex of a level mostly cancels out (0.5 on all 30 depth-1 vertices leaves',
          'the radius between 0.92 and 1.004: no spikes); spikes need sparse details.'],
  });
}

// 3. The torus: genus 1, 6 x 4 quads split into triangles, n = 3, every vertex on an exact torus.
const TORUS = { R: 1, r: 0.4, nu: 6, nv: 4 };
{
  const { R, r, nu, nv } = TORUS;
  // The vertices' angles (u, v) are found by subdividing unit-circle embeddings with the linear
  // scheme one level at a time and renormalising: the midpoint of two unit vectors points at the
  // bisecting angle, so every vertex lands on the uniform 8nu x 8nv grid of angles.
  let uMesh = gridTorus(nu, nv, (u) => [Math.cos(u), Math.sin(u), 0]);
  let vMesh = gridTorus(nu, nv, (u, v) => [Math.cos(v), Math.sin(v), 0]);
  const normalise2 = (p) => {
    for (let i = 0; i < p.length; i += 3) {
      const l = Math.hypot(p[i], p[i + 1]);
      p[i] /= l, p[i + 1] /= l;
    }
    return p;
  };
  for (let l = 0; l < 3; ++l) {
    const mu = mrvol.subdivide(uMesh, { levels: 1, scheme: 'linear' }), mv = mrvol.subdivide(vMesh, { levels: 1, scheme: 'linear' });
    uMesh = { positions: normalise2(mu.positions()), faces: mu.faces() };
    vMesh = { positions: normalise2(mv.positions()), faces: mv.faces() };
    mu.delete(), mv.delete();
  }
  if (uMesh.faces.some((f, i) => f !== vMesh.faces[i])) throw new Error('torus: the two subdivisions disagree');
  const n = uMesh.positions.length / 3, positions = new Float64Array(3 * n);
  for (let i = 0; i < n; ++i) {
    const u = Math.atan2(uMesh.positions[3 * i + 1], uMesh.positions[3 * i]);
    const v = Math.atan2(vMesh.positions[3 * i + 1], vMesh.positions[3 * i]);
    positions.set(torusPoint(R, r, u, v), 3 * i);
  }
  const m = { positions, faces: uMesh.faces };
  models.push({
    name: 'torus', mesh: m, levels: 3, baseVertices: nu * nv, genus: 1,
    exactVolume: 2 * Math.PI * Math.PI * R * r * r,
    summary: `Torus (R = ${R}, r = ${r}), genus 1, every vertex on the exact torus.`,
    how: [`Base: ${nu} x ${nv} quads of the torus (${nu} around the z axis, ${nv} around the tube), split along alternating`,
          `diagonals (checkerboard): ${nu * nv} vertices of valence 8 and 4, ${2 * nu * nv} triangles. (With one diagonal direction`,
          'everywhere all vertices would have valence 6 and hierarchy detection could take any of 64 translated',
          'vertex sets as the base; the irregular valences make the detected base these 24 vertices.)',
          '3 levels of 1-to-4 splits; every vertex placed on the torus at its parametric angles, which makes',
          `the fine mesh the uniform ${8 * nu} x ${8 * nv} grid of angles (computed by linear subdivision of the unit-circle`,
          'embeddings of both angles, renormalised after each level).',
          `Exact torus volume 2π²Rr² = ${(2 * Math.PI * Math.PI * R * r * r).toFixed(6)}; the mesh is inscribed, so its volume is smaller.`],
  });
}

// 4. The blob: octahedron base, n = 4, smooth low-frequency radial bumps.
const BUMPS = [  // direction, amplitude, angular width (radians)
  { d: [0.6, 0.7, 0.4], a: 0.35, w: 0.4 },
  { d: [-0.8, 0.1, 0.55], a: 0.3, w: 0.45 },
  { d: [0.1, -0.6, -0.8], a: 0.3, w: 0.4 },
  { d: [-0.3, -0.9, 0.3], a: -0.15, w: 0.35 },
  { d: [0.8, -0.3, 0.1], a: 0.25, w: 0.35 },
  { d: [-0.4, 0.6, -0.7], a: 0.2, w: 0.5 },
];
{
  const oct = octahedron();
  const sphere = mrvol.subdivide(oct, { levels: 4, scheme: 'loop' });
  const dirs = projectToSphere(sphere.positions());
  const bumps = BUMPS.map(({ d, a, w }) => ({ c: [...projectToSphere(d)], a, w }));
  const positions = new Float64Array(dirs.length);
  for (let i = 0; i < dirs.length; i += 3) {
    const p = [dirs[i], dirs[i + 1], dirs[i + 2]];
    let radius = 1;
    for (const { c, a, w } of bumps) {
      const angle = Math.acos(Math.max(-1, Math.min(1, dot(p, c))));
      radius += a * Math.exp(-(angle * angle) / (2 * w * w));
    }
    positions[i] = radius * p[0], positions[i + 1] = radius * p[1], positions[i + 2] = radius * p[2];
  }
  const m = { positions, faces: sphere.faces() };
  sphere.delete();
  models.push({
    name: 'blob', mesh: m, levels: 4, baseVertices: 6, genus: 0, starShaped: true,
    summary: `Smooth blob: a sphere with ${BUMPS.length} broad radial bumps and dents.`,
    how: ['Base: the regular octahedron (vertices ±e_x, ±e_y, ±e_z); 4 levels of Loop subdivision, every vertex',
          'then projected on the unit sphere (direction p) and moved to radius',
          '1 + Σ a_k exp(-θ_k² / (2 w_k²)), θ_k the angle between p and the bump direction c_k:',
          ...BUMPS.map(({ d, a, w }) => `c = (${d.join(', ')}) normalised, a = ${a}, w = ${w}`)],
  });
}

// ---- check, write, document ---------------------------------------------------------------------

function fmt(x, digits = 6) {
  return Number(x.toPrecision(digits)).toString();
}

function checkModel(model, text) {
  const fail = (what) => { throw new Error(`${model.name}: ${what}`); };
  const read = mrvol.readObj(text);
  const mr = mrvol.openMesh(read);
  const info = mr.info();
  if (info.levels !== model.levels) fail(`detected ${info.levels} levels, expected ${model.levels}`);
  if (info.baseVertices !== model.baseVertices) fail(`detected ${info.baseVertices} base vertices, expected ${model.baseVertices}`);
  if (!info.closed || info.components !== 1) fail('not a closed connected mesh');
  if (info.genus !== model.genus) fail(`genus ${info.genus}, expected ${model.genus}`);
  if (!(info.volume > 0)) fail(`volume ${info.volume} is not positive (orientation?)`);
  const intersections = selfIntersections(read);
  if (intersections) fail(`${intersections} self-intersecting triangle pairs`);
  if (model.starShaped) {
    // Every face seen counter-clockwise from the centre: radial projection is one-to-one.
    const { positions: p, faces: f } = read;
    for (let i = 0; i < f.length; i += 3) {
      const a = [p[3 * f[i]], p[3 * f[i] + 1], p[3 * f[i] + 2]];
      const b = [p[3 * f[i + 1]], p[3 * f[i + 1] + 1], p[3 * f[i + 1] + 2]];
      const c = [p[3 * f[i + 2]], p[3 * f[i + 2] + 1], p[3 * f[i + 2] + 2]];
      if (!(dot(cross(a, b), c) > 0)) fail(`face ${i / 3} is not star-shaped around the origin`);
    }
  }
  const roundtrip = {};
  if (info.levels > 0)
    for (const scheme of ['loop', 'butterfly', 'linear']) {
      roundtrip[scheme] = mr.roundtripError({ level: 0, scheme });
      if (!(roundtrip[scheme] < 1e-12)) fail(`${scheme} round trip error ${roundtrip[scheme]}`);
    }
  mr.delete();
  return { info, roundtrip, shape: shapeStats(read), radius: radiusRange(read) };
}

const generator = 'scripts/make-models.mjs';
const rows = [];
const sections = [];
let changed = 0;
for (const model of models) {
  const text = sampleObjText(model, generator, mrvol.writeObj({ positions: Float64Array.from(model.mesh.positions), faces: Uint32Array.from(model.mesh.faces) }));
  const { info, roundtrip, shape, radius } = checkModel(model, text);
  changed += writeOrCheckModel(join(outDir, `${model.name}.obj`), model.name, text, checkOnly);
  process.stderr.write(`models: ${model.name}.obj: ${info.vertices} vertices, ${info.faces} faces, ${info.levels} levels, ` +
                       `${info.baseVertices} base vertices, genus ${info.genus}, volume ${fmt(info.volume, 8)}\n`);
  rows.push(`| [${model.name}.obj](${model.name}.obj) | ${info.vertices} | ${info.faces} | ${info.levels} | ${info.baseVertices} | ` +
            `${info.genus} | ${fmt(info.volume, 8)} |`);
  const facts = [
    `- ${info.vertices} vertices, ${info.faces} faces, ${info.levels} levels, ${info.baseVertices} base vertices ` +
      `(indices ${info.baseVertices === info.vertices ? 'all' : `${info.baseVertexIndices[0]}..${info.baseVertexIndices[info.baseVertices - 1]}`}), ` +
      `closed, genus ${info.genus}, volume ${fmt(info.volume, 10)}` +
      (model.exactVolume ? ` (exact torus: ${fmt(model.exactVolume, 10)})` : '') + '.',
    `- Distance from the origin ${fmt(radius[0], 5)} .. ${fmt(radius[1], 5)}; edge lengths ${fmt(shape.minEdge, 4)} .. ` +
      `${fmt(shape.maxEdge, 4)}; smallest triangle angle ${fmt(shape.minAngle, 3)}°.`,
    '- Checked: no self-intersections (all triangle pairs)' + (model.starShaped ? ', star-shaped around the origin' : '') +
      (info.levels > 0 ? `, analysis-synthesis round trip to level 0 exact to ${fmt(Math.max(...Object.values(roundtrip)), 2)}` +
                         ' (Loop, Butterfly, linear)' : '') + '.',
  ];
  sections.push(`## ${model.name}.obj\n\n${model.summary}\n\n${model.how.join('\n')}\n\n${facts.join('\n')}\n`);
}

const readme = `# Sample models

Closed semi-regular triangle meshes for trying mrvol: \`mrvol info\`, \`mrvol roundtrip\`, the web
editor. All are generated by [\`${generator}\`](../../${generator}) (\`npm run models\`) with the WASM
core through the JS API (lib/node.mjs); the script is deterministic and checks every model before
writing it (hierarchy detected with the intended levels, closed, genus, positive volume, no
self-intersecting triangle pairs, exact analysis-synthesis round trip). This file is written by the
same script: edit the script, not this file.

Vertex order: the hierarchy order the API gives, base vertices first, then the vertices born at
level 1, level 2 ... Faces are counter-clockwise seen from outside. Coordinates are written with 17
significant digits. Each file starts with \`#\` comment lines saying how it was made.

| file | vertices | faces | levels | base vertices | genus | volume |
|---|---:|---:|---:|---:|---:|---:|
${rows.join('\n')}

${sections.join('\n')}`;

// scripts/make-remeshed-models.mjs keeps its own part at the end of the README, after a marker
// line (scripts/models-readme.mjs): this script owns the text before it and keeps the rest. With
// --check both are checked: the remeshed models through that script's own --check.
const status = finishReadme(join(outDir, 'README.md'), null, readme,
  { checkOnly, changed, what: 'models', written: `${models.length} models and README.md to public/models` });
if (checkOnly) {
  const remeshed = spawnSync(process.execPath, [join(root, 'scripts/make-remeshed-models.mjs'), '--check'], { stdio: 'inherit' });
  process.exitCode = status || remeshed.status !== 0 ? 1 : 0;
}
