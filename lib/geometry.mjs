// Small geometry helpers shared by the remesher and the repair stage (flat Float64Array positions,
// 3 per vertex; flat face arrays, 3 vertex indices per face).

/**
 * Math.hypot(x, y, z) bit for bit (V8's steps: the largest magnitude scales the three, whose
 * squares are summed with Kahan's compensation in argument order), several times faster than the
 * builtin (its variadic call was a sixth of the remesher's time).
 */
export function hypot3(x, y, z) {
  const ax = Math.abs(x), ay = Math.abs(y), az = Math.abs(z);
  if (ax === Infinity || ay === Infinity || az === Infinity) return Infinity;
  if (ax !== ax || ay !== ay || az !== az) return NaN;
  const max = Math.max(ax, ay, az);
  if (max === 0) return 0;
  // (The first square is summed exactly: the compensation stays 0.)
  let n = ax / max, sum = n * n;
  n = ay / max;
  let summand = n * n, next = sum + summand;
  const compensation = next - sum - summand;
  sum = next;
  n = az / max;
  summand = n * n - compensation;
  sum += summand;
  return Math.sqrt(sum) * max;
}

/** Length of the diagonal of the axis-aligned bounding box. */
export function boundingDiagonal(positions) {
  const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i < positions.length; i += 3)
    for (let k = 0; k < 3; k++) {
      lo[k] = Math.min(lo[k], positions[i + k]);
      hi[k] = Math.max(hi[k], positions[i + k]);
    }
  return hypot3(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
}

/** Normal of the triangle a, b, c (not normalized: twice its area long). */
export function triangleNormal(p, a, b, c) {
  const ux = p[3 * b] - p[3 * a], uy = p[3 * b + 1] - p[3 * a + 1], uz = p[3 * b + 2] - p[3 * a + 2];
  const vx = p[3 * c] - p[3 * a], vy = p[3 * c + 1] - p[3 * a + 1], vz = p[3 * c + 2] - p[3 * a + 2];
  return [uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx];
}

/**
 * Unit normal of the triangle a, b, c written to out[0..2] (triangleNormal's arithmetic, divided
 * by its length; zero for a degenerate triangle), without an array per call.
 */
export function unitTriangleNormal(p, a, b, c, out) {
  const ux = p[3 * b] - p[3 * a], uy = p[3 * b + 1] - p[3 * a + 1], uz = p[3 * b + 2] - p[3 * a + 2];
  const vx = p[3 * c] - p[3 * a], vy = p[3 * c + 1] - p[3 * a + 1], vz = p[3 * c + 2] - p[3 * a + 2];
  const x = uy * vz - uz * vy, y = uz * vx - ux * vz, z = ux * vy - uy * vx;
  const l = hypot3(x, y, z);
  out[0] = l > 0 ? x / l : 0, out[1] = l > 0 ? y / l : 0, out[2] = l > 0 ? z / l : 0;
  return out;
}

/** Area-weighted vertex normals, unit length. */
export function vertexNormals(positions, faces) {
  const n = new Float64Array(positions.length), p = positions;
  for (let f = 0; f < faces.length; f += 3) {
    // triangleNormal's arithmetic, without an array per face.
    const a = 3 * faces[f], b = 3 * faces[f + 1], c = 3 * faces[f + 2];
    const ux = p[b] - p[a], uy = p[b + 1] - p[a + 1], uz = p[b + 2] - p[a + 2];
    const vx = p[c] - p[a], vy = p[c + 1] - p[a + 1], vz = p[c + 2] - p[a + 2];
    const tx = uy * vz - uz * vy, ty = uz * vx - ux * vz, tz = ux * vy - uy * vx;
    n[a] += tx, n[a + 1] += ty, n[a + 2] += tz;
    n[b] += tx, n[b + 1] += ty, n[b + 2] += tz;
    n[c] += tx, n[c + 1] += ty, n[c + 2] += tz;
  }
  for (let i = 0; i < n.length; i += 3) {
    const l = hypot3(n[i], n[i + 1], n[i + 2]) || 1;
    n[i] /= l, n[i + 1] /= l, n[i + 2] /= l;
  }
  return n;
}

/** Meshes side by side in one (vertices and faces appended in order). */
export function concatenate(meshes) {
  let vertexCount = 0, faceCount = 0;
  for (const m of meshes) vertexCount += m.positions.length / 3, faceCount += m.faces.length / 3;
  const positions = new Float64Array(3 * vertexCount), faces = new Uint32Array(3 * faceCount);
  let v = 0, f = 0;
  for (const m of meshes) {
    positions.set(m.positions, 3 * v);
    for (let i = 0; i < m.faces.length; i++) faces[3 * f + i] = m.faces[i] + v;
    v += m.positions.length / 3, f += m.faces.length / 3;
  }
  return { positions, faces };
}
