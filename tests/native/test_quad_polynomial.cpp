// The cage polynomial of quad meshes (docs/catmull-clark.md, section 5): built from the fine quads'
// bilinear patches and the cage basis functions, it equals theta^e contracted with the details and
// the bilinear volume of the synthesized mesh; the quad editor's polynomial path and free sets.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "mrvol/cage_polynomial_builder.h"
#include "mrvol/error.h"
#include "mrvol/quad_editor.h"
#include "mrvol/quad_multires_mesh.h"
#include "quad_fixtures.h"

using namespace mrvol;

namespace {

struct Case {
  std::string name;
  QuadMesh mesh;  // subdivided and perturbed: details at every level
};

QuadMesh perturbedSplit(quadfix::PolyMesh base, int levels, unsigned seed) {
  quadfix::jitter(base, 0.05, seed);
  const QuadMesh b = quadfix::toQuadMesh(base);
  QuadMultiresMesh s = QuadMultiresMesh::subdivide(b, levels);
  QuadMesh m{s.subdivisionPositions(b.positions), s.quads()};
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.02, 0.02);
  for (double& v : m.positions) v += u(rng);
  return m;
}

// Closed and open meshes, valences 3 to 6, and the cube (analysis from level 1).
std::vector<Case> cases() {
  return {{"torus", perturbedSplit(quadfix::quadTorus(), 2, 3)},
          {"bipyramid5", perturbedSplit(quadfix::textbookCatmullClark(quadfix::bipyramid(5)).mesh, 2, 4)},
          {"pyramid6", perturbedSplit(quadfix::textbookCatmullClark(quadfix::pyramid(6)).mesh, 2, 5)},
          {"grid (boundary)", perturbedSplit(quadfix::grid(3, 2), 3, 6)},
          {"open box (boundary)", perturbedSplit(quadfix::openBox(), 2, 7)},
          {"cube", perturbedSplit(quadfix::cube(), 3, 8)}};
}

double maxAbs(const std::vector<double>& v) {
  double m = 0;
  for (double x : v) m = std::max(m, std::fabs(x));
  return m;
}

std::vector<double> shiftedCage(const std::vector<double>& x, uint32_t cage, Vec3 o) {
  std::vector<double> out(x.begin(), x.begin() + 3 * size_t(cage));
  for (size_t i = 0; i < out.size(); i += 3) out[i] -= o.x, out[i + 1] -= o.y, out[i + 2] -= o.z;
  return out;
}

}  // namespace

TEST(QuadCagePolynomial, EqualsThetaContractedWithTheDetailsAndTheBilinearVolume) {
  std::mt19937 rng(13);
  int checked = 0;
  for (const Case& c : cases()) {
    QuadMultiresMesh mm(c.mesh);  // detected: the caller's vertex order is not the hierarchy's
    const QuadHierarchy& q = mm.hierarchy();
    const Hierarchy& h = q.h;
    const FineForm form = bilinearPatchForm(q.fineQuads());
    const Vec3 origin = quadReferencePoint(c.mesh);
    std::vector<double> fine(c.mesh.positions.size());
    h.toHierarchyOrder(c.mesh.positions.data(), fine.data());
    const double volume = form.evaluate(fine.data(), origin);
    ASSERT_NEAR(volume, bilinearVolume(c.mesh), 1e-13 * std::fabs(volume));
    for (int e = mm.lowestLevel(); e <= mm.levels(); ++e) {
      SCOPED_TRACE(c.name + " e=" + std::to_string(e));
      std::vector<double> x = fine;
      mm.transform().analyze(x.data(), e);
      const uint32_t cage = h.vertexCount[e];
      const RegionForm regions = bilinearPatchRegions(q, e);
      ASSERT_EQ(regions.regionCount, q.quads[e].size() / 4);
      CagePolynomialBuilder builder(mm.transform(), e, regions);
      const CagePolynomial built = builder.build(x.data());
      ASSERT_EQ(built.cageSize, cage);
      // The builder forms the detail-only terms too: its constant needs no fixing.
      const std::vector<double> at = shiftedCage(x, cage, origin);
      EXPECT_NEAR(built.evaluate(at.data(), nullptr), volume, 1e-12 * std::fabs(volume));

      CagePolynomial theta = contractCageRows(mm.computeTensor(e, TensorStorage::Cage), x.data());
      theta.constant = volume - (theta.evaluate(at.data(), nullptr) - theta.constant);
      theta.indexRuns();
      const double size = maxAbs(at);
      std::uniform_real_distribution<double> u(-0.3 * size, 0.3 * size);
      for (int trial = 0; trial < 3; ++trial) {
        std::vector<double> moved = x;
        for (size_t i = 0; i < 3 * size_t(cage); ++i)
          if (!h.boundary[i / 3]) moved[i] += u(rng);
        const std::vector<double> cageAt = shiftedCage(moved, cage, origin);
        std::vector<double> direction(cageAt.size());
        for (double& d : direction) d = u(rng);
        mm.transform().synthesize(moved.data(), e);
        const double v = form.evaluate(moved.data(), origin);
        std::vector<double> g1(cageAt.size()), g2(cageAt.size());
        const double v1 = built.evaluate(cageAt.data(), g1.data()), v2 = theta.evaluate(cageAt.data(), g2.data());
        const double scale = std::max(std::fabs(v), std::fabs(volume));
        EXPECT_NEAR(v1, v, 1e-12 * scale);
        EXPECT_NEAR(v1, v2, 1e-12 * scale);
        const double gScale = maxAbs(g2);
        ASSERT_GT(gScale, 0.0);
        for (size_t i = 0; i < g1.size(); ++i) ASSERT_NEAR(g1[i], g2[i], 1e-12 * gScale) << "gradient " << i;
        double k1[4], k2[4];
        built.alongDirection(cageAt.data(), direction.data(), k1);
        theta.alongDirection(cageAt.data(), direction.data(), k2);
        double kScale = 0;
        for (double k : k2) kScale = std::max(kScale, std::fabs(k));
        for (int k = 0; k < 4; ++k) EXPECT_NEAR(k1[k], k2[k], 1e-12 * kScale) << "cubic coefficient " << k;
      }
      EXPECT_GE(builder.basisEntries(), h.fineVertexCount());
      ++checked;
    }
  }
  EXPECT_EQ(checked, 3 + 3 + 3 + 4 + 3 + 3);  // every level analysis reaches (the cube's from 1)
}

TEST(QuadCagePolynomial, EditorPolynomialPathKeepsTheVolumeAndMatchesTheTensorGradient) {
  for (const Case& c : cases()) {
    QuadMultiresMesh mm(c.mesh);
    const Hierarchy& h = mm.hierarchy().h;
    for (int e = mm.lowestLevel(); e < mm.levels(); ++e) {
      SCOPED_TRACE(c.name + " e=" + std::to_string(e));
      QuadVolumeEditor poly(mm.hierarchy(), mm.transform(), e, c.mesh.positions.data());
      ASSERT_TRUE(poly.usePolynomial());
      EXPECT_EQ(poly.path(), GradientPath::Polynomial);
      QuadVolumeEditor tensor(mm.hierarchy(), mm.transform(), e, c.mesh.positions.data());
      tensor.useTensor(mm.computeTensor(e, TensorStorage::Cage));
      std::vector<double> g1, g2, g3;
      const double v1 = poly.gradientPolynomial(g1), v2 = tensor.gradientPolynomial(g2);
      EXPECT_NEAR(v1, v2, 1e-12 * std::fabs(v2));
      EXPECT_NEAR(v1, bilinearVolume(c.mesh), 1e-12 * std::fabs(v1));
      // The matrix-free gradient's cage part is the same Theta_tau.
      poly.gradientMatrixFree(g3);
      const double scale = maxAbs(g2);
      for (size_t i = 0; i < g1.size(); ++i) {
        ASSERT_NEAR(g1[i], g2[i], 1e-12 * scale) << i;
        ASSERT_NEAR(g1[i], g3[i], 1e-12 * scale) << i;
      }

      std::vector<double> target = poly.cagePositions();
      uint32_t moved = 0;
      while (h.boundary[moved]) ++moved;
      for (int k = 0; k < 3; ++k) target[3 * moved + k] *= 1.3;
      std::vector<uint8_t> held(poly.cageSize(), 0);
      held[moved] = 1;
      const EditReport r = poly.deformCage(target, held, EditOptions{});
      EXPECT_TRUE(r.converged) << r.message;
      EXPECT_EQ(r.path, GradientPath::Polynomial);
      EXPECT_NE(r.volumeTarget, r.volumeReference);
      const double v = bilinearVolume(QuadMesh{poly.positions(), c.mesh.quads});
      EXPECT_LT(std::fabs(v - poly.referenceVolume()) / std::fabs(poly.referenceVolume()), 1e-5);
      for (int k = 0; k < 3; ++k) EXPECT_EQ(poly.cagePositions()[3 * moved + k], target[3 * moved + k]);
    }
  }
}

TEST(QuadCagePolynomial, FreeListAndFreeDetailsAsForTriangles) {
  const Case c = cases()[1];  // closed, valences 3 to 5
  QuadMultiresMesh mm(c.mesh);
  const Hierarchy& h = mm.hierarchy().h;
  QuadVolumeEditor ed(mm.hierarchy(), mm.transform(), 0, c.mesh.positions.data());
  ASSERT_TRUE(ed.usePolynomial());
  EXPECT_THROW(ed.setFreeSet(FreeCage::List, {ed.cageSize()}), Error);
  EXPECT_THROW(ed.setFreeSet(FreeCage::MinusHeld, {}, {mm.levels()}), Error);
  // Only the listed vertices absorb the correction.
  ed.setFreeSet(FreeCage::List, {2, 3});
  std::vector<double> target = ed.cagePositions();
  for (int k = 0; k < 3; ++k) target[k] *= 1.2;
  std::vector<uint8_t> held(ed.cageSize(), 0);
  held[0] = 1;
  const std::vector<double> before = ed.cagePositions();
  EditReport r = ed.deformCage(target, held, EditOptions{});
  ASSERT_TRUE(r.converged) << r.message;
  std::vector<double> after = ed.cagePositions();
  for (uint32_t v = 1; v < ed.cageSize(); ++v)
    for (int k = 0; k < 3; ++k)
      if (v == 2 || v == 3) continue;
      else EXPECT_EQ(after[3 * v + k], before[3 * v + k]) << v;
  EXPECT_NE(after[6], before[6]);
  // Free details: the correction runs on the fine mesh and moves details only.
  ed.setFreeSet(FreeCage::List, {}, {0, 1});
  for (int k = 0; k < 3; ++k) target[k] *= 1.1;
  target.resize(3 * size_t(ed.cageSize()));
  for (uint32_t v = 1; v < ed.cageSize(); ++v)
    for (int k = 0; k < 3; ++k) target[3 * v + k] = after[3 * v + k];
  const std::vector<double> coefficientsBefore = ed.coefficients();
  r = ed.deformCage(target, held, EditOptions{});
  ASSERT_TRUE(r.converged) << r.message;
  EXPECT_EQ(r.path, GradientPath::MatrixFree);
  EXPECT_EQ(ed.cagePositions(), target);
  const std::vector<double> coefficients = ed.coefficients();
  double detailChange = 0;
  for (size_t i = 3 * size_t(ed.cageSize()); i < coefficients.size(); ++i)
    if (!h.boundary[i / 3]) detailChange = std::max(detailChange, std::fabs(coefficients[i] - coefficientsBefore[i]));
  EXPECT_GT(detailChange, 0.0);
  EXPECT_LT(std::fabs(ed.volume() - ed.referenceVolume()) / ed.referenceVolume(), 1e-5);
  // Back on the cage: the polynomial is rebuilt for the moved details and agrees with the mesh.
  ed.setFreeSet(FreeCage::MinusHeld);
  r = ed.correct(held, EditOptions{});
  EXPECT_EQ(r.path, GradientPath::Polynomial);
  std::vector<double> g;
  EXPECT_NEAR(ed.gradientPolynomial(g), ed.volume(), 1e-12 * ed.volume());
  EXPECT_NEAR(ed.volume(), bilinearVolume(QuadMesh{ed.positions(), c.mesh.quads}), 1e-12 * ed.volume());
}

TEST(QuadCagePolynomial, TooManyTriplesFallsBackToMatrixFree) {
  const Case c = cases()[0];
  QuadMultiresMesh mm(c.mesh);
  QuadVolumeEditor ed(mm.hierarchy(), mm.transform(), 1, c.mesh.positions.data());
  EXPECT_FALSE(ed.usePolynomial(100));
  EXPECT_EQ(ed.path(), GradientPath::MatrixFree);
  try {
    CagePolynomialBuilder(mm.transform(), 1, bilinearPatchRegions(mm.hierarchy(), 1), 100);
    FAIL() << "accepted";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("more than 100 cage triples"), std::string::npos) << error.what();
  }
  EXPECT_THROW(bilinearPatchRegions(mm.hierarchy(), 3), Error);
}
