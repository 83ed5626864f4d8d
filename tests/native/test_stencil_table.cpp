// Basis stencils and the fine positions kept in step with the coefficients (stencil_table.h):
// every stencil is the zero-detail synthesis of its cage vertex, and the positions after any
// sequence of cage moves, detail changes and followed directions are the synthesis of the
// coefficients.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "fixtures.h"
#include "mrvol/hierarchy.h"
#include "mrvol/lifting.h"
#include "mrvol/stencil_table.h"

using namespace mrvol;

TEST(StencilTable, EveryStencilIsTheZeroDetailSynthesisOfItsCageVertex) {
  for (const auto& fx : fixtures::baseFixtures())
    for (const auto& o : fixtures::allSchemes())
      for (int e = 0; e < fx.levels; ++e) {
        Hierarchy h = Hierarchy::subdivide(fx.base, fx.levels);
        WaveletTransform wt(h, o);
        StencilTable table(wt, e);
        const size_t n = h.fineVertexCount();
        for (uint32_t c = 0; c < h.vertexCount[e]; ++c) {
          std::vector<double> unit(3 * n, 0.0);
          unit[3 * c] = 1.0, unit[3 * c + 1] = 2.0, unit[3 * c + 2] = -0.5;
          wt.synthesizeZeroDetails(unit.data(), e);
          // Applied to a 3-vector, the stencil gives the same fine displacement.
          std::vector<double> applied(3 * n, 0.0);
          const double d[3] = {1.0, 2.0, -0.5};
          table.add(c, d, applied.data());
          for (size_t i = 0; i < applied.size(); ++i)
            ASSERT_NEAR(applied[i], unit[i], 1e-15) << fx.name << " " << fixtures::label(o) << " e=" << e << " c=" << c;
          EXPECT_LE(table.stencilCount(), StencilTable::kMaxStencils);
        }
      }
}

TEST(FinePositions, StayTheSynthesisOfTheCoefficientsThroughEveryKindOfUpdate) {
  std::mt19937 rng(3);
  for (const auto& fx : fixtures::baseFixtures())
    for (const auto& o : fixtures::allSchemes()) {
      Hierarchy h = Hierarchy::subdivide(fx.base, fx.levels);
      WaveletTransform wt(h, o);
      const int e = 0;
      const size_t n3 = 3 * h.fineVertexCount(), cage = h.vertexCount[e];
      const Vec3 origin{0.3, -0.2, 0.1};
      std::vector<double> x = fixtures::randomVector(n3, 9, 0.1);
      for (size_t i = 0; i < 3 * cage; ++i) x[i] = fixtures::randomVector(3 * cage, 10, 1.0)[i];
      FinePositions fine(wt, e, origin);
      std::uniform_int_distribution<uint32_t> pick(0, uint32_t(cage - 1));
      std::uniform_real_distribution<double> u(-0.05, 0.05);
      double worst = 0;
      for (int step = 0; step < 200; ++step) {
        const int kind = step % 5;
        if (kind == 0 || kind == 1) {  // one or two cage vertices: along the stencils
          for (int m = 0; m <= kind; ++m) x[3 * pick(rng) + m] += u(rng);
          fine.cageChanged();
        } else if (kind == 2) {  // the whole cage: one zero-detail synthesis
          for (size_t i = 0; i < 3 * cage; ++i) x[i] += u(rng);
          fine.cageChanged();
        } else if (kind == 3) {  // a followed direction (cage only, zero-detail synthesis)
          fine.of(x);
          std::vector<double> q(n3 + 3, 0.0);
          for (size_t i = 0; i < 3 * cage; ++i) q[i] = u(rng);
          std::vector<double> direction(q.begin(), q.begin() + 3 * cage);
          wt.synthesizeZeroDetails(q.data(), e);
          const double s = 0.7;
          for (size_t i = 0; i < direction.size(); ++i) x[i] += s * direction[i];
          fine.followDirection(x, s, q);
        } else {  // a detail changes: a full synthesis
          x[3 * cage + step % (n3 - 3 * cage)] += u(rng);
          fine.detailsChanged();
        }
        const uint64_t before = fine.version();
        const std::vector<double>& got = fine.of(x);
        EXPECT_TRUE(fine.current());
        EXPECT_EQ(got.size(), n3 + 3);
        EXPECT_EQ(got[n3], 0.0);
        if (kind != 3) EXPECT_NE(fine.version(), before);
        std::vector<double> expected = x;
        for (size_t i = 0; i < 3 * cage; i += 3) expected[i] -= origin.x, expected[i + 1] -= origin.y, expected[i + 2] -= origin.z;
        wt.synthesize(expected.data(), e);
        for (size_t i = 0; i < n3; ++i) worst = std::max(worst, std::fabs(got[i] - expected[i]));
      }
      EXPECT_LT(worst, 1e-12) << fx.name << " " << fixtures::label(o);
    }
}
