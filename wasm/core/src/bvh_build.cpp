#include "mrvol/bvh_build.h"

#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "mrvol/error.h"

namespace mrvol {

namespace {

// three-mesh-bvh's constants (src/core/Constants.js): the default options, and the float32
// epsilon its triangle bounds are widened by.
constexpr size_t kTargetLeafSize = 10;
constexpr int kMaxDepth = 40;
const double kFloat32Epsilon = std::ldexp(1.0, -24);
constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Every step below is the library's JS: arithmetic in double, a store into a Float32Array rounds
// to float (a cast to float rounds the same way, to nearest, ties to even).
class Builder {
 public:
  Builder(const std::vector<float>& positions, std::vector<uint32_t>& index) : index_(index) {
    const size_t count = index.size() / 3;
    bounds_.resize(6 * count);
    // computePrimitiveBounds: per axis the centre and the half extent, widened by the epsilon.
    for (size_t t = 0; t < count; ++t)
      for (int k = 0; k < 3; ++k) {
        const double a = positions[3 * index[3 * t] + k], b = positions[3 * index[3 * t + 1] + k],
                     c = positions[3 * index[3 * t + 2] + k];
        double lo = a, hi = a;
        if (b < lo) lo = b;
        if (c < lo) lo = c;
        if (b > hi) hi = b;
        if (c > hi) hi = c;
        const double half = (hi - lo) / 2;
        bounds_[6 * t + 2 * k] = static_cast<float>(lo + half);
        bounds_[6 * t + 2 * k + 1] = static_cast<float>(half + (std::fabs(lo) + half) * kFloat32Epsilon);
      }
    nodes_.reserve(8 * (2 * count));
    getBounds(0, count);
    splitNode(0, count, 0);
  }

  std::vector<uint32_t> take() { return std::move(nodes_); }

 private:
  // getBounds: the union of the triangles' boxes and the box of their centres, as float32.
  void getBounds(size_t offset, size_t count) {
    double lo[3] = {kInfinity, kInfinity, kInfinity}, hi[3] = {-kInfinity, -kInfinity, -kInfinity};
    double clo[3] = {kInfinity, kInfinity, kInfinity}, chi[3] = {-kInfinity, -kInfinity, -kInfinity};
    for (size_t t = offset; t < offset + count; ++t)
      for (int k = 0; k < 3; ++k) {
        const double c = bounds_[6 * t + 2 * k], h = bounds_[6 * t + 2 * k + 1], l = c - h, r = c + h;
        if (l < lo[k]) lo[k] = l;
        if (r > hi[k]) hi[k] = r;
        if (c < clo[k]) clo[k] = c;
        if (c > chi[k]) chi[k] = c;
      }
    for (int k = 0; k < 3; ++k) {
      nodeBounds_[k] = static_cast<float>(lo[k]), nodeBounds_[k + 3] = static_cast<float>(hi[k]);
      centroidBounds_[k] = static_cast<float>(clo[k]), centroidBounds_[k + 3] = static_cast<float>(chi[k]);
    }
  }

  // Hoare partition of [offset, offset + count) by the centre on `axis` against pos (a centre on
  // the plane goes right): the index's triangles and their boxes swapped alike. Returns the first
  // on the right.
  size_t partition(size_t offset, size_t count, int axis, double pos) {
    // Signed: `right` goes below `left`, and below 0 when everything is on the right.
    long long left = static_cast<long long>(offset), right = static_cast<long long>(offset + count) - 1;
    for (;;) {
      while (left <= right && static_cast<double>(bounds_[6 * left + 2 * axis]) < pos) ++left;
      while (left <= right && static_cast<double>(bounds_[6 * right + 2 * axis]) >= pos) --right;
      if (left >= right) return static_cast<size_t>(left);
      for (int i = 0; i < 3; ++i) std::swap(index_[3 * left + i], index_[3 * right + i]);
      for (int i = 0; i < 6; ++i) std::swap(bounds_[6 * left + i], bounds_[6 * right + i]);
      ++left, --right;
    }
  }

  void splitNode(size_t offset, size_t count, int depth) {
    const size_t node = nodes_.size() / 8;
    nodes_.resize(nodes_.size() + 8, 0);
    std::memcpy(&nodes_[8 * node], nodeBounds_, sizeof nodeBounds_);
    if (count <= kTargetLeafSize || depth >= kMaxDepth) return writeLeaf(node, offset, count);
    // CENTER: the longest side of the centres' box, split at its middle.
    int axis = -1;
    double longest = -kInfinity;
    for (int k = 0; k < 3; ++k) {
      const double d = static_cast<double>(centroidBounds_[k + 3]) - centroidBounds_[k];
      if (d > longest) longest = d, axis = k;
    }
    if (axis < 0) return writeLeaf(node, offset, count);
    const double pos = (static_cast<double>(centroidBounds_[axis]) + centroidBounds_[axis + 3]) / 2;
    const size_t split = partition(offset, count, axis, pos);
    if (split == offset || split == offset + count) return writeLeaf(node, offset, count);
    nodes_[8 * node + 7] = static_cast<uint32_t>(axis);
    const size_t leftCount = split - offset;
    getBounds(offset, leftCount);
    splitNode(offset, leftCount, depth + 1);
    const size_t right = nodes_.size() / 8 - node;
    if (right > std::numeric_limits<uint32_t>::max()) throw Error("bvh: a child more than 2^32 nodes after its parent");
    nodes_[8 * node + 6] = static_cast<uint32_t>(right);
    getBounds(split, count - leftCount);
    splitNode(split, count - leftCount, depth + 1);
  }

  // A leaf: its first triangle, and its count (uint16, as the library stores it) beside 0xffff.
  void writeLeaf(size_t node, size_t offset, size_t count) {
    nodes_[8 * node + 6] = static_cast<uint32_t>(offset);
    nodes_[8 * node + 7] = (static_cast<uint32_t>(count) & 0xffffu) | (0xffffu << 16);
  }

  std::vector<uint32_t>& index_;
  std::vector<float> bounds_;
  std::vector<uint32_t> nodes_;
  float nodeBounds_[6] = {0, 0, 0, 0, 0, 0}, centroidBounds_[6] = {0, 0, 0, 0, 0, 0};
};

}  // namespace

std::vector<uint32_t> buildThreeMeshBvh(const std::vector<float>& positions, std::vector<uint32_t>& index) {
  if (positions.size() % 3 != 0)
    throw Error("bvh: positions must hold 3 numbers per vertex, got " + std::to_string(positions.size()));
  if (index.size() % 3 != 0 || index.empty())
    throw Error("bvh: the index must hold 3 vertex indices per triangle and at least one triangle, got " +
                std::to_string(index.size()));
  if (index.size() / 3 > std::numeric_limits<uint32_t>::max() / 2) throw Error("bvh: too many triangles");
  const size_t vertexCount = positions.size() / 3;
  for (size_t i = 0; i < index.size(); ++i)
    if (index[i] >= vertexCount)
      throw Error("bvh: triangle " + std::to_string(i / 3) + " refers to vertex " + std::to_string(index[i]) + " but there are " +
                  std::to_string(vertexCount) + " vertices");
  return Builder(positions, index).take();
}

}  // namespace mrvol
