// The solver (volume_solver.h) on constraints given in closed form: one iteration is the
// minimal-norm solution of the linearized rows, the cubic line search meets one cubic row exactly,
// and what cannot be met is reported.
#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <cmath>

#include "fixtures.h"
#include "mrvol/error.h"
#include "mrvol/volume_solver.h"

using namespace mrvol;

namespace {

// Row r: a_r . x + c_r |x|^2 x_0 (a cubic term in row 0 only when cubic is set), over 3 m coefficients.
struct Rows final : VolumeConstraints {
  std::vector<std::vector<double>> a;
  std::vector<double> refs, x;
  bool cubic = false;
  size_t rowCount() const override { return a.size(); }
  double reference(size_t r) const override { return refs[r]; }
  double row(size_t r, const std::vector<double>& at) const {
    double v = 0;
    for (size_t i = 0; i < at.size(); ++i) v += a[r][i] * at[i];
    if (cubic && r == 0) v += at[0] * at[0] * at[0];
    return v;
  }
  void evaluate(double* values) override {
    for (size_t r = 0; r < a.size(); ++r) values[r] = row(r, x);
  }
  void gradients(const std::vector<uint32_t>& free, double* gradients) override {
    for (size_t r = 0; r < a.size(); ++r) {
      for (size_t i = 0; i < free.size(); ++i)
        for (int k = 0; k < 3; ++k) {
          const size_t c = 3 * free[i] + k;
          gradients[r * 3 * free.size() + 3 * i + k] = a[r][c] + (cubic && r == 0 && c == 0 ? 3 * x[0] * x[0] : 0.0);
        }
    }
  }
  void alongDirection(const std::vector<uint32_t>& free, const double* d, double* k) override {
    std::vector<double> full(x.size(), 0.0);
    for (size_t i = 0; i < free.size(); ++i)
      for (int c = 0; c < 3; ++c) full[3 * free[i] + c] = d[3 * i + c];
    double lin = 0;
    for (size_t i = 0; i < x.size(); ++i) lin += a[0][i] * full[i];
    const double x0 = cubic ? x[0] : 0, d0 = cubic ? full[0] : 0;
    k[0] = row(0, x), k[1] = lin + 3 * x0 * x0 * d0, k[2] = 3 * x0 * d0 * d0, k[3] = d0 * d0 * d0;
  }
  void step(const std::vector<uint32_t>& free, const double* d, double s, const double*) override {
    for (size_t i = 0; i < free.size(); ++i)
      for (int c = 0; c < 3; ++c) x[3 * free[i] + c] += s * d[3 * i + c];
  }
};

}  // namespace

TEST(VolumeSolver, OneIterationIsTheMinimalNormSolutionOfSeveralRows) {
  Rows rows;
  const size_t m = 5;
  rows.x = fixtures::randomVector(3 * m, 1, 1.0);
  rows.a = {fixtures::randomVector(3 * m, 2, 1.0), fixtures::randomVector(3 * m, 3, 1.0), fixtures::randomVector(3 * m, 4, 1.0)};
  rows.refs = {0.5, -0.25, 1.0};
  const std::vector<uint32_t> free = {0, 2, 3};
  const auto before = rows.x;
  VolumeSolver solver(rows, free);
  EditOptions one;
  one.maxIterations = 1;
  EditReport report;
  solver.solve(one, report);
  EXPECT_EQ(report.iterations, 1);
  // Independent: the minimal-norm solution of J delta = r by a complete orthogonal decomposition.
  Eigen::MatrixXd J(3, 3 * free.size());
  Eigen::VectorXd r(3);
  for (int row = 0; row < 3; ++row) {
    r[row] = rows.refs[row] - rows.row(row, before);
    for (size_t i = 0; i < free.size(); ++i)
      for (int k = 0; k < 3; ++k) J(row, 3 * i + k) = rows.a[row][3 * free[i] + k];
  }
  const Eigen::VectorXd expected = J.completeOrthogonalDecomposition().solve(r);
  for (size_t i = 0; i < free.size(); ++i)
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(rows.x[3 * free[i] + k] - before[3 * free[i] + k], expected[3 * i + k], 1e-12);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(rows.x[3 + k], before[3 + k]) << "not free";
  // Linear rows: that step meets them all.
  for (int row = 0; row < 3; ++row) EXPECT_NEAR(rows.row(row, rows.x), rows.refs[row], 1e-12);
}

TEST(VolumeSolver, TheLineSearchMeetsOneCubicRowInOneIteration) {
  Rows rows;
  rows.x = fixtures::randomVector(6, 5, 1.0);
  rows.a = {fixtures::randomVector(6, 6, 1.0)};
  rows.cubic = true;
  rows.refs = {rows.row(0, rows.x) + 0.8};
  VolumeSolver solver(rows, {0, 1});
  EditOptions options;
  options.tolerance = 1e-12;
  EditReport report;
  solver.solve(options, report);
  EXPECT_TRUE(report.converged) << report.message;
  EXPECT_EQ(report.iterations, 1);
  EXPECT_NEAR(rows.row(0, rows.x), rows.refs[0], 1e-12 * std::fabs(rows.refs[0]));
  EXPECT_NEAR(report.volumeResult, rows.row(0, rows.x), 1e-12 * std::fabs(rows.refs[0]));  // the cubic's value
}

TEST(VolumeSolver, SaysWhatCannotBeMet) {
  Rows rows;
  rows.x = fixtures::randomVector(6, 7, 1.0);
  const auto a = fixtures::randomVector(6, 8, 1.0);
  rows.a = {a, a};  // two equal rows with different references: J J^T is singular
  rows.refs = {1.0, 2.0};
  EditReport report;
  VolumeSolver(rows, {0, 1}).solve(EditOptions{}, report);
  EXPECT_FALSE(report.converged);
  EXPECT_NE(report.message.find("cannot all be met"), std::string::npos) << report.message;
  EditReport empty;
  VolumeSolver(rows, {}).solve(EditOptions{}, empty);
  EXPECT_NE(empty.message.find("free set is empty"), std::string::npos) << empty.message;
  EditOptions bad;
  bad.tolerance = 1;
  EXPECT_THROW(checkEditOptions(bad), Error);
  bad.tolerance = 1e-5, bad.maxIterations = 0;
  EXPECT_THROW(checkEditOptions(bad), Error);
}
