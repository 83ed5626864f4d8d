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
      level_(checkedLevel(hierarchy, level)),
      session_(startSession(hierarchy, transform, level, positions)),
      fineVolume_(hierarchy.fineQuads(), uint32_t(hierarchy.h.fineVertexCount())),
      fineConstraints_(transform, level, session_) {
  fineConstraints_.setRows(fineVolume_, {}, false);
  reference_ = volume();
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
  CagePolynomial poly = contractCageRows(tensor, session_.x.data());
  // The detail-only entries were never formed: the constant comes from the exact volume.
  std::vector<double> shifted;
  session_.shiftedCage(shifted);
  poly.constant = volume() - (poly.evaluate(shifted.data(), nullptr) - poly.constant);
  polynomial_ = std::make_unique<CagePolynomialVolume>(std::move(poly));
  cageConstraint_ = std::make_unique<CageVolumeConstraint>(*polynomial_, session_);
  solver_.reset();
}

void QuadVolumeEditor::useMatrixFree() {
  polynomial_.reset();
  cageConstraint_.reset();
  solver_.reset();
}

VolumeConstraints& QuadVolumeEditor::constraints() {
  if (polynomial_) {
    cageConstraint_->referenceVolume = reference_;
    return *cageConstraint_;
  }
  fineConstraints_.references = {reference_};
  return fineConstraints_;
}

double QuadVolumeEditor::currentVolume(bool withGradient) {
  if (polynomial_) return cageConstraint_->value();
  return withGradient ? fineConstraints_.valueWithGradient() : fineConstraints_.value();
}

VolumeSolver& QuadVolumeEditor::solver(const std::vector<uint8_t>& held) {
  VolumeConstraints& c = constraints();
  std::vector<uint32_t> free;
  for (uint32_t v = 0; v < cageSize(); ++v)
    if (!hierarchy_->h.boundary[v] && (allFree_ || !(v < held.size() && held[v]))) free.push_back(v);
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
  checkEditOptions(o);
  EditReport report;
  report.path = path();
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
  const size_t cage3 = 3 * size_t(cageSize());
  if (target.size() != cage3)
    throw Error("the cage target needs " + std::to_string(cage3) + " coordinates, got " + std::to_string(target.size()));
  checkEditOptions(o);
  std::vector<double> move(cage3);
  for (uint32_t c = 0; c < cageSize(); ++c)
    for (int k = 0; k < 3; ++k) {
      const double t = target[3 * c + k];
      if (!std::isfinite(t)) throw Error("the cage target has a non-finite coordinate");
      move[3 * c + k] = t - session_.x[3 * c + k];
      if (hierarchy_->h.boundary[c] && move[3 * c + k] != 0.0)
        throw Error("vertex " + std::to_string(hierarchy_->h.inputIndex[c]) +
                    " is on the boundary: boundary vertices stay fixed so that the volume stays meaningful");
    }
  EditReport report;
  report.path = path();
  report.volumeReference = reference_;
  const std::vector<double> start(session_.x.begin(), session_.x.begin() + cage3);
  setCage(target.data());
  report.volumeTarget = currentVolume(o.preserve);
  if (!o.preserve) {
    report.volumeResult = report.volumeTarget;
    report.relativeError = relative(report.volumeResult, reference_);
    return report;
  }
  // Large moves are split so that the linearization holds (as the triangle editor).
  const int substeps = std::clamp(int(std::ceil(relative(report.volumeTarget, reference_) / o.substepError)), 1, o.maxSubsteps);
  report.substeps = substeps;
  VolumeSolver& solve = solver(held);
  if (substeps > 1) setCage(start.data());
  for (int s = 1; s <= substeps; ++s) {
    if (substeps > 1) {
      for (size_t i = 0; i < cage3; ++i) session_.x[i] += move[i] / substeps;
      session_.fine.cageChanged();
    }
    EditReport step;
    solve.solve(o, step);
    report.iterations += step.iterations;
    report.volumeResult = step.volumeResult;
    if (!step.converged) {
      report.converged = false;
      report.message = step.message;
      break;
    }
  }
  // Held vertices end exactly at the target (sub-steps add up with rounding).
  const auto& free = solve.free();
  bool snapped = false;
  for (uint32_t c = 0; c < cageSize(); ++c)
    if (c < held.size() && held[c] && !std::binary_search(free.begin(), free.end(), c))
      for (int k = 0; k < 3; ++k) {
        snapped = snapped || session_.x[3 * c + k] != target[3 * c + k];
        session_.x[3 * c + k] = target[3 * c + k];
      }
  if (snapped) {
    session_.fine.cageChanged();
    report.volumeResult = currentVolume(false);
  }
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
