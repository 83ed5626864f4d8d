// libFuzzer target: structured fuzzing of quadrisection detection (Hierarchy::detect).
//
// The bytes choose a base mesh, a number of 1-to-4 splits (Hierarchy::subdivide), then small
// corruptions (flip a face, swap two indices, drop a face, redirect an index, flip an edge, drop
// a whole tile) and a relabelling (vertex permutation, corner rotation, face order).
// validateMesh must agree with the plain validator of reference_mesh.h, and detect must then
// either throw mrvol::Error (exactly for invalid meshes) or return a hierarchy that really is a
// chain of 1-to-4 splits ending in the given mesh. Without corruption, detect must find exactly
// the subdivision levels (plus one for the open patch, itself a split of a hexagon fan), the same
// vertex counts and, where the split is unique (every base but the torus), the same depth for
// every vertex. Every inconsistency calls __builtin_trap(). The Loop, Butterfly and linear
// transforms of the detected hierarchy must reconstruct random positions, and their synthesis
// adjoint must be the transpose of synthesis.
//
//   build/fuzz/fuzz_hierarchy build/fuzz/corpus-fuzz_hierarchy
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <map>
#include <new>
#include <numeric>
#include <vector>

#include "mrvol/corners.h"
#include "mrvol/error.h"
#include "mrvol/hierarchy.h"
#include "mrvol/lifting.h"
#include "mrvol/mesh.h"
#include "mrvol/multires_mesh.h"
#include "../native/fixtures.h"
#include "reference_mesh.h"

using mrvol::Hierarchy;
using mrvol::kNone;
using mrvol::TriangleMesh;

namespace {

void check(bool ok) {
  if (!ok) __builtin_trap();
}

// ---- the input bytes as a stream of choices (zeros once exhausted) ------------------------------
class Bytes {
 public:
  Bytes(const uint8_t* data, size_t size) : data_(data), size_(size) {}
  uint8_t byte() { return pos_ < size_ ? data_[pos_++] : 0; }
  // A number in [0, n) from as many bytes as n needs.
  uint32_t below(uint32_t n) {
    if (n <= 1) return 0;
    uint32_t x = byte();
    if (n > 256) x = x << 8 | byte();
    if (n > 65536) x = x << 8 | byte();
    return x % n;
  }

 private:
  const uint8_t* data_;
  size_t size_, pos_ = 0;
};

// ---- base meshes (tests/native/fixtures.h; positions are irrelevant to detection) ---------------
using fixtures::icosahedron;
using fixtures::octahedron;
using fixtures::openPatch;
using fixtures::tetrahedron;
// A 4 x 3 torus of quads split in two: genus 1, valence 6 everywhere.
TriangleMesh torus() { return fixtures::torus(4, 3); }

TriangleMesh triangle() {
  TriangleMesh m;
  m.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  m.faces = {0, 1, 2};
  return m;
}

// Two components: a tetrahedron and an open patch beside it.
TriangleMesh twoComponents() {
  TriangleMesh a = tetrahedron(), b = openPatch();
  uint32_t shift = uint32_t(a.vertexCount());
  for (size_t i = 0; i < b.positions.size(); i += 3) a.positions.insert(a.positions.end(), {b.positions[i] + 5, b.positions[i + 1], b.positions[i + 2]});
  for (uint32_t f : b.faces) a.faces.push_back(f + shift);
  return a;
}

// The open patch is itself one split of a hexagon fan: centre 0, rim 7, 9, ..., 17; the others
// are the midpoints. Its depth in a detected hierarchy is one more than subdivide says.
int intrinsicLevels(int kind) { return kind == 3 ? 1 : 0; }
int baseDepth(int kind, uint32_t v) {
  if (kind != 3) return 0;
  return v == 0 || (v >= 7 && (v - 7) % 2 == 0) ? 0 : 1;
}

constexpr int kBaseKinds = 7;
TriangleMesh base(int kind) {
  switch (kind) {
    case 0: return tetrahedron();
    case 1: return octahedron();
    case 2: return icosahedron();
    case 3: return openPatch();
    case 4: return torus();
    case 5: return triangle();
    default: return twoComponents();
  }
}

// ---- checks -------------------------------------------------------------------------------------

// A face as a key independent of its starting corner (orientation kept).
std::array<uint32_t, 3> faceKey(uint32_t a, uint32_t b, uint32_t c) {
  if (b < a && b < c) return {b, c, a};
  if (c < a && c < b) return {c, a, b};
  return {a, b, c};
}

std::vector<std::array<uint32_t, 3>> faceKeys(const std::vector<uint32_t>& faces) {
  std::vector<std::array<uint32_t, 3>> keys;
  for (size_t f = 0; f + 2 < faces.size(); f += 3) keys.push_back(faceKey(faces[f], faces[f + 1], faces[f + 2]));
  std::sort(keys.begin(), keys.end());
  return keys;
}

uint64_t edgeKey(uint32_t a, uint32_t b) { return uint64_t(std::min(a, b)) << 32 | std::max(a, b); }

// The hierarchy is a chain of 1-to-4 splits whose last level is `fine` in hierarchy numbering.
void checkConsistent(const Hierarchy& h, const TriangleMesh& fine) {
  const size_t nv = fine.vertexCount();
  check(h.levels >= 0);
  check(h.vertexCount.size() == size_t(h.levels) + 1 && h.faces.size() == size_t(h.levels) + 1);
  check(h.fineVertexCount() == nv);
  check(h.vertexCount[0] >= 3);
  for (int l = 1; l <= h.levels; ++l) check(h.vertexCount[l] > h.vertexCount[l - 1]);
  // Numbering: a permutation and its inverse.
  check(h.inputIndex.size() == nv && h.hierarchyIndex.size() == nv);
  std::vector<uint8_t> seen(nv, 0);
  for (uint32_t v : h.inputIndex) {
    check(v < nv && !seen[v]);
    seen[v] = 1;
  }
  for (uint32_t v = 0; v < nv; ++v) check(h.hierarchyIndex[v] < nv && h.inputIndex[h.hierarchyIndex[v]] == v);
  // Every fine face, in place and orientation.
  check(h.fineFaces().size() == fine.faces.size());
  for (size_t i = 0; i < fine.faces.size(); ++i) check(h.fineFaces()[i] == h.hierarchyIndex[fine.faces[i]]);
  // Levels use exactly their vertices; the base is a valid mesh with interior valence >= 3.
  for (int l = 0; l <= h.levels; ++l) {
    check(h.faces[l].size() % 3 == 0 && !h.faces[l].empty());
    std::vector<uint8_t> used(h.vertexCount[l], 0);
    for (uint32_t v : h.faces[l]) {
      check(v < h.vertexCount[l]);
      used[v] = 1;
    }
    check(std::find(used.begin(), used.end(), 0) == used.end());
  }
  {
    TriangleMesh coarse;
    coarse.positions.assign(3 * size_t(h.vertexCount[0]), 0.0);
    coarse.faces = h.faces[0];
    mrvol::validateMesh(coarse);  // throws: a detected base that is no manifold is a bug
  }
  check(h.ends.size() == 2 * nv && h.wings.size() == 2 * nv && h.boundary.size() == nv);
  for (uint32_t v = 0; v < h.vertexCount[0]; ++v) check(h.ends[2 * v] == kNone && h.ends[2 * v + 1] == kNone);
  for (int l = 1; l <= h.levels; ++l) {
    const uint32_t ne = h.vertexCount[l - 1], nf = h.vertexCount[l];
    const auto& coarse = h.faces[l - 1];
    mrvol::VertexCorners corners(coarse.data(), coarse.size() / 3, ne);
    // Ends: two distinct coarse vertices joined by a coarse edge; one odd vertex per coarse edge.
    std::map<uint64_t, uint32_t> midpoint;
    for (uint32_t m = ne; m < nf; ++m) {
      check(h.depth(m) == l);
      uint32_t a = h.ends[2 * m], b = h.ends[2 * m + 1];
      check(a < ne && b < ne && a != b);
      check(midpoint.emplace(edgeKey(a, b), m).second);
      // Wings: the third vertices of the coarse faces at the edge, the existing one first.
      uint32_t w0 = h.wings[2 * m], w1 = h.wings[2 * m + 1];
      uint32_t oab = corners.opposite(a, b), oba = corners.opposite(b, a);
      check(oab != kNone || oba != kNone);
      check(w0 != kNone && w0 < ne);
      check(w1 == kNone || w1 < ne);
      check((w0 == oab && w1 == oba) || (w0 == oba && w1 == oab));
    }
    std::vector<uint64_t> coarseEdges;
    for (size_t f = 0; f < coarse.size(); f += 3)
      for (int k = 0; k < 3; ++k) coarseEdges.push_back(edgeKey(coarse[f + k], coarse[f + (k + 1) % 3]));
    std::sort(coarseEdges.begin(), coarseEdges.end());
    coarseEdges.erase(std::unique(coarseEdges.begin(), coarseEdges.end()), coarseEdges.end());
    check(coarseEdges.size() == midpoint.size());
    // Splitting the coarse faces at the midpoints gives exactly the level-l faces.
    std::vector<uint32_t> split;
    for (size_t f = 0; f < coarse.size(); f += 3) {
      uint32_t a = coarse[f], b = coarse[f + 1], c = coarse[f + 2];
      auto find = [&](uint32_t u, uint32_t v) {
        auto it = midpoint.find(edgeKey(u, v));
        check(it != midpoint.end());
        return it->second;
      };
      uint32_t ab = find(a, b), bc = find(b, c), ca = find(c, a);
      split.insert(split.end(), {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca});
    }
    check(faceKeys(split) == faceKeys(h.faces[l]));
  }
  for (uint32_t v = h.vertexCount[0]; v < nv; ++v) check(h.depth(v) >= 1);
  // Boundary flags: the ends of the fine edges with one face.
  std::vector<uint64_t> halfEdges;
  for (size_t f = 0; f < h.fineFaces().size(); f += 3)
    for (int k = 0; k < 3; ++k) halfEdges.push_back(edgeKey(h.fineFaces()[f + k], h.fineFaces()[f + (k + 1) % 3]));
  std::sort(halfEdges.begin(), halfEdges.end());
  std::vector<uint8_t> boundary(nv, 0);
  for (size_t i = 0; i < halfEdges.size(); ++i) {
    bool single = (i == 0 || halfEdges[i - 1] != halfEdges[i]) && (i + 1 == halfEdges.size() || halfEdges[i + 1] != halfEdges[i]);
    if (single) boundary[halfEdges[i] >> 32] = boundary[halfEdges[i] & 0xffffffffu] = 1;
  }
  check(boundary == h.boundary);
}

// Every scheme's transform of the hierarchy reconstructs pseudo-random positions at every level
// (Loop only on the largest meshes, to keep executions fast).
// The adjoint of synthesis is its transpose: <g, S c> = <S^T g, c>; stride 1 (a scalar per
// vertex) gives each component of stride 3.
double dot(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0;
  for (size_t i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
}

void checkAdjoint(const mrvol::WaveletTransform& wt, const std::vector<double>& c, const std::vector<double>& g, int e) {
  std::vector<double> sc = c, stg = g;
  wt.synthesize(sc.data(), e);
  wt.synthesisAdjoint(stg.data(), e, 3);
  const double lhs = dot(g, sc), rhs = dot(stg, c);
  const double scale = std::sqrt(dot(g, g) * dot(sc, sc)) + std::sqrt(dot(stg, stg) * dot(c, c));
  check(std::fabs(lhs - rhs) <= 1e-10 * scale + 1e-300);
  const size_t n = g.size() / 3;
  std::vector<double> scalar(n);
  for (size_t v = 0; v < n; ++v) scalar[v] = g[3 * v + 1];
  wt.synthesisAdjoint(scalar.data(), e, 1);
  for (size_t v = 0; v < n; ++v) check(std::fabs(scalar[v] - stg[3 * v + 1]) <= 1e-12 * (1 + std::fabs(stg[3 * v + 1])));
}

void checkTransforms(const Hierarchy& h, uint32_t seed, bool allSchemes) {
  if (h.levels == 0) return;
  std::vector<double> x(3 * h.fineVertexCount()), g(x.size());
  uint64_t s = 0x9e3779b97f4a7c15ull ^ seed;
  for (std::vector<double>* vec : {&x, &g})
    for (double& v : *vec) {
      s = s * 6364136223846793005ull + 1442695040888963407ull;
      v = double(s >> 11) / double(1ull << 53) * 2 - 1;
    }
  for (auto kind : {mrvol::SchemeKind::Loop, mrvol::SchemeKind::Butterfly, mrvol::SchemeKind::Linear}) {
    if (kind != mrvol::SchemeKind::Loop && !allSchemes) break;
    mrvol::SchemeOptions options;
    options.kind = kind;
    mrvol::WaveletTransform wt(h, options);
    for (int e = 0; e <= h.levels; e += 1 + (h.levels > 1)) {
      std::vector<double> y = x;
      wt.analyze(y.data(), e);
      wt.synthesize(y.data(), e);
      double err = 0;
      for (size_t i = 0; i < x.size(); ++i) err = std::fmax(err, std::fabs(x[i] - y[i]));
      check(err < 1e-9);
      checkAdjoint(wt, x, g, e);
    }
  }
}

void run(const uint8_t* data, size_t size) {
  Bytes in(data, size);
  const int kind = in.byte() % kBaseKinds;
  const int levels = in.byte() % 4;
  const TriangleMesh coarse = base(kind);
  const Hierarchy original = Hierarchy::subdivide(coarse, levels);
  const uint32_t nv = uint32_t(original.fineVertexCount());
  TriangleMesh fine;
  fine.faces = original.fineFaces();
  fine.positions.resize(3 * size_t(nv));
  for (uint32_t v = 0; v < nv; ++v)
    for (int k = 0; k < 3; ++k) fine.positions[3 * v + k] = std::sin(1.7 * v + 2.3 * k);

  // Corruptions, on the subdivision's own numbering.
  const int corruptions = in.byte() % 4;
  for (int i = 0; i < corruptions; ++i) {
    const uint32_t nf = uint32_t(fine.faceCount());
    if (nf <= 1) break;
    switch (in.byte() % 6) {
      case 0: {  // flip one face
        uint32_t f = in.below(nf);
        std::swap(fine.faces[3 * f + 1], fine.faces[3 * f + 2]);
        break;
      }
      case 1: {  // swap two indices anywhere
        uint32_t a = in.below(3 * nf), b = in.below(3 * nf);
        std::swap(fine.faces[a], fine.faces[b]);
        break;
      }
      case 2: {  // drop one face
        uint32_t f = in.below(nf);
        fine.faces.erase(fine.faces.begin() + 3 * f, fine.faces.begin() + 3 * f + 3);
        break;
      }
      case 3: {  // point one corner at another vertex
        uint32_t a = in.below(3 * nf);
        fine.faces[a] = in.below(nv);
        break;
      }
      case 4: {  // flip an interior edge: (a, b, c) + (b, a, d) -> (c, a, d) + (d, b, c); stays valid
                 // unless c and d are already neighbours, and keeps the face count
        uint32_t f = in.below(nf), k = in.below(3);
        uint32_t a = fine.faces[3 * f + k], b = fine.faces[3 * f + (k + 1) % 3], c = fine.faces[3 * f + (k + 2) % 3];
        for (uint32_t g = 0; g < nf; ++g)
          for (uint32_t j = 0; j < 3; ++j)
            if (fine.faces[3 * g + j] == b && fine.faces[3 * g + (j + 1) % 3] == a) {
              uint32_t d = fine.faces[3 * g + (j + 2) % 3];
              const uint32_t ff[3] = {c, a, d}, gg[3] = {d, b, c};
              std::copy(ff, ff + 3, fine.faces.begin() + 3 * f);
              std::copy(gg, gg + 3, fine.faces.begin() + 3 * g);
              g = nf;
              break;
            }
        break;
      }
      default: {  // drop the four faces of one split triangle (a hole; still a split mesh)
        if (levels == 0 || nf % 4 != 0) break;
        uint32_t t = in.below(nf / 4);
        fine.faces.erase(fine.faces.begin() + 12 * t, fine.faces.begin() + 12 * t + 12);
        break;
      }
    }
  }
  const bool corrupted = fine.faces != original.fineFaces();

  // Relabelling: vertex permutation, corner rotation, face order. None changes the mesh.
  const uint8_t relabel = in.byte();
  std::vector<uint32_t> perm(nv);
  std::iota(perm.begin(), perm.end(), 0u);
  if (relabel & 1)
    for (uint32_t i = nv - 1; i > 0; --i) std::swap(perm[i], perm[in.below(i + 1)]);
  else if (relabel & 8)
    std::reverse(perm.begin(), perm.end());
  TriangleMesh input;
  input.positions.resize(fine.positions.size());
  for (uint32_t v = 0; v < nv; ++v)
    for (int k = 0; k < 3; ++k) input.positions[3 * perm[v] + k] = fine.positions[3 * v + k];
  const uint32_t nf = uint32_t(fine.faceCount());
  std::vector<uint32_t> order(nf);
  std::iota(order.begin(), order.end(), 0u);
  if (relabel & 2)
    for (uint32_t i = nf > 0 ? nf - 1 : 0; i > 0; --i) std::swap(order[i], order[in.below(i + 1)]);
  for (uint32_t f : order) {
    uint32_t r = (relabel & 4) ? in.byte() % 3 : 0;
    for (uint32_t k = 0; k < 3; ++k) input.faces.push_back(perm[fine.faces[3 * f + (k + r) % 3]]);
  }

  bool valid = false;
  const reference::Topology plain = reference::validate(input);
  try {
    mrvol::MeshTopology topology = mrvol::validateMesh(input);
    check(topology.edges == plain.edges && topology.boundaryEdges == plain.boundaryEdges &&
          topology.components == plain.components);
    valid = true;
  } catch (const mrvol::Error&) {
  }
  check(valid == plain.valid);  // the plain reference implementation agrees
  if (!corrupted) check(valid);    // a subdivided base mesh is always valid
  if (!valid) {
    // detect validates first: it must refuse the same meshes.
    try {
      (void)Hierarchy::detect(input);
    } catch (const mrvol::Error&) {
      return;
    }
    __builtin_trap();
  }

  const Hierarchy h = Hierarchy::detect(input);
  checkConsistent(h, input);
  // MultiresMesh detects in a local vertex numbering (vertex_order.h): the very same hierarchy.
  if (input.faceCount() <= 4096) {
    const mrvol::MultiresMesh opened(input);
    const Hierarchy& o = opened.hierarchy();
    check(o.levels == h.levels && o.vertexCount == h.vertexCount && o.faces == h.faces && o.ends == h.ends &&
          o.wings == h.wings && o.boundary == h.boundary && o.inputIndex == h.inputIndex &&
          o.hierarchyIndex == h.hierarchyIndex && opened.faces() == input.faces);
  }
  const int expected = levels + intrinsicLevels(kind);
  check(h.levels <= expected);
  if (!corrupted) {
    check(h.levels == expected);
    check(std::equal(original.vertexCount.begin(), original.vertexCount.end(), h.vertexCount.end() - (levels + 1)));
    // The split is unique except on the torus, whose regular lattice has shifted tilings.
    if (kind != 4)
      for (uint32_t v = 0; v < nv; ++v) {
        int d = original.depth(v);
        check(h.depth(h.hierarchyIndex[perm[v]]) == (d == 0 ? baseDepth(kind, v) : d + intrinsicLevels(kind)));
      }
  }
  // A maxLevels bound stops detection early, from the top: the finest levels are found first.
  const bool small = input.faceCount() <= 1024;
  if (h.levels > 0 && small) {
    const Hierarchy capped = Hierarchy::detect(input, h.levels - 1);
    checkConsistent(capped, input);
    check(capped.levels == h.levels - 1);
    for (int l = 0; l <= capped.levels; ++l) check(capped.vertexCount[l] == h.vertexCount[l + 1]);
  }
  checkTransforms(h, uint32_t(size), small);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    run(data, size);
  } catch (const mrvol::Error&) {
    // Only validateMesh/detect may refuse, and run() traps where that would be wrong; an Error
    // from checkConsistent's validateMesh of the detected base is a bug too, so it traps here.
    __builtin_trap();
  }
  return 0;
}
