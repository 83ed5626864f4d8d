// Volume-preserving editing of a quad mesh's level-e cage (docs/catmull-clark.md, section 5): the
// volume is the bilinear patches' (quad_volume.h), the solver and its gradient paths are the
// triangle editor's (volume_solver.h, coefficient_volumes.h, cage_edit.h): the cage polynomial
// contracted from the quad theta^e (tensor) or built from the fine quads (polynomial,
// CagePolynomialBuilder over bilinearPatchRegions), or the bilinear volume of the fine positions
// with the adjoint of synthesis (matrix-free). One global volume, optionally with the centre of
// mass (matrix-free); the free set as the triangle editor's (cage minus the held vertices, all, a
// list; details of chosen levels); boundary vertices stay fixed.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "mrvol/cage_editor.h"
#include "mrvol/cage_polynomial_builder.h"
#include "mrvol/quad_hierarchy.h"
#include "mrvol/quad_volume.h"

namespace mrvol {

// The session, the gradient paths, the free set and the edits are CageEditor's; this class adds
// the bilinear patches' volume and the polynomial built from the fine quads.
class QuadVolumeEditor final : public CageEditor {
 public:
  // positions: 3 per vertex, caller's order. Throws Error when level is out of range or analysis
  // cannot reach it (a cube's level 0, quad_lifting.h).
  QuadVolumeEditor(const QuadHierarchy& hierarchy, const WaveletTransform& transform, int level,
                   const double* positions);

  // volume(): the bilinear volume of the current fine positions; keepCentroid(): the bilinear
  // patches' centre of mass (QuadFirstMoment rows) with it (CageEditor's).

  // The same cage polynomial built from the fine quads (no tensor); rebuilt when a correction has
  // moved free details. Returns false, and runs matrix-free, when the builder refuses (more than
  // maxTerms cage triples). useTensor takes theta^e with cage storage of the bilinear form.
  bool usePolynomial(uint64_t maxTerms = 8'000'000);
  // false: only the held vertices' complement is free (default); true: every non-boundary cage vertex.
  void setAllFree(bool all) { setFreeSet(all ? FreeCage::All : FreeCage::MinusHeld); }

 private:
  const VolumeFunction& meshVolume() const override { return fineVolume_; }

  const QuadHierarchy* quadHierarchy_;
  QuadPatchVolume fineVolume_;
};

}  // namespace mrvol
