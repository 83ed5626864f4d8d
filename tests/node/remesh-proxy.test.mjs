// The proxy of a large input (lib/remesh-proxy.mjs, the `proxy` option of lib/remesh.mjs): a torus
// with thin needles, which meshoptimizer's quadric error lets go cheaply, with the real WASM core.
import { test, before } from 'node:test';
import assert from 'node:assert/strict';
import { TorusGeometry } from 'three';
import { createMrvol } from '../../lib/node.mjs';
import { remesh, Surface, weld } from '../../lib/remesh.mjs';
import { proxyInput, proxyPiece } from '../../lib/remesh-proxy.mjs';
import { boundingDiagonal } from '../../lib/geometry.mjs';

let mrvol;
before(async () => {
  mrvol = await createMrvol();
  Surface.core = mrvol;
});

/** A torus of 2 x radial x tubular faces with `needles` of its vertices pushed out along their normal by `length`. */
function needledTorus(radial, tubular, needles, length = 0.6) {
  const g = new TorusGeometry(1, 0.4, radial, tubular);
  const mesh = weld({ positions: Float64Array.from(g.attributes.position.array), faces: Uint32Array.from(g.index.array) });
  const p = mesh.positions, n = p.length / 3, tips = [];
  for (let k = 0; k < needles; k++) {
    const v = Math.floor(((k + 0.5) * n) / needles);
    // Outward from the tube's centre circle (radius 1 in the xy plane).
    const r = Math.hypot(p[3 * v], p[3 * v + 1]), cx = p[3 * v] / r, cy = p[3 * v + 1] / r;
    const d = [p[3 * v] - cx, p[3 * v + 1] - cy, p[3 * v + 2]], l = Math.hypot(...d);
    for (let j = 0; j < 3; j++) p[3 * v + j] += (length * d[j]) / l;
    tips.push(v);
  }
  return { mesh, tips };
}

test('proxyPiece: the vertices the first simplification leaves beyond the limit are locked; every input vertex within it, genus kept', () => {
  const { mesh, tips } = needledTorus(48, 96, 4);
  const diagonal = boundingDiagonal(mesh.positions), limit = 0.0015 * diagonal;
  const p = proxyPiece(mrvol, { mesh, genus: 1 }, { target: 2500, limit, surfaceOf: (m) => new Surface(m, { normals: false }) });
  assert.ok(p, 'a proxy');
  assert.ok(p.rounds >= 2, `the first simplification leaves vertices beyond the limit (rounds ${p.rounds})`);
  assert.equal(p.genus, 1);
  assert.ok(p.faces <= 2600, `${p.faces} faces`);
  const v = mrvol.validate(p.mesh);
  assert.ok(v.closed && v.components === 1 && v.genus === 1);
  // Its vertices are input vertices; the needles' tips among them.
  const keys = new Set();
  for (let i = 0; i < p.mesh.positions.length; i += 3) keys.add(`${p.mesh.positions[i]} ${p.mesh.positions[i + 1]} ${p.mesh.positions[i + 2]}`);
  for (const t of tips) assert.ok(keys.has(`${mesh.positions[3 * t]} ${mesh.positions[3 * t + 1]} ${mesh.positions[3 * t + 2]}`), `tip ${t} kept`);
  const distances = new Surface(p.mesh, { normals: false }).distances(mesh.positions);
  assert.ok(distances.every((d) => d <= limit), 'every input vertex within the limit');
  assert.ok(p.distance <= limit);
});

test('proxyPiece: after its last round a proxy within slack x the limit is taken, its distance said; beyond that none', () => {
  const { mesh } = needledTorus(48, 96, 4);
  const diagonal = boundingDiagonal(mesh.positions), limit = 0.0015 * diagonal;
  const surfaceOf = (m) => new Surface(m, { normals: false });
  // One round: the needles' tips are not locked yet, so some input vertex is beyond the limit.
  const one = proxyPiece(mrvol, { mesh, genus: 1 }, { target: 2500, limit, surfaceOf, rounds: 1, slack: Infinity });
  assert.ok(one && one.rounds === 1 && one.distance > limit, `the first round's proxy is beyond the limit (${one?.distance / limit}x)`);
  const distances = surfaceOf(one.mesh).distances(mesh.positions);
  assert.equal(Math.max(...distances), one.distance, 'its distance is the farthest input vertex\'s');
  const ratio = one.distance / limit;
  const within = proxyPiece(mrvol, { mesh, genus: 1 }, { target: 2500, limit, surfaceOf, rounds: 1, slack: 1.01 * ratio });
  assert.ok(within && within.distance === one.distance, 'taken within the slack');
  assert.equal(proxyPiece(mrvol, { mesh, genus: 1 }, { target: 2500, limit, surfaceOf, rounds: 1, slack: 0.99 * ratio }), null, 'none beyond it');
  assert.equal(proxyPiece(mrvol, { mesh, genus: 1 }, { target: 2500, limit, surfaceOf, rounds: 1, slack: 1 }), null, 'none without slack');
});

test('proxyInput: only above minFaces, without features, and with a proxy the parametrised fit can take', () => {
  const { mesh } = needledTorus(48, 96, 4);
  const prepared = { pieces: [{ mesh, faces: mesh.faces.length / 3, genus: 1 }], inputFaces: mesh.faces.length / 3, diagonal: boundingDiagonal(mesh.positions), features: null };
  assert.equal(proxyInput(mrvol, prepared, Surface), null, 'a small input is fitted as it is');
  const settings = { minFaces: 5000, minTarget: 2500, limit: 0.0015 };
  const made = proxyInput(mrvol, prepared, Surface, settings);
  assert.ok(made && made.proxy.pieces === 1 && made.pieces[0].faces === mesh.faces.length / 3 && made.mesh.faces.length / 3 <= 2600, JSON.stringify(made?.proxy));
  assert.equal(proxyInput(mrvol, prepared, Surface, { ...settings, limit: 0.0001 }), null, 'no proxy within the limit: none');
  assert.equal(proxyInput(mrvol, prepared, Surface, { ...settings, maxFaces: 2000 }), null, 'a proxy over maxFaces: none');
  assert.equal(proxyInput(mrvol, { ...prepared, features: { edgeCount: 3 } }, Surface, settings), null, 'sharp features: none');
});

test('remesh with a proxy: parametrised against it, measured against the input itself, unfolded and within the goal', async () => {
  // (No needles: their edges are sharp features, and those keep the input itself.)
  const { mesh } = needledTorus(48, 96, 0);
  const diagonal = boundingDiagonal(mesh.positions);
  const r = await remesh(mrvol, mesh, { proxy: { minFaces: 5000, minTarget: 2500, limit: 0.0015 } });
  assert.ok(r.proxy, 'fitted against a proxy');
  assert.ok(r.proxy.faces <= 2600 && r.proxy.distance <= 0.0015 && r.proxy.genusLost === 0, JSON.stringify(r.proxy));
  assert.equal(r.fit, 'parametrised');
  assert.equal(r.flippedTriangles, 0);
  assert.ok(r.hausdorff <= 0.005, `Hausdorff ${r.hausdorff}`);
  assert.ok(Math.abs(r.volumeChange) < 0.01, `volume change ${r.volumeChange}`);
  assert.equal(mrvol.validate(r.mesh).genus, 1);
  // The distance reported is the input's: every input vertex (each a sample of the measure here) within it.
  const fromInput = new Surface(r.mesh, { normals: false }).distances(mesh.positions);
  assert.ok(fromInput.every((d) => d <= r.hausdorffFromInput * diagonal * (1 + 1e-9)), 'the input vertices within the reported distance');
  const off = await remesh(mrvol, mesh, { proxy: false, levels: 2 });
  assert.equal(off.proxy, null);
  assert.equal(off.fit, 'simplified');
});

test('remesh with a proxy still above the goal: fitted without it too, the closer kept', async () => {
  const { mesh } = needledTorus(48, 96, 0);
  const options = { proxy: { minFaces: 5000, minTarget: 2500, limit: 0.0015 }, hausdorffGoal: 0.0005, maxVertices: 12000, dragTips: false, nudge: false };
  const r = await remesh(mrvol, mesh, options);
  assert.ok(r.proxyFallback, 'the fit without the proxy was made');
  assert.equal(r.proxyFallback.flippedTriangles, 0);
  const without = await remesh(mrvol, mesh, { ...options, proxy: false });
  assert.equal(without.proxyFallback, null);
  assert.ok(r.hausdorff <= without.hausdorff, `${r.hausdorff} vs ${without.hausdorff}`);
  assert.equal(r.proxyFallback.hausdorff, without.hausdorff, 'the same fit as with proxy: false');
  assert.equal(r.flippedTriangles, 0);
});
