// Quad remeshing (issue 16): a closed manifold triangle mesh to a semi-regular quad mesh with n
// Catmull-Clark levels. The triangle remesher (lib/remesh.mjs) gives a fitted semi-regular
// triangle mesh; its base triangles are split into three quads each (centroid and edge midpoints:
// the Catmull-Clark topology of a triangle mesh), that quad base is subdivided n times by
// Catmull-Clark, and every vertex is moved to the closest point of the fitted triangle surface
// (BVH from three-mesh-bvh). Reports the vertices' largest distance to the input and the volume
// change (bilinear patches against the input's triangles).
import { BufferAttribute, BufferGeometry, Vector3 } from 'three';
import { MeshBVH } from 'three-mesh-bvh';
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
  // The triangle remesh with one level more than the quads' finest needs of it (its fine mesh is the surface fitted to).
  const tri = await remesh(mrvol, input, { ...options, levels: Math.max(1, levels) });
  const mr = mrvol.openMesh(tri.mesh);
  let baseTriangles;
  try {
    baseTriangles = mr.levelFaces(0);
  } finally {
    mr.delete();
  }
  const onSurface = closestOn(tri.mesh);
  const fine = tri.mesh.positions;
  // Quad base: base vertices (renumbered), triangle centroids, edge midpoints, all on the surface.
  const index = new Map(), positions = [], quads = [];
  const put = (x, y, z) => {
    const h = onSurface(x, y, z);
    positions.push(h ? h.point.x : x, h ? h.point.y : y, h ? h.point.z : z);
    return positions.length / 3 - 1;
  };
  const vertex = (v) => {
    if (!index.has(`v${v}`)) index.set(`v${v}`, put(fine[3 * v], fine[3 * v + 1], fine[3 * v + 2]));
    return index.get(`v${v}`);
  };
  const midpoint = (a, b) => {
    const key = a < b ? `e${a},${b}` : `e${b},${a}`;
    if (!index.has(key))
      index.set(key, put((fine[3 * a] + fine[3 * b]) / 2, (fine[3 * a + 1] + fine[3 * b + 1]) / 2, (fine[3 * a + 2] + fine[3 * b + 2]) / 2));
    return index.get(key);
  };
  for (let f = 0; f < baseTriangles.length; f += 3) {
    const [a, b, c] = [baseTriangles[f], baseTriangles[f + 1], baseTriangles[f + 2]];
    const centre = put(...[0, 1, 2].map((k) => (fine[3 * a + k] + fine[3 * b + k] + fine[3 * c + k]) / 3));
    const ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
    quads.push(vertex(a), ab, centre, ca, vertex(b), bc, centre, ab, vertex(c), ca, centre, bc);
  }
  const base = { positions: Float64Array.from(positions), quads: Uint32Array.from(quads) };
  // Catmull-Clark subdivision, then every vertex onto the surface.
  const split = mrvol.subdivideQuads(base, { levels });
  let mesh;
  try {
    mesh = split.toMesh();
  } finally {
    split.delete();
  }
  const p = mesh.positions;
  for (let v = 0; v < p.length / 3; v++) {
    const h = onSurface(p[3 * v], p[3 * v + 1], p[3 * v + 2]);
    if (h) p[3 * v] = h.point.x, p[3 * v + 1] = h.point.y, p[3 * v + 2] = h.point.z;
  }
  // Distance of the result's vertices to the input surface.
  const onInput = closestOn(input);
  let farthest = 0;
  for (let v = 0; v < p.length / 3; v++) farthest = Math.max(farthest, onInput(p[3 * v], p[3 * v + 1], p[3 * v + 2])?.distance ?? 0);
  const volume = mrvol.quadVolume(mesh);
  return {
    mesh,
    levels,
    baseVertices: base.positions.length / 3,
    baseFaces: base.quads.length / 4,
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
