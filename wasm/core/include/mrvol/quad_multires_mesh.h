// A semi-regular quad mesh with its Catmull-Clark hierarchy and transform: what the bindings and
// the command line work with for quads (the counterpart of multires_mesh.h). Positions and
// coefficients cross it in the caller's vertex order.
#pragma once
#include <memory>
#include <vector>

#include "mrvol/multires_mesh.h"
#include "mrvol/quad_hierarchy.h"
#include "mrvol/quad_lifting.h"
#include "mrvol/quad_volume.h"
#include "mrvol/volume_tensor.h"

namespace mrvol {

class QuadMultiresMesh {
 public:
  // Validates the quad mesh and detects its splits (at most maxLevels).
  explicit QuadMultiresMesh(const QuadMesh& mesh, int maxLevels = 16);
  // n splits of a valid base quad mesh (its vertices keep their indices, the new ones follow).
  static QuadMultiresMesh subdivide(const QuadMesh& base, int levels);
  // Catmull-Clark subdivision of the base positions (zero-detail synthesis), hierarchy = caller order.
  std::vector<double> subdivisionPositions(const std::vector<double>& basePositions) const;

  const QuadHierarchy& hierarchy() const { return *hierarchy_; }
  const WaveletTransform& transform() const { return *transform_; }
  const std::vector<uint32_t>& quads() const { return quads_; }  // the caller's quads
  size_t vertexCount() const { return hierarchy_->h.fineVertexCount(); }
  int levels() const { return hierarchy_->levels(); }
  // The lowest level analysis reaches: 1 when the base is a cube (quad_lifting.h), else 0.
  int lowestLevel() const { return lowestLevel_; }
  const MeshTopology& topology() const { return topology_; }
  void checkPositions(const std::vector<double>& positions) const;
  // volume: the bilinear patches' (quad_volume.h).
  MeshInfo info(const std::vector<double>& positions) const;
  double volume(const std::vector<double>& positions) const;
  // Quads of level l in the caller's indices (l = n: the caller's quads as the hierarchy orders them).
  std::vector<uint32_t> levelQuads(int level) const;

  // Level l's synthesis steps (1 <= l <= n: "P_f", "P_e", "N_3k"/"P_3k" per valence-3 layer, "N_v",
  // "P_v"; quad_lifting.h) with targets and sources in the caller's vertex indices, for teaching views.
  std::vector<LiftingStep> liftingSteps(int level) const;

  std::vector<double> analyze(const std::vector<double>& positions, int level) const;
  std::vector<double> synthesize(const std::vector<double>& coefficients, int level) const;
  double roundtripError(const std::vector<double>& positions, int level) const;

  VolumeTensor computeTensor(int level, TensorStorage storage, const TensorProgress& progress = {}) const;
  ThetaFileHeader thetaHeader(const VolumeTensor& tensor) const;
  uint64_t fingerprint() const;
  void checkTheta(const ThetaFileHeader& header, int level) const;
  double tensorVolume(const VolumeTensor& tensor, const std::vector<double>& positions) const;

 private:
  QuadMultiresMesh() = default;
  void build();
  void checkLevel(int level, bool analysis) const;
  std::vector<uint32_t> quads_;
  MeshTopology topology_;
  std::unique_ptr<QuadHierarchy> hierarchy_;
  std::unique_ptr<WaveletTransform> transform_;
  std::unique_ptr<FineForm> form_;
  int lowestLevel_ = 0;
};

}  // namespace mrvol
