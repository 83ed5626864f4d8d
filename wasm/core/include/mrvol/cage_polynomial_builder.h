// The volume as a cubic polynomial of the level-e cage (CagePolynomial), built directly from the
// fine mesh's volume form and the cage's basis functions instead of from theta^e: O(N) time and
// memory.
//
// Fine position (relative to the origin) p_v = sum_c B_c(v) x_c + D_v, with B_c the zero-detail
// synthesis of a unit at cage vertex c (sparse), x_c = cage coefficient - origin and D the
// synthesis of the fixed details with a zero cage. The volume is a trilinear form of the fine
// positions, sum_t w_t det(p_a, p_b, p_c) (FineForm: the triangles with weight 1/6, or the four
// triangles of weight 1/12 of each bilinear quad patch). Per term, by Cauchy-Binet, det is the
// 3 x 3 minors of w_a, w_b, w_c in R^(s + 3) (the s cage weights of a vertex followed by its D)
// against the minors of [x_1 .. x_s | I_3]. The terms are grouped by level-e face (their s
// influencing cage vertices are few and fixed per face), and per face the minors are summed as
// sum_a w_a (x) G_a, G_a = sum of w_t w_b ^ w_c over the terms given to a (their first corner):
// the fewer corners carry terms the cheaper (for triangles one corner of a 3-colouring class of the
// face's lattice, about a third of the vertices). Cost per carrying vertex ~ (s + 3)^3 / 2.
#pragma once
#include <cstdint>
#include <vector>

#include "mrvol/lifting.h"
#include "mrvol/cage_polynomial.h"
#include "mrvol/volume_tensor.h"

namespace mrvol {

// The level-e cage basis functions at the fine level by rows, a stencil table: fine vertex v
// (hierarchy order) has the weights value[p] of cage vertices index[p] (ascending) for p in
// [offset[v], offset[v + 1]); the zero-detail synthesis of cage coefficients x is sum_p value[p] x_index[p].
struct CageBasis {
  std::vector<uint64_t> offset{0};
  std::vector<uint32_t> index;
  std::vector<double> value;
};
// A cage of at most denseCageUpTo vertices is carried as dense columns (a few passes over the
// steps, in chunks of at most denseBytes), a larger one on sparse rows: the same rows, bit for bit.
CageBasis cageBasis(const WaveletTransform& transform, int level, uint32_t denseCageUpTo = 32,
                    size_t denseBytes = size_t(64) << 20);

// A volume form grouped by level-e face: term t of `form` (hierarchy numbering) lies in region
// region[t] < regionCount, and its first corner carries it (any choice is exact; see above).
struct RegionForm {
  FineForm form;
  std::vector<uint32_t> region;
  size_t regionCount = 0;
  // Optional (empty: the builder finds them): each region's fine vertices, ascending, in
  // [vertexStart[r], vertexStart[r + 1]) of `vertices` (triangleRegions has them already).
  std::vector<uint32_t> vertexStart, vertices;
};

class CagePolynomialBuilder {
 public:
  // Precomputes what depends on connectivity and scheme only: the cage basis functions at the
  // fine level, the grouping of the fine triangles by level-e face, and the polynomial's terms.
  // Throws Error when the faces would touch more than maxTerms cage triples in all (a fine cage:
  // about 220 per level-e face for Loop; such a polynomial is no faster than the matrix-free path).
  // basisOut, when given, receives the cage basis rows (cageBasis) it made, for a CageBasisTable
  // (the rows are not made twice); else they are freed.
  CagePolynomialBuilder(const WaveletTransform& transform, int level, uint64_t maxTerms = 8'000'000, CageBasis* basisOut = nullptr);
  // The same for any volume form grouped by regions (quad meshes: bilinearPatchRegions, quad_volume.h).
  CagePolynomialBuilder(const WaveletTransform& transform, int level, const RegionForm& form, uint64_t maxTerms = 8'000'000,
                        CageBasis* basisOut = nullptr);

  // coefficients: 3 N level-e coefficients in hierarchy order; only the details are read. The
  // polynomial's variables are the cage coefficients minus any point o (VolumeEditor's origin),
  // its value the volume about o (the signed cone volume to o for a mesh with boundary): a
  // translation changes only the cage coefficients (the basis functions sum to one), so the
  // polynomial does not depend on o.
  CagePolynomial build(const double* coefficients) const;

  int level() const { return level_; }
  uint32_t cageSize() const { return cageSize_; }
  size_t regionCount() const { return regionCage_.size() - 1; }
  size_t maxRegionCage() const { return maxCage_; }         // largest s over the faces
  size_t basisEntries() const { return basisEntries_; }     // sum over fine vertices of their cage weights
  size_t bytes() const;                                     // memory of the precomputed tables

 private:
  const WaveletTransform* transform_;
  int level_;
  uint32_t cageSize_;
  size_t maxCage_ = 0, basisEntries_ = 0;
  // Per level-e face (region) r, CSR-like starts into the arrays below.
  std::vector<uint32_t> regionCage_;       // -> cage_: its influencing cage vertices, ascending
  std::vector<uint32_t> regionVertex_;     // -> vertex_: its fine vertices (hierarchy indices), ascending
  std::vector<uint64_t> regionWeight_;     // -> weight_: dense local weights, one row of s per vertex
  std::vector<uint32_t> regionRun_;        // -> runVertex_ / runStart_: triangles by carrying vertex
  std::vector<uint64_t> regionTriple_;     // -> tripleSlot_: C(s, 3) slots into the polynomial's triples
  std::vector<uint64_t> regionPair_;       // -> pairSlot_: C(s, 2) slots into its pairs
  std::vector<uint32_t> cage_, vertex_;
  std::vector<double> weight_;
  std::vector<uint32_t> runVertex_;        // local vertex a of each run
  std::vector<uint32_t> runStart_;         // -> triangleB_ / triangleC_ (one more than the runs)
  std::vector<uint32_t> triangleB_, triangleC_;  // local (b, c): the term (a, b, c), orientation kept
  std::vector<double> triangleWeight_;           // its weight w_t
  std::vector<uint32_t> tripleSlot_, pairSlot_;
  // The polynomial's terms, ascending (i < j < k, i < j), before the exact zeros are dropped.
  std::vector<uint32_t> tripleI_, tripleJ_, tripleK_, pairI_, pairJ_;

  // Region r's minors for build(), in the order it adds them (w, wedges, outer: scratch).
  void regionMinors(size_t r, const double* detail, std::vector<double>& w, std::vector<double>& wedges,
                    std::vector<double>& outer, double* out) const;
  static constexpr size_t kRegionsPerChunk = 1024;  // regions whose minors are held at once
};

}  // namespace mrvol
