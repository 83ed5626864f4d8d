// OBJ through the WASM module: readObj of a Uint8Array (bytes straight into the heap) and of a
// string, polygons (triangulated, counted), vt/vn/colours kept, writeObjLike (an edit keeps the
// file's other lines), and the CLI: `mrvol info` reads a quad mesh and says it is not
// semi-regular; `mrvol edit` writes the original file with the new positions.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync, writeFileSync } from 'node:fs';
import { createMrvol, MrvolError } from '../../lib/node.mjs';
import { tempFolder, runCliSync, json, model, throwsMrvol } from './helpers.mjs';

const mrvol = await createMrvol();
const file = tempFolder('mrvol-obj-test-');
const mrvolCli = (...args) => runCliSync(args, { timeout: 60000 });

const CUBE = '# a unit cube of quads\r\nmtllib cube.mtl\r\no cube\r\n' +
  'v 0 0 0 1 0 0\r\nv 1 0 0 0 1 0\r\nv 0 1 0 0 0 1\r\nv 1 1 0 1 1 0\r\nv 0 0 1 1 0 1\r\nv 1 0 1 0 1 1\r\nv 0 1 1 1 1 1\r\nv 1 1 1 0 0 0\r\n' +
  'vt 0 0\r\nvt 1 0\r\nvt 1 1\r\nvt 0 1\r\nvn 0 0 -1\r\ng sides\r\nusemtl white\r\ns 1\r\n' +
  'f 1/1/1 3/4/1 4/3/1 2/2/1\r\nf 5 6 8 7\r\nf 1//1 2//1 6//1 5//1\r\nf 3/1 7/2 8/3 4/4\r\nf -8 -4 -2 -6\r\nf 2 4 8 6\r\n';

test('readObj: a Uint8Array and a string give the same mesh', () => {
  const text = readFileSync(model('spiky-ball'), 'utf8');
  const fromBytes = mrvol.readObj(readFileSync(model('spiky-ball')));
  const fromText = mrvol.readObj(text);
  assert.ok(fromBytes.positions instanceof Float64Array && fromBytes.faces instanceof Uint32Array);
  assert.equal(fromBytes.positions.length, 3 * 642);
  assert.deepEqual(fromBytes.positions, fromText.positions);
  assert.deepEqual(fromBytes.faces, fromText.faces);
  assert.deepEqual(fromBytes.lines, fromText.lines);
  assert.equal(fromBytes.polygons, 0);
  // A Node Buffer that is a view into a larger pool is read from its own bytes only.
  const pooled = Buffer.from('# padding\n' + text).subarray('# padding\n'.length);
  assert.deepEqual(mrvol.readObj(pooled).positions, fromText.positions);
});

test('readObj: a cube of quads (every face form, CRLF, colours) is triangulated and closed', () => {
  for (const input of [CUBE, new TextEncoder().encode(CUBE)]) {
    const mesh = mrvol.readObj(input);
    assert.equal(mesh.polygons, 6);
    assert.equal(mesh.polygonTriangles, 12);
    assert.equal(mesh.faces.length, 36);
    assert.deepEqual(Array.from(mesh.lines.face.slice(0, 4)), [20, 20, 21, 21]);
    assert.deepEqual(Array.from(mesh.texCoords), [0, 0, 1, 0, 1, 1, 0, 1]);
    assert.deepEqual(Array.from(mesh.normals), [0, 0, -1]);
    assert.equal(mesh.colors.length, 24);
    assert.equal(mesh.cornerTexCoords.length, 36);
    assert.deepEqual(Array.from(mesh.cornerTexCoords.slice(0, 6)), [0, 3, 2, 0, 2, 1]);
    assert.equal(mesh.cornerTexCoords[6], 0xffffffff);
    const mr = mrvol.openMesh(mesh);
    const info = mr.info();
    mr.delete();
    assert.equal(info.levels, 0);
    assert.equal(info.closed, true);
    assert.ok(Math.abs(info.volume - 1) < 1e-15, `volume ${info.volume}`);
  }
});

test('readObj: faces referring to vt / vn lines the file lacks: the mesh read, those attributes left out and said (dropped)', () => {
  const text = 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nvn 0 0 1\nf 1/1/1 3/1/1 2/1/1\nf 1/9/1 2/1/1 4/1/1\nf 1 4 3\nf 2 3 4\n';
  for (const input of [text, new TextEncoder().encode(text)]) {
    const mesh = mrvol.readObj(input);
    assert.equal(mesh.faces.length, 12);
    assert.equal(mesh.cornerTexCoords, undefined);
    assert.equal(mesh.cornerNormals.length, 12, 'the normals are consistent: kept');
    assert.equal(mesh.dropped, 'texture coordinates left out: face corners refer to vt 9, and the file has 1 vt line');
  }
  // the chunked reader (a file over one chunk) says the same
  const reader = mrvol.createObjReader();
  reader.push(new TextEncoder().encode(text));
  assert.equal(reader.finish().dropped, 'texture coordinates left out: face corners refer to vt 9, and the file has 1 vt line');
  assert.equal(mrvol.readObj(CUBE).dropped, undefined);
  // mrvol info names it
  writeFileSync(file('bad-vt.obj'), text);
  const info = mrvolCli('info', file('bad-vt.obj'));
  assert.equal(info.status, 0, info.stderr);
  assert.equal(json(mrvolCli('info', file('bad-vt.obj'), '--json')).leftOut, mrvol.readObj(text).dropped);
  assert.match(info.stdout, /^left out {7}texture coordinates left out: face corners refer to vt 9, and the file has 1 vt line$/m);
});

test('readObj: hostile polygons fail with their line, as MrvolError', () => {
  const square = 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n';
  throwsMrvol(() => mrvol.readObj(square + 'f 1 2\n'), 'line 5: face has 2 vertices, a triangle needs 3');
  throwsMrvol(() => mrvol.readObj(square + 'f 0 1 2 3\n'), 'line 5: face index 0 is not valid (OBJ indices start at 1)');
  throwsMrvol(() => mrvol.readObj('f -1 -2 -3 -4\n' + square), "line 1: relative face index '-1' reaches before the first vertex (0 vertices so far)");
  throwsMrvol(() => mrvol.readObj(square + 'f 1 2 1 3\n'), 'line 5: polygon with 4 vertices uses vertex 1 more than once');
  // (a repeat of the corner before, the last of the first included, is left out: 'f 1 2 3 1' is the triangle)
  assert.deepEqual(Array.from(mrvol.readObj(square + 'f 1 2 3 1\n').faces), [0, 1, 2]);
  throwsMrvol(() => mrvol.readObj(new Uint8Array([...new TextEncoder().encode(square), 0xef, 0xbb, 0xbf, 0x66, 0x20, 0x31, 0x20, 0x32, 0x20, 0x33])),
              "line 5: unknown statement '???f': this does not look like an OBJ file");
  throwsMrvol(() => mrvol.writeObjLike(square + 'f 1 2 3 4\n', new Float64Array(9)), 'the original OBJ has 4 vertices but 3 positions were given');
  throwsMrvol(() => mrvol.writeObjLike(square + 'f 1 2 3 4\n', [0, 0, 0]), 'positions must be a Float64Array');
});

test('writeObjLike: the original file with new positions, every other line kept', () => {
  const mesh = mrvol.readObj(CUBE);
  assert.equal(mrvol.writeObjLike(CUBE, mesh.positions), CUBE, 'unchanged positions: the same text');
  const moved = mesh.positions.slice();
  moved[23] = 2;  // vertex 7 z: 1 -> 2
  const text = mrvol.writeObjLike(CUBE, moved);
  assert.equal(typeof text, 'string');
  const before = CUBE.split('\r\n'), after = text.split('\r\n');
  assert.equal(after.length, before.length);
  for (let i = 0; i < before.length; ++i) {
    if (i === 10) assert.equal(after[i], 'v 1 1 2 0 0 0');
    else assert.equal(after[i], before[i], `line ${i + 1}`);
  }
  const bytes = mrvol.writeObjLike(new TextEncoder().encode(CUBE), moved);
  assert.ok(bytes instanceof Uint8Array);
  assert.equal(new TextDecoder().decode(bytes), text);
  assert.deepEqual(mrvol.readObj(bytes).positions, moved);
});

test('mrvol info on a quad OBJ: read, not semi-regular, polygons counted', () => {
  writeFileSync(file('cube.obj'), CUBE);
  const r = mrvolCli('info', file('cube.obj'));
  assert.equal(r.status, 0, r.stderr);
  assert.match(r.stdout, /^semi-regular\s+no /m);
  assert.match(r.stdout, /^polygons\s+6 \(triangulated into 12 triangles\)$/m);
  assert.match(r.stdout, /^levels\s+0$/m);
  const j = json(mrvolCli('info', file('cube.obj'), '--json'));
  assert.equal(j.semiRegular, false);
  assert.equal(j.polygons, 6);
  assert.equal(j.faces, 12);
  const spiky = json(mrvolCli('info', model('spiky-ball'), '--json'));
  assert.equal(spiky.semiRegular, true);
  assert.equal(spiky.polygons, 0);
});

test('mrvol edit writes the original file with the new positions (comments and other lines kept)', () => {
  const original = readFileSync(model('spiky-ball'), 'utf8');
  const decorated = original.replace(/^v /m, 'mtllib ball.mtl\ng ball\nv ');
  writeFileSync(file('ball.obj'), decorated);
  const r = mrvolCli('edit', file('ball.obj'), '--move', '3:0.1,0.2,-0.1', '-o', file('ball-edited.obj'));
  assert.equal(r.status, 0, r.stderr);
  const edited = readFileSync(file('ball-edited.obj'), 'utf8');
  const a = decorated.split('\n'), b = edited.split('\n');
  assert.equal(b.length, a.length);
  let changed = 0;
  for (let i = 0; i < a.length; ++i) {
    if (a[i].startsWith('v ')) changed += a[i] !== b[i];
    else assert.equal(b[i], a[i], `line ${i + 1} is not a vertex and must be kept`);
  }
  assert.ok(changed > 0);
  const moved = mrvol.readObj(edited), input = mrvol.readObj(decorated);
  assert.deepEqual(moved.faces, input.faces);
  assert.ok([0, 1, 2].some((k) => moved.positions[9 + k] !== input.positions[9 + k]), 'vertex 3 moved');
});

test('a MrvolError, not a crash, for a non-OBJ argument', () => {
  assert.throws(() => mrvol.readObj({}), MrvolError);
});

// three.js's OBJExporter writes a non-indexed geometry (its polyhedra, for one) with three v lines per
// triangle, and vt / vn per corner. The vertices are welded on reading, so the icosphere opens as the
// semi-regular mesh it is (a 4x4 split of each face: two levels); an edit written with writeObjLike
// keeps every line of the file and moves each v line of a welded vertex alike; the CLI says so.
test('an OBJ from three.js\'s OBJExporter (a vertex per corner): welded, opens semi-regular, written back line for line', async () => {
  const THREE = await import('three');
  const { OBJExporter } = await import('three/examples/jsm/exporters/OBJExporter.js');
  const geometry = new THREE.IcosahedronGeometry(1, 3);
  assert.equal(geometry.index, null, 'three.js gives it non-indexed');
  const text = new OBJExporter().parse(new THREE.Mesh(geometry));
  const vLines = text.split('\n').filter((l) => l.startsWith('v ')).length;
  assert.equal(vLines, 960);
  const mesh = mrvol.readObj(text);
  assert.equal(mesh.positions.length / 3, 162);
  assert.equal(mesh.welded, 960 - 162);
  assert.equal(mesh.lines.vertex.length, 162);
  assert.equal(mesh.texCoords.length, 2 * 960, 'vt lines as the file has them');
  // the same from bytes, and through readMesh (whose sourceVertex gives each vertex's first v line)
  assert.deepEqual(mrvol.readObj(new TextEncoder().encode(text)).faces, mesh.faces);
  const imported = mrvol.readMesh(new TextEncoder().encode(text), { name: 'ico.obj' });
  assert.deepEqual([imported.welded, imported.sourceVertex.length, imported.sourceVertices], [798, 162, 960]);
  assert.deepEqual(imported.positions, mesh.positions);
  const mr = mrvol.openMesh(mesh);
  const info = mr.info();
  assert.deepEqual([info.levels, info.baseVertices, info.closed, info.genus], [2, 12, true, 0]);
  const editor = mr.createEditor({ level: 0 });
  const volume = editor.volume();
  const report = editor.moveVertices([{ vertex: editor.cageVertices()[0], offset: [0.2, 0, 0] }]);
  assert.ok(Math.abs(editor.volume() - volume) <= 1e-5 * volume, JSON.stringify(report));
  const edited = editor.positions();
  mr.delete();
  const written = mrvol.writeObjLike(text, edited);
  const before = text.split('\n'), after = written.split('\n');
  assert.equal(after.length, before.length);
  let changed = 0;
  for (let i = 0; i < before.length; i++) {
    if (before[i].startsWith('v ')) changed += before[i] !== after[i];
    else assert.equal(after[i], before[i], `line ${i + 1} is not a vertex and is kept`);
  }
  assert.ok(changed > 0);
  const back = mrvol.readObj(written);
  assert.equal(back.welded, 798, 'the v lines of one vertex moved alike: still welded the same way');
  assert.deepEqual(back.positions, edited);
  assert.deepEqual(back.faces, mesh.faces);
  // one position per v line still writes as before
  assert.equal(mrvol.writeObjLike(text, mrvol.readObj(text).positions), text);
  throwsMrvol(() => mrvol.writeObjLike(text, edited.subarray(0, 3 * 100)),
              /the original OBJ has 960 vertices \(162 once those at one position are welded\) but 100 positions were given/);
});
