#include "mrvol/stencil_table.h"

#include <algorithm>

#include "mrvol/vector3.h"

namespace mrvol {

StencilTable::StencilTable(const WaveletTransform& transform, int level)
    : transform_(&transform), level_(level), vertexCount_(transform.hierarchy().fineVertexCount()) {}

size_t StencilTable::find(uint32_t c) {
  ++clock_;
  for (size_t s = 0; s < vertex_.size(); ++s)
    if (vertex_[s] == c) return used_[s] = clock_, s;
  // The scheme acts on each coordinate alike: synthesize the unit x and keep the x components.
  scratch_.assign(3 * vertexCount_, 0.0);
  scratch_[3 * size_t(c)] = 1.0;
  transform_->synthesizeZeroDetails(scratch_.data(), level_);
  vertex_.push_back(c);
  used_.push_back(clock_);
  for (size_t v = 0; v < vertexCount_; ++v)
    if (scratch_[3 * v] != 0.0) fineVertex_.push_back(uint32_t(v)), weight_.push_back(scratch_[3 * v]);
  start_.push_back(fineVertex_.size());
  // Bounded: the least recently used go first, the new one always stays.
  while (vertex_.size() > 1 && (vertex_.size() > kMaxStencils || fineVertex_.size() > 4 * vertexCount_)) {
    const size_t s = size_t(std::min_element(used_.begin(), used_.end()) - used_.begin());
    const size_t b = start_[s], e = start_[s + 1];
    fineVertex_.erase(fineVertex_.begin() + b, fineVertex_.begin() + e);
    weight_.erase(weight_.begin() + b, weight_.begin() + e);
    for (size_t t = s + 1; t < start_.size(); ++t) start_[t] -= e - b;
    start_.erase(start_.begin() + s);
    vertex_.erase(vertex_.begin() + s);
    used_.erase(used_.begin() + s);
  }
  return vertex_.size() - 1;
}

void StencilTable::add(uint32_t c, const double* d, double* fine, std::vector<uint32_t>* touched) {
  const size_t s = find(c);
  const uint32_t* v = fineVertex_.data();
  const double* w = weight_.data();
  for (size_t k = start_[s], end = start_[s + 1]; k < end; ++k) axpy(w[k], d, fine + 3 * size_t(v[k]));
  if (touched) touched->insert(touched->end(), v + start_[s], v + start_[s + 1]);
}

void StencilTable::stencil(uint32_t c, std::vector<uint32_t>& vertices, std::vector<double>& weights) {
  const size_t s = find(c);
  vertices.assign(fineVertex_.begin() + start_[s], fineVertex_.begin() + start_[s + 1]);
  weights.assign(weight_.begin() + start_[s], weight_.begin() + start_[s + 1]);
}

FinePositions::FinePositions(const WaveletTransform& transform, int level, Vec3 origin)
    : transform_(&transform),
      level_(level),
      cage3_(3 * size_t(transform.hierarchy().vertexCount[level])),
      origin_(origin),
      stencils_(transform, level) {}

const std::vector<double>& FinePositions::of(const std::vector<double>& x) {
  if (current_) return fine_;
  const size_t n3 = x.size();
  // Since the last synthesis only the cage moved (and not too often): add the zero-detail synthesis
  // of the move, along the stencils of a few moved vertices, else by a synthesis of the whole move.
  const bool incremental = base_ && incrementalUpdates_ < kResyncAfter;
  std::vector<uint32_t> moved;
  for (size_t i = 0; incremental && i < cage3_ && moved.size() <= kSparseMoveLimit; i += 3)
    if (x[i] != cage_[i] || x[i + 1] != cage_[i + 1] || x[i + 2] != cage_[i + 2]) moved.push_back(uint32_t(i / 3));
  if (incremental && moved.size() <= kSparseMoveLimit) {
    for (uint32_t c : moved) {
      const size_t i = 3 * size_t(c);
      const double d[3] = {x[i] - cage_[i], x[i + 1] - cage_[i + 1], x[i + 2] - cage_[i + 2]};
      // A follower is told the stencils' vertices, or everything once that is no shorter.
      stencils_.add(c, d, fine_.data(), changes_.whole ? nullptr : &changes_.vertices);
      if (changes_.vertices.size() > n3 / 24) changes_ = Changes{};
    }
    ++incrementalUpdates_;
  } else if (incremental) {
    delta_.resize(n3);
    for (size_t i = 0; i < cage3_; ++i) delta_[i] = x[i] - cage_[i];
    transform_->synthesizeZeroDetails(delta_.data(), level_);
    for (size_t i = 0; i < n3; ++i) fine_[i] += delta_[i];
    ++incrementalUpdates_;
    changes_ = Changes{};
  } else {
    // Synthesis commutes with translations of the cage: shifting the cage before synthesis gives the
    // fine positions relative to the origin without cancellation.
    fine_.assign(n3 + 3, 0.0);
    std::copy(x.begin(), x.end(), fine_.begin());
    for (size_t i = 0; i < cage3_; i += 3) fine_[i] -= origin_.x, fine_[i + 1] -= origin_.y, fine_[i + 2] -= origin_.z;
    transform_->synthesize(fine_.data(), level_);
    incrementalUpdates_ = 0;
    changes_ = Changes{};
  }
  cage_.assign(x.begin(), x.begin() + cage3_);
  current_ = base_ = true;
  ++version_;
  return fine_;
}

void FinePositions::followDirection(const std::vector<double>& x, double s, const std::vector<double>& q, bool detailsMoved) {
  if (detailsMoved) ++detailsVersion_;
  const size_t n3 = x.size();
  for (size_t i = 0; i < n3; ++i) fine_[i] += s * q[i];
  changes_ = Changes{};
  cage_.assign(x.begin(), x.begin() + cage3_);
  ++incrementalUpdates_;
  ++version_;
}

}  // namespace mrvol
