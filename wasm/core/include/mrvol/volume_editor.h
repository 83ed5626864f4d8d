// Volume-preserving deformation of the level-e cage (method section 7): given any target shape of
// the cage, the smallest change of the free coefficients that restores the reference volume(s).
//
// The editing session: it holds the coefficients and chooses, once, what the solver
// (volume_solver.h) works on: the cage polynomial (cage_polynomial.h, tensor path) or the volume
// functions of the fine positions (volume_function.h, matrix-free path: the whole mesh, or one per
// part), with the fine positions kept in step by the stencils (stencil_table.h).
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "mrvol/cage_edit.h"
#include "mrvol/cage_polynomial.h"
#include "mrvol/cage_polynomial_builder.h"
#include "mrvol/cage_polynomial_path.h"
#include "mrvol/coefficient_volumes.h"
#include "mrvol/lifting.h"
#include "mrvol/mesh.h"
#include "mrvol/volume_function.h"
#include "mrvol/volume_solver.h"
#include "mrvol/volume_tensor.h"

namespace mrvol {

// An editing session on one mesh at level e. Coefficients live in hierarchy order; the calls that
// take or give positions use the caller's vertex order.
class VolumeEditor {
 public:
  VolumeEditor(const Hierarchy& hierarchy, const WaveletTransform& transform, int level, const double* positions);
  VolumeEditor(const VolumeEditor&) = delete;  // its parts refer to each other
  VolumeEditor& operator=(const VolumeEditor&) = delete;

  int level() const { return level_; }
  uint32_t cageSize() const { return session_.cageSize; }
  // Caller's index of every cage vertex, in cage order (hierarchy order).
  std::vector<uint32_t> cageVertices() const;
  // Cage order index of a caller's vertex, or throws Error if it is not a level-e cage vertex.
  uint32_t cageIndexOf(uint32_t callerVertex) const;

  double referenceVolume() const { return reference_; }
  void setReferenceVolume(double volume);
  double volume() const;  // current volume (from the fine mesh, or its limit surface; exact)

  // The surface whose volume is kept: the fine mesh (default) or, given the Loop limit surface's
  // volume form of the fine mesh (limit_volume.h, hierarchy numbering), the limit surface. The
  // reference becomes the current volume of that surface. The limit surface runs matrix-free, or
  // on the tensor path with theta^e of the limit form (useTensor); the polynomial builder knows
  // only the mesh's triangles. Not with parts or the centre of mass.
  void useLimitSurface(const FineForm& limitForm);
  bool limitSurface() const { return limitVolume_ != nullptr; }

  // Keeping the centre of mass (of the mesh's solid) with the volume: three more rows, the first
  // moments about the centre of mass now, each kept at zero (matrix-free path; not with parts). A
  // moment row's error is relative to |V| times a tenth of the bounding-box diagonal: the centroid's
  // drift stays under a tenth of the tolerance times the model's size, whatever the volume's error.
  void keepCentroid(bool keep);
  bool keepsCentroid() const { return keepCentroid_; }
  // The mesh solid's centre of mass now (caller's frame) and the one kept (reference moments over
  // the reference volume).
  Vec3 centroid() const;
  Vec3 referenceCentroid() const;

  // Gradient path. The tensor must be theta^e with Cage storage for this mesh and scheme.
  void useTensor(const VolumeTensor& tensor);
  // The same cage polynomial built from the fine triangles (CagePolynomialBuilder), no tensor; it
  // is rebuilt when a correction has moved the details (free detail levels). Returns false, and
  // runs matrix-free, when the builder refuses (more than maxTerms cage triples).
  bool usePolynomial(uint64_t maxTerms = 8'000'000);
  void useMatrixFree();
  GradientPath path() const {
    return polynomial_.path();
  }

  // Free set: which cage vertices may absorb the correction (the ones not held in a deformation,
  // all of them, or a list in cage order), and optionally the details of chosen levels (e <= l < n:
  // d^l, the vertices born at level l + 1; matrix-free path only). Boundary vertices are never free.
  using FreeCage = mrvol::FreeCage;  // cage_edit.h
  void setFreeSet(FreeCage mode, std::vector<uint32_t> list = {}, std::vector<int> detailLevels = {});

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
  // The fine positions as the session keeps them (3 N doubles and 3 more, hierarchy order, relative
  // to referencePoint()), brought up to date; their version changes whenever they do (SurfaceBuffers).
  const std::vector<double>& finePositions() const { return session_.fine.of(session_.x); }
  uint64_t finePositionsVersion() const { return session_.fine.version(); }
  void takeFinePositionChanges(FinePositions::Changes& out) const { session_.fine.takeChanges(out); }
  Vec3 referencePoint() const { return session_.origin; }
  // The level-e coefficients (3 * N, hierarchy order: the cage's first) without a copy, and what a
  // follower of cage moves needs besides (SurfaceBuffers with a CageBasisTable).
  const double* coefficientData() const { return session_.x.data(); }
  uint64_t detailsVersion() const { return session_.fine.detailsVersion(); }
  const WaveletTransform& transform() const { return *transform_; }

  // Theta_tau for every coefficient at level e (3 * N, hierarchy order) by the matrix-free path,
  // and for the cage (3 * cageSize) by the tensor polynomial; both for tests.
  double gradientMatrixFree(std::vector<double>& gradient) const;
  double gradientTensor(std::vector<double>& gradient) const;

 private:
  // The one choice of what the solver works on: the polynomial when a tensor is in use and
  // neither details nor parts call for the fine mesh.
  bool usesTensor() const { return polynomial_.active() && free_.detailLevels.empty() && parts_.empty() && !keepCentroid_; }
  const VolumeFunction& surfaceVolume() const;  // the mesh's or the limit surface's
  double meshMoments(double moments[3]) const;  // the mesh volume, and its first moments about the moments' centre
  double momentChange() const;                  // the moments' largest relative deviation now
  VolumeConstraints& constraints();  // the active ones, references up to date
  // Row 0 of the active constraints (the global volume or part 0); withGradient: on the matrix-free
  // path, its gradient is computed in the same pass and kept for the solver's first iteration.
  double constrainedVolume(bool withGradient);
  void configureFineRows();  // the matrix-free rows for the current parts and free details
  VolumeSolver& solver(const std::vector<uint8_t>& held);  // precomputed for this free set
  void setCage(const double* cage);  // the cage coefficients take these values
  GradientPath activePath() const { return usesTensor() ? path() : GradientPath::MatrixFree; }
  void startEdit(const EditOptions& options);  // checks the options, brings the polynomial up to date
  void finishReport(EditReport& report) const;

  const Hierarchy* hierarchy_;
  const WaveletTransform* transform_;
  int level_;
  mutable SessionCoefficients session_;
  FineEdgeVolume fineVolume_;
  std::unique_ptr<FormVolume> limitVolume_;
  std::vector<FirstMoment> moments_;  // x, y, z
  bool keepCentroid_ = false;
  double momentScale_ = 1;
  double reference_ = 0;
  CagePolynomialPath polynomial_{session_};
  // Set on the polynomial path: the builder, and whether the details moved since the build.
  mutable FineVolumeConstraints fineConstraints_;
  FreeSet free_;
  std::vector<TriangleSetVolume> parts_;
  std::vector<double> partReference_;
  // The precomputed solver, kept while the constraints and the free set stay the same.
  std::unique_ptr<VolumeSolver> solver_;
  const VolumeConstraints* solverConstraints_ = nullptr;
};

}  // namespace mrvol
