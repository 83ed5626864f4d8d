// Volume-preserving correction: volume kept after every drag, details and held vertices untouched,
// the step is the minimal-norm solution of the linearized constraint, both gradient paths agree.
#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <random>

#include "fixtures.h"
#include "mrvol/error.h"
#include "mrvol/hierarchy.h"
#include "mrvol/lifting.h"
#include "mrvol/volume_editor.h"
#include "mrvol/volume_tensor.h"

using namespace mrvol;

namespace {

struct EditFixture {
  Hierarchy h;
  WaveletTransform wt;
  std::vector<double> positions;  // caller order = hierarchy order here
  EditFixture(const fixtures::Fixture& fx, const SchemeOptions& o, unsigned seed) : h(Hierarchy::subdivide(fx.base, fx.levels)), wt(h, o) {
    positions.assign(3 * h.fineVertexCount(), 0.0);
    std::copy(fx.base.positions.begin(), fx.base.positions.end(), positions.begin());
    auto noise = fixtures::randomVector(positions.size(), seed, 0.03);
    for (size_t i = fx.base.positions.size(); i < positions.size(); ++i) positions[i] = noise[i];
    wt.synthesize(positions.data(), 0);
  }
};

std::vector<SchemeOptions> schemes() {
  SchemeOptions loop, butterfly, linear;
  butterfly.kind = SchemeKind::Butterfly;
  linear.kind = SchemeKind::Linear;
  return {loop, butterfly, linear};
}

double maxAbs(const std::vector<double>& v) {
  double m = 0;
  for (double x : v) m = std::max(m, std::fabs(x));
  return m;
}

}  // namespace

TEST(VolumeEditor, VolumeKeptAfterRandomDragsOnEveryFixture) {
  std::mt19937 rng(2024);
  int drags = 0;
  for (const auto& fx : fixtures::baseFixtures())
    for (const auto& o : schemes())
      for (int e : {0, 1}) {
        EditFixture s(fx, o, 1);
        VolumeEditor editor(s.h, s.wt, e, s.positions.data());
        const double reference = editor.referenceVolume();
        const auto before = editor.coefficients();
        const double size = maxAbs(s.positions);
        std::uniform_real_distribution<double> u(-0.15 * size, 0.15 * size);
        for (int d = 0; d < 50; ++d, ++drags) {
          auto cage = editor.cagePositions();
          std::uniform_int_distribution<uint32_t> pick(0, editor.cageSize() - 1);
          uint32_t c = pick(rng);
          if (s.h.boundary[c]) continue;
          std::vector<uint8_t> held(editor.cageSize(), 0);
          held[c] = 1;
          for (int k = 0; k < 3; ++k) cage[3 * c + k] += u(rng);
          auto target = cage;
          EditReport r = editor.deformCage(target, held, EditOptions{});
          ASSERT_TRUE(r.converged) << fx.name << " " << r.message;
          EXPECT_LT(r.relativeError, 1e-5) << fx.name;
          // Independently of the editor's own bookkeeping: the volume of the fine mesh it gives.
          TriangleMesh out{editor.positions(), s.h.fineFaces()};
          EXPECT_NEAR(meshVolume(out), reference, 1e-5 * std::fabs(reference)) << fx.name;
          auto now = editor.cagePositions();
          for (int k = 0; k < 3; ++k) EXPECT_EQ(now[3 * c + k], target[3 * c + k]) << "held vertex moved";
          for (uint32_t b = 0; b < editor.cageSize(); ++b)
            if (s.h.boundary[b])
              for (int k = 0; k < 3; ++k) EXPECT_EQ(now[3 * b + k], target[3 * b + k]) << "boundary vertex moved";
        }
        // Details ride along untouched.
        auto after = editor.coefficients();
        for (size_t i = 3 * size_t(editor.cageSize()); i < after.size(); ++i) ASSERT_EQ(after[i], before[i]);
      }
  EXPECT_GT(drags, 1000);
}

TEST(VolumeEditor, TensorAndMatrixFreeGradientsAgree) {
  for (const auto& fx : fixtures::baseFixtures())
    for (const auto& o : schemes())
      for (int e = 0; e < fx.levels; ++e) {
        EditFixture s(fx, o, 2);
        VolumeEditor editor(s.h, s.wt, e, s.positions.data());
        editor.useTensor(computeVolumeTensor(s.wt, e, TensorStorage::Cage));
        std::vector<double> gFree, gTensor;
        double v1 = editor.gradientMatrixFree(gFree);
        double v2 = editor.gradientTensor(gTensor);
        EXPECT_NEAR(v1, v2, 1e-10 * std::fabs(v1));
        const double scale = maxAbs(gTensor);
        for (size_t i = 0; i < gTensor.size(); ++i)
          EXPECT_NEAR(gFree[i], gTensor[i], 1e-10 * scale) << fx.name << " " << schemeName(o.kind) << " e=" << e;
        // And a drag ends in the same place on both paths.
        VolumeEditor other(s.h, s.wt, e, s.positions.data());
        auto target = editor.cagePositions();
        target[0] += 0.2, target[1] -= 0.1;
        std::vector<uint8_t> held(editor.cageSize(), 0);
        held[0] = 1;
        auto r1 = editor.deformCage(target, held, EditOptions{});
        auto r2 = other.deformCage(target, held, EditOptions{});
        EXPECT_EQ(r1.path, GradientPath::Tensor);
        EXPECT_EQ(r2.path, GradientPath::MatrixFree);
        auto a = editor.cagePositions(), b = other.cagePositions();
        for (size_t i = 0; i < a.size(); ++i) EXPECT_NEAR(a[i], b[i], 1e-9) << fx.name;
      }
}

// The polynomial built from the fine triangles (no theta) is the tensor path's polynomial: the same
// volume, gradient and drags to 1e-10, and it keeps the volume.
TEST(VolumeEditor, PolynomialPathEqualsTheTensorPath) {
  std::mt19937 rng(77);
  for (const auto& fx : fixtures::baseFixtures())
    for (const auto& o : schemes())
      for (int e = 0; e < fx.levels; ++e) {
        EditFixture s(fx, o, 4);
        VolumeEditor tensor(s.h, s.wt, e, s.positions.data()), poly(s.h, s.wt, e, s.positions.data());
        tensor.useTensor(computeVolumeTensor(s.wt, e, TensorStorage::Cage));
        ASSERT_TRUE(poly.usePolynomial()) << fx.name;
        EXPECT_EQ(poly.path(), GradientPath::Polynomial);
        EXPECT_STREQ(gradientPathName(poly.path()), "polynomial");
        std::vector<double> gT, gP;
        const double vT = tensor.gradientTensor(gT), vP = poly.gradientTensor(gP);
        EXPECT_NEAR(vP, vT, 1e-10 * std::fabs(vT)) << fx.name;
        EXPECT_NEAR(vP, poly.volume(), 1e-10 * std::fabs(vT)) << fx.name;
        const double scale = maxAbs(gT);
        for (size_t i = 0; i < gT.size(); ++i)
          ASSERT_NEAR(gP[i], gT[i], 1e-10 * scale) << fx.name << " " << schemeName(o.kind) << " e=" << e;
        const double reference = poly.referenceVolume();
        const double size = maxAbs(s.positions);
        std::uniform_real_distribution<double> u(-0.1 * size, 0.1 * size);
        for (int d = 0; d < 5; ++d) {
          auto target = poly.cagePositions();
          const uint32_t c = std::uniform_int_distribution<uint32_t>(0, poly.cageSize() - 1)(rng);
          if (s.h.boundary[c]) continue;
          std::vector<uint8_t> held(poly.cageSize(), 0);
          held[c] = 1;
          for (int k = 0; k < 3; ++k) target[3 * c + k] += u(rng);
          const EditReport rT = tensor.deformCage(target, held, EditOptions{});
          const EditReport rP = poly.deformCage(target, held, EditOptions{});
          ASSERT_TRUE(rP.converged) << fx.name << " " << rP.message;
          EXPECT_EQ(rT.path, GradientPath::Tensor);
          EXPECT_EQ(rP.path, GradientPath::Polynomial);
          EXPECT_EQ(rP.iterations, rT.iterations) << fx.name;
          const auto a = tensor.cagePositions(), b = poly.cagePositions();
          for (size_t i = 0; i < a.size(); ++i) ASSERT_NEAR(b[i], a[i], 1e-10 * size) << fx.name << " e=" << e;
          TriangleMesh out{poly.positions(), s.h.fineFaces()};
          EXPECT_NEAR(meshVolume(out), reference, 1e-5 * std::fabs(reference)) << fx.name;
        }
      }
}

// Free details run matrix-free; back on the cage alone the polynomial is rebuilt for the moved
// details, so it still gives the fine volume. A refused builder falls back to matrix-free.
TEST(VolumeEditor, PolynomialFollowsTheDetailsAndFallsBackToMatrixFree) {
  const fixtures::Fixture fx = fixtures::baseFixtures().front();  // a copy: the vector is a temporary
  EditFixture s(fx, SchemeOptions{}, 5);
  VolumeEditor editor(s.h, s.wt, 0, s.positions.data());
  ASSERT_TRUE(editor.usePolynomial());
  const double reference = editor.referenceVolume();
  std::vector<uint8_t> held(editor.cageSize(), 0);
  held[0] = 1;
  editor.setFreeSet(VolumeEditor::FreeCage::MinusHeld, {}, {0});
  auto target = editor.cagePositions();
  target[0] += 0.3, target[2] -= 0.2;
  EditReport r = editor.deformCage(target, held, EditOptions{});
  EXPECT_EQ(r.path, GradientPath::MatrixFree);
  EXPECT_EQ(editor.path(), GradientPath::Polynomial) << "the polynomial waits for the cage-only free set";
  editor.setFreeSet(VolumeEditor::FreeCage::MinusHeld);
  target = editor.cagePositions();
  target[0] -= 0.25;
  r = editor.deformCage(target, held, EditOptions{});
  EXPECT_EQ(r.path, GradientPath::Polynomial);
  ASSERT_TRUE(r.converged) << r.message;
  std::vector<double> g;
  EXPECT_NEAR(editor.gradientTensor(g), editor.volume(), 1e-10 * std::fabs(reference)) << "built for the moved details";
  EXPECT_NEAR(editor.volume(), reference, 1e-5 * std::fabs(reference));

  VolumeEditor refused(s.h, s.wt, 0, s.positions.data());
  EXPECT_FALSE(refused.usePolynomial(1));
  EXPECT_EQ(refused.path(), GradientPath::MatrixFree);
  EXPECT_TRUE(refused.correct(held, EditOptions{}).converged);
}

TEST(VolumeEditor, OneIterationIsTheMinimalNormSolutionOfTheLinearizedConstraint) {
  for (const auto& fx : fixtures::baseFixtures()) {
    EditFixture s(fx, SchemeOptions{}, 3);
    VolumeEditor editor(s.h, s.wt, 0, s.positions.data());
    editor.setReferenceVolume(editor.referenceVolume() * 1.03);
    std::vector<double> g;
    const double v = editor.gradientMatrixFree(g);
    std::vector<uint8_t> held(editor.cageSize(), 0);
    held[0] = 1;
    std::vector<uint32_t> free;
    for (uint32_t c = 1; c < editor.cageSize(); ++c)
      if (!s.h.boundary[c]) free.push_back(c);
    // Independent: minimal-norm solution of J delta = r by a complete orthogonal decomposition.
    Eigen::MatrixXd J(1, 3 * free.size());
    for (size_t i = 0; i < free.size(); ++i)
      for (int k = 0; k < 3; ++k) J(0, 3 * i + k) = g[3 * free[i] + k];
    Eigen::VectorXd r(1);
    r[0] = editor.referenceVolume() - v;
    Eigen::VectorXd expected = J.completeOrthogonalDecomposition().solve(r);
    const auto before = editor.coefficients();
    EditOptions one;
    one.maxIterations = 1;
    one.tolerance = 1e-15;
    one.lineSearch = false;  // the paper's iteration, one step of it
    editor.correct(held, one);
    const auto after = editor.coefficients();
    for (size_t i = 0; i < free.size(); ++i)
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(after[3 * free[i] + k] - before[3 * free[i] + k], expected[3 * i + k], 1e-12 * (1 + expected.norm()))
            << fx.name;
    for (int k = 0; k < 3; ++k) EXPECT_EQ(after[k], before[k]);  // held
    // With the line search, one step goes along the same direction and meets the constraint.
    VolumeEditor searched(s.h, s.wt, 0, s.positions.data());
    searched.setReferenceVolume(searched.referenceVolume() * 1.03);
    EditOptions line;
    line.maxIterations = 1;
    line.tolerance = 1e-15;
    EditReport searchReport = searched.correct(held, line);
    const auto moved = searched.coefficients();
    Eigen::VectorXd d(3 * free.size());
    for (size_t i = 0; i < free.size(); ++i)
      for (int k = 0; k < 3; ++k) d[3 * i + k] = moved[3 * free[i] + k] - before[3 * free[i] + k];
    EXPECT_NEAR(std::fabs(d.normalized().dot(expected.normalized())), 1.0, 1e-12) << fx.name;
    EXPECT_LT(std::fabs(searched.volume() - searched.referenceVolume()), 1e-12 * std::fabs(searched.referenceVolume()));
    EXPECT_EQ(searchReport.iterations, 1);
  }
}

TEST(VolumeEditor, LocalizedPreservationKeepsEveryPartsVolume) {
  fixtures::Fixture fx{"icosahedron", fixtures::icosahedron(), 3};
  EditFixture s(fx, SchemeOptions{}, 4);
  VolumeEditor editor(s.h, s.wt, 0, s.positions.data());
  // Two halves of the cage by the sign of z.
  std::vector<std::vector<uint32_t>> parts(2);
  auto cage = editor.cagePositions();
  for (uint32_t c = 0; c < editor.cageSize(); ++c) parts[cage[3 * c + 2] >= 0 ? 0 : 1].push_back(c);
  editor.setParts(parts);
  auto refs = editor.partVolumes();
  double sum = refs[0] + refs[1];
  EXPECT_NEAR(sum, editor.volume(), 1e-12 * std::fabs(sum));  // the parts cover the mesh
  std::vector<uint8_t> held(editor.cageSize(), 0);
  uint32_t c = parts[0][0];
  held[c] = 1;
  auto target = cage;
  target[3 * c] += 0.3, target[3 * c + 2] += 0.4;
  EditReport r = editor.deformCage(target, held, EditOptions{});
  ASSERT_TRUE(r.converged) << r.message;
  auto now = editor.partVolumes();
  for (int p = 0; p < 2; ++p) EXPECT_NEAR(now[p], refs[p], 1e-5 * std::fabs(refs[p]));
}

TEST(VolumeEditor, ReportsWhatCannotConverge) {
  fixtures::Fixture fx{"icosahedron", fixtures::icosahedron(), 2};
  EditFixture s(fx, SchemeOptions{}, 5);
  VolumeEditor editor(s.h, s.wt, 0, s.positions.data());
  editor.setFreeSet(VolumeEditor::FreeCage::List, {});  // nothing is free
  auto target = editor.cagePositions();
  target[0] += 0.5;
  std::vector<uint8_t> held(editor.cageSize(), 0);
  held[0] = 1;
  EditReport r = editor.deformCage(target, held, EditOptions{});
  EXPECT_FALSE(r.converged);
  EXPECT_NE(r.message.find("free set is empty"), std::string::npos) << r.message;
  EXPECT_THROW(editor.cageIndexOf(100), Error);  // not a level-0 cage vertex
  EXPECT_THROW(editor.deformCage({1.0, 2.0}, held, EditOptions{}), Error);
}

TEST(VolumeEditor, FreeDetailsAbsorbTheCorrectionToo) {
  fixtures::Fixture fx{"octahedron", fixtures::octahedron(), 3};
  EditFixture s(fx, SchemeOptions{}, 6);
  VolumeEditor editor(s.h, s.wt, 0, s.positions.data());
  editor.setFreeSet(VolumeEditor::FreeCage::List, {}, {1, 2});  // only details of levels 1 and 2 are free
  auto target = editor.cagePositions();
  target[2] += 0.3;
  std::vector<uint8_t> held(editor.cageSize(), 0);
  held[0] = 1;
  EditReport r = editor.deformCage(target, held, EditOptions{});
  ASSERT_TRUE(r.converged) << r.message;
  EXPECT_LT(r.relativeError, 1e-5);
  EXPECT_EQ(r.path, GradientPath::MatrixFree);
}

TEST(VolumeEditor, CagePolynomialAlongADirectionIsItsCubic) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  CagePolynomial p;
  p.cageSize = 9;
  p.constant = 0.3;
  for (int i = 0; i < 27; ++i) p.linear.push_back(u(rng));
  for (uint32_t i = 0; i < 9; ++i)
    for (uint32_t j = i + 1; j < 9; ++j) {
      if ((i + j) % 2) p.pairI.push_back(i), p.pairJ.push_back(j), p.pairQ.insert(p.pairQ.end(), {u(rng), u(rng), u(rng)});
      for (uint32_t k = j + 1; k < 9; ++k)
        if ((i * j + k) % 3 == 0) p.tripleI.push_back(i), p.tripleJ.push_back(j), p.tripleK.push_back(k), p.tripleT.push_back(u(rng));
    }
  std::vector<double> c(27), g(27);
  for (auto& x : c) x = u(rng);
  for (auto& x : g) x = u(rng);
  double k[4];
  p.alongDirection(c.data(), g.data(), k);
  for (double s : {0.0, 0.3, -0.7, 1.9}) {
    auto at = c;
    for (size_t i = 0; i < at.size(); ++i) at[i] += s * g[i];
    EXPECT_NEAR(k[0] + s * (k[1] + s * (k[2] + s * k[3])), p.evaluate(at.data(), nullptr), 1e-12) << "s=" << s;
  }
}

TEST(VolumeEditor, FinePositionsStayTheSynthesisOfTheCoefficientsOverLongDrags) {
  // The editor updates its fine positions incrementally (a move of a few cage vertices along their
  // cached basis functions, a larger one by a zero-detail synthesis, each correction along its
  // direction) with a full synthesis now and then: they must not drift from the coefficients.
  std::mt19937 rng(11);
  for (const auto& fx : fixtures::baseFixtures())
    for (const auto& o : schemes()) {
      EditFixture s(fx, o, 3);
      VolumeEditor editor(s.h, s.wt, 0, s.positions.data());
      const double size = maxAbs(s.positions);
      std::uniform_real_distribution<double> u(-0.01 * size, 0.01 * size);
      double worst = 0;
      for (int d = 0; d < 150; ++d) {
        auto cage = editor.cagePositions();
        const uint32_t c = d / 10 % editor.cageSize();
        if (s.h.boundary[c]) continue;
        std::vector<uint8_t> held(editor.cageSize(), 0);
        held[c] = 1;
        for (int k = 0; k < 3; ++k) cage[3 * c + k] += u(rng);
        if (d % 7 == 6)  // now and then every free vertex moves: the update by a whole synthesis
          for (uint32_t b = 0; b < editor.cageSize(); ++b)
            if (!s.h.boundary[b]) cage[3 * b + 1] += 0.2 * u(rng);
        ASSERT_TRUE(editor.deformCage(cage, held, EditOptions{}).converged);
        auto expected = editor.coefficients();
        s.wt.synthesize(expected.data(), 0);
        const auto got = editor.positions();
        for (size_t i = 0; i < got.size(); ++i) worst = std::max(worst, std::fabs(got[i] - expected[i]));
      }
      EXPECT_LT(worst, 1e-12 * size) << fx.name << " " << schemeName(o.kind);
    }
}
