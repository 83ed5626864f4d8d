// The cage polynomial built from the fine triangles equals the one contracted from theta^e, term by
// term and as a function (value, gradient, cubic along a direction), and its value is the volume of
// the synthesized mesh; over every fixture, scheme and level, for built and detected hierarchies.
#include <gtest/gtest.h>

#include <map>
#include <random>
#include <tuple>

#include "fixtures.h"
#include "mrvol/cage_polynomial_builder.h"
#include "mrvol/error.h"
#include "mrvol/hierarchy.h"
#include "mrvol/lifting.h"
#include "mrvol/volume_editor.h"
#include "mrvol/volume_tensor.h"

using namespace mrvol;

namespace {

inline void cross(const double* a, const double* b, double* out) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}

// The contraction VolumeEditor::useTensor performs, written out as the reference: triples from the
// cage entries of theta^e, q_ij = sum_k T_ijk d_k over detail k, a_i += d_j x q for detail j, and
// the constant from the volume.
CagePolynomial contractFromTheta(const VolumeTensor& tensor, const std::vector<double>& x, uint32_t cageSize,
                                 const std::vector<double>& shiftedCage, double volume) {
  CagePolynomial poly;
  poly.cageSize = cageSize;
  poly.linear.assign(3 * size_t(cageSize), 0.0);
  for (uint32_t i = 0; i < tensor.rowCount; ++i)
    for (uint32_t p = tensor.rowStart[i]; p < tensor.rowStart[i + 1]; ++p) {
      const uint32_t j = tensor.pairJ[p];
      double q[3] = {0, 0, 0};
      for (uint32_t t = tensor.pairStart[p]; t < tensor.pairStart[p + 1]; ++t) {
        const uint32_t k = tensor.kIndex(t);
        if (k < cageSize) {
          poly.tripleI.push_back(i), poly.tripleJ.push_back(j), poly.tripleK.push_back(k);
          poly.tripleT.push_back(tensor.values[t]);
        } else {
          for (int d = 0; d < 3; ++d) q[d] += tensor.values[t] * x[3 * size_t(k) + d];
        }
      }
      if (j >= cageSize) {
        double t[3];
        cross(&x[3 * size_t(j)], q, t);
        for (int d = 0; d < 3; ++d) poly.linear[3 * i + d] += t[d];
      } else if (q[0] != 0 || q[1] != 0 || q[2] != 0) {
        poly.pairI.push_back(i), poly.pairJ.push_back(j);
        poly.pairQ.insert(poly.pairQ.end(), q, q + 3);
      }
    }
  poly.constant = volume - poly.evaluate(shiftedCage.data(), nullptr);
  return poly;
}

using Key = std::tuple<uint32_t, uint32_t, uint32_t>;

// Every coefficient of the polynomial by (i, j, k, component): triples (i, j, k, 0), pairs
// (i, j, cageSize, d), linear (i, cageSize, cageSize, d); canonical whatever the storage order.
std::map<std::pair<Key, int>, double> terms(const CagePolynomial& p) {
  std::map<std::pair<Key, int>, double> out;
  const uint32_t none = p.cageSize;
  for (size_t t = 0; t < p.tripleT.size(); ++t) {
    uint32_t v[3] = {p.tripleI[t], p.tripleJ[t], p.tripleK[t]};
    // Canonical i < j < k: the triple product changes sign with each swap.
    double sign = 1;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b + 1 < 3 - a; ++b)
        if (v[b] > v[b + 1]) std::swap(v[b], v[b + 1]), sign = -sign;
    out[{{v[0], v[1], v[2]}, 0}] += sign * p.tripleT[t];
  }
  for (size_t t = 0; t < p.pairI.size(); ++t) {
    const bool swap = p.pairI[t] > p.pairJ[t];
    for (int d = 0; d < 3; ++d)
      out[{{std::min(p.pairI[t], p.pairJ[t]), std::max(p.pairI[t], p.pairJ[t]), none}, d}] += (swap ? -1 : 1) * p.pairQ[3 * t + d];
  }
  for (uint32_t i = 0; i < p.cageSize; ++i)
    for (int d = 0; d < 3; ++d) out[{{i, none, none}, d}] += p.linear[3 * i + d];
  return out;
}

struct Case {
  std::string name;
  Hierarchy h;
  std::vector<double> fine;  // positions, hierarchy order
};

// Positions: the base shape plus random details at every level (Loop synthesis), hierarchy order.
std::vector<double> finePositions(const Hierarchy& h, const TriangleMesh& base, unsigned seed) {
  std::vector<double> x = fixtures::randomVector(3 * h.fineVertexCount(), seed, 0.05);
  std::copy(base.positions.begin(), base.positions.end(), x.begin());
  WaveletTransform(h, SchemeOptions{}).synthesize(x.data(), 0);
  return x;
}

// Every base fixture subdivided, and the same meshes shuffled and detected (another vertex and
// face order: regions must come from the hierarchy, not from face blocks).
std::vector<Case> cases() {
  std::vector<Case> out;
  for (const auto& fx : fixtures::baseFixtures()) {
    Hierarchy h = Hierarchy::subdivide(fx.base, fx.levels);
    std::vector<double> fine = finePositions(h, fx.base, 3);
    auto shuffled = fixtures::shuffle(TriangleMesh{fine, h.fineFaces()}, 7);
    Hierarchy detected = Hierarchy::detect(shuffled.mesh, fx.levels);
    std::vector<double> detectedFine(fine.size());
    detected.toHierarchyOrder(shuffled.mesh.positions.data(), detectedFine.data());
    out.push_back({fx.name, std::move(h), std::move(fine)});
    out.push_back({fx.name + " (detected)", std::move(detected), std::move(detectedFine)});
  }
  return out;
}

double maxAbsOf(const std::vector<double>& v) { return fixtures::maxAbs(v); }

}  // namespace

TEST(CagePolynomialBuilder, EqualsTheContractionOfThetaOnEveryFixtureSchemeAndLevel) {
  std::mt19937 rng(11);
  int checked = 0, expected = 0;
  for (const auto& c : cases())
    for (const auto& options : fixtures::allSchemes()) {
      WaveletTransform wt(c.h, options);
      const std::vector<double>& fine = c.fine;
      expected += c.h.levels + 1;
      const TriangleMesh mesh{fine, c.h.fineFaces()};
      const Vec3 origin = volumeReferencePoint(mesh);
      for (int e = 0; e <= c.h.levels; ++e) {
        SCOPED_TRACE(c.name + " " + fixtures::label(options) + " e=" + std::to_string(e));
        std::vector<double> x = fine;
        wt.analyze(x.data(), e);
        const uint32_t cage = c.h.vertexCount[e];
        std::vector<double> shifted(x.begin(), x.begin() + 3 * size_t(cage));
        for (size_t i = 0; i < shifted.size(); i += 3) shifted[i] -= origin.x, shifted[i + 1] -= origin.y, shifted[i + 2] -= origin.z;
        const double volume = meshVolume(fine.data(), mesh.faces.data(), mesh.faceCount(), origin);

        CagePolynomialBuilder builder(wt, e);
        const CagePolynomial built = builder.build(x.data());
        const CagePolynomial reference =
            contractFromTheta(computeVolumeTensor(wt, e, TensorStorage::Cage), x, cage, shifted, volume);
        ASSERT_EQ(built.cageSize, cage);

        // Term by term, in canonical order; a term one side lacks must be zero on the other.
        auto a = terms(built), b = terms(reference);
        double scaleTriple = 0, scaleOther = 0;
        for (auto& [key, v] : b) (std::get<2>(key.first) == cage ? scaleOther : scaleTriple) = std::max(std::get<2>(key.first) == cage ? scaleOther : scaleTriple, std::fabs(v));
        for (auto& [key, v] : a) {
          auto it = b.find(key);
          const double other = it == b.end() ? 0.0 : it->second;
          const double scale = std::get<2>(key.first) == cage ? scaleOther : scaleTriple;
          ASSERT_NEAR(v, other, 1e-12 * scale) << "term " << std::get<0>(key.first) << "," << std::get<1>(key.first) << ","
                                               << std::get<2>(key.first) << " component " << key.second;
        }
        for (auto& [key, v] : b)
          if (!a.count(key)) ASSERT_NEAR(v, 0.0, 1e-12 * (std::get<2>(key.first) == cage ? scaleOther : scaleTriple));
        EXPECT_NEAR(built.constant, reference.constant, 1e-12 * std::fabs(volume));
        // Triples in runs of one (i, j), i < j < k, as evaluate() expects and the contraction gives.
        for (size_t t = 0; t < built.tripleT.size(); ++t) {
          ASSERT_TRUE(built.tripleI[t] < built.tripleJ[t] && built.tripleJ[t] < built.tripleK[t]);
          if (t > 0) ASSERT_TRUE(std::make_tuple(built.tripleI[t - 1], built.tripleJ[t - 1], built.tripleK[t - 1]) <
                                 std::make_tuple(built.tripleI[t], built.tripleJ[t], built.tripleK[t]));
        }

        // Its value is the volume of the mesh, here and at random cage positions (synthesized).
        EXPECT_NEAR(built.evaluate(shifted.data(), nullptr), volume, 1e-12 * std::fabs(volume));
        const double size = maxAbsOf(shifted);
        std::uniform_real_distribution<double> u(-0.3 * size, 0.3 * size);
        for (int trial = 0; trial < 3; ++trial) {
          std::vector<double> moved = x;
          for (size_t i = 0; i < 3 * size_t(cage); ++i)
            if (!c.h.boundary[i / 3]) moved[i] += u(rng);
          std::vector<double> cageAt(moved.begin(), moved.begin() + 3 * size_t(cage)), direction(3 * size_t(cage));
          for (size_t i = 0; i < cageAt.size(); i += 3) cageAt[i] -= origin.x, cageAt[i + 1] -= origin.y, cageAt[i + 2] -= origin.z;
          for (auto& d : direction) d = u(rng);
          std::vector<double> synthesized = moved;
          wt.synthesize(synthesized.data(), e);
          const double v = meshVolume(synthesized.data(), mesh.faces.data(), mesh.faceCount(), origin);
          std::vector<double> g1(cageAt.size()), g2(cageAt.size());
          const double v1 = built.evaluate(cageAt.data(), g1.data()), v2 = reference.evaluate(cageAt.data(), g2.data());
          const double scale = std::max(std::fabs(v), std::fabs(volume));
          EXPECT_NEAR(v1, v, 1e-12 * scale);
          EXPECT_NEAR(v1, v2, 1e-12 * scale);
          const double gScale = maxAbsOf(g2);
          for (size_t i = 0; i < g1.size(); ++i) ASSERT_NEAR(g1[i], g2[i], 1e-12 * gScale) << "gradient " << i;
          double k1[4], k2[4];
          built.alongDirection(cageAt.data(), direction.data(), k1);
          reference.alongDirection(cageAt.data(), direction.data(), k2);
          double kScale = 0;
          for (double k : k2) kScale = std::max(kScale, std::fabs(k));
          for (int k = 0; k < 4; ++k) EXPECT_NEAR(k1[k], k2[k], 1e-12 * kScale) << "cubic coefficient " << k;
        }
        ++checked;
      }
    }
  EXPECT_EQ(checked, expected);
  EXPECT_EQ(expected, 2 * 4 * (4 + 4 + 4 + 3 + 3));  // every level of every case
}

TEST(CagePolynomialBuilder, MatchesTheEditorsTensorPath) {
  // Through the real editor: its tensor polynomial's value and gradient at its own cage.
  for (const auto& fx : fixtures::baseFixtures()) {
    Hierarchy h = Hierarchy::subdivide(fx.base, fx.levels);
    WaveletTransform wt(h, SchemeOptions{});
    const std::vector<double> fine = finePositions(h, fx.base, 5);
    for (int e = 0; e < fx.levels; ++e) {
      VolumeEditor editor(h, wt, e, fine.data());
      editor.useTensor(computeVolumeTensor(wt, e, TensorStorage::Cage));
      std::vector<double> expected;
      const double v = editor.gradientTensor(expected);
      const Vec3 origin = volumeReferencePoint(TriangleMesh{fine, h.fineFaces()});
      std::vector<double> cage = editor.cagePositions();
      for (size_t i = 0; i < cage.size(); i += 3) cage[i] -= origin.x, cage[i + 1] -= origin.y, cage[i + 2] -= origin.z;
      const CagePolynomial built = CagePolynomialBuilder(wt, e).build(editor.coefficients().data());
      std::vector<double> g(cage.size());
      EXPECT_NEAR(built.evaluate(cage.data(), g.data()), v, 1e-12 * std::fabs(v)) << fx.name << " e=" << e;
      const double scale = maxAbsOf(expected);
      for (size_t i = 0; i < g.size(); ++i) ASSERT_NEAR(g[i], expected[i], 1e-12 * scale) << fx.name << " e=" << e;
    }
  }
}

TEST(CageBasis, RowsAreTheZeroDetailSynthesisOfTheCage) {
  // The stencil table applied to random cage coefficients equals synthesizeZeroDetails of them, and
  // its weights sum to one at every fine vertex (a translation moves the mesh rigidly).
  for (const auto& c : cases())
    for (const auto& options : fixtures::allSchemes()) {
      WaveletTransform wt(c.h, options);
      for (int e = 0; e <= c.h.levels; ++e) {
        SCOPED_TRACE(c.name + " " + fixtures::label(options) + " e=" + std::to_string(e));
        const CageBasis basis = cageBasis(wt, e);
        const size_t n = c.h.fineVertexCount();
        ASSERT_EQ(basis.offset.size(), n + 1);
        std::vector<double> x = fixtures::randomVector(3 * n, 9);
        std::vector<double> expected = x;
        wt.synthesizeZeroDetails(expected.data(), e);
        for (size_t v = 0; v < n; ++v) {
          double p[3] = {0, 0, 0}, sum = 0;
          for (uint64_t k = basis.offset[v]; k < basis.offset[v + 1]; ++k) {
            ASSERT_LT(basis.index[k], c.h.vertexCount[e]);
            if (k > basis.offset[v]) ASSERT_LT(basis.index[k - 1], basis.index[k]);
            for (int d = 0; d < 3; ++d) p[d] += basis.value[k] * x[3 * size_t(basis.index[k]) + d];
            sum += basis.value[k];
          }
          EXPECT_NEAR(sum, 1.0, 1e-13) << "vertex " << v;
          for (int d = 0; d < 3; ++d) ASSERT_NEAR(p[d], expected[3 * v + d], 1e-13) << "vertex " << v;
        }
      }
    }
}

TEST(CageBasis, DenseColumnsGiveTheSparseRowsBitForBit) {
  // The dense columns (small cages; in one chunk or in chunks of a few columns) and the sparse rows
  // make the same rows: the same indices and the same weights to the bit.
  for (const auto& c : cases())
    for (const auto& options : fixtures::allSchemes()) {
      WaveletTransform wt(c.h, options);
      for (int e = 0; e <= c.h.levels; ++e) {
        SCOPED_TRACE(c.name + " " + fixtures::label(options) + " e=" + std::to_string(e));
        const CageBasis sparse = cageBasis(wt, e, 0);
        const size_t columnBytes = 8 * c.h.fineVertexCount();
        for (size_t bytes : {size_t(64) << 20, columnBytes, 3 * columnBytes}) {
          const CageBasis dense = cageBasis(wt, e, ~0u, bytes);
          ASSERT_EQ(dense.offset, sparse.offset) << bytes;
          ASSERT_EQ(dense.index, sparse.index) << bytes;
          for (size_t k = 0; k < sparse.value.size(); ++k) ASSERT_EQ(dense.value[k], sparse.value[k]) << "entry " << k;
        }
      }
    }
}

TEST(CagePolynomialBuilder, RegionsCoverTheMeshOnce) {
  // Level-e faces as regions: one per face; each region's cage vertices include its corners.
  for (const auto& fx : fixtures::baseFixtures()) {
    Hierarchy h = Hierarchy::subdivide(fx.base, fx.levels);
    for (const auto& options : fixtures::allSchemes()) {
      WaveletTransform wt(h, options);
      for (int e = 0; e <= h.levels; ++e) {
        CagePolynomialBuilder builder(wt, e);
        EXPECT_EQ(builder.regionCount(), h.faces[e].size() / 3);
        EXPECT_GE(builder.maxRegionCage(), 3u);
        EXPECT_LE(builder.maxRegionCage(), size_t(h.vertexCount[e]));
        // Partition of unity: every fine vertex has weights, at least one.
        EXPECT_GE(builder.basisEntries(), h.fineVertexCount());
        if (e == h.levels) EXPECT_EQ(builder.basisEntries(), h.fineVertexCount());
        EXPECT_GT(builder.bytes(), 0u);
      }
    }
  }
}

TEST(CagePolynomialBuilder, RefusesMoreTermsThanAllowed) {
  Hierarchy h = Hierarchy::subdivide(fixtures::icosahedron(), 3);
  WaveletTransform wt(h, SchemeOptions{});
  EXPECT_NO_THROW(CagePolynomialBuilder(wt, 1, 80 * 220));  // 80 level-1 faces, at most 12 cage vertices each
  try {
    CagePolynomialBuilder builder(wt, 1, 1000);
    FAIL() << "accepted";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("level-1 cage polynomial would touch more than 1000 cage triples"), std::string::npos)
        << error.what();
  }
}

TEST(CagePolynomialBuilder, RefusesALevelOutOfRange) {
  Hierarchy h = Hierarchy::subdivide(fixtures::tetrahedron(), 2);
  WaveletTransform wt(h, SchemeOptions{});
  for (int e : {-1, 3}) {
    try {
      CagePolynomialBuilder builder(wt, e);
      FAIL() << "level " << e << " accepted";
    } catch (const Error& error) {
      EXPECT_NE(std::string(error.what()).find("level " + std::to_string(e) + " is out of range"), std::string::npos) << error.what();
    }
  }
}
