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

#include "mrvol/cage_editor.h"
#include "mrvol/cage_polynomial_builder.h"
#include "mrvol/lifting.h"
#include "mrvol/mesh.h"
#include "mrvol/volume_function.h"

namespace mrvol {

// An editing session on one mesh at level e. Coefficients live in hierarchy order; the calls that
// take or give positions use the caller's vertex order. The session, the gradient paths, the free
// set and the edits are CageEditor's; this class adds the triangle mesh's volume, its limit
// surface, parts and the centre of mass.
class VolumeEditor final : public CageEditor {
 public:
  VolumeEditor(const Hierarchy& hierarchy, const WaveletTransform& transform, int level, const double* positions);

  double volume() const override;  // current volume (from the fine mesh, or its limit surface; exact)

  // The surface whose volume is kept: the fine mesh (default) or, given the Loop limit surface's
  // volume form of the fine mesh (limit_volume.h, hierarchy numbering), the limit surface. The
  // reference becomes the current volume of that surface. The limit surface runs matrix-free, or
  // on the tensor path with theta^e of the limit form (useTensor); the polynomial builder knows
  // only the mesh's triangles. Not with parts or the centre of mass.
  void useLimitSurface(const FineForm& limitForm);
  bool limitSurface() const { return limitVolume_ != nullptr; }

  // The centre of mass (keepCentroid, centroid: CageEditor's) is kept for the mesh surface only,
  // and not with parts.

  // The same cage polynomial built from the fine triangles (CagePolynomialBuilder), no tensor; it
  // is rebuilt when a correction has moved the details (free detail levels). Returns false, and
  // runs matrix-free, when the builder refuses (more than maxTerms cage triples).
  bool usePolynomial(uint64_t maxTerms = 8'000'000);
  // The cage basis rows the polynomial's builder made, handed over once (to the renderer's
  // CageBasisTable, so that they are not made again); null when none are waiting. After the first
  // call none are kept any more (a later usePolynomial would keep them for no one).
  std::unique_ptr<CageBasis> takeCageBasis() const { return cageBasisTaken_ = true, std::move(cageBasis_); }

  // Localized preservation: parts of the cage (cage order indices), each keeping its own volume
  // (the volume of the fine triangles it dominates, as a cone to the reference point). Empty: one
  // global constraint. References default to the current part volumes.
  void setParts(const std::vector<std::vector<uint32_t>>& parts, const std::vector<double>& references = {});
  size_t partCount() const { return partReference_.size(); }
  std::vector<double> partVolumes() const;

  // Theta_tau for the cage by the polynomial in use (tensor or built); for tests.
  double gradientTensor(std::vector<double>& gradient) const { return gradientPolynomial(gradient); }

 private:
  const VolumeFunction& meshVolume() const override { return fineVolume_; }
  double meshMoments(double moments[3]) const override;  // one pass over the triangles for all four
  void checkCentroidKept() const override;
  bool needsFineRows() const override { return !parts_.empty() || keepCentroid_; }
  void configureFineRows() override;  // the matrix-free rows for the current parts and free details
  void setFineReferences() override;
  bool rowIsVolume() const override { return parts_.empty(); }
  void finishReport(EditReport& report) const override;
  const VolumeFunction& surfaceVolume() const;  // the mesh's or the limit surface's

  FineEdgeVolume fineVolume_;
  std::unique_ptr<FormVolume> limitVolume_;
  std::vector<TriangleSetVolume> parts_;
  std::vector<double> partReference_;
  mutable std::unique_ptr<CageBasis> cageBasis_;  // until takeCageBasis
  mutable bool cageBasisTaken_ = false;
};

}  // namespace mrvol
