#include "mrvol/quad_multires_mesh.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "mrvol/error.h"

namespace mrvol {

QuadMultiresMesh::QuadMultiresMesh(const QuadMesh& mesh, int maxLevels) : quads_(mesh.quads) {
  if (maxLevels < 0) throw Error("maxLevels must be at least 0, got " + std::to_string(maxLevels));
  topology_ = validateQuadMesh(mesh);
  hierarchy_ = std::make_unique<QuadHierarchy>(QuadHierarchy::detect(mesh, maxLevels));
  build();
}

QuadMultiresMesh QuadMultiresMesh::subdivide(const QuadMesh& base, int levels) {
  if (levels < 0 || levels > 12) throw Error("levels must be in 0..12, got " + std::to_string(levels));
  validateQuadMesh(base);
  // What the split mesh will need, before building it: as many vertices as quads (closed), two
  // triangles per quad in the estimate of checkMeshSize.
  const double quads = double(base.faceCount()) * std::pow(4.0, levels);
  checkMeshSize(size_t(std::min(quads, 1e15)), size_t(std::min(2 * quads, 1e15)));
  QuadMultiresMesh m;
  m.hierarchy_ = std::make_unique<QuadHierarchy>(QuadHierarchy::subdivide(base.quads, uint32_t(base.vertexCount()), levels));
  m.quads_ = m.hierarchy_->fineQuads();
  m.topology_ = validateQuadMesh(QuadMesh{std::vector<double>(3 * m.vertexCount(), 0.0), m.quads_});
  m.build();
  return m;
}

void QuadMultiresMesh::build() {
  transform_ = std::make_unique<WaveletTransform>(catmullClarkTransform(*hierarchy_, &lowestLevel_));
  form_ = std::make_unique<FineForm>(bilinearPatchForm(hierarchy_->fineQuads()));
}

std::vector<double> QuadMultiresMesh::subdivisionPositions(const std::vector<double>& basePositions) const {
  const size_t base3 = 3 * size_t(hierarchy_->h.vertexCount[0]);
  if (basePositions.size() != base3)
    throw Error("expected " + std::to_string(base3) + " base coordinates (3 per vertex), got " +
                std::to_string(basePositions.size()));
  std::vector<double> x(3 * vertexCount(), 0.0);
  std::copy(basePositions.begin(), basePositions.end(), x.begin());
  transform_->synthesizeZeroDetails(x.data(), 0);
  std::vector<double> out(x.size());
  hierarchy_->h.toInputOrder(x.data(), out.data());
  return out;
}

void QuadMultiresMesh::checkPositions(const std::vector<double>& positions) const { checkPositionArray(positions, vertexCount()); }

void QuadMultiresMesh::checkLevel(int level, bool analysis) const {
  if (level < 0 || level > levels())
    throw Error("level " + std::to_string(level) + " is out of range: this mesh has levels 0.." + std::to_string(levels()));
  if (analysis && level < lowestLevel_)
    throw Error("analysis cannot reach level " + std::to_string(level) +
                ": the base is a cube, whose first Catmull-Clark split is not invertible (use level " +
                std::to_string(lowestLevel_) + " or above)");
}

double QuadMultiresMesh::volume(const std::vector<double>& positions) const {
  checkPositions(positions);
  return bilinearVolume(QuadMesh{positions, quads_});
}

MeshInfo QuadMultiresMesh::info(const std::vector<double>& positions) const {
  const double v = volume(positions);  // checks the positions
  MeshInfo info = hierarchyInfo(hierarchy_->h, topology_, quads_.size() / 4);
  info.volume = v;
  return info;
}

std::vector<uint32_t> QuadMultiresMesh::levelQuads(int level) const {
  checkLevel(level, false);
  std::vector<uint32_t> out = hierarchy_->quads[level];
  for (uint32_t& v : out) v = hierarchy_->h.inputIndex[v];
  return out;
}

std::vector<LiftingStep> QuadMultiresMesh::liftingSteps(int level) const {
  if (level < 1 || level > levels())
    throw Error("level " + std::to_string(level) + " has no lifting steps: levels 1.." + std::to_string(levels()) +
                " build M^l from M^(l-1)");
  std::vector<LiftingStep> out = transform_->synthesisSteps(level);
  for (auto& step : out) {
    for (auto& t : step.targets) t = hierarchy_->h.inputIndex[t];
    for (auto& s : step.sources) s = hierarchy_->h.inputIndex[s];
  }
  return out;
}

std::vector<double> QuadMultiresMesh::analyze(const std::vector<double>& positions, int level) const {
  checkPositions(positions);
  checkLevel(level, true);
  std::vector<double> x(positions.size()), out(positions.size());
  hierarchy_->h.toHierarchyOrder(positions.data(), x.data());
  transform_->analyze(x.data(), level);
  hierarchy_->h.toInputOrder(x.data(), out.data());
  return out;
}

std::vector<double> QuadMultiresMesh::synthesize(const std::vector<double>& coefficients, int level) const {
  if (coefficients.size() != 3 * vertexCount())
    throw Error("expected " + std::to_string(3 * vertexCount()) + " coefficients (3 per vertex), got " +
                std::to_string(coefficients.size()));
  checkLevel(level, false);
  std::vector<double> x(coefficients.size()), out(coefficients.size());
  hierarchy_->h.toHierarchyOrder(coefficients.data(), x.data());
  transform_->synthesize(x.data(), level);
  hierarchy_->h.toInputOrder(x.data(), out.data());
  return out;
}

double QuadMultiresMesh::roundtripError(const std::vector<double>& positions, int level) const {
  std::vector<double> back = synthesize(analyze(positions, level), level);
  double m = 0;
  for (size_t i = 0; i < back.size(); ++i) m = std::max(m, std::fabs(back[i] - positions[i]));
  return m;
}

VolumeTensor QuadMultiresMesh::computeTensor(int level, TensorStorage storage, const TensorProgress& progress) const {
  checkLevel(level, false);
  VolumeTensor t = computeVolumeTensor(*transform_, level, storage, *form_, progress);
  t.level = level;
  t.storage = storage;
  return t;
}

uint64_t QuadMultiresMesh::fingerprint() const {
  // Quads and triangles of the same indices must not match: the quads' triangulation with a tag.
  return connectivityFingerprint(triangulateQuads(quads_), vertexCount()) ^ 0x51ad5c4e11c1a4bULL;
}

ThetaFileHeader QuadMultiresMesh::thetaHeader(const VolumeTensor& tensor) const {
  ThetaFileHeader h;
  h.scheme = transform_->options();
  h.levels = levels();
  h.level = tensor.level;
  h.storage = tensor.storage;
  h.fingerprint = fingerprint();
  h.vertexCount = uint32_t(vertexCount());
  h.nnzFull = tensor.nnzFull;
  h.nnzStored = tensor.storedCount();
  return h;
}

void QuadMultiresMesh::checkTheta(const ThetaFileHeader& h, int level) const {
  if (h.fingerprint != fingerprint() || h.vertexCount != vertexCount() || h.levels != levels())
    throw Error("theta file does not match this mesh: it was computed for another connectivity (" +
                std::to_string(h.vertexCount) + " vertices, " + std::to_string(h.levels) + " levels)");
  if (h.scheme.kind != SchemeKind::CatmullClark)
    throw Error(std::string("theta file was computed for the ") + schemeName(h.scheme.kind) + " scheme, not catmull-clark");
  if (h.level != level) throw Error("theta file is for level " + std::to_string(h.level) + ", not level " + std::to_string(level));
  if (h.limitSurface) throw Error("theta file holds a limit surface's volume, not the bilinear patches'");
}

double QuadMultiresMesh::tensorVolume(const VolumeTensor& tensor, const std::vector<double>& positions) const {
  checkPositions(positions);
  checkLevel(tensor.level, true);
  if (tensor.vertexCount != vertexCount()) throw Error("the tensor is for another mesh");
  const Vec3 o = quadReferencePoint(QuadMesh{positions, quads_});
  const size_t n = vertexCount();
  std::vector<double> x(3 * n);
  hierarchy_->h.toHierarchyOrder(positions.data(), x.data());
  for (size_t v = 0; v < n; ++v) x[3 * v] -= o.x, x[3 * v + 1] -= o.y, x[3 * v + 2] -= o.z;
  transform_->analyze(x.data(), tensor.level);
  double volume = tensor.evaluate(x.data());
  if (tensor.storage == TensorStorage::Cage) {
    std::fill(x.begin(), x.begin() + 3 * size_t(hierarchy_->h.vertexCount[tensor.level]), 0.0);
    transform_->synthesize(x.data(), tensor.level);
    volume += form_->evaluate(x.data());
  }
  return volume;
}

}  // namespace mrvol
