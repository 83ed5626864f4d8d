#include "mrvol/volume_editor.h"

#include <algorithm>
#include <cmath>

#include "mrvol/error.h"
#include "mrvol/hierarchy.h"

namespace mrvol {

namespace {
// The level-e coefficients of the caller's positions, their reference point and fine positions.
SessionCoefficients startSession(const Hierarchy& hierarchy, const WaveletTransform& transform, int level,
                                 const double* positions) {
  const size_t n = hierarchy.fineVertexCount();
  std::vector<double> x(3 * n);
  hierarchy.toHierarchyOrder(positions, x.data());
  for (double v : x)
    if (!std::isfinite(v)) throw Error("positions must be finite numbers");
  // The boundary vertices are the hierarchy's (the same as the fine faces' open edges give, without
  // corner lists of the fine mesh).
  const std::vector<char> onBoundary(hierarchy.boundary.begin(), hierarchy.boundary.end());
  const Vec3 origin = volumeReferencePoint(x.data(), n, onBoundary);
  transform.analyze(x.data(), level);
  return SessionCoefficients{std::move(x), FinePositions(transform, level, origin), origin, hierarchy.vertexCount[level]};
}

}  // namespace

VolumeEditor::VolumeEditor(const Hierarchy& hierarchy, const WaveletTransform& transform, int level,
                           const double* positions)
    : CageEditor(hierarchy, transform, checkedLevel(hierarchy, level),
                 startSession(hierarchy, transform, checkedLevel(hierarchy, level), positions)),
      fineVolume_(hierarchy.fineFaces(), uint32_t(hierarchy.fineVertexCount())) {
  for (int k = 0; k < 3; ++k)
    moments_.push_back(std::make_unique<FirstMoment>(hierarchy.fineFaces(), uint32_t(hierarchy.fineVertexCount()), k));
  configureFineRows();
  reference_ = volume();
}

double VolumeEditor::volume() const {
  if (parts_.empty()) return fineConstraints_.value();  // row 0 is the whole surface (cached)
  return fineVolume_.value(session_.fine.of(session_.x).data(), nullptr);
}

double VolumeEditor::meshMoments(double moments[3]) const {
  const double centre[3] = {moments_[0]->centre(), moments_[1]->centre(), moments_[2]->centre()};
  return FirstMoment::volumeAndMoments(hierarchy_->fineFaces(), session_.fine.of(session_.x).data(), centre, moments);
}

const VolumeFunction& VolumeEditor::surfaceVolume() const {
  if (limitVolume_) return *limitVolume_;
  return fineVolume_;
}

void VolumeEditor::useLimitSurface(const FineForm& limitForm) {
  if (!parts_.empty()) throw Error("the limit surface's volume is kept as a whole: clear the parts first");
  if (keepCentroid_) throw Error("the centre of mass is kept for the mesh surface only: stop keeping it first");
  limitVolume_ = std::make_unique<FormVolume>(limitForm, uint32_t(hierarchy_->fineVertexCount()));
  useMatrixFree();  // a polynomial or tensor in use was the mesh's
  configureFineRows();
  reference_ = volume();
}

void VolumeEditor::checkCentroidKept() const {
  if (limitVolume_) throw Error("the centre of mass is kept for the mesh surface only, not with the limit surface");
  if (!parts_.empty()) throw Error("the centre of mass is kept with the whole volume, not with parts");
}

bool VolumeEditor::usePolynomial(uint64_t maxTerms) {
  if (limitVolume_) {  // the builder sums the mesh's triangles, not the limit form
    useMatrixFree();
    return false;
  }
  std::unique_ptr<CagePolynomialBuilder> builder;
  auto basis = cageBasisTaken_ ? nullptr : std::make_unique<CageBasis>();
  try {
    builder = std::make_unique<CagePolynomialBuilder>(*transform_, level_, maxTerms, basis.get());
  } catch (const Error&) {  // too many cage triples: no faster than the fine mesh
    useMatrixFree();
    return false;
  }
  polynomial_.useBuilder(std::move(builder), volume());
  cageBasis_ = std::move(basis);
  solver_.reset();
  return true;
}

void VolumeEditor::setParts(const std::vector<std::vector<uint32_t>>& parts, const std::vector<double>& references) {
  if (limitVolume_ && !parts.empty()) throw Error("parts keep volumes of the mesh's triangles, not of the limit surface");
  if (keepCentroid_ && !parts.empty()) throw Error("the centre of mass is kept with the whole volume, not with parts");
  if (!references.empty() && references.size() != parts.size())
    throw Error("give one reference volume per part (" + std::to_string(parts.size()) + ")");
  const size_t n = session_.x.size() / 3;
  // Weight of each part at each fine vertex: synthesis of its cage indicator (partition of unity).
  std::vector<std::vector<double>> weight(parts.size(), std::vector<double>(n, 0.0));
  std::vector<int> owner(cageSize(), -1);
  for (size_t p = 0; p < parts.size(); ++p)
    for (uint32_t c : parts[p]) {
      if (c >= cageSize()) throw Error("part " + std::to_string(p) + " lists " + std::to_string(c) + ", not a cage vertex");
      if (owner[c] >= 0) throw Error("cage vertex " + std::to_string(hierarchy_->inputIndex[c]) + " is in two parts");
      owner[c] = int(p);
      weight[p][c] = 1.0;
    }
  for (auto& w : weight)
    for (int l = level_ + 1; l <= hierarchy_->levels; ++l)
      for (const auto& step : transform_->synthesisSteps(l)) step.forward(w.data(), 1);
  const auto& faces = hierarchy_->fineFaces();
  std::vector<std::vector<uint8_t>> triangles(parts.size(), std::vector<uint8_t>(faces.size() / 3, 0));
  for (size_t f = 0, tri = 0; f < faces.size(); f += 3, ++tri) {
    double best = 0, total = 0;
    int bestPart = -1;
    for (size_t p = 0; p < parts.size(); ++p) {
      const double w = weight[p][faces[f]] + weight[p][faces[f + 1]] + weight[p][faces[f + 2]];
      total += w;
      if (w > best) best = w, bestPart = int(p);
    }
    if (bestPart >= 0 && best > 3.0 - total) triangles[bestPart][tri] = 1;  // beats the unassigned rest
  }
  parts_.clear();
  for (auto& t : triangles) parts_.emplace_back(faces, uint32_t(n), std::move(t));
  partReference_ = references.empty() ? partVolumes() : references;
  configureFineRows();
}

std::vector<double> VolumeEditor::partVolumes() const {
  std::vector<double> v;
  if (parts_.empty()) return v;
  const double* p = session_.fine.of(session_.x).data();
  for (const auto& part : parts_) v.push_back(part.value(p, nullptr));
  return v;
}

void VolumeEditor::configureFineRows() {
  std::vector<const FineFunction*> more;
  if (parts_.empty() && keepCentroid_)
    for (const auto& m : moments_) more.push_back(m.get());
  for (size_t p = 1; p < parts_.size(); ++p) more.push_back(&parts_[p]);
  fineConstraints_.setRows(parts_.empty() ? surfaceVolume() : parts_[0], std::move(more), !free_.detailLevels.empty());
  solver_.reset();
}

void VolumeEditor::setFineReferences() {
  if (parts_.empty()) return CageEditor::setFineReferences();  // the volume, and the moments when kept
  fineConstraints_.references = partReference_;
  fineConstraints_.scales.clear();
}

void VolumeEditor::finishReport(EditReport& report) const {
  if (parts_.empty()) CageEditor::finishReport(report);  // the error, and the centres of mass when kept
  else report.volumeResult = volume();
  report.partReferences = partReference_;
  report.partVolumes = partVolumes();
}

}  // namespace mrvol
