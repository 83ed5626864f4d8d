// Sharp features of a closed triangle mesh for the remesher (lib/remesh.mjs): feature edges (the
// dihedral angle between the two faces over a threshold), cut into lines at corners (vertices
// with one or more than two feature edges, or where a line turns sharply). The fit keeps corners
// where they are and slides the vertices born on a line along that line (closest point on its
// segments), so that a CAD part's edges stay sharp.
import { connectivity, edgeKey } from './connectivity.mjs';
import { boundingDiagonal, hypot3, triangleNormal } from './geometry.mjs';

/**
 * @param {{ positions: Float64Array, faces: Uint32Array }} mesh welded, closed, manifold
 * @param {{ angle?: number, maxFraction?: number, turn?: number }} options angle: dihedral
 *   threshold in degrees (default 35); maxFraction: more feature edges than this fraction of all
 *   edges of a mesh of more than 3000 edges is noise (a scan), not features: none kept (default 0.05); turn: a line turning by more
 *   than this many degrees at a vertex has a corner there (default 40); minLength: lines shorter
 *   than this fraction of the bounding-box diagonal are dropped (default 0.03).
 * @returns {Features}
 */
export function findFeatures(mesh, { angle = 35, maxFraction = 0.05, turn = 40, minLength = 0.03 } = {}) {
  const { positions: p, faces } = mesh;
  const vertexCount = p.length / 3, faceCount = faces.length / 3;
  const normals = new Float64Array(faces.length);
  for (let f = 0; f < faceCount; f++) {
    const n = triangleNormal(p, faces[3 * f], faces[3 * f + 1], faces[3 * f + 2]);
    const l = hypot3(n[0], n[1], n[2]) || 1;
    for (let k = 0; k < 3; k++) normals[3 * f + k] = n[k] / l;
  }
  const twins = connectivity(faces, vertexCount).twins;
  const cosine = Math.cos((angle * Math.PI) / 180);
  let edges = [];
  for (let f = 0; f < faceCount; f++)
    for (let j = 0; j < 3; j++) {
      const g = twins[3 * f + j], a = faces[3 * f + j], b = faces[3 * f + (j + 1) % 3];
      if (g < 0 || a > b) continue;  // each interior edge once
      const c = normals[3 * f] * normals[3 * g] + normals[3 * f + 1] * normals[3 * g + 1] + normals[3 * f + 2] * normals[3 * g + 2];
      if (c < cosine) edges.push(a, b);
    }
  const totalEdges = faces.length / 2;
  if (edges.length / 2 > maxFraction * totalEdges && totalEdges > 3000) return new Features(p, [], vertexCount, edges.length / 2);
  // Lines shorter than `minLength` of the diagonal are bumps, not creases: dropped, then the
  // spurs they leave, until none is left.
  const found = edges.length / 2, limit = minLength * boundingDiagonal(p);
  let features;
  for (let round = 0; round < 4; round++) {
    pruneDanglingEdges(edges);
    features = new Features(p, edges, vertexCount, 0, Math.cos((turn * Math.PI) / 180));
    const short = new Set();
    features.lines.forEach((s, id) => {
      let length = 0;
      for (let i = 0; i < s.length; i += 6) length += hypot3(s[i + 3] - s[i], s[i + 4] - s[i + 1], s[i + 5] - s[i + 2]);
      if (length < limit) short.add(id);
    });
    if (short.size === 0) break;
    const kept = [];
    for (let e = 0; e < edges.length; e += 2) if (!short.has(features.lineOfEdge.get(edgeKey(Math.min(edges[e], edges[e + 1]), Math.max(edges[e], edges[e + 1]))))) kept.push(edges[e], edges[e + 1]);
    edges = kept;
  }
  features.noisyEdges = found - features.edgeCount;
  return features;
}

/**
 * Drops feature edges that end nowhere (at a vertex with no other feature edge), repeatedly: a
 * part's creases end at corners where three or more meet, or close on themselves; the bumps of a
 * scan or an organic shape that pass the angle test are short spurs. In place (edges is a flat
 * array of vertex pairs; dropped pairs removed).
 */
function pruneDanglingEdges(edges) {
  const degree = new Map(), alive = new Uint8Array(edges.length / 2).fill(1);
  const at = new Map();
  for (let e = 0; e < edges.length / 2; e++)
    for (const v of [edges[2 * e], edges[2 * e + 1]]) {
      degree.set(v, (degree.get(v) ?? 0) + 1);
      if (!at.has(v)) at.set(v, []);
      at.get(v).push(e);
    }
  const queue = [...degree].filter(([, d]) => d === 1).map(([v]) => v);
  while (queue.length) {
    const v = queue.pop();
    for (const e of at.get(v)) {
      if (!alive[e]) continue;
      alive[e] = 0;
      for (const w of [edges[2 * e], edges[2 * e + 1]]) {
        degree.set(w, degree.get(w) - 1);
        if (degree.get(w) === 1) queue.push(w);
      }
    }
  }
  let n = 0;
  for (let e = 0; e < alive.length; e++) if (alive[e]) edges[2 * n] = edges[2 * e], edges[2 * n + 1] = edges[2 * e + 1], n++;
  edges.length = 2 * n;
}

export class Features {
  constructor(positions, edges, vertexCount, noisyEdges = 0, turnCosine = 0.77) {
    this.positions = positions;
    this.noisyEdges = noisyEdges;
    this.edgeCount = edges.length / 2;
    // Feature neighbours of each vertex.
    const around = new Map();
    for (let e = 0; e < edges.length; e += 2) {
      const a = edges[e], b = edges[e + 1];
      if (!around.has(a)) around.set(a, []);
      if (!around.has(b)) around.set(b, []);
      around.get(a).push(b);
      around.get(b).push(a);
    }
    const corner = new Set();
    for (const [v, list] of around) {
      if (list.length !== 2) {
        corner.add(v);
        continue;
      }
      const d = list.map((w) => [0, 1, 2].map((k) => positions[3 * w + k] - positions[3 * v + k]));
      const l0 = Math.hypot(...d[0]), l1 = Math.hypot(...d[1]);
      // Straight on: the two edges point opposite ways (cosine -1).
      const c = (d[0][0] * d[1][0] + d[0][1] * d[1][1] + d[0][2] * d[1][2]) / (l0 * l1 || 1);
      if (-c < turnCosine) corner.add(v);
    }
    this.corners = corner;
    // Lines: chains of feature edges between corners (or closed loops), each a list of segments.
    const lineOfEdge = (this.lineOfEdge = new Map());
    this.lines = [];
    /** Lines through each feature vertex (one; several at a corner). */
    this.linesAt = new Map();
    const addAt = (v, id) => {
      const list = this.linesAt.get(v);
      if (!list) this.linesAt.set(v, [id]);
      else if (!list.includes(id)) list.push(id);
    };
    const walk = (start, next) => {
      const id = this.lines.length, segments = [];
      let a = start, b = next;
      for (;;) {
        const key = edgeKey(Math.min(a, b), Math.max(a, b));
        if (lineOfEdge.has(key)) break;
        lineOfEdge.set(key, id);
        segments.push(a, b);
        addAt(a, id), addAt(b, id);
        if (corner.has(b)) break;
        const [x, y] = around.get(b);
        const c = x === a ? y : x;
        a = b, b = c;
      }
      this.lines.push(Float64Array.from(segments.flatMap((v) => [positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]])));
    };
    for (const v of corner) for (const w of around.get(v)) if (!lineOfEdge.has(edgeKey(Math.min(v, w), Math.max(v, w)))) walk(v, w);
    for (const [v, list] of around) for (const w of list) if (!lineOfEdge.has(edgeKey(Math.min(v, w), Math.max(v, w)))) walk(v, w);
  }

  /** Closest point to (x, y, z) on line `id`: [x, y, z, distance, arc length from the line's start]. */
  projectToLine(id, x, y, z) {
    const s = this.lines[id];
    let best = Infinity, bx = x, by = y, bz = z, arc = 0, walked = 0;
    for (let i = 0; i < s.length; i += 6) {
      const ax = s[i], ay = s[i + 1], az = s[i + 2], ux = s[i + 3] - ax, uy = s[i + 4] - ay, uz = s[i + 5] - az;
      const uu = ux * ux + uy * uy + uz * uz;
      const t = uu > 0 ? Math.max(0, Math.min(1, ((x - ax) * ux + (y - ay) * uy + (z - az) * uz) / uu)) : 0;
      const qx = ax + t * ux, qy = ay + t * uy, qz = az + t * uz;
      const d = (qx - x) ** 2 + (qy - y) ** 2 + (qz - z) ** 2, length = Math.sqrt(uu);
      if (d < best) best = d, bx = qx, by = qy, bz = qz, arc = walked + t * length;
      walked += length;
    }
    return [bx, by, bz, Math.sqrt(best), arc];
  }

  /** Whether arc position c lies between a and b on line id (the shorter way round a closed line). */
  between(id, a, b, c) {
    const s = this.lines[id], n = s.length;
    let total = 0;
    for (let i = 0; i < n; i += 6) total += hypot3(s[i + 3] - s[i], s[i + 4] - s[i + 1], s[i + 5] - s[i + 2]);
    const closed = s[0] === s[n - 3] && s[1] === s[n - 2] && s[2] === s[n - 1];
    const d = (x, y) => (closed ? Math.min(Math.abs(x - y), total - Math.abs(x - y)) : Math.abs(x - y));
    return d(a, c) + d(c, b) <= d(a, b) + 1e-9 * total && d(a, c) > 1e-12 * total && d(c, b) > 1e-12 * total;
  }
}

/**
 * Constraints of the vertices of a subdivided base mesh: `kind` 0 free, 1 on a line (`line` its
 * id), 2 a corner (held). A base vertex is a corner or on a line if it sits on an input corner or
 * feature vertex (looked up by exact position: the simplifier keeps input vertices); a vertex born
 * on the edge between two parents is on a line if both parents are on it (a corner is on all its
 * lines) and the edge's midpoint lies within a tenth of the edge's length of that line. Vertices
 * can also be held where they are (`hold`: kind 2 without lines).
 */
export class Constraints {
  constructor(features, vertexCount) {
    this.features = features;
    this.kind = new Uint8Array(vertexCount);
    this.line = new Int32Array(vertexCount).fill(-1);
    this.linesOf = new Map();
    this.count = 0;
    this.corners = 0;
    this.byPosition = new Map();
    if (!features) return;
    const input = features.positions;
    for (const v of features.linesAt.keys()) this.byPosition.set(`${input[3 * v]},${input[3 * v + 1]},${input[3 * v + 2]}`, v);
  }

  /** Base vertex m at its (input) position. */
  assignBase(positions, m) {
    if (!this.features || this.features.edgeCount === 0) return;
    const v = this.byPosition.get(`${positions[3 * m]},${positions[3 * m + 1]},${positions[3 * m + 2]}`);
    if (v === undefined) return;
    const lines = this.features.linesAt.get(v);
    this.linesOf.set(m, lines);
    if (this.features.corners.has(v)) this.kind[m] = 2, this.corners++;
    else this.kind[m] = 1, this.line[m] = lines[0];
    this.count++;
  }

  /**
   * Vertex m born on the edge a-b (`opposite`: the vertices facing that edge): if on a line, placed
   * on it (closest point to the midpoint); returns whether. An edge that skips a vertex of the same
   * line (a triangle with its three corners on the line) cuts across: not on it.
   */
  assignChild(positions, m, a, b, opposite = []) {
    const la = this.linesOf.get(a), lb = this.linesOf.get(b);
    if (!la || !lb) return false;
    const mx = (positions[3 * a] + positions[3 * b]) / 2, my = (positions[3 * a + 1] + positions[3 * b + 1]) / 2,
          mz = (positions[3 * a + 2] + positions[3 * b + 2]) / 2;
    const length = hypot3(positions[3 * a] - positions[3 * b], positions[3 * a + 1] - positions[3 * b + 1], positions[3 * a + 2] - positions[3 * b + 2]);
    for (const id of la) {
      if (!lb.includes(id)) continue;
      const q = this.features.projectToLine(id, mx, my, mz);
      if (q[3] > length / 10) continue;
      const arc = (v) => this.features.projectToLine(id, positions[3 * v], positions[3 * v + 1], positions[3 * v + 2])[4];
      if (opposite.some((c) => this.onLine(c, id) && this.features.between(id, arc(a), arc(b), arc(c)))) continue;
      this.kind[m] = 1, this.line[m] = id;
      positions[3 * m] = q[0], positions[3 * m + 1] = q[1], positions[3 * m + 2] = q[2];
      this.linesOf.set(m, [id]);
      this.count++;
      return true;
    }
    return false;
  }

  /** Whether vertex w lies on line id (on it, or a corner of it). */
  onLine(w, id) {
    return (this.kind[w] === 1 && this.line[w] === id) || (this.kind[w] === 2 && !!this.linesOf.get(w)?.includes(id));
  }

  /** Vertex m stays where it is. */
  hold(m) {
    this.kind[m] = 2;
  }
}
