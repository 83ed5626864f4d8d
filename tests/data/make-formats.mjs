#!/usr/bin/env node
// Generates the STL, PLY, OFF, glTF and GLB test files from the octahedron of
// tests/data/good/octahedron.obj (and a cube of quads), good ones in tests/data/good and hostile
// ones in tests/data/bad (their expected messages: tests/data/bad/expected-formats.json). The
// files are committed; rerun to regenerate them byte for byte:
//   node tests/data/make-formats.mjs
import { writeFileSync } from 'node:fs';

const good = (name, bytes) => writeFileSync(new URL(`good/${name}`, import.meta.url), bytes);
const bad = (name, bytes) => writeFileSync(new URL(`bad/${name}`, import.meta.url), bytes);

// The octahedron of octahedron.obj (0-based faces).
const P = [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]];
const F = [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]];
// A unit cube of 6 quads (outward, counter-clockwise), for the fan triangulation.
const CP = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]];
const CQ = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]];

const normalOf = ([a, b, c]) => {
  const u = P[b].map((x, k) => x - P[a][k]), v = P[c].map((x, k) => x - P[a][k]);
  const n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
  const l = Math.hypot(...n);
  return n.map((x) => x / l);
};

// ---- STL ------------------------------------------------------------------------------------

function asciiStl() {
  let s = 'solid octahedron\n';
  for (const f of F) {
    s += `  facet normal ${normalOf(f).join(' ')}\n    outer loop\n`;
    for (const v of f) s += `      vertex ${P[v].join(' ')}\n`;
    s += '    endloop\n  endfacet\n';
  }
  return s + 'endsolid octahedron\n';
}

function binaryStl(header = 'binary STL of the octahedron', triangles = F, declared = triangles.length) {
  const b = Buffer.alloc(84 + 50 * triangles.length);
  b.write(header.padEnd(80, ' ').slice(0, 80), 0, 'latin1');
  b.writeUInt32LE(declared, 80);
  triangles.forEach((f, t) => {
    const o = 84 + 50 * t;
    normalOf(f).forEach((x, k) => b.writeFloatLE(x, o + 4 * k));
    f.forEach((v, c) => P[v].forEach((x, k) => b.writeFloatLE(x, o + 12 + 12 * c + 4 * k)));
  });
  return b;
}

good('octahedron-ascii.stl', asciiStl());
good('octahedron-binary.stl', binaryStl());
// Binary STL whose header starts with "solid" (many exporters do this).
good('octahedron-binary-solid-header.stl', binaryStl('solid octahedron, binary all the same'));

// ---- PLY ------------------------------------------------------------------------------------

// ASCII with extra vertex properties (normal, colour), an extra element, and an int index list.
function asciiPly() {
  let s = 'ply\nformat ascii 1.0\ncomment made by tests/data/make-formats.mjs\n';
  s += `element vertex ${P.length}\nproperty float x\nproperty float y\nproperty float z\n`;
  s += 'property float nx\nproperty float ny\nproperty float nz\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n';
  s += `element face ${F.length}\nproperty list uchar int vertex_indices\nproperty uchar flags\n`;
  s += 'element material 1\nproperty float shininess\nproperty list uchar float tint\nend_header\n';
  for (const p of P) s += `${p.join(' ')} ${p.join(' ')} 255 128 0\n`;
  for (const f of F) s += `3 ${f.join(' ')} 7\n`;
  return s + '0.5 3 1 0.5 0.25\n';
}

// Binary, with types of every kind: x float64, y float32, z int16, an extra list, ushort count of
// uint32 indices (little) or uchar count of int16 indices (big).
function binaryPly(bigEndian) {
  const header = `ply\nformat binary_${bigEndian ? 'big' : 'little'}_endian 1.0\n` +
    `element vertex ${P.length}\nproperty double x\nproperty float y\nproperty short z\nproperty list uchar uchar extra\n` +
    `element face ${F.length}\n` +
    (bigEndian ? 'property list uchar short vertex_index\n' : 'property list ushort uint vertex_indices\n') +
    'end_header\n';
  const parts = [Buffer.from(header, 'latin1')];
  for (const p of P) {
    const b = Buffer.alloc(8 + 4 + 2 + 1 + 2);
    const w = (fn, v, o) => b[`${fn}${bigEndian ? 'BE' : 'LE'}`](v, o);
    w('writeDouble', p[0], 0);
    w('writeFloat', p[1], 8);
    w('writeInt16', p[2], 12);
    b.writeUInt8(2, 14);
    b.writeUInt8(9, 15);
    b.writeUInt8(9, 16);
    parts.push(b);
  }
  for (const f of F) {
    const b = Buffer.alloc(bigEndian ? 1 + 6 : 2 + 12);
    if (bigEndian) {
      b.writeUInt8(3, 0);
      f.forEach((v, k) => b.writeInt16BE(v, 1 + 2 * k));
    } else {
      b.writeUInt16LE(3, 0);
      f.forEach((v, k) => b.writeUInt32LE(v, 2 + 4 * k));
    }
    parts.push(b);
  }
  return Buffer.concat(parts);
}

good('octahedron-ascii.ply', asciiPly());
good('octahedron-binary-le.ply', binaryPly(false));
good('octahedron-binary-be.ply', binaryPly(true));
good('cube-quads.ply', `ply\nformat ascii 1.0\nelement vertex 8\nproperty double x\nproperty double y\nproperty double z\n` +
     `element face 6\nproperty list uchar uint vertex_indices\nend_header\n` +
     CP.map((p) => p.join(' ')).join('\n') + '\n' + CQ.map((q) => `4 ${q.join(' ')}`).join('\n') + '\n');

// ---- OFF ------------------------------------------------------------------------------------

const offFaces = F.map((f) => `3 ${f.join(' ')}`).join('\n');
good('octahedron.off', `OFF\n# the octahedron\n${P.length} ${F.length} 12\n${P.map((p) => p.join(' ')).join('\n')}\n${offFaces}\n`);
good('octahedron.coff', `COFF ${P.length} ${F.length} 12\n${P.map((p) => `${p.join(' ')} 0.5 0.5 1 1`).join('\n')}\n` +
     `${F.map((f) => `3 ${f.join(' ')} 255 0 0`).join('\n')}\n`);
good('octahedron.noff', `NOFF\n\n${P.length} ${F.length} 0\n${P.map((p) => `${p.join(' ')}  ${p.join(' ')}`).join('\n')}\n${offFaces}`);
good('cube-quads.off', `OFF\n8 6 12\n${CP.map((p) => p.join(' ')).join('\n')}\n${CQ.map((q) => `4 ${q.join(' ')}`).join('\n')}\n`);

// ---- glTF / GLB -------------------------------------------------------------------------------

// A buffer with the octahedron's POSITION (float32) then its uint16 indices, and the accessors.
function octahedronBuffer() {
  const positions = Buffer.alloc(4 * 3 * P.length);
  P.flat().forEach((x, i) => positions.writeFloatLE(x, 4 * i));
  const indices = Buffer.alloc(2 * 3 * F.length);
  F.flat().forEach((v, i) => indices.writeUInt16LE(v, 2 * i));
  return Buffer.concat([positions, indices]);
}

function octahedronDocument(buffer, extra = {}) {
  return {
    asset: { version: '2.0', generator: 'tests/data/make-formats.mjs' },
    scene: 0,
    scenes: [{ nodes: [0] }],
    nodes: [{ mesh: 0 }],
    meshes: [{ primitives: [{ attributes: { POSITION: 0 }, indices: 1 }] }],
    accessors: [
      { bufferView: 0, componentType: 5126, count: P.length, type: 'VEC3', min: [-1, -1, -1], max: [1, 1, 1] },
      { bufferView: 1, componentType: 5123, count: 3 * F.length, type: 'SCALAR' },
    ],
    bufferViews: [
      { buffer: 0, byteOffset: 0, byteLength: 4 * 3 * P.length },
      { buffer: 0, byteOffset: 4 * 3 * P.length, byteLength: 2 * 3 * F.length },
    ],
    buffers: [buffer],
    ...extra,
  };
}

function glb(doc, bin, { jsonLength, binLength } = {}) {
  let json = Buffer.from(JSON.stringify(doc));
  json = Buffer.concat([json, Buffer.alloc((4 - (json.length % 4)) % 4, 0x20)]);
  const binPadded = Buffer.concat([bin, Buffer.alloc((4 - (bin.length % 4)) % 4)]);
  const header = Buffer.alloc(12), jh = Buffer.alloc(8), bh = Buffer.alloc(8);
  const total = 12 + 8 + json.length + 8 + binPadded.length;
  header.write('glTF', 0, 'latin1');
  header.writeUInt32LE(2, 4);
  header.writeUInt32LE(total, 8);
  jh.writeUInt32LE(jsonLength ?? json.length, 0);
  jh.writeUInt32LE(0x4e4f534a, 4);
  bh.writeUInt32LE(binLength ?? binPadded.length, 0);
  bh.writeUInt32LE(0x004e4942, 4);
  return Buffer.concat([header, jh, json, bh, binPadded]);
}

const bin = octahedronBuffer();
const dataUri = `data:application/octet-stream;base64,${bin.toString('base64')}`;
good('octahedron-embedded.gltf', JSON.stringify(octahedronDocument({ byteLength: bin.length, uri: dataUri }), null, 1));
good('octahedron-sidecar.gltf', JSON.stringify(octahedronDocument({ byteLength: bin.length, uri: 'octahedron-sidecar.bin' })));
good('octahedron-sidecar.bin', bin);
good('octahedron.glb', glb(octahedronDocument({ byteLength: bin.length }), bin));

// Unindexed (each triangle its own 3 vertices, welded on reading) and as two triangle fans.
{
  const soup = Buffer.alloc(4 * 9 * F.length);
  F.flat().forEach((v, i) => P[v].forEach((x, k) => soup.writeFloatLE(x, 4 * (3 * i + k))));
  const fans = [4, 0, 2, 1, 3, 0, 5, 0, 3, 1, 2, 0];  // around vertex 4, then around vertex 5
  const fanIndices = Buffer.alloc(2 * fans.length);
  fans.forEach((v, i) => fanIndices.writeUInt16LE(v, 2 * i));
  const positions = bin.subarray(0, 4 * 3 * P.length);
  const all = Buffer.concat([soup, positions, fanIndices]);
  const doc = {
    asset: { version: '2.0' },
    scenes: [{ nodes: [0, 1] }],
    nodes: [{ mesh: 0 }, { mesh: 1 }],
    meshes: [{ primitives: [{ attributes: { POSITION: 0 } }] },
             { primitives: [{ attributes: { POSITION: 1 }, indices: 2, mode: 6 }, { attributes: { POSITION: 1 }, indices: 3, mode: 6 }] }],
    accessors: [
      { bufferView: 0, componentType: 5126, count: 3 * F.length, type: 'VEC3', min: [-1, -1, -1], max: [1, 1, 1] },
      { bufferView: 1, componentType: 5126, count: P.length, type: 'VEC3', min: [-1, -1, -1], max: [1, 1, 1] },
      { bufferView: 2, componentType: 5123, count: 6, type: 'SCALAR' },
      { bufferView: 2, byteOffset: 12, componentType: 5123, count: 6, type: 'SCALAR' },
    ],
    bufferViews: [
      { buffer: 0, byteOffset: 0, byteLength: soup.length },
      { buffer: 0, byteOffset: soup.length, byteLength: positions.length },
      { buffer: 0, byteOffset: soup.length + positions.length, byteLength: fanIndices.length },
    ],
    buffers: [{ byteLength: all.length }],
  };
  // Two halves: the upper half unindexed (from the soup's first 4 triangles), the lower as a fan.
  doc.accessors[0].count = 12;
  doc.meshes[1].primitives = [doc.meshes[1].primitives[1]];
  good('octahedron-soup-and-fan.glb', glb(doc, all));
}

// Node transforms: parent TRS (translation 1 2 3, 90 degrees about z, scale 2), a child with a
// mirroring matrix (x -> -x), each instancing the octahedron.
{
  const s = Math.SQRT1_2;
  const doc = octahedronDocument({ byteLength: bin.length }, {
    scenes: [{ nodes: [0] }],
    nodes: [
      { translation: [1, 2, 3], rotation: [0, 0, s, s], scale: [2, 2, 2], mesh: 0, children: [1] },
      { matrix: [-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 10, 0, 0, 1], mesh: 0 },
    ],
  });
  good('octahedron-transforms.glb', glb(doc, bin));
}

// ---- hostile files -------------------------------------------------------------------------

// Binary STL: 8 triangles declared, the file cut in the middle of the 8th.
bad('stl-truncated.stl', binaryStl().subarray(0, 84 + 50 * 7 + 20));
// Binary STL whose count lies: 1,000 declared, bytes for 312 (the octahedron's triangles repeated).
bad('stl-count-lies.stl', binaryStl('count lies', Array.from({ length: 312 }, (_, i) => F[i % 8]), 1000));
// PLY: the header declares 1,000,000 vertices of a binary file holding 6.
{
  const b = binaryPly(false);
  bad('ply-vertex-count-lies.ply', Buffer.from(b.toString('latin1').replace('element vertex 6', 'element vertex 1000000'), 'latin1'));
}
// ASCII PLY declaring 10 faces, holding 8.
bad('ply-face-count-lies.ply', asciiPly().replace('element face 8', 'element face 10').replace(/0\.5 3 1 0\.5 0\.25\n$/, ''));
// ASCII PLY whose face 3 refers to vertex 6 (there are 6: 0..5).
bad('ply-face-index-out-of-range.ply', asciiPly().replace('3 3 0 4 7', '3 3 6 4 7'));
// GLB whose BIN chunk claims 9,999,999 bytes.
bad('glb-bad-chunk-length.glb', glb(octahedronDocument({ byteLength: bin.length }), bin, { binLength: 9999999 }));
// GLB whose JSON chunk claims more than the file.
bad('glb-json-chunk-too-long.glb', glb(octahedronDocument({ byteLength: bin.length }), bin, { jsonLength: 100000 }));
// glTF whose POSITION accessor reads 600 vertices from a 72-byte bufferView.
{
  const doc = octahedronDocument({ byteLength: bin.length, uri: dataUri });
  doc.accessors[0].count = 600;
  bad('gltf-accessor-out-of-bounds.gltf', JSON.stringify(doc));
}
// glTF whose only primitive is lines.
{
  const doc = octahedronDocument({ byteLength: bin.length, uri: dataUri });
  doc.meshes[0].primitives[0].mode = 1;
  bad('gltf-lines.gltf', JSON.stringify(doc));
}
// OFF declaring 4e9 vertices and faces in a tiny file.
bad('off-huge-counts.off', 'OFF\n4000000000 4000000000 0\n1 0 0\n-1 0 0\n0 1 0\n3 0 1 2\n');
// A ZIP archive renamed .glb (local file header, then a stored file).
bad('zip-renamed.glb', Buffer.concat([Buffer.from([0x50, 0x4b, 0x03, 0x04, 0x14, 0, 0, 0, 0, 0]),
                                      Buffer.from('model.gltf{"asset":{"version":"2.0"}}'.padEnd(118, ' '))]));
// Empty files of each extension.
for (const ext of ['stl', 'ply', 'off', 'gltf', 'glb']) bad(`empty.${ext}`, '');
