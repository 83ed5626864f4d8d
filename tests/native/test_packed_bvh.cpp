// three-mesh-bvh's packed tree built in the core (packed_bvh.h): on random soups, a flat grid whose
// centers tie on split planes and degenerate triangles, the tree is well formed (each triangle in
// exactly one leaf, the index a reordering of the triangles, every box holding its triangles,
// leaves of at most 10 unless unsplittable, right offsets past the left subtree), the build is
// deterministic, and bad indices are refused. Bit-for-bit equality with three-mesh-bvh's own
// build is tests/node/packed-bvh.test.mjs (it needs the JS library).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "mrvol/error.h"
#include "mrvol/packed_bvh.h"

using namespace mrvol;

namespace {

float floatOf(uint32_t u) {
  float f;
  std::memcpy(&f, &u, 4);
  return f;
}

struct Checked {
  size_t leaves = 0, triangles = 0, deepest = 0;
};

// Walks node `n` (depth `depth`), checking its box holds its triangles and its children's layout.
void walk(const std::vector<uint32_t>& nodes, const std::vector<float>& p, const std::vector<uint32_t>& index,
          std::vector<int>& seen, size_t n, size_t depth, Checked& out, float (&lo)[3], float (&hi)[3]) {
  ASSERT_LT(n * 8 + 7, nodes.size());
  const uint32_t* node = &nodes[n * 8];
  for (int d = 0; d < 3; d++) lo[d] = floatOf(node[d]), hi[d] = floatOf(node[d + 3]);
  out.deepest = std::max(out.deepest, depth);
  if ((node[7] >> 16) == 0xffff) {
    const uint32_t first = node[6], count = node[7] & 0xffff;
    out.leaves++, out.triangles += count;
    for (uint32_t t = first; t < first + count; t++) {
      ASSERT_LT(3 * t + 2, index.size());
      seen[t]++;
      for (int j = 0; j < 3; j++)
        for (int d = 0; d < 3; d++) {
          const float x = p[3 * index[3 * t + j] + d];
          EXPECT_LE(lo[d], x);
          EXPECT_GE(hi[d], x);
        }
    }
    return;
  }
  EXPECT_LE(node[7], 2u) << "split axis";
  float llo[3], lhi[3], rlo[3], rhi[3];
  walk(nodes, p, index, seen, n + 1, depth + 1, out, llo, lhi);
  ASSERT_GT(node[6], 1u) << "the right child follows the left subtree";
  walk(nodes, p, index, seen, n + node[6], depth + 1, out, rlo, rhi);
  for (int d = 0; d < 3; d++) {
    EXPECT_LE(lo[d], std::min(llo[d], rlo[d]));
    EXPECT_GE(hi[d], std::max(lhi[d], rhi[d]));
  }
}

void expectWellFormed(const std::vector<float>& p, const std::vector<uint32_t>& input) {
  std::vector<uint32_t> index = input;
  const std::vector<uint32_t> nodes = buildPackedBvh(p, index);
  const size_t triangles = input.size() / 3;
  ASSERT_EQ(nodes.size() % 8, 0u);
  EXPECT_LE(nodes.size() / 8, std::max<size_t>(1, 2 * triangles - 1));
  // The index holds the same triangles (as corner triples), reordered.
  std::vector<std::vector<uint32_t>> before, after;
  for (size_t t = 0; t < triangles; t++) before.push_back({input[3 * t], input[3 * t + 1], input[3 * t + 2]});
  for (size_t t = 0; t < triangles; t++) after.push_back({index[3 * t], index[3 * t + 1], index[3 * t + 2]});
  std::sort(before.begin(), before.end()), std::sort(after.begin(), after.end());
  EXPECT_EQ(before, after);
  std::vector<int> seen(triangles, 0);
  Checked out;
  float lo[3], hi[3];
  walk(nodes, p, index, seen, 0, 0, out, lo, hi);
  EXPECT_EQ(out.triangles, triangles);
  for (size_t t = 0; t < triangles; t++) EXPECT_EQ(seen[t], 1) << "triangle " << t;
  EXPECT_LE(out.deepest, 40u);
  EXPECT_EQ(nodes.size() / 8, 2 * out.leaves - 1);
  // Deterministic: the same input, the same bytes.
  std::vector<uint32_t> again = input;
  EXPECT_EQ(buildPackedBvh(p, again), nodes);
  EXPECT_EQ(again, index);
}

}  // namespace

TEST(PackedBvh, RandomSoupsAreWellFormed) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1, 1);
  for (size_t n : {1u, 2u, 9u, 10u, 11u, 64u, 1000u, 20000u}) {
    std::vector<float> p;
    std::vector<uint32_t> index;
    for (size_t t = 0; t < n; t++) {
      const float cx = u(rng), cy = u(rng), cz = u(rng);
      for (int j = 0; j < 3; j++) {
        p.push_back(cx + 0.05f * u(rng)), p.push_back(cy + 0.05f * u(rng)), p.push_back(cz + 0.05f * u(rng));
        index.push_back(static_cast<uint32_t>(3 * t + j));
      }
    }
    SCOPED_TRACE(n);
    expectWellFormed(p, index);
  }
}

TEST(PackedBvh, FlatGridWithTiesAndDegenerateTriangles) {
  // A 40 x 40 grid in z = 0 (every center ties with others along x and y), plus slivers and
  // zero-area triangles (repeated corners) and many triangles at one point (unsplittable: one leaf).
  std::vector<float> p;
  std::vector<uint32_t> index;
  const int n = 40;
  for (int j = 0; j <= n; j++)
    for (int i = 0; i <= n; i++) p.push_back(static_cast<float>(i)), p.push_back(static_cast<float>(j)), p.push_back(0);
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++) {
      const uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      index.insert(index.end(), {a, b, d, a, d, c});
    }
  for (uint32_t v = 0; v < 100; v++) index.insert(index.end(), {v, v, v + 1});
  const uint32_t lone = static_cast<uint32_t>(p.size() / 3);
  p.insert(p.end(), {5.5f, 5.5f, 3});
  for (int k = 0; k < 25; k++) index.insert(index.end(), {lone, lone, lone});
  expectWellFormed(p, index);
}

TEST(PackedBvh, EmptyMeshIsOneEmptyLeaf) {
  std::vector<uint32_t> index;
  const std::vector<uint32_t> nodes = buildPackedBvh({0, 0, 0}, index);
  ASSERT_EQ(nodes.size(), 8u);
  EXPECT_EQ(nodes[6], 0u);
  EXPECT_EQ(nodes[7], 0xffffu << 16);
}

TEST(PackedBvh, BadIndicesAreRefusedWithTheTriangle) {
  std::vector<uint32_t> index = {0, 1, 2, 0, 2, 3};
  try {
    buildPackedBvh({0, 0, 0, 1, 0, 0, 0, 1, 0}, index);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("triangle 1 names vertex 3 of 3"), std::string::npos) << e.what();
  }
  std::vector<uint32_t> partial = {0, 1};
  EXPECT_THROW(buildPackedBvh({0, 0, 0, 1, 0, 0}, partial), Error);
}
