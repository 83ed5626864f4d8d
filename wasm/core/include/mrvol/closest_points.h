// Closest points on a fixed triangle mesh: a static AABB tree built once (flat arrays, median
// splits), queried one point at a time or in batches (threaded by parallelFor: each query writes
// only its own outputs, so the results are the same at any thread count). The remesher's
// projections and its sampled Hausdorff distance run on it (lib/remesh.mjs).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace mrvol {

struct ClosestHit {
  double point[3];
  double distanceSquared;
  uint32_t triangle;  // index into the triangles as given
};

class ClosestPoints {
 public:
  // positions: 3 per vertex; triangles: 3 vertex indices each (checked: in range, finite corners).
  // The tree: median splits of the centroids, 4 triangles a leaf.
  ClosestPoints(const std::vector<double>& positions, const std::vector<uint32_t>& triangles);
  // The same mesh with a tree built elsewhere (three-mesh-bvh's, so that the answers, ties
  // included, are that library's): per node its box (6 numbers: lo, hi), and first / count: a
  // leaf holds triangles first .. first + count - 1 (as given); an inner node (count = kInner)
  // has its first child next and its second at index `first`. Node 0 is the root. Checked:
  // children after their parent and in range, leaves' triangles in range, depth < 120.
  static constexpr uint32_t kInner = 0xffffffffu;
  ClosestPoints(const std::vector<double>& positions, const std::vector<uint32_t>& triangles,
                const std::vector<double>& nodeBounds, const std::vector<uint32_t>& nodeFirst,
                const std::vector<uint32_t>& nodeCount);

  size_t triangleCount() const { return triangleIds_.size(); }

  // The closest point of the mesh to p (maxDistanceSquared infinite), as three-mesh-bvh walks its
  // tree: depth first, the nearer child first, a box skipped unless nearer than both the best so
  // far and the bound. With a bound: the closest point if it lies within it; else false, or the
  // closest among the triangles of the boxes that reach within it (the remesher's bounds are
  // upper bounds of the distance). False: hit left as it was.
  bool closest(const double p[3], double maxDistanceSquared, ClosestHit& hit) const;

  // n queries: points (3 each), bounds (n distances, or null: none); a query with nothing within
  // its bound is searched again without it. Each query is also bounded by the one before it (its
  // distance plus the step), which gives the same answers faster for points in order along a
  // surface. Writes 3 coordinates, the squared distance and the triangle per query (points3,
  // distanceSquared, triangles: n each).
  void closestMany(const double* points, size_t n, const double* bounds, double* points3, double* distanceSquared,
                   uint32_t* triangles) const;

  // The largest distance to this mesh from the sample points of another mesh: its vertices, then
  // per face the centroid and the points of barycentric weights (2/3, 1/6, 1/6) and its
  // rotations; every `stride`-th sample with stride = ceil((V + 4F) / maxSamples) (at least 1).
  double sampledDistanceFrom(const std::vector<double>& positions, const std::vector<uint32_t>& triangles,
                             size_t maxSamples) const;

 private:
  // The tree as built or given: per node its box; a leaf's triangles, or an inner node's second child.
  struct Node {
    double lo[3], hi[3];
    uint32_t first;  // a leaf: its first triangle slot; inner: the second child (the first is next)
    uint32_t count;  // triangles in a leaf; kInner for an inner node
  };
  // The tree as walked: an inner node holds its two children's boxes side by side (a step reads
  // two adjacent cache lines, not two nodes apart); child c is an inner node's index (count[c] =
  // kInner) or a leaf's first triangle slot (count[c] triangles).
  struct alignas(64) Inner {
    double lo[2][3], hi[2][3];
    uint32_t child[2], count[2];
  };
  void checkMesh(const std::vector<double>& positions, const std::vector<uint32_t>& triangles) const;
  void storeCorners(const std::vector<double>& positions, const std::vector<uint32_t>& triangles);
  void build(std::vector<Node>& nodes, uint32_t begin, uint32_t end, const std::vector<double>& centroids);
  void pack(const std::vector<Node>& nodes);
  // Closest within maxDistanceSquared, from `hit`'s current best (distanceSquared: infinity first).
  void search(const double p[3], double maxDistanceSquared, ClosestHit& hit) const;

  std::vector<Inner> inner_;
  uint32_t rootFirst_ = 0, rootCount_ = kInner;  // the root: inner_[0], or a leaf
  std::vector<uint32_t> triangleIds_;  // tree order -> the caller's triangle index
  std::vector<double> corners_;        // tree order: 9 coordinates per triangle (a, b, c)
};

// The closest point of triangle (a, b, c) to p (Ericson's regions, in three.js's
// Triangle.closestPointToPoint's steps); writes q, returns the squared distance.
double closestPointOnTriangle(const double p[3], const double* a, const double* b, const double* c, double q[3]);

}  // namespace mrvol
