// three-mesh-bvh's tree built in the core (bvh_build.h): on random triangle soups the packed tree is
// well formed (every triangle in exactly one leaf, the index a permutation of the triangles, each
// leaf's box holding its triangles' corners, each inner box holding its children's, leaves of at
// most 10 triangles but where centres coincide or the depth is 40) and the same at every call; bad
// input refused with a message. That the bytes are the library's is tests/node/bvh-build.test.mjs.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "mrvol/bvh_build.h"
#include "mrvol/error.h"

using namespace mrvol;

namespace {

struct Node {
  float lo[3], hi[3];
  uint32_t word6, word7;
  bool leaf() const { return (word7 >> 16) == 0xffffu; }
  uint32_t count() const { return word7 & 0xffffu; }
};

Node nodeAt(const std::vector<uint32_t>& nodes, size_t i) {
  Node n;
  std::memcpy(&n, &nodes[8 * i], sizeof n);
  return n;
}

// Walks the tree from `i`: checks boxes, returns the node after its subtree; counts each triangle.
size_t walk(const std::vector<uint32_t>& nodes, size_t i, const std::vector<float>& p, const std::vector<uint32_t>& index,
            std::vector<int>& seen, int depth, float parentLo[3], float parentHi[3]) {
  const Node n = nodeAt(nodes, i);
  for (int k = 0; k < 3; ++k) {
    EXPECT_LE(parentLo[k], n.lo[k]);
    EXPECT_GE(parentHi[k], n.hi[k]);
  }
  if (n.leaf()) {
    EXPECT_GT(n.count(), 0u) << "node " << i;
    // More than 10 only where no split separates them (here: the repeated triangle) or at depth 40.
    if (n.count() > 10 && depth < 40)
      for (uint32_t t = n.word6 + 1; t < n.word6 + n.count(); ++t)
        EXPECT_TRUE(std::equal(&index[3 * t], &index[3 * t] + 3, &index[3 * n.word6])) << "a leaf of " << n.count() << " at node " << i;
    for (uint32_t t = n.word6; t < n.word6 + n.count(); ++t) {
      seen[t]++;
      for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k) {
          EXPECT_LE(n.lo[k], p[3 * index[3 * t + j] + k]);
          EXPECT_GE(n.hi[k], p[3 * index[3 * t + j] + k]);
        }
    }
    return i + 1;
  }
  EXPECT_LT(n.word7, 3u) << "the split axis of node " << i;
  float lo[3], hi[3];
  std::copy(n.lo, n.lo + 3, lo), std::copy(n.hi, n.hi + 3, hi);
  const size_t afterLeft = walk(nodes, i + 1, p, index, seen, depth + 1, lo, hi);
  EXPECT_EQ(afterLeft, i + n.word6) << "the right child follows the left subtree";
  return walk(nodes, i + n.word6, p, index, seen, depth + 1, lo, hi);
}

std::vector<float> soup(std::mt19937& rng, size_t triangles, std::vector<uint32_t>& index) {
  std::uniform_real_distribution<float> u(-1, 1);
  std::vector<float> p(9 * triangles);
  for (float& x : p) x = u(rng);
  index.resize(3 * triangles);
  for (size_t i = 0; i < index.size(); ++i) index[i] = static_cast<uint32_t>(i);
  std::shuffle(index.begin(), index.end(), rng);  // corners shared between triangles
  return p;
}

}  // namespace

TEST(BvhBuild, WellFormedOnRandomSoups) {
  std::mt19937 rng(5);
  for (size_t triangles : {1u, 7u, 11u, 100u, 5000u}) {
    std::vector<uint32_t> index;
    const std::vector<float> p = soup(rng, triangles, index);
    // Some triangles repeated: their centres coincide.
    if (triangles >= 100)
      for (size_t t = 50; t < 80; ++t) std::copy(index.begin() + 3 * 10, index.begin() + 3 * 11, index.begin() + 3 * t);
    std::vector<uint32_t> original = index, again = index;
    const std::vector<uint32_t> nodes = buildThreeMeshBvh(p, index);
    ASSERT_EQ(nodes.size() % 8, 0u);
    // The index holds the same triangles (as corner triples), reordered.
    auto triples = [](const std::vector<uint32_t>& v) {
      std::vector<std::array<uint32_t, 3>> out(v.size() / 3);
      for (size_t t = 0; t < out.size(); ++t) out[t] = {v[3 * t], v[3 * t + 1], v[3 * t + 2]};
      std::sort(out.begin(), out.end());
      return out;
    };
    EXPECT_EQ(triples(index), triples(original));
    std::vector<int> seen(triangles, 0);
    float lo[3] = {-1e30f, -1e30f, -1e30f}, hi[3] = {1e30f, 1e30f, 1e30f};
    EXPECT_EQ(walk(nodes, 0, p, index, seen, 0, lo, hi), nodes.size() / 8);
    EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int s) { return s == 1; })) << triangles << " triangles";
    // Deterministic.
    EXPECT_EQ(buildThreeMeshBvh(p, again), nodes);
    EXPECT_EQ(again, index);
  }
}

TEST(BvhBuild, BadInputRefused) {
  std::vector<float> p(9, 0.0f);
  std::vector<uint32_t> outOfRange = {0, 1, 3}, partial = {0, 1}, none;
  EXPECT_THROW(buildThreeMeshBvh(p, outOfRange), Error);
  EXPECT_THROW(buildThreeMeshBvh(p, partial), Error);
  EXPECT_THROW(buildThreeMeshBvh(p, none), Error);
  std::vector<float> ragged(8, 0.0f);
  std::vector<uint32_t> one = {0, 1, 2};
  EXPECT_THROW(buildThreeMeshBvh(ragged, one), Error);
  try {
    buildThreeMeshBvh(p, outOfRange);
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("refers to vertex 3"), std::string::npos) << e.what();
  }
}
