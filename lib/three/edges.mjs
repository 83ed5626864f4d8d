// Unique edges of a triangle or quad list (for drawing cages and wireframes), and the triangles a
// quad mesh is drawn with. No three.js: the editing session and the drawing helpers share it.

/**
 * Unique edges of triangles as pairs of indices; with `index` (a Map), the face's vertices are
 * mapped through it first (caller's vertex -> cage index) and must all be in it.
 * @param {ArrayLike<number>} faces 3 indices per triangle
 * @param {Map<number, number> | null} [index]
 * @returns {Uint32Array}
 */
export function edgesOf(faces, index = null) {
  return polygonEdges(faces, 3, index);
}

/** Unique edges of quads (4 indices each, the quads' sides: no diagonals), as edgesOf. */
export function quadEdgesOf(quads, index = null) {
  return polygonEdges(quads, 4, index);
}

/**
 * The triangles a quad mesh is drawn with: each quad (a, b, c, d) split along a-c into (a, b, c)
 * and (a, c, d), keeping its orientation. Triangle t belongs to quad floor(t / 2).
 */
export function trianglesOfQuads(quads) {
  const triangles = new Uint32Array(quads.length / 4 * 6);
  for (let q = 0, t = 0; q < quads.length; q += 4, t += 6) {
    const a = quads[q], b = quads[q + 1], c = quads[q + 2], d = quads[q + 3];
    triangles[t] = a, triangles[t + 1] = b, triangles[t + 2] = c;
    triangles[t + 3] = a, triangles[t + 4] = c, triangles[t + 5] = d;
  }
  return triangles;
}

function polygonEdges(faces, corners, index) {
  const seen = new Set();
  const edges = [];
  for (let f = 0; f < faces.length; f += corners)
    for (let k = 0; k < corners; k++) {
      let a = faces[f + k], b = faces[f + (k + 1) % corners];
      if (index) {
        a = index.get(a);
        b = index.get(b);
        if (a === undefined || b === undefined) throw new Error('a coarse face refers to a vertex outside the cage');
      }
      const lo = Math.min(a, b), hi = Math.max(a, b);
      const id = lo * 4294967296 + hi;
      if (seen.has(id)) continue;
      seen.add(id);
      edges.push(lo, hi);
    }
  return Uint32Array.from(edges);
}
