// Edges of the level-e control cage, for drawing: the cage's faces come from the core
// (MultiresMesh.levelFaces), this only lists their unique edges in cage indices.

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
