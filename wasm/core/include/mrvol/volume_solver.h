// The volume-preserving correction (method section 7), written once: k volume constraints V_r of the
// level-e coefficients (the global volume, or one per part), and the smallest change of the free
// coefficients that brings every V_r back to its reference. Each iteration takes the closed form
// delta = J^T (J J^T)^-1 r of the linearized constraints (J: k rows of gradients over the free
// coefficients, r: the residuals); with one constraint, the volume is an exact cubic along that
// direction, and solving it replaces further linearizations.
//
// Split as libigl's arap_precomputation / arap_solve: a VolumeSolver is built once per constraint
// set and free set (its buffers sized), then solve() runs per move of the cage.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace mrvol {

// Tensor: the cage polynomial contracted from theta^e; Polynomial: the same polynomial built from the
// fine triangles (CagePolynomialBuilder, no theta); MatrixFree: the fine volume and the adjoint.
enum class GradientPath { Tensor, Polynomial, MatrixFree };
const char* gradientPathName(GradientPath path);

struct EditOptions {
  double tolerance = 1e-5;  // relative volume error to reach
  int maxIterations = 50;   // per sub-step
  int maxSubsteps = 64;
  double substepError = 0.05;  // a move whose raw relative volume change exceeds this is split
  bool preserve = true;
  // With one constraint: after the linearized step, solve the cubic the volume is along its
  // direction instead of iterating linearizations. Off: the paper's iteration.
  bool lineSearch = true;
};
// Throws Error unless the tolerance is in (0, 1) and the iteration limits are at least 1.
void checkEditOptions(const EditOptions& options);

struct EditReport {
  double volumeReference = 0, volumeTarget = 0, volumeResult = 0, relativeError = 0;
  int iterations = 0, substeps = 0;
  bool converged = true;
  std::string message;  // why it did not converge
  GradientPath path = GradientPath::MatrixFree;
  std::vector<double> partVolumes, partReferences;
  // While the centre of mass is kept: the kept one and where it ended (3 each, else empty).
  std::vector<double> centroidReference, centroidResult;
};

// What the solver restores: rows r = 0..k-1, each a volume of the current coefficients with its
// reference. Vectors over the free coefficients hold 3 doubles per free coefficient, in the order
// of the free list.
class VolumeConstraints {
 public:
  virtual ~VolumeConstraints() = default;
  virtual size_t rowCount() const = 0;
  virtual double reference(size_t row) const = 0;
  // What a row's error is relative to: |reference| for a volume; a moment about the reference
  // point, which may be near zero, takes a scale of its own (volume times the model's size).
  virtual double scale(size_t row) const;
  // The value of every row at the current coefficients.
  virtual void evaluate(double* values) = 0;
  // After evaluate(), at the same coefficients: the rows' gradients with respect to the free
  // coefficients (rowCount rows of 3 free.size(), row after row). Asked for only when the values
  // are not within tolerance.
  virtual void gradients(const std::vector<uint32_t>& free, double* gradients) = 0;
  // With one row: the cubic of row 0 along `direction` from the current coefficients; k[0] (its value) and k[1]
  // (its derivative along the direction) come in known.
  virtual void alongDirection(const std::vector<uint32_t>& free, const double* direction, double* k) = 0;
  // The free coefficients move by s times `direction`. With `cubicValue`, the direction is the one
  // alongDirection() was last given (what it computed may be reused) and *cubicValue is row 0's
  // value there.
  virtual void step(const std::vector<uint32_t>& free, const double* direction, double s, const double* cubicValue) = 0;
};

class VolumeSolver {
 public:
  // The precomputation: the constraints to restore and the coefficients that may move (sorted).
  VolumeSolver(VolumeConstraints& constraints, std::vector<uint32_t> free);
  const std::vector<uint32_t>& free() const { return free_; }
  // Moves the free coefficients until every row is within options.tolerance (relative) of its
  // reference, or says in the report why it cannot. Fills iterations, converged, message,
  // relativeError (the worst row) and volumeResult (row 0).
  void solve(const EditOptions& options, EditReport& report);

 private:
  VolumeConstraints* constraints_;
  std::vector<uint32_t> free_;
  std::vector<double> values_, gradients_, direction_;
};

}  // namespace mrvol
