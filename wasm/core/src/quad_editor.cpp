#include "mrvol/quad_editor.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "mrvol/error.h"

namespace mrvol {

namespace {
int checkedLevel(const QuadHierarchy& h, int level) {
  if (level < 0 || level > h.levels())
    throw Error("level " + std::to_string(level) + " is out of range: this mesh has levels 0.." + std::to_string(h.levels()));
  return level;
}

SessionCoefficients startSession(const QuadHierarchy& h, const WaveletTransform& transform, int level,
                                 const double* positions) {
  QuadMesh fine;
  fine.positions.resize(3 * h.h.fineVertexCount());
  h.h.toHierarchyOrder(positions, fine.positions.data());
  for (double v : fine.positions)
    if (!std::isfinite(v)) throw Error("positions must be finite numbers");
  fine.quads = h.fineQuads();
  const Vec3 origin = quadReferencePoint(fine);
  transform.analyze(fine.positions.data(), level);
  for (double v : fine.positions)
    if (!std::isfinite(v))
      throw Error("analysis cannot reach level " + std::to_string(level) +
                  " of this mesh (a cube's first Catmull-Clark split is not invertible): edit at level 1 or above");
  return SessionCoefficients{std::move(fine.positions), FinePositions(transform, level, origin), origin,
                             h.h.vertexCount[level]};
}

double relative(double value, double reference) {
  return std::fabs(value - reference) / std::max(std::fabs(reference), 1e-300);
}
}  // namespace

QuadVolumeEditor::QuadVolumeEditor(const QuadHierarchy& hierarchy, const WaveletTransform& transform, int level,
                                   const double* positions)
    : hierarchy_(&hierarchy),
      transform_(&transform),
      level_(checkedLevel(hierarchy, level)),
      session_(startSession(hierarchy, transform, level, positions)),
      fineVolume_(hierarchy.fineQuads(), uint32_t(hierarchy.h.fineVertexCount())),
      fineConstraints_(transform, level, session_) {
  fineConstraints_.setRows(fineVolume_, {}, false);
  reference_ = volume();
}

void QuadVolumeEditor::setFreeSet(FreeCage mode, std::vector<uint32_t> list, std::vector<int> detailLevels) {
  FreeSet free{mode, std::move(list), std::move(detailLevels)};
  free.check(hierarchy_->h, level_);
  free_ = std::move(free);
  fineConstraints_.setRows(fineVolume_, {}, !free_.detailLevels.empty());
  solver_.reset();
}

std::vector<uint32_t> QuadVolumeEditor::cageVertices() const {
  return std::vector<uint32_t>(hierarchy_->h.inputIndex.begin(), hierarchy_->h.inputIndex.begin() + cageSize());
}

uint32_t QuadVolumeEditor::cageIndexOf(uint32_t callerVertex) const {
  const auto& index = hierarchy_->h.hierarchyIndex;
  if (callerVertex >= index.size())
    throw Error("vertex " + std::to_string(callerVertex) + " does not exist (the mesh has " + std::to_string(index.size()) +
                " vertices)");
  const uint32_t v = index[callerVertex];
  if (v >= cageSize())
    throw Error("vertex " + std::to_string(callerVertex) + " is not a vertex of the level-" + std::to_string(level_) +
                " cage (it is born at level " + std::to_string(hierarchy_->h.depth(v)) + ")");
  return v;
}

void QuadVolumeEditor::setReferenceVolume(double volume) {
  if (!std::isfinite(volume)) throw Error("the reference volume must be a finite number");
  reference_ = volume;
}

double QuadVolumeEditor::volume() const { return fineConstraints_.value(); }

void QuadVolumeEditor::useTensor(const VolumeTensor& tensor) {
  if (tensor.storage != TensorStorage::Cage || tensor.level != level_ || tensor.vertexCount != session_.x.size() / 3 ||
      tensor.rowCount != cageSize())
    throw Error("the tensor is not theta^" + std::to_string(level_) + " with cage storage for this mesh");
  polynomial_.useTensor(tensor, volume());
  solver_.reset();
}

bool QuadVolumeEditor::usePolynomial(uint64_t maxTerms) {
  std::unique_ptr<CagePolynomialBuilder> builder;
  try {
    builder = std::make_unique<CagePolynomialBuilder>(*transform_, level_, bilinearPatchRegions(*hierarchy_, level_), maxTerms);
  } catch (const Error&) {  // too many cage triples: no faster than the fine mesh
    useMatrixFree();
    return false;
  }
  polynomial_.useBuilder(std::move(builder), volume());
  solver_.reset();
  return true;
}

void QuadVolumeEditor::useMatrixFree() {
  polynomial_.reset();
  solver_.reset();
}

double QuadVolumeEditor::gradientMatrixFree(std::vector<double>& gradient) const {
  const std::vector<double>& p = session_.fine.of(session_.x);
  gradient.resize(p.size());
  const double v = fineVolume_.value(p.data(), gradient.data());
  transform_->synthesisAdjoint(gradient.data(), level_);
  gradient.resize(session_.x.size());
  return v;
}

double QuadVolumeEditor::gradientPolynomial(std::vector<double>& gradient) const { return polynomial_.gradient(gradient); }

void QuadVolumeEditor::startEdit(const EditOptions& o) {
  checkEditOptions(o);
  // Back on the polynomial after corrections moved the details: build it for the new details.
  if (usesPolynomial() && polynomial_.stale()) {
    polynomial_.rebuild(volume());
    solver_.reset();
  }
  if (o.preserve && !free_.detailLevels.empty()) polynomial_.detailsMoved();  // this correction moves details
}

VolumeConstraints& QuadVolumeEditor::constraints() {
  if (usesPolynomial()) return polynomial_.constraint(reference_);
  fineConstraints_.references = {reference_};
  return fineConstraints_;
}

double QuadVolumeEditor::currentVolume(bool withGradient) {
  if (usesPolynomial()) return polynomial_.value();
  return withGradient ? fineConstraints_.valueWithGradient() : fineConstraints_.value();
}

VolumeSolver& QuadVolumeEditor::solver(const std::vector<uint8_t>& held) {
  VolumeConstraints& c = constraints();
  std::vector<uint32_t> free = free_.coefficients(hierarchy_->h, level_, held);
  if (!solver_ || solverConstraints_ != &c || solver_->free() != free) {
    solver_ = std::make_unique<VolumeSolver>(c, std::move(free));
    solverConstraints_ = &c;
  }
  return *solver_;
}

void QuadVolumeEditor::setCage(const double* cage) {
  std::copy(cage, cage + 3 * size_t(cageSize()), session_.x.begin());
  session_.fine.cageChanged();
}

EditReport QuadVolumeEditor::correct(const std::vector<uint8_t>& held, const EditOptions& o) {
  startEdit(o);
  EditReport report;
  report.path = activePath();
  report.volumeReference = reference_;
  report.volumeTarget = volume();
  report.substeps = 1;
  if (o.preserve) solver(held).solve(o, report);
  else report.volumeResult = report.volumeTarget;
  report.relativeError = relative(report.volumeResult, reference_);
  return report;
}

EditReport QuadVolumeEditor::deformCage(const std::vector<double>& target, const std::vector<uint8_t>& held,
                                        const EditOptions& o) {
  const std::vector<double> move = checkedCageMove(hierarchy_->h, session_, target);
  checkEditOptions(o);
  startEdit(o);
  EditReport report;
  report.path = activePath();
  report.volumeReference = reference_;
  const std::vector<double> start = cagePositions();
  setCage(target.data());
  report.volumeTarget = currentVolume(o.preserve);
  if (!o.preserve) {
    report.volumeResult = report.volumeTarget;
    report.relativeError = relative(report.volumeResult, reference_);
    return report;
  }
  report.substeps = substepCount(relative(report.volumeTarget, reference_), o);
  VolumeSolver& solve = solver(held);
  solveInSubsteps(session_, start, move, report.substeps, solve, o, report);
  if (snapHeldToTarget(session_, target, held, solve.free())) report.volumeResult = currentVolume(false);
  report.relativeError = relative(report.volumeResult, reference_);
  return report;
}

std::vector<double> QuadVolumeEditor::cagePositions() const {
  return std::vector<double>(session_.x.begin(), session_.x.begin() + 3 * size_t(cageSize()));
}

std::vector<double> QuadVolumeEditor::positions() const {
  const std::vector<double>& fine = session_.fine.of(session_.x);
  std::vector<double> out(session_.x.size());
  hierarchy_->h.toInputOrder(fine.data(), out.data());
  const Vec3 o = session_.origin;
  for (size_t i = 0; i < out.size(); i += 3) out[i] += o.x, out[i + 1] += o.y, out[i + 2] += o.z;
  return out;
}

}  // namespace mrvol
