// A simplifier that cannot change the topology: half-edge collapses (a vertex moved onto a
// neighbour, so the output's vertices are input vertices) ordered by quadric error, each allowed
// only if it passes the link condition (the two ends share exactly the two vertices facing their
// edge) and turns no triangle by more than a bound. On a closed 2-manifold this keeps it closed,
// manifold, one piece per piece and of the same genus, at any size down to a tetrahedron, where
// meshoptimizer's simplifier, which does not check the topology, pinches a scan's thin parts into
// fins and tiny tunnels closed (lib/remesh.mjs then had to take a base 1.5x larger each time).
// Made for bases of a few hundred to a few thousand faces from a mesh already simplified by
// meshoptimizer to some thousands: plain JS, Maps and Sets.

import { hypot3 } from './geometry.mjs';

/**
 * A binary min-heap of collapses (cost, u, v and the two stamps) in flat typed arrays: no array
 * per entry (millions are pushed, most of them stale). The same sift steps as a heap of
 * [cost, u, v, su, sv] arrays, so the same order, ties included.
 */
class Heap {
  constructor(capacity = 1024) {
    this.size = 0;
    this.grow(capacity);
  }
  grow(capacity) {
    const cost = new Float64Array(capacity), ids = new Uint32Array(4 * capacity);
    if (this.cost) cost.set(this.cost.subarray(0, this.size)), ids.set(this.ids.subarray(0, 4 * this.size));
    this.cost = cost, this.ids = ids;
  }
  /** Puts the entry (cost, u, v, su, sv) at slot i. */
  #put(i, cost, u, v, su, sv) {
    this.cost[i] = cost;
    const k = 4 * i;
    this.ids[k] = u, this.ids[k + 1] = v, this.ids[k + 2] = su, this.ids[k + 3] = sv;
  }
  #move(to, from) {
    const ids = this.ids, t = 4 * to, f = 4 * from;
    this.cost[to] = this.cost[from];
    ids[t] = ids[f], ids[t + 1] = ids[f + 1], ids[t + 2] = ids[f + 2], ids[t + 3] = ids[f + 3];
  }
  push(cost, u, v, su, sv) {
    if (this.size === this.cost.length) this.grow(2 * this.size);
    let i = this.size++;
    // Up: parents with a larger cost move down into the hole.
    while (i > 0) {
      const p = (i - 1) >> 1;
      if (this.cost[p] <= cost) break;
      this.#move(i, p);
      i = p;
    }
    this.#put(i, cost, u, v, su, sv);
  }
  /** Removes the cheapest entry; its u, v, su, sv into out[0..3]. */
  pop(out) {
    const ids = this.ids, c = this.cost;
    out[0] = ids[0], out[1] = ids[1], out[2] = ids[2], out[3] = ids[3];
    const n = --this.size;
    if (n === 0) return;
    // The last entry sifts down from the root (the smaller child moves up; the left one on ties).
    const lastCost = c[n], lk = 4 * n, lu = ids[lk], lv = ids[lk + 1], lsu = ids[lk + 2], lsv = ids[lk + 3];
    let i = 0;
    for (;;) {
      const l = 2 * i + 1, r = l + 1;
      let m = i, mc = lastCost;
      if (l < n && c[l] < mc) m = l, mc = c[l];
      if (r < n && c[r] < mc) m = r;
      if (m === i) break;
      this.#move(i, m);
      i = m;
    }
    this.#put(i, lastCost, lu, lv, lsu, lsv);
  }
}

function faceNormal(p, a, b, c) {
  const ux = p[3 * b] - p[3 * a], uy = p[3 * b + 1] - p[3 * a + 1], uz = p[3 * b + 2] - p[3 * a + 2];
  const vx = p[3 * c] - p[3 * a], vy = p[3 * c + 1] - p[3 * a + 1], vz = p[3 * c + 2] - p[3 * a + 2];
  return [uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx];
}

/**
 * Collapses `mesh` (a closed 2-manifold, one piece) towards `targetFaces` faces; the vertices of
 * `lock` (a mask over its vertices, or null) stay. Stops early when no allowed collapse is left.
 * Returns a compacted { positions, faces } whose positions are some of the input's.
 * `maxTurn`: the cosine below which a collapse that turns a triangle that far is refused.
 */
export function collapseToTarget(mesh, targetFaces, lock = null, { maxTurn = 0.2, track = false } = {}) {
  const p = mesh.positions, vertexCount = p.length / 3, faceCount = mesh.faces.length / 3;
  const faces = Uint32Array.from(mesh.faces);
  const alive = new Uint8Array(faceCount).fill(1);
  const facesOf = Array.from({ length: vertexCount }, () => new Set());
  const neighbours = Array.from({ length: vertexCount }, () => new Set());
  // Quadrics (area-weighted planes of the faces around each vertex): a, b, c, d -> 10 sums.
  const quadric = new Float64Array(10 * vertexCount);
  for (let f = 0; f < faceCount; f++) {
    const [a, b, c] = [faces[3 * f], faces[3 * f + 1], faces[3 * f + 2]];
    for (const [x, y] of [[a, b], [b, c], [c, a]]) neighbours[x].add(y), neighbours[y].add(x);
    facesOf[a].add(f), facesOf[b].add(f), facesOf[c].add(f);
    const n = faceNormal(p, a, b, c), l = hypot3(n[0], n[1], n[2]);
    if (!(l > 0)) continue;
    const nx = n[0] / l, ny = n[1] / l, nz = n[2] / l, d = -(nx * p[3 * a] + ny * p[3 * a + 1] + nz * p[3 * a + 2]), w = l / 2;
    const q = [nx * nx, nx * ny, nx * nz, nx * d, ny * ny, ny * nz, ny * d, nz * nz, nz * d, d * d];
    for (const v of [a, b, c]) for (let k = 0; k < 10; k++) quadric[10 * v + k] += w * q[k];
  }
  // The quadric of vertex s at (x, y, z).
  const quadricAt = (s, x, y, z) => {
    const q = quadric, o = 10 * s;
    return q[o] * x * x + 2 * q[o + 1] * x * y + 2 * q[o + 2] * x * z + 2 * q[o + 3] * x + q[o + 4] * y * y + 2 * q[o + 5] * y * z +
      2 * q[o + 6] * y + q[o + 7] * z * z + 2 * q[o + 8] * z + q[o + 9];
  };
  const error = (u, v, at) => {
    const x = p[3 * at], y = p[3 * at + 1], z = p[3 * at + 2];
    let e = 0;
    e += quadricAt(u, x, y, z);
    e += quadricAt(v, x, y, z);
    return Math.max(0, e);
  };
  const stamp = new Uint32Array(vertexCount);
  const heap = new Heap();
  // refused[u]: the v of each collapse u -> v popped and refused since u's or v's neighbourhood last changed.
  const refused = Array.from({ length: vertexCount }, () => new Set());
  // u moves onto v (u disappears).
  const offer = (u, v) => {
    if (lock?.[u]) return;
    heap.push(error(u, v, v), u, v, stamp[u], stamp[v]);
  };
  for (let u = 0; u < vertexCount; u++) for (const v of neighbours[u]) offer(u, v);

  const allowed = (u, v) => {
    // Link condition: the common neighbours are the two vertices facing the edge.
    let common = 0;
    for (const w of neighbours[u]) if (neighbours[v].has(w)) common++;
    if (common !== 2) return false;
    // No triangle of u (but the two that vanish) turns over or far, or becomes degenerate.
    for (const f of facesOf[u]) {
      const a = faces[3 * f], b = faces[3 * f + 1], c = faces[3 * f + 2];
      if (a === v || b === v || c === v) continue;
      const before = faceNormal(p, a, b, c);
      const after = faceNormal(p, a === u ? v : a, b === u ? v : b, c === u ? v : c);
      const lb = Math.hypot(...before), la = Math.hypot(...after);
      if (!(la > 1e-12 * (lb || 1))) return false;
      if (before[0] * after[0] + before[1] * after[1] + before[2] * after[2] < maxTurn * la * lb) return false;
    }
    return true;
  };

  // MAPS (Lee et al. 1998): each removed vertex keeps the face of the current mesh it lies in
  // and its barycentrics there, carried through every later collapse.
  const tracker = track ? new Tracker(p, faces, facesOf, vertexCount, faceCount) : null;
  let remaining = faceCount;
  const top = new Uint32Array(4);
  while (remaining > targetFaces && remaining > 4 && heap.size > 0) {
    heap.pop(top);
    const u = top[0], v = top[1], su = top[2], sv = top[3];
    if (su !== stamp[u] || sv !== stamp[v] || !neighbours[u].has(v)) continue;
    if (!allowed(u, v) || (tracker && !tracker.collapse(u, v))) {
      refused[u].add(v);
      continue;
    }
    for (const f of [...facesOf[u]]) {
      const a = faces[3 * f], b = faces[3 * f + 1], c = faces[3 * f + 2];
      if (a === v || b === v || c === v) {
        alive[f] = 0, remaining--;
        for (const w of [a, b, c]) facesOf[w].delete(f);
        continue;
      }
      for (let j = 0; j < 3; j++) if (faces[3 * f + j] === u) faces[3 * f + j] = v;
      facesOf[v].add(f);
    }
    facesOf[u].clear();
    for (const w of neighbours[u]) {
      neighbours[w].delete(u);
      if (w !== v) neighbours[w].add(v), neighbours[v].add(w);
    }
    neighbours[v].delete(u);
    neighbours[u].clear();
    for (let k = 0; k < 10; k++) quadric[10 * v + k] += quadric[10 * u + k];
    // Only v's quadric changed: the collapses onto and off v are offered again with their new cost.
    // The others around v keep their cost and their heap entry, but those refused may be allowed
    // now (their link or their triangles changed): they are offered again too.
    stamp[u]++, stamp[v]++;
    refused[u].clear(), refused[v].clear();
    for (const w of neighbours[v]) {
      offer(w, v), offer(v, w);
      for (const x of refused[w]) if (x !== v && neighbours[w].has(x)) offer(w, x);
      refused[w].clear();
      for (const x of neighbours[w]) if (x !== v && refused[x].delete(w)) offer(x, w);
    }
  }
  // Compacted, the vertices in their input order.
  const remap = new Int32Array(vertexCount).fill(-1);
  const faceRemap = new Int32Array(faceCount).fill(-1);
  let count = 0;
  const out = [];
  for (let f = 0; f < faceCount; f++) {
    if (!alive[f]) continue;
    faceRemap[f] = out.length / 3;
    for (let j = 0; j < 3; j++) {
      const v = faces[3 * f + j];
      if (remap[v] < 0) remap[v] = -2;
      out.push(v);
    }
  }
  for (let v = 0; v < vertexCount; v++) if (remap[v] === -2) remap[v] = count++;
  const positions = new Float64Array(3 * count);
  for (let v = 0; v < vertexCount; v++) if (remap[v] >= 0) positions.set(p.subarray(3 * v, 3 * v + 3), 3 * remap[v]);
  const result = { positions, faces: Uint32Array.from(out, (v) => remap[v]) };
  if (tracker) result.parameters = tracker.parameters(remap, faceRemap);
  return result;
}

/**
 * The MAPS bookkeeping of collapseToTarget(): when u moves onto v, u's 1-ring is flattened by
 * the z^a map (angles at u scaled to 2π, lengths to the power a), the points held by u's faces
 * (and u) are placed in that plane and located in the new fan around v (the triangle whose
 * smallest barycentric is the largest, clamped when a point falls outside the fan).
 */
class Tracker {
  constructor(p, faces, facesOf, vertexCount, faceCount) {
    this.p = p, this.faces = faces, this.facesOf = facesOf;
    this.face = new Int32Array(vertexCount).fill(-1);
    this.bary = new Float64Array(3 * vertexCount);
    this.held = Array.from({ length: faceCount }, () => []);
  }

  collapse(u, v) {
    const { p, faces, facesOf } = this;
    // u's ring in order (faces u, x, y give x -> y).
    const next = new Map();
    for (const f of facesOf[u]) {
      const j = faces[3 * f] === u ? 0 : faces[3 * f + 1] === u ? 1 : 2;
      next.set(faces[3 * f + (j + 1) % 3], faces[3 * f + (j + 2) % 3]);
    }
    const ring = [];
    for (let w = next.keys().next().value; ring.length <= next.size; w = next.get(w)) {
      if (w === undefined) return false;
      if (ring.length && w === ring[0]) break;
      ring.push(w);
    }
    if (ring.length !== next.size) return false;
    const d = (w) => [p[3 * w] - p[3 * u], p[3 * w + 1] - p[3 * u + 1], p[3 * w + 2] - p[3 * u + 2]];
    const lengths = ring.map((w) => Math.hypot(...d(w)));
    const angles = ring.map((w, i) => {
      const a = d(w), b = d(ring[(i + 1) % ring.length]);
      const c = (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) / (lengths[i] * lengths[(i + 1) % ring.length] || 1);
      return Math.acos(Math.max(-1, Math.min(1, c)));
    });
    const total = angles.reduce((t, x) => t + x, 0);
    if (!(total > 0)) return false;
    const a = (2 * Math.PI) / total, longest = Math.max(...lengths) || 1;
    const plane = new Map([[u, [0, 0]]]);
    let phi = 0;
    ring.forEach((w, i) => {
      const r = (lengths[i] / longest) ** a;
      plane.set(w, [r * Math.cos(phi), r * Math.sin(phi)]);
      phi += a * angles[i];
    });
    // The points to place: u and those held by u's faces, in the plane.
    const points = [u];
    const at = [[0, 0]];
    for (const f of facesOf[u]) {
      for (const q of this.held[f]) {
        let x = 0, y = 0;
        for (let j = 0; j < 3; j++) {
          const c = plane.get(faces[3 * f + j]), w = this.bary[3 * q + j];
          x += w * c[0], y += w * c[1];
        }
        points.push(q), at.push([x, y]);
      }
      this.held[f] = [];
    }
    // The new fan: u's faces without v, u read as v.
    const fan = [];
    for (const f of facesOf[u]) {
      const c = [faces[3 * f], faces[3 * f + 1], faces[3 * f + 2]];
      if (c.includes(v)) continue;
      fan.push({ f, c: c.map((w) => plane.get(w === u ? v : w)) });
    }
    points.forEach((q, i) => {
      let best = null, bestMin = -Infinity;
      for (const t of fan) {
        const b = barycentric2(at[i], t.c);
        if (!b) continue;
        const m = Math.min(b[0], b[1], b[2]);
        if (m > bestMin) bestMin = m, best = { f: t.f, b };
      }
      if (!best) best = { f: fan[0].f, b: [1 / 3, 1 / 3, 1 / 3] };
      const b = best.b.map((x) => Math.max(0, x)), s = b[0] + b[1] + b[2] || 1;
      this.face[q] = best.f;
      for (let j = 0; j < 3; j++) this.bary[3 * q + j] = b[j] / s;
      this.held[best.f].push(q);
    });
    return true;
  }

  /** Per input vertex, its weights over the output's vertices: { ids: [..], weights: [..] } (1 to 3 entries). */
  parameters(remap, faceRemap) {
    const { faces } = this, vertexCount = this.face.length;
    const out = new Array(vertexCount);
    for (let q = 0; q < vertexCount; q++) {
      if (remap[q] >= 0) {
        out[q] = { ids: [remap[q]], weights: [1] };
        continue;
      }
      const f = this.face[q];
      out[q] = { ids: [0, 1, 2].map((j) => remap[faces[3 * f + j]]), weights: [0, 1, 2].map((j) => this.bary[3 * q + j]), face: faceRemap[f] };
    }
    return out;
  }
}

/** Barycentrics of point `q` in the 2D triangle `c` (three [x, y]), or null when degenerate. */
export function barycentric2(q, c) {
  const [a, b, d] = c;
  const ux = b[0] - a[0], uy = b[1] - a[1], vx = d[0] - a[0], vy = d[1] - a[1];
  const det = ux * vy - uy * vx;
  if (!(Math.abs(det) > 1e-18)) return null;
  const wx = q[0] - a[0], wy = q[1] - a[1];
  const s = (wx * vy - wy * vx) / det, t = (ux * wy - uy * wx) / det;
  return [1 - s - t, s, t];
}
