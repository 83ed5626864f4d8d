// Connectivity of the level-e control cage, for drawing its edges. Topology only (no positions):
// the API gives the fine faces and the depth (level of birth) of every vertex; one 1-to-4 split is
// undone at a time. In a split, the face whose three vertices are all new (depth l) is the middle
// one of four, and across each of its edges lies a corner face whose third vertex is an old one.
//
// A coarse face (A, B, C), counter-clockwise, has midpoints m_AB, m_BC, m_CA; its middle fine face
// is (m_AB, m_BC, m_CA), and across the directed edge (m_BC -> m_AB) lies the corner at B.

/**
 * Faces of the level-`level` mesh (caller's vertex indices), from the faces of the finest level.
 * @param {Uint32Array} faces fine faces, 3 per triangle
 * @param {Uint8Array} depths level of birth of every vertex
 * @param {number} levels levels n of the mesh
 * @param {number} level target level e (0..n)
 */
export function coarseFaces(faces, depths, levels, level) {
  let current = faces;
  for (let l = levels; l > level; l--) current = undoSplit(current, depths, l);
  return current;
}

function undoSplit(faces, depths, l) {
  const opposite = new Map(); // directed edge a -> b  =>  third vertex of the face that has it
  const key = (a, b) => a * 4294967296 + b;
  for (let f = 0; f < faces.length; f += 3) {
    const a = faces[f], b = faces[f + 1], c = faces[f + 2];
    opposite.set(key(a, b), c);
    opposite.set(key(b, c), a);
    opposite.set(key(c, a), b);
  }
  const coarse = [];
  for (let f = 0; f < faces.length; f += 3) {
    const m1 = faces[f], m2 = faces[f + 1], m3 = faces[f + 2];
    if (depths[m1] !== l || depths[m2] !== l || depths[m3] !== l) continue;
    const a = opposite.get(key(m1, m3)), b = opposite.get(key(m2, m1)), c = opposite.get(key(m3, m2));
    if (a === undefined || b === undefined || c === undefined) throw new Error(`level ${l} is not a 1-to-4 split`);
    coarse.push(a, b, c);
  }
  if (coarse.length * 4 !== faces.length) throw new Error(`level ${l} is not a 1-to-4 split`);
  return Uint32Array.from(coarse);
}

/**
 * Unique edges of a face list, as pairs of cage indices.
 * @param {Uint32Array} faces caller's vertex indices
 * @param {Map<number, number>} cageIndex caller's vertex index -> cage index
 */
export function cageEdges(faces, cageIndex) {
  const seen = new Set();
  const edges = [];
  for (let f = 0; f < faces.length; f += 3)
    for (let k = 0; k < 3; k++) {
      const a = cageIndex.get(faces[f + k]), b = cageIndex.get(faces[f + (k + 1) % 3]);
      if (a === undefined || b === undefined) throw new Error('a coarse face refers to a vertex outside the cage');
      const lo = Math.min(a, b), hi = Math.max(a, b);
      const id = lo * 4294967296 + hi;
      if (seen.has(id)) continue;
      seen.add(id);
      edges.push(lo, hi);
    }
  return Uint32Array.from(edges);
}
