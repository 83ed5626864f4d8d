// Triangle pairs of a mesh that intersect: a BVH of its triangles (three-mesh-bvh) cast against
// itself, pairs that share a vertex skipped (they touch by construction). Pairs inside one
// connected piece are told apart from pairs of two pieces (parts of a scene that pass through
// each other, which a remesher keeps as the input had them).
import { BufferAttribute, BufferGeometry, Matrix4 } from 'three';
import { MeshBVH } from 'three-mesh-bvh';

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
  let withinPieces = 0, betweenPieces = 0, first = null, firstWithin = null, firstBetween = null, stopped = false;
  bvh.bvhcast(bvh, identity, {
    intersectsTriangles(t1, t2, i1, i2) {
      if (i1 >= i2) return false;
      const a = 3 * i1, b = 3 * i2;
      for (let p = 0; p < 3; p++)
        for (let q = 0; q < 3; q++) if (corners[a + p] === corners[b + q]) return false;
      const within = piece[corners[a]] === piece[corners[b]];
      if (!within && skipBetween && firstBetween) return false;
      if (!t1.intersectsTriangle(t2)) return false;
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
