// A simplifier that cannot change the topology: half-edge collapses (a vertex moved onto a
// neighbour, so the output's vertices are input vertices) ordered by quadric error, each allowed
// only if it passes the link condition (the two ends share exactly the two vertices facing their
// edge) and turns no triangle by more than a bound. On a closed 2-manifold this keeps it closed,
// manifold, one piece per piece and of the same genus, at any size down to a tetrahedron, where
// meshoptimizer's simplifier, which does not check the topology, pinches a scan's thin parts into
// fins and tiny tunnels closed (lib/remesh.mjs then had to take a base 1.5x larger each time).
// Made for bases of a few hundred to a few thousand faces from a mesh already simplified by
// meshoptimizer to some thousands: plain JS, Maps and Sets.

/** A binary min-heap of [cost, ...] arrays. */
class Heap {
  constructor() {
    this.items = [];
  }
  get size() {
    return this.items.length;
  }
  push(item) {
    const a = this.items;
    a.push(item);
    for (let i = a.length - 1; i > 0;) {
      const p = (i - 1) >> 1;
      if (a[p][0] <= a[i][0]) break;
      [a[p], a[i]] = [a[i], a[p]];
      i = p;
    }
  }
  pop() {
    const a = this.items, top = a[0], last = a.pop();
    if (a.length > 0) {
      a[0] = last;
      for (let i = 0; ;) {
        const l = 2 * i + 1, r = l + 1;
        let m = i;
        if (l < a.length && a[l][0] < a[m][0]) m = l;
        if (r < a.length && a[r][0] < a[m][0]) m = r;
        if (m === i) break;
        [a[m], a[i]] = [a[i], a[m]];
        i = m;
      }
    }
    return top;
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
export function collapseToTarget(mesh, targetFaces, lock = null, { maxTurn = 0.2 } = {}) {
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
    const n = faceNormal(p, a, b, c), l = Math.hypot(n[0], n[1], n[2]);
    if (!(l > 0)) continue;
    const nx = n[0] / l, ny = n[1] / l, nz = n[2] / l, d = -(nx * p[3 * a] + ny * p[3 * a + 1] + nz * p[3 * a + 2]), w = l / 2;
    const q = [nx * nx, nx * ny, nx * nz, nx * d, ny * ny, ny * nz, ny * d, nz * nz, nz * d, d * d];
    for (const v of [a, b, c]) for (let k = 0; k < 10; k++) quadric[10 * v + k] += w * q[k];
  }
  const error = (u, v, at) => {
    const x = p[3 * at], y = p[3 * at + 1], z = p[3 * at + 2];
    let e = 0;
    for (const s of [u, v]) {
      const q = quadric.subarray(10 * s, 10 * s + 10);
      e += q[0] * x * x + 2 * q[1] * x * y + 2 * q[2] * x * z + 2 * q[3] * x + q[4] * y * y + 2 * q[5] * y * z + 2 * q[6] * y +
        q[7] * z * z + 2 * q[8] * z + q[9];
    }
    return Math.max(0, e);
  };
  const stamp = new Uint32Array(vertexCount);
  const heap = new Heap();
  // u moves onto v (u disappears).
  const offer = (u, v) => {
    if (lock?.[u]) return;
    heap.push([error(u, v, v), u, v, stamp[u], stamp[v]]);
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

  let remaining = faceCount;
  while (remaining > targetFaces && remaining > 4 && heap.size > 0) {
    const [, u, v, su, sv] = heap.pop();
    if (su !== stamp[u] || sv !== stamp[v] || !neighbours[u].has(v)) continue;
    if (!allowed(u, v)) continue;
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
    stamp[u]++, stamp[v]++;
    for (const w of neighbours[v]) {
      stamp[w]++;
      for (const x of neighbours[w]) offer(w, x), offer(x, w);
    }
  }
  // Compacted, the vertices in their input order.
  const remap = new Int32Array(vertexCount).fill(-1);
  let count = 0;
  const out = [];
  for (let f = 0; f < faceCount; f++) {
    if (!alive[f]) continue;
    for (let j = 0; j < 3; j++) {
      const v = faces[3 * f + j];
      if (remap[v] < 0) remap[v] = -2;
      out.push(v);
    }
  }
  for (let v = 0; v < vertexCount; v++) if (remap[v] === -2) remap[v] = count++;
  const positions = new Float64Array(3 * count);
  for (let v = 0; v < vertexCount; v++) if (remap[v] >= 0) positions.set(p.subarray(3 * v, 3 * v + 3), 3 * remap[v]);
  return { positions, faces: Uint32Array.from(out, (v) => remap[v]) };
}
