// The first moments of the solid enclosed by bilinear patches (QuadFirstMoment): exactly the
// triangles' on flat quads, the limit of finer and finer triangulations of warped patches, the
// moment about a centre q is the moment about the origin less q times the bilinear volume, and the
// gradient is the value's derivative.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "mrvol/error.h"
#include "mrvol/mesh.h"
#include "mrvol/quad_volume.h"
#include "mrvol/volume_function.h"
#include "quad_fixtures.h"

using namespace mrvol;

namespace {

// N positions and the origin's slot (FineFunction's N + 1).
std::vector<double> withOriginSlot(const std::vector<double>& positions) {
  std::vector<double> x = positions;
  x.insert(x.end(), {0.0, 0.0, 0.0});
  return x;
}

// Each bilinear patch sampled on an m x m grid of its (u, v) square and split into 2 m^2 flat
// triangles: its moments tend to the patch's as m grows (the triangles' own vertices are apart).
TriangleMesh finelyTriangulated(const QuadMesh& mesh, int m) {
  TriangleMesh out;
  for (size_t f = 0; f < mesh.quads.size(); f += 4) {
    const double* c[4];
    for (int i = 0; i < 4; ++i) c[i] = &mesh.positions[3 * size_t(mesh.quads[f + i])];
    const uint32_t first = uint32_t(out.positions.size() / 3);
    for (int j = 0; j <= m; ++j)
      for (int i = 0; i <= m; ++i) {
        const double u = double(i) / m, v = double(j) / m;
        const double n[4] = {(1 - u) * (1 - v), u * (1 - v), u * v, (1 - u) * v};
        for (int k = 0; k < 3; ++k) out.positions.push_back(n[0] * c[0][k] + n[1] * c[1][k] + n[2] * c[2][k] + n[3] * c[3][k]);
      }
    auto at = [&](int i, int j) { return first + uint32_t(j * (m + 1) + i); };
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i)
        out.faces.insert(out.faces.end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j), at(i + 1, j + 1), at(i, j + 1)});
  }
  return out;
}

double triangleMoment(const TriangleMesh& mesh, int axis) {
  const std::vector<double> x = withOriginSlot(mesh.positions);
  return FirstMoment(mesh.faces, uint32_t(mesh.positions.size() / 3), axis).value(x.data(), nullptr);
}

QuadMesh warpedTorus() {
  quadfix::PolyMesh torus = quadfix::quadTorus(8, 5);
  quadfix::jitter(torus, 0.25, 7);
  for (auto& p : torus.p) p[0] += 0.6, p[1] -= 0.3, p[2] += 0.9;  // off the origin: every term counts
  return quadfix::toQuadMesh(torus);
}

}  // namespace

TEST(QuadFirstMoment, FlatQuadsGiveTheTrianglesMomentsAndTheBoxCentre) {
  quadfix::PolyMesh box = quadfix::cube();
  const double scale[3] = {0.7, 1.3, 2.1}, shift[3] = {0.4, -1.2, 0.25};
  for (auto& p : box.p)
    for (int k = 0; k < 3; ++k) p[k] = p[k] * scale[k] + shift[k];
  const QuadMesh mesh = quadfix::toQuadMesh(box);
  TriangleMesh triangles{mesh.positions, triangulateQuads(mesh.quads)};
  const std::vector<double> x = withOriginSlot(mesh.positions);
  const double volume = 8 * scale[0] * scale[1] * scale[2];
  for (int k = 0; k < 3; ++k) {
    const double m = QuadFirstMoment(mesh.quads, 8, k).value(x.data(), nullptr);
    EXPECT_NEAR(m, triangleMoment(triangles, k), 1e-13 * volume) << "axis " << k;
    EXPECT_NEAR(m, volume * shift[k], 1e-13 * volume) << "axis " << k;
  }
  EXPECT_THROW(QuadFirstMoment(mesh.quads, 8, 3), Error);
}

TEST(QuadFirstMoment, WarpedPatchesAreTheLimitOfFinerTriangulations) {
  const QuadMesh mesh = warpedTorus();
  const std::vector<double> x = withOriginSlot(mesh.positions);
  const uint32_t n = uint32_t(mesh.positions.size() / 3);
  for (int k = 0; k < 3; ++k) {
    const double exact = QuadFirstMoment(mesh.quads, n, k).value(x.data(), nullptr);
    // the plain triangulation (one diagonal per quad) differs: the patches are warped
    const double coarse = triangleMoment(TriangleMesh{mesh.positions, triangulateQuads(mesh.quads)}, k);
    const double e8 = std::fabs(triangleMoment(finelyTriangulated(mesh, 8), k) - exact);
    const double e32 = std::fabs(triangleMoment(finelyTriangulated(mesh, 32), k) - exact);
    const double scale = std::fabs(exact);
    EXPECT_GT(std::fabs(coarse - exact), 1e-4 * scale) << "axis " << k << ": the test's patches are not warped";
    // second order: 16 times smaller for 4 times finer, and small
    EXPECT_LT(e32, e8 / 10) << "axis " << k << ": " << e8 << " then " << e32;
    EXPECT_LT(e32, 1e-4 * scale) << "axis " << k;
  }
}

TEST(QuadFirstMoment, AboutACentreIsAboutTheOriginLessCentreTimesBilinearVolume) {
  const QuadMesh mesh = warpedTorus();
  const std::vector<double> x = withOriginSlot(mesh.positions);
  const uint32_t n = uint32_t(mesh.positions.size() / 3);
  const double volume = QuadPatchVolume(mesh.quads, n).value(x.data(), nullptr);
  ASSERT_GT(volume, 0);
  for (int k = 0; k < 3; ++k) {
    QuadFirstMoment m(mesh.quads, n, k);
    const double about0 = m.value(x.data(), nullptr);
    m.setCentre(about0 / volume);  // the centre of mass: the moment about it vanishes
    EXPECT_NEAR(m.value(x.data(), nullptr), 0.0, 1e-13 * std::fabs(about0) + 1e-15);
    m.setCentre(-0.8);
    EXPECT_NEAR(m.value(x.data(), nullptr), about0 + 0.8 * volume, 1e-13 * (std::fabs(about0) + volume));
  }
}

TEST(QuadFirstMoment, GradientIsTheDerivative) {
  const QuadMesh mesh = warpedTorus();
  std::vector<double> x = withOriginSlot(mesh.positions);
  const uint32_t n = uint32_t(mesh.positions.size() / 3);
  for (int k = 0; k < 3; ++k) {
    QuadFirstMoment m(mesh.quads, n, k);
    m.setCentre(0.3 * k - 0.2);
    std::vector<double> gradient(m.size());
    const double value = m.value(x.data(), gradient.data());
    EXPECT_DOUBLE_EQ(value, m.value(x.data(), nullptr));
    for (size_t i : {size_t(0), size_t(7), size_t(3 * n / 2), size_t(3 * n - 1)}) {
      const double h = 1e-6, keep = x[i];
      x[i] = keep + h;
      const double up = m.value(x.data(), nullptr);
      x[i] = keep - h;
      const double down = m.value(x.data(), nullptr);
      x[i] = keep;
      EXPECT_NEAR(gradient[i], (up - down) / (2 * h), 1e-6 * (1 + std::fabs(gradient[i]))) << "axis " << k << ", coordinate " << i;
    }
  }
}
