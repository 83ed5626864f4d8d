#include "mrvol/coefficient_volumes.h"

#include <algorithm>

#include "mrvol/vector3.h"
#include "mrvol/volume_function.h"

namespace mrvol {

namespace {
// Scatters a vector over the free coefficients (3 each, free order) into a full one.
void scatter(const std::vector<uint32_t>& free, const double* compact, double* full) {
  for (size_t i = 0; i < free.size(); ++i)
    for (int k = 0; k < 3; ++k) full[3 * size_t(free[i]) + k] = compact[3 * i + k];
}
void gather(const std::vector<uint32_t>& free, const double* full, double* compact) {
  for (size_t i = 0; i < free.size(); ++i)
    for (int k = 0; k < 3; ++k) compact[3 * i + k] = full[3 * size_t(free[i]) + k];
}
void moveFree(const std::vector<uint32_t>& free, const double* direction, double s, std::vector<double>& x) {
  for (size_t i = 0; i < free.size(); ++i) axpy(s, direction + 3 * i, &x[3 * size_t(free[i])]);
}
}  // namespace

void SessionCoefficients::shiftedCage(std::vector<double>& out) const {
  out.assign(x.begin(), x.begin() + 3 * size_t(cageSize));
  for (size_t i = 0; i < out.size(); i += 3) out[i] -= origin.x, out[i + 1] -= origin.y, out[i + 2] -= origin.z;
}

double CageVolumeConstraint::value() {
  session_->shiftedCage(cage_);
  if (cage_ != valueCage_) {
    if (gradientFollowed_) gradient_.resize(cage_.size());
    value_ = volume_->value(cage_.data(), gradientFollowed_ ? gradient_.data() : nullptr);
    valueCage_ = cage_;
    gradientCurrent_ = gradientFollowed_;
    gradientFollowed_ = false;
  }
  return value_;
}

void CageVolumeConstraint::evaluate(double* values) { values[0] = value(); }

void CageVolumeConstraint::gradients(const std::vector<uint32_t>& free, double* gradients) {
  value();  // the cage of the last value (valueCage_) is the current one
  gradientFollowed_ = true;
  if (!gradientCurrent_) {
    gradient_.resize(cage_.size());
    volume_->value(cage_.data(), gradient_.data());
    gradientCurrent_ = true;
  }
  gather(free, gradient_.data(), gradients);
}

void CageVolumeConstraint::alongDirection(const std::vector<uint32_t>& free, const double* direction, double* k) {
  session_->shiftedCage(cage_);
  direction_.assign(cage_.size(), 0.0);
  scatter(free, direction, direction_.data());
  volume_->alongDirection(cage_.data(), direction_.data(), k, true);
}

void CageVolumeConstraint::step(const std::vector<uint32_t>& free, const double* direction, double s, const double*) {
  moveFree(free, direction, s, session_->x);
  session_->fine.cageChanged();
}

void FineVolumeConstraints::setRows(const VolumeFunction& first, std::vector<const FineFunction*> more, bool detailsFree) {
  first_ = &first;
  rows_ = {&first};
  rows_.insert(rows_.end(), more.begin(), more.end());
  references.clear();
  scales.clear();
  detailsFree_ = detailsFree;
  cacheVersion_ = ~uint64_t(0);
  gradientCached_ = false;
}

double FineVolumeConstraints::value() {
  const std::vector<double>& p = session_->fine.of(session_->x);
  if (cacheVersion_ != session_->fine.version()) {
    cachedValue_ = rows_[0]->value(p.data(), nullptr);
    cacheVersion_ = session_->fine.version();
    gradientCached_ = false;
  }
  return cachedValue_;
}

double FineVolumeConstraints::valueWithGradient() {
  const std::vector<double>& p = session_->fine.of(session_->x);
  if (cacheVersion_ != session_->fine.version() || !gradientCached_) {
    gradient_.resize(p.size());
    cachedValue_ = rows_[0]->value(p.data(), gradient_.data());
    cacheVersion_ = session_->fine.version();
    gradientCached_ = true;
  }
  return cachedValue_;
}

void FineVolumeConstraints::evaluate(double* values) {
  const std::vector<double>& p = session_->fine.of(session_->x);
  values[0] = valueWithGradient();
  rowGradients_.resize(rows_.size() - 1);
  // The centre of mass's three moments in one pass (they share each triangle's cross products).
  size_t r = 1;
  momentsTogether_ = false;
  if (rows_.size() >= 4) {
    momentGradients_.resize(3 * p.size());
    momentsTogether_ = FirstMoment::valuesWithGradients(&rows_[1], p.data(), values + 1, momentGradients_.data());
    if (momentsTogether_) r = 4;
  }
  for (; r < rows_.size(); ++r) {
    rowGradients_[r - 1].resize(p.size());
    values[r] = rows_[r]->value(p.data(), rowGradients_[r - 1].data());
  }
}

void FineVolumeConstraints::gradients(const std::vector<uint32_t>& free, double* gradients) {
  const size_t m3 = 3 * free.size();
  for (size_t r = 0; r < rows_.size(); ++r) {
    if (momentsTogether_ && r >= 1 && r <= 3) {
      // the three moments' gradients carried in one adjoint of stride 9, then taken apart
      if (r == 1) transform_->synthesisAdjoint(momentGradients_.data(), level_, 9, detailsFree_);
      const size_t axis = r - 1;
      double* out = gradients + r * m3;
      for (size_t i = 0; i < free.size(); ++i)
        for (int k = 0; k < 3; ++k) out[3 * i + k] = momentGradients_[9 * size_t(free[i]) + 3 * axis + k];
      continue;
    }
    // The fine gradient to the coefficients' (coarse part only unless details are free); it is
    // used up by the adjoint.
    std::vector<double>& g = r == 0 ? gradient_ : rowGradients_[r - 1];
    transform_->synthesisAdjoint(g.data(), level_, 3, detailsFree_);
    if (r == 0) gradientCached_ = false;
    gather(free, g.data(), gradients + r * m3);
  }
}

void FineVolumeConstraints::alongDirection(const std::vector<uint32_t>& free, const double* direction, double* k) {
  const std::vector<double>& p = session_->fine.of(session_->x);
  // The direction's synthesis: zero-detail unless details are free; vertex N (the origin) stays 0.
  const size_t n3 = session_->x.size(), cage3 = 3 * size_t(session_->cageSize);
  if (direction_.size() != n3 + 3) direction_.assign(n3 + 3, 0.0);
  std::fill(direction_.begin(), direction_.begin() + (detailsFree_ ? n3 : cage3), 0.0);  // zero-detail synthesis overwrites the rest
  scatter(free, direction, direction_.data());
  if (detailsFree_) transform_->synthesize(direction_.data(), level_);
  else transform_->synthesizeZeroDetails(direction_.data(), level_);
  first_->alongDirection(p.data(), direction_.data(), k, true);
}

void FineVolumeConstraints::step(const std::vector<uint32_t>& free, const double* direction, double s, const double* cubicValue) {
  moveFree(free, direction, s, session_->x);
  if (!cubicValue) {
    if (detailsFree_) session_->fine.detailsChanged();
    else session_->fine.cageChanged();
    return;
  }
  // The fine positions follow along the direction's synthesis; the cubic gave the value there.
  session_->fine.followDirection(session_->x, s, direction_, detailsFree_);
  cachedValue_ = *cubicValue;
  cacheVersion_ = session_->fine.version();
  gradientCached_ = false;
}

}  // namespace mrvol
