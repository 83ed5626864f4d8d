#!/usr/bin/env node
// Reading speed of the mesh formats through the WASM module (Node): a Loop-subdivided
// icosahedron (7 levels: 163,842 vertices, 327,680 triangles) as binary STL, binary PLY and GLB,
// as OBJ, ASCII PLY, OFF and ASCII STL text; and the OBJ export's speed. readMesh copies the bytes into the heap, parses, welds (STL),
// and copies the arrays out. Best of 15 runs per file (the machine is shared and noisy). A reference row: the
// file's bytes copied into the heap and nothing else, the time a reader at memory speed would take.
// Side by side in the same run, the peer a three.js page would use: three.js's loader parsing the
// same bytes into a BufferGeometry (float32, not welded), and for the STL also welded by position
// with BufferGeometryUtils.mergeVertices (its normals dropped first, else nothing merges).
//   node bench/formats.mjs        (writes bench/RESULTS-formats.md)
import { writeFileSync } from 'node:fs';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
import { OBJLoader } from 'three/examples/jsm/loaders/OBJLoader.js';
import { PLYLoader } from 'three/examples/jsm/loaders/PLYLoader.js';
import { STLLoader } from 'three/examples/jsm/loaders/STLLoader.js';
import { mergeVertices } from 'three/examples/jsm/utils/BufferGeometryUtils.js';
import { createMrvol } from '../lib/node.mjs';

const mrvol = await createMrvol();
const RUNS = 15;
const ico = mrvol.readObj(`v -1 1.618 0\nv 1 1.618 0\nv -1 -1.618 0\nv 1 -1.618 0\nv 0 -1 1.618\nv 0 1 1.618\nv 0 -1 -1.618\n` +
  `v 0 1 -1.618\nv 1.618 0 -1\nv 1.618 0 1\nv -1.618 0 -1\nv -1.618 0 1\n` +
  [[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4], [11, 10, 2], [10, 7, 6], [7, 1, 8],
   [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]]
    .map((f) => `f ${f.map((i) => i + 1).join(' ')}`).join('\n'));
const mr = mrvol.subdivide(ico, { levels: 7 });
const mesh = mr.toMesh();
mr.delete();
const nv = mesh.positions.length / 3, nf = mesh.faces.length / 3;

function binaryStl() {
  const b = Buffer.alloc(84 + 50 * nf);
  b.writeUInt32LE(nf, 80);
  for (let f = 0; f < nf; f++)
    for (let c = 0; c < 3; c++)
      for (let k = 0; k < 3; k++) b.writeFloatLE(mesh.positions[3 * mesh.faces[3 * f + c] + k], 84 + 50 * f + 12 + 12 * c + 4 * k);
  return new Uint8Array(b.buffer, b.byteOffset, b.length);
}

function binaryPly() {
  const header = Buffer.from(`ply\nformat binary_little_endian 1.0\nelement vertex ${nv}\nproperty float x\nproperty float y\n` +
    `property float z\nelement face ${nf}\nproperty list uchar int vertex_indices\nend_header\n`);
  const body = Buffer.alloc(12 * nv + 13 * nf);
  for (let i = 0; i < 3 * nv; i++) body.writeFloatLE(mesh.positions[i], 4 * i);
  for (let f = 0; f < nf; f++) {
    body.writeUInt8(3, 12 * nv + 13 * f);
    for (let c = 0; c < 3; c++) body.writeInt32LE(mesh.faces[3 * f + c], 12 * nv + 13 * f + 1 + 4 * c);
  }
  return new Uint8Array(Buffer.concat([header, body]));
}

// The text formats: float32 positions as the binary files hold them, spelt as JS spells them (shortest).
const float32 = Float32Array.from(mesh.positions);
const xyz = (v) => `${float32[3 * v]} ${float32[3 * v + 1]} ${float32[3 * v + 2]}`;
function asciiPly() {
  const lines = ['ply', 'format ascii 1.0', `element vertex ${nv}`, 'property float x', 'property float y', 'property float z',
    `element face ${nf}`, 'property list uchar int vertex_indices', 'end_header'];
  for (let v = 0; v < nv; v++) lines.push(xyz(v));
  for (let f = 0; f < nf; f++) lines.push(`3 ${mesh.faces[3 * f]} ${mesh.faces[3 * f + 1]} ${mesh.faces[3 * f + 2]}`);
  return new TextEncoder().encode(lines.join('\n') + '\n');
}
function off() {
  const lines = ['OFF', `${nv} ${nf} 0`];
  for (let v = 0; v < nv; v++) lines.push(xyz(v));
  for (let f = 0; f < nf; f++) lines.push(`3 ${mesh.faces[3 * f]} ${mesh.faces[3 * f + 1]} ${mesh.faces[3 * f + 2]}`);
  return new TextEncoder().encode(lines.join('\n') + '\n');
}
function asciiStl() {
  const lines = ['solid a'];
  for (let f = 0; f < nf; f++) {
    lines.push('  facet normal 0 0 0', '    outer loop');
    for (let c = 0; c < 3; c++) lines.push(`      vertex ${xyz(mesh.faces[3 * f + c])}`);
    lines.push('    endloop', '  endfacet');
  }
  lines.push('endsolid a');
  return new TextEncoder().encode(lines.join('\n') + '\n');
}

const files = {
  'binary STL': binaryStl(),
  'binary PLY (little-endian)': binaryPly(),
  GLB: mrvol.writeGlb(mesh),
  OBJ: new TextEncoder().encode(mrvol.writeObj(mesh)),
  'ASCII PLY': asciiPly(),
  OFF: off(),
  'ASCII STL': asciiStl(),
};

// The peers: each returns the position count it made (checked: the file's corners, or the welded vertices).
const arrayBuffer = (bytes) => bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
const positionCount = (geometry) => geometry.getAttribute('position').count;
const peers = {
  'binary STL': [['three.js STLLoader.parse', async (b) => positionCount(new STLLoader().parse(arrayBuffer(b))), 3 * nf],
    ['three.js STLLoader.parse + mergeVertices', async (b) => {
      const geometry = new STLLoader().parse(arrayBuffer(b));
      geometry.deleteAttribute('normal');
      return positionCount(mergeVertices(geometry));
    }, nv]],
  'binary PLY (little-endian)': [['three.js PLYLoader.parse', async (b) => positionCount(new PLYLoader().parse(arrayBuffer(b))), nv]],
  GLB: [['three.js GLTFLoader.parseAsync', async (b) => positionCount((await new GLTFLoader().parseAsync(arrayBuffer(b), '')).scene.children[0].geometry), nv]],
  OBJ: [['three.js OBJLoader.parse (text decoded first)', async (b) => positionCount(new OBJLoader().parse(new TextDecoder().decode(b)).children[0].geometry), 3 * nf]],
  'ASCII PLY': [['three.js PLYLoader.parse', async (b) => positionCount(new PLYLoader().parse(arrayBuffer(b))), nv]],
  OFF: [],
  'ASCII STL': [['three.js STLLoader.parse', async (b) => positionCount(new STLLoader().parse(arrayBuffer(b))), 3 * nf]],
};
const bestOf = async (run) => {
  let best = Infinity, result;
  for (let i = 0; i < RUNS; i++) {
    const t0 = performance.now();
    result = await run();
    best = Math.min(best, performance.now() - t0);
  }
  return { best, result };
};

const rows = [];
for (const [what, bytes] of Object.entries(files)) {
  const name = { 'binary STL': 'a.stl', 'binary PLY (little-endian)': 'a.ply', GLB: 'a.glb', OBJ: 'a.obj', 'ASCII PLY': 'a.ply', OFF: 'a.off',
                 'ASCII STL': 'a.stl' }[what];
  const { best, result } = await bestOf(async () => mrvol.readMesh(bytes, { name }));
  if (result.positions.length !== 3 * nv || result.faces.length !== 3 * nf) throw new Error(`${what}: wrong mesh`);
  const peerRows = [];
  for (const [peer, run, expected] of peers[what]) {
    const p = await bestOf(() => run(bytes));
    if (p.result !== expected) throw new Error(`${peer}: ${p.result} positions, expected ${expected}`);
    peerRows.push(`${peer}: ${p.best.toFixed(1)} ms (${(p.best / best).toFixed(1)}x)`);
  }
  rows.push({ what, mb: bytes.length / 1e6, ms: best, mbs: bytes.length / 1e6 / (best / 1000), peers: peerRows.join('; ') });
}
// The floor for any reader: the file's bytes copied once into the WASM heap, which readMesh does
// first (detectFormat does that copy and looks at the first bytes only). Measured on the largest file.
{
  const bytes = files['binary STL'];
  let best = Infinity;
  for (let run = 0; run < RUNS; run++) {
    const t0 = performance.now();
    if (mrvol.detectFormat(bytes, 'a.stl') !== 'stl') throw new Error('reference: not detected as STL');
    best = Math.min(best, performance.now() - t0);
  }
  rows.push({ what: 'reference: the bytes copied into the heap only (detectFormat of the STL)', mb: bytes.length / 1e6, ms: best,
              mbs: bytes.length / 1e6 / (best / 1000), peers: '' });
}

// Writing: the OBJ export (writeObj: the shortest spelling of each double that reads back as it)
// beside three.js's OBJExporter on the same mesh (float32 positions, as three.js holds them).
const exportRows = [];
{
  const ours = await bestOf(async () => mrvol.writeObj(mesh));
  const back = mrvol.readObj(ours.result);
  if (back.positions.some((x, i) => x !== mesh.positions[i])) throw new Error('writeObj: the positions do not read back exactly');
  const { BufferGeometry, BufferAttribute, Mesh } = await import('three');
  const { OBJExporter } = await import('three/examples/jsm/exporters/OBJExporter.js');
  const geometry = new BufferGeometry();
  geometry.setAttribute('position', new BufferAttribute(float32, 3));
  geometry.setIndex(new BufferAttribute(mesh.faces, 1));
  const peer = await bestOf(async () => new OBJExporter().parse(new Mesh(geometry)));
  exportRows.push(`| OBJ (writeObj) | ${(ours.result.length / 1e6).toFixed(1)} MB | ${ours.best.toFixed(1)} ms | ` +
    `${(ours.result.length / 1e6 / (ours.best / 1000)).toFixed(0)} MB/s | three.js OBJExporter.parse (float32): ${peer.best.toFixed(1)} ms ` +
    `(${(peer.best / ours.best).toFixed(1)}x), ${(peer.result.length / 1e6).toFixed(1)} MB |`);
}

const table = [`| file | size | readMesh (best of ${RUNS}) | throughput | the peer in the same run (best of ${RUNS}; its time over readMesh's) |`, '| --- | --- | --- | --- | --- |',
  ...rows.map((r) => `| ${r.what} | ${r.mb.toFixed(1)} MB | ${r.ms.toFixed(1)} ms | ${r.mbs.toFixed(0)} MB/s | ${r.peers} |`)].join('\n');
const text = `# Mesh file reading (bench/formats.mjs)\n\n${nv.toLocaleString('en')} vertices, ${nf.toLocaleString('en')} triangles ` +
  `(Loop-subdivided icosahedron, 7 levels), WASM under Node ${process.version}, ${new Date().toISOString().slice(0, 10)}:\n\n${table}\n\n` +
  `Writing (best of ${RUNS}; the positions read back bit for bit):\n\n| file | size | time | throughput | the peer in the same run |\n| --- | --- | --- | --- | --- |\n` +
  `${exportRows.join('\n')}\n\n` +
  `The binary STL is welded on reading (3 corners per triangle: 983,040 source vertices, welded through a hash table of positions; ` +
  `with ${mrvol.threads} threads here, in one block of triangles per thread, the blocks merged after). ` +
  'The reference row is the one copy of the file into the WASM heap that every read starts with: a reader at memory speed would take about that. ' +
  "The peers' geometries are float32 and, but for the mergeVertices row, not welded (the STL's 983,040 corners stay apart); readMesh's are float64, welded, validated.\n";
writeFileSync(new URL('RESULTS-formats.md', import.meta.url), text);
process.stdout.write(text);
