// The tensor and polynomial gradient paths of an editing session (VolumeEditor on triangles,
// QuadVolumeEditor on quads): the cage polynomial in use, contracted from theta^e or built from
// the fine mesh (the builder is kept to build it again after a correction moved free details),
// and the solver's constraint on it.
#pragma once
#include <memory>
#include <vector>

#include "mrvol/cage_polynomial.h"
#include "mrvol/cage_polynomial_builder.h"
#include "mrvol/coefficient_volumes.h"
#include "mrvol/volume_solver.h"
#include "mrvol/volume_tensor.h"

namespace mrvol {

class CagePolynomialPath {
 public:
  explicit CagePolynomialPath(SessionCoefficients& session) : session_(&session) {}
  CagePolynomialPath(const CagePolynomialPath&) = delete;  // its constraint refers to the session
  CagePolynomialPath& operator=(const CagePolynomialPath&) = delete;

  // The polynomial of theta^e (Cage storage, checked by the caller), or of a builder, equal to
  // volumeNow at the current cage: the entries made of details only were never formed (tensor)
  // or are summed in another order (builder), so the constant comes from the exact volume.
  void useTensor(const VolumeTensor& tensor, double volumeNow);
  void useBuilder(std::unique_ptr<CagePolynomialBuilder> builder, double volumeNow);
  void reset();

  bool active() const { return polynomial_ != nullptr; }
  GradientPath path() const {
    return !polynomial_ ? GradientPath::MatrixFree : builder_ ? GradientPath::Polynomial : GradientPath::Tensor;
  }
  // Corrections that move free details make a built polynomial stale; the next use rebuilds it.
  void detailsMoved() { detailsMoved_ = true; }
  bool stale() const { return builder_ && detailsMoved_; }
  void rebuild(double volumeNow);

  // The solver's constraint (one row: the polynomial against `reference`) and its value now.
  CageVolumeConstraint& constraint(double reference);
  double value() { return constraint_->value(); }
  // Theta_tau for the cage (3 * cageSize) and the value at the current cage; throws Error when
  // no polynomial is in use.
  double gradient(std::vector<double>& gradient) const;

 private:
  void set(CagePolynomial polynomial, double volumeNow);

  SessionCoefficients* session_;
  std::unique_ptr<CagePolynomialVolume> polynomial_;
  std::unique_ptr<CagePolynomialBuilder> builder_;
  std::unique_ptr<CageVolumeConstraint> constraint_;
  bool detailsMoved_ = false;
};

}  // namespace mrvol
