// Semi-regular remeshing of any closed manifold triangle mesh (method.md section 8), the package's
// `mrvol/remesh` entry: weld, optionally repair, and validate (lib/repair.mjs); simplify to a base
// mesh with meshoptimizer (checked: closed, manifold, one component, same genus; retried with a
// larger target otherwise); n levels of 1-to-4 splits through the core (linear scheme: new
// vertices at edge midpoints); level by level, the new vertices moved onto the original surface
// (ray along the normal both ways, capped, falling back to the closest point; BVH from
// three-mesh-bvh), then tangential relaxation and reprojection. Reports the two-sided Hausdorff
// distance, flipped triangles and the volume change, and refuses a result that folds over.
//
// Environment-agnostic (Node and browsers): it takes the mrvol API object (createMrvol()) as a
// parameter and uses only npm packages that run in both. The core entries (lib/api.mjs,
// lib/node.mjs, lib/browser.mjs) do not load it, nor three.js, three-mesh-bvh or meshoptimizer.
import { MeshoptSimplifier } from 'meshoptimizer';
import { Box3, BufferAttribute, BufferGeometry, DoubleSide, Ray, Triangle, Vector3 } from 'three';
import { MeshBVH } from 'three-mesh-bvh';
import { connectivity } from './connectivity.mjs';
import { collapseToTarget } from './remesh-collapse.mjs';
import { measureForNudge, nudgeToGoal } from './remesh-nudge.mjs';
import { BaseParametrisation } from './remesh-param.mjs';
import { pointGrid } from './point-grid.mjs';
import { InputOnResult } from './remesh-input-on-result.mjs';
import { PROXY_MIN_FACES, proxyInput } from './remesh-proxy.mjs';
import { boundingDiagonal, concatenate, hypot3, triangleNormal, unitTriangleNormal, vertexNormals } from './geometry.mjs';
import { Constraints, findFeatures } from './features.mjs';
import { meshProblem, repair, weld } from './repair.mjs';

export { repair, weld };

const now = () => globalThis.performance?.now() ?? Date.now();

// ---- the original surface as a BVH ---------------------------------------------------------------

export class Surface {
  /**
   * The mrvol API whose closestPoints (a tree in the WASM core) the surfaces query; remesh sets it.
   * null: three-mesh-bvh's tree walked in JS (closestPointQuery).
   */
  static core = null;
  constructor(mesh, { normals = true, core = Surface.core } = {}) {
    this.mesh = mesh;
    this.point = new Vector3();
    this.hit = { point: new Vector3(), distance: 0, faceIndex: 0 };
    this.ray = new Ray();
    this.diagonal = boundingDiagonal(mesh.positions);
    const geometry = new BufferGeometry();
    geometry.setAttribute('position', new BufferAttribute(Float32Array.from(mesh.positions), 3));
    geometry.setIndex(new BufferAttribute(Uint32Array.from(mesh.faces), 1));
    // The tree: three-mesh-bvh's own, built in the core when there is one (the same bytes and the
    // same reordered index, a tenth of the remesher's time in JS), else by the library.
    this.bvh = core && typeof core.threeMeshBvh === 'function'
      ? MeshBVH.deserialize({ version: 1, ...core.threeMeshBvh(geometry.attributes.position.array, geometry.index.array) }, geometry)
      : new MeshBVH(geometry);
    if (!geometry.boundingBox) geometry.boundingBox = this.bvh.getBoundingBox(new Box3());
    // The BVH reorders the triangles of the index: face indices (hits, normals) follow this.index.
    this.index = geometry.index.array;
    // The core walks the same tree over the same float32 positions: the same answers, ties included.
    const nodes = core && bvhNodes(this.bvh);
    if (nodes) this.core = core, this.nodes = nodes, this.positions64 = Float64Array.from(geometry.attributes.position.array), this.found = new Float64Array(5);
    if (!normals) return;
    const index = this.index, p = mesh.positions;
    this.normals = new Float64Array(index.length);
    for (let f = 0; f < index.length; f += 3) {
      const n = triangleNormal(p, index[f], index[f + 1], index[f + 2]);
      const l = Math.hypot(n[0], n[1], n[2]) || 1;
      for (let k = 0; k < 3; k++) this.normals[f + k] = n[k] / l;
    }
    // Smoothed vertex normals (area-weighted, then averaged over the 1-ring three times): the
    // reference orientation for flipped triangles, insensitive to scanner noise.
    let vn = vertexNormals(p, mesh.faces);
    const ring = connectivity(mesh.faces, p.length / 3).neighbours;
    for (let it = 0; it < 3; it++) {
      const next = new Float64Array(vn.length);
      for (let i = 0; i < vn.length / 3; i++) {
        for (let k = 0; k < 3; k++) next[3 * i + k] = vn[3 * i + k];
        for (let e = ring.offsets[i]; e < ring.offsets[i + 1]; e++)
          for (let k = 0; k < 3; k++) next[3 * i + k] += vn[3 * ring.list[e] + k];
      }
      vn = next;
    }
    this.smoothNormals = new Float64Array(index.length);
    for (let f = 0; f < index.length; f += 3) {
      const m = [0, 0, 0];
      for (let j = 0; j < 3; j++) for (let k = 0; k < 3; k++) m[k] += vn[3 * index[f + j] + k];
      const l = Math.hypot(m[0], m[1], m[2]) || 1;
      for (let k = 0; k < 3; k++) this.smoothNormals[f + k] = m[k] / l;
    }
  }
  /**
   * Closest point: { point: Vector3, distance, faceIndex } (reused object). A bound on the
   * distance, when known, prunes the search (searched without it if nothing is that close).
   */
  closest(x, y, z, bound = Infinity) {
    if (this.tree) {
      const found = this.found;
      if (!(bound < Infinity && this.tree.closest(x, y, z, bound, found))) this.tree.closest(x, y, z, Infinity, found);
      this.hit.point.set(found[0], found[1], found[2]);
      this.hit.distance = found[3];
      this.hit.faceIndex = found[4];
      return this.hit;
    }
    this.closestQuery ??= closestPointQuery(this.bvh, this.hit);
    return (bound < Infinity && this.closestQuery(x, y, z, bound)) || this.closestQuery(x, y, z, Infinity);
  }
  /**
   * Closest points of many points (Float64Array, 3 each; bounds as for closest, or null): { points,
   * distances, triangles } (face indices). One batch in the core.
   */
  closestMany(points, bounds = null) {
    if (this.tree) return this.tree.closestMany(points, bounds);
    const n = points.length / 3, out = { points: new Float64Array(3 * n), distances: new Float64Array(n), triangles: new Uint32Array(n) };
    for (let i = 0; i < n; i++) {
      const hit = this.closest(points[3 * i], points[3 * i + 1], points[3 * i + 2], bounds ? bounds[i] : Infinity);
      out.points[3 * i] = hit.point.x, out.points[3 * i + 1] = hit.point.y, out.points[3 * i + 2] = hit.point.z;
      out.distances[i] = hit.distance, out.triangles[i] = hit.faceIndex;
    }
    return out;
  }
  /** Distances from the points (Float64Array, 3 each) to the surface. */
  distances(points) {
    return this.closestMany(points).distances;
  }
  /** The core's closest-point tree (built at the first query; null without the core). */
  get tree() {
    if (!this.core) return null;
    this.#tree ??= this.core.closestPoints({ positions: this.positions64, faces: this.index }, { tree: this.nodes });
    return this.#tree;
  }
  #tree = null;
  /**
   * Frees the core's tree now (else when the surface is collected: not before the remesh's
   * synchronous run ends). A later query builds it again.
   */
  dispose() {
    this.#tree?.dispose();
    this.#tree = null;
  }
  /** Nearest hit of the line through (x,y,z) along ±n within `cap`, or null. */
  castBothWays(x, y, z, n, cap) {
    let best = null;
    for (const s of [1, -1]) {
      this.ray.origin.set(x, y, z);
      this.ray.direction.set(s * n[0], s * n[1], s * n[2]);
      const h = this.bvh.raycastFirst(this.ray, DoubleSide, 0, cap);
      if (h && (!best || h.distance < best.distance)) best = h;
    }
    return best;
  }
  normal(faceIndex) {
    return [this.normals[3 * faceIndex], this.normals[3 * faceIndex + 1], this.normals[3 * faceIndex + 2]];
  }
}

/**
 * The nodes of three-mesh-bvh's packed tree (one root, not indirect; else null) as the core takes
 * them (closest_points.h): per node its box, and first / count (a leaf's triangles; an inner
 * node's second child, count 0xffffffff). Read as closestPointQuery reads them.
 */
export function bvhNodes(bvh) {
  const roots = bvh._roots;
  if (!roots || roots.length !== 1 || bvh.indirect) return null;
  const f32 = new Float32Array(roots[0]), u16 = new Uint16Array(roots[0]), u32 = new Uint32Array(roots[0]);
  const count = f32.length / 8;
  const nodes = { bounds: new Float64Array(6 * count), first: new Uint32Array(count), count: new Uint32Array(count) };
  for (let i = 0; i < count; i++) {
    const n32 = 8 * i;
    for (let k = 0; k < 6; k++) nodes.bounds[6 * i + k] = f32[n32 + k];
    if (u16[2 * n32 + 15] === 0xffff) nodes.first[i] = u32[n32 + 6], nodes.count[i] = u16[2 * n32 + 14];
    else nodes.first[i] = i + u32[n32 + 6], nodes.count[i] = 0xffffffff;
  }
  return nodes;
}

/**
 * three-mesh-bvh's closestPointToPoint (0.9.x) without its generic shapecast (callbacks, boxes and
 * triangles as objects: most of the remesher's time): the same traversal of the packed BVH (the
 * nearer child first, pruned by the best squared distance and the bound) and the same
 * floating-point steps as three's Triangle.closestPointToPoint on the Float32 positions, so the
 * same result bit for bit. Writes into `hit` ({ point, distance, faceIndex }); null if nothing
 * lies within `maxDistance`.
 */
export function closestPointQuery(bvh, hit) {
  const roots = bvh._roots;
  if (!roots || roots.length !== 1 || bvh.indirect) {
    const point = new Vector3();
    return (x, y, z, maxDistance) => bvh.closestPointToPoint(point.set(x, y, z), hit, 0, maxDistance);
  }
  const f32 = new Float32Array(roots[0]), u16 = new Uint16Array(roots[0]), u32 = new Uint32Array(roots[0]);
  const index = bvh.geometry.index.array, pos = bvh.geometry.attributes.position.array;
  let px = 0, py = 0, pz = 0, bestSq = Infinity, maxSq = Infinity, bestTri = -1, bx = 0, by = 0, bz = 0;
  const boxScore = (n32) => {
    const dx = Math.max(f32[n32], Math.min(f32[n32 + 3], px)) - px;
    const dy = Math.max(f32[n32 + 1], Math.min(f32[n32 + 4], py)) - py;
    const dz = Math.max(f32[n32 + 2], Math.min(f32[n32 + 5], pz)) - pz;
    return dx * dx + dy * dy + dz * dz;
  };
  const leaf = (n32) => {
    const offset = u32[n32 + 6], end = offset + u16[2 * n32 + 14];
    for (let t = offset; t < end; t++) {
      const ia = 3 * index[3 * t], ib = 3 * index[3 * t + 1], ic = 3 * index[3 * t + 2];
      const ax = pos[ia], ay = pos[ia + 1], az = pos[ia + 2];
      const abx = pos[ib] - ax, aby = pos[ib + 1] - ay, abz = pos[ib + 2] - az;
      const acx = pos[ic] - ax, acy = pos[ic + 1] - ay, acz = pos[ic + 2] - az;
      const apx = px - ax, apy = py - ay, apz = pz - az;
      let qx, qy, qz;
      const d1 = abx * apx + aby * apy + abz * apz, d2 = acx * apx + acy * apy + acz * apz;
      if (d1 <= 0 && d2 <= 0) {
        qx = ax, qy = ay, qz = az;
      } else {
        const bpx = px - pos[ib], bpy = py - pos[ib + 1], bpz = pz - pos[ib + 2];
        const d3 = abx * bpx + aby * bpy + abz * bpz, d4 = acx * bpx + acy * bpy + acz * bpz;
        if (d3 >= 0 && d4 <= d3) {
          qx = pos[ib], qy = pos[ib + 1], qz = pos[ib + 2];
        } else {
          const vc = d1 * d4 - d3 * d2;
          if (vc <= 0 && d1 >= 0 && d3 <= 0 && d1 - d3 > 0) {
            const v = d1 / (d1 - d3);
            qx = ax + abx * v, qy = ay + aby * v, qz = az + abz * v;
          } else {
            const cpx = px - pos[ic], cpy = py - pos[ic + 1], cpz = pz - pos[ic + 2];
            const d5 = abx * cpx + aby * cpy + abz * cpz, d6 = acx * cpx + acy * cpy + acz * cpz;
            if (d6 >= 0 && d5 <= d6) {
              qx = pos[ic], qy = pos[ic + 1], qz = pos[ic + 2];
            } else {
              const vb = d5 * d2 - d1 * d6;
              if (vb <= 0 && d2 >= 0 && d6 <= 0) {
                const w = d2 / (d2 - d6);
                qx = ax + acx * w, qy = ay + acy * w, qz = az + acz * w;
              } else {
                const va = d3 * d6 - d5 * d4;
                if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
                  const w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
                  const bcx = pos[ic] - pos[ib], bcy = pos[ic + 1] - pos[ib + 1], bcz = pos[ic + 2] - pos[ib + 2];
                  qx = pos[ib] + bcx * w, qy = pos[ib + 1] + bcy * w, qz = pos[ib + 2] + bcz * w;
                } else {
                  const denom = 1 / (va + vb + vc), v = vb * denom, w = vc * denom;
                  qx = ax + abx * v + acx * w, qy = ay + aby * v + acy * w, qz = az + abz * v + acz * w;
                }
              }
            }
          }
        }
      }
      const ex = px - qx, ey = py - qy, ez = pz - qz, dSq = ex * ex + ey * ey + ez * ez;
      if (dSq < bestSq) bestSq = dSq, bestTri = t, bx = qx, by = qy, bz = qz;
    }
  };
  // Depth first, the nearer child first, each child checked against the best distance so far.
  const traverse = (n32) => {
    if (u16[2 * n32 + 15] === 0xffff) return leaf(n32);
    let c1 = n32 + 8, c2 = n32 + 8 * u32[n32 + 6];
    let s1 = boxScore(c1), s2 = boxScore(c2);
    if (s2 < s1) {
      const c = c1; c1 = c2, c2 = c;
      const s = s1; s1 = s2, s2 = s;
    }
    if (s1 < bestSq && s1 < maxSq) traverse(c1);
    if (s2 < bestSq && s2 < maxSq) traverse(c2);
  };
  return (x, y, z, maxDistance) => {
    px = x, py = y, pz = z, bestSq = Infinity, maxSq = maxDistance * maxDistance, bestTri = -1;
    traverse(0);
    if (bestSq === Infinity) return null;
    hit.point.set(bx, by, bz);
    hit.distance = Math.sqrt(bestSq);
    hit.faceIndex = bestTri;
    return hit;
  };
}

// ---- simplification --------------------------------------------------------------------------------

/**
 * meshoptimizer's simplifier to about `targetFaces`, compacted; the vertices of `lock` (a mask,
 * or null) are kept. The output's vertices are input vertices (same coordinates).
 */
function simplifyOnce(mesh, targetFaces, lock, emphasis = null) {
  const positions32 = Float32Array.from(mesh.positions);
  const attributes = emphasis ? emphasisAttributes(mesh.positions, emphasis) : new Float32Array(0);
  const [indices] = lock || emphasis
    ? MeshoptSimplifier.simplifyWithAttributes(mesh.faces, positions32, 3, attributes, emphasis ? 3 : 0, emphasis ? [1, 1, 1] : [], lock, 3 * targetFaces, emphasis ? 1e30 : 1.0, [])
    : MeshoptSimplifier.simplify(mesh.faces, positions32, 3, 3 * targetFaces, 1.0, []);
  const copy = Uint32Array.from(indices);
  const [remap, unique] = MeshoptSimplifier.compactMesh(copy);
  const positions = new Float64Array(3 * unique);
  // compactMesh rewrote `copy` in place; remap[old] = new (or 0xffffffff when unused).
  for (let i = 0; i < remap.length; i++)
    if (remap[i] !== 0xffffffff) for (let k = 0; k < 3; k++) positions[3 * remap[i] + k] = mesh.positions[3 * i + k];
  return { positions, faces: copy };
}

/**
 * A base mesh of about `targetFaces` faces for one component, closed, manifold, one component,
 * with the input's genus: the simplifier's output is validated, and the target raised by half
 * until one passes. A component smaller than the target is its own base.
 */
/**
 * The attributes that make meshoptimizer keep detail where `emphasis` (a weight per vertex, 0
 * elsewhere) is high: the position scaled to the simplifier's unit box, times the weight. Its
 * attribute error then grows like the weight squared times the geometric one there, so collapses
 * go elsewhere and the base keeps more of those regions at the same face count.
 */
function emphasisAttributes(positions, emphasis) {
  const n = positions.length / 3, lo = [Infinity, Infinity, Infinity];
  let extent = 0;
  for (let k = 0; k < 3; k++) {
    let hi = -Infinity;
    for (let v = 0; v < n; v++) lo[k] = Math.min(lo[k], positions[3 * v + k]), hi = Math.max(hi, positions[3 * v + k]);
    extent = Math.max(extent, hi - lo[k]);
  }
  const out = new Float32Array(3 * n), scale = 1 / (extent || 1);
  for (let v = 0; v < n; v++) for (let k = 0; k < 3; k++) out[3 * v + k] = emphasis[v] * (positions[3 * v + k] - lo[k]) * scale;
  return out;
}

/**
 * Per vertex of `mesh`: how far the fit whose distances (per vertex) are `distances` left its
 * neighbourhood, as a weight for emphasisAttributes(): distance over `limit` (up to `cap`) at the
 * far vertices, falling off linearly to 0 at `radius` from them; added to `into` (max) if given;
 * null if no vertex is far and there is no `into`.
 */
function farEmphasis(mesh, distances, limit, radius, cap, into = null) {
  const p = mesh.positions, n = p.length / 3;
  // A piece with nothing far keeps its plain base (null).
  if (!into && !distances.some((d) => d > limit)) return null;
  const out = into ?? new Float32Array(n);
  const grid = pointGrid(p, radius);
  // The grid's cells read in place (not within()'s lists: the 871k scan's tens of thousands of far
  // vertices have thousands of neighbours each); a vertex already weighted at w or more keeps its weight.
  const near = 1.000001 * radius * radius;
  for (let u = 0; u < n; u++) {
    if (!(distances[u] > limit)) continue;
    const w = Math.min(cap, distances[u] / limit), x = p[3 * u], y = p[3 * u + 1], z = p[3 * u + 2];
    for (const cell of grid.cellsNear(x, y, z, radius))
      for (let j = grid.start[cell]; j < grid.start[cell + 1]; j++) {
        const v = grid.order[j];
        if (out[v] >= w) continue;
        const dx = p[3 * v] - x, dy = p[3 * v + 1] - y, dz = p[3 * v + 2] - z;
        if (dx * dx + dy * dy + dz * dz > near) continue;
        const r = hypot3(dx, dy, dz);
        if (r <= radius) out[v] = Math.max(out[v], w * (1 - r / radius));
      }
  }
  return out;
}

function simplifyToBase(mrvol, mesh, genus, targetFaces, attempts, repairBase, lock, emphasis = null) {
  // An emphasised base is asked for again when the early emphasis round (remesh) is not kept: known
  // by its weights' values (the rounds add to a weights array in place).
  if (emphasis) {
    let made = emphasisedMade.get(mesh);
    if (!made) emphasisedMade.set(mesh, (made = []));
    const key = `${genus} ${targetFaces} ${attempts} ${repairBase} ${lockKey(lock)}`;
    let known = made.find((m) => m.key === key && m.emphasis.length === emphasis.length && m.emphasis.every((w, v) => w === emphasis[v]));
    if (!known) made.push((known = { key, emphasis: emphasis.slice(), base: makeBase(mrvol, mesh, genus, targetFaces, attempts, repairBase, lock, emphasis) }));
    return known.base;
  }
  // The same piece, target and lock give the same base (meshoptimizer, the checks and the collapse are
  // deterministic): made once per remesh (the fits at 2, 3, 4 levels ask for the same base; on the large
  // scans each simplification of the whole piece costs seconds). The base is only read by its users.
  let known = basesMade.get(mesh);
  if (!known) basesMade.set(mesh, (known = new Map()));
  const key = `${genus} ${targetFaces} ${attempts} ${repairBase} ${lockKey(lock)}`;
  if (!known.has(key)) known.set(key, makeBase(mrvol, mesh, genus, targetFaces, attempts, repairBase, lock));
  return known.get(key);
}

/** Bases made per input piece (its mesh object): by simplifyToBase()'s arguments; the emphasised ones apart. */
const basesMade = new WeakMap(), emphasisedMade = new WeakMap();

/** The locked vertices of `lock` (a mask or null) as a string. */
function lockKey(lock) {
  if (!lock) return '-';
  const locked = [];
  for (let v = 0; v < lock.length; v++) if (lock[v]) locked.push(v);
  return locked.join(',');
}

/** Per input piece (its mesh object): the largest base size whose simplification lost its genus. */
const genusLostAt = new WeakMap();

/** simplifyToBase()'s work. */
function makeBase(mrvol, mesh, genus, targetFaces, attempts, repairBase, lock, emphasis = null) {
  const problems = [];
  const first = Math.max(4, targetFaces);
  let target = first;
  for (let attempt = 0; attempt < attempts; attempt++, target = Math.ceil(target * 1.5)) {
    if (target >= mesh.faces.length / 3) return { base: mesh, target, problems, simplified: false };
    // The piece's tiny tunnels closed in a base at least this large already: a smaller one loses
    // them too, and only the third try takes a base of another genus (each simplification of the
    // 871k scan costs about a second, three per base).
    const lost = genusLostAt.get(mesh) ?? 0;
    if (attempt < 2 && target <= lost) {
      problems.push(`${target} faces: not simplified (the genus was lost at ${lost} faces)`);
      continue;
    }
    // (Simplified from the whole piece each time: bases of the 871k scan made from one 60k-face
    // intermediate cost 30% less CPU but fitted farther, 0.55% -> 2.24%, with its genus-changed bases
    // collapsed back: tried and dropped.)
    let base = simplifyOnce(mesh, target, lock, emphasis);
    const check = (m = base, wanted = genus) => {
      try {
        const v = mrvol.validate(m);
        if (!v.closed) return `${v.boundaryEdges} boundary edges`;
        if (v.components !== 1) return `${v.components} components`;
        if (v.genus !== wanted) return `genus ${v.genus} instead of ${wanted}`;
        return null;
      } catch (e) {
        return e.message;
      }
    };
    let problem = check();
    // On a repaired scan thin parts collapse into fins and pinched edges: the same repair (small
    // holes only) cleans the base, which must then pass the same checks.
    if (problem && repairBase) {
      base = repair(base, { maxHoleEdges: 12, sharpCorners: true }).mesh;
      problem = check();
    }
    if (!problem) {
      // A larger base passed (a scan's thin parts pinched at the smaller ones): collapsed back to
      // the size asked for by collapseToTarget() (lib/remesh-collapse.mjs), which keeps the
      // topology, rather than a cage 1.5x larger per failed try.
      if (attempt > 0) {
        const smaller = collapseToTarget(base, first, lockOf(base, mesh, lock));
        if (smaller.faces.length < base.faces.length && !check(smaller))
          return { base: smaller, target: first, problems, simplified: true, collapsedFrom: base.faces.length / 3 };
      }
      return { base, target, problems, simplified: true };
    }
    problems.push(`${target} faces: ${problem}`);
    if (/^genus \d+ instead of/.test(problem)) genusLostAt.set(mesh, Math.max(lost, target));
    // Tiny tunnels of a scan (genus 52 for the full dragon) close at any cage size: after two
    // tries a closed, manifold, one-piece base of another genus is taken (reported).
    // Collapsed back to the size asked for as well (collapseToTarget keeps the genus it has): the
    // full dragon's base of 3376 faces (a 1722-handle cage) was kept as it came.
    if (attempt >= 2 && /^genus \d+ instead of/.test(problem)) {
      const changed = { base, target, problems, simplified: true, genusChanged: true };
      const had = mrvol.validate(base).genus;
      const smaller = collapseToTarget(base, first, lockOf(base, mesh, lock));
      if (smaller.faces.length < base.faces.length && !check(smaller, had))
        return { ...changed, base: smaller, target: first, collapsedFrom: base.faces.length / 3 };
      return changed;
    }
  }
  // Nothing simpler passed: the component itself is the base (always valid).
  return { base: mesh, target, problems, simplified: false };
}

/**
 * A base made by collapseToTarget() straight from the piece, with its MAPS parametrisation (the
 * base -> input map); null (the simplifier's base is taken) when the piece is too large for the
 * plain-JS collapse or the base does not pass the checks.
 */
function parametrisedBase(mrvol, piece, target, lock) {
  const mesh = piece.mesh;
  if (target >= mesh.faces.length / 3 || mesh.faces.length / 3 > PARAMETRISE_MAX_FACES) return null;
  const base = collapseToTarget(mesh, target, lock, { track: true });
  try {
    const v = mrvol.validate(base);
    if (!v.closed || v.components !== 1 || v.genus !== piece.genus) return null;
  } catch {
    return null;
  }
  const parametrisation = new BaseParametrisation(base, mesh, base.parameters);
  return { base: { positions: base.positions, faces: base.faces }, target, problems: [], simplified: true, parametrisation };
}
/**
 * A base of `target` faces refined around some points (where the closest fit stayed far): the
 * vertices of the simplifier's base of twice the size within `radius` of them (`at`, x y z each)
 * are locked in the simplification to `target` (they are input vertices), so that the faces are
 * spent there and saved elsewhere. Null if that base is not simplified. (When its fit folds, the
 * fit's base twice as large is made the same way, around the same points.)
 */
function refinedBase(mrvol, piece, target, repairBase, lock, emphasis, at, radius) {
  const mesh = piece.mesh;
  const larger = simplifyToBase(mrvol, mesh, piece.genus, 2 * target, 8, repairBase, lock, emphasis);
  if (!larger.simplified) return null;
  const p = larger.base.positions, keys = new Set();
  for (let v = 0; v < p.length / 3; v++)
    for (let j = 0; j < at.length; j += 3)
      if (hypot3(p[3 * v] - at[j], p[3 * v + 1] - at[j + 1], p[3 * v + 2] - at[j + 2]) <= radius) {
        keys.add(positionKey(p, v));
        break;
      }
  if (keys.size === 0) return null;
  const refined = lock ? Uint8Array.from(lock) : new Uint8Array(mesh.positions.length / 3);
  for (let v = 0; v < refined.length; v++) if (keys.has(positionKey(mesh.positions, v))) refined[v] = 1;
  const b = simplifyToBase(mrvol, mesh, piece.genus, target, 8, repairBase, refined, emphasis);
  return b.simplified ? { ...b, refined: keys.size } : null;
}
// Around a far point, the larger base's vertices locked in a refined base: within this (of the diagonal).
const REFINED_RADIUS = 0.03;

// Above this the Maps and Sets of the JS collapse take too long: the simplifier's base instead.
const PARAMETRISE_MAX_FACES = 60000;

/** The most faces a remesh makes: those of the 2,621,442-vertex sphere, the largest mesh the editor is benchmarked on (issue 14). */
export const MAX_RESULT_FACES = 5242880;

/** `lock` (a mask over the vertices of `mesh`, or null) as a mask over those of `base` (by position). */
function lockOf(base, mesh, lock) {
  if (!lock) return null;
  const keys = new Set();
  for (let v = 0; v < lock.length; v++) if (lock[v]) keys.add(positionKey(mesh.positions, v));
  const out = new Uint8Array(base.positions.length / 3);
  for (let v = 0; v < out.length; v++) if (keys.has(positionKey(base.positions, v))) out[v] = 1;
  return out;
}

/** The faces of component `c` (of `ofFace`) as a mesh of their own (exact positions). */
function componentMesh(mesh, ofFace, c) {
  const faces = [];
  for (let f = 0; f < ofFace.length; f++) if (ofFace[f] === c) faces.push(mesh.faces[3 * f], mesh.faces[3 * f + 1], mesh.faces[3 * f + 2]);
  return weld({ positions: mesh.positions, faces: Uint32Array.from(faces) });
}


// ---- fitting the subdivided mesh to the surface ------------------------------------------------

/**
 * Tangential uniform-Laplacian smoothing, each step followed by closest-point reprojection. With
 * `constraints` (lib/features.mjs): corners stay, vertices on a feature line move towards the
 * mean of their two neighbours on that line and back onto it.
 */
function relaxTangentially(surface, positions, faces, adjacency, iterations, weight, fixed, constraints = null) {
  const { offsets, list } = adjacency;
  const vertexCount = positions.length / 3;
  // Only the vertices that move (in this level's mesh, not held) are computed.
  let count = 0;
  const kind = constraints?.kind;
  const moves = (i) => offsets[i + 1] > offsets[i] && !fixed[i] && !(kind && kind[i] === 2);
  for (let i = 0; i < vertexCount; i++) if (moves(i)) count++;
  if (count === 0) return;
  const active = new Uint32Array(count);
  for (let i = 0, c = 0; i < vertexCount; i++) if (moves(i)) active[c++] = i;
  const next = new Float64Array(3 * count);
  // The moved points, projected in one batch (the vertices that slide on a feature line are not).
  const targets = new Float64Array(3 * count), bounds = new Float64Array(count), projected = new Uint32Array(count);
  // Few vertices: their normals from their own faces (the same sums, in the same face order).
  const local = count < vertexCount / 4;
  const around = local ? connectivity(faces, vertexCount).vertexFaces : null;
  const normals = local ? new Float64Array(3 * count) : null;
  for (let it = 0; it < iterations; it++) {
    let all = null;
    if (local) {
      for (let c = 0; c < count; c++) {
        const i = active[c];
        let n0 = 0, n1 = 0, n2 = 0;
        for (let e = around.offsets[i]; e < around.offsets[i + 1]; e++) {
          const f = 3 * around.list[e];
          const t = triangleNormal(positions, faces[f], faces[f + 1], faces[f + 2]);
          n0 += t[0], n1 += t[1], n2 += t[2];
        }
        const l = hypot3(n0, n1, n2) || 1;
        normals[3 * c] = n0 / l, normals[3 * c + 1] = n1 / l, normals[3 * c + 2] = n2 / l;
      }
    } else {
      all = vertexNormals(positions, faces);
    }
    let toProject = 0;
    for (let c = 0; c < count; c++) {
      const i = active[c], m = local ? 3 * c : 3 * i, nv = local ? normals : all;
      if (kind && kind[i] === 1) {
        slideOnLine(constraints, positions, adjacency, i, weight, next, 3 * c);
        continue;
      }
      const degree = offsets[i + 1] - offsets[i];
      let d0 = 0, d1 = 0, d2 = 0;
      for (let e = offsets[i]; e < offsets[i + 1]; e++) {
        const w = 3 * list[e];
        d0 += positions[w], d1 += positions[w + 1], d2 += positions[w + 2];
      }
      d0 = d0 / degree - positions[3 * i], d1 = d1 / degree - positions[3 * i + 1], d2 = d2 / degree - positions[3 * i + 2];
      const dn = d0 * nv[m] + d1 * nv[m + 1] + d2 * nv[m + 2];
      const x = positions[3 * i] + weight * (d0 - dn * nv[m]);
      const y = positions[3 * i + 1] + weight * (d1 - dn * nv[m + 1]);
      const z = positions[3 * i + 2] + weight * (d2 - dn * nv[m + 2]);
      // The vertex was on the surface: the step is an upper bound of the distance back to it.
      const step = weight * hypot3(d0, d1, d2);
      const t = toProject++;
      targets[3 * t] = x, targets[3 * t + 1] = y, targets[3 * t + 2] = z, bounds[t] = 1.01 * step + 1e-12, projected[t] = c;
    }
    if (toProject > 0) {
      const onSurface = surface.closestMany(targets.subarray(0, 3 * toProject), bounds.subarray(0, toProject)).points;
      for (let t = 0; t < toProject; t++) {
        const c = projected[t];
        next[3 * c] = onSurface[3 * t], next[3 * c + 1] = onSurface[3 * t + 1], next[3 * c + 2] = onSurface[3 * t + 2];
      }
    }
    for (let c = 0; c < count; c++) {
      const i = active[c];
      positions[3 * i] = next[3 * c], positions[3 * i + 1] = next[3 * c + 1], positions[3 * i + 2] = next[3 * c + 2];
    }
  }
}

/** Moves vertex i on its feature line towards the mean of its two neighbours on that line; into next[at..]. */
function slideOnLine(constraints, positions, adjacency, i, weight, next, at) {
  const id = constraints.line[i];
  let count = 0, x = 0, y = 0, z = 0;
  for (let e = adjacency.offsets[i]; e < adjacency.offsets[i + 1]; e++) {
    const w = adjacency.list[e];
    if (!constraints.onLine(w, id)) continue;
    count++, x += positions[3 * w], y += positions[3 * w + 1], z += positions[3 * w + 2];
  }
  if (count !== 2) {
    next[at] = positions[3 * i], next[at + 1] = positions[3 * i + 1], next[at + 2] = positions[3 * i + 2];
    return;
  }
  const q = constraints.features.projectToLine(id, positions[3 * i] + weight * (x / 2 - positions[3 * i]),
                                               positions[3 * i + 1] + weight * (y / 2 - positions[3 * i + 1]),
                                               positions[3 * i + 2] + weight * (z / 2 - positions[3 * i + 2]));
  next[at] = q[0], next[at + 1] = q[1], next[at + 2] = q[2];
}

/**
 * Tips and ridges the base mesh cut off stay cut off by the fit (rays from a midpoint do not reach
 * them and relaxation does not spread outwards). Each input vertex farther than 0.2% of the
 * diagonal from the result pulls the nearest corner of the closest result triangle onto itself
 * (at most a local edge length away); those corners are then held while the others relax, and a
 * snap that folds the surface (flipped triangles around it) is pulled halfway back, twice, then
 * undone. Two rounds. Returns the input's closest points on the result (an InputOnResult whose
 * limit is the threshold) if a round ended with nothing to snap (the result as they were found: the
 * pull after it starts from them), else null.
 */
function snapToFeatures(surface, positions, faces, relaxIterations, constraints = null) {
  const input = surface.mesh.positions;
  const threshold = 0.002 * boundingDiagonal(input);
  const vertexCount = positions.length / 3;
  // Vertices on features are not snapped (held = 2: never).
  const held = constraints ? constraints.kind.map((k) => (k ? 2 : 0)) : new Uint8Array(vertexCount);
  const adjacency = connectivity(faces, vertexCount).neighbours;
  const closest = new InputOnResult(input, threshold);
  for (let round = 0; round < 2; round++) {
    const { distances, corners } = closest.update(positions, faces), candidates = [];
    for (let i = 0; i < input.length / 3; i++)
      if (distances[i] > threshold) candidates.push([distances[i], i]);
    if (candidates.length === 0) return closest;
    candidates.sort((a, b) => b[0] - a[0]);
    let moved = 0;
    const before = new Map();
    for (const [, i] of candidates) {
      let best = -1, bestDistance = Infinity;
      for (let j = 0; j < 3; j++) {
        const v = corners[3 * i + j];
        if (held[v]) continue;
        const d = hypot3(positions[3 * v] - input[3 * i], positions[3 * v + 1] - input[3 * i + 1], positions[3 * v + 2] - input[3 * i + 2]);
        if (d < bestDistance) best = v, bestDistance = d;
      }
      if (best < 0) continue;
      // The move must stay local: no farther than the longest edge at that vertex.
      let reach = 0;
      for (let e = adjacency.offsets[best]; e < adjacency.offsets[best + 1]; e++) {
        const w = adjacency.list[e];
        reach = Math.max(reach, hypot3(positions[3 * w] - positions[3 * best], positions[3 * w + 1] - positions[3 * best + 1], positions[3 * w + 2] - positions[3 * best + 2]));
      }
      if (bestDistance > reach) continue;
      before.set(best, positions.slice(3 * best, 3 * best + 3));
      for (let k = 0; k < 3; k++) positions[3 * best + k] = input[3 * i + k];
      held[best] = 1;
      moved++;
    }
    if (moved === 0) return closest;
    // Only the neighbourhood of the snapped vertices (6 rings) relaxes and is checked for folds.
    let front = [...before.keys()];
    const near = new Uint8Array(vertexCount);
    for (const v of front) near[v] = 1;
    for (let ring = 0; ring < 6; ring++) {
      const next = [];
      for (const v of front)
        for (let e = adjacency.offsets[v]; e < adjacency.offsets[v + 1]; e++)
          if (!near[adjacency.list[e]]) near[adjacency.list[e]] = 1, next.push(adjacency.list[e]);
      front = next;
    }
    const nearFaces = [];
    for (let f = 0; f < faces.length / 3; f++)
      if (near[faces[3 * f]] || near[faces[3 * f + 1]] || near[faces[3 * f + 2]]) nearFaces.push(f);
    const frozen = () => held.map((h, v) => (h === 1 || !near[v] ? 1 : 0));
    if (relaxIterations > 0) relaxTangentially(surface, positions, faces, adjacency, relaxIterations, 0.5, frozen(), constraints);
    // A snap that folds the surface is undone: the corners of flipped triangles go back.
    for (let pass = 0; pass < 4; pass++) {
      const flipped = flippedFaces({ positions, faces }, surface, nearFaces);
      const touched = new Set();
      let undone = 0;
      for (const f of flipped)
        for (let j = 0; j < 3; j++) {
          const v = faces[3 * f + j];
          if (held[v] !== 1 || !before.has(v) || touched.has(v)) continue;
          touched.add(v);
          const b = before.get(v);
          if (pass < 2) {
            // Halfway back first (then reprojected): part of the tip is kept if that unfolds it.
            const p = surface.closest((b[0] + positions[3 * v]) / 2, (b[1] + positions[3 * v + 1]) / 2, (b[2] + positions[3 * v + 2]) / 2).point;
            positions[3 * v] = p.x, positions[3 * v + 1] = p.y, positions[3 * v + 2] = p.z;
          } else {
            positions.set(b, 3 * v);
            held[v] = 2;  // never snapped again
          }
          undone++;
        }
      if (undone === 0) break;
      if (relaxIterations > 0) relaxTangentially(surface, positions, faces, adjacency, relaxIterations, 0.5, frozen(), constraints);
    }
  }
  return null;
}

/**
 * Two-sided fitting, after snapToFeatures(): what is still far from the result (a thin tip the
 * base cut off and the fit slid down from) is pulled back gradually. Each round, the input
 * vertices farther than 0.2% of the diagonal and than half the current worst distance pull the
 * corners of their closest result triangle by their offset (barycentric weights, farther points
 * weighing more); the pulled corners go back onto the surface and are held while their 3-ring
 * relaxes; the corners of triangles that this flips, and their neighbours, return (and are not
 * pulled again). A round is kept only if it lowers the worst input-vertex distance (or keeps it
 * and lowers the sum of squared excesses); otherwise it is undone and retried with half the
 * step, down to a quarter. At most `rounds` rounds. Deterministic. `known`: the input's closest
 * points on the result as it is (snapToFeatures' answer), else null.
 */
function attractToInput(surface, positions, faces, { threshold = 0.002, focus = 0.5, rounds = 10 } = {}, constraints = null, known = null) {
  const input = surface.mesh.positions, inputCount = input.length / 3;
  const limit = threshold * boundingDiagonal(input);
  const vertexCount = positions.length / 3;
  let adjacency = null;
  // Vertices on features stay on them.
  const noMore = constraints ? constraints.kind.map((k) => (k ? 1 : 0)) : new Uint8Array(vertexCount);
  const disp = new Float64Array(3 * vertexCount), weight = new Float64Array(vertexCount);
  // The input's closest points, asked again each round where they can be beyond the limit.
  const closest = known && known.limit <= limit ? known : new InputOnResult(input, limit);
  let accepted = null, acceptedWorst = Infinity, acceptedExcess = Infinity, step = 1, retry = false;
  for (let round = 0; round < rounds; round++) {
    const { distances: distance, points: hitPoint, corners: hitCorners } = closest.update(positions, faces);
    let worst = 0, excess = 0;
    for (let i = 0; i < inputCount; i++) {
      worst = Math.max(worst, distance[i]);
      if (distance[i] > limit) excess += (distance[i] - limit) ** 2;
    }
    if (worst <= limit) break;
    if (accepted && !retry && !(worst < acceptedWorst || (worst <= 1.001 * acceptedWorst && excess < acceptedExcess))) {
      positions.set(accepted);
      step /= 2;
      if (step < 0.25) break;
      retry = true;
      continue;
    }
    if (!retry) {
      step = 1;
      accepted = positions.slice(), acceptedWorst = worst, acceptedExcess = excess;
    }
    retry = false;
    adjacency ??= connectivity(faces, vertexCount).neighbours;
    disp.fill(0), weight.fill(0);
    const pull = Math.max(limit, focus * worst);
    for (let i = 0; i < inputCount; i++) {
      if (distance[i] <= pull) continue;
      const qx = hitPoint[3 * i], qy = hitPoint[3 * i + 1], qz = hitPoint[3 * i + 2];
      const corners = [hitCorners[3 * i], hitCorners[3 * i + 1], hitCorners[3 * i + 2]];
      const w = barycentric(positions, corners[0], corners[1], corners[2], qx, qy, qz);
      const o = [input[3 * i] - qx, input[3 * i + 1] - qy, input[3 * i + 2] - qz];
      for (let j = 0; j < 3; j++) {
        const v = corners[j];
        if (noMore[v] || w[j] <= 0) continue;
        const s = w[j] * distance[i];
        for (let k = 0; k < 3; k++) disp[3 * v + k] += s * o[k];
        weight[v] += s;
      }
    }
    const before = positions.slice();
    const moved = [];
    for (let v = 0; v < vertexCount; v++) if (weight[v] !== 0) moved.push(v);
    // The pulled points back onto the surface in one batch.
    const pulled = new Float64Array(3 * moved.length);
    for (const [t, v] of moved.entries()) {
      const s = step / weight[v];
      for (let k = 0; k < 3; k++) pulled[3 * t + k] = positions[3 * v + k] + s * disp[3 * v + k];
    }
    const onSurface = surface.closestMany(pulled).points;
    for (const [t, v] of moved.entries()) for (let k = 0; k < 3; k++) positions[3 * v + k] = onSurface[3 * t + k];
    if (moved.length === 0) break;
    // The 3-ring around the pulled corners relaxes (they are held) and is checked for folds.
    const near = new Uint8Array(vertexCount);
    let front = moved;
    for (const v of front) near[v] = 1;
    for (let ring = 0; ring < 3; ring++) {
      const next = [];
      for (const v of front)
        for (let e = adjacency.offsets[v]; e < adjacency.offsets[v + 1]; e++)
          if (!near[adjacency.list[e]]) near[adjacency.list[e]] = 1, next.push(adjacency.list[e]);
      front = next;
    }
    const frozen = new Uint8Array(vertexCount);
    for (let v = 0; v < vertexCount; v++) frozen[v] = !near[v] || weight[v] > 0 ? 1 : 0;
    relaxTangentially(surface, positions, faces, adjacency, 2, 0.5, frozen, constraints);
    const nearFaces = [];
    for (let f = 0; f < faces.length / 3; f++)
      if (near[faces[3 * f]] || near[faces[3 * f + 1]] || near[faces[3 * f + 2]]) nearFaces.push(f);
    // Triangles already flipped before the round (there should be none) are not its doing.
    // (Found only when something is flipped after it: usually nothing is.)
    let flippedBefore = null;
    for (let pass = 0; pass < 6; pass++) {
      let flipped = flippedFaces({ positions, faces }, surface, nearFaces);
      if (flipped.length > 0) {
        flippedBefore ??= new Set(flippedFaces({ positions: before, faces }, surface, nearFaces));
        flipped = flipped.filter((f) => !flippedBefore.has(f));
      }
      if (flipped.length === 0) break;
      const back = (w) => {
        if (weight[w] > 0) noMore[w] = 1;
        for (let k = 0; k < 3; k++) positions[3 * w + k] = before[3 * w + k];
      };
      if (pass === 5) {
        for (let v = 0; v < vertexCount; v++) if (near[v]) back(v);
        break;
      }
      for (const f of flipped)
        for (let j = 0; j < 3; j++) {
          const v = faces[3 * f + j];
          back(v);
          for (let e = adjacency.offsets[v]; e < adjacency.offsets[v + 1]; e++) back(adjacency.list[e]);
        }
    }
  }
  // The last round may have been refused: the accepted state stays.
  if (accepted && retry) positions.set(accepted);
}

/**
 * Tips the fit still misses (a claw, a horn, a lip the base cut off: rays and relaxation never
 * climb them, and attractToInput()'s pulls of one triangle's corners fold there) are reached by
 * dragging a patch: for each input vertex or face centroid farther than `threshold` of the diagonal
 * from the result (the farthest first), one of the result vertices nearest it (a corner of its closest result
 * triangle or a neighbour of one) moves onto it, and the `rings` rings around that vertex follow
 * with a linear falloff, each back onto the surface (closest point). A drag is kept only if it
 * flips no triangle and brings no input vertex near the patch farther from the result, and no
 * patch face's centroid farther from the input, than it was or than `tolerance` of the diagonal;
 * otherwise a smaller drag (3/4, 1/2 of the way), then the next candidate. Vertices on features (`fixed`) stay.
 * `rounds` rounds, each over far input vertices `spacing` of the diagonal apart. Deterministic.
 */
function dragToTips(surface, positions, faces, fixed, { threshold = 0.0025, tolerance = 0.0045, rings = 3, candidates = 2, rounds = 2, spacing = 0.01, perRound = 200 } = {}) {
  // Targets: the input's vertices and face centroids (a large face's middle can be the far part).
  const { positions: inputPositions, faces: inputFaces } = surface.mesh, inputVertices = inputPositions.length / 3;
  const input = new Float64Array(inputPositions.length + inputFaces.length);
  input.set(inputPositions);
  for (let f = 0; f < inputFaces.length / 3; f++)
    for (let k = 0; k < 3; k++)
      input[3 * inputVertices + 3 * f + k] = (inputPositions[3 * inputFaces[3 * f] + k] + inputPositions[3 * inputFaces[3 * f + 1] + k] + inputPositions[3 * inputFaces[3 * f + 2] + k]) / 3;
  const inputCount = input.length / 3;
  const limit = threshold * surface.diagonal, slack = 1e-9 * surface.diagonal, allowed = tolerance * surface.diagonal;
  const vertexCount = positions.length / 3;
  const { neighbours: adjacency, vertexFaces: around, twins } = connectivity(faces, vertexCount);
  const grid = pointGrid(input, 0.01 * surface.diagonal);
  const apart = spacing * surface.diagonal;
  const closest = new InputOnResult(input, limit);
  // The patch faces' centroids on the input (the fold and distance checks before and after each try).
  const centroidsOn = centroidsOnSurface(surface, faces.length / 3);
  let result = null;
  for (let round = 0; round < rounds; round++) {
    result?.dispose();
    result = new Surface({ positions, faces }, { normals: false });
    const index = result.index;
    // The result's BVH is of the round's start (drags of a round are apart, and touch no vertex
    // twice): an input vertex's distance after a drag is the smaller of its distance to the
    // patch's faces and, if its closest face then was not one of them, that distance.
    // Asked as whether that distance is within `limit`: the round's closest point of the q-th near
    // vertex (`before`, a batch) answers first, then the patch's faces until one is that close.
    const withinAfter = (j, q, before, patch, limit) => {
      const f = before.triangles[q];
      if (before.distances[q] <= limit && !(patch.has(index[3 * f]) && patch.has(index[3 * f + 1]) && patch.has(index[3 * f + 2])))
        return true;
      const x = input[3 * j], y = input[3 * j + 1], z = input[3 * j + 2];
      for (const g of patchFaces) if (pointTriangleDistance(x, y, z, positions, faces[3 * g], faces[3 * g + 1], faces[3 * g + 2]) <= limit) return true;
      return false;
    };
    let patchFaces = [];
    // The near input points' closest points on the round's result, each asked once a round (the
    // patches of a coarse fit are wide, and their near points overlap from tip to tip): the same
    // answers as asking each patch's points apart (the tree is the round's start).
    const beforeDistance = new Float64Array(inputCount), beforeTriangle = new Uint32Array(inputCount), known = new Uint8Array(inputCount);
    const beforeOf = (nearInput) => {
      const missing = [];
      for (const j of nearInput) if (!known[j]) missing.push(j);
      if (missing.length > 0) {
        const points = new Float64Array(3 * missing.length);
        for (let q = 0; q < missing.length; q++) {
          const j = missing[q];
          points[3 * q] = input[3 * j], points[3 * q + 1] = input[3 * j + 1], points[3 * q + 2] = input[3 * j + 2];
        }
        const found = result.closestMany(points);
        for (let q = 0; q < missing.length; q++) {
          const j = missing[q];
          beforeDistance[j] = found.distances[q], beforeTriangle[j] = found.triangles[q], known[j] = 1;
        }
      }
      const out = { distances: new Float64Array(nearInput.length), triangles: new Uint32Array(nearInput.length) };
      for (let q = 0; q < nearInput.length; q++) out.distances[q] = beforeDistance[nearInput[q]], out.triangles[q] = beforeTriangle[nearInput[q]];
      return out;
    };
    const far = [], { distances } = closest.update(positions, faces, result);
    for (let i = 0; i < inputCount; i++) if (distances[i] > limit) far.push([distances[i], i]);
    if (far.length === 0) break;
    far.sort((x, y) => y[0] - x[0] || x[1] - y[1]);
    const used = new Uint8Array(vertexCount);
    let kept = 0;
    // A few apart per round (a tip's other far vertices come in the next rounds).
    const tips = [];
    for (const [, i] of far) {
      if (tips.length >= perRound) break;
      if (!tips.some((j) => hypot3(input[3 * i] - input[3 * j], input[3 * i + 1] - input[3 * j + 1], input[3 * i + 2] - input[3 * j + 2]) < apart)) tips.push(i);
    }
    for (const i of tips) {
      const tx = input[3 * i], ty = input[3 * i + 1], tz = input[3 * i + 2];
      const hit = result.closest(tx, ty, tz);
      if (hit.distance <= limit) continue;  // an earlier drag reached it
      const corners = [index[3 * hit.faceIndex], index[3 * hit.faceIndex + 1], index[3 * hit.faceIndex + 2]];
      const near = new Set(corners);
      for (const u of corners) for (let e = adjacency.offsets[u]; e < adjacency.offsets[u + 1]; e++) near.add(adjacency.list[e]);
      const order = [...near].filter((u) => !fixed[u] && !used[u])
        .map((u) => [hypot3(positions[3 * u] - tx, positions[3 * u + 1] - ty, positions[3 * u + 2] - tz), u])
        .sort((x, y) => x[0] - y[0] || x[1] - y[1]).slice(0, candidates);
      let done = false;
      for (const [, v] of order) {
        const ox = tx - positions[3 * v], oy = ty - positions[3 * v + 1], oz = tz - positions[3 * v + 2];
        {
          const k = rings, ring = ringsOf(adjacency, v, k + 1);
          // Patches of one round do not overlap (the BVH is the round's).
          if ([...ring.keys()].some((w) => used[w])) continue;
          const faceSet = new Set();
          for (const [w] of ring) for (let e = around.offsets[w]; e < around.offsets[w + 1]; e++) faceSet.add(around.list[e]);
          const faceList = [...faceSet].sort((x, y) => x - y);
          patchFaces = faceList;
          const nearBefore = centroidsOn(positions, faces, faceList);
          const flippedBefore = new Set(flippedFaces({ positions, faces }, surface, faceList, 0, twins, nearBefore));
          let radius = 0;
          for (const [w, r] of ring) if (r <= k) radius = Math.max(radius, hypot3(positions[3 * w] - positions[3 * v], positions[3 * w + 1] - positions[3 * v + 1], positions[3 * w + 2] - positions[3 * v + 2]));
          const nearInput = grid.within(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2], radius + hypot3(ox, oy, oz));
          const before = beforeOf(nearInput);
          const facesBefore = nearBefore.distances;
          const saved = [];
          for (const [w] of ring) saved.push(w, positions[3 * w], positions[3 * w + 1], positions[3 * w + 2]);
          for (const share of [1, 0.75, 0.5]) {
            for (const [w, r] of ring) {
              if (r > k || fixed[w]) continue;
              const s = share * (1 - r / (k + 1));
              const p = w === v && share === 1 ? { x: tx, y: ty, z: tz }
                : surface.closest(positions[3 * w] + s * ox, positions[3 * w + 1] + s * oy, positions[3 * w + 2] + s * oz).point;
              positions[3 * w] = p.x, positions[3 * w + 1] = p.y, positions[3 * w + 2] = p.z;
            }
            const nearNow = centroidsOn(positions, faces, faceList);
            const good = flippedFaces({ positions, faces }, surface, faceList, 0, twins, nearNow).every((f) => flippedBefore.has(f)) &&
              nearInput.every((j, q) => withinAfter(j, q, before, ring, Math.max(before.distances[q], allowed) + slack)) &&
              faceList.every((f, q) => nearNow.distances[q] <= Math.max(facesBefore[q], allowed) + slack);
            if (good) {
              for (const [w] of ring) used[w] = 1;
              done = true;
              break;
            }
            for (let q = 0; q < saved.length; q += 4) positions[3 * saved[q]] = saved[q + 1], positions[3 * saved[q] + 1] = saved[q + 2], positions[3 * saved[q] + 2] = saved[q + 3];
          }
        }
        if (done) break;
      }
      if (done) kept++;
    }
    if (kept === 0) break;
  }
  result?.dispose();
}

// Distance from (x, y, z) to triangle (a, b, c) of positions p: three's Triangle.closestPointToPoint.
const triangleScratch = new Triangle(), pointScratch = new Vector3(), closestScratch = new Vector3();
function pointTriangleDistance(x, y, z, p, a, b, c) {
  triangleScratch.a.fromArray(p, 3 * a), triangleScratch.b.fromArray(p, 3 * b), triangleScratch.c.fromArray(p, 3 * c);
  pointScratch.set(x, y, z);
  return triangleScratch.closestPointToPoint(pointScratch, closestScratch).distanceTo(pointScratch);
}

/** Ring index (0 = v) of every vertex within `k` edges of v. */
function ringsOf(adjacency, v, k) {
  const ring = new Map([[v, 0]]);
  let front = [v];
  for (let r = 1; r <= k; r++) {
    const next = [];
    for (const u of front)
      for (let e = adjacency.offsets[u]; e < adjacency.offsets[u + 1]; e++)
        if (!ring.has(adjacency.list[e])) ring.set(adjacency.list[e], r), next.push(adjacency.list[e]);
    front = next;
  }
  return ring;
}

/** Barycentric coordinates of the point q (on or near the triangle a, b, c). */
function barycentric(p, a, b, c, qx, qy, qz) {
  const u0 = p[3 * b] - p[3 * a], u1 = p[3 * b + 1] - p[3 * a + 1], u2 = p[3 * b + 2] - p[3 * a + 2];
  const v0 = p[3 * c] - p[3 * a], v1 = p[3 * c + 1] - p[3 * a + 1], v2 = p[3 * c + 2] - p[3 * a + 2];
  const w0 = qx - p[3 * a], w1 = qy - p[3 * a + 1], w2 = qz - p[3 * a + 2];
  const d00 = u0 * u0 + u1 * u1 + u2 * u2, d01 = u0 * v0 + u1 * v1 + u2 * v2, d11 = v0 * v0 + v1 * v1 + v2 * v2;
  const d20 = w0 * u0 + w1 * u1 + w2 * u2, d21 = w0 * v0 + w1 * v1 + w2 * v2;
  const den = d00 * d11 - d01 * d01;
  if (!(den > 0)) return [1 / 3, 1 / 3, 1 / 3];
  const v = (d11 * d20 - d01 * d21) / den, w = (d00 * d21 - d01 * d20) / den;
  return [1 - v - w, v, w];
}

// ---- measures --------------------------------------------------------------------------------------

/**
 * Largest distance from the sample points of `mesh` (vertices, face centroids and three interior
 * points per face, strided to at most `maxSamples`) to `surface`.
 */
function oneSidedHausdorff(mesh, surface, maxSamples) {
  if (surface.tree) return surface.tree.sampledDistanceFrom(mesh, maxSamples);
  const { positions: p, faces } = mesh;
  const vertexCount = p.length / 3, faceCount = faces.length / 3;
  const total = vertexCount + 4 * faceCount;
  const stride = Math.max(1, Math.ceil(total / maxSamples));
  const BARY = [[1 / 3, 1 / 3, 1 / 3], [2 / 3, 1 / 6, 1 / 6], [1 / 6, 2 / 3, 1 / 6], [1 / 6, 1 / 6, 2 / 3]];
  let worst = 0, previous = Infinity, px = 0, py = 0, pz = 0;
  for (let s = 0; s < total; s += stride) {
    let x, y, z;
    if (s < vertexCount) {
      x = p[3 * s], y = p[3 * s + 1], z = p[3 * s + 2];
    } else {
      const f = Math.floor((s - vertexCount) / 4), w = BARY[(s - vertexCount) % 4];
      const a = faces[3 * f], b = faces[3 * f + 1], c = faces[3 * f + 2];
      x = w[0] * p[3 * a] + w[1] * p[3 * b] + w[2] * p[3 * c];
      y = w[0] * p[3 * a + 1] + w[1] * p[3 * b + 1] + w[2] * p[3 * c + 1];
      z = w[0] * p[3 * a + 2] + w[1] * p[3 * b + 2] + w[2] * p[3 * c + 2];
    }
    // Distance to a surface is 1-Lipschitz: the previous sample's distance plus the step bounds it.
    const bound = previous + hypot3(x - px, y - py, z - pz);
    previous = surface.closest(x, y, z, 1.0001 * bound + 1e-12).distance;
    px = x, py = y, pz = z;
    worst = Math.max(worst, previous);
  }
  return worst;
}

/**
 * The result's flipped triangles, but for those whose corners are all held (a piece that is its
 * own base: exact, even where another piece's surface is closer to it than its own).
 */
function resultFlipped(mesh, surface, constraints, onlyFaces = null) {
  const kind = constraints?.kind, f = mesh.faces;
  return flippedFaces(mesh, surface, onlyFaces, RESULT_AGAINST)
    .filter((t) => !(kind && kind[f[3 * t]] === 2 && kind[f[3 * t + 1]] === 2 && kind[f[3 * t + 2]] === 2));
}

/**
 * The result's test: clearly against the input's smoothed normal (a face across a right-angled
 * crease from its closest point is not); the fit's own moves are undone on any disagreement (0).
 */
const RESULT_AGAINST = -0.25;

/**
 * Triangles of `mesh` (or of `onlyFaces`) whose normal points against the surface's (smoothed)
 * normal at the closest point to their centroid (cosine below `against`) and against an edge
 * neighbour's, or that are degenerate.
 */
export function flippedFaces(mesh, surface, onlyFaces = null, against = 0, twins = null, near = null) {
  const { positions: p, faces } = mesh;
  // Edge-adjacent faces: the face on the other side of each directed edge (given, or found).
  const across = twins ?? connectivity(faces, p.length / 3).twins;
  const count = onlyFaces ? onlyFaces.length : faces.length / 3;
  if (!near) {
    const { centroids, bounds } = centroidsAndBounds(p, faces, onlyFaces, count);
    near = surface.closestMany(centroids, bounds);
  }
  return facesAgainst(p, faces, onlyFaces, count, surface, near, against, across);
}

/**
 * The closest points on `surface` of the centroids of a mesh's faces as its positions move: asked
 * only for faces whose centroid changed since they were last asked (a drag tries a patch, undoes
 * it, and the next patch overlaps it). Returns (positions, faces, list) => { distances, triangles }
 * for the faces of `list`, as flippedFaces' batch (or surface.closest of each centroid) gives them.
 */
export function centroidsOnSurface(surface, faceCount) {
  const at = new Float64Array(3 * faceCount), distance = new Float64Array(faceCount), triangle = new Uint32Array(faceCount);
  const asked = new Uint8Array(faceCount);
  return (positions, faces, list) => {
    const { centroids, bounds } = centroidsAndBounds(positions, faces, list, list.length);
    const missing = [];
    for (let q = 0; q < list.length; q++) {
      const f = list[q];
      if (!(asked[f] && at[3 * f] === centroids[3 * q] && at[3 * f + 1] === centroids[3 * q + 1] && at[3 * f + 2] === centroids[3 * q + 2]))
        missing.push(q);
    }
    if (missing.length > 0) {
      const points = new Float64Array(3 * missing.length), limits = new Float64Array(missing.length);
      for (let m = 0; m < missing.length; m++) {
        const q = missing[m];
        points[3 * m] = centroids[3 * q], points[3 * m + 1] = centroids[3 * q + 1], points[3 * m + 2] = centroids[3 * q + 2], limits[m] = bounds[q];
      }
      const found = surface.closestMany(points, limits);
      for (let m = 0; m < missing.length; m++) {
        const q = missing[m], f = list[q];
        at[3 * f] = centroids[3 * q], at[3 * f + 1] = centroids[3 * q + 1], at[3 * f + 2] = centroids[3 * q + 2];
        distance[f] = found.distances[m], triangle[f] = found.triangles[m], asked[f] = 1;
      }
    }
    const out = { distances: new Float64Array(list.length), triangles: new Uint32Array(list.length) };
    for (let q = 0; q < list.length; q++) out.distances[q] = distance[list[q]], out.triangles[q] = triangle[list[q]];
    return out;
  };
}

// flippedFaces' two loops are functions of their own: V8 optimises a long-running loop while it
// runs (on-stack replacement), and code made in the first loop has no type feedback for the
// second, so it bailed out there at every later call.

/** The faces' centroids, and for each a bound on its distance to the surface (the corners lie on it). */
function centroidsAndBounds(p, faces, onlyFaces, count) {
  const centroids = new Float64Array(3 * count), bounds = new Float64Array(count);
  for (let q = 0; q < count; q++) {
    const f = onlyFaces ? onlyFaces[q] : q;
    const a = faces[3 * f], b = faces[3 * f + 1], c = faces[3 * f + 2];
    const cx = (p[3 * a] + p[3 * b] + p[3 * c]) / 3, cy = (p[3 * a + 1] + p[3 * b + 1] + p[3 * c + 1]) / 3,
          cz = (p[3 * a + 2] + p[3 * b + 2] + p[3 * c + 2]) / 3;
    centroids[3 * q] = cx, centroids[3 * q + 1] = cy, centroids[3 * q + 2] = cz;
    // The nearest corner bounds the centroid's distance.
    bounds[q] = 1.0001 * Math.min(hypot3(p[3 * a] - cx, p[3 * a + 1] - cy, p[3 * a + 2] - cz),
                                  hypot3(p[3 * b] - cx, p[3 * b + 1] - cy, p[3 * b + 2] - cz),
                                  hypot3(p[3 * c] - cx, p[3 * c + 1] - cy, p[3 * c + 2] - cz)) + 1e-12;
  }
  return { centroids, bounds };
}

/** flippedFaces' judgement of each face, given its centroid's closest point on the surface (`near`). */
function facesAgainst(p, faces, onlyFaces, count, surface, near, against, across) {
  // Unit face normals, made where needed (no table over the whole mesh: the drag's checks ask
  // about a few faces of a big mesh, many times).
  const own = new Float64Array(3), other = new Float64Array(3);
  const sn = surface.smoothNormals, rn = surface.normals, touching = 1e-9 * surface.diagonal;
  const flipped = [];
  for (let q = 0; q < count; q++) {
    const f = onlyFaces ? onlyFaces[q] : q;
    unitTriangleNormal(p, faces[3 * f], faces[3 * f + 1], faces[3 * f + 2], own);
    const n0 = own[0], n1 = own[1], n2 = own[2];
    if (n0 === 0 && n1 === 0 && n2 === 0) {
      flipped.push(f);
      continue;
    }
    const m = 3 * near.triangles[q];
    if (n0 * sn[m] + n1 * sn[m + 1] + n2 * sn[m + 2] >= against) continue;
    // Lying on an input face that faces the same way: the input itself is crumpled there.
    if (against < 0 && near.distances[q] < touching && n0 * rn[m] + n1 * rn[m + 1] + n2 * rn[m + 2] > 0) continue;
    // Against the input's normal: a fold if it also turns away from a neighbour (a thin part's
    // tip, where the input's normal is ambiguous, has neighbours that agree with it).
    for (let j = 0; j < 3; j++) {
      const g = across[3 * f + j];
      if (g < 0) continue;
      unitTriangleNormal(p, faces[3 * g], faces[3 * g + 1], faces[3 * g + 2], other);
      if (n0 * other[0] + n1 * other[1] + n2 * other[2] < 0) {
        flipped.push(f);
        break;
      }
    }
  }
  return flipped;
}

// ---- folds ---------------------------------------------------------------------------------------

/** Mask of the vertices within `rings` edges of a corner of the faces `faceList`. */
function ringsAround(faces, vertexCount, faceList, rings) {
  const { offsets, list } = connectivity(faces, vertexCount).neighbours;
  const near = new Uint8Array(vertexCount);
  let front = [];
  for (const f of faceList) for (let j = 0; j < 3; j++) if (!near[faces[3 * f + j]]) near[faces[3 * f + j]] = 1, front.push(faces[3 * f + j]);
  for (let ring = 0; ring < rings; ring++) {
    const next = [];
    for (const v of front) for (let e = offsets[v]; e < offsets[v + 1]; e++) if (!near[list[e]]) near[list[e]] = 1, next.push(list[e]);
    front = next;
  }
  return near;
}

/**
 * Local untangling: the vertices around flipped triangles (a ring more each round) move to the
 * mean of their neighbours and back onto the surface (on their line if on a feature; corners
 * stay), a few steps per round, until no triangle is flipped or `rounds` rounds. Without
 * `project` they stay at the mean (a crumpled input re-creates the fold on it; the Hausdorff
 * distance measured after says what that cost). Returns the flipped triangles left.
 */
function untangle(surface, positions, faces, constraints, rounds = 6, project = true, flippedNow = null) {
  const vertexCount = positions.length / 3;
  const adjacency = connectivity(faces, vertexCount).neighbours;
  const { offsets, list } = adjacency;
  const around = connectivity(faces, vertexCount).vertexFaces;
  let flipped = flippedNow ?? resultFlipped({ positions, faces }, surface, constraints);
  for (let round = 0; round < rounds && flipped.length > 0; round++) {
    const near = new Uint8Array(vertexCount);
    let front = [];
    for (const f of flipped) for (let j = 0; j < 3; j++) if (!near[faces[3 * f + j]]) near[faces[3 * f + j]] = 1, front.push(faces[3 * f + j]);
    for (let ring = 0; ring <= round; ring++) {
      const next = [];
      for (const v of front)
        for (let e = offsets[v]; e < offsets[v + 1]; e++) if (!near[list[e]]) near[list[e]] = 1, next.push(list[e]);
      front = next;
    }
    const region = [];
    for (let v = 0; v < vertexCount; v++) if (near[v] && !(constraints && constraints.kind[v] === 2)) region.push(v);
    const next = new Float64Array(3 * region.length);
    for (let step = 0; step < 6; step++) {
      region.forEach((v, r) => {
        if (constraints && constraints.kind[v] === 1) return slideOnLine(constraints, positions, adjacency, v, 1, next, 3 * r);
        let x = 0, y = 0, z = 0;
        const degree = offsets[v + 1] - offsets[v];
        for (let e = offsets[v]; e < offsets[v + 1]; e++) x += positions[3 * list[e]], y += positions[3 * list[e] + 1], z += positions[3 * list[e] + 2];
        if (!project) {
          next[3 * r] = x / degree, next[3 * r + 1] = y / degree, next[3 * r + 2] = z / degree;
          return;
        }
        const p = surface.closest(x / degree, y / degree, z / degree).point;
        next[3 * r] = p.x, next[3 * r + 1] = p.y, next[3 * r + 2] = p.z;
      });
      region.forEach((v, r) => positions.set(next.subarray(3 * r, 3 * r + 3), 3 * v));
    }
    // Only faces with a corner in the region or a ring around it (their edge neighbours turned)
    // can have changed: those are checked again, the others keep their state.
    const recheck = new Uint8Array(faces.length / 3), faceList = [];
    for (const v of region)
      for (let e = offsets[v]; e <= offsets[v + 1]; e++) {
        const w = e < offsets[v + 1] ? list[e] : v;
        for (let k = around.offsets[w]; k < around.offsets[w + 1]; k++)
          if (!recheck[around.list[k]]) recheck[around.list[k]] = 1, faceList.push(around.list[k]);
      }
    faceList.sort((a, b) => a - b);
    flipped = [...flipped.filter((f) => !recheck[f]), ...resultFlipped({ positions, faces }, surface, constraints, faceList)].sort((a, b) => a - b);
  }
  return flipped.length;
}

// ---- the pipeline ----------------------------------------------------------------------------------

/**
 * Default base size (faces over all components): the input's face count / 12 within 200..1000,
 * a level-0 cage of roughly 100-500 handles (a smaller input is its own base).
 */
export function defaultBaseFaces(inputFaces) {
  return Math.min(1000, Math.max(200, Math.round(inputFaces / 12)));
}

// Emphasis rounds (remesh): how many, how far around a far vertex its weight reaches (of the
// diagonal), and the largest weight.
const EMPHASIS_ROUNDS = 3, EMPHASIS_RADIUS = 0.03, EMPHASIS_CAP = 8;

// Inputs up to this size get the early emphasis round (remesh): beyond it a fit costs more than a
// round that may not be kept is worth (dragon-203k reaches its goal by the tips rounds).
const EARLY_EMPHASIS_MAX_FACES = 60000;

// Refined rounds (remesh): at most this many.
const REFINED_ROUNDS = 2;

// A first fit farther than this factor of the goal, on an input that gets the early rounds (remesh):
// no level more before them (a level quarters the faces, but this far it is the base that is far:
// dragon-48k 2.07% at 2 levels, 2.17% at 3).
const FAR_LEVEL_FACTOR = 3;

// The most faces asked for in the larger bases (remesh), over all pieces: a cage within 500 handles.
const LARGER_BASE_FACES = 880;

// The nudge (remesh): the distance (of the goal) it brings far samples to, and the farthest a
// nudged vertex or its triangles' samples may then be from the input.
const NUDGE_AIM = 0.9, NUDGE_TOLERANCE = 0.95;
// A nudged triangle counts as turned over below this cosine to the input's normal: a little past
// perpendicular is let through (a triangle on a fold's side), with a margin to the result's own
// test (RESULT_AGAINST, checked after the nudge). At 0 every move of dragon-11k's last far sample
// (on a fold) was refused: 0.502%; at -0.05 to -0.25: 0.450-0.474%.
const NUDGE_AGAINST = -0.1;

// A closest fit within this factor of the goal is dragged and nudged before the emphasis rounds and
// before each further round (remesh), which run only if that leaves it above the goal (the drag and
// the nudge brought the teapot's 0.562% and dragon-11k's 0.651% fits within it).
const NEAR_GOAL = 1.5;
// The same for a fit against a proxy (lib/remesh-proxy.mjs), where the drag and nudge cost less than
// a fit, and for an input of more than PROXY_MIN_FACES faces, where a fit costs more than they do.
const PROXY_NEAR_GOAL = 3;

/** Two-sided Hausdorff distance (over the diagonal) a remeshing should keep by default. */
export const DEFAULT_HAUSDORFF = 0.005;

/**
 * What remesh() makes of its input before any fit (the same for the default and the parametrised
 * fit): repaired or welded, in checked pieces, their surfaces (BVHs) and the sharp features.
 */
function prepareInput(mrvol, input, options, progress) {
  const { MrvolError } = mrvol;
  // Repair (optional) or weld only; then the input must be closed 2-manifolds.
  progress(0, options.repair ? 'repairing' : 'welding');
  const repaired = options.repair ? repair(input, { keepLargest: options.keepLargest, maxHoleEdges: options.maxHoleEdges,
                                                   smooth: options.smooth }) : null;
  const welded = repaired ? repaired.mesh : weld(input);
  // Every triangle gone by the weld or the repair: all of them had corners at one point.
  if (welded.faces.length === 0 && input.faces.length > 0)
    throw new MrvolError(`all ${input.faces.length / 3} of the input's triangles are degenerate (zero area: their corners ` +
                         'fall together), so there is no surface to remesh');
  // Smoothing that collapsed the surface (Taubin's steps shrink a coarse mesh: a 12-triangle box
  // went to a point in 1000) would be fitted and reported as kept.
  const smoothing = repaired?.report.smoothing;
  if (smoothing && !(smoothing.volumeAfter > 0.01 * Math.abs(smoothing.volumeBefore)))
    throw new MrvolError(`smoothing collapsed the surface: its volume went from ${smoothing.volumeBefore.toPrecision(4)} to ` +
                         `${smoothing.volumeAfter.toPrecision(4)} in ${options.smooth} steps; use fewer smoothing steps (--smooth)`);
  // A one-sided surface bounds no solid: cutting it open and filling the cuts would make up a shape.
  if (repaired?.report.oneSidedEdges > 0)
    throw new MrvolError(`the surface is one-sided (not orientable, like a Klein bottle): ${repaired.report.oneSidedEdges} edges join faces that no orientation can make agree, so no closed 2-manifold with an inside can be made of it`);
  progress(0, 'finding the pieces');
  const { pieces, genus, droppedComponents, droppedPieces } = inputPieces(mrvol, welded, options.keepLargest, !!repaired);
  const mesh = pieces.length === 1 ? pieces[0].mesh : concatenate(pieces.map((p) => p.mesh));
  const inputVolume = mrvol.volume(mesh);
  const diagonal = boundingDiagonal(mesh.positions);
  const inputFaces = mesh.faces.length / 3, inputVertices = mesh.positions.length / 3;

  progress(0, 'building the search tree');
  const surface = new Surface(mesh);
  const pieceSurfaces = new Map();
  const surfaceOf = (i) => {
    if (pieces.length === 1) return surface;
    if (!pieceSurfaces.has(i)) pieceSurfaces.set(i, new Surface(pieces[i].mesh));
    return pieceSurfaces.get(i);
  };
  if (options.features !== false) progress(0, 'finding sharp features');
  const features = options.features === false ? null : findFeatures(mesh, { angle: options.featureAngle });
  const featureKeys = { corners: new Set([...(features?.corners ?? [])].map((v) => positionKey(mesh.positions, v))),
                        features: new Set([...(features?.linesAt.keys() ?? [])].map((v) => positionKey(mesh.positions, v))) };
  return { repaired, welded, pieces, genus, droppedComponents, droppedPieces, mesh, inputVolume, diagonal, inputFaces, inputVertices,
           surface, surfaceOf, features, featureKeys };
}

/**
 * Remeshes a closed manifold triangle mesh (several components and any genus) into a
 * semi-regular one: each component simplified to a base mesh (corners kept), the bases split
 * 1-to-4 `levels` times and fitted to the input level by level, sharp features kept (corners
 * held, vertices on creases slid along them), folds untangled locally and retried with a larger
 * base. Without `levels`: as many levels (from 2) as reach a two-sided Hausdorff distance of
 * 0.5% of the diagonal, within max(2x the input's vertices, 10000) vertices.
 * @param {object} mrvol the API object of createMrvol()
 * @param {{ positions: Float64Array, faces: Uint32Array }} input
 * @param {object} [options] see lib/remesh.d.ts (RemeshOptions)
 * @param {object} [reuse] internal: prepareInput()'s result for this input and options (the fallback's second run)
 */
export async function remesh(mrvol, input, options = {}, reuse = null) {
  const { MrvolError } = mrvol;
  // The surfaces' closest points in the core (the JS walk of three-mesh-bvh's tree without it).
  Surface.core = typeof mrvol.closestPoints === 'function' ? mrvol : null;
  const started = now();
  const auto = options.levels === undefined;
  if (!auto && !(Number.isInteger(options.levels) && options.levels >= 0 && options.levels <= 6))
    throw new MrvolError(`levels must be an integer in 0..6, got ${options.levels}`);
  if (!input || !(input.positions instanceof Float64Array) || !(input.faces instanceof Uint32Array))
    throw new MrvolError('remesh expects a mesh { positions: Float64Array, faces: Uint32Array }');
  const problem = reuse ? null : meshProblem(input);
  if (problem) throw new MrvolError(`remesh: ${problem}`);
  if (options.baseFaces !== undefined && !(Number.isInteger(options.baseFaces) && options.baseFaces >= 4))
    throw new MrvolError(`baseFaces must be an integer >= 4, got ${options.baseFaces}`);
  // Levels given: a result past what the editor is made for is refused before any work, not after
  // minutes of fitting and an out-of-memory error (6 levels on 4000 base faces: 16 million faces, 111 s).
  if (!auto) {
    const faces = input.faces.length / 3, base = Math.min(options.baseFaces ?? defaultBaseFaces(faces), faces);
    const made = base * 4 ** options.levels;
    if (made > MAX_RESULT_FACES)
      throw new MrvolError(`${options.levels} levels on ${base} base faces would make about ${made.toLocaleString('en-US')} faces, ` +
                           `more than the ${MAX_RESULT_FACES.toLocaleString('en-US')} the remesher makes (the 2.6-million-vertex ` +
                           'meshes the editor is made for): ask fewer levels or base faces');
  }
  const relaxIterations = options.relaxIterations ?? 4;
  const maxSamples = options.maxSamples ?? 200000;
  const goal = options.hausdorffGoal ?? DEFAULT_HAUSDORFF;
  const progress = (fraction, stage) => options.onProgress?.(fraction, stage);

  // The prepared input (repair, pieces, surfaces, features): the parametrised fallback reuses the first run's.
  const prepared = reuse ?? prepareInput(mrvol, input, options, progress);
  const { repaired, welded, genus, droppedComponents, droppedPieces, inputVolume, diagonal, inputFaces, inputVertices,
          features, featureKeys } = prepared;
  // A large input is fitted against a proxy (lib/remesh-proxy.mjs), and the chosen fit measured,
  // dragged and nudged against the input itself (see the end); only by the parametrised fit (the
  // simplified one on the proxy lost). Made once per prepared input (the fallbacks' runs reuse it).
  const useProxy = options.proxy !== false && options.parametrise !== false;
  if (useProxy && prepared.proxied === undefined)
    prepared.proxied = proxyInput(mrvol, prepared, Surface, { ...(typeof options.proxy === 'object' ? options.proxy : {}), maxFaces: PARAMETRISE_MAX_FACES });
  const proxied = useProxy ? prepared.proxied : null;
  // By default there the parametrised fit against the proxy (dragon-203k: 0.464% with a cage of 521
  // handles); if it folds or stays above the goal, the input fitted without the proxy too (the
  // simplified fit and its own fallback), the closer of the two without folds kept.
  if (options.parametrise === undefined && proxied) {
    let first = null, error = null;
    try {
      first = await remesh(mrvol, input, { ...options, parametrise: true }, prepared);
    } catch (e) {
      if (!(e instanceof MrvolError)) throw e;
      error = e.message;
    }
    if (first && first.hausdorff <= goal) return { ...first, ms: now() - started };
    const other = await remesh(mrvol, input, { ...options, proxy: false,
                                                onProgress: (f, stage) => progress(0.5 + 0.5 * f, `fit without the proxy: ${stage}`) }, prepared);
    const kept = !first || (other.flippedTriangles === 0 && other.hausdorff < first.hausdorff);
    const proxyFallback = { hausdorff: other.hausdorff, flippedTriangles: other.flippedTriangles, kept, error };
    return { ...(kept ? other : first), proxyFallback, ms: now() - started };
  }
  let { pieces, mesh, surface, surfaceOf } = proxied ?? prepared;
  await MeshoptSimplifier.ready;
  // (let: a base size given that folds until grown is grown for the rounds after it, see fit below.)
  let requested = options.baseFaces ?? defaultBaseFaces(inputFaces);
  // The base size given when the first fit without folds needed a larger one (else null).
  let grownFrom = null;
  const budget = options.maxVertices ?? Math.max(2 * inputVertices, 10000);

  const genusChanges = new Set();
  // Input vertices the base must keep: tips that a fit left too far away (see below).
  const tipKeys = new Set();
  // Whether the fits hold the tips on their input vertex (see tipsRounds below).
  let holdTips = false;
  // Per piece (or null): weights that make the simplifier keep the regions a fit left far (see emphasisRounds below).
  let emphasis = null;
  // Per piece (or null): points (x y z each) where a refined base keeps more faces (see refinedRounds below).
  let refineAt = null;
  // A fit that folds is made again on bases twice and four times as large: those asked for with
  // at most this many faces (see the levels below).
  let retryFaces = Infinity;
  // One fit at `levels` levels: bases of growing size until no triangle is left flipped.
  const simplifierProblems = [];
  let featuresFolded = false;
  // Fitted pieces by base (a retry often makes some pieces' bases again).
  const fitted = new Map();
  // The base scales a fit that folds is retried at (null: 2x and 4x); the early refined round sets its own.
  let foldRetryScales = null;
  // Parametrised bases by piece, size and locks: the fits of other levels ask for the same one (the collapse is deterministic).
  const parametrised = new Map();
  const parametrisedOnce = (i, piece, target, lock) => {
    const key = `${i} ${target}`, known = (parametrised.get(key) ?? []).find((k) => sameMask(k.lock, lock));
    if (known) return known.base;
    const base = parametrisedBase(mrvol, piece, target, lock);
    parametrised.set(key, [...(parametrised.get(key) ?? []), { lock, base }]);
    return base;
  };
  // baseScale: one factor, or one per piece; keep: fitted parts to reuse as they are (at `levels`).
  // The scales a base size given grows by when the first fit folds on it: 1.5x to 16x of the size
  // the simplifier makes (at least 64 faces a piece), up to 4x the default size (a torus knot asked
  // for 4 or 20 faces fits on 128-256).
  const grownScales = () => {
    const made = Math.max(requested, 64), most = Math.max(4 * defaultBaseFaces(inputFaces), 1.5 * made);
    return [1.5, 2, 4, 8, 16].map((k) => (k * made) / requested).filter((scale) => requested * scale <= most);
  };
  const fit = (levels, fraction, share, baseScale = 1, keep = null, size = null) => {
    // Folds left after untangling: once more without the feature constraints (if any), then with a
    // base twice and four times as large (or foldRetryScales'). A base size given is kept unless no
    // fit without folds is made yet: then it grows (grownScales) rather than give up (the torus
    // knot and the genus-3 pretzel fold on 100 base faces and fit on 150), and the rounds after go
    // on at the size that fitted (the report's baseGrown says so).
    const useFeatures = features && features.edgeCount > 0 && !featuresFolded;
    const given = options.baseFaces !== undefined;
    const retryScales = given ? (haveFit() ? [] : grownScales()) : (foldRetryScales ?? [2, 4]).filter((scale) => requested * scale <= retryFaces);
    const attempts = [...(useFeatures ? [[1, features]] : []), [1, null], ...retryScales.map((scale) => [scale, null])];
    let result = null;
    // Per piece: the base size asked for in the attempt before and whether its part folded there.
    let targets = null, folded = null, previousScale = 1;
    for (const [attempt, [scale, withFeatures]] of attempts.entries()) {
      progress(fraction, attempt ? `simplifying (attempt ${attempt + 1})` : 'simplifying');
      const asked = [];
      // Each piece on its own (its own surface: parts that touch or cross do not pull each other).
      const bases = pieces.map((piece, i) => {
        if (keep?.[i]) return null;
        // A small piece (64 faces or fewer) is its own base: exact.
        const pieceScale = Array.isArray(baseScale) ? baseScale[i] : baseScale;
        let target = Math.max(Math.min(64, piece.mesh.faces.length / 3), Math.round((requested * pieceScale * scale * piece.faces) / inputFaces));
        // Room for every feature vertex in the base (a cage of at most about 500 handles).
        if (withFeatures) target = Math.max(target, Math.min(1000, Math.ceil(2.2 * countFeatureVertices(piece.mesh, featureKeys))));
        // A small piece whose part folded grows with the retry too (at the 64-face floor its base
        // stayed the same, and so did its fold: `--levels 3` on dragon-871k failed on every base
        // size, on 2 flipped triangles of its second piece, a 204-face fragment).
        if (scale > previousScale && folded?.[i] && target <= targets[i])
          target = Math.min(piece.mesh.faces.length / 3, Math.ceil((targets[i] * scale) / previousScale));
        asked[i] = target;
        const lock = withLocks(withFeatures ? lockedFeatures(piece.mesh, featureKeys, target) : null, piece.mesh, tipKeys, target);
        const b = (options.parametrise && parametrisedOnce(i, piece, target, lock)) ||
          (refineAt?.[i] && refinedBase(mrvol, piece, target, !!repaired, lock, emphasis?.[i] ?? null, refineAt[i], REFINED_RADIUS * diagonal)) ||
          simplifyToBase(mrvol, piece.mesh, piece.genus, target, 8, !!repaired, lock, emphasis?.[i] ?? null);
        simplifierProblems.push(...b.problems);
        if (b.genusChanged) genusChanges.add(i);
        return b;
      });
      // Default levels: no more than the vertex budget allows over the bases actually made.
      const baseFaces = bases.reduce((t, b, i) => t + (b ? b.base.faces.length / 3 : keep[i].baseFaces), 0);
      let used = levels;
      while (auto && used > 0 && (baseFaces * 4 ** used) / 2 > budget) used--;
      // Kept parts need the same levels (else no fit of this size); a base of another size than
      // asked for (locked tips change the simplifier's count) is not fitted.
      if ((keep && used !== levels) || (size !== null && baseFaces !== size)) return null;
      let done = 0;
      const parts = pieces.map((piece, i) => {
        if (keep?.[i]) return keep[i];
        const b = bases[i], own = surfaceOf(i), weight = piece.faces / inputFaces;
        // The same base at the same levels fits the same (deterministic): done once.
        const hold = holdTips && tipKeys.size > 0;
        const keyOf = (held) => `${i} ${used} ${withFeatures ? 1 : 0} ${b.simplified ? 1 : 0} ${held ? 1 : 0} ${b.parametrisation ? 1 : 0}`;
        const key = keyOf(hold);
        const known = (fitted.get(key) ?? []).find((k) => sameMesh(k.base, b.base));
        if (known) {
          done += weight;
          return known.part;
        }
        const fitPart = (tips) => {
          const part = fitLevels(mrvol, own, b.base, used, relaxIterations, withFeatures, !b.simplified,
                                 (f, stage) => progress(fraction + share * (done + weight * f), stage), tips, b.parametrisation);
          const flippedNow = resultFlipped(part.mesh, own, part.constraints);
          options.debug?.('fitted', { piece: i, levels: used, base: b.base, mesh: { positions: part.mesh.positions.slice(), faces: part.mesh.faces }, flipped: flippedNow });
          part.untangled = flippedNow.length;
          part.flippedTriangles = part.untangled ? untangle(own, part.mesh.positions, part.mesh.faces, part.constraints, 6, true, flippedNow) : 0;
          // Held tips next to a fold left are let go (a wider ring each time, then all) and untangled again.
          for (let ring = 2; ring <= 8 && part.flippedTriangles > 0 && part.heldTips.length; ring += 2) {
            const flipped = resultFlipped(part.mesh, own, part.constraints);
            const near = ring < 8 ? ringsAround(part.mesh.faces, part.mesh.positions.length / 3, flipped, ring) : null;
            let released = 0;
            for (const m of part.heldTips) if ((!near || near[m]) && part.constraints.kind[m] === 2) part.constraints.kind[m] = 0, released++;
            if (released) part.flippedTriangles = untangle(own, part.mesh.positions, part.mesh.faces, part.constraints, 6, true, flipped);
          }
          if (part.flippedTriangles > 0) {
            part.flippedTriangles = untangle(own, part.mesh.positions, part.mesh.faces, part.constraints, 8, false);
          }
          options.debug?.('untangled', { piece: i, levels: used, mesh: part.mesh, flippedTriangles: part.flippedTriangles });
          return part;
        };
        // Tips held on their input vertex; if that folds the fit, they relax like the others.
        const remember = (k, part) => {
          if (!fitted.has(k)) fitted.set(k, []);
          fitted.get(k).push({ base: b.base, part });
        };
        let part = fitPart(hold ? tipKeys : null);
        if (part.flippedTriangles > 0 && hold) {
          part = (fitted.get(keyOf(false)) ?? []).find((k) => sameMesh(k.base, b.base))?.part ?? fitPart(null);
          remember(keyOf(false), part);
        }
        done += weight;
        remember(key, part);
        return part;
      });
      const sum = (key) => parts.reduce((t, p) => t + p[key], 0);
      result = parts.length === 1 ? parts[0] : {
        mesh: concatenate(parts.map((p) => p.mesh)), baseVertices: sum('baseVertices'), baseFaces: sum('baseFaces'),
        fallbacks: sum('fallbacks'), untangled: sum('untangled'), flippedTriangles: sum('flippedTriangles'),
        constraints: { count: parts.reduce((t, p) => t + p.constraints.count, 0), corners: parts.reduce((t, p) => t + p.constraints.corners, 0) },
      };
      result.levelsUsed = used;
      result.parts = parts;
      if (result.flippedTriangles === 0 || options.allowFlipped) {
        if (given && scale > 1) grownFrom = requested, requested = Math.round(requested * scale);
        break;
      }
      targets = asked, folded = parts.map((p, i) => !keep?.[i] && p.flippedTriangles > 0), previousScale = scale;
      // Features that fold a fit (a ridge the fit cannot follow, held corners on a thin tip) fold
      // the fits of more levels on the same base too: those go without them.
      if (withFeatures) featuresFolded = true;
    }
    return result;
  };

  let result = null, measured = null, lastMeasured = null;
  // Whether a fit without folds is kept (fit() above shadows `result`).
  const haveFit = () => result !== null;
  // The distances of input points (positions) from a measured fit's result: the tips, emphasis and
  // refined rounds ask for the same fit's more than once (the 871k scan's 435k vertices each time).
  const distancesKnown = new WeakMap();
  const distancesTo = (m, positions) => {
    if (!distancesKnown.has(m)) distancesKnown.set(m, new Map());
    const known = distancesKnown.get(m);
    if (!known.has(positions)) known.set(positions, m.surface.distances(positions));
    return known.get(positions);
  };
  const tried = [], measures = [];
  const distance = (m) => Math.max(m.toInput, m.fromInput) / diagonal;
  // One fit, kept if it is the first or closer to the input; false if it folded.
  const tryFit = (levels, baseScale, keep = null, baseFaces = null) => {
    const fraction = Math.min(0.8, 0.05 + 0.25 * tried.length);
    const attempt = fit(levels, fraction, auto ? 0.25 : 0.2, baseScale, keep, baseFaces);
    if (!attempt) return false;
    tried.push({ levels, baseFaces: attempt.baseFaces, flipped: attempt.flippedTriangles });
    if (attempt.flippedTriangles > 0 && !options.allowFlipped) {
      if (result) return false;  // a fit without folds is kept
      throw new MrvolError(`the remeshed surface folds over: ${attempt.flippedTriangles} flipped triangles after untangling (base of ${attempt.baseFaces} faces, ${levels} levels); try more base faces${levels > 0 ? ' or fewer levels' : ''}`);
    }
    progress(Math.min(0.9, fraction + 0.2), 'measuring the Hausdorff distance');
    // The same pieces as an earlier fit: the same distances.
    const same = measures.find((k) => k.parts.length === attempt.parts.length && k.parts.every((p, i) => p === attempt.parts[i]));
    const m = same ? same.m : measure(attempt.mesh, mesh, surface, maxSamples);
    if (!same) measures.push({ parts: attempt.parts, m });
    lastMeasured = m;
    tried.at(-1).hausdorff = distance(m);
    attempt.levels = attempt.levelsUsed ?? levels;
    tried.at(-1).levels = attempt.levels;
    if (!result || distance(m) < distance(measured)) result = attempt, measured = m;
    return true;
  };
  // Fits dragged and nudged (dragAndNudge below), each once: fit -> { result, measured }.
  const finishedFits = new Map();
  const finished = (fitted, fittedMeasured) => {
    if (!finishedFits.has(fitted)) finishedFits.set(fitted, dragAndNudge(fitted, fittedMeasured));
    return finishedFits.get(fitted);
  };
  // Whether the closest fit is near the goal and its drag and nudge bring it within (then no
  // emphasis round is needed: each is a fit from a new base).
  // Against a proxy the drag and nudge cost a fraction of a fit: tried from farther (PROXY_NEAR_GOAL).
  // So on an input of the proxy's size fitted as it is: dragon-871k's 1.041% fit (4062 faces) was
  // nudged to 0.492% only after an emphasis round and a refined round (4 fits, all farther or folded).
  const nearGoal = proxied || inputFaces > PROXY_MIN_FACES ? PROXY_NEAR_GOAL : NEAR_GOAL;
  const nearlyDone = () => distance(measured) <= nearGoal * goal && distance(finished(result, measured).measured) <= goal;
  // Still far: the input vertices farthest from the result (tips the base cut off, a few apart)
  // are kept in the base, up to three times, and the closest fit so far is kept. With the levels
  // and base size given (no larger base to fall back on), only bases of the first fit's size, and
  // the tips held on their input vertex during the fit (a held tip next to a fold left is let go):
  // the dragon sample 0.74% -> 0.42%. By default they relax like the other vertices: held, they
  // folded the corpus's dragons and teapot more than they brought them closer.
  // With only the levels given (the app's remeshing offer): no tips rounds, one fit as before.
  const tipsRounds = (sameSize) => {
    // A closest fit the drag and nudge bring within the goal needs no further round (see nearlyDone):
    // dragon-203k's third round was a 1.58% fit, after a 0.61% one nudged to 0.46%.
    for (let round = 0; round < 3 && distance(measured) > goal && !(round > 0 && nearlyDone()); round++) {
      const added = addTips(mesh, distancesTo(measured, mesh.positions), goal * diagonal, 0.02 * diagonal, Math.max(8, Math.round(requested / 16)), tipKeys);
      if (added === 0) break;
      const before = distance(measured);
      holdTips = sameSize;
      tryFit(result.levels, 1, null, sameSize ? result.baseFaces : null);
      holdTips = false;
      // A round that gained less than 5% leaves little for the next one.
      if (distance(measured) > 0.95 * before) break;
    }
  };
  // Still far after the rounds below: the base made again with more of its faces where the first
  // fit was far (the claws and horns a uniform simplification cuts off: 4-6% of the diagonal on
  // the dragons), at the same face count, so the cage does not grow; each round adds the weights
  // of its own fit's far regions; the closest fit of all is kept. Run last, from the first fit, so
  // the other rounds go as before (run first, a closer emphasised fit led the tips rounds and
  // larger bases elsewhere: the teapot 0.53% -> 2.06%); tips are not locked in these bases.
  const emphasisRounds = (from, size = null) => {
    // (The parametrised fit's bases are collapsed, not simplified: no weights there.)
    if (options.emphasis === false || options.parametrise) return;
    const locked = [...tipKeys];
    tipKeys.clear();
    let last = from;
    for (let round = 0; round < EMPHASIS_ROUNDS && distance(measured) > goal && !(round > 0 && nearlyDone()); round++) {
      emphasis = pieces.map((piece, i) => farEmphasis(piece.mesh, distancesTo(last, piece.mesh.positions), goal * diagonal,
                                                      EMPHASIS_RADIUS * diagonal, EMPHASIS_CAP, emphasis?.[i]));
      if (!tryFit(result.levels, 1, null, size)) break;
      // A round that left its fit no closer than the one it started from: no further round.
      if (distance(lastMeasured) > 0.95 * distance(last)) break;
      last = lastMeasured;
    }
    // The closest fit so far not of these rounds (a tips round's, a larger base's): one round from its far regions
    // too (dragon-48k 1.685% -> 1.628%; from it alone, dragon-11k's round was 5.07% against 0.65% from the first).
    if (distance(measured) > goal && measured !== last && !nearlyDone()) {
      emphasis = pieces.map((piece) => farEmphasis(piece.mesh, distancesTo(measured, piece.mesh.positions), goal * diagonal,
                                                   EMPHASIS_RADIUS * diagonal, EMPHASIS_CAP));
      tryFit(result.levels, 1, null, size);
    }
    emphasis = null;
    for (const k of locked) tipKeys.add(k);
  };
  // Still far after those: a base of the same size refined where the closest fit is far (the
  // vertices of the emphasised base twice as large near the far input points locked in the
  // simplification: refinedBase), so the faces go where the input has detail the base bridged (the
  // 48k dragon's toes); kept if closer, up to REFINED_ROUNDS rounds. If its fit folds, the retry's
  // base twice as large is refined the same way (the 48k dragon: 1.19% -> 0.41%, cage 535 -> 1034).
  // refine: false keeps the cage instead.
  const refinedRounds = (rounds = REFINED_ROUNDS, scale = 1) => {
    if (options.refine === false || options.parametrise) return;
    for (let round = 0; round < rounds && distance(measured) > goal; round++) {
      const before = distance(measured);
      const far = pieces.map((piece) => distancesTo(measured, piece.mesh.positions));
      refineAt = pieces.map((piece, i) => farPoints(piece.mesh.positions, far[i], goal * diagonal, 0.005 * diagonal, 400));
      emphasis = pieces.map((piece, i) => farEmphasis(piece.mesh, far[i], goal * diagonal, EMPHASIS_RADIUS * diagonal, EMPHASIS_CAP));
      tryFit(result.levels, scale);
      refineAt = null, emphasis = null;
      if (distance(measured) > 0.95 * before) break;
    }
  };
  if (!auto) {
    if (tryFit(options.levels, 1) && options.baseFaces !== undefined) {
      const first = measured;
      tipsRounds(true);
      emphasisRounds(first, result.baseFaces);
    }
  } else {
    // From 2 levels (fewer if even 2 exceed the budget), one more while the distance is above the
    // goal and the vertices fit the budget; then, if still above it, tips kept in the base, then a
    // base twice and four times as large (within about 500 handles) at the most levels that fit.
    const fits = (levels, scale) => (requested * scale * 4 ** levels) / 2 <= budget;
    let levels = 2;
    while (levels > 0 && !fits(levels, 1)) levels--;
    // The early rounds below (a small input whose base cannot grow: no larger base fits the cage
    // goal). (The larger bases' first step, below, at its largest: its far pieces the smallest
    // piece, or all; a piece of 64 faces or fewer is its own base, never far.)
    const smallest = Math.min(inputFaces, ...pieces.map((p) => p.faces).filter((f) => f > 64)) / inputFaces;
    const room = LARGER_BASE_FACES / requested;
    const noLargerBase = room < 1 || 1 + (room - 1) / smallest < 0.75 * 2;
    const early = noLargerBase && inputFaces <= EARLY_EMPHASIS_MAX_FACES && options.emphasis !== false && !options.parametrise;
    // There, a fit over FAR_LEVEL_FACTOR x the goal gets the early rounds first; its level more
    // only if they do not reach the goal (deferred).
    let deferred = null;
    // A level that gained less than 5% over the one before leaves little for the next: the base is
    // what is far (dragon-203k: 3.87% at 2 levels, 3.77% at 3, 4.00% at 4, a 4-level fit of 3 s).
    // A level added that folds is made again only on bases within the larger bases' limit or the
    // closest fit's own size (not a larger cage for one level more): dragon-871k's 3-level fit folded
    // on bases of 1064, 2128 and 4062 faces (about 15 s of CPU; its 2-level fit is on 1064).
    let before = Infinity;
    // (Against a proxy, not past a fit its drag and nudge bring within the goal: the 203k's 4-level fit folded.)
    const levelLoop = () => {
      for (; tryFit(levels, 1) && distance(measured) > goal && levels < 6 && fits(levels + 1, 1) && result.levels === levels &&
             distance(lastMeasured) <= 0.95 * before && !(proxied && nearlyDone()); levels++) {
        before = distance(lastMeasured), retryFaces = Math.max(LARGER_BASE_FACES, 1.1 * result.baseFaces);
        if (early && !deferred && distance(lastMeasured) > FAR_LEVEL_FACTOR * goal) {
          deferred = { levels: levels + 1, before, retryFaces };
          break;
        }
        // A large input fitted without a proxy, this far: the base is what is far, and a fit of a level
        // more costs seconds (dragon-871k: 3.27% at 2 levels, its 3-level fit folded, 6.5 s).
        if (!proxied && inputFaces > PROXY_MIN_FACES && distance(lastMeasured) > FAR_LEVEL_FACTOR * goal) break;
      }
      retryFaces = Infinity;
    };
    levelLoop();
    let first = measured;
    // Against a proxy, a closest fit that its drag and nudge bring within the goal ends the fits
    // (dragon-203k's parametrised 3-level fit: 1.351%, 0.464% at the end; its tips round, a fold and
    // a base twice as large, was 2.689%).
    const proxyDone = !!proxied && distance(measured) > goal && nearlyDone();
    // The state before an early round: restore() forgets the round (its result, measures, fits list,
    // simplifier problems and genus changes), so the rounds go on as before.
    const saved = () => {
      const state = { result, measured, lastMeasured, tried: tried.length, problems: simplifierProblems.length, genusChanges: [...genusChanges] };
      return () => {
        if (result !== state.result) finishedFits.delete(result);
        ({ result, measured, lastMeasured } = state);
        tried.length = state.tried, simplifierProblems.length = state.problems;
        genusChanges.clear();
        for (const i of state.genusChanges) genusChanges.add(i);
      };
    };
    // A small input whose base cannot grow (no larger base fits the cage goal): the first emphasis
    // round tried before the tips rounds, kept if its drag and nudge reach the goal (dragon-11k:
    // the emphasis fit gave its 0.450%, the two tips rounds before it nothing); else forgotten, so
    // the rounds go as before (the emphasis round, made again later, comes from the fits' cache).
    let earlyDone = false;
    if (distance(measured) > goal && early && !proxyDone) {
      const restore = saved(), start = result;
      emphasis = pieces.map((piece) => farEmphasis(piece.mesh, distancesTo(first, piece.mesh.positions), goal * diagonal,
                                                   EMPHASIS_RADIUS * diagonal, EMPHASIS_CAP));
      const closer = tryFit(result.levels, 1) && result !== start;
      emphasis = null;
      earlyDone = closer && nearlyDone();
      if (!earlyDone) restore();
      // No closer than the first fit (dragon-48k: 2.60% against 2.07%): this base size misses more
      // than weights bring back (the 48k's toes), so the tips and emphasis rounds at this size are
      // predicted not to win either (the 48k's reached 1.63%). One refined round (see refinedRounds:
      // a base of the size asked for, twice as large if that folds) from the first fit, dragged and
      // nudged, kept if that reaches the goal; else forgotten too, and, if its base was of the size
      // asked for, one on a base twice as large, likewise. The smallest cage first: the 48k decimated
      // to 25k faces 1.706% on the asked size, 0.456% after (cage 537); the corpus's 48k (STL) folds
      // there, its retry twice as large 0.974%, 0.382% after (2 fits instead of 7); the npm package's
      // 48k (another vertex order) is not within the goal on the asked size, 0.362% twice as large.
      // Between them, a base 1.5x as large (not retried larger if it folds: the round on 2x follows),
      // and a fold on the asked size retried on one 1.25x as large before 2x: the smallest cage that
      // reaches the goal (the corpus's 48k: cage 1037 -> 660 handles, 0.451%; the package's: 1034 ->
      // 783, 0.450%).
      for (const scale of [1, 1.5, 2]) {
        if (closer || options.refine === false) break;
        const restoreRefined = saved(), made = tried.length;
        foldRetryScales = scale === 1 ? [1.25, 2, 4] : scale === 1.5 ? [] : null;
        refinedRounds(1, scale);
        foldRetryScales = null;
        earlyDone = result !== start && distance(finished(result, measured).measured) <= goal;
        if (earlyDone) break;
        // (A fold retried on twice this round's base: the rounds on larger bases are made.)
        const larger = tried.length > made && tried.at(-1).baseFaces > 1.5 * scale * start.baseFaces;
        restoreRefined();
        if (larger) break;
      }
    }
    // Not done early: the level deferred above, as the levels loop would have made it.
    if (!earlyDone && deferred) {
      ({ levels, before, retryFaces } = deferred);
      levelLoop();
      first = measured;
    }
    // (Kept: no larger base is tried; the rounds below are skipped.)
    if (!earlyDone && !proxyDone) tipsRounds(false);
    // Only the pieces that are still far get the larger base (a lid the fit cuts, not the body).
    let lastEnlarged = 1;
    for (const scale of [2, 4]) {
      if (distance(measured) <= goal || earlyDone || proxyDone) break;
      // (Pieces whose input vertices are all near: the far side is the result's, say where
      // centroids of the result bulge off a spike: then every piece is enlarged.)
      let far = farPieces(pieces.map((piece) => distancesTo(measured, piece.mesh.positions)), goal * diagonal);
      if (!far.some((f) => f)) far = far.map(() => true);
      // The far pieces' scale lowered so that the bases stay within the cage goal (500 handles:
      // 880 faces asked for leaves room for the small pieces' own bases and the simplifier's count);
      // none less than 3/4 of the scale (a base a few percent larger fits no closer; the teapot's cage 598 -> 479 handles),
      // unless a quarter larger than the step before (the teapot scaled by 1.001: its far pieces 2.77x after 2x; 1.217%
      // without that step, 0.751% with it; as read 3.08x, 0.453%).
      const farShare = pieces.reduce((t, p, i) => t + (far[i] ? p.faces : 0), 0) / inputFaces;
      const enlarged = Math.min(scale, (LARGER_BASE_FACES / requested - (1 - farShare)) / farShare);
      if (enlarged < 0.75 * scale && !(lastEnlarged > 1 && enlarged >= 1.25 * lastEnlarged)) break;
      lastEnlarged = enlarged;
      const scales = far.map((f) => (f ? enlarged : 1));
      const overall = pieces.reduce((t, p, i) => t + scales[i] * p.faces, 0) / inputFaces;
      let l = result.levels;
      while (l > 0 && !fits(l, overall)) l--;
      // The near pieces as in the best fit (at its levels).
      const keep = pieces.length > 1 && l === result.levels && far.some((f) => !f) ? far.map((f, i) => (f ? null : result.parts[i])) : null;
      if (!tryFit(l, scales, keep) && keep) tryFit(l, scales);
    }
    // Near the goal already: the drag and the nudge may close the gap (teapot 0.562% -> 0.453%); the
    // emphasis rounds (a fit each, from a new base) and the refined rounds only if they do not (see nearlyDone).
    if (!earlyDone && !nearlyDone()) {
      emphasisRounds(first);
      if (!nearlyDone()) refinedRounds();
    }
  }

  // Each result vertex's constraint kind (0 free, 1 on a crease line, 2 held), the pieces' end to end.
  function heldVertices(chosen) {
    const kinds = new Uint8Array(chosen.mesh.positions.length / 3);
    let offset = 0;
    for (const part of chosen.parts) kinds.set(part.constraints.kind, offset), offset += part.mesh.positions.length / 3;
    return kinds;
  }

  // Tips still missed: the fit dragged onto them (dragToTips), kept if closer and not more folded
  // (checked against the whole input: pieces apart are never closer than that). Then, still a
  // little above the goal: the samples that make the distance brought within it by moving their
  // triangle's corners off the input where need be (lib/remesh-nudge.mjs); kept if closer and not
  // more folded. Done once per fit (see below).
  function dragAndNudge(chosen, chosenMeasured) {
    let done = chosen, doneMeasured = chosenMeasured, nudgeStart = null;
    // Flipped triangles per positions array (the drag's result, or the fit, is the nudge's start:
    // counted once; the held vertices are the same).
    const flippedOf = new Map();
    const flippedCount = (m, held) => {
      if (!flippedOf.has(m.positions)) flippedOf.set(m.positions, resultFlipped(m, surface, held).length);
      return flippedOf.get(m.positions);
    };
    if (distance(doneMeasured) > goal && options.dragTips !== false) {
      progress(0.92, 'reaching tips');
      const fixed = heldVertices(done);
      const dragged = { positions: done.mesh.positions.slice(), faces: done.mesh.faces };
      options.debug?.('chosen', { mesh: done.mesh, measured: doneMeasured });
      dragToTips(surface, dragged.positions, dragged.faces, fixed, { threshold: goal / 2, tolerance: 0.9 * goal });
      const held = { kind: fixed };
      if (flippedCount(dragged, held) <= flippedCount(done.mesh, held)) {
        // Measured with the queries the nudge starts from (where they are all of the measure's samples).
        const found = measureForNudge(surface, dragged.positions, dragged.faces, maxSamples);
        const m = found ? measuredBy(found, dragged) : measure(dragged, mesh, surface, maxSamples);
        if (distance(m) < distance(doneMeasured)) done = { ...done, mesh: dragged }, doneMeasured = m, nudgeStart = found?.start ?? null;
      }
    }
    if (distance(doneMeasured) > goal && options.nudge !== false) {
      progress(0.94, 'nudging the farthest samples');
      const fixed = heldVertices(done);
      options.debug?.('nudging', { mesh: done.mesh, fixed, measured: doneMeasured });
      const nudged = { positions: done.mesh.positions.slice(), faces: done.mesh.faces };
      const held = { kind: fixed };
      const nudging = nudgeToGoal(surface, nudged.positions, nudged.faces, fixed,
                                  { goal, aim: NUDGE_AIM * goal, tolerance: NUDGE_TOLERANCE * goal, against: NUDGE_AGAINST, maxSamples, start: nudgeStart });
      if (nudging.kept > 0 && flippedCount(nudged, held) <= flippedCount(done.mesh, held)) {
        // The nudge's last queries measured the result as it ended, if they were all of the measure's samples.
        const m = nudging.measured ? measuredBy(nudging.measured, nudged) : measure(nudged, mesh, surface, maxSamples);
        if (distance(m) < distance(doneMeasured)) done = { ...done, mesh: nudged }, doneMeasured = m;
      }
    }
    return { result: done, measured: doneMeasured };
  }
  // Fitted against a proxy: the closest fit, or the closest of those dragged and nudged against the
  // proxy, measured against the input, and dragged and nudged against it.
  if (proxied) {
    const best = [...finishedFits.values()].reduce((b, f) => (distance(f.measured) < distance(b.measured) ? f : b), { result, measured });
    ({ mesh, surface, pieces } = prepared);
    finishedFits.clear();
    result = best.result, measured = measure(result.mesh, mesh, surface, maxSamples);
  }
  // The closest fit dragged and nudged; the closest of those made (one before the emphasis rounds, see above).
  finished(result, measured);
  ({ result, measured } = [...finishedFits.values()].reduce((best, f) => (distance(f.measured) < distance(best.measured) ? f : best)));
  const volume = mrvol.volume(result.mesh);
  const constraints = result.constraints;
  const report = {
    mesh: result.mesh,
    levels: result.levels,
    levelsTried: tried.map((t) => t.levels),
    fits: tried,
    baseVertices: result.baseVertices,
    baseFaces: result.baseFaces,
    // A base size given whose first fit folded, grown until a fit did not (see fit above).
    baseGrown: grownFrom === null ? null : { asked: grownFrom, to: requested },
    vertices: result.mesh.positions.length / 3,
    faces: result.mesh.faces.length / 3,
    components: pieces.length,
    hausdorff: Math.max(measured.toInput, measured.fromInput) / diagonal,
    hausdorffToInput: measured.toInput / diagonal,
    hausdorffFromInput: measured.fromInput / diagonal,
    diagonal,
    flippedTriangles: result.flippedTriangles,
    untangledTriangles: result.untangled,
    volumeInput: inputVolume,
    volume,
    volumeChange: (volume - inputVolume) / inputVolume,
    // With smoothing the surface fitted is the smoothed one: the change from the input as repaired too.
    volumeChangeFromUnsmoothed: repaired?.report.smoothing ? (volume - repaired.report.smoothing.volumeBefore) / repaired.report.smoothing.volumeBefore : null,
    rayFallbacks: result.fallbacks,
    features: { edges: features?.edgeCount ?? 0, corners: features?.corners.size ?? 0, lines: features?.lines.length ?? 0,
                ignoredAsNoise: features?.noisyEdges ?? 0, cornerVertices: constraints?.corners ?? 0,
                creaseVertices: constraints ? constraints.count - constraints.corners : 0 },
    input: { vertices: input.positions.length / 3, faces: input.faces.length / 3,
             weldedVertices: repaired ? repaired.report.weldedVertices : welded.merged,
             droppedFaces: repaired ? repaired.report.degenerateFaces : welded.droppedFaces,
             droppedComponents: droppedComponents + (repaired?.report.droppedComponents ?? 0), droppedPieces, genus },
    // Pieces whose base (and so the result) lost tiny tunnels the simplifier could not keep.
    genusChangedPieces: genusChanges.size,
    repair: repaired?.report ?? null,
    simplifierRetries: simplifierProblems,
    fit: options.parametrise ? 'parametrised' : 'simplified',
    parametrisedFallback: null,
    proxy: proxied?.proxy ?? null,
    proxyFallback: null,
    ms: now() - started,
  };
  // Still far by default: the MAPS fit (parametrise) too (closer on the teapot and bunny, farther on
  // dragon-11k); the closer of the two without folds is kept. Only where it can take every piece: a
  // piece over its limit would be fitted again as before, doubling the time of the large scans for nothing.
  const pieceFaces = pieces.map((p) => p.mesh.faces.length / 3);
  const canParametrise = pieceFaces.every((f) => f <= PARAMETRISE_MAX_FACES) && pieceFaces.some((f) => f > 64);
  if (options.parametrise === undefined && report.hausdorff > goal && canParametrise) {
    let other = null, error = null;
    try {
      other = await remesh(mrvol, input, { ...options, parametrise: true,
                                           onProgress: (f, stage) => progress(0.95 + 0.05 * f, `parametrised fit: ${stage}`) }, prepared);
    } catch (e) {
      if (!(e instanceof MrvolError)) throw e;
      error = e.message;
    }
    const kept = !!other && other.flippedTriangles === 0 && other.hausdorff < report.hausdorff;
    const fallback = other ? { hausdorff: other.hausdorff, flippedTriangles: other.flippedTriangles, kept } : { error, kept };
    const chosen = kept ? other : report;
    return { ...chosen, parametrisedFallback: fallback, ms: now() - started };
  }
  return report;
}

/** Whether two meshes have the same faces and positions. */
function sameMesh(a, b) {
  if (a.faces.length !== b.faces.length || a.positions.length !== b.positions.length) return false;
  for (let i = 0; i < a.faces.length; i++) if (a.faces[i] !== b.faces[i]) return false;
  for (let i = 0; i < a.positions.length; i++) if (a.positions[i] !== b.positions[i]) return false;
  return true;
}

/** Whether two vertex masks (arrays of 0 / 1, or null for none) are the same. */
function sameMask(a, b) {
  if (!a || !b) return !a && !b;
  if (a.length !== b.length) return false;
  for (let i = 0; i < a.length; i++) if (!a[i] !== !b[i]) return false;
  return true;
}

const positionKey = (p, v) => `${p[3 * v]},${p[3 * v + 1]},${p[3 * v + 2]}`;

function countFeatureVertices(mesh, keys) {
  let count = 0;
  for (let v = 0; v < mesh.positions.length / 3; v++) if (keys.features.has(positionKey(mesh.positions, v))) count++;
  return count;
}

/**
 * A simplifier lock for `mesh`: all its feature vertices (by position) if they fit in the base
 * of `target` faces (then the base's edges can follow every crease), else its corners if they
 * fit, else null.
 */
function lockedFeatures(mesh, keys, target) {
  const n = mesh.positions.length / 3;
  for (const [set, room] of [[keys.features, target / 2], [keys.corners, target / 4]]) {
    if (set.size === 0) continue;
    const lock = new Uint8Array(n);
    let count = 0;
    for (let v = 0; v < n; v++) if (set.has(positionKey(mesh.positions, v))) lock[v] = 1, count++;
    if (count > 0 && count <= room) return lock;
  }
  return null;
}

/**
 * The points of `p` (x y z each) whose distance is over `limit`, the farthest first, each at
 * least `spacing` from those chosen, at most `count` (x y z each); null if none.
 */
function farPoints(p, distances, limit, spacing, count) {
  const far = [];
  for (let i = 0; i < p.length / 3; i++) if (distances[i] > limit) far.push([distances[i], i]);
  if (far.length === 0) return null;
  far.sort((a, b) => b[0] - a[0]);
  const grid = new Map(), chosen = [];
  const cell = (x) => Math.floor(x / spacing);
  for (const [, i] of far) {
    if (chosen.length >= 3 * count) break;
    const [cx, cy, cz] = [cell(p[3 * i]), cell(p[3 * i + 1]), cell(p[3 * i + 2])];
    let near = false;
    for (let dx = -1; dx <= 1 && !near; dx++)
      for (let dy = -1; dy <= 1 && !near; dy++)
        for (let dz = -1; dz <= 1 && !near; dz++)
          for (const j of grid.get(`${cx + dx} ${cy + dy} ${cz + dz}`) ?? [])
            if (hypot3(p[3 * i] - p[3 * j], p[3 * i + 1] - p[3 * j + 1], p[3 * i + 2] - p[3 * j + 2]) < spacing) near = true;
    if (near) continue;
    const key = `${cx} ${cy} ${cz}`;
    if (!grid.has(key)) grid.set(key, []);
    grid.get(key).push(i);
    chosen.push(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
  }
  return Float64Array.from(chosen);
}

/** A measure (as measure() makes) from distances found otherwise; the result's surface is made when asked for. */
function measuredBy({ toInput, fromInput }, result) {
  let resultSurface = null;
  return {
    toInput, fromInput,
    get surface() {
      return (resultSurface ??= new Surface(result, { normals: false }));
    },
  };
}

/** Two-sided sampled distances between the result and the input (and the result's surface). */
function measure(result, input, surface, maxSamples) {
  const resultSurface = new Surface(result, { normals: false });
  const measured = { toInput: oneSidedHausdorff(result, surface, maxSamples), fromInput: oneSidedHausdorff(input, resultSurface, maxSamples),
                     surface: resultSurface };
  resultSurface.dispose();  // kept measures hold no tree (one is built again if asked: addTips, farPieces)
  return measured;
}

/**
 * Adds to `keys` the positions of the input vertices farther than `limit` from the result (their
 * `distances` from it), the farthest first, each at least `spacing` from those already chosen, at most `count`. Returns how
 * many were added.
 */
function addTips(input, distances, limit, spacing, count, keys) {
  const p = input.positions, far = [];
  for (let i = 0; i < p.length / 3; i++) if (distances[i] > limit) far.push([distances[i], i]);
  far.sort((a, b) => b[0] - a[0]);
  const chosen = [];
  for (const [, i] of far) {
    if (chosen.length >= count) break;
    if (chosen.some((j) => hypot3(p[3 * i] - p[3 * j], p[3 * i + 1] - p[3 * j + 1], p[3 * i + 2] - p[3 * j + 2]) < spacing)) continue;
    chosen.push(i);
  }
  let added = 0;
  for (const i of chosen) if (!keys.has(positionKey(p, i))) keys.add(positionKey(p, i)), added++;
  return added;
}

/** For each piece (its vertices' distances from the result): whether one is farther than `limit`. */
function farPieces(distances, limit) {
  return distances.map((d) => d.some((x) => x > limit));
}

/** `lock` (or none) with the vertices of `mesh` at the positions of `keys` added, if they fit the target. */
function withLocks(lock, mesh, keys, target) {
  if (keys.size === 0) return lock;
  const n = mesh.positions.length / 3, out = lock ? Uint8Array.from(lock) : new Uint8Array(n);
  let count = 0;
  for (let v = 0; v < n; v++) if (keys.has(positionKey(mesh.positions, v))) out[v] = 1, count++;
  return count > 0 && count <= target / 4 ? out : lock;
}

/**
 * The welded (or repaired) input as closed 2-manifold pieces, one per connected component, each
 * with its genus and outward: errors name what is wrong (not manifold, holes, inside out). Pieces
 * enclosing no volume (fewer than 4 faces, a flat double sheet) are dropped when others remain.
 */
function inputPieces(mrvol, mesh, keepLargest, repaired) {
  const { MrvolError } = mrvol;
  if (mesh.faces.length === 0) throw new MrvolError('the input has no triangle');
  let v;
  try {
    v = mrvol.validate(mesh);
  } catch (e) {
    throw new MrvolError(`the input is not a manifold triangle mesh: ${e.message}${repaired ? '' : ' (--repair drops such faces and closes the holes)'}`);
  }
  if (!v.closed)
    throw new MrvolError(`the input has holes (${v.boundaryEdges} boundary edges); remeshing needs a closed surface: ` +
                         (repaired ? 'holes larger than the repair closes are left (raise maxHoleEdges / --max-hole)' : 'close the holes first (or try --repair)'));
  const { ofFace, count } = connectivity(mesh.faces, mesh.positions.length / 3).components;
  let pieces = [];
  for (let c = 0; c < count; c++) {
    const piece = count === 1 ? mesh : componentMesh(mesh, ofFace, c);
    pieces.push({ mesh: piece, faces: piece.faces.length / 3 });
  }
  let droppedComponents = 0, droppedPieces = 0;
  if (keepLargest && pieces.length > 1) {
    const largest = pieces.reduce((x, y) => (y.faces > x.faces ? y : x));
    droppedComponents = pieces.length - 1;
    pieces = [largest];
  }
  const diagonal = boundingDiagonal(mesh.positions);
  let genus = 0;
  const kept = [];
  for (const [i, piece] of pieces.entries()) {
    const where = pieces.length > 1 ? ` (component ${i + 1} of ${pieces.length})` : '';
    const volume = mrvol.volume(piece.mesh);
    if (piece.faces < 4 || Math.abs(volume) <= 1e-9 * diagonal ** 3) {
      droppedPieces++;
      continue;
    }
    if (volume < 0) {
      if (!repaired) throw new MrvolError(`the input encloses no positive volume (${volume})${where}: is it inside out? (--repair turns it)`);
      throw new MrvolError(`a component encloses a negative volume (${volume})${where}`);
    }
    piece.genus = mrvol.validate(piece.mesh).genus;
    genus += piece.genus;
    kept.push(piece);
  }
  if (kept.length === 0) throw new MrvolError('the input encloses no volume: no piece is a closed surface around a solid');
  return { pieces: kept, genus, droppedComponents, droppedPieces };
}

/**
 * Subdivides `base` (linear scheme: 1-to-4 splits at edge midpoints) and fits level by level: the
 * vertices born at level l start at the midpoint of their parent edge (whose ends are already on
 * the surface): on a feature line if both parents are (lib/features.mjs), else moved along the
 * mean normal of the level-(l-1) faces around that edge, at most one parent edge long; then the
 * level-l mesh is relaxed tangentially and reprojected. Output in the hierarchy order of the core
 * (base vertices first).
 */
function fitLevels(mrvol, surface, base, levels, relaxIterations, features, exact, onProgress = () => {}, tips = null, parametrisation = null) {
  const mr = mrvol.subdivide(base, { levels, scheme: 'linear' });
  try {
    const positions = Float64Array.from(mr.positions());
    const faces = Uint32Array.from(mr.faces());
    const depths = mr.depths();
    const vertexCount = positions.length / 3;
    // With a MAPS parametrisation: each vertex's weights over the base's vertices (a base vertex
    // its own, a child its parents' mean), mapped to the input instead of cast and relaxed.
    const weightsOf = parametrisation ? new Array(vertexCount) : null;
    if (weightsOf) {
      const baseIndex = new Map();
      for (let v = 0; v < base.positions.length / 3; v++) baseIndex.set(positionKey(base.positions, v), v);
      for (let m = 0; m < vertexCount; m++) if (depths[m] === 0) weightsOf[m] = new Map([[baseIndex.get(positionKey(positions, m)), 1]]);
    }
    const mapped = [0, 0, 0];
    let unmapped = 0;
    const constraints = new Constraints(features && features.edgeCount > 0 ? features : null, vertexCount);
    for (let m = 0; m < vertexCount; m++) if (depths[m] === 0) constraints.assignBase(positions, m);
    // Tips kept in the base (input vertices a fit left far) stay on their tip: relaxed, they
    // would slide down the thin part they end.
    const heldTips = [];
    if (tips?.size)
      for (let m = 0; m < vertexCount; m++)
        if (depths[m] === 0 && constraints.kind[m] === 0 && tips.has(positionKey(positions, m))) constraints.hold(m), heldTips.push(m);
    // A piece that is its own base: the linear subdivision is exact, every vertex stays.
    if (exact) for (let m = 0; m < vertexCount; m++) constraints.hold(m);
    // Holding the base vertices (input vertices) keeps tips but folds the triangles around them:
    // every vertex relaxes (except corners).
    const held = new Uint8Array(vertexCount);
    let fallbacks = 0;
    // Level l's work grows as 4^l; the feature snap and pull after them count as one more level.
    const work = (l) => (4 ** (l + 1) - 4) / 3;
    for (let level = 1; level <= levels; level++) {
      onProgress(work(level - 1) / work(levels + 1), `fitting level ${level} of ${levels}`);
      const coarse = level === 1 ? base.faces : mr.levelFaces(level - 1);
      const fine = level === levels ? faces : mr.levelFaces(level);
      const coarseNormals = vertexNormals(positions, coarse);
      const adjacency = connectivity(fine, vertexCount).neighbours;
      const { offsets, list } = adjacency;
      const normal = [0, 0, 0];
      const around = connectivity(coarse, vertexCount).vertexFaces;
      // The vertices facing the coarse edge a-b (in the one or two faces that hold it).
      const opposite = (a, b) => {
        const out = [];
        for (let e = around.offsets[a]; e < around.offsets[a + 1]; e++) {
          const f = 3 * around.list[e];
          if (coarse[f] !== b && coarse[f + 1] !== b && coarse[f + 2] !== b) continue;
          for (let j = 0; j < 3; j++) if (coarse[f + j] !== a && coarse[f + j] !== b) out.push(coarse[f + j]);
        }
        return out;
      };
      for (let m = 0; m < vertexCount; m++) {
        if (depths[m] !== level) continue;
        // Parents: the two neighbours born earlier (the ends of the split edge).
        let a = -1, b = -1;
        for (let e = offsets[m]; e < offsets[m + 1]; e++) {
          if (depths[list[e]] >= level) continue;
          if (a < 0) a = list[e];
          else b = list[e];
        }
        if (weightsOf) {
          const w = new Map();
          for (const parent of [a, b]) for (const [id, x] of weightsOf[parent]) w.set(id, (w.get(id) ?? 0) + x / 2);
          weightsOf[m] = w;
        }
        if (constraints.kind[m] === 2 || constraints.assignChild(positions, m, a, b, opposite(a, b))) continue;
        if (weightsOf) {
          if (parametrisation.map([...weightsOf[m].keys()], [...weightsOf[m].values()], mapped)) {
            positions[3 * m] = mapped[0], positions[3 * m + 1] = mapped[1], positions[3 * m + 2] = mapped[2];
            continue;
          }
          unmapped++;
        }
        const x = (positions[3 * a] + positions[3 * b]) / 2, y = (positions[3 * a + 1] + positions[3 * b + 1]) / 2,
              z = (positions[3 * a + 2] + positions[3 * b + 2]) / 2;
        for (let k = 0; k < 3; k++) normal[k] = coarseNormals[3 * a + k] + coarseNormals[3 * b + k];
        const l = hypot3(normal[0], normal[1], normal[2]) || 1;
        for (let k = 0; k < 3; k++) normal[k] /= l;
        const cap = hypot3(positions[3 * a] - positions[3 * b], positions[3 * a + 1] - positions[3 * b + 1],
                               positions[3 * a + 2] - positions[3 * b + 2]);
        let hit = surface.castBothWays(x, y, z, normal, cap);
        // A hit on a sheet facing the other way is the far side of a thin part: not this one.
        if (hit) {
          const n = surface.normal(hit.faceIndex);
          if (n[0] * normal[0] + n[1] * normal[1] + n[2] * normal[2] < 0) hit = null;
        }
        const p = hit ? hit.point : (fallbacks++, surface.closest(x, y, z).point);
        positions[3 * m] = p.x, positions[3 * m + 1] = p.y, positions[3 * m + 2] = p.z;
      }
      // Mapped vertices are not relaxed: relaxed (all, or all but the base's), the dragon-11k went 0.78% -> 0.79-0.85%.
      if (relaxIterations > 0 && !parametrisation) relaxTangentially(surface, positions, fine, adjacency, relaxIterations, 0.5, held, constraints);
    }
    if (levels > 0) {
      onProgress(work(levels) / work(levels + 1), 'fitting features');
      const known = snapToFeatures(surface, positions, faces, relaxIterations, constraints);
      attractToInput(surface, positions, faces, {}, constraints, known);
    }
    return { mesh: { positions, faces }, baseVertices: base.positions.length / 3, baseFaces: base.faces.length / 3, fallbacks, constraints, heldTips, unmapped };
  } finally {
    mr.delete();
  }
}
