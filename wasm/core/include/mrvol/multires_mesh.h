// A semi-regular mesh's connectivity with its hierarchy and wavelet transforms: the object the
// bindings, the JS API and the command line work with. It holds no positions (connectivity apart
// from geometry, as geometry-central's SurfaceMesh): positions are passed to the calls that need
// them. Positions and coefficients cross it in the caller's vertex order; inside, everything is in
// hierarchy order.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "mrvol/hierarchy.h"
#include "mrvol/lifting.h"
#include "mrvol/mesh.h"
#include "mrvol/volume_tensor.h"

namespace mrvol {

struct MeshInfo {
  size_t vertices = 0, faces = 0;
  int levels = 0;
  size_t baseVertices = 0;
  std::vector<uint32_t> baseVertexIndices;  // caller's indices of the level-0 vertices, ascending
  bool closed = false;
  size_t boundaryEdges = 0;
  long genus = 0;
  size_t components = 0;
  double volume = 0;
};

// What MultiresMesh and QuadMultiresMesh share. Throws Error unless `positions` are 3 finite
// numbers per vertex of a mesh of vertexCount vertices.
void checkPositionArray(const std::vector<double>& positions, size_t vertexCount);
// The counts, levels, base vertices and topology of a hierarchy's fine mesh (volume left 0).
MeshInfo hierarchyInfo(const Hierarchy& hierarchy, const MeshTopology& topology, size_t faces);

class MultiresMesh {
 public:
  // Validates the mesh and detects its hierarchy (at most maxLevels levels); keeps its faces.
  // `lines` (from readObj) add the OBJ line of what validation messages name.
  explicit MultiresMesh(const TriangleMesh& mesh, int maxLevels = 16, const SourceLines* lines = nullptr);
  // The same, taking the arrays over: the positions are freed once validated and the faces kept
  // without a copy (opening a large mesh holds one copy of each at most).
  explicit MultiresMesh(TriangleMesh&& mesh, int maxLevels = 16, const SourceLines* lines = nullptr);
  // n splits of a validated base mesh (its vertices keep their indices, the new ones follow).
  static MultiresMesh subdivide(const TriangleMesh& base, int levels);
  // A validated mesh's faces with its known topology and hierarchy (hierarchy_transfer.h checks them).
  static MultiresMesh fromParts(std::vector<uint32_t> faces, MeshTopology topology, Hierarchy hierarchy);
  // Positions of the split mesh: zero-detail synthesis with `scheme` of the base positions.
  std::vector<double> subdivisionPositions(const std::vector<double>& basePositions, const SchemeOptions& scheme) const;

  const Hierarchy& hierarchy() const { return hierarchy_; }
  const std::vector<uint32_t>& faces() const { return faces_; }  // the caller's faces
  size_t vertexCount() const { return hierarchy_.fineVertexCount(); }
  const MeshTopology& topology() const { return topology_; }
  int levels() const { return hierarchy_.levels; }
  // Throws Error unless `positions` holds 3 finite coordinates per vertex.
  void checkPositions(const std::vector<double>& positions) const;
  MeshInfo info(const std::vector<double>& positions) const;
  // Triangles of the level-l mesh (0 <= l <= n) in the caller's vertex indices; l = n gives the
  // caller's faces as the hierarchy orders them.
  std::vector<uint32_t> levelFaces(int level) const;

  // The transform for a scheme, built on first use and kept.
  const WaveletTransform& transform(const SchemeOptions& scheme) const;

  // Caller's order in and out: coefficients of level e (coarse c^e for depth <= e, details beyond).
  std::vector<double> analyze(const std::vector<double>& positions, int level, const SchemeOptions& scheme) const;
  std::vector<double> synthesize(const std::vector<double>& coefficients, int level, const SchemeOptions& scheme) const;
  // max |synthesis(analysis(x)) - x| over the positions.
  double roundtripError(const std::vector<double>& positions, int level, const SchemeOptions& scheme) const;

  // One level's lifting phases (paper Figure 3), for teaching views. Level l (1 <= l <= n) is the
  // synthesis step from M^{l-1} to M^l: liftingSteps gives its steps in the order they apply ("U",
  // "P_o", "N", "P_e" for Loop; "U", "P" for Butterfly and linear) with targets and sources in the
  // caller's vertex indices (offsets, weights, scaling factors as in LiftingStep).
  std::vector<LiftingStep> liftingSteps(int level, const SchemeOptions& scheme) const;
  int liftingStepCount(int level, const SchemeOptions& scheme) const;
  // Caller's order in and out (3 per vertex, all N vertices; only depth <= l are touched).
  // synthesizeSteps runs the first `steps` steps of level l on level-(l-1) coefficients (c^{l-1}
  // for depth < l, d^{l-1} for depth l); all of them give the level-l coefficients c^l.
  // analyzeSteps undoes the last `steps` steps in reverse order, from c^l: it runs analysis phase
  // by phase, and analyzeSteps(synthesizeSteps(c, l, S), l, S - k) == synthesizeSteps(c, l, k).
  std::vector<double> synthesizeSteps(const std::vector<double>& coefficients, int level, int steps,
                                      const SchemeOptions& scheme) const;
  std::vector<double> analyzeSteps(const std::vector<double>& coefficients, int level, int steps,
                                   const SchemeOptions& scheme) const;
  // The adjoint of level l's synthesis, phase by phase (paper Figure 5: the masks applied
  // outwards): the transposes of the last `steps` steps, in reverse order, on a covector of the
  // level-l vertices; all of them give the covector of (c^{l-1}, d^{l-1}).
  std::vector<double> transposeSteps(const std::vector<double>& covector, int level, int steps,
                                     const SchemeOptions& scheme) const;

  // theta^e for this connectivity and scheme, and the header a theta file of it carries.
  VolumeTensor computeTensor(int level, const SchemeOptions& scheme, TensorStorage storage,
                             const TensorProgress& progress = {}) const;
  TensorEstimate estimateTensor(int level, const SchemeOptions& scheme) const;
  ThetaFileHeader thetaHeader(const VolumeTensor& tensor, const SchemeOptions& scheme) const;
  uint64_t fingerprint() const;
  // Throws Error naming the first mismatch (mesh connectivity, scheme, level) of a theta file.
  void checkTheta(const ThetaFileHeader& header, int level, const SchemeOptions& scheme, bool limitSurface = false) const;
  // Volume of the positions evaluated through the tensor (in the frame of volumeReferencePoint).
  // With Cage storage the detail-only entries, which were never formed, contribute Theta(x with
  // cage coefficients zeroed), computed by synthesis.
  double tensorVolume(const VolumeTensor& tensor, const SchemeOptions& scheme, const std::vector<double>& positions) const;

  // The same for the Loop limit surface of the fine mesh (limit_volume.h): its volume from the
  // positions, theta^e of the limit form, and the volume through such a tensor. Closed meshes
  // only (throws Error otherwise).
  double limitVolume(const std::vector<double>& positions) const;
  VolumeTensor computeLimitTensor(int level, const SchemeOptions& scheme, TensorStorage storage,
                                  const TensorProgress& progress = {}) const;
  double limitTensorVolume(const VolumeTensor& tensor, const SchemeOptions& scheme,
                           const std::vector<double>& positions) const;
  // The limit volume form itself, in hierarchy numbering (built on first use; editors keep it).
  const FineForm& limitForm() const;

 private:
  MultiresMesh() = default;
  void checkLevel(int level) const;
  // volumeReferencePoint of the caller's positions, from the hierarchy's boundary flags (no corner
  // lists, no copy of the arrays).
  Vec3 volumeReferencePoint(const std::vector<double>& positions) const;
  const std::vector<LiftingStep>& stepsOfLevel(int level, const SchemeOptions& scheme) const;
  const std::vector<LiftingStep>& checkedSteps(int level, int steps, const SchemeOptions& scheme) const;
  double tensorVolumeOf(const VolumeTensor& tensor, const SchemeOptions& scheme, const FineForm& fine,
                        const std::vector<double>& positions) const;
  template <class Apply>
  std::vector<double> inHierarchyOrder(const std::vector<double>& values, const char* what, int level, Apply&& apply) const;
  std::vector<uint32_t> faces_;
  MeshTopology topology_;
  Hierarchy hierarchy_;
  mutable std::vector<std::unique_ptr<WaveletTransform>> transforms_;
  mutable std::unique_ptr<FineForm> limitForm_;
};

}  // namespace mrvol
