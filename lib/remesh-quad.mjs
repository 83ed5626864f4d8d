// Quad remeshing (issue 16): a closed manifold triangle mesh to a semi-regular quad mesh with n
// Catmull-Clark levels. The triangle remesher (lib/remesh.mjs) gives a fitted semi-regular
// triangle mesh with n levels: a piecewise-linear map of each base triangle, split 1-to-4 n times.
// Its base triangles are split into three quads each (centroid and edge midpoints: the
// Catmull-Clark topology of a triangle mesh), those are split n times (edge and face points), and
// every quad vertex is placed through that map: at its point of the base triangle (barycentric,
// the mean of its parents'), on the fitted surface. The quads follow the fit's parametrisation, so
// they keep its creases and do not jump between close sheets (a pipe's inner and outer walls, which
// projecting Catmull-Clark positions onto the nearest surface did: -14% of the pipe's volume).
// Reports the vertices' largest distance to the input and the volume change (bilinear patches
// against the input's triangles).
import { BufferAttribute, BufferGeometry, Vector3 } from 'three';
import { MeshBVH } from 'three-mesh-bvh';
import { edgeKey } from './connectivity.mjs';
import { boundingDiagonal } from './geometry.mjs';
import { closestPointQuery, remesh } from './remesh.mjs';

function closestOn(mesh) {
  const geometry = new BufferGeometry();
  geometry.setAttribute('position', new BufferAttribute(Float32Array.from(mesh.positions), 3));
  geometry.setIndex(new BufferAttribute(Uint32Array.from(mesh.faces), 1));
  const hit = { point: new Vector3(), distance: 0, faceIndex: 0 };
  const query = closestPointQuery(new MeshBVH(geometry), hit);
  return (x, y, z) => query(x, y, z, Infinity);
}

const pairKey = (a, b) => (a < b ? edgeKey(a, b) : edgeKey(b, a));

/**
 * The fitted triangle mesh as a map of its base: point(a, b, c, α, β, γ) is the point of base
 * triangle (a, b, c) at barycentric (α, β, γ) on the level-`levels` mesh (its vertices' positions
 * interpolated in the fine triangle that holds it). Each child's parents come from the level faces.
 */
function baseMap(mr, positions, levels) {
  const depths = mr.depths();
  const children = new Map(); // parent pair -> the vertex born on that edge
  for (let level = 1; level <= levels; level++) {
    const faces = mr.levelFaces(level), parents = new Map();
    for (let f = 0; f < faces.length; f += 3)
      for (let j = 0; j < 3; j++) {
        const v = faces[f + j];
        if (depths[v] !== level) continue;
        if (!parents.has(v)) parents.set(v, new Set());
        for (let k = 1; k < 3; k++) if (depths[faces[f + (j + k) % 3]] < level) parents.get(v).add(faces[f + (j + k) % 3]);
      }
    for (const [v, pair] of parents) {
      if (pair.size !== 2) throw new Error(`remeshQuads: vertex ${v} of level ${level} has ${pair.size} parents, not 2`);
      const [a, b] = pair;
      children.set(pairKey(a, b), v);
    }
  }
  const child = (a, b) => children.get(pairKey(a, b));
  return (a, b, c, x, y, z) => {
    for (let level = 0; level < levels; level++) {
      const ab = child(a, b), bc = child(b, c), ca = child(c, a);
      if (x >= 0.5) [b, c, x, y, z] = [ab, ca, 2 * x - 1, 2 * y, 2 * z];
      else if (y >= 0.5) [a, c, x, y, z] = [ab, bc, 2 * x, 2 * y - 1, 2 * z];
      else if (z >= 0.5) [a, b, x, y, z] = [ca, bc, 2 * x, 2 * y, 2 * z - 1];
      else [a, b, c, x, y, z] = [bc, ca, ab, 1 - 2 * x, 1 - 2 * y, 1 - 2 * z];
    }
    return [0, 1, 2].map((k) => x * positions[3 * a + k] + y * positions[3 * b + k] + z * positions[3 * c + k]);
  };
}

/**
 * @param {object} mrvol the API object of createMrvol()
 * @param {{ positions: Float64Array, faces: Uint32Array }} input a closed manifold triangle mesh
 * @param {object} [options] levels (Catmull-Clark levels, 0..5, default 2) and the triangle
 *   remesher's options (baseFaces, keepLargest, repair, maxHoleEdges, smooth, onProgress)
 * @returns {Promise<object>} { mesh: { positions, quads }, levels, baseVertices, baseFaces, vertices, faces,
 *   distanceToInput (largest vertex distance / bounding-box diagonal), volumeInput, volume, volumeChange, ms }
 */
export async function remeshQuads(mrvol, input, options = {}) {
  const { MrvolError } = mrvol;
  const started = performance.now();
  const levels = options.levels ?? 2;
  if (!Number.isInteger(levels) || levels < 0 || levels > 5) throw new MrvolError(`levels must be an integer in 0..5, got ${levels}`);
  // The triangle remesh with as many levels as the quads (at least 1: the quads' edge points are its level-1 vertices).
  const tri = await remesh(mrvol, input, { ...options, levels: Math.max(1, levels) });
  const mr = mrvol.openMesh(tri.mesh);
  let baseTriangles, point;
  try {
    baseTriangles = mr.levelFaces(0);
    point = baseMap(mr, tri.mesh.positions, tri.levels);
  } finally {
    mr.delete();
  }
  // Each quad vertex as a point of a base triangle: (a, b, c) and its barycentric weights. One on a
  // base edge is the same point from either triangle (its weight on the third corner is 0).
  const where = [];  // per quad vertex: [a, b, c, α, β, γ]
  const index = new Map();
  const vertexAt = (key, at) => {
    if (!index.has(key)) index.set(key, where.push(at) - 1);
    return index.get(key);
  };
  const inside = (w) => (w[3] > 0) + (w[4] > 0) + (w[5] > 0);
  const mean = (ids) => {
    // in the triangle of the parent most inside one (a quad's face point is inside its base triangle;
    // the parents on a base edge may be kept with the triangle across it)
    const [a, b, c] = ids.map((id) => where[id]).reduce((x, y) => (inside(y) > inside(x) ? y : x)), weight = [0, 0, 0];
    for (const id of ids) {
      const w = where[id];
      for (let j = 0; j < 3; j++) {
        if (w[3 + j] === 0) continue;
        const k = w[j] === a ? 0 : w[j] === b ? 1 : w[j] === c ? 2 : -1;
        if (k < 0) throw new Error('remeshQuads: a quad across two base triangles');
        weight[k] += w[3 + j] / ids.length;
      }
    }
    return [a, b, c, ...weight];
  };
  // Quad base: base vertices, edge midpoints, triangle centroids.
  let quads = [];
  for (let f = 0; f < baseTriangles.length; f += 3) {
    const [a, b, c] = [baseTriangles[f], baseTriangles[f + 1], baseTriangles[f + 2]];
    const corner = (v) => vertexAt(`v${v}`, [a, b, c, v === a ? 1 : 0, v === b ? 1 : 0, v === c ? 1 : 0]);
    const edge = (u, v) => vertexAt(`e${pairKey(u, v)}`, [a, b, c, ...[a, b, c].map((x) => (x === u || x === v ? 0.5 : 0))]);
    const centre = vertexAt(`f${f}`, [a, b, c, 1 / 3, 1 / 3, 1 / 3]);
    const ab = edge(a, b), bc = edge(b, c), ca = edge(c, a);
    quads.push(corner(a), ab, centre, ca, corner(b), bc, centre, ab, corner(c), ca, centre, bc);
  }
  const baseVertices = where.length, baseFaces = quads.length / 4;
  // n splits: edge points and face points, each at the mean of its parents' base points (the same
  // base triangle: a quad lies in one).
  for (let level = 0; level < levels; level++) {
    const next = [];
    for (let q = 0; q < quads.length; q += 4) {
      const p = quads.slice(q, q + 4);
      const centre = vertexAt(`q${level},${q}`, mean(p));
      const e = [0, 1, 2, 3].map((i) => vertexAt(`e${level},${pairKey(p[i], p[(i + 1) % 4])}`, mean([p[i], p[(i + 1) % 4]])));
      for (let i = 0; i < 4; i++) next.push(p[i], e[i], centre, e[(i + 3) % 4]);
    }
    quads = next;
  }
  const p = new Float64Array(3 * where.length);
  where.forEach((w, v) => p.set(point(...w), 3 * v));
  const mesh = { positions: p, quads: Uint32Array.from(quads) };
  // Distance of the result's vertices to the input surface.
  const onInput = closestOn(input);
  let farthest = 0;
  for (let v = 0; v < p.length / 3; v++) farthest = Math.max(farthest, onInput(p[3 * v], p[3 * v + 1], p[3 * v + 2])?.distance ?? 0);
  const volume = mrvol.quadVolume(mesh);
  return {
    mesh,
    levels,
    baseVertices,
    baseFaces,
    vertices: p.length / 3,
    faces: mesh.quads.length / 4,
    distanceToInput: farthest / boundingDiagonal(input.positions),
    volumeInput: tri.volumeInput,
    volume,
    volumeChange: (volume - tri.volumeInput) / tri.volumeInput,
    triangleRemesh: { baseFaces: tri.baseFaces, hausdorff: tri.hausdorff },
    // What the triangle remesh read, repaired and kept (the pieces), as its report says.
    components: tri.components,
    input: tri.input,
    repair: tri.repair,
    ms: performance.now() - started,
  };
}
