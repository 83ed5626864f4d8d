// A simplified proxy of a large input for remesh()'s fits (issue 12: the large scans' time). The
// fits' closest-point queries scale with the input's vertices (the pull of every input vertex,
// the measures' samples), and a large scan is fitted many times (levels, tips rounds, larger
// bases, emphasis and refined rounds). Each large piece is simplified by meshoptimizer to a
// fraction of its faces, its vertices that end up farther than PROXY_LIMIT from the proxy locked
// and the simplification made again (a scan's thin spikes, which the quadric error lets go
// cheaply), until every input vertex is within the limit (after the last round, or with nothing
// left to lock, within PROXY_SLACK x the limit); the fits then run against the proxy and
// only the chosen fit is measured, dragged and nudged against the input itself (lib/remesh.mjs).
// The proxy's vertices are input vertices (same coordinates), so position keys (tips, feature
// vertices) carry over.
import { MeshoptSimplifier } from 'meshoptimizer';
import { concatenate } from './geometry.mjs';
import { repair } from './repair.mjs';

/** Inputs of more faces than this are fitted against a proxy (the 203k and 871k dragons). */
export const PROXY_MIN_FACES = 150000;
/** The proxy's faces: the input's over PROXY_RATIO, at least PROXY_MIN_TARGET. */
export const PROXY_RATIO = 8, PROXY_MIN_TARGET = 55000;
/** Every input vertex within this (over the diagonal) of its piece's proxy (the proxy's vertices are on the input); PROXY_SLACK x this after the last round. */
export const PROXY_LIMIT = 0.0004;
/** Simplifications per piece (the 871k's spikes: 3). */
const PROXY_ROUNDS = 4;
/** After the rounds, a proxy within this many times the limit is taken (0.16% of the diagonal: a third of the fits' goal). */
const PROXY_SLACK = 4;

/**
 * A proxy of one piece ({ mesh, genus }): { mesh, genus, faces, distance, surface, rounds }, one
 * closed 2-manifold of at most the piece's genus with every input vertex within `limit` (within
 * `slack` x `limit` after the last of `rounds` simplifications, or when nothing is left to lock),
 * or null (the simplifier pinched thin parts into fins or pieces apart that its repair does not
 * mend, or a vertex is left beyond that). `surfaceOf(mesh)` makes a Surface.
 */
export function proxyPiece(mrvol, piece, { target, limit, surfaceOf, rounds = PROXY_ROUNDS, slack = PROXY_SLACK }) {
  const { mesh } = piece;
  const n = mesh.positions.length / 3;
  const positions32 = Float32Array.from(mesh.positions);
  const lock = new Uint8Array(n);
  for (let round = 0; round < rounds; round++) {
    const [indices] = MeshoptSimplifier.simplifyWithAttributes(mesh.faces, positions32, 3, new Float32Array(0), 0, [], lock, 3 * target, 1.0, []);
    let proxy = compact(mesh, indices);
    // Pinched thin parts (fins, a non-manifold edge, faces made twice: the core refuses those) cleaned
    // as the bases are (small holes only). (Refused ones were given up: dragon-203k rotated, a pair of
    // duplicate faces in its first proxy, was fitted without a proxy: 1.736% against 0.464% as read.)
    let checked = check(mrvol, proxy);
    if (!checked?.ok) proxy = repair(proxy, { maxHoleEdges: 12, sharpCorners: true }).mesh, checked = check(mrvol, proxy);
    // Tunnels the simplifier closes at this size close in any cage made by it too (a scan's tiny
    // tunnels): the bases are checked against the piece's genus as before. (The 871k dragon's
    // proxies came out in 3 to 17 pieces: never clean.)
    if (!checked?.ok || checked.genus > piece.genus) return null;
    // So many vertices locked that the proxy is twice the size asked for: none.
    if (proxy.faces.length / 3 > 2 * target) return null;
    const surface = surfaceOf(proxy);
    const distances = surface.distances(mesh.positions);
    let worst = 0, far = 0;
    for (let v = 0; v < n; v++) {
      worst = Math.max(worst, distances[v]);
      if (distances[v] > limit && !lock[v]) lock[v] = 1, far++;
    }
    // The last round, or nothing left to lock: within PROXY_SLACK x the limit the proxy is taken still.
    // (A thin part the simplifier folds into faces made twice, which the repair takes out, leaves its
    // locked vertices out every round: dragon-203k rotated 1.70x, scaled by 1.001 3.73x; without a
    // proxy they were fitted at 1.736% and 0.782%. The fits are measured, dragged and nudged against
    // the input itself in the end.)
    const last = round === rounds - 1 || far === 0;
    if (worst <= limit || (last && worst <= slack * limit))
      return { mesh: proxy, genus: checked.genus, faces: proxy.faces.length / 3, distance: worst, surface, rounds: round + 1 };
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
 * The prepared input (remesh's prepareInput) with its pieces replaced by proxies, or null: an
 * input of `minFaces` or fewer; sharp features found (their lines are the input's vertices); a
 * proxy larger than `maxFaces` (the parametrised fit's limit: on a proxy the simplified fit
 * lost, dragon-203k 0.461% -> 1.87%); a piece with no proxy (proxyPiece). Pieces of at most twice
 * their share of the proxy stay as they are. Its mesh, surfaces and pieces are the proxies';
 * `proxy` says what was made: { faces, distance (over the diagonal, the farthest input vertex),
 * pieces (proxied), rounds, genusLost (the proxies' tunnels fewer) }.
 */
export function proxyInput(mrvol, prepared, Surface, { minFaces = PROXY_MIN_FACES, ratio = PROXY_RATIO, minTarget = PROXY_MIN_TARGET, limit = PROXY_LIMIT,
                                                      maxFaces = Infinity } = {}) {
  const { pieces, inputFaces, diagonal, features } = prepared;
  if (inputFaces <= minFaces || (features && features.edgeCount > 0)) return null;
  const target = Math.max(minTarget, Math.round(inputFaces / ratio));
  if (target > maxFaces) return null;
  let distance = 0, proxied = 0, rounds = 0, genusLost = 0;
  const proxies = [];
  for (const piece of pieces) {
    const pieceTarget = Math.round((target * piece.faces) / inputFaces);
    if (pieceTarget >= piece.faces / 2) {
      proxies.push(piece);
      continue;
    }
    const p = proxyPiece(mrvol, piece, { target: pieceTarget, limit: limit * diagonal, surfaceOf: (m) => new Surface(m, { normals: false }) });
    // (A small piece the simplifier cannot make clean, 26 faces of the 203k scan, stays as it is.)
    if (!p && piece.faces <= Math.min(maxFaces, target)) {
      proxies.push(piece);
      continue;
    }
    if (!p) return null;
    p.surface.dispose();
    distance = Math.max(distance, p.distance), proxied++, rounds = Math.max(rounds, p.rounds), genusLost += piece.genus - p.genus;
    // (faces: the piece's own, by which the fits share the base faces out.)
    proxies.push({ mesh: p.mesh, faces: piece.faces, genus: piece.genus });
  }
  if (proxied === 0 || proxies.reduce((t, p) => t + p.mesh.faces.length / 3, 0) > maxFaces) return null;
  const mesh = proxies.length === 1 ? proxies[0].mesh : concatenate(proxies.map((p) => p.mesh));
  const surface = new Surface(mesh);
  const surfaces = new Map();
  const surfaceOf = (i) => {
    if (proxies.length === 1) return surface;
    if (!surfaces.has(i)) surfaces.set(i, new Surface(proxies[i].mesh));
    return surfaces.get(i);
  };
  return { ...prepared, pieces: proxies, mesh, surface, surfaceOf,
           proxy: { faces: mesh.faces.length / 3, distance: distance / diagonal, pieces: proxied, rounds, genusLost } };
}
