// A simplified proxy of a large input for remesh()'s fits (issue 12: the large scans' time). The
// fits' closest-point queries scale with the input's vertices (the pull of every input vertex,
// the measures' samples), and a large scan is fitted many times (levels, tips rounds, larger
// bases, emphasis and refined rounds). Each large piece is simplified by meshoptimizer to a
// fraction of its faces, its vertices that end up farther than PROXY_LIMIT from the proxy locked
// and the simplification made again (a scan's thin spikes, which the quadric error lets go
// cheaply), until every input vertex is within the limit; the fits then run against the proxy and
// only the chosen fit is measured, dragged and nudged against the input itself (lib/remesh.mjs).
// The proxy's vertices are input vertices (same coordinates), so position keys (tips, feature
// vertices) carry over.
import { MeshoptSimplifier } from 'meshoptimizer';
import { repair } from './repair.mjs';

/** Inputs of more faces than this are fitted against a proxy (the 203k and 871k dragons). */
export const PROXY_MIN_FACES = 150000;
/** The proxy's faces: the input's over PROXY_RATIO, at least PROXY_MIN_TARGET. */
export const PROXY_RATIO = 8, PROXY_MIN_TARGET = 55000;
/** Every input vertex within this (over the diagonal) of its piece's proxy (the proxy's vertices are on the input). */
export const PROXY_LIMIT = 0.0004;
/** Simplifications per piece (the 871k's spikes: 3). */
const PROXY_ROUNDS = 4;

/**
 * A proxy of one piece ({ mesh, genus }): { mesh, genus, faces, distance, clean, surface, rounds },
 * or null when no proxy has every input vertex within `limit` (the piece is then fitted as it is).
 * clean: the proxy is one closed 2-manifold of at most the piece's genus (the bases can be made
 * from it); else (the simplifier pinched thin parts into fins, pieces apart) it is the
 * simplifier's output as it came, good for the fits' closest points only. `surfaceOf(mesh)` makes a Surface.
 */
export function proxyPiece(mrvol, piece, { target, limit, surfaceOf }) {
  const { mesh } = piece;
  const faces = mesh.faces.length / 3;
  if (target >= faces / 2) return null;
  const n = mesh.positions.length / 3;
  const positions32 = Float32Array.from(mesh.positions);
  const lock = new Uint8Array(n);
  for (let round = 0; round < PROXY_ROUNDS; round++) {
    const [indices] = MeshoptSimplifier.simplifyWithAttributes(mesh.faces, positions32, 3, new Float32Array(0), 0, [], lock, 3 * target, 1.0, []);
    const raw = compact(mesh, indices);
    // Pinched thin parts (fins, a non-manifold edge) cleaned as the bases are (small holes only).
    let proxy = raw, checked = check(mrvol, proxy);
    if (checked && !checked.ok) proxy = repair(proxy, { maxHoleEdges: 12 }).mesh, checked = check(mrvol, proxy);
    // Tunnels the simplifier closes at this size close in any cage made by it too (a scan's tiny
    // tunnels): the bases are checked against the piece's genus as before. Not clean: the raw output
    // (the repair's dropped fins and filled holes would leave input vertices far).
    const clean = !!checked?.ok && checked.genus <= piece.genus;
    if (!clean) proxy = raw;
    const surface = surfaceOf(proxy);
    const distances = surface.distances(mesh.positions);
    let worst = 0, far = 0;
    for (let v = 0; v < n; v++) {
      worst = Math.max(worst, distances[v]);
      if (distances[v] > limit && !lock[v]) lock[v] = 1, far++;
    }
    if (worst <= limit) return { mesh: proxy, genus: clean ? checked.genus : null, faces: proxy.faces.length / 3, distance: worst, clean, surface, rounds: round + 1 };
    surface.dispose();
    if (far === 0) return null;
  }
  return null;
}

/** The simplifier's faces over the mesh's vertices, compacted (positions copied). */
function compact(mesh, indices) {
  const faces = Uint32Array.from(indices);
  const [remap, unique] = MeshoptSimplifier.compactMesh(faces);
  const positions = new Float64Array(3 * unique);
  for (let i = 0; i < remap.length; i++)
    if (remap[i] !== 0xffffffff) for (let k = 0; k < 3; k++) positions[3 * remap[i] + k] = mesh.positions[3 * i + k];
  return { positions, faces };
}

/** Closed, manifold, one component: { ok, genus }; null when the core refuses it. */
function check(mrvol, mesh) {
  try {
    const v = mrvol.validate(mesh);
    return { ok: v.closed && v.components === 1, genus: v.genus };
  } catch {
    return null;
  }
}

/**
 * The prepared input (remesh's prepareInput) with its large pieces replaced by proxies, or null
 * (no piece large enough, sharp features found: their lines are the input's vertices). Its mesh
 * and surfaces (the fits' closest points, the measures) are the proxies'; its pieces (the bases
 * are made from them) the clean proxies and the input's other pieces. `parametrisable`: every
 * piece of more than 64 faces a clean proxy of at most `parametriseMaxFaces` faces. `proxy` says
 * what was made: { faces, distance (over the diagonal, the farthest input vertex), pieces
 * (proxied), clean (of those), rounds, genusLost (the clean proxies' tunnels fewer) }.
 */
export function proxyInput(mrvol, prepared, Surface, { minFaces = PROXY_MIN_FACES, ratio = PROXY_RATIO, minTarget = PROXY_MIN_TARGET, limit = PROXY_LIMIT,
                                                      parametriseMaxFaces = Infinity } = {}) {
  const { pieces, inputFaces, diagonal, features } = prepared;
  if (inputFaces <= minFaces || (features && features.edgeCount > 0)) return null;
  const target = Math.max(minTarget, Math.round(inputFaces / ratio));
  let distance = 0, proxied = 0, clean = 0, rounds = 0, genusLost = 0;
  const surfaces = new Map();
  const made = pieces.map((piece) => {
    const pieceTarget = Math.round((target * piece.faces) / inputFaces);
    const p = proxyPiece(mrvol, piece, { target: pieceTarget, limit: limit * diagonal, surfaceOf: (m) => new Surface(m, { normals: false }) });
    if (!p) return null;
    p.surface.dispose();
    distance = Math.max(distance, p.distance), proxied++, rounds = Math.max(rounds, p.rounds);
    if (p.clean) clean++, genusLost += piece.genus - p.genus;
    return p;
  });
  if (proxied === 0) return null;
  // (faces: the piece's own, by which the fits share the base faces out.)
  const fitted = pieces.map((piece, i) => (made[i]?.clean ? { mesh: made[i].mesh, faces: piece.faces, genus: piece.genus } : piece));
  const surfaceMeshes = pieces.map((piece, i) => made[i]?.mesh ?? piece.mesh);
  const mesh = pieces.length === 1 ? surfaceMeshes[0] : concatenate(surfaceMeshes);
  const surface = new Surface(mesh);
  const surfaceOf = (i) => {
    if (pieces.length === 1) return surface;
    if (!surfaces.has(i)) surfaces.set(i, new Surface(surfaceMeshes[i]));
    return surfaces.get(i);
  };
  const parametrisable = fitted.every((p, i) => p.mesh.faces.length / 3 <= 64 || (made[i]?.clean && p.mesh.faces.length / 3 <= parametriseMaxFaces));
  return { ...prepared, pieces: fitted, mesh, surface, surfaceOf, parametrisable,
           proxy: { faces: mesh.faces.length / 3, distance: distance / diagonal, pieces: proxied, clean, rounds, genusLost } };
}

/** Meshes end to end. */
function concatenate(meshes) {
  const positions = new Float64Array(meshes.reduce((t, m) => t + m.positions.length, 0));
  const faces = new Uint32Array(meshes.reduce((t, m) => t + m.faces.length, 0));
  let p = 0, f = 0;
  for (const m of meshes) {
    positions.set(m.positions, p);
    for (let i = 0; i < m.faces.length; i++) faces[f + i] = m.faces[i] + p / 3;
    p += m.positions.length, f += m.faces.length;
  }
  return { positions, faces };
}
