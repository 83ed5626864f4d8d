// Closest points on a mesh (closest_points.h): the tree's answers against a brute-force scan of
// every triangle on random meshes (the same squared distance), with its own tree and with one given
// from outside, the point-triangle step against sampled points of the triangle, bounds, batches
// and the sampled distance at 1, 2 and 3 threads (the same bits), a given tree walked in
// three-mesh-bvh's order (the same triangle, point and distance bits, exact ties included), and
// bad meshes and trees refused with a message.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "mrvol/closest_points.h"
#include "mrvol/error.h"
#include "mrvol/thread_pool.h"

using namespace mrvol;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct Soup {
  std::vector<double> positions;
  std::vector<uint32_t> triangles;
};

// A random closed-ish surface: a bumpy sphere of (rings x segments) quads, plus loose random
// triangles (slivers and degenerate ones among them) around it.
Soup randomMesh(std::mt19937& rng, int rings, int segments, int loose) {
  std::uniform_real_distribution<double> u(-1, 1);
  Soup m;
  for (int i = 0; i <= rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const double th = M_PI * i / rings, ph = 2 * M_PI * j / segments, r = 1 + 0.2 * u(rng);
      m.positions.insert(m.positions.end(), {r * std::sin(th) * std::cos(ph), r * std::sin(th) * std::sin(ph), r * std::cos(th)});
    }
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const uint32_t a = i * segments + j, b = i * segments + (j + 1) % segments, c = a + segments, d = b + segments;
      m.triangles.insert(m.triangles.end(), {a, c, b, b, c, d});
    }
  for (int t = 0; t < loose; ++t) {
    const uint32_t base = static_cast<uint32_t>(m.positions.size() / 3);
    const double cx = 2 * u(rng), cy = 2 * u(rng), cz = 2 * u(rng), s = 0.3 * std::abs(u(rng));
    for (int k = 0; k < 3; ++k) m.positions.insert(m.positions.end(), {cx + s * u(rng), cy + s * u(rng), cz + s * u(rng)});
    if (t % 7 == 0)  // degenerate: two corners the same
      for (int k = 0; k < 3; ++k) m.positions[3 * (base + 2) + k] = m.positions[3 * base + k];
    m.triangles.insert(m.triangles.end(), {base, base + 1, base + 2});
  }
  return m;
}

double bruteForce(const Soup& m, const double p[3]) {
  double best = kInf, q[3];
  for (size_t t = 0; t < m.triangles.size() / 3; ++t) {
    const double* a = &m.positions[3 * m.triangles[3 * t]];
    const double* b = &m.positions[3 * m.triangles[3 * t + 1]];
    const double* c = &m.positions[3 * m.triangles[3 * t + 2]];
    best = std::min(best, closestPointOnTriangle(p, a, b, c, q));
  }
  return best;
}

double distanceToTriangle(const Soup& m, uint32_t t, const double p[3]) {
  double q[3];
  return closestPointOnTriangle(p, &m.positions[3 * m.triangles[3 * t]], &m.positions[3 * m.triangles[3 * t + 1]],
                                &m.positions[3 * m.triangles[3 * t + 2]], q);
}

std::vector<double> randomPoints(std::mt19937& rng, size_t n, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  std::vector<double> points(3 * n);
  for (double& x : points) x = u(rng);
  return points;
}

struct Threads {
  explicit Threads(unsigned count) {
    setThreadCount(count);
    setGrainCap(16);
  }
  ~Threads() {
    setGrainCap(0);
    setThreadCount(1);
  }
};

}  // namespace

TEST(ClosestPoints, PointOnTriangleIsOnItAndNoSampleOfItIsCloser) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1), w(0, 1);
  for (int trial = 0; trial < 2000; ++trial) {
    double a[3], b[3], c[3], p[3], q[3];
    for (int k = 0; k < 3; ++k) a[k] = u(rng), b[k] = u(rng), c[k] = u(rng), p[k] = 2 * u(rng);
    const double d = closestPointOnTriangle(p, a, b, c, q);
    EXPECT_NEAR(d, (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]), 1e-12);
    for (int s = 0; s < 200; ++s) {
      double x = w(rng), y = w(rng);
      if (x + y > 1) x = 1 - x, y = 1 - y;
      double r[3], e = 0;
      for (int k = 0; k < 3; ++k) r[k] = a[k] + x * (b[k] - a[k]) + y * (c[k] - a[k]), e += (p[k] - r[k]) * (p[k] - r[k]);
      ASSERT_LE(d, e + 1e-12) << "trial " << trial;
    }
  }
}

TEST(ClosestPoints, SameDistanceAsBruteForceOnRandomMeshes) {
  std::mt19937 rng(11);
  for (int mesh = 0; mesh < 6; ++mesh) {
    const Soup m = randomMesh(rng, 4 + 3 * mesh, 5 + 4 * mesh, 3 + 20 * mesh);
    const ClosestPoints tree(m.positions, m.triangles);
    ASSERT_EQ(tree.triangleCount(), m.triangles.size() / 3);
    const std::vector<double> points = randomPoints(rng, 400, mesh % 2 ? 1.5 : 6.0);
    for (size_t i = 0; i < points.size() / 3; ++i) {
      const double* p = &points[3 * i];
      ClosestHit hit{};
      ASSERT_TRUE(tree.closest(p, kInf, hit));
      const double expected = bruteForce(m, p);
      ASSERT_NEAR(hit.distanceSquared, expected, 1e-12 * std::max(1.0, expected)) << "mesh " << mesh << " point " << i;
      ASSERT_LT(hit.triangle, m.triangles.size() / 3);
      EXPECT_NEAR(distanceToTriangle(m, hit.triangle, p), hit.distanceSquared, 1e-12 * std::max(1.0, expected));
      const double dx = p[0] - hit.point[0], dy = p[1] - hit.point[1], dz = p[2] - hit.point[2];
      EXPECT_NEAR(dx * dx + dy * dy + dz * dz, hit.distanceSquared, 1e-12 * std::max(1.0, expected));
    }
  }
}

TEST(ClosestPoints, ABoundAboveTheDistanceNeverChangesTheAnswer) {
  std::mt19937 rng(5);
  const Soup m = randomMesh(rng, 12, 16, 40);
  const ClosestPoints tree(m.positions, m.triangles);
  const std::vector<double> points = randomPoints(rng, 300, 3.0);
  for (size_t i = 0; i < points.size() / 3; ++i) {
    const double* p = &points[3 * i];
    const double expected = bruteForce(m, p);
    ClosestHit hit{{9, 9, 9}, 42, 7};
    // A bound below the distance: false with the hit untouched, or a triangle no closer than the
    // closest (one of a box that reaches within the bound).
    if (expected > 1e-6) {
      if (tree.closest(p, 0.99 * expected, hit)) {
        EXPECT_GE(hit.distanceSquared, expected * (1 - 1e-12));
        EXPECT_NEAR(distanceToTriangle(m, hit.triangle, p), hit.distanceSquared, 1e-12 * std::max(1.0, expected));
      } else {
        EXPECT_EQ(hit.distanceSquared, 42);
        EXPECT_EQ(hit.triangle, 7u);
      }
    }
    ASSERT_TRUE(tree.closest(p, 1.01 * expected + 1e-300, hit));
    EXPECT_NEAR(hit.distanceSquared, expected, 1e-12 * std::max(1.0, expected));
  }
}

TEST(ClosestPoints, BatchesAndSampledDistanceAreTheSameAtAnyThreadCount) {
  std::mt19937 rng(3);
  const Soup m = randomMesh(rng, 14, 20, 30);
  const Soup other = randomMesh(rng, 9, 11, 10);
  const ClosestPoints tree(m.positions, m.triangles);
  const size_t n = 777;
  const std::vector<double> points = randomPoints(rng, n, 2.0);
  std::vector<double> bounds(n);
  for (size_t i = 0; i < n; ++i) bounds[i] = (i % 3 == 0 ? 0.5 : 2.0) * std::sqrt(bruteForce(m, &points[3 * i]));
  std::vector<double> firstPoints, firstDistances;
  std::vector<uint32_t> firstTriangles;
  double firstSampled = -1;
  for (unsigned threads : {1u, 2u, 3u}) {
    Threads t(threads);
    std::vector<double> out(3 * n), d(n);
    std::vector<uint32_t> tri(n);
    tree.closestMany(points.data(), n, bounds.data(), out.data(), d.data(), tri.data());
    std::vector<double> unboundedOut(3 * n), unboundedD(n);
    std::vector<uint32_t> unboundedTri(n);
    tree.closestMany(points.data(), n, nullptr, unboundedOut.data(), unboundedD.data(), unboundedTri.data());
    for (size_t i = 0; i < n; ++i) {
      const double expected = bruteForce(m, &points[3 * i]);
      ASSERT_NEAR(unboundedD[i], expected, 1e-12 * std::max(1.0, expected)) << threads << " threads, query " << i;
      // A bound above the distance: the same; below it: a triangle no closer (or, if none within
      // reach, searched again without it).
      if (i % 3 != 0) EXPECT_EQ(d[i], unboundedD[i]) << threads << " threads, query " << i;
      else EXPECT_GE(d[i], expected * (1 - 1e-12)) << threads << " threads, query " << i;
    }
    const double sampled = tree.sampledDistanceFrom(other.positions, other.triangles, 500);
    if (threads == 1) {
      firstPoints = out, firstDistances = d, firstTriangles = tri, firstSampled = sampled;
      // Brute force over the same samples: every 4th... per the documented stride.
      const size_t V = other.positions.size() / 3, F = other.triangles.size() / 3, total = V + 4 * F;
      const size_t stride = (total + 499) / 500;
      const double W[4][3] = {{1.0 / 3, 1.0 / 3, 1.0 / 3}, {2.0 / 3, 1.0 / 6, 1.0 / 6}, {1.0 / 6, 2.0 / 3, 1.0 / 6}, {1.0 / 6, 1.0 / 6, 2.0 / 3}};
      double worst = 0;
      for (size_t s = 0; s < total; s += stride) {
        double p[3];
        if (s < V) {
          for (int k = 0; k < 3; ++k) p[k] = other.positions[3 * s + k];
        } else {
          const size_t f = (s - V) / 4;
          const double* w = W[(s - V) % 4];
          for (int k = 0; k < 3; ++k)
            p[k] = w[0] * other.positions[3 * other.triangles[3 * f] + k] + w[1] * other.positions[3 * other.triangles[3 * f + 1] + k] +
                   w[2] * other.positions[3 * other.triangles[3 * f + 2] + k];
        }
        worst = std::max(worst, std::sqrt(bruteForce(m, p)));
      }
      EXPECT_NEAR(sampled, worst, 1e-12 * std::max(1.0, worst));
      EXPECT_GT(worst, 0);
    } else {
      EXPECT_EQ(out, firstPoints) << threads << " threads";
      EXPECT_EQ(d, firstDistances) << threads << " threads";
      EXPECT_EQ(tri, firstTriangles) << threads << " threads";
      EXPECT_EQ(sampled, firstSampled) << threads << " threads";
    }
  }
}

namespace {

// A tree given from outside: median splits of the triangles in their given order (a valid, not a
// spatial, tree), boxes from their corners, depth-first; leaves of at most `leaf` triangles.
struct GivenTree {
  std::vector<double> bounds;
  std::vector<uint32_t> first, count;
};
uint32_t addNode(const Soup& m, uint32_t begin, uint32_t end, uint32_t leaf, GivenTree& tree) {
  const uint32_t index = static_cast<uint32_t>(tree.first.size());
  double lo[3] = {kInf, kInf, kInf}, hi[3] = {-kInf, -kInf, -kInf};
  for (uint32_t t = begin; t < end; ++t)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k)
        lo[k] = std::min(lo[k], m.positions[3 * m.triangles[3 * t + j] + k]), hi[k] = std::max(hi[k], m.positions[3 * m.triangles[3 * t + j] + k]);
  tree.bounds.insert(tree.bounds.end(), {lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]});
  tree.first.push_back(begin), tree.count.push_back(end - begin);
  if (end - begin <= leaf) return index;
  tree.count[index] = ClosestPoints::kInner;
  addNode(m, begin, (begin + end) / 2, leaf, tree);
  tree.first[index] = addNode(m, (begin + end) / 2, end, leaf, tree);
  return index;
}

}  // namespace

TEST(ClosestPoints, AGivenTreeGivesTheSameDistancesAsBruteForce) {
  std::mt19937 rng(17);
  const Soup m = randomMesh(rng, 10, 13, 25);
  for (uint32_t leaf : {1u, 3u, 10u}) {
    GivenTree given;
    addNode(m, 0, static_cast<uint32_t>(m.triangles.size() / 3), leaf, given);
    const ClosestPoints tree(m.positions, m.triangles, given.bounds, given.first, given.count);
    const std::vector<double> points = randomPoints(rng, 300, 2.5);
    for (size_t i = 0; i < points.size() / 3; ++i) {
      ClosestHit hit{};
      ASSERT_TRUE(tree.closest(&points[3 * i], kInf, hit));
      const double expected = bruteForce(m, &points[3 * i]);
      ASSERT_NEAR(hit.distanceSquared, expected, 1e-12 * std::max(1.0, expected)) << "leaf " << leaf << " point " << i;
      EXPECT_NEAR(distanceToTriangle(m, hit.triangle, &points[3 * i]), hit.distanceSquared, 1e-12 * std::max(1.0, expected));
    }
  }
  // Bad trees: children before their parent or out of range, leaves past the mesh, sizes that disagree.
  GivenTree given;
  addNode(m, 0, static_cast<uint32_t>(m.triangles.size() / 3), 4, given);
  auto refused = [&](GivenTree t, const char* what) {
    try {
      ClosestPoints tree(m.positions, m.triangles, t.bounds, t.first, t.count);
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
      return;
    }
    ADD_FAILURE() << "accepted a tree with " << what;
  };
  GivenTree loop = given;
  loop.first[0] = 0;
  refused(loop, "out of order");
  GivenTree past = given;
  past.first.back() = static_cast<uint32_t>(m.triangles.size() / 3);
  past.count.back() = 1;
  refused(past, "past the mesh");
  GivenTree short_ = given;
  short_.bounds.pop_back();
  refused(short_, "6 bounds");
}

TEST(ClosestPoints, BadMeshesAreRefusedWithAMessage) {
  auto message = [](const std::vector<double>& p, const std::vector<uint32_t>& t) {
    try {
      ClosestPoints tree(p, t);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::vector<double> p = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  EXPECT_NE(message(p, {}).find("no triangles"), std::string::npos);
  EXPECT_NE(message(p, {0, 1}).find("3 indices"), std::string::npos);
  EXPECT_NE(message({0, 0, 0, 1}, {0, 0, 0}).find("3 numbers"), std::string::npos);
  EXPECT_NE(message(p, {0, 1, 3}).find("refers to vertex 3"), std::string::npos);
  EXPECT_NE(message({0, 0, NAN, 1, 0, 0, 0, 1, 0}, {0, 1, 2}).find("finite"), std::string::npos);
  const ClosestPoints tree(p, {0, 1, 2});
  EXPECT_THROW(tree.sampledDistanceFrom(p, {0, 1, 5}, 10), Error);
}

namespace {

// three-mesh-bvh's walk (lib/remesh.mjs closestPointQuery), recursive, over the given tree's
// double boxes: the reference for which triangle wins a tie.
struct ReferenceWalk {
  const Soup& m;
  const GivenTree& tree;
  const double* p;
  double maxSquared, best = kInf;
  ClosestHit hit{};
  double box(uint32_t n) const {
    double s = 0;
    for (int k = 0; k < 3; ++k) {
      const double d = std::max(tree.bounds[6 * n + k], std::min(tree.bounds[6 * n + 3 + k], p[k])) - p[k];
      s += d * d;
    }
    return s;
  }
  void traverse(uint32_t n) {
    if (tree.count[n] != ClosestPoints::kInner) {
      for (uint32_t t = tree.first[n]; t < tree.first[n] + tree.count[n]; ++t) {
        double q[3];
        const double d = closestPointOnTriangle(p, &m.positions[3 * m.triangles[3 * t]], &m.positions[3 * m.triangles[3 * t + 1]],
                                                &m.positions[3 * m.triangles[3 * t + 2]], q);
        if (d < best) best = d, hit = ClosestHit{{q[0], q[1], q[2]}, d, t};
      }
      return;
    }
    uint32_t c1 = n + 1, c2 = tree.first[n];
    double s1 = box(c1), s2 = box(c2);
    if (s2 < s1) std::swap(c1, c2), std::swap(s1, s2);
    if (s1 < best && s1 < maxSquared) traverse(c1);
    if (s2 < best && s2 < maxSquared) traverse(c2);
  }
};

// A flat grid of unit squares (two triangles each) at z = 0, float-exact: most points above it
// are equally near several triangles.
Soup gridMesh(int size) {
  Soup m;
  for (int i = 0; i <= size; ++i)
    for (int j = 0; j <= size; ++j) m.positions.insert(m.positions.end(), {double(i), double(j), 0.0});
  for (int i = 0; i < size; ++i)
    for (int j = 0; j < size; ++j) {
      const uint32_t a = i * (size + 1) + j, b = a + 1, c = a + size + 1, d = c + 1;
      m.triangles.insert(m.triangles.end(), {a, c, b, b, c, d});
    }
  return m;
}

}  // namespace

TEST(ClosestPoints, AGivenTreeIsWalkedAsThreeMeshBvhWalksItTiesIncluded) {
  std::mt19937 rng(23);
  Soup bumpy = randomMesh(rng, 12, 17, 40);
  // Float32 corners, as the remesher's surfaces (three-mesh-bvh over a Float32Array) have.
  for (double& x : bumpy.positions) x = static_cast<float>(x);
  std::uniform_real_distribution<double> u(0, 1);
  Soup grid = gridMesh(9);
  for (Soup* m : {&bumpy, &grid}) {
    for (uint32_t leaf : {1u, 4u, 10u}) {
      GivenTree given;
      addNode(*m, 0, static_cast<uint32_t>(m->triangles.size() / 3), leaf, given);
      const ClosestPoints tree(m->positions, m->triangles, given.bounds, given.first, given.count);
      std::vector<double> points = randomPoints(rng, 400, 2.5);
      if (m == &grid)  // above the grid, on its vertices, edges and centres: exact ties
        for (size_t i = 0; i < points.size() / 3; ++i)
          points[3 * i] = std::floor(9 * u(rng)) + 0.5 * (i % 3), points[3 * i + 1] = std::floor(9 * u(rng)) + 0.5 * (i % 2),
          points[3 * i + 2] = 0.25 * (i % 5);
      for (size_t i = 0; i < points.size() / 3; ++i) {
        for (double bound : {kInf, 0.5, 0.05}) {
          ReferenceWalk ref{*m, given, &points[3 * i], bound * bound};
          ref.traverse(0);
          ClosestHit hit{};
          const bool found = tree.closest(&points[3 * i], bound * bound, hit);
          ASSERT_EQ(found, ref.best < kInf) << "leaf " << leaf << " point " << i << " bound " << bound;
          if (!found) continue;
          ASSERT_EQ(hit.triangle, ref.hit.triangle) << "leaf " << leaf << " point " << i << " bound " << bound;
          for (int k = 0; k < 3; ++k) ASSERT_EQ(hit.point[k], ref.hit.point[k]);
          ASSERT_EQ(hit.distanceSquared, ref.hit.distanceSquared);
        }
      }
    }
  }
}

// A batch without bounds bounds each query by the one before it (the distance is 1-Lipschitz): the
// answers must be those of the unbounded walk, bit for bit and ties included, for queries in order
// along a surface (the grid's vertices, edge midpoints and centres, above and on it: exact ties)
// and for scattered ones (each far from the one before), at 1 and 2 threads.
TEST(ClosestPoints, ABatchAnswersAsTheUnboundedWalkTiesIncluded) {
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> u(0, 1);
  Soup bumpy = randomMesh(rng, 12, 17, 40);
  for (double& x : bumpy.positions) x = static_cast<float>(x);
  Soup grid = gridMesh(9);
  for (Soup* m : {&bumpy, &grid}) {
    GivenTree given;
    addNode(*m, 0, static_cast<uint32_t>(m->triangles.size() / 3), 4, given);
    const ClosestPoints tree(m->positions, m->triangles, given.bounds, given.first, given.count);
    std::vector<double> points;
    for (int y = 0; y <= 18; ++y)  // a raster over the grid at half steps: neighbours in order
      for (int x = 0; x <= 18; ++x) points.insert(points.end(), {0.5 * x, 0.5 * y, 0.25 * ((x + y) % 3)});
    const std::vector<double> scattered = randomPoints(rng, 300, 2.5);
    points.insert(points.end(), scattered.begin(), scattered.end());
    const size_t n = points.size() / 3;
    for (unsigned threads : {1u, 2u}) {
      Threads t(threads);
      std::vector<double> out(3 * n), d(n);
      std::vector<uint32_t> tri(n);
      tree.closestMany(points.data(), n, nullptr, out.data(), d.data(), tri.data());
      for (size_t i = 0; i < n; ++i) {
        ReferenceWalk ref{*m, given, &points[3 * i], kInf};
        ref.traverse(0);
        ASSERT_EQ(tri[i], ref.hit.triangle) << "point " << i << " threads " << threads;
        for (int k = 0; k < 3; ++k) ASSERT_EQ(out[3 * i + k], ref.hit.point[k]) << "point " << i;
        ASSERT_EQ(d[i], ref.hit.distanceSquared) << "point " << i;
      }
    }
  }
}

TEST(ClosestPoints, PointsBesideCornersGetExactlyTheBruteForceDistance) {
  // A point just beside a corner, in any direction: the boxes the walk keeps in the parents must
  // still hold that corner, so the closest triangle is never pruned.
  std::mt19937 rng(29);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 200; ++trial) {
    Soup m = randomMesh(rng, 3, 5, 30);
    const ClosestPoints tree(m.positions, m.triangles);
    for (size_t v = 0; v < m.positions.size() / 3; v += 7) {
      const double* c = &m.positions[3 * v];
      const double p[3] = {c[0] + 1e-12 * u(rng), c[1] + 1e-12 * u(rng), c[2] + 1e-12 * u(rng)};
      ClosestHit hit{};
      ASSERT_TRUE(tree.closest(p, kInf, hit));
      ASSERT_EQ(hit.distanceSquared, bruteForce(m, p)) << "trial " << trial << " vertex " << v;
    }
  }
}
