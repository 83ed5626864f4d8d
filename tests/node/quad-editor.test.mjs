// The quad editor beside the triangle editor, through the real WASM module and the command line:
// the cage polynomial built from the fine quads (its gradient equals theta^e's and the matrix-free
// one's cage part), 'auto' choosing it on a coarse cage, free lists and free details, and the same
// JS surface as VolumeEditor.
import { test, describe, before } from 'node:test';
import assert from 'node:assert/strict';
import { writeFileSync, readFileSync } from 'node:fs';
import { createMrvol } from '../../lib/node.mjs';
import { tempFolder, runCliSync, json, usageError, rng, relErr, maxAbs, throwsMrvol, icosahedron, model } from './helpers.mjs';

let mrvol;
const file = tempFolder('mrvol-quad-editor-test-');
const cli = (...args) => runCliSync(args, { timeout: 60000 });

// A closed quad base with valences 3, 4 and 5: the Catmull-Clark split of a pentagonal bipyramid
// (apexes valence 5), written as quads directly (vertex, edge point, face point, edge point).
function bipyramidQuads() {
  const p = [], tris = [];
  for (let i = 0; i < 5; ++i) p.push([Math.cos(2 * Math.PI * i / 5), Math.sin(2 * Math.PI * i / 5), 0.1 * (i % 2)]);
  p.push([0.05, 0, 1.3], [0, -0.05, -1.2]);
  for (let i = 0; i < 5; ++i) tris.push([i, (i + 1) % 5, 5], [(i + 1) % 5, i, 6]);
  const mid = (...vs) => [0, 1, 2].map((k) => vs.reduce((s, v) => s + p[v][k], 0) / vs.length);
  const edge = new Map(), quads = [];
  const edgePoint = (a, b) => {
    const key = a < b ? `${a},${b}` : `${b},${a}`;
    if (!edge.has(key)) edge.set(key, p.push(mid(a, b)) - 1);
    return edge.get(key);
  };
  for (const t of tris) {
    const f = p.push(mid(...t)) - 1;
    t.forEach((v, i) => quads.push(v, edgePoint(v, t[(i + 1) % 3]), f, edgePoint(t[(i + 2) % 3], v)));
  }
  return { positions: Float64Array.from(p.flat()), quads: Uint32Array.from(quads) };
}

// Subdivided `levels` times, then every vertex moved a little (details at every level).
function detailedQuads(levels, seed) {
  const built = mrvol.subdivide(bipyramidQuads(), { levels, scheme: 'catmull-clark' });
  const m = built.toMesh();
  built.delete();
  const r = rng(seed);
  for (let i = 0; i < m.positions.length; ++i) m.positions[i] += 0.02 * (r() - 0.5);
  return m;
}

const bilinear = (editor, mesh) => mrvol.quadVolume({ positions: editor.positions(), quads: mesh.quads });

before(async () => {
  mrvol = await createMrvol();
});

describe('quad editor: the cage polynomial', () => {
  test("the polynomial's gradient is theta^e's and the matrix-free one's; 'auto' takes it on a coarse cage", () => {
    const mesh = detailedQuads(3, 5);
    const mr = mrvol.openMesh(mesh);
    assert.equal(mr.levels, 3);
    const auto = mr.createEditor({ level: 0 });
    assert.equal(auto.path(), 'polynomial');
    assert.equal(mr.createEditor({ level: 1 }).path(), 'matrix-free');  // two levels of details: the fine pass
    const theta = mr.computeTheta({ level: 0 });
    const tensor = mr.createEditor({ level: 0, theta });
    assert.equal(tensor.path(), 'tensor');
    const gp = auto.gradient('polynomial'), gt = tensor.gradient('tensor'), gm = auto.gradient('matrix-free');
    assert.equal(gp.length, 3 * auto.cageSize);
    assert.equal(gm.length, 3 * mr.vertexCount);
    const scale = maxAbs(gt);
    assert.ok(scale > 0);
    for (let i = 0; i < gp.length; ++i) {
      assert.ok(Math.abs(gp[i] - gt[i]) <= 1e-12 * scale, `polynomial vs theta at ${i}: ${gp[i]} ${gt[i]}`);
      assert.ok(Math.abs(gp[i] - gm[i]) <= 1e-12 * scale, `polynomial vs matrix-free at ${i}`);
    }
    // A drag keeps the bilinear volume on the polynomial path.
    const volume = mrvol.quadVolume(mesh);
    const vertex = auto.cageVertices()[5];
    const report = auto.moveVertices([{ vertex, offset: [0, 0, 0.5] }]);
    assert.ok(report.converged, report.message);
    assert.equal(report.path, 'polynomial');
    assert.ok(relErr(report.volumeTarget, volume) > 1e-2, 'the move changes the volume');
    assert.ok(relErr(bilinear(auto, mesh), volume) < 1e-5);
    // Explicit paths; a wrong one is named.
    const explicit = mr.createEditor({ level: 1, path: 'polynomial' });
    assert.equal(explicit.path(), 'polynomial');
    assert.equal(mr.createEditor({ level: 0, path: 'matrix-free' }).path(), 'matrix-free');
    throwsMrvol(() => mr.createEditor({ level: 0, path: 'fast' }), /gradient path must be auto, polynomial, tensor or matrix-free, got 'fast'/);
    theta.delete();
    mr.delete();
  });

  test('free lists and free details as for triangles', () => {
    const mesh = detailedQuads(2, 9);
    const mr = mrvol.openMesh(mesh);
    const volume = mrvol.quadVolume(mesh);
    const editor = mr.createEditor({ level: 0, path: 'polynomial' });
    const cageVertices = editor.cageVertices();
    // Only the listed cage vertices absorb the correction.
    const free = [cageVertices[2], cageVertices[3]];
    editor.setFreeSet({ cage: free });
    const before = editor.cagePositions();
    let report = editor.moveVertices([{ vertex: cageVertices[0], offset: [0.3, 0, 0] }]);
    assert.ok(report.converged, report.message);
    assert.equal(report.path, 'polynomial');
    const after = editor.cagePositions();
    for (let c = 1; c < editor.cageSize; ++c) {
      const moved = [0, 1, 2].some((k) => after[3 * c + k] !== before[3 * c + k]);
      assert.equal(moved, c === 2 || c === 3, `cage vertex ${c}`);
    }
    assert.ok(relErr(bilinear(editor, mesh), volume) < 1e-5);
    // Details only: the cage stays where the move puts it, the correction runs on the fine mesh.
    editor.setFreeSet({ cage: [], detailLevels: [0, 1] });
    const cageBefore = editor.cagePositions();
    report = editor.moveVertices([{ vertex: cageVertices[0], offset: [0.2, 0, 0] }]);
    assert.ok(report.converged, report.message);
    assert.equal(report.path, 'matrix-free');
    const cageAfter = editor.cagePositions();
    cageBefore[0] += 0.2;
    assert.deepEqual(Array.from(cageAfter.slice(3)), Array.from(cageBefore.slice(3)));
    assert.ok(relErr(bilinear(editor, mesh), volume) < 1e-5);
    // Back on the cage: the polynomial rebuilt for the moved details agrees with the mesh.
    editor.setFreeSet({ cage: 'minus-held' });
    editor.setReferenceVolume(1.02 * volume);
    report = editor.correct();
    assert.equal(report.path, 'polynomial');
    assert.ok(relErr(bilinear(editor, mesh), 1.02 * volume) < 1e-5);
    throwsMrvol(() => editor.setFreeSet({ cage: 'some' }), /unknown free set 'some'/);
    throwsMrvol(() => editor.setFreeSet({ detailLevels: [2] }), /free detail level 2 is out of range 0..1/);
    throwsMrvol(() => editor.setFreeSet({ cage: [mr.vertexCount - 1] }), /is not a vertex of the level-0 cage/);
    editor.delete();
    mr.delete();
  });

  test('the centre of mass of the bilinear patches, kept with the volume through a drag', () => {
    // Reference: every patch split into 16 x 16 flat triangles (cone moments), near the patches' own.
    const centroidOf = (positions, quads, m = 16) => {
      let volume = 0;
      const moment = [0, 0, 0];
      const at = (f, u, v) => [0, 1, 2].map((k) => {
        const c = (i) => positions[3 * quads[f + i] + k];
        return (1 - u) * (1 - v) * c(0) + u * (1 - v) * c(1) + u * v * c(2) + (1 - u) * v * c(3);
      });
      const cone = (a, b, c) => {
        const det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
        volume += det / 6;
        for (let k = 0; k < 3; k++) moment[k] += det * (a[k] + b[k] + c[k]) / 24;
      };
      for (let f = 0; f < quads.length; f += 4)
        for (let j = 0; j < m; j++)
          for (let i = 0; i < m; i++) {
            const p00 = at(f, i / m, j / m), p10 = at(f, (i + 1) / m, j / m), p11 = at(f, (i + 1) / m, (j + 1) / m), p01 = at(f, i / m, (j + 1) / m);
            cone(p00, p10, p11);
            cone(p00, p11, p01);
          }
      return moment.map((x) => x / volume);
    };
    const distance = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
    const mesh = detailedQuads(2, 13);
    const size = maxAbs(mesh.positions);
    const start = centroidOf(mesh.positions, mesh.quads);
    const volume = mrvol.quadVolume(mesh);
    const mr = mrvol.openMesh(mesh);
    for (const keep of [true, false]) {
      const editor = mr.createEditor({ level: 0 });
      assert.ok(distance(editor.centroid(), start) < 1e-3 * size, `${editor.centroid()} against ${start}`);
      editor.keepCentroid(keep);
      assert.equal(editor.keepsCentroid(), keep);
      const report = editor.moveVertices([{ vertex: editor.cageVertices()[0], offset: [0.4 * size, 0.2 * size, 0] }]);
      assert.ok(report.converged, report.message);
      assert.ok(relErr(bilinear(editor, mesh), volume) < 1e-5);
      const after = centroidOf(editor.positions(), mesh.quads);
      if (keep) {
        assert.ok(distance(after, start) < 2e-3 * size, `the centre of mass moved by ${distance(after, start) / size} of the size`);
        assert.ok(distance(editor.centroid(), editor.referenceCentroid()) < 1e-6 * size);
        assert.equal(report.centroidResult.length, 3);
      } else {
        assert.ok(distance(after, start) > 1e-2 * size, 'the drag moves the centre when it is not kept');
      }
      editor.delete();
    }
    mr.delete();
  });

  test('the quad editor offers what the triangle editor offers (or names what quads lack)', () => {
    const tri = mrvol.subdivide(icosahedron(), { levels: 1 });
    const quad = mrvol.openMesh(detailedQuads(1, 3));
    const te = tri.createEditor({ level: 0 }), qe = quad.createEditor({ level: 0 });
    // names starting with _ are internal hand-overs (the module transfer of big files, triangle-only)
    const methods = (o) => Object.getOwnPropertyNames(Object.getPrototypeOf(o)).filter((n) => n !== 'constructor' && !n.startsWith('_'));
    // Renderer views over WASM memory are triangle-only so far.
    const triangleOnly = ['positionsView', 'normalsView', 'surfaceVersion', 'updatedRanges'];
    const missing = methods(te).filter((m) => !methods(qe).includes(m) && !triangleOnly.includes(m));
    assert.deepEqual(missing, []);
    assert.equal(qe.surface(), 'mesh');
    assert.equal(qe.keepsCentroid(), false);
    assert.equal(qe.partVolumes().length, 0);
    qe.setParts([]);
    throwsMrvol(() => qe.setParts([[0]]), /parts\) is not available for quad meshes/);
    // createEditor's options as the triangle editor takes them: keep the centroid, or name what quads lack
    for (const keep of [['volume', 'centroid'], 'volume,centroid']) {
      const kept = quad.createEditor({ level: 0, keep });
      assert.equal(kept.keepsCentroid(), true, `keep ${JSON.stringify(keep)}`);
      const report = kept.moveVertices([{ vertex: kept.cageVertices()[0], offset: [0.1, 0, 0] }]);
      assert.ok(report.converged && report.centroidResult.length === 3, report.message);
      kept.delete();
    }
    throwsMrvol(() => quad.createEditor({ level: 0, keep: ['volume', 'inertia'] }), /keep: unknown quantity "inertia"/);
    throwsMrvol(() => quad.createEditor({ level: 0, keep: ['volume', 'centroid'], path: 'polynomial' }), /with the centroid kept use 'auto' or 'matrix-free'/);
    for (const call of [() => quad.createEditor({ level: 0, surface: 'limit' }), () => quad.info({ surface: 'limit' }),
                        () => quad.computeTheta({ level: 0, surface: 'limit' })])
      throwsMrvol(call, /surface 'limit' is the Loop limit surface of triangle meshes; a quad mesh keeps the volume of its bilinear patches/);
    assert.equal(quad.createEditor({ level: 0, surface: 'mesh' }).surface(), 'mesh');
    // a quad mesh handed to a triangle call, and triangles to a quad call: the other call named
    throwsMrvol(() => mrvol.volume(detailedQuads(0, 1)), /this is a quad mesh \{ positions, quads \} \(quadVolume gives its volume/);
    throwsMrvol(() => mrvol.openMesh({ positions: tri.positions(), faces: tri.faces() }, { scheme: 'catmull-clark' }), /readObjQuads reads an OBJ file's quads/);
    te.delete();
    qe.delete();
    tri.delete();
    quad.delete();
  });
});

describe('mrvol edit --scheme catmull-clark --path', () => {
  test('polynomial (auto on a coarse cage), free lists and details', () => {
    const mesh = detailedQuads(3, 11);
    writeFileSync(file('bi3.obj'), mrvol.writeObjQuads(mesh));
    const volume = mrvol.quadVolume(mesh);
    const edited = (name) => mrvol.quadVolume(mrvol.readObjQuads(readFileSync(file(name))));
    const auto = json(cli('edit', file('bi3.obj'), '--scheme', 'catmull-clark', '--move', '5:0,0,0.4', '-o', file('auto.obj'), '--json'));
    assert.equal(auto.path, 'polynomial');
    assert.ok(relErr(edited('auto.obj'), volume) < 1e-5);
    const asked = json(cli('edit', file('bi3.obj'), '--scheme', 'catmull-clark', '--level', '1', '--path', 'polynomial',
      '--move', '5:0,0,0.4', '-o', file('poly1.obj'), '--json'));
    assert.equal(asked.path, 'polynomial');
    assert.ok(relErr(edited('poly1.obj'), volume) < 1e-5);
    const details = json(cli('edit', file('bi3.obj'), '--scheme', 'catmull-clark', '--free', '1,2', '--free-details', '0',
      '--move', '5:0,0,0.4', '-o', file('details.obj'), '--json'));
    assert.equal(details.path, 'matrix-free');
    assert.ok(relErr(edited('details.obj'), volume) < 1e-5);
    usageError(cli('edit', file('bi3.obj'), '--scheme', 'catmull-clark', '--path', 'fast', '--move', '5:0,0,1', '-o', file('x.obj')),
      /--path must be auto, polynomial, tensor or matrix-free/);
    // The bilinear centre of mass kept with the volume (matrix-free): it stays where it was, the volume too.
    const kept = json(cli('edit', file('bi3.obj'), '--scheme', 'catmull-clark', '--keep', 'volume,centroid',
      '--move', '5:0,0,0.4', '-o', file('kept.obj'), '--json'));
    assert.equal(kept.path, 'matrix-free');
    assert.ok(relErr(edited('kept.obj'), volume) < 1e-5);
    const size = Math.cbrt(Math.abs(volume));
    assert.ok(Math.hypot(...kept.centroidAfter.map((x, k) => x - kept.centroidBefore[k])) < 1e-5 * size, JSON.stringify(kept));
    const free = json(cli('edit', file('bi3.obj'), '--scheme', 'catmull-clark', '--move', '5:0,0,0.4', '-o', file('free.obj'), '--json'));
    assert.ok(Math.hypot(...free.centroidAfter.map((x, k) => x - free.centroidBefore[k])) > 1e-3 * size, 'an unkept drag moves the centre');
    usageError(cli('edit', file('bi3.obj'), '--scheme', 'catmull-clark', '--keep', 'volume,centroid', '--path', 'polynomial',
      '--move', '5:0,0,1', '-o', file('x.obj')), /--keep centroid runs matrix-free/);
    usageError(cli('edit', file('bi3.obj'), '--scheme', 'catmull-clark', '--keep', 'volume,inertia', '--move', '5:0,0,1', '-o', file('x.obj')),
      /--keep expects volume or volume,centroid/);
  });

  test('a quad file edited as triangles says on stderr that its quads have levels; the limit surface refused as usage', () => {
    writeFileSync(file('bi2.obj'), mrvol.writeObjQuads(detailedQuads(2, 17)));
    for (const args of [['edit', file('bi2.obj'), '--move', '0:0,0,0.1', '-o', file('tri.obj')], ['volume', file('bi2.obj')],
                        ['roundtrip', file('bi2.obj')]]) {
      const r = cli(...args);
      assert.equal(r.status, 0, r.stderr);
      assert.match(r.stderr, /^mrvol: note: .*bi2\.obj is read as triangles, which have no levels here .*its quads have 2 Catmull-Clark levels: add --scheme catmull-clark/, args[0]);
    }
    // with the scheme, or on a file of triangles: no note
    assert.equal(cli('volume', file('bi2.obj'), '--scheme', 'catmull-clark').stderr, '');
    assert.doesNotMatch(cli('volume', model('spiky-ball')).stderr, /note/);
    // an open quad mesh has no genus to give (as for triangles)
    writeFileSync(file('grid.obj'), 'v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\nf 1 2 5 4\nf 2 3 6 5\n');
    assert.match(cli('info', file('grid.obj'), '--scheme', 'catmull-clark').stdout, /^genus {10}- \(not a closed surface\)$/m);
    // the cage's level said, the lowest a cube's base allows by default
    const cubeFile = file('cube.obj');
    writeFileSync(cubeFile, 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n' +
                            'f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n');
    assert.equal(cli('subdivide', cubeFile, '--scheme', 'catmull-clark', '--levels', '2', '-o', file('cube2.obj')).status, 0);
    assert.match(cli('edit', file('cube2.obj'), '--scheme', 'catmull-clark', '--move', '0:0.1,0,0', '-o', file('cube2e.obj')).stdout,
      /^cage {13}level 1, 26 vertices \(the lowest level: the base is a cube\)$/m);
    for (const command of ['volume', 'theta'])
      usageError(cli(command, file('bi2.obj'), '--scheme', 'catmull-clark', '--surface', 'limit', ...(command === 'theta' ? ['-o', file('x.theta')] : [])),
        /--surface limit is not available for catmull-clark \(the bilinear patches' volume is kept\)/);
  });
});
