#include "mrvol/cage_editor.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "mrvol/error.h"

namespace mrvol {

CageEditor::CageEditor(const Hierarchy& hierarchy, const WaveletTransform& transform, int level,
                       SessionCoefficients session)
    : hierarchy_(&hierarchy),
      transform_(&transform),
      level_(level),
      session_(std::move(session)),
      fineConstraints_(transform, level, session_) {}

int CageEditor::checkedLevel(const Hierarchy& hierarchy, int level) {
  if (level < 0 || level > hierarchy.levels)
    throw Error("level " + std::to_string(level) + " is out of range: this mesh has levels 0.." +
                std::to_string(hierarchy.levels));
  return level;
}

double CageEditor::relative(double value, double reference) {
  return std::fabs(value - reference) / std::max(std::fabs(reference), 1e-300);
}

std::vector<uint32_t> CageEditor::cageVertices() const {
  return std::vector<uint32_t>(hierarchy_->inputIndex.begin(), hierarchy_->inputIndex.begin() + cageSize());
}

uint32_t CageEditor::cageIndexOf(uint32_t callerVertex) const {
  if (callerVertex >= hierarchy_->hierarchyIndex.size())
    throw Error("vertex " + std::to_string(callerVertex) + " does not exist (the mesh has " +
                std::to_string(hierarchy_->hierarchyIndex.size()) + " vertices)");
  const uint32_t h = hierarchy_->hierarchyIndex[callerVertex];
  if (h >= cageSize())
    throw Error("vertex " + std::to_string(callerVertex) + " is not a vertex of the level-" + std::to_string(level_) +
                " cage (it is born at level " + std::to_string(hierarchy_->depth(h)) + ")");
  return h;
}

void CageEditor::setReferenceVolume(double volume) {
  if (!std::isfinite(volume)) throw Error("the reference volume must be a finite number");
  if (keepCentroid_ && reference_ != 0) momentScale_ *= std::fabs(volume / reference_);  // the same centre, its tolerance
  reference_ = volume;
}

double CageEditor::meshMoments(double m[3]) const {
  const double* p = session_.fine.of(session_.x).data();
  for (int k = 0; k < 3; ++k) m[k] = moments_[k]->value(p, nullptr);
  return meshVolume().value(p, nullptr);
}

Vec3 CageEditor::centroid() const {
  double m[3];
  const double v = meshMoments(m);
  if (!(v != 0)) throw Error("the centre of mass is undefined: the enclosed volume is zero");
  // m = M - q V about the moments' centre q (relative to the origin): c = o + q + m / V.
  const Vec3 o = session_.origin;
  return {o.x + moments_[0]->centre() + m[0] / v, o.y + moments_[1]->centre() + m[1] / v,
          o.z + moments_[2]->centre() + m[2] / v};
}

Vec3 CageEditor::referenceCentroid() const {
  if (!keepCentroid_) return centroid();
  const Vec3 o = session_.origin;
  return {o.x + moments_[0]->centre(), o.y + moments_[1]->centre(), o.z + moments_[2]->centre()};
}

void CageEditor::keepCentroid(bool keep) {
  if (keep) checkCentroidKept();
  if (keep && !keepCentroid_) {
    const std::vector<double>& p = session_.fine.of(session_.x);
    double lo[3] = {p[0], p[1], p[2]}, hi[3] = {p[0], p[1], p[2]};
    for (size_t i = 0; i + 3 < p.size(); i += 3)  // not vertex N (the origin)
      for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[i + k]), hi[k] = std::max(hi[k], p[i + k]);
    const double diagonal = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                      (hi[2] - lo[2]) * (hi[2] - lo[2]));
    // The rows are the moments about the centre of mass now: zero while it stays there.
    const Vec3 c = centroid(), o = session_.origin;
    moments_[0]->setCentre(c.x - o.x), moments_[1]->setCentre(c.y - o.y), moments_[2]->setCentre(c.z - o.z);
    momentScale_ = std::fabs(reference_) * diagonal / 10;  // the centre to a tenth of the tolerance times the size
  }
  keepCentroid_ = keep;
  configureFineRows();
}

double CageEditor::momentChange() const {
  double m[3];
  meshMoments(m);
  return std::max({std::fabs(m[0]), std::fabs(m[1]), std::fabs(m[2])}) / std::max(momentScale_, 1e-300);
}

double CageEditor::rawChange(double volumeTarget) const {
  return std::max(relative(volumeTarget, reference_), keepCentroid_ ? momentChange() : 0.0);
}

void CageEditor::useTensor(const VolumeTensor& tensor) {
  if (tensor.storage != TensorStorage::Cage || tensor.level != level_ || tensor.vertexCount != session_.x.size() / 3 ||
      tensor.rowCount != cageSize())
    throw Error("the tensor is not theta^" + std::to_string(level_) + " with cage storage for this mesh");
  // Translation only moves the cage coefficients: the details contract as they are.
  polynomial_.useTensor(tensor, volume());
  solver_.reset();
}

void CageEditor::useMatrixFree() {
  polynomial_.reset();
  solver_.reset();
}

void CageEditor::setFreeSet(FreeCage mode, std::vector<uint32_t> list, std::vector<int> detailLevels) {
  FreeSet free{mode, std::move(list), std::move(detailLevels)};
  free.check(*hierarchy_, level_);
  free_ = std::move(free);
  configureFineRows();
}

void CageEditor::configureFineRows() {
  std::vector<const FineFunction*> more;
  if (keepCentroid_)
    for (const auto& m : moments_) more.push_back(m.get());
  fineConstraints_.setRows(meshVolume(), std::move(more), !free_.detailLevels.empty());
  solver_.reset();
}

void CageEditor::setFineReferences() {
  fineConstraints_.references = {reference_};
  fineConstraints_.scales.clear();
  if (keepCentroid_) {
    fineConstraints_.references.insert(fineConstraints_.references.end(), {0.0, 0.0, 0.0});  // moments about the kept centre
    fineConstraints_.scales = {std::fabs(reference_), momentScale_, momentScale_, momentScale_};
  }
}

VolumeConstraints& CageEditor::constraints() {
  if (usesPolynomial()) return polynomial_.constraint(reference_);
  setFineReferences();
  return fineConstraints_;
}

double CageEditor::constrainedVolume(bool withGradient) {
  if (usesPolynomial()) return polynomial_.value();
  return withGradient ? fineConstraints_.valueWithGradient() : fineConstraints_.value();
}

VolumeSolver& CageEditor::solver(const std::vector<uint8_t>& held) {
  VolumeConstraints& c = constraints();
  // A drag holds the same vertices step after step: the free set is the kept solver's (every change
  // of the free set or the rows resets the solver).
  if (solver_ && solverConstraints_ == &c && held == solverHeld_) return *solver_;
  std::vector<uint32_t> free = free_.coefficients(*hierarchy_, level_, held);
  if (!solver_ || solverConstraints_ != &c || solver_->free() != free) {
    solver_ = std::make_unique<VolumeSolver>(c, std::move(free));
    solverConstraints_ = &c;
  }
  solverHeld_ = held;
  return *solver_;
}

void CageEditor::setCage(const double* cage) {
  std::copy(cage, cage + 3 * size_t(cageSize()), session_.x.begin());
  session_.fine.cageChanged();
}

void CageEditor::startEdit(const EditOptions& o) {
  checkEditOptions(o);
  // Back on the polynomial after corrections moved the details: build it for the new details.
  if (usesPolynomial() && polynomial_.stale()) {
    polynomial_.rebuild(volume());
    solver_.reset();
  }
  if (o.preserve && !free_.detailLevels.empty()) polynomial_.detailsMoved();  // this correction moves details
}

void CageEditor::finishReport(EditReport& report) const {
  report.relativeError = relative(report.volumeResult, reference_);
  if (keepCentroid_) {
    const Vec3 r = referenceCentroid(), c = centroid();
    report.centroidReference = {r.x, r.y, r.z};
    report.centroidResult = {c.x, c.y, c.z};
  }
}

EditReport CageEditor::correct(const std::vector<uint8_t>& held, const EditOptions& o) {
  startEdit(o);
  EditReport report;
  report.path = activePath();
  report.volumeReference = reference_;
  report.volumeTarget = volume();
  report.substeps = 1;
  if (o.preserve) solver(held).solve(o, report);
  else report.volumeResult = report.volumeTarget;
  finishReport(report);
  return report;
}

EditReport CageEditor::deformCage(const std::vector<double>& target, const std::vector<uint8_t>& held,
                                  const EditOptions& o) {
  const std::vector<double> move = checkedCageMove(*hierarchy_, session_, target);
  checkEditOptions(o);
  startEdit(o);
  EditReport report;
  report.path = activePath();
  report.volumeReference = reference_;
  const std::vector<double> start = cagePositions();
  // The cage takes the target as given (x + (t - x) need not round to t). On the matrix-free path the
  // pass that gives the target's volume gives the solver's first gradient too.
  setCage(target.data());
  report.volumeTarget = rowIsVolume() ? constrainedVolume(o.preserve) : volume();
  if (!o.preserve) {
    report.volumeResult = report.volumeTarget;
    finishReport(report);
    return report;
  }
  report.substeps = substepCount(rawChange(report.volumeTarget), o);
  VolumeSolver& solve = solver(held);
  solveInSubsteps(session_, start, move, report.substeps, solve, o, report);
  if (snapHeldToTarget(session_, target, held, solve.free()) && rowIsVolume())
    report.volumeResult = constrainedVolume(false);  // rounding of the sub-steps: re-evaluate
  finishReport(report);
  return report;
}

std::vector<double> CageEditor::cagePositions() const {
  return std::vector<double>(session_.x.begin(), session_.x.begin() + 3 * size_t(cageSize()));
}

std::vector<double> CageEditor::positions() const {
  const std::vector<double>& fine = session_.fine.of(session_.x);
  std::vector<double> out(session_.x.size());
  hierarchy_->toInputOrder(fine.data(), out.data());
  const Vec3 o = session_.origin;
  for (size_t i = 0; i < out.size(); i += 3) out[i] += o.x, out[i + 1] += o.y, out[i + 2] += o.z;
  return out;
}

double CageEditor::gradientMatrixFree(std::vector<double>& gradient) const {
  const std::vector<double>& p = session_.fine.of(session_.x);
  gradient.resize(p.size());
  const double v = meshVolume().value(p.data(), gradient.data());
  transform_->synthesisAdjoint(gradient.data(), level_);
  gradient.resize(session_.x.size());
  return v;
}

}  // namespace mrvol
