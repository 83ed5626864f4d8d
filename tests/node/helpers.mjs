// Shared helpers of the Node tests: a temporary folder, running the CLI as a child process and checking its output
// contract, the sample models, small test meshes, a seeded PRNG, mesh shuffling, numeric
// comparisons and MrvolError assertions.
import { before, after } from 'node:test';
import assert from 'node:assert/strict';
import { spawn, spawnSync } from 'node:child_process';
import { mkdtempSync, rmSync, readFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { MrvolError } from '../../lib/node.mjs';

export const ROOT = fileURLToPath(new URL('../../', import.meta.url));
export const CLI = fileURLToPath(new URL('../../bin/mrvol.mjs', import.meta.url));
export const MODELS = fileURLToPath(new URL('../../public/models/', import.meta.url));

// A fresh temporary folder (named PREFIX...) made before the tests of the calling file and
// removed after them: returns `file`, with file(name) the path of `name` in that folder.
export function tempFolder(prefix) {
  let dir;
  before(() => {
    dir = mkdtempSync(join(tmpdir(), prefix));
  });
  after(() => {
    if (dir) rmSync(dir, { recursive: true, force: true });
  });
  return (name) => join(dir, name);
}

// ---- the command line ---------------------------------------------------------------------------

// Runs `mrvol ARGS...` and waits for it: { status, stdout, stderr }.
export function runCliSync(args, { timeout = 60000 } = {}) {
  const r = spawnSync(process.execPath, [CLI, ...args], { encoding: 'utf8', timeout });
  if (r.error) throw r.error;
  return { status: r.status, stdout: r.stdout, stderr: r.stderr };
}

// Runs `mrvol ARGS...` in the background: a promise of { status, signal, stdout, stderr }.
export function runCli(args, { cwd, timeout } = {}) {
  return new Promise((resolve, reject) => {
    const child = spawn(process.execPath, [CLI, ...args], { cwd, timeout, stdio: ['ignore', 'pipe', 'pipe'] });
    let stdout = '', stderr = '';
    child.stdout.setEncoding('utf8').on('data', (d) => { stdout += d; });
    child.stderr.setEncoding('utf8').on('data', (d) => { stderr += d; });
    child.on('error', reject);
    child.on('close', (status, signal) => resolve({ status, signal, stdout, stderr }));
  });
}

// Exit 0, nothing on stderr and exactly one line of JSON on stdout: that JSON, parsed.
export function json(r) {
  assert.equal(r.status, 0, `exit ${r.status}: ${r.stderr}`);
  assert.equal(r.stderr, '');
  const lines = r.stdout.trimEnd().split('\n');
  assert.equal(lines.length, 1, 'one line of JSON');
  return JSON.parse(lines[0]);
}

// Exit 1 and exactly one stderr line `mrvol: error: ...`; nothing on stdout.
export function failsWith(r, pattern) {
  assert.equal(r.status, 1, `expected exit 1, got ${r.status}; stderr: ${r.stderr}`);
  assert.equal(r.stdout, '');
  assert.ok(r.stderr.endsWith('\n'));
  const lines = r.stderr.slice(0, -1).split('\n');
  assert.equal(lines.length, 1, `one stderr line, got: ${r.stderr}`);
  assert.match(lines[0], /^mrvol: error: \S/);
  if (pattern) assert.match(lines[0], pattern);
}

// Exit 2 (bad usage), nothing on stdout; the first stderr line matches `pattern` if given.
export function usageError(r, pattern) {
  assert.equal(r.status, 2, `expected exit 2, got ${r.status}; stderr: ${r.stderr}`);
  assert.equal(r.stdout, '');
  if (pattern) assert.match(r.stderr.split('\n')[0], pattern);
}

// ---- models -------------------------------------------------------------------------------------

// The path of a sample model (public/models/NAME.obj).
export const model = (name) => join(MODELS, `${name}.obj`);
// An OBJ file read with the module `mrvol`.
export const readObjFile = (mrvol, path) => mrvol.readObj(readFileSync(path, 'utf8'));
// A sample model read with the module `mrvol`.
export const loadModel = (mrvol, name) => readObjFile(mrvol, model(name));

// ---- fixtures (the same models as tests/native/fixtures.h) -------------------------------------

export function mesh(positions, faces) {
  return { positions: Float64Array.from(positions), faces: Uint32Array.from(faces) };
}

const T = (1 + Math.sqrt(5)) / 2;

export const icosahedron = () => mesh(
  [-1, T, 0, 1, T, 0, -1, -T, 0, 1, -T, 0, 0, -1, T, 0, 1, T, 0, -1, -T, 0, 1, -T, T, 0, -1, T, 0, 1, -T, 0, -1, -T, 0, 1],
  [0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4, 11, 10, 2, 10, 7, 6, 7, 1, 8,
    3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8, 3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8, 1]);

export const octahedron = () => mesh([1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1],
  [0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5]);

// Hexagon fan plus an outer ring of 12: an open mesh with 12 boundary edges (the outer ring).
export function openPatch() {
  const p = [0, 0, 0.3], f = [];
  for (let k = 0; k < 6; ++k) p.push(Math.cos(k * Math.PI / 3), Math.sin(k * Math.PI / 3), 0.1 * k);
  for (let k = 0; k < 12; ++k) p.push(2 * Math.cos(k * Math.PI / 6), 2 * Math.sin(k * Math.PI / 6), -0.05 * k);
  for (let k = 0; k < 6; ++k) f.push(0, 1 + k, 1 + (k + 1) % 6);
  for (let k = 0; k < 6; ++k) {
    const in0 = 1 + k, in1 = 1 + (k + 1) % 6, o0 = 7 + 2 * k, o1 = 7 + 2 * k + 1, o2 = 7 + (2 * k + 2) % 12;
    f.push(in0, o0, o1, in0, o1, in1, in1, o1, o2);
  }
  return mesh(p, f);
}

// ---- randomness ---------------------------------------------------------------------------------

// Seeded PRNG (mulberry32).
export function rng(seed) {
  let a = seed >>> 0;
  return () => {
    a = (a + 0x6d2b79f5) >>> 0;
    let t = a;
    t = Math.imul(t ^ (t >>> 15), t | 1);
    t ^= t + Math.imul(t ^ (t >>> 7), t | 61);
    return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
  };
}

// Random vertex order; perm[v] = the new index of vertex v. With `shuffleFaces`, the faces are
// also put in a random order and rotated (orientation kept); otherwise they keep their order.
export function shuffleMesh(m, seed, { shuffleFaces = false } = {}) {
  const r = rng(seed), nv = m.positions.length / 3;
  const perm = Array.from({ length: nv }, (_, i) => i);
  for (let i = nv - 1; i > 0; --i) {
    const j = Math.floor(r() * (i + 1));
    [perm[i], perm[j]] = [perm[j], perm[i]];
  }
  const positions = new Float64Array(m.positions.length);
  for (let v = 0; v < nv; ++v) for (let k = 0; k < 3; ++k) positions[3 * perm[v] + k] = m.positions[3 * v + k];
  if (!shuffleFaces) return { mesh: { positions, faces: m.faces.map((i) => perm[i]) }, perm };
  const nf = m.faces.length / 3;
  const order = Array.from({ length: nf }, (_, i) => i);
  for (let i = nf - 1; i > 0; --i) {
    const j = Math.floor(r() * (i + 1));
    [order[i], order[j]] = [order[j], order[i]];
  }
  const faces = new Uint32Array(m.faces.length);
  order.forEach((f, i) => {
    const rot = Math.floor(r() * 3);
    for (let k = 0; k < 3; ++k) faces[3 * i + k] = perm[m.faces[3 * f + (k + rot) % 3]];
  });
  return { mesh: { positions, faces }, perm };
}

// ---- numbers ------------------------------------------------------------------------------------

export const relErr = (a, b) => Math.abs(a - b) / Math.abs(b);
export const maxAbs = (a) => a.reduce((m, x) => Math.max(m, Math.abs(x)), 0);
export function maxDiff(a, b) {
  assert.equal(a.length, b.length);
  let m = 0;
  for (let i = 0; i < a.length; ++i) m = Math.max(m, Math.abs(a[i] - b[i]));
  return m;
}

// ---- errors -------------------------------------------------------------------------------------

// `fn` throws a MrvolError whose message is exactly `message` (or matches a RegExp; any message
// when undefined). With `named`, also checks that it is an Error whose name is 'MrvolError'.
export function throwsMrvol(fn, message, { named = false } = {}) {
  assert.throws(fn, (e) => {
    assert.ok(e instanceof MrvolError, `expected a MrvolError, got ${e?.constructor?.name}: ${e?.message}`);
    if (named) {
      assert.ok(e instanceof Error);
      assert.equal(e.name, 'MrvolError');
    }
    if (message instanceof RegExp) assert.match(e.message, message);
    else if (message !== undefined) assert.equal(e.message, message);
    return true;
  });
}
