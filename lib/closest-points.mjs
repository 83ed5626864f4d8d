// Closest points on a fixed triangle mesh, in the WASM core (wasm/core closest_points.h): a tree
// built once, then single queries (no allocation: the answer is written into the caller's array)
// and batches (threaded in the -pthread module). The queries talk through buffers in the module's
// memory (views of it made again when it grows).

// Frees the trees of the objects dropped without dispose() (a tree holds ~100 bytes per triangle).
const registry = new FinalizationRegistry((raw) => raw.delete());

/**
 * The closest-point tree of { positions: Float64Array, faces: Uint32Array } in `module` (the raw
 * embind module): the core's own, or `tree` ({ bounds: 6 per node, first, count: per node, as
 * closest_points.h says; e.g. three-mesh-bvh's }). Throws MrvolError (lib/api.mjs's, passed in)
 * for a bad mesh (an index out of range, a non-finite corner) or tree.
 */
export function createClosestPoints(module, mesh, MrvolError, tree = null) {
  const take = () => {
    const error = module._takeClosestPointsError();
    if (error) throw new MrvolError(error);
  };
  let raw = tree ? module._closestPointsWithTree(mesh.positions, mesh.faces, tree.bounds, tree.first, tree.count)
    : module._closestPoints(mesh.positions, mesh.faces);
  take();
  if (!raw) throw new MrvolError('closest points: the tree could not be built');
  const triangleCount = raw.triangleCount();
  let inAt = 0, outAt = 0, trianglesAt = 0;
  const locate = () => {
    inAt = raw.inAddress() / 8, outAt = raw.outAddress() / 8, trianglesAt = raw.trianglesAddress() / 4;
  };
  locate();
  // Views of the module's memory, made again when it has grown (in the -pthread module a worker
  // may grow it, leaving the module's own views short until its next call).
  let f64 = null, u32 = null;
  const views = () => {
    const buffer = module.wasmMemory?.buffer ?? module.HEAPF64.buffer;
    if (f64?.buffer !== buffer) f64 = new Float64Array(buffer), u32 = new Uint32Array(buffer);
  };
  const live = () => {
    if (!raw) throw new MrvolError('these closest points were disposed');
    return raw;
  };
  const closestPoints = {
    /** Triangles in the tree. */
    triangleCount,
    /**
     * The closest point of (x, y, z) written into `out` (5 numbers: x, y, z, distance, triangle
     * index as given). `maxDistance` (Infinity: none) prunes the walk: the closest point if it lies
     * within it; else false (out untouched), or the closest of the triangles in boxes that reach
     * within it (as three-mesh-bvh's closestPointToPoint).
     */
    closest(x, y, z, maxDistance, out) {
      const squared = live().one(x, y, z, maxDistance);
      if (squared < 0) return false;
      views();
      out[0] = f64[outAt], out[1] = f64[outAt + 1], out[2] = f64[outAt + 2], out[3] = Math.sqrt(squared);
      out[4] = u32[trianglesAt];
      return true;
    },
    /**
     * The closest points of n points (Float64Array, 3 each); `bounds` (n distances, optional) prune
     * the search (a point with nothing within its bound is searched again without it). Returns
     * { points (3 each), distances, triangles }.
     */
    closestMany(points, bounds = null) {
      const n = points.length / 3;
      if (!Number.isInteger(n)) throw new MrvolError('closestMany: points must hold 3 numbers per point');
      if (bounds && bounds.length !== n) throw new MrvolError(`closestMany: ${bounds.length} bounds for ${n} points`);
      const r = live();
      if (r.capacity() < n) {
        r.reserve(n);
        take();
        locate();
      }
      views();
      f64.set(points, inAt);
      if (bounds) f64.set(bounds, inAt + 3 * n);
      r.many(n, !!bounds);
      take();
      views();
      const distances = f64.slice(outAt + 3 * n, outAt + 4 * n);
      for (let i = 0; i < n; i++) distances[i] = Math.sqrt(distances[i]);
      return { points: f64.slice(outAt, outAt + 3 * n), distances, triangles: u32.slice(trianglesAt, trianglesAt + n) };
    },
    /**
     * The largest distance from the sample points of `other` (its vertices, then per face the
     * centroid and the points of weights (2/3, 1/6, 1/6) and rotations; every ceil(samples /
     * maxSamples)-th) to this mesh.
     */
    sampledDistanceFrom(other, maxSamples = 200000) {
      const d = live().sampledDistanceFrom(other.positions, other.faces, maxSamples);
      take();
      return d;
    },
    /** Frees the tree now (else when this object is collected). */
    dispose() {
      if (!raw) return;
      registry.unregister(closestPoints);
      raw.delete();
      raw = null;
    },
  };
  registry.register(closestPoints, raw, closestPoints);
  return closestPoints;
}
