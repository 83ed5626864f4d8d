// The solver's constraints on the level-e coefficients of an editing session, one class per
// gradient path: the cage polynomial (tensor path), or volume functions of the fine positions with
// their gradients carried to the coefficients by the adjoint of synthesis (matrix-free path).
#pragma once
#include <cstdint>
#include <vector>

#include "mrvol/cage_polynomial.h"
#include "mrvol/lifting.h"
#include "mrvol/mesh.h"
#include "mrvol/stencil_table.h"
#include "mrvol/volume_function.h"
#include "mrvol/volume_solver.h"

namespace mrvol {

// Coefficients of a session: x (3 N, hierarchy order), their fine positions and the volumes'
// reference point. Volumes are evaluated about the origin (fixed: the boundary stays put), so that
// meshes far from it keep their digits; a translation only shifts the cage coefficients.
struct SessionCoefficients {
  std::vector<double> x;
  FinePositions fine;
  Vec3 origin;
  uint32_t cageSize;
  // The cage coefficients relative to the origin (what the cage polynomial takes).
  void shiftedCage(std::vector<double>& out) const;
};

// One row: the cage polynomial of the cage coefficients relative to the origin.
class CageVolumeConstraint final : public VolumeConstraints {
 public:
  CageVolumeConstraint(const CagePolynomialVolume& volume, SessionCoefficients& session)
      : volume_(&volume), session_(&session) {}
  double referenceVolume = 0;
  size_t rowCount() const override { return 1; }
  double reference(size_t) const override { return referenceVolume; }
  void evaluate(double* values) override;
  void gradients(const std::vector<uint32_t>& free, double* gradients) override;
  void alongDirection(const std::vector<uint32_t>& free, const double* direction, double* k) override;
  void step(const std::vector<uint32_t>& free, const double* direction, double s, const double* cubicValue) override;
  // The polynomial at the current cage.
  double value();

 private:
  const CagePolynomialVolume* volume_;
  SessionCoefficients* session_;
  std::vector<double> cage_, gradient_, direction_;
  // The last value and the cage it is of: the editor's value() before a solve spares the solver's
  // first evaluation, and the gradient is formed only when a correction needs it.
  std::vector<double> valueCage_;
  double value_ = 0;
  bool gradientCurrent_ = false;
  // Whether the gradient was asked for at the cage of the last value: then the next value is taken
  // with its gradient in the same pass over the polynomial (a drag that corrects every step needs
  // both; one that seldom corrects pays for the value only).
  bool gradientFollowed_ = false;
};

// Rows: functions of the fine positions (3 (N + 1), see FinePositions), each with its reference
// (and optionally its error scale). Row 0 is a volume; its value and fine gradient are cached for
// the current fine positions.
class FineVolumeConstraints final : public VolumeConstraints {
 public:
  FineVolumeConstraints(const WaveletTransform& transform, int level, SessionCoefficients& session)
      : transform_(&transform), level_(level), session_(&session) {}
  // The functions must outlive their use here. detailsFree: the free set holds details too.
  void setRows(const VolumeFunction& first, std::vector<const FineFunction*> more, bool detailsFree);
  std::vector<double> references;
  std::vector<double> scales;  // per row, or empty: |reference|
  size_t rowCount() const override { return rows_.size(); }
  double reference(size_t row) const override { return references[row]; }
  double scale(size_t row) const override { return scales.empty() ? VolumeConstraints::scale(row) : scales[row]; }
  // Each row's value and fine gradient in one pass (row 0's from the cache when it holds them).
  void evaluate(double* values) override;
  // The fine gradients of evaluate() carried to the coefficients by the adjoint of synthesis.
  void gradients(const std::vector<uint32_t>& free, double* gradients) override;
  void alongDirection(const std::vector<uint32_t>& free, const double* direction, double* k) override;
  void step(const std::vector<uint32_t>& free, const double* direction, double s, const double* cubicValue) override;
  // Row 0 at the current fine positions (cached); with the gradient also computed and kept for the
  // next evaluate().
  double value();
  double valueWithGradient();

 private:
  const WaveletTransform* transform_;
  int level_;
  SessionCoefficients* session_;
  const VolumeFunction* first_ = nullptr;
  std::vector<const FineFunction*> rows_;  // first_, then the others
  bool detailsFree_ = false;
  // Cache of row 0 at fine positions version cacheVersion_: its value, and its fine gradient in
  // gradient_ while gradientCached_.
  uint64_t cacheVersion_ = ~uint64_t(0);
  double cachedValue_ = 0;
  bool gradientCached_ = false;
  std::vector<double> gradient_, direction_;  // 3 (N + 1): no allocation per step
  std::vector<std::vector<double>> rowGradients_;  // fine gradients of rows 1.. (parts)
  // Rows 1-3 when they are the centre of mass's moments: their fine gradients side by side, 9 per
  // vertex (one pass to make, one adjoint of stride 9 to carry), while momentsTogether_.
  std::vector<double> momentGradients_;
  bool momentsTogether_ = false;
};

}  // namespace mrvol
