// The triangles a big mesh's floor shadow is drawn from (floor-shadow.js): a coarser level of its
// subdivision hierarchy (the core's MultiresMesh.levelFaces, on the fine mesh's own vertices). The
// shadow map is 256 x 256 and blurred: a million triangles drawn into it look as a hundred thousand
// do, and on software WebGL the depth pass of 1.3M triangles took 1-2 s of a frame
// (docs/big-file-frames.md).

/**
 * The finest level of a triangle hierarchy (`levels` levels above level 0, `triangles` at the finest)
 * with at most `maxTriangles` triangles: each level has a quarter of the next one's.
 */
export function shadowLevel(triangles, levels, maxTriangles) {
  let level = levels;
  while (level > 0 && triangles > maxTriangles) level--, triangles /= 4;
  return level;
}

/** Faces for the shadow of a triangle MultiresMesh `mr` (`levels`, `triangles` at the finest): null when its own faces do. */
export function shadowFaces(mr, levels, triangles, maxTriangles) {
  if (triangles <= maxTriangles) return null;
  const level = shadowLevel(triangles, levels, maxTriangles);
  return level < levels ? mr.levelFaces(level) : null;
}
