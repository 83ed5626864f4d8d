// three-mesh-bvh 0.9.17's build (src/core/build/*.js and MeshBVH.computePrimitiveBounds) for the
// default options, step for step: JS numbers are doubles and its Float32Arrays round on store, so
// the arithmetic here is in double and every value JS keeps in a Float32Array goes through float.
#include "mrvol/packed_bvh.h"

#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "mrvol/error.h"

namespace mrvol {
namespace {

constexpr int kTargetLeafSize = 10;
constexpr int kMaxDepth = 40;
constexpr double kFloat32Epsilon = 5.9604644775390625e-8;  // 2^-24 (FLOAT32_EPSILON)

uint32_t bitsOf(float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}

struct Builder {
  // Per triangle (in the order the partition leaves them): center and half extent per axis, as floats.
  std::vector<float> bounds;
  std::vector<uint32_t>& index;
  std::vector<uint32_t> nodes;
  size_t nodeCount = 0;
  float nodeBounds[6];
  float centroidBounds[6];

  // getBounds: the union of the triangles' boxes and of their centers over [offset, offset + count).
  void getBounds(size_t offset, size_t count) {
    const double inf = std::numeric_limits<double>::infinity();
    double mn[3] = {inf, inf, inf}, mx[3] = {-inf, -inf, -inf}, cmn[3] = {inf, inf, inf}, cmx[3] = {-inf, -inf, -inf};
    for (size_t i = offset * 6, end = (offset + count) * 6; i < end; i += 6)
      for (int d = 0; d < 3; d++) {
        const double c = bounds[i + 2 * d], h = bounds[i + 2 * d + 1];
        const double l = c - h, r = c + h;
        if (l < mn[d]) mn[d] = l;
        if (r > mx[d]) mx[d] = r;
        if (c < cmn[d]) cmn[d] = c;
        if (c > cmx[d]) cmx[d] = c;
      }
    for (int d = 0; d < 3; d++) {
      nodeBounds[d] = static_cast<float>(mn[d]), nodeBounds[d + 3] = static_cast<float>(mx[d]);
      centroidBounds[d] = static_cast<float>(cmn[d]), centroidBounds[d + 3] = static_cast<float>(cmx[d]);
    }
  }

  // getLongestEdgeIndex (the first axis of the largest extent; -1 if none is > -Infinity, e.g. NaN).
  static int longestAxis(const float* b) {
    int axis = -1;
    double longest = -std::numeric_limits<double>::infinity();
    for (int i = 0; i < 3; i++) {
      const double d = static_cast<double>(b[i + 3]) - static_cast<double>(b[i]);
      if (d > longest) longest = d, axis = i;
    }
    return axis;
  }

  // Hoare partition on the centers along `axis` at `pos` (a center on the plane goes right).
  size_t partition(size_t offset, size_t count, int axis, double pos) {
    size_t left = offset;
    // (right may go one below offset: signed.)
    long long right = static_cast<long long>(offset + count) - 1;
    const int a = 2 * axis;
    for (;;) {
      while (static_cast<long long>(left) <= right && static_cast<double>(bounds[left * 6 + a]) < pos) left++;
      while (static_cast<long long>(left) <= right && static_cast<double>(bounds[static_cast<size_t>(right) * 6 + a]) >= pos) right--;
      if (static_cast<long long>(left) < right) {
        const size_t r = static_cast<size_t>(right);
        for (int i = 0; i < 3; i++) std::swap(index[left * 3 + i], index[r * 3 + i]);
        for (int i = 0; i < 6; i++) std::swap(bounds[left * 6 + i], bounds[r * 6 + i]);
        left++, right--;
      } else {
        return left;
      }
    }
  }

  void writeLeaf(size_t node, size_t offset, size_t count) {
    nodes[node * 8 + 6] = static_cast<uint32_t>(offset);
    nodes[node * 8 + 7] = static_cast<uint32_t>(count & 0xffff) | (0xffffu << 16);
  }

  // splitNode: writes the node whose box is in nodeBounds, then its children depth first.
  void split(size_t offset, size_t count, int depth) {
    const size_t node = nodeCount++;
    for (int k = 0; k < 6; k++) nodes[node * 8 + k] = bitsOf(nodeBounds[k]);
    if (count <= static_cast<size_t>(kTargetLeafSize) || depth >= kMaxDepth) return writeLeaf(node, offset, count);
    const int axis = longestAxis(centroidBounds);
    size_t at = 0;
    if (axis != -1) {
      const double pos = (static_cast<double>(centroidBounds[axis]) + static_cast<double>(centroidBounds[axis + 3])) / 2;
      at = partition(offset, count, axis, pos);
    }
    if (axis == -1 || at == offset || at == offset + count) return writeLeaf(node, offset, count);
    nodes[node * 8 + 7] = static_cast<uint32_t>(axis);
    const size_t leftCount = at - offset;
    getBounds(offset, leftCount);
    split(offset, leftCount, depth + 1);
    nodes[node * 8 + 6] = static_cast<uint32_t>(nodeCount - node);
    getBounds(at, count - leftCount);
    split(at, count - leftCount, depth + 1);
  }
};

}  // namespace

std::vector<uint32_t> buildPackedBvh(const std::vector<float>& positions, std::vector<uint32_t>& index) {
  if (index.size() % 3 != 0) throw Error("packed BVH: the index holds " + std::to_string(index.size()) + " numbers, not 3 per triangle");
  const size_t vertexCount = positions.size() / 3, triangleCount = index.size() / 3;
  for (size_t i = 0; i < index.size(); i++)
    if (index[i] >= vertexCount)
      throw Error("packed BVH: triangle " + std::to_string(i / 3) + " names vertex " + std::to_string(index[i]) + " of " +
                  std::to_string(vertexCount));
  Builder b{std::vector<float>(6 * triangleCount), index, {}, 0, {}, {}};
  // computePrimitiveBounds: per axis the center and the half extent grown by float32 epsilon.
  for (size_t t = 0; t < triangleCount; t++)
    for (int el = 0; el < 3; el++) {
      const double a = positions[3 * index[3 * t] + el], bb = positions[3 * index[3 * t + 1] + el], c = positions[3 * index[3 * t + 2] + el];
      double mn = a, mx = a;
      if (bb < mn) mn = bb;
      if (c < mn) mn = c;
      if (bb > mx) mx = bb;
      if (c > mx) mx = c;
      const double half = (mx - mn) / 2;
      b.bounds[6 * t + 2 * el] = static_cast<float>(mn + half);
      b.bounds[6 * t + 2 * el + 1] = static_cast<float>(half + (std::fabs(mn) + half) * kFloat32Epsilon);
    }
  // At most 2n - 1 nodes (one for an empty mesh, as three-mesh-bvh allocates).
  b.nodes.assign(8 * (triangleCount > 0 ? 2 * triangleCount - 1 : 1), 0);
  b.getBounds(0, triangleCount);
  b.split(0, triangleCount, 0);
  b.nodes.resize(8 * b.nodeCount);
  return b.nodes;
}

}  // namespace mrvol
