// The volume functions (volume_function.h, cage_polynomial.h): each value against an independent
// volume, each gradient against central finite differences, each cubic along a direction against
// evaluations along the line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <tuple>

#include "fixtures.h"
#include "mrvol/cage_polynomial.h"
#include "mrvol/error.h"
#include "mrvol/hierarchy.h"
#include "mrvol/lifting.h"
#include "mrvol/limit_volume.h"
#include "mrvol/mesh.h"
#include "mrvol/thread_pool.h"
#include "mrvol/vector3.h"
#include "mrvol/volume_function.h"
#include "mrvol/volume_tensor.h"

using namespace mrvol;

namespace {

// Checks the gradient (central differences on a few coordinates) and the cubic (against value()
// along the line) of f at x. The last `fixed` doubles stay put (the fine functions' vertex N, the
// reference point, is at zero by contract).
void checkFunction(const VolumeFunction& f, const std::vector<double>& x, unsigned seed, const std::string& what,
                   size_t fixed = 0) {
  ASSERT_EQ(x.size(), f.size()) << what;
  std::vector<double> gradient(f.size());
  const double v = f.value(x.data(), gradient.data());
  EXPECT_NEAR(v, f.value(x.data(), nullptr), 1e-14 * (1 + std::fabs(v))) << what << ": value with and without the gradient";
  std::mt19937 rng(seed);
  std::uniform_int_distribution<size_t> pick(0, f.size() - fixed - 1);
  const double h = 1e-6;
  for (int n = 0; n < 24; ++n) {
    const size_t i = pick(rng);
    auto plus = x, minus = x;
    plus[i] += h, minus[i] -= h;
    const double fd = (f.value(plus.data(), nullptr) - f.value(minus.data(), nullptr)) / (2 * h);
    EXPECT_NEAR(gradient[i], fd, 1e-7 * (1 + std::fabs(fd))) << what << " coordinate " << i;
  }
  std::vector<double> d = fixtures::randomVector(f.size(), seed + 1, 0.3);
  std::fill(d.end() - fixed, d.end(), 0.0);
  double k[4], known[4];
  f.alongDirection(x.data(), d.data(), k);
  double slope = 0;
  for (size_t i = 0; i < d.size(); ++i) slope += gradient[i] * d[i];
  EXPECT_NEAR(k[0], v, 1e-12 * (1 + std::fabs(v))) << what;
  EXPECT_NEAR(k[1], slope, 1e-10 * (1 + std::fabs(slope))) << what;
  known[0] = v, known[1] = slope;
  f.alongDirection(x.data(), d.data(), known, true);
  for (int j = 2; j < 4; ++j) EXPECT_NEAR(known[j], k[j], 1e-12 * (1 + std::fabs(k[j]))) << what << " k" << j << " (low known)";
  for (double s : {-1.3, -0.2, 0.5, 2.0}) {
    auto at = x;
    for (size_t i = 0; i < at.size(); ++i) at[i] += s * d[i];
    const double expected = f.value(at.data(), nullptr);
    EXPECT_NEAR(k[0] + s * (k[1] + s * (k[2] + s * k[3])), expected, 1e-11 * (1 + std::fabs(expected))) << what << " s=" << s;
  }
}

}  // namespace

TEST(VolumeFunction, FineEdgeVolumeIsTheMeshVolumeWithItsGradientAndCubic) {
  for (const auto& fx : fixtures::baseFixtures()) {
    Hierarchy h = Hierarchy::subdivide(fx.base, 2);
    const uint32_t n = uint32_t(h.fineVertexCount());
    std::vector<double> x = fixtures::randomVector(3 * (size_t(n) + 1), 3, 1.0);
    x[3 * n] = x[3 * n + 1] = x[3 * n + 2] = 0.0;  // vertex N: the reference point
    FineEdgeVolume f(h.fineFaces(), n);
    // Independent: the triangle sum (cones to the point on a mesh with boundary).
    const auto& faces = h.fineFaces();
    EXPECT_NEAR(f.value(x.data(), nullptr), meshVolume(x.data(), faces.data(), faces.size() / 3, Vec3{}),
                1e-12 * (1 + std::fabs(f.value(x.data(), nullptr))))
        << fx.name;
    checkFunction(f, x, 5, fx.name, 3);
  }
}

TEST(VolumeFunction, TriangleSetVolumeSumsItsTrianglesWithItsGradientAndCubic) {
  for (const auto& fx : fixtures::baseFixtures()) {
    Hierarchy h = Hierarchy::subdivide(fx.base, 1);
    const uint32_t n = uint32_t(h.fineVertexCount());
    const auto& faces = h.fineFaces();
    std::vector<double> x = fixtures::randomVector(3 * (size_t(n) + 1), 4, 1.0);
    x[3 * n] = x[3 * n + 1] = x[3 * n + 2] = 0.0;
    std::vector<uint8_t> flags(faces.size() / 3), rest(faces.size() / 3);
    std::vector<uint32_t> chosen;
    for (size_t t = 0; t < flags.size(); ++t) {
      flags[t] = t % 3 != 1, rest[t] = !flags[t];
      if (flags[t]) chosen.insert(chosen.end(), faces.begin() + 3 * t, faces.begin() + 3 * t + 3);
    }
    TriangleSetVolume part(faces, n, flags), other(faces, n, rest);
    EXPECT_NEAR(part.value(x.data(), nullptr), meshVolume(x.data(), chosen.data(), chosen.size() / 3, Vec3{}), 1e-12)
        << fx.name;
    // The parts of a partition add up to the whole.
    FineEdgeVolume whole(faces, n);
    EXPECT_NEAR(part.value(x.data(), nullptr) + other.value(x.data(), nullptr), whole.value(x.data(), nullptr), 1e-12)
        << fx.name;
    checkFunction(part, x, 6, fx.name, 3);
  }
  Hierarchy h = Hierarchy::subdivide(fixtures::tetrahedron(), 1);
  EXPECT_THROW(TriangleSetVolume(h.fineFaces(), uint32_t(h.fineVertexCount()), std::vector<uint8_t>(3)), Error);
}

TEST(VolumeFunction, CagePolynomialFromTheTensorIsTheVolumeOfTheCageWithItsGradientAndCubic) {
  for (const auto& fx : fixtures::baseFixtures())
    for (const auto& o : fixtures::allSchemes()) {
      Hierarchy h = Hierarchy::subdivide(fx.base, 2);
      WaveletTransform wt(h, o);
      const VolumeTensor tensor = computeVolumeTensor(wt, 0, TensorStorage::Cage);
      std::vector<double> x = fixtures::randomVector(3 * h.fineVertexCount(), 7, 1.0);
      CagePolynomial poly = contractCageRows(tensor, x.data());
      // The constant: the volume with a zero cage (detail-only entries), by synthesis.
      const auto& faces = h.fineFaces();
      std::vector<double> zeroCage = x;
      std::fill(zeroCage.begin(), zeroCage.begin() + 3 * tensor.rowCount, 0.0);
      wt.synthesize(zeroCage.data(), 0);
      poly.constant = meshVolume(zeroCage.data(), faces.data(), faces.size() / 3, Vec3{});
      CagePolynomialVolume f(poly);
      const std::vector<double> cage(x.begin(), x.begin() + 3 * tensor.rowCount);
      std::vector<double> fine = x;
      wt.synthesize(fine.data(), 0);
      const double volume = meshVolume(fine.data(), faces.data(), faces.size() / 3, Vec3{});
      EXPECT_NEAR(f.value(cage.data(), nullptr), volume, 1e-10 * (1 + std::fabs(volume))) << fx.name << " " << fixtures::label(o);
      checkFunction(f, cage, 8, fx.name + " " + fixtures::label(o));
    }
}

TEST(VolumeFunction, FormVolumeIsItsFormWithItsGradientAndCubic) {
  // The Loop limit form of each closed fixture, and the mesh's own triangle form: the runs of
  // pairs give the same value as the form, whatever the order of its entries.
  for (const auto& fx : fixtures::baseFixtures()) {
    Hierarchy h = Hierarchy::subdivide(fx.base, 1);
    const uint32_t n = uint32_t(h.fineVertexCount());
    const auto& faces = h.fineFaces();
    std::vector<double> x = fixtures::randomVector(3 * (size_t(n) + 1), 11, 1.0);
    x[3 * n] = x[3 * n + 1] = x[3 * n + 2] = 0.0;
    std::vector<std::pair<std::string, FineForm>> forms = {{"triangles", triangleForm(faces)}};
    if (fx.name != "open-patch") forms.emplace_back("limit", limitVolumeForm(faces.data(), faces.size() / 3, n));
    for (const auto& [kind, form] : forms) {
      FormVolume f(form, n);
      EXPECT_EQ(f.entryCount(), form.size());
      const double expected = form.evaluate(x.data());
      EXPECT_NEAR(f.value(x.data(), nullptr), expected, 1e-12 * (1 + std::fabs(expected))) << fx.name << " " << kind;
      checkFunction(f, x, 12, fx.name + " " + kind, 3);
    }
    if (fx.name == "open-patch") {
      FormVolume f(triangleForm(faces), n);
      EXPECT_NEAR(f.value(x.data(), nullptr), FineEdgeVolume(faces, n).value(x.data(), nullptr), 1e-12);
    }
  }
  FineForm bad;
  bad.corners = {0, 1, 9};
  bad.weights = {1.0};
  EXPECT_THROW(FormVolume(bad, 4), Error);
}

TEST(VolumeFunction, FirstMomentsAreVolumeTimesCentroidWithTheirGradients) {
  // A box [1, 3] x [-1, 0] x [2, 5]: volume 6, centroid (2, -0.5, 3.5), as triangles.
  TriangleMesh box;
  const double lo[3] = {1, -1, 2}, hi[3] = {3, 0, 5};
  for (int i = 0; i < 8; ++i) box.positions.insert(box.positions.end(), {i & 1 ? hi[0] : lo[0], i & 2 ? hi[1] : lo[1], i & 4 ? hi[2] : lo[2]});
  box.faces = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
  std::vector<double> x = box.positions;
  x.insert(x.end(), {0, 0, 0});  // vertex N, the reference point
  ASSERT_NEAR(FineEdgeVolume(box.faces, 8).value(x.data(), nullptr), 6.0, 1e-12);
  const double centroid[3] = {2, -0.5, 3.5};
  for (int k = 0; k < 3; ++k) {
    FirstMoment m(box.faces, 8, k);
    EXPECT_NEAR(m.value(x.data(), nullptr), 6.0 * centroid[k], 1e-12);
    m.setCentre(centroid[k]);  // about the centre of mass: zero
    EXPECT_NEAR(m.value(x.data(), nullptr), 0.0, 1e-12);
    m.setCentre(centroid[k] + 0.5);
    EXPECT_NEAR(m.value(x.data(), nullptr), -0.5 * 6.0, 1e-12);
  }
  EXPECT_THROW(FirstMoment(box.faces, 8, 3), Error);
  // Gradients against central differences, on fixtures (closed and open).
  for (const auto& fx : fixtures::baseFixtures()) {
    Hierarchy h = Hierarchy::subdivide(fx.base, 1);
    const uint32_t n = uint32_t(h.fineVertexCount());
    std::vector<double> p = fixtures::randomVector(3 * (size_t(n) + 1), 13, 1.0);
    p[3 * n] = p[3 * n + 1] = p[3 * n + 2] = 0.0;
    for (int k = 0; k < 3; ++k) {
      FirstMoment m(h.fineFaces(), n, k);
      m.setCentre(0.3 * (k - 1));
      std::vector<double> g(m.size());
      const double v = m.value(p.data(), g.data());
      EXPECT_NEAR(v, m.value(p.data(), nullptr), 1e-14 * (1 + std::fabs(v)));
      for (size_t i = 0; i < 3 * size_t(n); i += 7) {
        auto plus = p, minus = p;
        plus[i] += 1e-6, minus[i] -= 1e-6;
        const double fd = (m.value(plus.data(), nullptr) - m.value(minus.data(), nullptr)) / 2e-6;
        EXPECT_NEAR(g[i], fd, 1e-7 * (1 + std::fabs(fd))) << fx.name << " axis " << k << " coordinate " << i;
      }
    }
  }
}

// The centre of mass's one pass (volume and the three moments together) gives what the four passes
// give, to round-off, on closed and open meshes and on one of several blocks; the same bits at 1 and
// 2 threads (fixed blocks summed in order).
TEST(VolumeFunction, VolumeAndMomentsInOnePassAreTheSeparatePasses) {
  std::vector<std::pair<std::vector<uint32_t>, std::vector<double>>> meshes;
  for (const auto& fx : fixtures::baseFixtures()) {
    Hierarchy h = Hierarchy::subdivide(fx.base, 2);
    const uint32_t n = uint32_t(h.fineVertexCount());
    std::vector<double> p = fixtures::randomVector(3 * (size_t(n) + 1), 29, 1.0);
    p[3 * n] = p[3 * n + 1] = p[3 * n + 2] = 0.0;
    meshes.emplace_back(h.fineFaces(), std::move(p));
  }
  {
    Hierarchy big = Hierarchy::subdivide(fixtures::baseFixtures()[0].base, 7);  // over 2^15 triangles: several blocks
    const uint32_t n = uint32_t(big.fineVertexCount());
    ASSERT_GT(big.fineFaces().size() / 3, size_t(1) << 16);
    std::vector<double> p = fixtures::randomVector(3 * (size_t(n) + 1), 31, 1.0);
    p[3 * n] = p[3 * n + 1] = p[3 * n + 2] = 0.0;
    meshes.emplace_back(big.fineFaces(), std::move(p));
  }
  const double centre[3] = {0.1, -0.2, 0.3};
  for (const auto& [faces, p] : meshes) {
    const uint32_t n = uint32_t(p.size() / 3 - 1);
    const double volume = FineEdgeVolume(faces, n).value(p.data(), nullptr);
    double moments[3], again[3];
    setThreadCount(1);
    const double v1 = FirstMoment::volumeAndMoments(faces, p.data(), centre, moments);
    setThreadCount(2);
    const double v2 = FirstMoment::volumeAndMoments(faces, p.data(), centre, again);
    setThreadCount(1);
    EXPECT_NEAR(v1, volume, 1e-12 * (1 + std::fabs(volume)));
    EXPECT_EQ(v1, v2);
    for (int k = 0; k < 3; ++k) {
      FirstMoment m(faces, n, k);
      m.setCentre(centre[k]);
      const double separate = m.value(p.data(), nullptr);
      EXPECT_NEAR(moments[k], separate, 1e-12 * (1 + std::fabs(separate))) << "axis " << k;
      EXPECT_EQ(moments[k], again[k]);
    }
  }
}

// The centre of mass's three rows in one pass (what the editor's constraints evaluate): the values
// and gradients of three value() calls, bit for bit; not taken for moments of other axes or faces.
TEST(VolumeFunction, ThreeMomentsWithGradientsInOnePassAreTheSeparateCalls) {
  for (const auto& fx : fixtures::baseFixtures()) {
    Hierarchy h = Hierarchy::subdivide(fx.base, 2);
    const uint32_t n = uint32_t(h.fineVertexCount());
    std::vector<double> p = fixtures::randomVector(3 * (size_t(n) + 1), 37, 1.0);
    p[3 * n] = p[3 * n + 1] = p[3 * n + 2] = 0.0;
    const double centre[3] = {0.25, -0.5, 0.125};
    FirstMoment m0(h.fineFaces(), n, 0), m1(h.fineFaces(), n, 1), m2(h.fineFaces(), n, 2);
    FirstMoment* all[3] = {&m0, &m1, &m2};
    for (int k = 0; k < 3; ++k) all[k]->setCentre(centre[k]);
    std::vector<double> together(3 * p.size(), -1.0), separate;  // overwritten, not added to
    double values[3];
    const FineFunction* const rows[3] = {&m0, &m1, &m2};
    ASSERT_TRUE(FirstMoment::valuesWithGradients(rows, p.data(), values, together.data())) << fx.name;
    for (int k = 0; k < 3; ++k) {
      separate.assign(p.size(), 0.0);
      EXPECT_EQ(values[k], all[k]->value(p.data(), separate.data())) << fx.name << " axis " << k;
      for (size_t v = 0; v < p.size() / 3; ++v)
        for (int c = 0; c < 3; ++c) ASSERT_EQ(together[9 * v + 3 * k + c], separate[3 * v + c]) << fx.name << " axis " << k << " vertex " << v;
    }
    const FineFunction* const swapped[3] = {&m1, &m0, &m2};
    EXPECT_FALSE(FirstMoment::valuesWithGradients(swapped, p.data(), values, together.data()));
    FineEdgeVolume volume(h.fineFaces(), n);
    const FineFunction* const other[3] = {&m0, &m1, &volume};
    EXPECT_FALSE(FirstMoment::valuesWithGradients(other, p.data(), values, together.data()));
  }
}

// The edge table's order is part of the value's bits (a sum in edge order): edges by (smaller end,
// larger end), the half from the smaller end first. A plain sort of the half-edges gives the same sum,
// bit for bit, on a closed and an open mesh with vertices in shuffled order.
TEST(VolumeFunction, FineEdgeVolumeSumsEdgesInOrderOfTheirEnds) {
  for (const TriangleMesh& base : {fixtures::icosahedron(), fixtures::openPatch()}) {
    const Hierarchy h = Hierarchy::subdivide(base, 3);
    const fixtures::Shuffled shuffled = fixtures::shuffle(TriangleMesh{std::vector<double>(3 * h.fineVertexCount(), 0.0), h.fineFaces()}, 7);
    const std::vector<uint32_t>& faces = shuffled.mesh.faces;
    const uint32_t n = uint32_t(shuffled.mesh.vertexCount());
    std::vector<double> p = fixtures::randomVector(3 * size_t(n), 11);
    p.insert(p.end(), {0, 0, 0});
    struct Half { uint32_t lo, hi, b, c, a; };
    std::vector<Half> halves;
    for (size_t f = 0; f < faces.size(); f += 3)
      for (int k = 0; k < 3; ++k) {
        const uint32_t a = faces[f + k], b = faces[f + (k + 1) % 3], c = faces[f + (k + 2) % 3];
        halves.push_back({std::min(b, c), std::max(b, c), b, c, a});
      }
    std::stable_sort(halves.begin(), halves.end(), [](const Half& x, const Half& y) {
      return std::tie(x.lo, x.hi, x.b) < std::tie(y.lo, y.hi, y.b);
    });
    double sum = 0, w[3];
    for (size_t i = 0; i < halves.size();) {
      const bool paired = i + 1 < halves.size() && halves[i + 1].lo == halves[i].lo && halves[i + 1].hi == halves[i].hi;
      const uint32_t d = paired ? halves[i + 1].a : n;
      cross(&p[3 * size_t(halves[i].b)], &p[3 * size_t(halves[i].c)], w);
      sum += dotDifference(&p[3 * size_t(halves[i].a)], &p[3 * size_t(d)], w);
      i += paired ? 2 : 1;
    }
    EXPECT_EQ(FineEdgeVolume(faces, n).value(p.data(), nullptr), sum / 18.0);
  }
}

TEST(VolumeFunction, FineEdgeVolumeRefusesAnInconsistentOrientation) {
  std::vector<uint32_t> faces = fixtures::icosahedron().faces;
  std::swap(faces[1], faces[2]);  // one face turned over: its edges run the same way as their neighbours'
  try {
    FineEdgeVolume(faces, 12);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("is not a manifold edge of a consistently oriented mesh"), std::string::npos) << e.what();
  }
}
