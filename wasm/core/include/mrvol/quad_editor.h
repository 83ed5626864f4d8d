// Volume-preserving editing of a quad mesh's level-e cage (docs/catmull-clark.md, section 5): the
// volume is the bilinear patches' (quad_volume.h), the solver and its two gradient paths are the
// triangle editor's (volume_solver.h, coefficient_volumes.h): the cage polynomial contracted from
// the quad theta^e, or the bilinear volume of the fine positions with the adjoint of synthesis.
// One global volume; the free set is the cage minus the held vertices (or all of it); boundary
// vertices stay fixed.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "mrvol/cage_polynomial.h"
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
  void useMatrixFree();
  GradientPath path() const { return polynomial_ ? GradientPath::Tensor : GradientPath::MatrixFree; }
  // false: only the held vertices' complement is free (default); true: every non-boundary cage vertex.
  void setAllFree(bool all) { allFree_ = all, solver_.reset(); }

  EditReport deformCage(const std::vector<double>& target, const std::vector<uint8_t>& held, const EditOptions& options);
  EditReport correct(const std::vector<uint8_t>& held, const EditOptions& options);

  std::vector<double> cagePositions() const;  // 3 * cageSize, cage order
  std::vector<double> positions() const;      // fine positions, caller's order
  std::vector<double> coefficients() const { return session_.x; }

 private:
  VolumeConstraints& constraints();
  VolumeSolver& solver(const std::vector<uint8_t>& held);
  void setCage(const double* cage);
  double currentVolume(bool withGradient);

  const QuadHierarchy* hierarchy_;
  int level_;
  mutable SessionCoefficients session_;
  QuadPatchVolume fineVolume_;
  mutable FineVolumeConstraints fineConstraints_;
  double reference_ = 0;
  bool allFree_ = false;
  std::unique_ptr<CagePolynomialVolume> polynomial_;
  std::unique_ptr<CageVolumeConstraint> cageConstraint_;
  std::unique_ptr<VolumeSolver> solver_;
  const VolumeConstraints* solverConstraints_ = nullptr;
};

}  // namespace mrvol
