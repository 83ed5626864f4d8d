// Unique edges of a triangle list (for drawing cages and wireframes). No three.js: the editing
// session and the drawing helpers share it.

/**
 * Unique edges of triangles as pairs of indices; with `index` (a Map), the face's vertices are
 * mapped through it first (caller's vertex -> cage index) and must all be in it.
 * @param {ArrayLike<number>} faces 3 indices per triangle
 * @param {Map<number, number> | null} [index]
 * @returns {Uint32Array}
 */
export function edgesOf(faces, index = null) {
  const seen = new Set();
  const edges = [];
  for (let f = 0; f < faces.length; f += 3)
    for (let k = 0; k < 3; k++) {
      let a = faces[f + k], b = faces[f + (k + 1) % 3];
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
