// What both editing sessions (VolumeEditor on triangle meshes, QuadVolumeEditor on quad meshes)
// share: the level-e coefficients and their fine positions, the reference volume, the free set,
// the gradient paths (the cage polynomial, or the fine rows with the adjoint of synthesis), the
// solver kept for them, and the two edits made of these: correct() and deformCage(). What differs
// comes through a few virtual calls, a handful per edit and none inside the solver's iterations:
// the surface's volume function, the rows kept besides the volume (the triangle editor's parts and
// centre of mass), and what the report says of them.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "mrvol/cage_edit.h"
#include "mrvol/cage_polynomial_path.h"
#include "mrvol/coefficient_volumes.h"
#include "mrvol/hierarchy.h"
#include "mrvol/lifting.h"
#include "mrvol/volume_function.h"
#include "mrvol/volume_solver.h"
#include "mrvol/volume_tensor.h"

namespace mrvol {

class CageEditor {
 public:
  CageEditor(const CageEditor&) = delete;  // its parts refer to each other
  CageEditor& operator=(const CageEditor&) = delete;
  virtual ~CageEditor() = default;

  int level() const { return level_; }
  uint32_t cageSize() const { return session_.cageSize; }
  // Caller's index of every cage vertex, in cage order (hierarchy order).
  std::vector<uint32_t> cageVertices() const;
  // Cage order index of a caller's vertex, or throws Error if it is not a level-e cage vertex.
  uint32_t cageIndexOf(uint32_t callerVertex) const;

  double referenceVolume() const { return reference_; }
  void setReferenceVolume(double volume);
  // The current volume of the surface kept (exact, from the fine positions).
  virtual double volume() const { return fineConstraints_.value(); }

  // Keeping the centre of mass (of the mesh's solid) with the volume: three more rows, the first
  // moments about the centre of mass now, each kept at zero (matrix-free path). A moment row's
  // error is relative to |V| times a tenth of the bounding-box diagonal: the centroid's drift stays
  // under a tenth of the tolerance times the model's size, whatever the volume's error.
  void keepCentroid(bool keep);
  bool keepsCentroid() const { return keepCentroid_; }
  // The mesh solid's centre of mass now (caller's frame) and the one kept (reference moments over
  // the reference volume).
  Vec3 centroid() const;
  Vec3 referenceCentroid() const;

  // Gradient paths. The tensor must be theta^e with Cage storage for this mesh and scheme.
  void useTensor(const VolumeTensor& tensor);
  void useMatrixFree();
  GradientPath path() const { return polynomial_.path(); }

  using FreeCage = mrvol::FreeCage;  // cage_edit.h
  // Free set (cage_edit.h): which cage vertices may absorb the correction, and optionally the
  // details of chosen levels (matrix-free path only). Boundary vertices are never free.
  void setFreeSet(FreeCage mode, std::vector<uint32_t> list = {}, std::vector<int> detailLevels = {});

  // Moves the cage to `target` (3 * cageSize, cage order) with the `held` cage vertices kept where
  // the target puts them, then restores the volume with the smallest change of the free set.
  EditReport deformCage(const std::vector<double>& target, const std::vector<uint8_t>& held, const EditOptions& options);
  // Restores the volume of the current shape (no move).
  EditReport correct(const std::vector<uint8_t>& held, const EditOptions& options);

  std::vector<double> cagePositions() const;  // 3 * cageSize, cage order
  std::vector<double> positions() const;      // fine positions, caller's order
  std::vector<double> coefficients() const { return session_.x; }  // level-e coefficients, hierarchy order
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

  // Theta_tau for every coefficient at level e (3 * N, hierarchy order) by the matrix-free path
  // (the fine mesh's volume), and for the cage (3 * cageSize) by the polynomial in use (throws
  // Error without one); both for tests.
  double gradientMatrixFree(std::vector<double>& gradient) const;
  double gradientPolynomial(std::vector<double>& gradient) const { return polynomial_.gradient(gradient); }

 protected:
  // hierarchy: the triangle or quad hierarchy's vertex numbering and levels; session: the
  // coefficients at `level` (checked by checkedLevel before the analysis that made them).
  CageEditor(const Hierarchy& hierarchy, const WaveletTransform& transform, int level, SessionCoefficients session);
  static int checkedLevel(const Hierarchy& hierarchy, int level);
  static double relative(double value, double reference);

  // The fine mesh's volume function (the matrix-free gradient's, and row 0 by default), and its
  // first moments along x, y, z (set by the constructor: FirstMoment, QuadFirstMoment).
  virtual const VolumeFunction& meshVolume() const = 0;
  std::vector<std::unique_ptr<MomentFunction>> moments_;
  // Throws Error when the centre of mass cannot be kept now (the triangle editor's limit surface, parts).
  virtual void checkCentroidKept() const {}
  // Rows kept besides the one volume (parts, the centre of mass): they run on the fine rows.
  virtual bool needsFineRows() const { return keepCentroid_; }
  // The fine rows for the current free set (and whatever else the editor keeps); resets the solver.
  virtual void configureFineRows();
  // The fine rows' references (and scales) before a solve.
  virtual void setFineReferences();
  // Whether row 0 is the volume reported (not part 0 of several).
  virtual bool rowIsVolume() const { return true; }
  // The relative change a move of the cage made, for the sub-step count.
  double rawChange(double volumeTarget) const;
  // The mesh volume, and its first moments about the moments' centre (a pass of each by default).
  virtual double meshMoments(double moments[3]) const;
  double momentChange() const;                  // the moments' largest relative deviation now
  // The report's error and whatever else the editor keeps (part volumes, centres of mass).
  virtual void finishReport(EditReport& report) const;

  // The one choice of what the solver works on: the polynomial when one is in use and neither
  // details nor other rows call for the fine mesh.
  bool usesPolynomial() const { return polynomial_.active() && free_.detailLevels.empty() && !needsFineRows(); }
  GradientPath activePath() const { return usesPolynomial() ? path() : GradientPath::MatrixFree; }
  VolumeConstraints& constraints();  // the active ones, references up to date
  // Row 0 of the active constraints; withGradient: on the matrix-free path, its gradient is
  // computed in the same pass and kept for the solver's first iteration.
  double constrainedVolume(bool withGradient);
  VolumeSolver& solver(const std::vector<uint8_t>& held);  // precomputed for this free set
  void setCage(const double* cage);                        // the cage coefficients take these values
  void startEdit(const EditOptions& options);  // checks the options, brings the polynomial up to date

  const Hierarchy* hierarchy_;
  const WaveletTransform* transform_;
  int level_;
  mutable SessionCoefficients session_;
  double reference_ = 0;
  bool keepCentroid_ = false;
  double momentScale_ = 1;
  FreeSet free_;
  // The polynomial in use (tensor or builder), and whether the details moved since a build.
  CagePolynomialPath polynomial_{session_};
  mutable FineVolumeConstraints fineConstraints_;
  // The precomputed solver, kept while the constraints and the free set stay the same.
  std::unique_ptr<VolumeSolver> solver_;
  const VolumeConstraints* solverConstraints_ = nullptr;
  std::vector<uint8_t> solverHeld_;  // the held flags the solver's free set was made for
};

}  // namespace mrvol
