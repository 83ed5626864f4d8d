// Lifting schemes: perfect reconstruction, zero-detail synthesis equals subdivision, and the
// transposed steps equal the transposes of the steps' assembled matrices.
#include <Eigen/Sparse>
#include <cmath>
#include <gtest/gtest.h>

#include "fixtures.h"
#include "mrvol/corners.h"
#include "mrvol/hierarchy.h"
#include "mrvol/lifting.h"

using namespace mrvol;

namespace {

double maxAbs(const std::vector<double>& v) {
  double m = 0;
  for (double x : v) m = std::max(m, std::fabs(x));
  return m;
}

using fixtures::allSchemes;

// Positions of the zero-detail synthesis from the base positions.
std::vector<double> zeroDetailSynthesis(const WaveletTransform& wt, const TriangleMesh& base) {
  std::vector<double> x(3 * wt.hierarchy().fineVertexCount(), 0.0);
  std::copy(base.positions.begin(), base.positions.end(), x.begin());
  wt.synthesize(x.data(), 0);
  return x;
}

}  // namespace

TEST(Lifting, PerfectReconstructionEveryFixtureSchemeAndLevel) {
  for (const auto& fx : fixtures::baseFixtures()) {
    Hierarchy h = Hierarchy::subdivide(fx.base, fx.levels);
    for (const auto& options : allSchemes()) {
      WaveletTransform wt(h, options);
      for (int e = 0; e <= h.levels; ++e) {
        auto x = fixtures::randomVector(3 * h.fineVertexCount(), 7 + e);
        auto y = x;
        wt.analyze(y.data(), e);
        wt.synthesize(y.data(), e);
        double err = 0;
        for (size_t i = 0; i < x.size(); ++i) err = std::max(err, std::fabs(x[i] - y[i]));
        EXPECT_LT(err, 1e-12 * maxAbs(x)) << fx.name << " " << schemeName(options.kind) << " e=" << e;
      }
    }
  }
}

// Loop subdivision written directly from its rules (the paper's cos-based even weights).
std::vector<double> loopSubdivideOnce(const std::vector<double>& p, const std::vector<uint32_t>& faces,
                                      const Hierarchy& h, int l) {
  const uint32_t ne = h.vertexCount[l - 1], nf = h.vertexCount[l];
  VertexCorners coarse(faces.data(), faces.size() / 3, ne);
  std::vector<double> out(3 * nf, 0.0);
  std::vector<uint32_t> ring;
  for (uint32_t v = 0; v < ne; ++v) {
    bool boundary = false;
    coarse.ring(v, ring, &boundary);
    for (int k = 0; k < 3; ++k) {
      if (boundary) {
        out[3 * v + k] = 0.75 * p[3 * v + k] + 0.125 * (p[3 * ring.front() + k] + p[3 * ring.back() + k]);
        continue;
      }
      const int n = int(ring.size());
      const double eta = 3.0 / 8.0 + std::cos(2 * M_PI / n) / 4.0, b = (5.0 / 8.0 - eta * eta) / n;
      double s = 0;
      for (uint32_t w : ring) s += p[3 * w + k];
      out[3 * v + k] = (1 - n * b) * p[3 * v + k] + b * s;
    }
  }
  for (uint32_t e = ne; e < nf; ++e) {
    uint32_t a = h.ends[2 * e], b = h.ends[2 * e + 1], c = h.wings[2 * e], d = h.wings[2 * e + 1];
    for (int k = 0; k < 3; ++k)
      out[3 * e + k] = d == kNone ? 0.5 * (p[3 * a + k] + p[3 * b + k])
                                  : 0.375 * (p[3 * a + k] + p[3 * b + k]) + 0.125 * (p[3 * c + k] + p[3 * d + k]);
  }
  return out;
}

TEST(Lifting, ZeroDetailLoopSynthesisEqualsLoopSubdivision) {
  for (const auto& fx : fixtures::baseFixtures()) {
    Hierarchy h = Hierarchy::subdivide(fx.base, fx.levels);
    for (double ab : {1.0, 0.0}) {
      SchemeOptions o;
      o.alpha *= ab, o.beta *= ab;
      WaveletTransform wt(h, o);
      auto x = zeroDetailSynthesis(wt, fx.base);
      std::vector<double> p = fx.base.positions;
      for (int l = 1; l <= h.levels; ++l) p = loopSubdivideOnce(p, h.faces[l - 1], h, l);
      double err = 0;
      for (size_t i = 0; i < x.size(); ++i) err = std::max(err, std::fabs(x[i] - p[i]));
      EXPECT_LT(err, 1e-12) << fx.name;
    }
  }
}

TEST(Lifting, TransposedStepEqualsTransposeOfAssembledMatrix) {
  for (const auto& fx : fixtures::baseFixtures()) {
    Hierarchy h = Hierarchy::subdivide(fx.base, 2);
    const int N = int(h.fineVertexCount());
    for (const auto& options : allSchemes()) {
      WaveletTransform wt(h, options);
      for (int l = 1; l <= h.levels; ++l)
        for (const auto& step : wt.synthesisSteps(l)) {
          // Assemble the step's matrix M (x -> forward(x)) from its data.
          std::vector<Eigen::Triplet<double>> t;
          for (int i = 0; i < N; ++i) t.emplace_back(i, i, 1.0);
          for (size_t r = 0; r < step.targets.size(); ++r) {
            if (step.scaling) { t.emplace_back(step.targets[r], step.targets[r], step.weights[r] - 1.0); continue; }
            for (uint32_t k = step.offsets[r]; k < step.offsets[r + 1]; ++k)
              t.emplace_back(step.targets[r], step.sources[k], step.weights[k]);
          }
          Eigen::SparseMatrix<double> M(N, N);
          M.setFromTriplets(t.begin(), t.end());
          auto xs = fixtures::randomVector(N, 11);
          Eigen::VectorXd x = Eigen::Map<Eigen::VectorXd>(xs.data(), N);
          Eigen::VectorXd forward = M * x, transposed = M.transpose() * x;
          std::vector<double> a = xs, b = xs, c = xs;
          step.forward(a.data(), 1);
          step.transposed(b.data(), 1);
          step.inverse(c.data(), 1);
          step.forward(c.data(), 1);
          for (int i = 0; i < N; ++i) {
            EXPECT_NEAR(a[i], forward[i], 1e-13) << fx.name << " step " << step.name;
            EXPECT_NEAR(b[i], transposed[i], 1e-13) << fx.name << " step " << step.name;
            EXPECT_NEAR(c[i], xs[i], 1e-13) << fx.name << " step " << step.name;
          }
        }
    }
  }
}

// Modified Butterfly subdivision written directly from its rules, closed meshes.
TEST(Lifting, ZeroDetailButterflySynthesisEqualsModifiedButterfly) {
  for (const auto& fx : fixtures::baseFixtures()) {
    if (fx.name == "open-patch") continue;
    Hierarchy h = Hierarchy::subdivide(fx.base, fx.levels);
    SchemeOptions o;
    o.kind = SchemeKind::Butterfly;
    WaveletTransform wt(h, o);
    auto x = zeroDetailSynthesis(wt, fx.base);
    std::vector<double> p = fx.base.positions;
    for (int l = 1; l <= h.levels; ++l) {
      const uint32_t ne = h.vertexCount[l - 1], nf = h.vertexCount[l];
      VertexCorners coarse(h.faces[l - 1].data(), h.faces[l - 1].size() / 3, ne);
      std::vector<double> out(3 * nf);
      std::copy(p.begin(), p.end(), out.begin());
      std::vector<uint32_t> ring;
      auto ringWeights = [&](uint32_t centre, uint32_t other, double share, uint32_t e) {
        coarse.ringFrom(centre, other, ring);
        const int K = int(ring.size());
        for (int k = 0; k < 3; ++k) out[3 * e + k] += share * 0.75 * p[3 * centre + k];
        for (int j = 0; j < K; ++j) {
          double s = K == 3 ? (j == 0 ? 5.0 / 12 : -1.0 / 12)
                     : K == 4 ? (j == 0 ? 3.0 / 8 : j == 2 ? -1.0 / 8 : 0.0)
                              : (0.25 + std::cos(2 * M_PI * j / K) + 0.5 * std::cos(4 * M_PI * j / K)) / K;
          for (int k = 0; k < 3; ++k) out[3 * e + k] += share * s * p[3 * ring[j] + k];
        }
      };
      for (uint32_t e = ne; e < nf; ++e) {
        uint32_t a = h.ends[2 * e], b = h.ends[2 * e + 1], c = h.wings[2 * e], d = h.wings[2 * e + 1];
        for (int k = 0; k < 3; ++k) out[3 * e + k] = 0;
        int va = int(coarse.count(a)), vb = int(coarse.count(b));
        if (va == 6 && vb == 6) {
          uint32_t q[4] = {coarse.opposite(a, c), coarse.opposite(c, b), coarse.opposite(d, a), coarse.opposite(b, d)};
          for (int k = 0; k < 3; ++k) {
            out[3 * e + k] = 0.5 * (p[3 * a + k] + p[3 * b + k]) + 0.125 * (p[3 * c + k] + p[3 * d + k]);
            for (uint32_t v : q) out[3 * e + k] -= p[3 * v + k] / 16.0;
          }
        } else if (va != 6 && vb != 6) {
          ringWeights(a, b, 0.5, e);
          ringWeights(b, a, 0.5, e);
        } else {
          ringWeights(va != 6 ? a : b, va != 6 ? b : a, 1.0, e);
        }
      }
      p = out;
    }
    double err = 0;
    for (size_t i = 0; i < x.size(); ++i) err = std::max(err, std::fabs(x[i] - p[i]));
    EXPECT_LT(err, 1e-12) << fx.name;
  }
}

TEST(Lifting, ButterflyIsInterpolating) {
  Hierarchy h = Hierarchy::subdivide(fixtures::icosahedron(), 3);
  SchemeOptions o;
  o.kind = SchemeKind::Butterfly;
  WaveletTransform wt(h, o);
  auto x = zeroDetailSynthesis(wt, fixtures::icosahedron());
  for (size_t i = 0; i < 36; ++i) EXPECT_NEAR(x[i], fixtures::icosahedron().positions[i], 1e-14);
}

TEST(Lifting, ZeroDetailSynthesisSkipsOnlyStepsThatReadDetails) {
  for (const auto& fx : fixtures::baseFixtures()) {
    Hierarchy h = Hierarchy::subdivide(fx.base, fx.levels);
    for (const auto& options : allSchemes()) {
      WaveletTransform wt(h, options);
      for (int e = 0; e < h.levels; ++e) {
        auto x = fixtures::randomVector(3 * h.fineVertexCount(), 17);
        std::fill(x.begin() + 3 * h.vertexCount[e], x.end(), 0.0);
        auto y = x;
        // The detail entries are not read: garbage (even NaN) there changes nothing.
        for (size_t i = 3 * h.vertexCount[e]; i < y.size(); ++i) y[i] = i % 7 == 0 ? NAN : 1e300;
        wt.synthesize(x.data(), e);
        wt.synthesizeZeroDetails(y.data(), e);
        for (size_t i = 0; i < x.size(); ++i) ASSERT_EQ(x[i], y[i]) << fx.name << " " << schemeName(options.kind);
      }
    }
  }
}

TEST(Lifting, CoarseOnlyAdjointEqualsTheFullAdjointOnTheCoarseCoefficients) {
  for (const auto& fx : fixtures::baseFixtures()) {
    Hierarchy h = Hierarchy::subdivide(fx.base, fx.levels);
    for (const auto& options : allSchemes()) {
      WaveletTransform wt(h, options);
      for (int e = 0; e < h.levels; ++e) {
        auto a = fixtures::randomVector(3 * h.fineVertexCount(), 23);
        auto b = a;
        wt.synthesisAdjoint(a.data(), e);
        wt.synthesisAdjoint(b.data(), e, 3, false);
        for (size_t i = 0; i < 3 * size_t(h.vertexCount[e]); ++i) ASSERT_EQ(a[i], b[i]) << fx.name;
      }
    }
  }
}
