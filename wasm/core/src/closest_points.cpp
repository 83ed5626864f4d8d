#include "mrvol/closest_points.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "mrvol/error.h"
#include "mrvol/thread_pool.h"

namespace mrvol {

namespace {

constexpr uint32_t kLeafSize = 4;
constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Queries per block of a batch: each costs a few microseconds.
constexpr size_t kQueryGrain = 256;

double boxDistanceSquared(const double lo[3], const double hi[3], const double p[3]) {
  double s = 0;
  for (int k = 0; k < 3; ++k) {
    const double d = p[k] < lo[k] ? lo[k] - p[k] : (p[k] > hi[k] ? p[k] - hi[k] : 0.0);
    s += d * d;
  }
  return s;
}

}  // namespace

double closestPointOnTriangle(const double p[3], const double* a, const double* b, const double* c, double q[3]) {
  const double abx = b[0] - a[0], aby = b[1] - a[1], abz = b[2] - a[2];
  const double acx = c[0] - a[0], acy = c[1] - a[1], acz = c[2] - a[2];
  const double apx = p[0] - a[0], apy = p[1] - a[1], apz = p[2] - a[2];
  const double d1 = abx * apx + aby * apy + abz * apz, d2 = acx * apx + acy * apy + acz * apz;
  auto set = [q](double x, double y, double z) { q[0] = x, q[1] = y, q[2] = z; };
  if (d1 <= 0 && d2 <= 0) {
    set(a[0], a[1], a[2]);
  } else {
    const double bpx = p[0] - b[0], bpy = p[1] - b[1], bpz = p[2] - b[2];
    const double d3 = abx * bpx + aby * bpy + abz * bpz, d4 = acx * bpx + acy * bpy + acz * bpz;
    if (d3 >= 0 && d4 <= d3) {
      set(b[0], b[1], b[2]);
    } else {
      const double vc = d1 * d4 - d3 * d2;
      if (vc <= 0 && d1 >= 0 && d3 <= 0 && d1 - d3 > 0) {
        const double v = d1 / (d1 - d3);
        set(a[0] + abx * v, a[1] + aby * v, a[2] + abz * v);
      } else {
        const double cpx = p[0] - c[0], cpy = p[1] - c[1], cpz = p[2] - c[2];
        const double d5 = abx * cpx + aby * cpy + abz * cpz, d6 = acx * cpx + acy * cpy + acz * cpz;
        if (d6 >= 0 && d5 <= d6) {
          set(c[0], c[1], c[2]);
        } else {
          const double vb = d5 * d2 - d1 * d6;
          if (vb <= 0 && d2 >= 0 && d6 <= 0) {
            const double w = d2 / (d2 - d6);
            set(a[0] + acx * w, a[1] + acy * w, a[2] + acz * w);
          } else {
            const double va = d3 * d6 - d5 * d4;
            if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
              const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
              set(b[0] + (c[0] - b[0]) * w, b[1] + (c[1] - b[1]) * w, b[2] + (c[2] - b[2]) * w);
            } else {
              const double denom = 1 / (va + vb + vc), v = vb * denom, w = vc * denom;
              set(a[0] + abx * v + acx * w, a[1] + aby * v + acy * w, a[2] + abz * v + acz * w);
            }
          }
        }
      }
    }
  }
  const double ex = p[0] - q[0], ey = p[1] - q[1], ez = p[2] - q[2];
  return ex * ex + ey * ey + ez * ez;
}

void ClosestPoints::checkMesh(const std::vector<double>& positions, const std::vector<uint32_t>& triangles) const {
  if (positions.size() % 3 != 0)
    throw Error("closest points: positions must hold 3 numbers per vertex, got " + std::to_string(positions.size()));
  if (triangles.size() % 3 != 0)
    throw Error("closest points: triangles must hold 3 indices each, got " + std::to_string(triangles.size()));
  if (triangles.empty()) throw Error("closest points: the mesh has no triangles");
  const size_t vertexCount = positions.size() / 3;
  if (triangles.size() / 3 > std::numeric_limits<uint32_t>::max() / 2) throw Error("closest points: too many triangles");
  for (size_t i = 0; i < triangles.size(); ++i) {
    if (triangles[i] >= vertexCount)
      throw Error("closest points: triangle " + std::to_string(i / 3) + " refers to vertex " + std::to_string(triangles[i]) +
                  " but the mesh has " + std::to_string(vertexCount) + " vertices");
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite(positions[3 * triangles[i] + k]))
        throw Error("closest points: vertex " + std::to_string(triangles[i]) + " has a coordinate that is not a finite number");
  }
}

// The corners in tree order: a leaf's triangles side by side in memory.
void ClosestPoints::storeCorners(const std::vector<double>& positions, const std::vector<uint32_t>& triangles) {
  corners_.resize(9 * triangleIds_.size());
  for (size_t s = 0; s < triangleIds_.size(); ++s)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) corners_[9 * s + 3 * j + k] = positions[3 * triangles[3 * triangleIds_[s] + j] + k];
}

ClosestPoints::ClosestPoints(const std::vector<double>& positions, const std::vector<uint32_t>& triangles) {
  checkMesh(positions, triangles);
  const size_t triangleCount = triangles.size() / 3;
  triangleIds_.resize(triangleCount);
  std::vector<double> centroids(3 * triangleCount);
  for (size_t t = 0; t < triangleCount; ++t) {
    triangleIds_[t] = static_cast<uint32_t>(t);
    for (int k = 0; k < 3; ++k)
      centroids[3 * t + k] = (positions[3 * triangles[3 * t] + k] + positions[3 * triangles[3 * t + 1] + k] +
                              positions[3 * triangles[3 * t + 2] + k]) / 3;
  }
  std::vector<Node> nodes;
  nodes.reserve(2 * (triangleCount / kLeafSize + 1));
  build(nodes, 0, static_cast<uint32_t>(triangleCount), centroids);
  storeCorners(positions, triangles);
  for (Node& node : nodes) {
    if (node.count == kInner) continue;
    std::fill(node.lo, node.lo + 3, kInfinity);
    std::fill(node.hi, node.hi + 3, -kInfinity);
    for (uint32_t s = node.first; s < node.first + node.count; ++s)
      for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k) {
          node.lo[k] = std::min(node.lo[k], corners_[9 * s + 3 * j + k]);
          node.hi[k] = std::max(node.hi[k], corners_[9 * s + 3 * j + k]);
        }
  }
  // Inner boxes from their children, the children being after their parent.
  for (size_t i = nodes.size(); i-- > 0;) {
    Node& node = nodes[i];
    if (node.count != kInner) continue;
    const Node &l = nodes[i + 1], &r = nodes[node.first];
    for (int k = 0; k < 3; ++k) node.lo[k] = std::min(l.lo[k], r.lo[k]), node.hi[k] = std::max(l.hi[k], r.hi[k]);
  }
  pack(nodes);
}

ClosestPoints::ClosestPoints(const std::vector<double>& positions, const std::vector<uint32_t>& triangles,
                             const std::vector<double>& nodeBounds, const std::vector<uint32_t>& nodeFirst,
                             const std::vector<uint32_t>& nodeCount) {
  checkMesh(positions, triangles);
  const size_t triangleCount = triangles.size() / 3, nodeCount_ = nodeFirst.size();
  if (nodeCount_ == 0 || nodeCount.size() != nodeCount_ || nodeBounds.size() != 6 * nodeCount_)
    throw Error("closest points: the tree needs 6 bounds, a first and a count per node (" + std::to_string(nodeBounds.size()) +
                " bounds, " + std::to_string(nodeFirst.size()) + " firsts, " + std::to_string(nodeCount.size()) + " counts)");
  std::vector<uint8_t> depth(nodeCount_, 0);
  std::vector<Node> nodes(nodeCount_);
  for (size_t i = 0; i < nodeCount_; ++i) {
    Node& node = nodes[i];
    for (int k = 0; k < 3; ++k) node.lo[k] = nodeBounds[6 * i + k], node.hi[k] = nodeBounds[6 * i + 3 + k];
    node.first = nodeFirst[i], node.count = nodeCount[i];
    if (node.count == kInner) {
      if (!(i + 1 < nodeCount_ && node.first > i + 1 && node.first < nodeCount_))
        throw Error("closest points: tree node " + std::to_string(i) + " has its children out of order or out of range");
      if (depth[i] >= 120) throw Error("closest points: the tree is deeper than 120 levels");
      depth[i + 1] = depth[node.first] = static_cast<uint8_t>(depth[i] + 1);
    } else if (node.first > triangleCount || node.count > triangleCount - node.first) {
      throw Error("closest points: tree leaf " + std::to_string(i) + " holds triangles past the mesh's " + std::to_string(triangleCount));
    }
  }
  triangleIds_.resize(triangleCount);
  for (size_t t = 0; t < triangleCount; ++t) triangleIds_[t] = static_cast<uint32_t>(t);
  storeCorners(positions, triangles);
  pack(nodes);
}

// The flat nodes as walked: children's boxes in their parent, leaves as their parent's (first, count).
void ClosestPoints::pack(const std::vector<Node>& nodes) {
  std::vector<uint32_t> slot(nodes.size());
  for (size_t i = 0; i < nodes.size(); ++i)
    if (nodes[i].count == kInner) slot[i] = static_cast<uint32_t>(inner_.size()), inner_.emplace_back();
  for (size_t i = 0; i < nodes.size(); ++i) {
    if (nodes[i].count != kInner) continue;
    Inner& node = inner_[slot[i]];
    const size_t children[2] = {i + 1, nodes[i].first};
    for (int c = 0; c < 2; ++c) {
      const Node& child = nodes[children[c]];
      node.child[c] = child.count == kInner ? slot[children[c]] : child.first;
      node.count[c] = child.count;
      for (int k = 0; k < 3; ++k) node.lo[c][k] = child.lo[k], node.hi[c][k] = child.hi[k];
    }
  }
  rootFirst_ = nodes[0].count == kInner ? 0 : nodes[0].first, rootCount_ = nodes[0].count;
}

// Median split along the longest side of the centroids' box; nodes in depth-first order.
void ClosestPoints::build(std::vector<Node>& nodes, uint32_t begin, uint32_t end, const std::vector<double>& centroids) {
  const size_t index = nodes.size();
  nodes.push_back(Node{{0, 0, 0}, {0, 0, 0}, begin, end - begin});
  if (end - begin <= kLeafSize) return;
  double lo[3] = {kInfinity, kInfinity, kInfinity}, hi[3] = {-kInfinity, -kInfinity, -kInfinity};
  for (uint32_t s = begin; s < end; ++s)
    for (int k = 0; k < 3; ++k)
      lo[k] = std::min(lo[k], centroids[3 * triangleIds_[s] + k]), hi[k] = std::max(hi[k], centroids[3 * triangleIds_[s] + k]);
  int axis = 0;
  for (int k = 1; k < 3; ++k)
    if (hi[k] - lo[k] > hi[axis] - lo[axis]) axis = k;
  const uint32_t middle = begin + (end - begin) / 2;
  std::nth_element(triangleIds_.begin() + begin, triangleIds_.begin() + middle, triangleIds_.begin() + end,
                   [&](uint32_t a, uint32_t b) {
                     const double ca = centroids[3 * a + axis], cb = centroids[3 * b + axis];
                     return ca < cb || (ca == cb && a < b);
                   });
  nodes[index].count = kInner;
  build(nodes, begin, middle, centroids);
  nodes[index].first = static_cast<uint32_t>(nodes.size());
  build(nodes, middle, end, centroids);
}

void ClosestPoints::search(const double p[3], double maxDistanceSquared, ClosestHit& hit) const {
  // Depth first, the nearer child first (the second on a tie), as three-mesh-bvh's walk: a child
  // is entered if its box is nearer than both the best so far and the bound (the farther one
  // checked again when popped: the best may have shrunk); every triangle of a leaf visited counts.
  // The root is always entered. Depth < 120 (checked, or median splits): 128 entries suffice.
  uint32_t stackNode[128], stackCount[128];
  double stackDistance[128];
  size_t top = 0;
  double best = hit.distanceSquared;
  uint32_t node = rootFirst_, count = rootCount_;
  for (;;) {
    if (count != kInner) {
      for (uint32_t s = node; s < node + count; ++s) {
        const double* c = &corners_[9 * s];
        double q[3];
        const double d = closestPointOnTriangle(p, c, c + 3, c + 6, q);
        if (d < best) {
          best = d;
          hit.point[0] = q[0], hit.point[1] = q[1], hit.point[2] = q[2];
          hit.distanceSquared = d;
          hit.triangle = triangleIds_[s];
        }
      }
    } else {
      const Inner& inner = inner_[node];
      uint32_t near = inner.child[0], far = inner.child[1], nearCount = inner.count[0], farCount = inner.count[1];
      double dn = boxDistanceSquared(inner.lo[0], inner.hi[0], p), df = boxDistanceSquared(inner.lo[1], inner.hi[1], p);
      if (df < dn) std::swap(near, far), std::swap(nearCount, farCount), std::swap(dn, df);
      const bool enterFar = df < best && df < maxDistanceSquared;
      if (dn < best && dn < maxDistanceSquared) {
        if (enterFar) stackNode[top] = far, stackCount[top] = farCount, stackDistance[top++] = df;
        node = near, count = nearCount;
        continue;
      }
      if (enterFar) {
        node = far, count = farCount;
        continue;
      }
    }
    while (top > 0 && !(stackDistance[top - 1] < best && stackDistance[top - 1] < maxDistanceSquared)) --top;
    if (top == 0) break;
    --top;
    node = stackNode[top], count = stackCount[top];
  }
}

bool ClosestPoints::closest(const double p[3], double maxDistanceSquared, ClosestHit& hit) const {
  ClosestHit found{{0, 0, 0}, kInfinity, 0};
  search(p, maxDistanceSquared, found);
  if (found.distanceSquared == kInfinity) return false;
  hit = found;
  return true;
}

void ClosestPoints::closestMany(const double* points, size_t n, const double* bounds, double* points3,
                                double* distanceSquared, uint32_t* triangles) const {
  parallelFor(0, n, kQueryGrain, [&](size_t begin, size_t end) {
    // As in sampledDistanceFrom: the previous query's distance plus the step bounds this one's
    // (distance to a surface is 1-Lipschitz), which prunes the search when the queries come in
    // order along a surface (a mesh's vertices). The answer is the same: the subtrees it skips hold
    // nothing within the bound, and the others are walked in the same order.
    double previous = kInfinity;
    const double* last = nullptr;
    for (size_t i = begin; i < end; ++i) {
      ClosestHit hit{{0, 0, 0}, kInfinity, 0};
      const double* p = points + 3 * i;
      double bound = bounds ? bounds[i] : kInfinity;
      if (last) {
        const double dx = p[0] - last[0], dy = p[1] - last[1], dz = p[2] - last[2];
        bound = std::min(bound, (previous + std::sqrt(dx * dx + dy * dy + dz * dz)) * 1.0001 + 1e-12);
      }
      if (!(bound < kInfinity && closest(p, bound * bound, hit))) closest(p, kInfinity, hit);
      for (int k = 0; k < 3; ++k) points3[3 * i + k] = hit.point[k];
      distanceSquared[i] = hit.distanceSquared;
      triangles[i] = hit.triangle;
      previous = std::sqrt(hit.distanceSquared), last = p;
    }
  });
}

double ClosestPoints::sampledDistanceFrom(const std::vector<double>& positions, const std::vector<uint32_t>& triangles,
                                          size_t maxSamples) const {
  const size_t vertexCount = positions.size() / 3, faceCount = triangles.size() / 3;
  for (uint32_t v : triangles)
    if (v >= vertexCount) throw Error("sampled distance: a triangle refers to vertex " + std::to_string(v) +
                                      " but the mesh has " + std::to_string(vertexCount) + " vertices");
  const size_t total = vertexCount + 4 * faceCount;
  const size_t stride = std::max<size_t>(1, (total + std::max<size_t>(1, maxSamples) - 1) / std::max<size_t>(1, maxSamples));
  const size_t count = (total + stride - 1) / stride;
  static const double kWeights[4][3] = {{1.0 / 3, 1.0 / 3, 1.0 / 3}, {2.0 / 3, 1.0 / 6, 1.0 / 6},
                                        {1.0 / 6, 2.0 / 3, 1.0 / 6}, {1.0 / 6, 1.0 / 6, 2.0 / 3}};
  std::vector<double> distances(count, 0.0);
  parallelFor(0, count, kQueryGrain, [&](size_t begin, size_t end) {
    // Distance to a surface is 1-Lipschitz: the previous sample's distance plus the step bounds the
    // next one, which prunes most of its search.
    double previous = kInfinity, last[3] = {0, 0, 0};
    for (size_t i = begin; i < end; ++i) {
      const size_t s = i * stride;
      double p[3];
      if (s < vertexCount) {
        for (int k = 0; k < 3; ++k) p[k] = positions[3 * s + k];
      } else {
        const size_t f = (s - vertexCount) / 4;
        const double* w = kWeights[(s - vertexCount) % 4];
        const uint32_t a = triangles[3 * f], b = triangles[3 * f + 1], c = triangles[3 * f + 2];
        for (int k = 0; k < 3; ++k) p[k] = w[0] * positions[3 * a + k] + w[1] * positions[3 * b + k] + w[2] * positions[3 * c + k];
      }
      const double bound = (previous + std::sqrt((p[0] - last[0]) * (p[0] - last[0]) + (p[1] - last[1]) * (p[1] - last[1]) +
                                                 (p[2] - last[2]) * (p[2] - last[2]))) * 1.0001 + 1e-12;
      ClosestHit hit{{0, 0, 0}, kInfinity, 0};
      if (!(bound < kInfinity && closest(p, bound * bound, hit))) closest(p, kInfinity, hit);
      previous = std::sqrt(hit.distanceSquared);
      distances[i] = previous;
      for (int k = 0; k < 3; ++k) last[k] = p[k];
    }
  });
  double worst = 0;
  for (double d : distances) worst = std::max(worst, d);
  return worst;
}

}  // namespace mrvol
