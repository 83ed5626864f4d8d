// Volume-preserving editing of a quad mesh's level-e cage (docs/catmull-clark.md, section 5): the
// volume is the bilinear patches' (quad_volume.h), the solver and its gradient paths are the
// triangle editor's (volume_solver.h, coefficient_volumes.h, cage_edit.h): the cage polynomial
// contracted from the quad theta^e (tensor) or built from the fine quads (polynomial,
// CagePolynomialBuilder over bilinearPatchRegions), or the bilinear volume of the fine positions
// with the adjoint of synthesis (matrix-free). One global volume; the free set as the triangle
// editor's (cage minus the held vertices, all, a list; details of chosen levels); boundary
// vertices stay fixed.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "mrvol/cage_edit.h"
#include "mrvol/cage_polynomial.h"
#include "mrvol/cage_polynomial_builder.h"
#include "mrvol/cage_polynomial_path.h"
#include "mrvol/coefficient_volumes.h"
#include "mrvol/quad_hierarchy.h"
#include "mrvol/quad_volume.h"
#include "mrvol/volume_solver.h"

namespace mrvol {

class QuadVolumeEditor {
 public:
  // positions: 3 per vertex, caller's order. Throws Error when level is out of range or analysis
  // cannot reach it (a cube's level 0, quad_lifting.h).
  QuadVolumeEditor(const QuadHierarchy& hierarchy, const WaveletTransform& transform, int level,
                   const double* positions);
  QuadVolumeEditor(const QuadVolumeEditor&) = delete;
  QuadVolumeEditor& operator=(const QuadVolumeEditor&) = delete;

  int level() const { return level_; }
  uint32_t cageSize() const { return session_.cageSize; }
  std::vector<uint32_t> cageVertices() const;  // caller's index of every cage vertex, cage order
  uint32_t cageIndexOf(uint32_t callerVertex) const;

  double referenceVolume() const { return reference_; }
  void setReferenceVolume(double volume);
  double volume() const;  // bilinear volume of the current fine positions

  void useTensor(const VolumeTensor& tensor);  // theta^e with cage storage of the bilinear form
  // The same cage polynomial built from the fine quads (no tensor); rebuilt when a correction has
  // moved free details. Returns false, and runs matrix-free, when the builder refuses (more than
  // maxTerms cage triples).
  bool usePolynomial(uint64_t maxTerms = 8'000'000);
  void useMatrixFree();
  GradientPath path() const { return polynomial_.path(); }
  // Free set (cage_edit.h). Free details run on the matrix-free path whatever the path chosen.
  void setFreeSet(FreeCage mode, std::vector<uint32_t> list = {}, std::vector<int> detailLevels = {});
  // false: only the held vertices' complement is free (default); true: every non-boundary cage vertex.
  void setAllFree(bool all) { setFreeSet(all ? FreeCage::All : FreeCage::MinusHeld); }

  // Theta_tau for every coefficient at level e (3 * N, hierarchy order) by the matrix-free path,
  // and for the cage (3 * cageSize) by the polynomial in use (throws Error without one).
  double gradientMatrixFree(std::vector<double>& gradient) const;
  double gradientPolynomial(std::vector<double>& gradient) const;

  EditReport deformCage(const std::vector<double>& target, const std::vector<uint8_t>& held, const EditOptions& options);
  EditReport correct(const std::vector<uint8_t>& held, const EditOptions& options);

  std::vector<double> cagePositions() const;  // 3 * cageSize, cage order
  std::vector<double> positions() const;      // fine positions, caller's order
  std::vector<double> coefficients() const { return session_.x; }

 private:
  bool usesPolynomial() const { return polynomial_.active() && free_.detailLevels.empty(); }
  GradientPath activePath() const { return usesPolynomial() ? path() : GradientPath::MatrixFree; }
  VolumeConstraints& constraints();
  VolumeSolver& solver(const std::vector<uint8_t>& held);
  void setCage(const double* cage);
  void startEdit(const EditOptions& options);     // checks the options, brings the polynomial up to date
  double currentVolume(bool withGradient);

  const QuadHierarchy* hierarchy_;
  const WaveletTransform* transform_;
  int level_;
  mutable SessionCoefficients session_;
  QuadPatchVolume fineVolume_;
  mutable FineVolumeConstraints fineConstraints_;
  double reference_ = 0;
  FreeSet free_;
  CagePolynomialPath polynomial_{session_};
  std::unique_ptr<VolumeSolver> solver_;
  const VolumeConstraints* solverConstraints_ = nullptr;
};

}  // namespace mrvol
