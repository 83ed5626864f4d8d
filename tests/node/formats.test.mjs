// Mesh files other than OBJ through the real WASM module and the CLI: every variant in
// tests/data/good reads like octahedron.obj; files written by other tools (three.js's
// STLExporter, PLYExporter, GLTFExporter) from the sample models read back to the same mesh
// and volume; writeGlb output opens in three.js's GLTFLoader; hostile files
// (tests/data/bad/expected-formats.json) fail with their messages, the module instance working on.
import { test, describe, before } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync, writeFileSync, readdirSync, copyFileSync } from 'node:fs';
import { join } from 'node:path';
import * as THREE from 'three';
import { STLExporter } from 'three/examples/jsm/exporters/STLExporter.js';
import { PLYExporter } from 'three/examples/jsm/exporters/PLYExporter.js';
import { GLTFExporter } from 'three/examples/jsm/exporters/GLTFExporter.js';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
import { createMrvol, MrvolError } from '../../lib/node.mjs';
import { ROOT, tempFolder, runCliSync, json, failsWith, usageError, loadModel } from './helpers.mjs';

// GLTFExporter reads its Blob with FileReader, which Node lacks: the same two reads over Blob.arrayBuffer().
globalThis.FileReader ??= class {
  readAsArrayBuffer(blob) {
    blob.arrayBuffer().then((b) => { this.result = b; this.onloadend?.(); });
  }
  readAsDataURL(blob) {
    blob.arrayBuffer().then((b) => {
      this.result = `data:${blob.type || 'application/octet-stream'};base64,${Buffer.from(b).toString('base64')}`;
      this.onloadend?.();
    });
  }
};

const good = (name) => join(ROOT, 'tests/data/good', name);
const bad = (name) => join(ROOT, 'tests/data/bad', name);
const bytesOf = (path) => new Uint8Array(readFileSync(path));
const file = tempFolder('mrvol-formats-test-');

let mrvol;
before(async () => {
  mrvol = await createMrvol();
});

// Triangles as position triples, each rotated to start at its smallest corner, sorted: equal for
// two meshes with the same triangles whatever the vertex numbering.
function canonicalTriangles(mesh, round = (x) => x) {
  const out = [];
  for (let f = 0; f < mesh.faces.length; f += 3) {
    const corners = [0, 1, 2].map((k) => Array.from(mesh.positions.subarray(3 * mesh.faces[f + k], 3 * mesh.faces[f + k] + 3), round));
    const key = corners.map((c) => c.join(' '));
    let start = 0;
    for (let k = 1; k < 3; ++k) if (compare(corners[k], corners[start]) < 0) start = k;
    out.push([0, 1, 2].map((k) => key[(start + k) % 3]).join(' | '));
  }
  return out.sort();
}
function compare(a, b) {
  for (let k = 0; k < 3; ++k) if (a[k] !== b[k]) return a[k] - b[k];
  return 0;
}

function assertSameMesh(actual, expected, what, round) {
  assert.equal(actual.positions.length, expected.positions.length, `${what}: vertex count`);
  assert.equal(actual.faces.length, expected.faces.length, `${what}: face count`);
  assert.deepEqual(canonicalTriangles(actual, round), canonicalTriangles(expected, round), `${what}: triangles`);
}

describe('readMesh through WASM', () => {
  test('every variant in tests/data/good reads like octahedron.obj', () => {
    const reference = mrvol.readObj(readFileSync(good('octahedron.obj'), 'utf8'));
    const variants = {
      'octahedron-ascii.stl': ['stl', 'ASCII STL'], 'octahedron-binary.stl': ['stl', 'binary STL'],
      'octahedron-binary-solid-header.stl': ['stl', 'binary STL'], 'octahedron-ascii.ply': ['ply', 'ASCII PLY'],
      'octahedron-binary-le.ply': ['ply', 'binary little-endian PLY'], 'octahedron-binary-be.ply': ['ply', 'binary big-endian PLY'],
      'octahedron.off': ['off', 'OFF'], 'octahedron.coff': ['off', 'COFF'], 'octahedron.noff': ['off', 'NOFF'],
      'octahedron-embedded.gltf': ['gltf', 'glTF'], 'octahedron.glb': ['glb', 'GLB'], 'octahedron-soup-and-fan.glb': ['glb', 'GLB'],
    };
    for (const [name, [format, variant]] of Object.entries(variants)) {
      const m = mrvol.readMesh(bytesOf(good(name)), { name });
      assert.equal(m.format, format, name);
      assert.equal(m.variant, variant, name);
      assert.ok(m.positions instanceof Float64Array && m.faces instanceof Uint32Array);
      assertSameMesh(m, reference, name);
      assert.equal(mrvol.volume(m), 4 / 3, name);
      assert.equal(m.sourceVertex.length, m.positions.length / 3);
    }
    // STL: 24 corners welded to 6 vertices.
    const stl = mrvol.readMesh(bytesOf(good('octahedron-binary.stl')));
    assert.deepEqual([stl.sourceVertices, stl.welded], [24, 18]);
    // OBJ through readMesh keeps the lines readObj records.
    const obj = mrvol.readMesh(bytesOf(good('octahedron.obj')), { name: 'octahedron.obj' });
    assert.equal(obj.format, 'obj');
    assert.deepEqual(Array.from(obj.lines.face), [9, 10, 11, 12, 13, 14, 15, 16]);
  });

  test('a .gltf sidecar buffer is passed as a resource; quads become fans', () => {
    const reference = mrvol.readObj(readFileSync(good('octahedron.obj'), 'utf8'));
    const m = mrvol.readMesh(bytesOf(good('octahedron-sidecar.gltf')), {
      name: 'octahedron-sidecar.gltf', resources: { 'octahedron-sidecar.bin': bytesOf(good('octahedron-sidecar.bin')) } });
    assertSameMesh(m, reference, 'sidecar');
    assert.throws(() => mrvol.readMesh(bytesOf(good('octahedron-sidecar.gltf'))),
                  { name: 'MrvolError', message: /buffer 0 refers to the file 'octahedron-sidecar.bin', which was not given/ });
    for (const name of ['cube-quads.ply', 'cube-quads.off']) {
      const cube = mrvol.readMesh(bytesOf(good(name)));
      assert.deepEqual([cube.triangulated, cube.faces.length / 3, mrvol.volume(cube)], [6, 12, 1], name);
    }
  });

  test('detectFormat: content first, then the extension', () => {
    assert.equal(mrvol.detectFormat(bytesOf(good('octahedron.glb')), 'renamed.obj'), 'glb');
    assert.equal(mrvol.detectFormat(bytesOf(good('octahedron-binary.stl'))), 'stl');
    assert.equal(mrvol.detectFormat(bytesOf(good('octahedron-binary-solid-header.stl')), 'x.stl'), 'stl');
    assert.throws(() => mrvol.detectFormat(bytesOf(bad('zip-renamed.glb')), 'zip-renamed.glb'),
                  { name: 'MrvolError', message: /^not a GLB file: .*\(looks like a ZIP archive\)$/ });
    assert.throws(() => mrvol.readMesh('text'), MrvolError);
  });
});

// ---- files written by other tools -----------------------------------------------------------------

function geometryOf(mesh, { indexed = true } = {}) {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(mesh.positions), 3));
  g.setIndex(new THREE.BufferAttribute(new Uint32Array(mesh.faces), 1));
  g.computeVertexNormals();
  return indexed ? g : g.toNonIndexed();
}

const SAMPLES = ['icosahedron', 'spiky-ball', 'torus', 'bunny-remeshed'];

describe('files written by three.js exporters read back to the same mesh', () => {
  for (const name of SAMPLES) {
    test(name, async () => {
      const obj = loadModel(mrvol, name);
      const rounded = { positions: Float64Array.from(new Float32Array(obj.positions)), faces: obj.faces };
      const volume = mrvol.volume(rounded);
      const levels = (() => { const mr = mrvol.openMesh(obj); const l = mr.levels; mr.delete(); return l; })();
      const mesh = new THREE.Mesh(geometryOf(obj));
      const soup = new THREE.Mesh(geometryOf(obj, { indexed: false }));
      const outputs = {
        'binary.stl': new Uint8Array(new STLExporter().parse(mesh, { binary: true }).buffer),
        'ascii.stl': new TextEncoder().encode(new STLExporter().parse(soup)),
        'ascii.ply': new TextEncoder().encode(new PLYExporter().parse(mesh, undefined, { binary: false })),
        'binary.ply': new Uint8Array(new PLYExporter().parse(mesh, undefined, { binary: true, littleEndian: true })),
        'binary-be.ply': new Uint8Array(new PLYExporter().parse(soup, undefined, { binary: true, littleEndian: false })),
        'model.glb': new Uint8Array(await new GLTFExporter().parseAsync(mesh, { binary: true })),
        'model.gltf': new TextEncoder().encode(JSON.stringify(await new GLTFExporter().parseAsync(soup, { binary: false }))),
      };
      for (const [kind, bytes] of Object.entries(outputs)) {
        const what = `${name} ${kind}`;
        const m = mrvol.readMesh(bytes, { name: kind });
        // ASCII STL prints floats in decimal: compare through float32 there too.
        assertSameMesh(m, rounded, what, (x) => Math.fround(x));
        assert.ok(Math.abs(mrvol.volume(m) - volume) <= 1e-6 * Math.abs(volume), `${what}: volume ${mrvol.volume(m)} vs ${volume}`);
        const mr = mrvol.openMesh(m);
        assert.equal(mr.levels, levels, `${what}: hierarchy detected`);
        mr.delete();
      }
    });
  }
});

// ---- GLB export ------------------------------------------------------------------------------------

describe('writeGlb', () => {
  test('reads back exactly (float32) and opens in three.js GLTFLoader', async () => {
    const obj = loadModel(mrvol, 'spiky-ball');
    const glb = mrvol.writeGlb(obj);
    assert.ok(glb instanceof Uint8Array);
    const back = mrvol.readMesh(glb, { name: 'out.glb' });
    assert.deepEqual(back.faces, obj.faces);
    assert.deepEqual(back.positions, Float64Array.from(new Float32Array(obj.positions)));
    // GLTFLoader.parse needs no DOM for a geometry-only file: no textures or images to decode.
    const gltf = await new GLTFLoader().parseAsync(glb.buffer.slice(glb.byteOffset, glb.byteOffset + glb.byteLength), '');
    const meshes = [];
    gltf.scene.traverse((o) => o.isMesh && meshes.push(o));
    assert.equal(meshes.length, 1);
    const g = meshes[0].geometry;
    assert.deepEqual(Array.from(g.index.array), Array.from(obj.faces));
    assert.deepEqual(Array.from(g.attributes.position.array), Array.from(new Float32Array(obj.positions)));
    assert.equal(g.attributes.normal.count, obj.positions.length / 3);
    assert.throws(() => mrvol.writeGlb({ positions: new Float64Array(0), faces: new Uint32Array(0) }), MrvolError);
  });
});

describe('writeGlb with the source glTF', () => {
  test("keeps a GLTFExporter file's material, texture coordinates and node transform; the CLI edit too", async () => {
    const obj = loadModel(mrvol, 'spiky-ball');
    const g = geometryOf(obj);
    const uv = new Float32Array((obj.positions.length / 3) * 2).map((_, i) => (i * 0.618) % 1);
    g.setAttribute('uv', new THREE.BufferAttribute(uv, 2));
    const object = new THREE.Mesh(g, new THREE.MeshStandardMaterial({ name: 'painted', color: 0x3366ff }));
    object.name = 'ball';
    object.position.set(1, 2, 3);
    object.scale.set(2, 2, 2);
    const glb = new Uint8Array(await new GLTFExporter().parseAsync(object, { binary: true }));
    const m = mrvol.readMesh(glb, { name: 'ball.glb' });
    assert.ok(Math.abs(mrvol.volume(m) - 8 * mrvol.volume(obj)) <= 1e-6 * 8 * mrvol.volume(obj));
    // Move every vertex outwards by 5% about (1, 2, 3), in the world frame the reader gives.
    const edited = m.positions.map((x, i) => [1, 2, 3][i % 3] + 1.05 * (x - [1, 2, 3][i % 3]));
    const out = mrvol.writeGlb({ positions: edited, faces: m.faces }, { source: m.source });
    const back = mrvol.readMesh(out, { name: 'out.glb' });
    assert.deepEqual(back.faces, m.faces);
    for (let i = 0; i < edited.length; i++) assert.ok(Math.abs(back.positions[i] - edited[i]) <= 1e-5, `${i}`);
    const gltf = await new GLTFLoader().parseAsync(out.buffer.slice(out.byteOffset, out.byteOffset + out.byteLength), '');
    const loaded = gltf.scene.getObjectByName('ball');
    assert.equal(loaded.material.name, 'painted');
    assert.deepEqual(loaded.position.toArray(), [1, 2, 3]);
    assert.deepEqual(Array.from(loaded.geometry.attributes.uv.array), Array.from(uv));
    // Local positions: the edit undone through the node transform (scale 2 about (1, 2, 3)).
    const local = loaded.geometry.attributes.position.array;
    for (let i = 0; i < local.length; i++) assert.ok(Math.abs(local[i] - 1.05 * Math.fround(obj.positions[i])) <= 1e-5, `${i}`);
    // Changed triangles cannot keep the source.
    const other = Uint32Array.from(m.faces);
    [other[0], other[1]] = [other[1], other[0]];
    assert.throws(() => mrvol.writeGlb({ positions: edited, faces: other }, { source: m.source }),
                  { name: 'MrvolError', message: /triangles differ from its source glTF's/ });
    // The CLI: edit a GLB, write a GLB: the material stays.
    writeFileSync(file('ball.glb'), glb);
    json(runCliSync(['edit', file('ball.glb'), '--move', '0:0.05,0,0', '-o', file('ball-edited.glb'), '--json']));
    const edited2 = readFileSync(file('ball-edited.glb'));
    const edgltf = await new GLTFLoader().parseAsync(edited2.buffer.slice(edited2.byteOffset, edited2.byteOffset + edited2.byteLength), '');
    assert.equal(edgltf.scene.getObjectByName('ball').material.name, 'painted');
  });
});

// ---- hostile files ---------------------------------------------------------------------------------

const manifest = JSON.parse(readFileSync(bad('expected-formats.json'), 'utf8')).files;
const hostile = readdirSync(join(ROOT, 'tests/data/bad')).filter((n) => !/\.(obj|json|mjs)$/.test(n)).sort();

function assertMessage(message, parts, what) {
  let from = 0;
  for (const part of parts) {
    const at = message.indexOf(part, from);
    assert.ok(at >= 0, `${what}: message ${JSON.stringify(message)} lacks ${JSON.stringify(part)}`);
    from = at;
  }
}

describe('hostile files', () => {
  test('every file is listed in expected-formats.json', () => {
    assert.deepEqual(hostile, Object.keys(manifest).sort());
  });

  test('WASM: each fails with its message, and the same module keeps working', () => {
    const octahedron = bytesOf(good('octahedron.glb'));
    for (const name of hostile) {
      let error;
      try {
        mrvol.validate(mrvol.readMesh(bytesOf(bad(name)), { name }));
      } catch (e) {
        error = e;
      }
      assert.ok(error instanceof MrvolError, `${name}: expected a MrvolError, got ${error}`);
      assertMessage(error.message, manifest[name].error, name);
      assert.equal(mrvol.volume(mrvol.readMesh(octahedron)), 4 / 3);
    }
  });

  test('CLI: exit 1 and one line naming the file', () => {
    for (const name of hostile) {
      const r = runCliSync(['info', bad(name)], { timeout: 30000 });
      failsWith(r);
      assert.ok(r.stderr.startsWith(`mrvol: error: ${bad(name)}: `), r.stderr);
      assertMessage(r.stderr, manifest[name].error, name);
    }
  });
});

// ---- the command line ------------------------------------------------------------------------------

describe('CLI', () => {
  test('info reads every format like the OBJ', () => {
    const expected = json(runCliSync(['info', good('octahedron.obj'), '--json']));
    for (const name of ['octahedron-binary.stl', 'octahedron-ascii.ply', 'octahedron.noff', 'octahedron.glb',
                        'octahedron-embedded.gltf', 'octahedron-sidecar.gltf']) {
      const r = json(runCliSync(['info', good(name), '--json']));
      assert.equal(r.volume, expected.volume, name);
      assert.equal(r.vertices, expected.vertices, name);
      assert.equal(r.faces, expected.faces, name);
    }
    // A renamed file is read by content.
    copyFileSync(good('octahedron-binary-be.ply'), file('no-extension'));
    assert.equal(json(runCliSync(['info', file('no-extension'), '--json'])).volume, expected.volume);
  });

  test('subdivide a PLY base to GLB, edit the GLB keeping the volume, write OBJ and GLB', () => {
    const sub = json(runCliSync(['subdivide', good('octahedron-binary-le.ply'), '--levels', '2', '-o', file('sub.glb'), '--json']));
    assert.equal(sub.vertices, 66);
    const info = json(runCliSync(['info', file('sub.glb'), '--json']));
    assert.equal(info.levels, 2);
    for (const out of ['edited.glb', 'edited.obj']) {
      const r = json(runCliSync(['edit', file('sub.glb'), '--move', '0:0.1,0,0', '-o', file(out), '--json']));
      assert.ok(r.relativeError <= 1e-5);
      const m = mrvol.readMesh(bytesOf(file(out)), { name: out });
      const v = mrvol.volume(m);
      // GLB rounds positions to float32.
      assert.ok(Math.abs(v - r.volumeReference) <= (out.endsWith('.glb') ? 1e-6 : 1e-9) * r.volumeReference, `${out}: ${v}`);
    }
    usageError(runCliSync(['subdivide', good('octahedron.off'), '--levels', '1', '-o', file('x.stl')]),
               /cannot write .*x\.stl: mrvol writes \.obj and \.glb/);
  });
});
