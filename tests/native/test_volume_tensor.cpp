// The volume tensor: recursion equals the direct construction, tensor volume equals mesh volume.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <map>

#include "fixtures.h"
#include "mrvol/hierarchy.h"
#include "mrvol/lifting.h"
#include "mrvol/volume_tensor.h"

using namespace mrvol;

namespace {

using fixtures::allSchemes;

// The stored entries by (i, j, k), through VolumeTensor::entries (checked against the CSR arrays
// in EntriesListTheStoredArrays).
std::map<std::tuple<uint32_t, uint32_t, uint32_t>, double> entries(const VolumeTensor& t) {
  std::map<std::tuple<uint32_t, uint32_t, uint32_t>, double> out;
  const VolumeTensor::Entries e = t.entries();
  for (size_t n = 0; n < e.values.size(); ++n) out[{e.i[n], e.j[n], e.k[n]}] = e.values[n];
  return out;
}

// A fine mesh with random-ish positions around the base shape (so volumes are non-trivial).
std::vector<double> finePositions(const Hierarchy& h, const WaveletTransform& wt, const TriangleMesh& base, unsigned seed) {
  std::vector<double> x(3 * h.fineVertexCount(), 0.0);
  std::copy(base.positions.begin(), base.positions.end(), x.begin());
  auto noise = fixtures::randomVector(x.size(), seed, 0.05);
  for (size_t i = base.positions.size(); i < x.size(); ++i) x[i] = noise[i];
  wt.synthesize(x.data(), 0);
  return x;
}

}  // namespace

// Small hierarchies: the direct construction is O(#triangles * |row|^3).
std::vector<fixtures::Fixture> smallFixtures() {
  return {{"tetrahedron", fixtures::tetrahedron(), 2}, {"octahedron", fixtures::octahedron(), 2},
          {"icosahedron", fixtures::icosahedron(), 1}, {"torus", fixtures::torus(), 1},
          {"open-patch", fixtures::openPatch(), 1}};
}

TEST(VolumeTensor, RecursionEqualsDirectConstruction) {
  for (const auto& fx : smallFixtures()) {
    Hierarchy h = Hierarchy::subdivide(fx.base, fx.levels);
    for (const auto& options : allSchemes()) {
      WaveletTransform wt(h, options);
      for (int e = 0; e <= h.levels; ++e)
        for (TensorStorage storage : {TensorStorage::Full, TensorStorage::Cage}) {
          auto a = entries(computeVolumeTensor(wt, e, storage));
          auto b = entries(computeVolumeTensorDirect(wt, e, storage));
          double scale = 0;
          for (auto& [key, v] : b) scale = std::max(scale, std::fabs(v));
          size_t missing = 0;
          double err = 0;
          for (auto& [key, v] : b) {
            auto it = a.find(key);
            if (it == a.end()) { err = std::max(err, std::fabs(v)); if (std::fabs(v) > 1e-12 * scale) ++missing; }
            else err = std::max(err, std::fabs(v - it->second));
          }
          for (auto& [key, v] : a)
            if (!b.count(key)) err = std::max(err, std::fabs(v));
          EXPECT_LT(err, 1e-12 * scale) << fx.name << " " << schemeName(options.kind) << " e=" << e;
          EXPECT_EQ(missing, 0u);
        }
    }
  }
}

TEST(VolumeTensor, FullTensorVolumeEqualsMeshVolume) {
  for (auto fx : fixtures::baseFixtures()) {
    fx.levels = std::min(fx.levels, fx.name == "icosahedron" || fx.name == "tetrahedron" ? 2 : 1);
    Hierarchy h = Hierarchy::subdivide(fx.base, fx.levels);
    for (const auto& options : allSchemes()) {
      WaveletTransform wt(h, options);
      auto fine = finePositions(h, wt, fx.base, 3);
      const double volume = meshVolume(fine.data(), h.fineFaces().data(), h.fineFaces().size() / 3, Vec3{});
      for (int e = 0; e <= h.levels; ++e) {
        VolumeTensor t = computeVolumeTensor(wt, e, TensorStorage::Full);
        auto x = fine;
        wt.analyze(x.data(), e);
        EXPECT_NEAR(t.evaluate(x.data()), volume, 1e-10 * std::fabs(volume))
            << fx.name << " " << schemeName(options.kind) << " e=" << e;
        // The gradient is the derivative: compare with central differences on a few coefficients.
        std::vector<double> grad(x.size());
        double v2 = t.evaluateWithGradient(x.data(), grad.data(), t.vertexCount);
        EXPECT_NEAR(v2, volume, 1e-10 * std::fabs(volume));
        for (size_t c : {size_t(0), size_t(4), x.size() - 1}) {
          auto xp = x, xm = x;
          const double hstep = 1e-6;
          xp[c] += hstep, xm[c] -= hstep;
          double fd = (t.evaluate(xp.data()) - t.evaluate(xm.data())) / (2 * hstep);
          EXPECT_NEAR(grad[c], fd, 1e-6 * (1 + std::fabs(fd))) << fx.name << " coefficient " << c;
        }
      }
    }
  }
}

TEST(VolumeTensor, CageStorageKeepsRowsOfCageVertices) {
  Hierarchy h = Hierarchy::subdivide(fixtures::icosahedron(), 3);
  WaveletTransform wt(h, SchemeOptions{});
  VolumeTensor full = computeVolumeTensor(wt, 0, TensorStorage::Full);
  VolumeTensor cage = computeVolumeTensor(wt, 0, TensorStorage::Cage);
  EXPECT_EQ(full.nnzFull, 42253800u);  // the paper: 42E6 non-zero coefficients
  EXPECT_LT(cage.storedCount(), full.storedCount());
  EXPECT_EQ(cage.rowCount, 12u);
  auto fine = finePositions(h, wt, fixtures::icosahedron(), 5);
  auto x = fine;
  wt.analyze(x.data(), 0);
  // The gradient with respect to the cage is the same from both.
  std::vector<double> g1(36), g2(36);
  full.evaluateWithGradient(x.data(), g1.data(), 12);
  cage.evaluateWithGradient(x.data(), g2.data(), 12);
  for (int c = 0; c < 36; ++c) EXPECT_NEAR(g1[c], g2[c], 1e-12 * (1 + std::fabs(g1[c])));
  // Moving only some coefficients changes the volume by the change of the terms involving them.
  std::vector<uint8_t> moving(h.fineVertexCount(), 0);
  moving[3] = moving[7] = 1;
  auto y = x;
  y[9] += 0.1, y[22] -= 0.05;
  double change = full.evaluate(y.data()) - full.evaluate(x.data());
  double local = cage.evaluateInvolving(y.data(), moving) - cage.evaluateInvolving(x.data(), moving);
  EXPECT_NEAR(local, change, 1e-12);
}

// Cage storage: Theta(x) = (stored entries)(x) + Theta(x with the cage coefficients set to zero),
// since every stored entry has a cage index and every dropped one has none.
TEST(VolumeTensor, CageTensorVolumeEqualsMeshVolume) {
  for (const auto& fx : fixtures::baseFixtures()) {
    Hierarchy h = Hierarchy::subdivide(fx.base, fx.levels);
    for (const auto& options : allSchemes()) {
      WaveletTransform wt(h, options);
      auto fine = finePositions(h, wt, fx.base, 9);
      const auto& faces = h.fineFaces();
      const double volume = meshVolume(fine.data(), faces.data(), faces.size() / 3, Vec3{});
      for (int e = 0; e <= h.levels; ++e) {
        VolumeTensor t = computeVolumeTensor(wt, e, TensorStorage::Cage);
        auto x = fine;
        wt.analyze(x.data(), e);
        auto detailsOnly = x;
        std::fill(detailsOnly.begin(), detailsOnly.begin() + 3 * h.vertexCount[e], 0.0);
        wt.synthesize(detailsOnly.data(), e);
        const double folded = meshVolume(detailsOnly.data(), faces.data(), faces.size() / 3, Vec3{});
        EXPECT_NEAR(t.evaluate(x.data()) + folded, volume, 1e-10 * std::fabs(volume))
            << fx.name << " " << schemeName(options.kind) << " e=" << e;
      }
    }
  }
}

// The estimate that decides between the tensor and the matrix-free path is of the right size.
TEST(VolumeTensor, EstimateIsWithinAFactorOfTheActualTensor) {
  for (int n : {3, 4})
    for (int e : {0, n - 2}) {
      Hierarchy h = Hierarchy::subdivide(fixtures::icosahedron(), n);
      WaveletTransform wt(h, SchemeOptions{});
      TensorEstimate est = estimateCageTensor(wt, e);
      VolumeTensor t = computeVolumeTensor(wt, e, TensorStorage::Cage);
      const double ratio = double(est.entries) / double(t.storedCount());
      EXPECT_GT(ratio, 0.8) << "n=" << n << " e=" << e;
      EXPECT_LT(ratio, 3.0) << "n=" << n << " e=" << e;
      EXPECT_TRUE(est.fits());
    }
  Hierarchy big = Hierarchy::subdivide(fixtures::icosahedron(), 6);
  WaveletTransform wt(big, SchemeOptions{});
  EXPECT_FALSE(estimateCageTensor(wt, 0, 2).fits());  // 12 patches of ~40k vertices: 12 GB each
}

// entries(): one (i < j < k, value) per stored entry, in storage order, the same sum as evaluate.
TEST(VolumeTensor, EntriesListTheStoredArrays) {
  for (const auto& fx : smallFixtures()) {
    Hierarchy h = Hierarchy::subdivide(fx.base, fx.levels);
    WaveletTransform wt(h, SchemeOptions{});
    const auto x = fixtures::randomVector(3 * h.fineVertexCount(), 11);
    for (TensorStorage storage : {TensorStorage::Full, TensorStorage::Cage}) {
      VolumeTensor t = computeVolumeTensor(wt, 0, storage);
      const VolumeTensor::Entries e = t.entries();
      ASSERT_EQ(e.values.size(), t.storedCount()) << fx.name;
      ASSERT_EQ(e.i.size(), t.storedCount());
      ASSERT_EQ(e.j.size(), t.storedCount());
      ASSERT_EQ(e.k.size(), t.storedCount());
      EXPECT_EQ(e.values, t.values);
      double sum = 0, scale = 0;
      for (size_t n = 0; n < e.values.size(); ++n) {
        ASSERT_LT(e.i[n], e.j[n]);
        ASSERT_LT(e.j[n], e.k[n]);
        ASSERT_LT(e.k[n], t.vertexCount);
        if (storage == TensorStorage::Cage) ASSERT_LT(e.i[n], h.vertexCount[0]);
        const double* a = &x[3 * e.i[n]];
        const double* b = &x[3 * e.j[n]];
        const double* c = &x[3 * e.k[n]];
        const double det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
        sum += e.values[n] * det;
        scale += std::fabs(e.values[n] * det);
      }
      EXPECT_NEAR(sum, t.evaluate(x.data()), 1e-12 * scale) << fx.name;
    }
  }
}

TEST(VolumeTensor, StoresNoRoundOffResidues) {
  // Cancellation leaves residues near 1e-17 of the largest entry where exact arithmetic gives 0;
  // they are dropped, and the entries kept stand far apart from them (at least 1e-12 of the largest,
  // ten times the cut), so that the count of non-zeros does not depend on where the cut lies.
  Hierarchy h = Hierarchy::subdivide(fixtures::icosahedron(), 3);  // the spiky ball's connectivity
  for (SchemeKind kind : {SchemeKind::Loop, SchemeKind::Butterfly, SchemeKind::Linear}) {
    SchemeOptions o;
    o.kind = kind;
    WaveletTransform wt(h, o);
    for (TensorStorage storage : {TensorStorage::Full, TensorStorage::Cage}) {
      VolumeTensor t = computeVolumeTensor(wt, 0, storage);
      double largest = 0, smallest = INFINITY;
      for (double v : t.values) largest = std::max(largest, std::fabs(v)), smallest = std::min(smallest, std::fabs(v));
      EXPECT_GT(smallest, 1e-12 * largest) << schemeName(kind);
      if (storage == TensorStorage::Full) EXPECT_EQ(t.nnzFull, 6 * uint64_t(t.storedCount()));
      // The CSR arrays stay consistent: every pair has an entry, rows count pairs.
      EXPECT_EQ(t.rowStart.back(), t.pairJ.size());
      EXPECT_EQ(t.pairStart.size(), t.pairJ.size() + 1);
      for (size_t p = 0; p < t.pairJ.size(); ++p) EXPECT_LT(t.pairStart[p], t.pairStart[p + 1]);
    }
  }
}
