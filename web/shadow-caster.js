// The triangles a big mesh's floor shadow is drawn from (floor-shadow.js): the faces of a coarser level
// of its subdivision hierarchy, on the fine mesh's own vertices. The shadow map is 256 x 256 and
// blurred: a million triangles drawn into it look as a hundred thousand do, and on software WebGL
// the depth pass of 1.3M triangles took 1-2 s of a frame (docs/big-file-frames.md).
//
// A 1-to-4 split (Loop and the other triangle schemes) turns the coarse face (a, b, c) into three
// corner faces (a, ab, ca), (b, bc, ab), (c, ca, bc) and a middle one; each new vertex (born at the
// finest depth) sits on one coarse edge, whose ends are the old vertices of the corner faces it is in.

/** Records old vertex a as an end of new vertex m's edge; false when m has two other ends already. */
function addEnd(ends, m, a) {
  if (ends[2 * m] === a || ends[2 * m + 1] === a) return true;
  if (ends[2 * m] < 0) ends[2 * m] = a;
  else if (ends[2 * m + 1] < 0) ends[2 * m + 1] = a;
  else return false;
  return true;
}

/** Coarse faces one level up, or null when the faces are not a 1-to-4 split of the vertices' depths. */
function oneLevelUp(faces, depths, depth) {
  const ends = new Int32Array(2 * depths.length).fill(-1); // the two old vertices beside each new one
  const out = new Uint32Array(faces.length / 4);
  let corners = 0;
  // the old corner of each face (-1: a middle face), then each new vertex's two ends
  for (let f = 0; f < faces.length; f += 3) {
    const o0 = depths[faces[f]] < depth, o1 = depths[faces[f + 1]] < depth, o2 = depths[faces[f + 2]] < depth;
    if (!o0 && !o1 && !o2) continue; // a middle face
    if (o0 + o1 + o2 !== 1) return null;
    corners++;
    const at = o0 ? 0 : o1 ? 1 : 2;
    const a = faces[f + at];
    if (!addEnd(ends, faces[f + (at + 1) % 3], a) || !addEnd(ends, faces[f + (at + 2) % 3], a)) return null;
  }
  if (corners * 4 !== faces.length) return null; // 3 corners and a middle per coarse face
  let n = 0;
  for (let f = 0; f < faces.length; f += 3) {
    const o0 = depths[faces[f]] < depth, o1 = depths[faces[f + 1]] < depth;
    const at = o0 ? 0 : o1 ? 1 : depths[faces[f + 2]] < depth ? 2 : -1;
    if (at < 0) continue;
    // (a, next, prev) in the fine face's order: the coarse face (a, b, c) keeps its orientation
    const a = faces[f + at], mb = faces[f + (at + 1) % 3], mc = faces[f + (at + 2) % 3];
    const b = ends[2 * mb] === a ? ends[2 * mb + 1] : ends[2 * mb];
    const c = ends[2 * mc] === a ? ends[2 * mc + 1] : ends[2 * mc];
    if (b < 0 || c < 0) return null;
    if (a < b && a < c) { // each coarse face once (from its least vertex's corner)
      if (n + 3 > out.length) return null;
      out[n++] = a;
      out[n++] = b;
      out[n++] = c;
    }
  }
  return n === out.length ? out : null;
}

/**
 * Faces for the shadow of a mesh (triangles, depths per vertex): coarser levels until at most
 * `maxTriangles`, or the faces themselves when they are no bigger or not a 1-to-4 hierarchy.
 */
export function shadowFaces(faces, depths, { maxTriangles = 200_000 } = {}) {
  if (!depths || depths.length === 0) return faces;
  let depth = 0;
  for (let i = 0; i < depths.length; i++) if (depths[i] > depth) depth = depths[i];
  let current = faces;
  while (current.length / 3 > maxTriangles && depth > 0) {
    const up = oneLevelUp(current, depths, depth);
    if (!up) break;
    current = up;
    depth--;
  }
  return current;
}
