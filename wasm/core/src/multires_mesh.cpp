#include "mrvol/multires_mesh.h"

#include <algorithm>
#include <cmath>

#include "mrvol/corners.h"
#include "mrvol/error.h"
#include "mrvol/limit_volume.h"
#include "mrvol/vertex_order.h"

namespace mrvol {

MultiresMesh::MultiresMesh(const TriangleMesh& mesh, int maxLevels, const SourceLines* lines)
    : MultiresMesh(TriangleMesh(mesh), maxLevels, lines) {}

MultiresMesh::MultiresMesh(TriangleMesh&& mesh, int maxLevels, const SourceLines* lines) {
  if (maxLevels < 0) throw Error("maxLevels must be at least 0, got " + std::to_string(maxLevels));
  // Validation and detection run in a local vertex numbering (vertex_order.h: far fewer cache
  // misses); a mesh it refuses is validated again in the caller's numbering, so that the message
  // names the same vertex, face and line as ever.
  const std::vector<uint32_t> localToCaller = renumberByFirstAppearance(mesh.faces, mesh.vertexCount());
  VertexCorners corners;  // validation's, handed to detection
  bool local = !localToCaller.empty();
  if (local) {
    try {
      topology_ = validateMesh(mesh, nullptr, &corners);
    } catch (const Error&) {
      restoreNumbering(mesh.faces, localToCaller);
      local = false;
    }
  }
  if (!local) topology_ = validateMesh(mesh, lines, &corners);
  const size_t vertexCount = mesh.vertexCount();
  std::vector<double>().swap(mesh.positions);  // detection needs the faces only
  hierarchy_ = Hierarchy::detectValidated(mesh.faces, vertexCount, maxLevels, &corners, local ? &localToCaller : nullptr);
  if (local) restoreNumbering(mesh.faces, localToCaller);
  faces_ = std::move(mesh.faces);
}

MultiresMesh MultiresMesh::subdivide(const TriangleMesh& base, int levels) {
  MultiresMesh m;
  validateMesh(base);
  m.hierarchy_ = Hierarchy::subdivide(base, levels);
  m.faces_ = m.hierarchy_.fineFaces();
  // The split of a valid mesh is valid; its topology (positions do not enter it).
  m.topology_ = validateMesh(TriangleMesh{std::vector<double>(3 * m.hierarchy_.fineVertexCount(), 0.0), m.faces_});
  return m;
}

std::vector<double> MultiresMesh::subdivisionPositions(const std::vector<double>& basePositions,
                                                       const SchemeOptions& scheme) const {
  const size_t base3 = 3 * size_t(hierarchy_.vertexCount[0]);
  if (basePositions.size() != base3)
    throw Error("expected " + std::to_string(base3) + " base coordinates (3 per vertex), got " +
                std::to_string(basePositions.size()));
  // Subdivision numbers the vertices in hierarchy order: no reordering.
  std::vector<double> x(3 * vertexCount(), 0.0);
  std::copy(basePositions.begin(), basePositions.end(), x.begin());
  transform(scheme).synthesize(x.data(), 0);
  return x;
}

void checkPositionArray(const std::vector<double>& positions, size_t vertexCount) {
  if (positions.size() != 3 * vertexCount)
    throw Error("expected " + std::to_string(3 * vertexCount) + " coordinates (3 per vertex), got " +
                std::to_string(positions.size()));
  for (size_t i = 0; i < positions.size(); ++i)
    if (!std::isfinite(positions[i])) throw Error("vertex " + std::to_string(i / 3) + " has a non-finite coordinate");
}

MeshInfo hierarchyInfo(const Hierarchy& h, const MeshTopology& topology, size_t faces) {
  MeshInfo info;
  info.vertices = h.fineVertexCount();
  info.faces = faces;
  info.levels = h.levels;
  info.baseVertices = h.vertexCount[0];
  info.baseVertexIndices.assign(h.inputIndex.begin(), h.inputIndex.begin() + info.baseVertices);
  std::sort(info.baseVertexIndices.begin(), info.baseVertexIndices.end());
  info.closed = topology.closed;
  info.boundaryEdges = topology.boundaryEdges;
  info.genus = topology.genus;
  info.components = topology.components;
  return info;
}

void MultiresMesh::checkPositions(const std::vector<double>& positions) const { checkPositionArray(positions, vertexCount()); }

MeshInfo MultiresMesh::info(const std::vector<double>& positions) const {
  checkPositions(positions);
  MeshInfo info = hierarchyInfo(hierarchy_, topology_, faces_.size() / 3);
  info.volume = meshVolume(positions.data(), faces_.data(), faces_.size() / 3, volumeReferencePoint(positions));
  return info;
}

Vec3 MultiresMesh::volumeReferencePoint(const std::vector<double>& positions) const {
  std::vector<char> onBoundary(vertexCount(), 0);
  if (!topology_.closed)
    for (size_t v = 0; v < onBoundary.size(); ++v) onBoundary[v] = char(hierarchy_.boundary[hierarchy_.hierarchyIndex[v]]);
  return mrvol::volumeReferencePoint(positions.data(), onBoundary.size(), onBoundary);
}

std::vector<uint32_t> MultiresMesh::levelFaces(int level) const {
  checkLevel(level);
  std::vector<uint32_t> out = hierarchy_.faces[level];
  for (auto& v : out) v = hierarchy_.inputIndex[v];
  return out;
}

const WaveletTransform& MultiresMesh::transform(const SchemeOptions& scheme) const {
  for (auto& t : transforms_)
    if (t->options().kind == scheme.kind && t->options().alpha == scheme.alpha && t->options().beta == scheme.beta)
      return *t;
  transforms_.push_back(std::make_unique<WaveletTransform>(hierarchy_, scheme));
  return *transforms_.back();
}

void MultiresMesh::checkLevel(int level) const {
  if (level < 0 || level > hierarchy_.levels)
    throw Error("level " + std::to_string(level) + " is out of range: this mesh has levels 0.." +
                std::to_string(hierarchy_.levels));
}

// Caller's order in, one transform in hierarchy order, caller's order out.
template <class Apply>
std::vector<double> MultiresMesh::inHierarchyOrder(const std::vector<double>& values, const char* what, int level,
                                                   Apply&& apply) const {
  checkLevel(level);
  if (values.size() != 3 * vertexCount())
    throw Error("expected " + std::to_string(3 * vertexCount()) + " " + what + ", got " + std::to_string(values.size()));
  std::vector<double> x(values.size()), out(values.size());
  hierarchy_.toHierarchyOrder(values.data(), x.data());
  apply(x.data());
  hierarchy_.toInputOrder(x.data(), out.data());
  return out;
}

std::vector<double> MultiresMesh::analyze(const std::vector<double>& positions, int level,
                                          const SchemeOptions& scheme) const {
  return inHierarchyOrder(positions, "coordinates", level, [&](double* x) { transform(scheme).analyze(x, level); });
}

std::vector<double> MultiresMesh::synthesize(const std::vector<double>& coefficients, int level,
                                             const SchemeOptions& scheme) const {
  return inHierarchyOrder(coefficients, "coefficients", level, [&](double* x) { transform(scheme).synthesize(x, level); });
}

double MultiresMesh::roundtripError(const std::vector<double>& positions, int level, const SchemeOptions& scheme) const {
  checkPositions(positions);
  auto back = synthesize(analyze(positions, level, scheme), level, scheme);
  double err = 0;
  for (size_t i = 0; i < back.size(); ++i) err = std::max(err, std::fabs(back[i] - positions[i]));
  return err;
}

// The steps of level l, after checking that the mesh has that level.
const std::vector<LiftingStep>& MultiresMesh::stepsOfLevel(int level, const SchemeOptions& scheme) const {
  if (hierarchy_.levels == 0) throw Error("this mesh has no subdivision level, so no lifting steps");
  if (level < 1 || level > hierarchy_.levels)
    throw Error("level " + std::to_string(level) + " is out of range for lifting steps: level l builds M^l from M^(l-1), l = 1.." +
                std::to_string(hierarchy_.levels));
  return transform(scheme).synthesisSteps(level);
}

// The same, checking a count of steps to run or undo: 0 <= steps <= their count.
const std::vector<LiftingStep>& MultiresMesh::checkedSteps(int level, int steps, const SchemeOptions& scheme) const {
  const auto& all = stepsOfLevel(level, scheme);
  if (steps < 0 || size_t(steps) > all.size())
    throw Error("steps " + std::to_string(steps) + " is out of range: the " + schemeName(scheme.kind) + " scheme has " +
                std::to_string(all.size()) + " lifting steps per level (0.." + std::to_string(all.size()) + ")");
  return all;
}

std::vector<LiftingStep> MultiresMesh::liftingSteps(int level, const SchemeOptions& scheme) const {
  std::vector<LiftingStep> out = stepsOfLevel(level, scheme);
  for (auto& step : out) {
    for (auto& t : step.targets) t = hierarchy_.inputIndex[t];
    for (auto& s : step.sources) s = hierarchy_.inputIndex[s];
  }
  return out;
}

int MultiresMesh::liftingStepCount(int level, const SchemeOptions& scheme) const {
  return int(stepsOfLevel(level, scheme).size());
}

std::vector<double> MultiresMesh::synthesizeSteps(const std::vector<double>& coefficients, int level, int steps,
                                                  const SchemeOptions& scheme) const {
  const auto& all = checkedSteps(level, steps, scheme);
  return inHierarchyOrder(coefficients, "coefficients", level, [&](double* x) {
    for (int k = 0; k < steps; ++k) all[k].forward(x);
  });
}

std::vector<double> MultiresMesh::analyzeSteps(const std::vector<double>& coefficients, int level, int steps,
                                               const SchemeOptions& scheme) const {
  const auto& all = checkedSteps(level, steps, scheme);
  return inHierarchyOrder(coefficients, "coefficients", level, [&](double* x) {
    for (int k = 0; k < steps; ++k) all[all.size() - 1 - k].inverse(x);
  });
}

std::vector<double> MultiresMesh::transposeSteps(const std::vector<double>& covector, int level, int steps,
                                                 const SchemeOptions& scheme) const {
  const auto& all = checkedSteps(level, steps, scheme);
  return inHierarchyOrder(covector, "covector", level, [&](double* x) {
    for (int k = 0; k < steps; ++k) all[all.size() - 1 - k].transposed(x);
  });
}

VolumeTensor MultiresMesh::computeTensor(int level, const SchemeOptions& scheme, TensorStorage storage,
                                         const TensorProgress& progress) const {
  checkLevel(level);
  return computeVolumeTensor(transform(scheme), level, storage, progress);
}

TensorEstimate MultiresMesh::estimateTensor(int level, const SchemeOptions& scheme) const {
  checkLevel(level);
  return estimateCageTensor(transform(scheme), level);
}

uint64_t MultiresMesh::fingerprint() const { return connectivityFingerprint(faces_, vertexCount()); }

ThetaFileHeader MultiresMesh::thetaHeader(const VolumeTensor& tensor, const SchemeOptions& scheme) const {
  ThetaFileHeader h;
  h.scheme = scheme;
  h.levels = hierarchy_.levels;
  h.level = tensor.level;
  h.storage = tensor.storage;
  h.fingerprint = fingerprint();
  h.vertexCount = uint32_t(vertexCount());
  h.nnzFull = tensor.nnzFull;
  h.nnzStored = tensor.storedCount();
  return h;
}

void MultiresMesh::checkTheta(const ThetaFileHeader& h, int level, const SchemeOptions& scheme, bool limitSurface) const {
  if (h.fingerprint != fingerprint() || h.vertexCount != vertexCount() || h.levels != hierarchy_.levels)
    throw Error("theta file does not match this mesh: it was computed for another connectivity (" +
                std::to_string(h.vertexCount) + " vertices, " + std::to_string(h.levels) + " levels)");
  if (h.scheme.kind != scheme.kind)
    throw Error(std::string("theta file was computed for the ") + schemeName(h.scheme.kind) + " scheme, not " +
                schemeName(scheme.kind));
  if (scheme.kind == SchemeKind::Loop && (h.scheme.alpha != scheme.alpha || h.scheme.beta != scheme.beta))
    throw Error("theta file was computed with Loop weights alpha = " + std::to_string(h.scheme.alpha) +
                ", beta = " + std::to_string(h.scheme.beta) + ", not the ones asked for");
  if (h.level != level)
    throw Error("theta file is for level " + std::to_string(h.level) + ", not level " + std::to_string(level));
  if (h.limitSurface != limitSurface)
    throw Error(std::string("theta file holds the volume of the ") + (h.limitSurface ? "limit surface" : "mesh") +
                ", not of the " + (limitSurface ? "limit surface" : "mesh"));
}

double MultiresMesh::tensorVolume(const VolumeTensor& tensor, const SchemeOptions& scheme,
                                  const std::vector<double>& positions) const {
  return tensorVolumeOf(tensor, scheme, triangleForm(hierarchy_.fineFaces()), positions);
}

const FineForm& MultiresMesh::limitForm() const {
  if (!topology_.closed)
    throw Error("the limit surface's volume needs a closed mesh: this one has " +
                std::to_string(topology_.boundaryEdges) + " boundary edges");
  if (!limitForm_) {
    const auto& faces = hierarchy_.fineFaces();
    limitForm_ = std::make_unique<FineForm>(limitVolumeForm(faces.data(), faces.size() / 3, hierarchy_.fineVertexCount()));
  }
  return *limitForm_;
}

double MultiresMesh::limitVolume(const std::vector<double>& positions) const {
  checkPositions(positions);
  const FineForm& form = limitForm();
  std::vector<double> x(positions.size());
  hierarchy_.toHierarchyOrder(positions.data(), x.data());
  return form.evaluate(x.data(), volumeReferencePoint(positions));
}

VolumeTensor MultiresMesh::computeLimitTensor(int level, const SchemeOptions& scheme, TensorStorage storage,
                                              const TensorProgress& progress) const {
  checkLevel(level);
  return computeVolumeTensor(transform(scheme), level, storage, limitForm(), progress);
}

double MultiresMesh::limitTensorVolume(const VolumeTensor& tensor, const SchemeOptions& scheme,
                                       const std::vector<double>& positions) const {
  return tensorVolumeOf(tensor, scheme, limitForm(), positions);
}

double MultiresMesh::tensorVolumeOf(const VolumeTensor& tensor, const SchemeOptions& scheme, const FineForm& fine,
                                    const std::vector<double>& positions) const {
  checkPositions(positions);
  const WaveletTransform& wt = transform(scheme);
  const Vec3 o = volumeReferencePoint(positions);
  const size_t n = vertexCount();
  std::vector<double> x(3 * n);
  hierarchy_.toHierarchyOrder(positions.data(), x.data());
  for (size_t v = 0; v < n; ++v) x[3 * v] -= o.x, x[3 * v + 1] -= o.y, x[3 * v + 2] -= o.z;
  wt.analyze(x.data(), tensor.level);
  double volume = tensor.evaluate(x.data());
  if (tensor.storage == TensorStorage::Cage) {
    std::fill(x.begin(), x.begin() + 3 * size_t(hierarchy_.vertexCount[tensor.level]), 0.0);
    wt.synthesize(x.data(), tensor.level);
    volume += fine.evaluate(x.data());
  }
  return volume;
}

}  // namespace mrvol

