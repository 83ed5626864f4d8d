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
  TriangleMesh fine;
  fine.positions.resize(3 * hierarchy.fineVertexCount());
  hierarchy.toHierarchyOrder(positions, fine.positions.data());
  for (double v : fine.positions)
    if (!std::isfinite(v)) throw Error("positions must be finite numbers");
  fine.faces = hierarchy.fineFaces();
  const Vec3 origin = volumeReferencePoint(fine);
  transform.analyze(fine.positions.data(), level);
  return SessionCoefficients{std::move(fine.positions), FinePositions(transform, level, origin), origin,
                             hierarchy.vertexCount[level]};
}

std::vector<FirstMoment> firstMoments(const std::vector<uint32_t>& faces, uint32_t vertexCount) {
  std::vector<FirstMoment> m;
  for (int k = 0; k < 3; ++k) m.emplace_back(faces, vertexCount, k);
  return m;
}
}  // namespace

VolumeEditor::VolumeEditor(const Hierarchy& hierarchy, const WaveletTransform& transform, int level,
                           const double* positions)
    : CageEditor(hierarchy, transform, checkedLevel(hierarchy, level),
                 startSession(hierarchy, transform, checkedLevel(hierarchy, level), positions)),
      fineVolume_(hierarchy.fineFaces(), uint32_t(hierarchy.fineVertexCount())),
      moments_(firstMoments(hierarchy.fineFaces(), uint32_t(hierarchy.fineVertexCount()))) {
  configureFineRows();
  reference_ = volume();
}

void VolumeEditor::setReferenceVolume(double volume) {
  if (!std::isfinite(volume)) throw Error("the reference volume must be a finite number");
  if (keepCentroid_ && reference_ != 0) momentScale_ *= std::fabs(volume / reference_);  // the same centre, its tolerance
  reference_ = volume;
}

double VolumeEditor::volume() const {
  if (parts_.empty()) return fineConstraints_.value();  // row 0 is the whole surface (cached)
  return fineVolume_.value(session_.fine.of(session_.x).data(), nullptr);
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

double VolumeEditor::meshMoments(double m[3]) const {
  const double* p = session_.fine.of(session_.x).data();
  for (int k = 0; k < 3; ++k) m[k] = moments_[k].value(p, nullptr);
  return fineVolume_.value(p, nullptr);
}

Vec3 VolumeEditor::centroid() const {
  double m[3];
  const double v = meshMoments(m);
  if (!(v != 0)) throw Error("the centre of mass is undefined: the enclosed volume is zero");
  // m = M - q V about the moments' centre q (relative to the origin): c = o + q + m / V.
  const Vec3 o = session_.origin;
  return {o.x + moments_[0].centre() + m[0] / v, o.y + moments_[1].centre() + m[1] / v, o.z + moments_[2].centre() + m[2] / v};
}

Vec3 VolumeEditor::referenceCentroid() const {
  if (!keepCentroid_) return centroid();
  const Vec3 o = session_.origin;
  return {o.x + moments_[0].centre(), o.y + moments_[1].centre(), o.z + moments_[2].centre()};
}

void VolumeEditor::keepCentroid(bool keep) {
  if (keep && limitVolume_) throw Error("the centre of mass is kept for the mesh surface only, not with the limit surface");
  if (keep && !parts_.empty()) throw Error("the centre of mass is kept with the whole volume, not with parts");
  if (keep && !keepCentroid_) {
    const std::vector<double>& p = session_.fine.of(session_.x);
    double lo[3] = {p[0], p[1], p[2]}, hi[3] = {p[0], p[1], p[2]};
    for (size_t i = 0; i + 3 < p.size(); i += 3)  // not vertex N (the origin)
      for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[i + k]), hi[k] = std::max(hi[k], p[i + k]);
    const double diagonal = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                      (hi[2] - lo[2]) * (hi[2] - lo[2]));
    // The rows are the moments about the centre of mass now: zero while it stays there.
    const Vec3 c = centroid(), o = session_.origin;
    moments_[0].setCentre(c.x - o.x), moments_[1].setCentre(c.y - o.y), moments_[2].setCentre(c.z - o.z);
    momentScale_ = std::fabs(reference_) * diagonal / 10;  // the centre to a tenth of the tolerance times the size
  }
  keepCentroid_ = keep;
  configureFineRows();
}

double VolumeEditor::momentChange() const {
  double m[3];
  meshMoments(m);
  return std::max({std::fabs(m[0]), std::fabs(m[1]), std::fabs(m[2])}) / std::max(momentScale_, 1e-300);
}

bool VolumeEditor::usePolynomial(uint64_t maxTerms) {
  if (limitVolume_) {  // the builder sums the mesh's triangles, not the limit form
    useMatrixFree();
    return false;
  }
  std::unique_ptr<CagePolynomialBuilder> builder;
  try {
    builder = std::make_unique<CagePolynomialBuilder>(*transform_, level_, maxTerms);
  } catch (const Error&) {  // too many cage triples: no faster than the fine mesh
    useMatrixFree();
    return false;
  }
  polynomial_.useBuilder(std::move(builder), volume());
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
    for (const auto& m : moments_) more.push_back(&m);
  for (size_t p = 1; p < parts_.size(); ++p) more.push_back(&parts_[p]);
  fineConstraints_.setRows(parts_.empty() ? surfaceVolume() : parts_[0], std::move(more), !free_.detailLevels.empty());
  solver_.reset();
}

void VolumeEditor::setFineReferences() {
  fineConstraints_.references = parts_.empty() ? std::vector<double>{reference_} : partReference_;
  fineConstraints_.scales.clear();
  if (parts_.empty() && keepCentroid_) {
    fineConstraints_.references.insert(fineConstraints_.references.end(), {0.0, 0.0, 0.0});  // moments about the kept centre
    fineConstraints_.scales = {std::fabs(reference_), momentScale_, momentScale_, momentScale_};
  }
}

double VolumeEditor::rawChange(double volumeTarget) const {
  return std::max(relative(volumeTarget, reference_), keepCentroid_ ? momentChange() : 0.0);
}

void VolumeEditor::finishReport(EditReport& report) const {
  if (parts_.empty()) report.relativeError = relative(report.volumeResult, reference_);
  else report.volumeResult = volume();
  if (keepCentroid_) {
    const Vec3 r = referenceCentroid(), c = centroid();
    report.centroidReference = {r.x, r.y, r.z};
    report.centroidResult = {c.x, c.y, c.z};
  }
  report.partReferences = partReference_;
  report.partVolumes = partVolumes();
}

}  // namespace mrvol
