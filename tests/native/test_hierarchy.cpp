// Semi-regular hierarchies: Hierarchy::subdivide builds a consistent one (counts, depth numbering,
// ends and wings, the 1-to-4 split itself), Hierarchy::detect recovers an equivalent one from the
// fine mesh whatever its vertex and face order, and MultiresMesh transforms in the caller's order.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "fixtures.h"
#include "mrvol/corners.h"
#include "mrvol/error.h"
#include "mrvol/hierarchy.h"
#include "mrvol/lifting.h"
#include "mrvol/mesh.h"
#include "mrvol/multires_mesh.h"

using namespace mrvol;

namespace {

using Edge = std::pair<uint32_t, uint32_t>;
using Tri = std::array<uint32_t, 3>;

Edge edgeKey(uint32_t a, uint32_t b) { return {std::min(a, b), std::max(a, b)}; }

std::set<Edge> edgesOf(const std::vector<uint32_t>& faces) {
  std::set<Edge> edges;
  for (size_t f = 0; f < faces.size() / 3; ++f)
    for (int k = 0; k < 3; ++k) edges.insert(edgeKey(faces[3 * f + k], faces[3 * f + (k + 1) % 3]));
  return edges;
}

// Oriented triangle rotated so that its smallest index comes first.
Tri canonical(uint32_t a, uint32_t b, uint32_t c) {
  if (b < a && b < c) return {b, c, a};
  if (c < a && c < b) return {c, a, b};
  return {a, b, c};
}

std::vector<Tri> sortedTriangles(const std::vector<uint32_t>& faces) {
  std::vector<Tri> t;
  for (size_t f = 0; f < faces.size() / 3; ++f) t.push_back(canonical(faces[3 * f], faces[3 * f + 1], faces[3 * f + 2]));
  std::sort(t.begin(), t.end());
  return t;
}

// Vertices on an edge used by one face only.
std::vector<uint8_t> boundaryVertices(const std::vector<uint32_t>& faces, size_t vertexCount) {
  std::map<Edge, int> uses;
  for (size_t f = 0; f < faces.size() / 3; ++f)
    for (int k = 0; k < 3; ++k) ++uses[edgeKey(faces[3 * f + k], faces[3 * f + (k + 1) % 3])];
  std::vector<uint8_t> out(vertexCount, 0);
  for (auto& [e, n] : uses)
    if (n == 1) out[e.first] = out[e.second] = 1;
  return out;
}

MeshTopology topologyOf(const std::vector<uint32_t>& faces, size_t vertexCount) {
  TriangleMesh m;
  m.positions.assign(3 * vertexCount, 0.0);
  m.faces = faces;
  return validateMesh(m);
}

// Every structural property a hierarchy must have, whichever way it was built.
void expectConsistent(const Hierarchy& h, const std::string& where) {
  SCOPED_TRACE(where);
  const int n = h.levels;
  ASSERT_EQ(h.vertexCount.size(), size_t(n + 1));
  ASSERT_EQ(h.faces.size(), size_t(n + 1));
  const size_t N = h.fineVertexCount();
  ASSERT_EQ(h.ends.size(), 2 * N);
  ASSERT_EQ(h.wings.size(), 2 * N);
  ASSERT_EQ(h.boundary.size(), N);
  ASSERT_EQ(h.inputIndex.size(), N);
  ASSERT_EQ(h.hierarchyIndex.size(), N);
  for (uint32_t v = 0; v < N; ++v) {
    ASSERT_LT(h.inputIndex[v], N);
    ASSERT_EQ(h.hierarchyIndex[h.inputIndex[v]], v);
  }
  for (uint32_t v = 0; v < h.vertexCount[0]; ++v) {
    EXPECT_EQ(h.depth(v), 0);
    EXPECT_EQ(h.ends[2 * v], kNone);
    EXPECT_EQ(h.ends[2 * v + 1], kNone);
  }
  for (int l = 0; l <= n; ++l) {
    // Level l uses exactly the vertices [0, V_l) and is a valid mesh.
    const uint32_t V = h.vertexCount[l];
    std::vector<uint8_t> used(V, 0);
    for (uint32_t i : h.faces[l]) {
      ASSERT_LT(i, V) << "level " << l;
      used[i] = 1;
    }
    EXPECT_EQ(std::count(used.begin(), used.end(), 1), long(V)) << "level " << l;
    MeshTopology topo = topologyOf(h.faces[l], V);
    if (l == 0) continue;
    const uint32_t Vc = h.vertexCount[l - 1];
    const auto& coarse = h.faces[l - 1];
    MeshTopology coarseTopo = topologyOf(coarse, Vc);
    ASSERT_GT(V, Vc) << "level " << l;
    EXPECT_EQ(V, Vc + coarseTopo.edges) << "level " << l;
    EXPECT_EQ(h.faces[l].size(), 4 * coarse.size()) << "level " << l;
    EXPECT_EQ(topo.genus, coarseTopo.genus);
    EXPECT_EQ(topo.boundaryEdges, 2 * coarseTopo.boundaryEdges);
    // Odd vertices: depth l, ends on a coarse edge, wings opposite it.
    VertexCorners corners(coarse.data(), coarse.size() / 3, Vc);
    std::map<Edge, uint32_t> oddOfEdge;
    for (uint32_t e = Vc; e < V; ++e) {
      EXPECT_EQ(h.depth(e), l);
      const uint32_t a = h.ends[2 * e], b = h.ends[2 * e + 1], c = h.wings[2 * e], d = h.wings[2 * e + 1];
      ASSERT_LT(a, Vc) << "odd " << e;
      ASSERT_LT(b, Vc) << "odd " << e;
      ASSERT_NE(a, b) << "odd " << e;
      ASSERT_TRUE(oddOfEdge.emplace(edgeKey(a, b), e).second) << "two odd vertices on edge " << a << "-" << b;
      ASSERT_NE(c, kNone) << "odd " << e << " has no wing";
      ASSERT_LT(c, Vc);
      EXPECT_NE(c, a);
      EXPECT_NE(c, b);
      EXPECT_EQ(corners.opposite(a, b), c) << "odd " << e << ": (a, b, wing 0) is no coarse face";
      if (d == kNone) {
        EXPECT_EQ(corners.opposite(b, a), kNone) << "odd " << e << " lacks a wing on an interior edge";
        EXPECT_TRUE(h.boundary[e] && h.boundary[a] && h.boundary[b]) << "odd " << e;
      } else {
        ASSERT_LT(d, Vc);
        EXPECT_NE(d, a);
        EXPECT_NE(d, b);
        EXPECT_NE(d, c);
        EXPECT_EQ(corners.opposite(b, a), d) << "odd " << e << ": (b, a, wing 1) is no coarse face";
        EXPECT_FALSE(h.boundary[e]) << "odd " << e << " on an interior edge is flagged boundary";
      }
    }
    EXPECT_EQ(oddOfEdge.size(), coarseTopo.edges);
    // The fine faces are exactly the 1-to-4 split of the coarse faces through those odd vertices.
    std::vector<uint32_t> split;
    for (size_t f = 0; f < coarse.size() / 3; ++f) {
      uint32_t a = coarse[3 * f], b = coarse[3 * f + 1], c = coarse[3 * f + 2];
      auto ab = oddOfEdge.find(edgeKey(a, b)), bc = oddOfEdge.find(edgeKey(b, c)), ca = oddOfEdge.find(edgeKey(c, a));
      ASSERT_TRUE(ab != oddOfEdge.end() && bc != oddOfEdge.end() && ca != oddOfEdge.end());
      uint32_t p = ab->second, q = bc->second, r = ca->second;
      split.insert(split.end(), {a, p, r, p, b, q, r, q, c, p, q, r});
    }
    EXPECT_TRUE(sortedTriangles(split) == sortedTriangles(h.faces[l])) << "level " << l << " is not the split of level " << l - 1;
  }
  // Boundary flags: vertices on an edge of the fine mesh with one face.
  EXPECT_EQ(h.boundary, boundaryVertices(h.fineFaces(), N));
}

using fixtures::Shuffled;
using fixtures::shuffle;

// A base mesh split `levels` times, with the positions of zero-detail synthesis.
TriangleMesh splitMesh(const MultiresMesh& split, const TriangleMesh& base, const SchemeOptions& scheme) {
  return TriangleMesh{split.subdivisionPositions(base.positions, scheme), split.faces()};
}

// detect(shuffled) against the hierarchy the mesh was built with.
void expectEquivalent(const Hierarchy& built, const Hierarchy& found, const std::vector<uint32_t>& perm,
                      const TriangleMesh& shuffledMesh, const std::string& where) {
  SCOPED_TRACE(where);
  ASSERT_EQ(found.levels, built.levels);
  ASSERT_EQ(found.vertexCount, built.vertexCount);
  const size_t N = built.fineVertexCount();
  // Same base vertex set, in file indices.
  std::set<uint32_t> baseBuilt, baseFound;
  for (uint32_t v = 0; v < built.vertexCount[0]; ++v) baseBuilt.insert(perm[v]);
  for (uint32_t v = 0; v < found.vertexCount[0]; ++v) baseFound.insert(found.inputIndex[v]);
  ASSERT_EQ(baseFound, baseBuilt);
  for (uint32_t v = 0; v < N; ++v) {
    const uint32_t w = found.hierarchyIndex[perm[v]];  // the same vertex in the detected numbering
    ASSERT_EQ(found.depth(w), built.depth(v)) << "vertex " << v;
    EXPECT_EQ(found.boundary[w], built.boundary[v]) << "vertex " << v;
    if (built.depth(v) == 0) continue;
    Edge a = edgeKey(perm[built.ends[2 * v]], perm[built.ends[2 * v + 1]]);
    Edge b = edgeKey(found.inputIndex[found.ends[2 * w]], found.inputIndex[found.ends[2 * w + 1]]);
    EXPECT_EQ(a, b) << "ends of vertex " << v;
    std::set<uint32_t> wa{perm[built.wings[2 * v]]}, wb{found.inputIndex[found.wings[2 * w]]};
    if (built.wings[2 * v + 1] != kNone) wa.insert(perm[built.wings[2 * v + 1]]);
    if (found.wings[2 * w + 1] != kNone) wb.insert(found.inputIndex[found.wings[2 * w + 1]]);
    EXPECT_EQ(wa, wb) << "wings of vertex " << v;
  }
  // The detected finest level is the caller's faces, renumbered.
  std::vector<uint32_t> fine = shuffledMesh.faces;
  for (auto& i : fine) i = found.hierarchyIndex[i];
  EXPECT_EQ(found.fineFaces(), fine);
}

using fixtures::maxAbs;
using fixtures::maxDiff;

using fixtures::allSchemes;

using fixtures::label;

// Bases whose subdivisions have a unique tiling: every vertex's role is forced by the valences or
// the boundary. The regular torus grid is not among them: every parity class of its fine grid is
// an equally good base, so detection may legitimately choose another one.
bool uniqueTiling(const std::string& name) { return name != "torus"; }

// Detection finds every level there is, and the open patch fixture is itself one split of a
// hexagonal fan (centre 0, outer vertices 7, 9, ..., 17; its inner ring and the odd outer vertices
// are the midpoints). So detection finds one level more than was built on it.
int extraLevels(const std::string& name) { return name == "open-patch" ? 1 : 0; }

// The orientation-preserving automorphism of a connected mesh that maps directed edge (u0, v0) to
// (u1, v1), if there is one (it is determined by the image of one directed edge).
bool automorphism(const VertexCorners& vc, size_t nv, uint32_t u0, uint32_t v0, uint32_t u1, uint32_t v1,
                  std::vector<uint32_t>& sigma) {
  sigma.assign(nv, kNone);
  std::vector<uint8_t> taken(nv, 0), done(vc.next.size(), 0);
  auto assign = [&](uint32_t x, uint32_t y) {
    if (y == kNone) return false;
    if (sigma[x] != kNone) return sigma[x] == y;
    if (taken[y]) return false;
    sigma[x] = y, taken[y] = 1;
    return true;
  };
  auto corner = [&](uint32_t x, uint32_t y) -> uint32_t {
    for (uint32_t c = vc.begin(x); c < vc.end(x); ++c)
      if (vc.next[c] == y) return c;
    return kNone;
  };
  if (!assign(u0, u1) || !assign(v0, v1)) return false;
  std::vector<Edge> queue{{u0, v0}, {v0, u0}};
  while (!queue.empty()) {
    auto [x, y] = queue.back();
    queue.pop_back();
    uint32_t c = corner(x, y);
    if (c != kNone) {
      if (done[c]) continue;
      done[c] = 1;
    }
    uint32_t w = vc.opposite(x, y), w1 = vc.opposite(sigma[x], sigma[y]);
    if ((w == kNone) != (w1 == kNone)) return false;
    if (w == kNone) continue;
    if (!assign(w, w1)) return false;
    for (Edge e : {Edge{y, w}, Edge{w, y}, Edge{w, x}, Edge{x, w}}) queue.push_back(e);
  }
  for (uint32_t x = 0; x < nv; ++x)
    if (sigma[x] == kNone) return false;
  return true;
}

// detect(shuffled) is the built hierarchy moved by a symmetry of the mesh: same counts, and some
// automorphism maps base vertices to base vertices, depths to depths and ends to ends.
void expectEquivalentUpToTranslation(const Hierarchy& built, const Hierarchy& found, const std::vector<uint32_t>& perm,
                                     const TriangleMesh& mesh, const std::string& where) {
  SCOPED_TRACE(where);
  ASSERT_EQ(found.levels, built.levels);
  ASSERT_EQ(found.vertexCount, built.vertexCount);
  const size_t N = mesh.vertexCount();
  // Both hierarchies in file indices.
  std::vector<int> depthB(N), depthD(N);
  std::vector<Edge> endsB(N, {kNone, kNone}), endsD(N, {kNone, kNone});
  for (uint32_t v = 0; v < N; ++v) {
    depthB[perm[v]] = built.depth(v);
    if (built.depth(v) > 0) endsB[perm[v]] = edgeKey(perm[built.ends[2 * v]], perm[built.ends[2 * v + 1]]);
    const uint32_t x = found.inputIndex[v];
    depthD[x] = found.depth(v);
    if (found.depth(v) > 0) endsD[x] = edgeKey(found.inputIndex[found.ends[2 * v]], found.inputIndex[found.ends[2 * v + 1]]);
  }
  VertexCorners vc(mesh.faces.data(), mesh.faceCount(), N);
  const uint32_t u0 = perm[0], v0 = vc.next[vc.begin(u0)];
  std::vector<uint32_t> sigma;
  bool matched = false;
  for (uint32_t u1 = 0; u1 < N && !matched; ++u1) {
    if (depthD[u1] != 0) continue;
    for (uint32_t c = vc.begin(u1); c < vc.end(u1) && !matched; ++c) {
      if (!automorphism(vc, N, u0, v0, u1, vc.next[c], sigma)) continue;
      bool ok = true;
      for (uint32_t x = 0; x < N && ok; ++x) {
        const uint32_t y = sigma[x];
        ok = depthD[y] == depthB[x] &&
             (depthB[x] == 0 || endsD[y] == edgeKey(sigma[endsB[x].first], sigma[endsB[x].second]));
      }
      matched = ok;
    }
  }
  EXPECT_TRUE(matched) << "no symmetry of the mesh maps the built hierarchy to the detected one";
}

}  // namespace

TEST(Hierarchy, SubdivideCountsNumberingEndsAndWings) {
  for (const auto& fx : fixtures::baseFixtures())
    for (int levels = 0; levels <= 3; ++levels) {
      Hierarchy h = Hierarchy::subdivide(fx.base, levels);
      ASSERT_EQ(h.levels, levels);
      EXPECT_EQ(h.vertexCount[0], fx.base.vertexCount());
      EXPECT_EQ(h.faces[0], fx.base.faces);
      for (int l = 1; l <= levels; ++l) {
        EXPECT_EQ(h.vertexCount[l], h.vertexCount[l - 1] + topologyOf(h.faces[l - 1], h.vertexCount[l - 1]).edges);
        EXPECT_EQ(h.faces[l].size() / 3, 4 * (h.faces[l - 1].size() / 3));
      }
      // Subdivision keeps the caller's order: identity maps.
      for (uint32_t v = 0; v < h.fineVertexCount(); ++v) {
        EXPECT_EQ(h.inputIndex[v], v);
        EXPECT_EQ(h.hierarchyIndex[v], v);
      }
      expectConsistent(h, fx.name + " levels " + std::to_string(levels));
    }
}

TEST(Hierarchy, ClosedFormVertexCountForGenus0Bases) {
  for (const TriangleMesh& base : {fixtures::icosahedron(), fixtures::tetrahedron(), fixtures::octahedron()}) {
    Hierarchy h = Hierarchy::subdivide(base, 4);
    const uint32_t V0 = uint32_t(base.vertexCount());
    for (int l = 0; l <= 4; ++l) {
      EXPECT_EQ(h.vertexCount[l], (1u << (2 * l)) * (V0 - 2) + 2) << "V0 " << V0 << " level " << l;
      EXPECT_EQ(h.faces[l].size() / 3, (1u << (2 * l)) * base.faceCount());
    }
  }
  EXPECT_EQ(Hierarchy::subdivide(fixtures::icosahedron(), 4).vertexCount,
            (std::vector<uint32_t>{12, 42, 162, 642, 2562}));
}

TEST(Hierarchy, DetectRecoversTheHierarchyOfAShuffledMesh) {
  for (const auto& fx : fixtures::baseFixtures())
    for (int levels = 0; levels <= 3; ++levels) {
      MultiresMesh built = MultiresMesh::subdivide(fx.base, levels);
      const Hierarchy& hb = built.hierarchy();
      for (unsigned seed : {1u, 2u, 3u}) {
        Shuffled s = shuffle(splitMesh(built, fx.base, SchemeOptions{}), 1000 * levels + seed);
        // Through the OBJ text, as a file would come.
        TriangleMesh read = readObj(writeObj(s.mesh));
        ASSERT_EQ(read.positions, s.mesh.positions);
        ASSERT_EQ(read.faces, s.mesh.faces);
        const std::string where = fx.name + " levels " + std::to_string(levels) + " seed " + std::to_string(seed);
        Hierarchy hd = Hierarchy::detect(read);
        EXPECT_EQ(hd.levels, levels + extraLevels(fx.name)) << where;
        // At most as many levels as were built: the same hierarchy.
        Hierarchy limited = extraLevels(fx.name) ? Hierarchy::detect(read, levels) : hd;
        ASSERT_EQ(limited.levels, levels) << where;
        if (extraLevels(fx.name)) expectConsistent(hd, where + " (detected, all levels)");
        expectConsistent(limited, where + " (detected)");
        if (uniqueTiling(fx.name)) expectEquivalent(hb, limited, s.perm, read, where);
        else expectEquivalentUpToTranslation(hb, limited, s.perm, read, where);
      }
    }
}

TEST(Hierarchy, DetectLimitsLevelsToMaxLevels) {
  Hierarchy hb = Hierarchy::subdivide(fixtures::icosahedron(), 3);
  TriangleMesh m;
  m.faces = hb.fineFaces();
  m.positions.assign(3 * hb.fineVertexCount(), 1.0);
  for (size_t i = 0; i < m.positions.size(); ++i) m.positions[i] = double(i % 7);
  for (int maxLevels = 0; maxLevels <= 4; ++maxLevels) {
    Hierarchy h = Hierarchy::detect(m, maxLevels);
    EXPECT_EQ(h.levels, std::min(maxLevels, 3));
    EXPECT_EQ(h.vertexCount[0], hb.vertexCount[3 - h.levels]);
    expectConsistent(h, "maxLevels " + std::to_string(maxLevels));
  }
}

TEST(Hierarchy, BaseMeshesAreNoSplit) {
  for (const auto& fx : fixtures::baseFixtures()) {
    if (extraLevels(fx.name)) continue;
    Hierarchy h = Hierarchy::detect(fx.base);
    EXPECT_EQ(h.levels, 0) << fx.name;
    EXPECT_EQ(h.vertexCount, (std::vector<uint32_t>{uint32_t(fx.base.vertexCount())})) << fx.name;
    EXPECT_EQ(h.fineFaces(), fx.base.faces) << fx.name;
    expectConsistent(h, fx.name);
  }
}

TEST(Hierarchy, OpenPatchIsOneSplitOfAHexagonalFan) {
  const TriangleMesh patch = fixtures::openPatch();
  Hierarchy h = Hierarchy::detect(patch);
  ASSERT_EQ(h.levels, 1);
  expectConsistent(h, "open patch");
  std::vector<uint32_t> base(h.inputIndex.begin(), h.inputIndex.begin() + h.vertexCount[0]);
  std::sort(base.begin(), base.end());
  EXPECT_EQ(base, (std::vector<uint32_t>{0, 7, 9, 11, 13, 15, 17}));
  EXPECT_EQ(h.faces[0].size(), 18u);
  EXPECT_EQ(Hierarchy::detect(patch, 0).levels, 0);
}

TEST(Hierarchy, SubdividedMeshWithOneFaceFlippedIsRejected) {
  MultiresMesh built = MultiresMesh::subdivide(fixtures::icosahedron(), 2);
  for (size_t f : {size_t(0), size_t(17), built.faces().size() / 3 - 1}) {
    TriangleMesh m = splitMesh(built, fixtures::icosahedron(), SchemeOptions{});
    std::swap(m.faces[3 * f + 1], m.faces[3 * f + 2]);
    EXPECT_THROW(validateMesh(m), Error) << "face " << f;
    EXPECT_THROW(Hierarchy::detect(m), Error) << "face " << f;
    EXPECT_THROW(MultiresMesh mm(m), Error) << "face " << f;
    try {
      Hierarchy::detect(m);
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("orientation"), std::string::npos) << e.what();
    }
  }
}

TEST(Hierarchy, BoundaryFlagsOfTheOpenPatch) {
  const TriangleMesh base = fixtures::openPatch();
  for (int levels = 0; levels <= 3; ++levels) {
    Hierarchy h = Hierarchy::subdivide(base, levels);
    // The base's boundary is its outer ring, vertices 7..18; each split doubles the boundary.
    for (uint32_t v = 0; v < base.vertexCount(); ++v) EXPECT_EQ(h.boundary[v], v >= 7) << "base vertex " << v;
    EXPECT_EQ(std::count(h.boundary.begin(), h.boundary.end(), 1), long(12u << levels)) << "levels " << levels;
    EXPECT_FALSE(h.closed());
    // An odd vertex is on the boundary exactly when its coarse edge is (one wing).
    for (uint32_t e = h.vertexCount[0]; e < h.fineVertexCount(); ++e)
      EXPECT_EQ(bool(h.boundary[e]), h.wings[2 * e + 1] == kNone) << "odd " << e;
    EXPECT_EQ(h.boundary, boundaryVertices(h.fineFaces(), h.fineVertexCount()));
  }
  for (const auto& fx : fixtures::baseFixtures())
    if (fx.name != "open-patch") EXPECT_TRUE(Hierarchy::subdivide(fx.base, 2).closed()) << fx.name;
}

// Analysis in the caller's (shuffled) order, then synthesis, gives the positions back; zero-detail
// synthesis analyses to zero details and the base positions.
TEST(Hierarchy, MultiresRoundTripInShuffledOrderForEveryScheme) {
  for (const auto& fx : fixtures::baseFixtures()) {
    const int n = std::min(fx.levels, 3);
    Hierarchy hb = Hierarchy::subdivide(fx.base, n);
    TriangleMesh fine;
    fine.faces = hb.fineFaces();
    fine.positions = fixtures::randomVector(3 * hb.fineVertexCount(), 5);
    Shuffled s = shuffle(fine, 77);
    MultiresMesh mm(s.mesh, n);
    ASSERT_EQ(mm.levels(), n) << fx.name;
    EXPECT_EQ(MultiresMesh(s.mesh).levels(), n + extraLevels(fx.name)) << fx.name;
    for (const auto& scheme : allSchemes())
      for (int e = 0; e <= n; ++e) {
        const std::string where = fx.name + " " + label(scheme) + " e=" + std::to_string(e);
        auto c = mm.analyze(s.mesh.positions, e, scheme);
        auto back = mm.synthesize(c, e, scheme);
        EXPECT_LT(maxDiff(back, s.mesh.positions), 1e-12 * maxAbs(s.mesh.positions)) << where;
        EXPECT_LT(mm.roundtripError(s.mesh.positions, e, scheme), 1e-12 * maxAbs(s.mesh.positions)) << where;
        // Analysis to the finest level changes nothing.
        if (e == n) EXPECT_EQ(c, s.mesh.positions) << where;
      }
  }
}

TEST(Hierarchy, ZeroDetailSynthesisAnalysesToTheBaseInShuffledOrder) {
  for (const auto& fx : fixtures::baseFixtures()) {
    if (!uniqueTiling(fx.name)) continue;
    for (const auto& scheme : allSchemes()) {
      const std::string where = fx.name + " " + label(scheme);
      MultiresMesh built = MultiresMesh::subdivide(fx.base, 2);
      const TriangleMesh split = splitMesh(built, fx.base, scheme);
      Shuffled s = shuffle(split, 9);
      MultiresMesh mm(s.mesh, 2);
      ASSERT_EQ(mm.levels(), 2) << where;
      auto c = mm.analyze(s.mesh.positions, 0, scheme);
      const double scale = maxAbs(fx.base.positions);
      for (uint32_t v = 0; v < built.hierarchy().fineVertexCount(); ++v)
        for (int k = 0; k < 3; ++k) {
          const double got = c[3 * s.perm[v] + k];
          if (v < fx.base.vertexCount())
            EXPECT_NEAR(got, fx.base.positions[3 * v + k], 1e-12 * scale) << where << " base vertex " << v;
          else
            EXPECT_NEAR(got, 0.0, 1e-12 * scale) << where << " detail of vertex " << v;
        }
      // The info names the base vertices in the caller's indices, ascending.
      MeshInfo info = mm.info(s.mesh.positions);
      std::vector<uint32_t> expected(s.perm.begin(), s.perm.begin() + fx.base.vertexCount());
      std::sort(expected.begin(), expected.end());
      EXPECT_EQ(info.baseVertexIndices, expected) << where;
      EXPECT_EQ(info.levels, 2);
      EXPECT_NEAR(info.volume, meshVolume(split), 1e-12 * std::fabs(info.volume) + 1e-15);
    }
  }
}

namespace {

TriangleMesh subdivided(const TriangleMesh& base, int levels) {
  return splitMesh(MultiresMesh::subdivide(base, levels), base, SchemeOptions{});
}

TriangleMesh disjointUnion(TriangleMesh a, const TriangleMesh& b, double dx) {
  const uint32_t offset = uint32_t(a.vertexCount());
  for (size_t i = 0; i < b.positions.size(); ++i) a.positions.push_back(b.positions[i] + (i % 3 == 0 ? dx : 0.0));
  for (uint32_t f : b.faces) a.faces.push_back(f + offset);
  return a;
}

}  // namespace

TEST(Hierarchy, DetectSeveralComponentsAndSmallOpenMeshes) {
  TriangleMesh triangle;
  triangle.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  triangle.faces = {0, 1, 2};
  for (int l = 0; l <= 3; ++l) {
    Hierarchy h = Hierarchy::detect(shuffle(subdivided(triangle, l), 3 + l).mesh);
    EXPECT_EQ(h.levels, l) << "triangle";
    EXPECT_EQ(h.vertexCount[0], 3u);
    expectConsistent(h, "triangle levels " + std::to_string(l));
  }
  const TriangleMesh ico2 = subdivided(fixtures::icosahedron(), 2);
  struct Case {
    const char* name;
    TriangleMesh mesh;
    int levels;
    uint32_t baseVertices;
  };
  const Case cases[] = {
      {"two icosahedra, 2 levels each", disjointUnion(ico2, ico2, 10), 2, 24},
      {"2 levels and 1 level: the common levels", disjointUnion(ico2, subdivided(fixtures::icosahedron(), 1), 10), 1, 54},
      {"2 levels and a base: none", disjointUnion(ico2, fixtures::icosahedron(), 10), 0, 174},
      {"icosahedron and torus, 2 levels", disjointUnion(ico2, subdivided(fixtures::torus(), 2), 10), 2, 36},
  };
  for (const Case& c : cases) {
    Hierarchy h = Hierarchy::detect(shuffle(c.mesh, 8).mesh);
    EXPECT_EQ(h.levels, c.levels) << c.name;
    EXPECT_EQ(h.vertexCount[0], c.baseVertices) << c.name;
    expectConsistent(h, c.name);
  }
}

// The level-l faces the API hands out (the cage the editor draws) are the hierarchy's, in the
// caller's indices: every one of them is a triangle of that level's 1-to-4 split structure.
TEST(Hierarchy, LevelFacesAreTheCoarseMeshesInCallerIndices) {
  for (const auto& fx : fixtures::baseFixtures()) {
    mrvol::Hierarchy built = mrvol::Hierarchy::subdivide(fx.base, 2);
    mrvol::TriangleMesh fine;
    fine.faces = built.fineFaces();
    fine.positions.assign(3 * built.fineVertexCount(), 0.0);
    mrvol::MultiresMesh mr(fine, 2);
    EXPECT_EQ(mr.levelFaces(2), fine.faces);
    const auto base = mr.levelFaces(0);
    EXPECT_EQ(base.size(), fx.base.faces.size());
    mrvol::TriangleMesh coarse{std::vector<double>(3 * fine.vertexCount(), 0.0), base};
    // Valid oriented manifold on the base vertices (unused fine vertices aside): same volume sign.
    for (uint32_t v : base) EXPECT_EQ(mr.hierarchy().depth(mr.hierarchy().hierarchyIndex[v]), 0);
    EXPECT_THROW(mr.levelFaces(3), mrvol::Error);
  }
}

TEST(Corners, HubsOfHighValenceAreWalkedByBinarySearchWithTheSameAnswers) {
  // A bipyramid with a rim of k vertices: two hubs of valence k (sorted corners), rim vertices of
  // valence 4 (scanned). Then the same with the bottom removed: an open cone.
  for (bool open : {false, true}) {
    const uint32_t k = 500, top = 0, bottom = 1;
    std::vector<uint32_t> faces;
    for (uint32_t i = 0; i < k; ++i) {
      const uint32_t a = 2 + i, b = 2 + (i + 1) % k;
      faces.insert(faces.end(), {top, a, b});
      if (!open) faces.insert(faces.end(), {bottom, b, a});
    }
    VertexCorners vc(faces.data(), faces.size() / 3, k + 2);
    ASSERT_GT(vc.count(top), VertexCorners::kScanLimit);
    for (uint32_t i = 0; i < k; ++i) {
      const uint32_t a = 2 + i, b = 2 + (i + 1) % k;
      EXPECT_EQ(vc.opposite(top, a), b);
      EXPECT_EQ(vc.opposite(a, b), top);
      EXPECT_EQ(vc.opposite(top, b) == a, false);
      EXPECT_EQ(vc.opposite(b, a), open ? kNone : bottom);
      if (!open) EXPECT_EQ(vc.opposite(bottom, b), a);
    }
    EXPECT_EQ(vc.opposite(top, bottom), kNone);
    std::vector<uint32_t> ring;
    bool boundary = true;
    vc.ring(top, ring, &boundary);
    EXPECT_FALSE(boundary);
    ASSERT_EQ(ring.size(), k);
    for (uint32_t i = 0; i + 1 < k; ++i) EXPECT_EQ(ring[i + 1], 2 + (ring[i] - 2 + 1) % k);
    vc.ring(2, ring, &boundary);
    EXPECT_EQ(boundary, open);
    ASSERT_EQ(ring.size(), open ? 3u : 4u);
    if (open) EXPECT_EQ(ring[0], 2 + 1u);  // starts at the boundary neighbour v with face (u, v, .) only
  }
}

// MultiresMesh validates and detects in a local vertex numbering (vertex_order.h): the hierarchy
// it keeps must be the one detection in the caller's numbering finds, array for array (numbering,
// level faces, ends and wings in order, boundary), and the faces the caller's own.
TEST(Hierarchy, LocalNumberingGivesTheCallersHierarchy) {
  std::vector<std::pair<std::string, TriangleMesh>> meshes;
  for (const auto& fx : fixtures::baseFixtures())
    for (int levels : {0, 2})
      for (unsigned seed : {5u, 6u})
        meshes.emplace_back(fx.name + " levels " + std::to_string(levels) + " seed " + std::to_string(seed),
                            shuffle(subdivided(fx.base, levels), seed).mesh);
  TriangleMesh triangle;
  triangle.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  triangle.faces = {0, 1, 2};
  meshes.emplace_back("open triangle, 3 levels", shuffle(subdivided(triangle, 3), 9).mesh);
  const TriangleMesh ico2 = subdivided(fixtures::icosahedron(), 2);
  meshes.emplace_back("two components", shuffle(disjointUnion(ico2, subdivided(fixtures::torus(), 2), 10), 4).mesh);
  meshes.emplace_back("subdivided, unshuffled", ico2);
  for (const auto& [name, mesh] : meshes) {
    const Hierarchy expected = Hierarchy::detect(mesh);
    const MultiresMesh opened(mesh);
    const Hierarchy& h = opened.hierarchy();
    EXPECT_EQ(h.levels, expected.levels) << name;
    EXPECT_EQ(h.vertexCount, expected.vertexCount) << name;
    EXPECT_EQ(h.faces, expected.faces) << name;
    EXPECT_EQ(h.ends, expected.ends) << name;
    EXPECT_EQ(h.wings, expected.wings) << name;
    EXPECT_EQ(h.boundary, expected.boundary) << name;
    EXPECT_EQ(h.inputIndex, expected.inputIndex) << name;
    EXPECT_EQ(h.hierarchyIndex, expected.hierarchyIndex) << name;
    EXPECT_EQ(opened.faces(), mesh.faces) << name;
    const MeshTopology t = validateMesh(mesh);
    EXPECT_EQ(opened.topology().edges, t.edges) << name;
    EXPECT_EQ(opened.topology().boundaryEdges, t.boundaryEdges) << name;
    EXPECT_EQ(opened.topology().components, t.components) << name;
    EXPECT_EQ(opened.topology().genus, t.genus) << name;
    EXPECT_EQ(opened.info(mesh.positions).volume, meshVolume(mesh)) << name;
  }
}
