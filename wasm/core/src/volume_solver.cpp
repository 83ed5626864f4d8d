#include "mrvol/volume_solver.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "mrvol/error.h"

namespace mrvol {

const char* gradientPathName(GradientPath path) {
  switch (path) {
    case GradientPath::Tensor: return "tensor";
    case GradientPath::Polynomial: return "polynomial";
    default: return "matrix-free";
  }
}

void checkEditOptions(const EditOptions& o) {
  if (!(o.tolerance > 0) || !(o.tolerance < 1)) throw Error("tolerance must be between 0 and 1");
  if (o.maxIterations < 1 || o.maxSubsteps < 1) throw Error("tolerance must be positive and iteration limits at least 1");
}

double VolumeConstraints::scale(size_t row) const { return std::fabs(reference(row)); }

VolumeSolver::VolumeSolver(VolumeConstraints& constraints, std::vector<uint32_t> free)
    : constraints_(&constraints), free_(std::move(free)) {
  const size_t k = constraints.rowCount(), m3 = 3 * free_.size();
  values_.resize(k);
  gradients_.resize(k * m3);
  direction_.resize(m3);
}

void VolumeSolver::solve(const EditOptions& o, EditReport& report) {
  VolumeConstraints& c = *constraints_;
  const size_t k = c.rowCount(), m3 = 3 * free_.size();
  auto relativeError = [&](size_t r) { return std::fabs(values_[r] - c.reference(r)) / std::max(c.scale(r), 1e-300); };
  bool cubicValue = false;  // values_[0] holds the exact volume after the last step (its cubic); no gradients
  for (int it = 0;; ++it) {
    if (!cubicValue || relativeError(0) >= o.tolerance) c.evaluate(values_.data());
    cubicValue = false;
    double worst = 0;
    for (size_t r = 0; r < k; ++r) worst = std::max(worst, relativeError(r));
    report.volumeResult = values_[0];
    report.relativeError = worst;
    if (worst < o.tolerance) return;
    if (it == o.maxIterations) {
      report.converged = false;
      report.message = "no convergence in " + std::to_string(o.maxIterations) + " iterations";
      return;
    }
    if (free_.empty()) {
      report.converged = false;
      report.message = "the free set is empty: nothing can absorb the volume change";
      return;
    }
    c.gradients(free_, gradients_.data());  // values_ are evaluate()d: a cubic's value within tolerance returned above
    // delta = J^T (J J^T)^-1 r: the minimal-norm solution of the k linearized constraints. With one
    // row, delta = r / |g|^2 g: the direction g and the step r / |g|^2.
    double step = 1, slope = 0;  // slope: the derivative of row 0 along the direction
    if (k == 1) {
      const double* g = gradients_.data();
      double norm2 = 0;
      for (size_t i = 0; i < m3; i += 3) norm2 += g[i] * g[i] + g[i + 1] * g[i + 1] + g[i + 2] * g[i + 2];
      if (!(norm2 > 0)) {
        report.converged = false;
        report.message = "the free coefficients cannot change the volume (their gradients vanish)";
        return;
      }
      std::copy(g, g + m3, direction_.begin());
      step = (c.reference(0) - values_[0]) / norm2;
      slope = norm2;
    } else {
      Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> J(gradients_.data(), k, m3);
      Eigen::VectorXd r(k);
      for (size_t row = 0; row < k; ++row) r[row] = c.reference(row) - values_[row];
      Eigen::FullPivLU<Eigen::MatrixXd> lu(J * J.transpose());
      lu.setThreshold(1e-12);
      if (lu.rank() < int(k)) {
        report.converged = false;
        report.message = "the constraints cannot all be met by the free set (some part has no free influence)";
        return;
      }
      Eigen::Map<Eigen::VectorXd>(direction_.data(), m3) = J.transpose() * lu.solve(r);
    }
    ++report.iterations;
    if (!o.lineSearch || k > 1) {
      c.step(free_, direction_.data(), step, nullptr);
      continue;
    }
    // Along that direction the volume is a cubic in the step length s: c0 = v and c1 = g . g are
    // known, one expansion gives c2 and c3; Newton on it, from the linearized step, replaces further
    // linearized iterations (each, on the matrix-free path, a synthesis and an adjoint).
    double cubic[4] = {values_[0], slope, 0, 0};
    c.alongDirection(free_, direction_.data(), cubic);
    const double target = c.reference(0);
    double s = step;
    for (int n = 0; n < 60; ++n) {
      const double f = cubic[0] + s * (cubic[1] + s * (cubic[2] + s * cubic[3])) - target;
      const double df = cubic[1] + s * (2 * cubic[2] + 3 * s * cubic[3]);
      if (!(df != 0) || !std::isfinite(f)) break;
      const double next = s - f / df;
      if (!std::isfinite(next) || std::fabs(next - step) > 4 * std::fabs(step) + 1e-300) break;  // stay near the linear step
      const bool done = std::fabs(next - s) <= 1e-15 * std::fabs(s);
      s = next;
      if (done) break;
    }
    values_[0] = cubic[0] + s * (cubic[1] + s * (cubic[2] + s * cubic[3]));
    c.step(free_, direction_.data(), s, &values_[0]);
    cubicValue = true;
  }
}

}  // namespace mrvol
