// What the editor keeps beyond the mesh volume: the Loop limit surface's volume, and the centre of
// mass with the volume (four rows). Checked on the positions the editor gives, independently of its
// own bookkeeping, after random drags; and the same drags without it move the kept quantity.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "fixtures.h"
#include "mrvol/error.h"
#include "mrvol/hierarchy.h"
#include "mrvol/lifting.h"
#include "mrvol/limit_volume.h"
#include "mrvol/volume_editor.h"
#include "mrvol/volume_tensor.h"

using namespace mrvol;

namespace {

struct Session {
  Hierarchy h;
  WaveletTransform wt;
  std::vector<double> positions;  // caller order = hierarchy order here
  Session(const fixtures::Fixture& fx, unsigned seed) : h(Hierarchy::subdivide(fx.base, fx.levels)), wt(h, SchemeOptions{}) {
    positions.assign(3 * h.fineVertexCount(), 0.0);
    std::copy(fx.base.positions.begin(), fx.base.positions.end(), positions.begin());
    auto noise = fixtures::randomVector(positions.size(), seed, 0.03);
    for (size_t i = fx.base.positions.size(); i < positions.size(); ++i) positions[i] = noise[i];
    wt.synthesize(positions.data(), 0);
  }
  TriangleMesh mesh(const std::vector<double>& p) const { return TriangleMesh{p, h.fineFaces()}; }
};

// Centre of mass of a mesh's solid, independently: tetrahedra to the first vertex... of the
// triangles, about the origin (closed meshes).
Vec3 centroidOf(const TriangleMesh& m) {
  double v = 0, c[3] = {0, 0, 0};
  const auto& p = m.positions;
  for (size_t f = 0; f < m.faces.size(); f += 3) {
    const double* a = &p[3 * size_t(m.faces[f])];
    const double* b = &p[3 * size_t(m.faces[f + 1])];
    const double* d = &p[3 * size_t(m.faces[f + 2])];
    const double det = a[0] * (b[1] * d[2] - b[2] * d[1]) - a[1] * (b[0] * d[2] - b[2] * d[0]) + a[2] * (b[0] * d[1] - b[1] * d[0]);
    v += det / 6;
    for (int k = 0; k < 3; ++k) c[k] += det / 6 * (a[k] + b[k] + d[k]) / 4;
  }
  return {c[0] / v, c[1] / v, c[2] / v};
}

double distance(Vec3 a, Vec3 b) { return std::sqrt((a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y) + (a.z - b.z) * (a.z - b.z)); }
// The centre is kept per coordinate (each moment row to its tolerance): the largest coordinate's move.
double coordinateMove(Vec3 a, Vec3 b) { return std::max({std::fabs(a.x - b.x), std::fabs(a.y - b.y), std::fabs(a.z - b.z)}); }

double diagonal(const std::vector<double>& p) {
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
  for (size_t i = 0; i < p.size(); i += 3)
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[i + k]), hi[k] = std::max(hi[k], p[i + k]);
  return std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
}

// A few random drags of single cage vertices by up to 15% of the model's size (the same drags for
// the same seed); calls check(report) after each.
template <class Check>
void randomDrags(VolumeEditor& editor, const Hierarchy& h, unsigned seed, int count, double size, Check check) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.15 * size, 0.15 * size);
  std::uniform_int_distribution<uint32_t> pick(0, editor.cageSize() - 1);
  for (int d = 0; d < count; ++d) {
    const uint32_t c = pick(rng);
    const double move[3] = {u(rng), u(rng), u(rng)};
    if (h.boundary[c]) continue;
    auto target = editor.cagePositions();
    std::vector<uint8_t> held(editor.cageSize(), 0);
    held[c] = 1;
    for (int k = 0; k < 3; ++k) target[3 * c + k] += move[k];
    check(editor.deformCage(target, held, EditOptions{}));
  }
}

std::vector<fixtures::Fixture> closedFixtures() {
  std::vector<fixtures::Fixture> out;
  for (auto& fx : fixtures::baseFixtures())
    if (fx.name != "open-patch") out.push_back(fx);
  return out;
}

}  // namespace

TEST(EditorKeep, CentroidAndVolumeKeptAfterRandomDrags) {
  for (const auto& fx : closedFixtures())
    for (int e : {0, 1}) {
      Session s(fx, 3);
      const double size = fixtures::maxAbs(s.positions), diag = diagonal(s.positions);
      const double reference = meshVolume(s.mesh(s.positions));
      const Vec3 start = centroidOf(s.mesh(s.positions));
      VolumeEditor editor(s.h, s.wt, e, s.positions.data());
      editor.keepCentroid(true);
      EXPECT_LT(distance(editor.centroid(), start), 1e-12 * diag);
      EXPECT_LT(distance(editor.referenceCentroid(), start), 1e-12 * diag);
      double worst = 0;
      randomDrags(editor, s.h, 7 + e, 12, size, [&](const EditReport& r) {
        ASSERT_TRUE(r.converged) << fx.name << " e=" << e << ": " << r.message;
        ASSERT_EQ(r.centroidResult.size(), 3u);
        const TriangleMesh out = s.mesh(editor.positions());
        EXPECT_NEAR(meshVolume(out), reference, 1e-5 * std::fabs(reference)) << fx.name;
        const double drift = coordinateMove(centroidOf(out), start) / diag;
        worst = std::max(worst, drift);
        EXPECT_LT(drift, 1e-6) << fx.name << " e=" << e;
      });
      std::printf("  %s e=%d: worst centroid drift %.3g of the diagonal\n", fx.name.c_str(), e, worst);
    }
}

TEST(EditorKeep, WithoutItTheCentroidMoves) {
  // The same drags keeping the volume only: the centre of mass does move (so the test above can fail).
  for (const auto& fx : closedFixtures()) {
    Session s(fx, 3);
    const double size = fixtures::maxAbs(s.positions), diag = diagonal(s.positions);
    const Vec3 start = centroidOf(s.mesh(s.positions));
    VolumeEditor editor(s.h, s.wt, 0, s.positions.data());
    randomDrags(editor, s.h, 7, 12, size, [&](const EditReport& r) {
      ASSERT_TRUE(r.converged);
      EXPECT_TRUE(r.centroidResult.empty());
    });
    EXPECT_GT(distance(centroidOf(s.mesh(editor.positions())), start) / diag, 1e-3) << fx.name;
  }
}

TEST(EditorKeep, CentroidOfAMeshWithBoundaryIsItsConeSolids) {
  const auto fx = fixtures::baseFixtures().back();
  ASSERT_EQ(fx.name, "open-patch");
  Session s(fx, 3);
  VolumeEditor editor(s.h, s.wt, 0, s.positions.data());
  editor.keepCentroid(true);
  const Vec3 start = editor.centroid();
  const double diag = diagonal(s.positions), reference = editor.referenceVolume();
  randomDrags(editor, s.h, 5, 10, fixtures::maxAbs(s.positions), [&](const EditReport& r) {
    ASSERT_TRUE(r.converged) << r.message;
    EXPECT_NEAR(r.volumeResult, reference, 1e-5 * std::fabs(reference));
    EXPECT_LT(coordinateMove(editor.centroid(), start) / diag, 1e-6);
  });
}

TEST(EditorKeep, LimitSurfaceVolumeKeptOnBothPaths) {
  for (const auto& fx : closedFixtures())
    for (int e : {0, 1})
      for (bool tensor : {false, true}) {
        Session s(fx, 4);
        const auto& faces = s.h.fineFaces();
        const FineForm form = limitVolumeForm(faces.data(), faces.size() / 3, s.h.fineVertexCount());
        const double reference = limitVolume(s.mesh(s.positions));
        const double meshBefore = meshVolume(s.mesh(s.positions));
        VolumeEditor editor(s.h, s.wt, e, s.positions.data());
        editor.useLimitSurface(form);
        EXPECT_TRUE(editor.limitSurface());
        EXPECT_NEAR(editor.referenceVolume(), reference, 1e-12 * std::fabs(reference));
        if (tensor) {
          editor.useTensor(computeVolumeTensor(s.wt, e, TensorStorage::Cage, form));
          EXPECT_EQ(editor.path(), GradientPath::Tensor);
        }
        if (!tensor) EXPECT_FALSE(editor.usePolynomial()) << "the builder knows the mesh's triangles only";
        double meshChange = 0;
        randomDrags(editor, s.h, 9 + e, 10, fixtures::maxAbs(s.positions), [&](const EditReport& r) {
          ASSERT_TRUE(r.converged) << fx.name << ": " << r.message;
          EXPECT_EQ(r.path, tensor ? GradientPath::Tensor : GradientPath::MatrixFree);
          const TriangleMesh out = s.mesh(editor.positions());
          EXPECT_NEAR(limitVolume(out), reference, 1e-5 * std::fabs(reference)) << fx.name << " e=" << e;
          meshChange = std::max(meshChange, std::fabs(meshVolume(out) - meshBefore) / std::fabs(meshBefore));
        });
        // The mesh's own volume is not what is kept: it does change (so the check above can fail).
        EXPECT_GT(meshChange, 1e-6) << fx.name << " e=" << e;
      }
}

TEST(EditorKeep, RefusesWhatDoesNotGoTogether) {
  const auto fixtures = fixtures::baseFixtures();
  Session s(fixtures[0], 1);
  const auto& faces = s.h.fineFaces();
  const FineForm form = limitVolumeForm(faces.data(), faces.size() / 3, s.h.fineVertexCount());
  {
    VolumeEditor editor(s.h, s.wt, 0, s.positions.data());
    editor.keepCentroid(true);
    EXPECT_THROW(editor.useLimitSurface(form), Error);
    EXPECT_THROW(editor.setParts({{0, 1}}), Error);
    editor.keepCentroid(false);
    editor.useLimitSurface(form);
    EXPECT_THROW(editor.keepCentroid(true), Error);
    EXPECT_THROW(editor.setParts({{0, 1}}), Error);
  }
  {
    VolumeEditor editor(s.h, s.wt, 0, s.positions.data());
    editor.setParts({{0, 1}, {2, 3}});
    EXPECT_THROW(editor.keepCentroid(true), Error);
    EXPECT_THROW(editor.useLimitSurface(form), Error);
  }
}

TEST(EditorKeep, ANewReferenceVolumeKeepsTheSameCentroid) {
  Session s(fixtures::baseFixtures()[0], 2);
  VolumeEditor editor(s.h, s.wt, 0, s.positions.data());
  editor.keepCentroid(true);
  const Vec3 c = editor.referenceCentroid();
  editor.setReferenceVolume(1.2 * editor.referenceVolume());
  EXPECT_LT(distance(editor.referenceCentroid(), c), 1e-12);
  const EditReport r = editor.correct({}, EditOptions{});
  ASSERT_TRUE(r.converged) << r.message;
  EXPECT_NEAR(meshVolume(s.mesh(editor.positions())), editor.referenceVolume(), 1e-5 * editor.referenceVolume());
  EXPECT_LT(coordinateMove(centroidOf(s.mesh(editor.positions())), c) / diagonal(s.positions), 1e-6);
}
