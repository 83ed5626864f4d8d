// Volume-preserving deformation of the level-e cage (method section 7): given any target shape of
// the cage, the smallest change of the free coefficients that restores the reference volume(s).
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "mrvol/lifting.h"
#include "mrvol/mesh.h"
#include "mrvol/volume_tensor.h"

namespace mrvol {

enum class GradientPath { Tensor, MatrixFree };
const char* gradientPathName(GradientPath path);

// The volume as a cubic polynomial of the cage coefficients c (details fixed), contracted once from
// the cage rows of theta^e:  Theta(c) = constant + sum_i a_i . c_i + sum_{i<j} c_i . (c_j x q_ij)
// + sum_{i<j<k} T_ijk c_i . (c_j x c_k). Evaluating it costs nothing like a pass over the mesh.
struct CagePolynomial {
  uint32_t cageSize = 0;
  double constant = 0;
  std::vector<double> linear;                          // a_i, 3 per cage vertex
  std::vector<uint32_t> pairI, pairJ;                  // cage pairs with a quadratic term
  std::vector<double> pairQ;                           // q_ij, 3 per pair
  std::vector<uint32_t> tripleI, tripleJ, tripleK;     // cage triples, in runs of one (i, j) (any order is
                                                       // correct; runs share their cross products)
  std::vector<double> tripleT;
  double evaluate(const double* cage, double* gradient /* 3 * cageSize or null */) const;
  // The cubic s -> Theta(cage + s direction): its coefficients k[0] + k[1] s + k[2] s^2 + k[3] s^3.
  void alongDirection(const double* cage, const double* direction, double* k) const;
};

struct EditOptions {
  double tolerance = 1e-5;  // relative volume error to reach
  int maxIterations = 50;   // per sub-step
  int maxSubsteps = 64;
  double substepError = 0.05;  // a move whose raw relative volume change exceeds this is split
  bool preserve = true;
  // Matrix-free path: after the linearized step, solve the cubic the volume is along its direction
  // (one pass over the triangles) instead of iterating linearizations. Off: the paper's iteration.
  bool lineSearch = true;
};

struct EditReport {
  double volumeReference = 0, volumeTarget = 0, volumeResult = 0, relativeError = 0;
  int iterations = 0, substeps = 0;
  bool converged = true;
  std::string message;  // why it did not converge
  GradientPath path = GradientPath::MatrixFree;
  std::vector<double> partVolumes, partReferences;
};

// An editing session on one mesh at level e. Coefficients live in hierarchy order; the calls that
// take or give positions use the caller's vertex order.
class VolumeEditor {
 public:
  VolumeEditor(const Hierarchy& hierarchy, const WaveletTransform& transform, int level, const double* positions);

  int level() const { return level_; }
  uint32_t cageSize() const { return cageSize_; }
  // Caller's index of every cage vertex, in cage order (hierarchy order).
  std::vector<uint32_t> cageVertices() const;
  // Cage order index of a caller's vertex, or throws Error if it is not a level-e cage vertex.
  uint32_t cageIndexOf(uint32_t callerVertex) const;

  double referenceVolume() const { return reference_; }
  void setReferenceVolume(double volume);
  double volume() const;  // current volume (from the fine mesh, exact)

  // Gradient path. The tensor must be theta^e with Cage storage for this mesh and scheme.
  void useTensor(const VolumeTensor& tensor);
  void useMatrixFree();
  GradientPath path() const { return polynomial_ ? GradientPath::Tensor : GradientPath::MatrixFree; }

  // Free set: which cage vertices may absorb the correction (the ones not held in a deformation,
  // all of them, or a list in cage order), and optionally the details of chosen levels (e <= l < n:
  // d^l, the vertices born at level l + 1; matrix-free path only). Boundary vertices are never free.
  enum class FreeCage { MinusHeld, All, List };
  void setFreeSet(FreeCage mode, std::vector<uint32_t> list = {}, std::vector<int> detailLevels = {});
  void clearFreeSet() { setFreeSet(FreeCage::MinusHeld); }

  // Localized preservation: parts of the cage (cage order indices), each keeping its own volume
  // (the volume of the fine triangles it dominates, as a cone to the reference point). Empty: one
  // global constraint. References default to the current part volumes.
  void setParts(const std::vector<std::vector<uint32_t>>& parts, const std::vector<double>& references = {});
  size_t partCount() const { return partReference_.size(); }
  std::vector<double> partVolumes() const;

  // Moves the cage to `target` (3 * cageSize, cage order) with the `held` cage vertices kept where
  // the target puts them, then restores the volume with the smallest change of the free set.
  EditReport deformCage(const std::vector<double>& target, const std::vector<uint8_t>& held, const EditOptions& options);
  // Restores the volume of the current shape (no move).
  EditReport correct(const std::vector<uint8_t>& held, const EditOptions& options);

  std::vector<double> cagePositions() const;  // 3 * cageSize, cage order
  std::vector<double> positions() const;      // fine positions, caller's order
  std::vector<double> coefficients() const;   // level-e coefficients, hierarchy order

  // Theta_tau for every coefficient at level e (3 * N, hierarchy order) by the matrix-free path,
  // and for the cage (3 * cageSize) by the tensor polynomial; both for tests.
  double gradientMatrixFree(std::vector<double>& gradient) const;
  double gradientTensor(std::vector<double>& gradient) const;

 private:
  // Fine positions of x_ relative to origin_, hierarchy order, plus one more vertex at the origin
  // (index N) that closes boundary loops as cones: 3 (N + 1) doubles (cached).
  const std::vector<double>& fine() const;
  // Volume of fine positions p (about origin_) and, if grad is given, its gradient (3 (N + 1)).
  double edgePass(const double* p, double* grad) const;
  double maskedVolume(const double* p, double* grad, const std::vector<uint8_t>& triangleMask) const;
  double fineVolumeAndGradient(std::vector<double>* fineGradient, const std::vector<uint8_t>* triangleMask) const;
  std::vector<double> shiftedCage() const;  // cage coefficients relative to origin_
  std::vector<uint32_t> freeCoefficients(const std::vector<uint8_t>& held) const;
  void solveGlobal(const std::vector<uint32_t>& free, const EditOptions& options, EditReport& report);
  void solveParts(const std::vector<uint32_t>& free, const EditOptions& options, EditReport& report);

  const Hierarchy* hierarchy_;
  const WaveletTransform* transform_;
  int level_;
  uint32_t cageSize_;
  Vec3 origin_;
  std::vector<double> x_;  // level-e coefficients, hierarchy order
  // Every fine edge once, 4 indices each: its ends b, c and the vertices opposite it, a in the
  // triangle (a, b, c) and d in (d, c, b), d = N on the boundary; sorted by the ends, so that the
  // passes over it walk the vertex arrays nearly in order.
  std::vector<uint32_t> edges_;
  // Volumes are evaluated about origin_ (fixed: the boundary stays put), so that meshes far from
  // the origin keep their digits; a translation only shifts the cage coefficients.
  mutable std::vector<double> fine_;  // see fine(); in step with x_ when fineValid_
  mutable bool fineValid_ = false;
  // While fineBaseValid_, fine_ is the synthesis of x_ with its cage replaced by fineCage_ (the
  // details agree): a cage move then updates fine_ by a zero-detail synthesis of the move.
  mutable bool fineBaseValid_ = false;
  mutable std::vector<double> fineCage_, fineDelta_;
  mutable int incrementalUpdates_ = 0;  // since the last full synthesis
  // Zero-detail synthesis of one cage vertex (its subdivision basis function at the fine level,
  // sparse), kept for the last few vertices moved (at most 8, and 4 entries per fine vertex in
  // all): a drag that moves one or two handles updates fine_ along their supports instead of by a
  // synthesis of the whole mesh.
  struct BasisColumn {
    uint32_t cageVertex;
    std::vector<uint32_t> vertices;
    std::vector<double> weights;
  };
  mutable std::vector<BasisColumn> basisCache_;  // most recently used last
  const BasisColumn& basisColumn(uint32_t cageVertex) const;
  // Volume (and fine-level gradient) of fine_, valid while fine_ is.
  mutable double cachedVolume_ = 0;
  mutable std::vector<double> cachedGradient_;
  mutable bool volumeValid_ = false, gradientValid_ = false;
  std::vector<double> scratchGradient_, scratchDirection_;  // kept between steps: no 3N allocations
  double volumeAndGradient(std::vector<double>& fineGradient) const;
  void prepareGradient() const;
  double reference_ = 0;
  std::unique_ptr<CagePolynomial> polynomial_;
  FreeCage freeMode_ = FreeCage::MinusHeld;
  std::vector<uint32_t> freeCage_;
  std::vector<int> freeDetailLevels_;
  std::vector<std::vector<uint8_t>> partTriangles_;  // per part, per fine triangle
  std::vector<double> partReference_;
};

}  // namespace mrvol
