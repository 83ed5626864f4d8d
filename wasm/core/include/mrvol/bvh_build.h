// three-mesh-bvh's tree (0.9.x, MeshBVH with its defaults: CENTER splits, 10 triangles a leaf, depth
// 40, not indirect) built here, bit for bit: the same packed nodes and the same reordering of the
// index. The remesher builds a tree per surface it asks closest points of (tens per remesh; a
// tenth of its time in JS); lib/remesh.mjs hands the result to MeshBVH.deserialize, so raycasts,
// closest points (closest_points.h walks the same tree) and tie-breaking are that library's.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace mrvol {

// positions: float32, 3 per vertex; index: 3 vertex indices per triangle, reordered in place as
// three-mesh-bvh's build reorders it (checked first: in range, a whole number of triangles, at
// least one). Returns the packed nodes, 8 words each, as three-mesh-bvh's root buffer holds them:
// the box (6 float32: min xyz, max xyz), then for a leaf the first triangle (uint32) and its
// count (uint16) with 0xffff beside it, for an inner node the right child's offset from this
// node (uint32) and the split axis; the left child follows its parent.
std::vector<uint32_t> buildThreeMeshBvh(const std::vector<float>& positions, std::vector<uint32_t>& index);

}  // namespace mrvol
