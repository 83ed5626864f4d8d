// Triangle pairs of a mesh that intersect: a BVH of its triangles (three-mesh-bvh) cast against
// itself, pairs that share a vertex skipped (they touch by construction). Pairs inside one
// connected piece are told apart from pairs of two pieces (parts of a scene that pass through
// each other, which a remesher keeps as the input had them).
import { BufferAttribute, BufferGeometry, Matrix4 } from 'three';
import { MeshBVH } from 'three-mesh-bvh';
import { boundingDiagonal, unitTriangleNormal } from './geometry.mjs';

const identity = new Matrix4();

/** The connected piece of each vertex (pieces joined through the faces' corners): a label per vertex. */
function vertexPieces(faces, vertexCount) {
  const parent = new Uint32Array(vertexCount);
  for (let v = 0; v < vertexCount; v++) parent[v] = v;
  const find = (v) => {
    while (parent[v] !== v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (let f = 0; f < faces.length; f += 3) {
    const a = find(faces[f]);
    parent[find(faces[f + 1])] = a;
    parent[find(faces[f + 2])] = a;
  }
  for (let v = 0; v < vertexCount; v++) parent[v] = find(v);
  return parent;
}

// Crossing test of two triangles on the float64 positions (Möller's interval test on the line where
// their planes meet, with a tolerance): three's test on the BVH's float32 copy reported flat regions'
// neighbours as crossing once synthesis round-off (1e-16) made them not quite coplanar (a quad pipe's
// end: 1,076 pairs after an edit, none before). Pairs that only touch within `eps` do not cross.
const cross3 = (u, v) => [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];

function unitNormal(p, t) {
  const n = unitTriangleNormal(p, t[0], t[1], t[2], [0, 0, 0]);
  return n[0] === 0 && n[1] === 0 && n[2] === 0 ? null : n;
}

// Signed distances of triangle t's corners to the plane (n through q), those within eps made 0.
function planeDistances(p, t, n, q, eps) {
  return t.map((v) => {
    const d = n[0] * (p[3 * v] - p[3 * q]) + n[1] * (p[3 * v + 1] - p[3 * q + 1]) + n[2] * (p[3 * v + 2] - p[3 * q + 2]);
    return Math.abs(d) <= eps ? 0 : d;
  });
}

// Corners strictly on both sides of the other's plane: a triangle that only reaches that plane with a
// corner or an edge touches the other (a hinge along a seam given twice, a tip resting on it), it does
// not pass through it.
const bothSides = (d) => (d[0] > 0 || d[1] > 0 || d[2] > 0) && (d[0] < 0 || d[1] < 0 || d[2] < 0);

// The segment of triangle t on the other plane, as an interval of the coordinates `key` gives.
function interval(p, t, d, key) {
  const k = t.map((v) => key(v));
  const points = [];
  for (let i = 0; i < 3; i++) {
    const j = (i + 1) % 3;
    if (d[i] === 0) points.push(k[i]);
    if ((d[i] > 0 && d[j] < 0) || (d[i] < 0 && d[j] > 0)) points.push(k[i] + (k[j] - k[i]) * (d[i] / (d[i] - d[j])));
  }
  return points.length ? [Math.min(...points), Math.max(...points)] : null;
}

// Coplanar triangles: whether their interiors overlap (no separating edge direction, with a margin).
function coplanarOverlap(p, a, b, n, eps) {
  const drop = Math.abs(n[0]) > Math.abs(n[1]) ? (Math.abs(n[0]) > Math.abs(n[2]) ? 0 : 2) : (Math.abs(n[1]) > Math.abs(n[2]) ? 1 : 2);
  const [x, y] = [[1, 2], [0, 2], [0, 1]][drop];
  const flat = (t) => t.map((v) => [p[3 * v + x], p[3 * v + y]]);
  const A = flat(a), B = flat(b);
  for (const T of [A, B])
    for (let i = 0; i < 3; i++) {
      const e = [T[(i + 1) % 3][1] - T[i][1], T[i][0] - T[(i + 1) % 3][0]];
      const l = Math.hypot(e[0], e[1]) || 1;
      const range = (U) => U.map((q) => (e[0] * q[0] + e[1] * q[1]) / l);
      const ra = range(A), rb = range(B);
      if (Math.max(...ra) <= Math.min(...rb) + eps || Math.max(...rb) <= Math.min(...ra) + eps) return false;
    }
  return true;
}

/** Whether triangles a and b (3 vertex indices each, no vertex in common) cross, on float64 positions p. */
export function trianglesCross(p, a, b, eps) {
  const na = unitNormal(p, a), nb = unitNormal(p, b);
  if (!na || !nb) return false;  // a degenerate triangle bounds nothing
  const da = planeDistances(p, a, nb, b[0], eps), db = planeDistances(p, b, na, a[0], eps);
  if (da.every((d) => d === 0) || db.every((d) => d === 0)) return coplanarOverlap(p, a, b, na, eps);
  if (!bothSides(da) || !bothSides(db)) return false;
  // Both cut the line where the planes meet: their segments on it overlap by more than eps.
  const line = cross3(na, nb), l = Math.hypot(line[0], line[1], line[2]);
  if (l < 1e-12) return false;  // parallel planes, not coplanar: apart
  const u = [line[0] / l, line[1] / l, line[2] / l];
  const key = (v) => u[0] * p[3 * v] + u[1] * p[3 * v + 1] + u[2] * p[3 * v + 2];
  const ia = interval(p, a, da, key), ib = interval(p, b, db, key);
  return !!ia && !!ib && Math.min(ia[1], ib[1]) - Math.max(ia[0], ib[0]) > eps;
}

/** The face of `faces` with the corners of triangle `t` of the BVH's reordered index (the same vertices). */
function originalFace(faces, corners, t) {
  const key = [corners[3 * t], corners[3 * t + 1], corners[3 * t + 2]].sort((x, y) => x - y).join(',');
  for (let f = 0; f < faces.length; f += 3)
    if ([faces[f], faces[f + 1], faces[f + 2]].sort((x, y) => x - y).join(',') === key) return f / 3;
  return -1;
}

/**
 * positions: Float64Array (3 per vertex), faces: Uint32Array (3 per triangle). Counts intersecting
 * triangle pairs, stopping once `limit` are found (or once `limitWithin` pairs within one piece are):
 * { withinPieces, betweenPieces, first: [i, j] (face indices of the first pair found) | null,
 * firstWithin, firstBetween (the first pair within one piece, of two pieces, or null), complete
 * (false when stopped at a limit) }. With `limitWithin`, pairs of two pieces after the first are
 * skipped untested (not counted): a surface folding into itself is what it looks for.
 */
export function selfIntersections(positions, faces, { limit = Infinity, limitWithin = Infinity } = {}) {
  const geometry = new BufferGeometry();
  geometry.setAttribute('position', new BufferAttribute(Float32Array.from(positions), 3));
  geometry.setIndex(new BufferAttribute(Uint32Array.from(faces), 1));
  const bvh = new MeshBVH(geometry);
  // The BVH reorders the triangles of the index: the pairs found are in its order.
  const corners = geometry.index.array;
  const piece = vertexPieces(faces, positions.length / 3);
  const skipBetween = limitWithin < Infinity;
  const eps = 1e-10 * (boundingDiagonal(positions) || 1);
  let withinPieces = 0, betweenPieces = 0, first = null, firstWithin = null, firstBetween = null, stopped = false;
  bvh.bvhcast(bvh, identity, {
    intersectsTriangles(t1, t2, i1, i2) {
      if (i1 >= i2) return false;
      const a = 3 * i1, b = 3 * i2;
      for (let p = 0; p < 3; p++)
        for (let q = 0; q < 3; q++) if (corners[a + p] === corners[b + q]) return false;
      const within = piece[corners[a]] === piece[corners[b]];
      if (!within && skipBetween && firstBetween) return false;
      // three's test on the float32 copy first (fast; it also says yes to pairs that only touch), then ours
      if (!t1.intersectsTriangle(t2)) return false;
      if (!trianglesCross(positions, [corners[a], corners[a + 1], corners[a + 2]], [corners[b], corners[b + 1], corners[b + 2]], eps)) return false;
      if (within) withinPieces++, firstWithin ??= [i1, i2];
      else betweenPieces++, firstBetween ??= [i1, i2];
      first ??= [i1, i2];
      stopped = withinPieces + betweenPieces >= limit || withinPieces >= limitWithin;
      return stopped;
    },
  });
  geometry.dispose();
  const original = (pair) => pair && [originalFace(faces, corners, pair[0]), originalFace(faces, corners, pair[1])];
  return { withinPieces, betweenPieces, first: original(first), firstWithin: original(firstWithin), firstBetween: original(firstBetween),
           complete: !stopped };
}
