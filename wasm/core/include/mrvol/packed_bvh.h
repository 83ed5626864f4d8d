// A bounding-volume hierarchy over a triangle mesh in three-mesh-bvh's packed layout, built as its
// 0.9.17 MeshBVH builds one with the default options (CENTER split of the centroids' longest axis,
// 10 triangles a leaf, depth 40): the same nodes and the same triangle order, bit for bit. The
// remesher raycasts that tree in JS (three-mesh-bvh, deserialized from these bytes) and walks it
// for closest points here (closest_points.h), so the two answer from one tree; the build in JS
// was a tenth of the remesher's time.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace mrvol {

/**
 * Builds the tree over `triangleCount` triangles of `index` (3 vertex indices each, into
 * `positions`: 3 floats a vertex) and reorders `index` by triangle as the build partitions them.
 * Returns the nodes, 8 words each: the box (6 floats: min x y z, max x y z), then for a leaf its
 * first triangle and (count | 0xffff << 16), for an inner node its right child's offset from it
 * (the left child follows it) and the split axis. Throws mrvol::Error for an index out of range.
 */
std::vector<uint32_t> buildPackedBvh(const std::vector<float>& positions, std::vector<uint32_t>& index);

}  // namespace mrvol
