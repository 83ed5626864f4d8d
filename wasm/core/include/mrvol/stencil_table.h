// The fine positions of the level-e coefficients, kept in step with them while the cage moves.
//
// Synthesis is linear: when only the cage moved since the last synthesis, the fine positions move
// by the zero-detail synthesis of the cage move. For a move of a few cage vertices that is a sum of
// their basis stencils (the zero-detail synthesis of one cage vertex: its subdivision basis function
// at the fine level, sparse), built once per vertex and applied in a tight loop, as OpenSubdiv's
// far::StencilTable applies its stencils; a larger move takes one zero-detail synthesis, and a full
// synthesis now and then keeps rounding from building up.
#pragma once
#include <cstdint>
#include <vector>

#include "mrvol/lifting.h"
#include "mrvol/mesh.h"

namespace mrvol {

// Basis stencils of level-e cage vertices, built on first use and kept (the least recently used go
// first: at most kMaxStencils of them and 4 entries per fine vertex in all: coarse levels have wide supports).
class StencilTable {
 public:
  static constexpr size_t kMaxStencils = 8;
  StencilTable(const WaveletTransform& transform, int level);
  // fine += sum over the stencil of cage vertex c of weight * delta (a 3-vector); fine has 3 per vertex.
  // The fine vertices it wrote are appended to `touched` when given.
  void add(uint32_t cageVertex, const double* delta, double* fine, std::vector<uint32_t>* touched = nullptr);
  size_t stencilCount() const { return vertex_.size(); }
  // The stencil of c: fine vertices and weights (for tests).
  void stencil(uint32_t cageVertex, std::vector<uint32_t>& vertices, std::vector<double>& weights);

 private:
  size_t find(uint32_t cageVertex);  // builds it if missing; index into the arrays below
  const WaveletTransform* transform_;
  int level_;
  size_t vertexCount_;
  // Stencils as CSR: stencil s covers entries [start_[s], start_[s + 1]).
  std::vector<uint32_t> vertex_;  // cage vertex of each stencil
  std::vector<uint64_t> used_;    // when each was last used (clock_)
  uint64_t clock_ = 0;
  std::vector<size_t> start_{0};
  std::vector<uint32_t> fineVertex_;
  std::vector<double> weight_;
  std::vector<double> scratch_;
};

class FinePositions {
 public:
  // After this many incremental updates, a full synthesis.
  static constexpr int kResyncAfter = 64;
  // Moves of at most this many cage vertices go through the stencils.
  static constexpr size_t kSparseMoveLimit = 4;

  FinePositions(const WaveletTransform& transform, int level, Vec3 origin);

  // The synthesis of the coefficients x (3 N, hierarchy order) relative to the origin, with one more
  // vertex N at the origin: 3 (N + 1) doubles. Brought in step with x if it is not.
  const std::vector<double>& of(const std::vector<double>& x);
  // Whether of(x) would return without work; version() changes whenever the positions do.
  bool current() const { return current_; }
  uint64_t version() const { return version_; }
  // The coefficients changed: the cage only (an update along the stencils will do), or the details too.
  void cageChanged() { current_ = false; }
  void detailsChanged() { current_ = base_ = false, ++detailsVersion_; }
  // x has just moved by s times a direction whose synthesis is `synthesized` (3 (N + 1), vertex N
  // zero): the positions follow by the same multiple, no synthesis needed. detailsMoved: the
  // direction has detail entries (not only the cage's).
  void followDirection(const std::vector<double>& x, double s, const std::vector<double>& synthesized, bool detailsMoved = true);
  // Changes whenever the details of x may have (a follower that adds cage moves to a base of its own
  // starts afresh then: CageBasisTable).
  uint64_t detailsVersion() const { return detailsVersion_; }

  // What changed in the positions since the last takeChanges(), for a follower such as a renderer's
  // buffers: every vertex (whole), or the listed fine vertices (hierarchy order, repeats possible)
  // when only stencils of a few cage vertices were added.
  struct Changes {
    bool whole = true;
    std::vector<uint32_t> vertices;
  };
  void takeChanges(Changes& out) { out = std::move(changes_), changes_ = Changes{false, {}}; }

 private:
  const WaveletTransform* transform_;
  int level_;
  size_t cage3_;
  Vec3 origin_;
  StencilTable stencils_;
  std::vector<double> fine_;  // see of()
  // While base_, fine_ is the synthesis of x with its cage replaced by cage_ (the details agree).
  std::vector<double> cage_, delta_;
  bool current_ = false, base_ = false;
  int incrementalUpdates_ = 0;  // since the last full synthesis
  uint64_t version_ = 0, detailsVersion_ = 0;
  Changes changes_;
};

}  // namespace mrvol
