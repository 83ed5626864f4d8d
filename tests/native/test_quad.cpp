// Catmull-Clark quad multiresolution: hierarchy (split, detection), the lifted filter bank against
// an independent textbook Catmull-Clark, perfect reconstruction, transposed steps, the bilinear
// volume and theta^e.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "mrvol/error.h"
#include "mrvol/quad_hierarchy.h"
#include "mrvol/quad_lifting.h"
#include "mrvol/quad_volume.h"
#include "quad_fixtures.h"

using namespace mrvol;
using quadfix::PolyMesh;

namespace {

struct Case {
  const char* name;
  PolyMesh base;  // quads only
  int levels;
};

// Closed and open quad meshes with interior valences 3, 4, 5, 6 (quadrangulated polyhedra).
std::vector<Case> cases() {
  std::vector<Case> out;
  out.push_back({"torus", quadfix::quadTorus(), 2});
  out.push_back({"bipyramid5 (valences 3, 4, 5)", quadfix::textbookCatmullClark(quadfix::bipyramid(5)).mesh, 2});
  out.push_back({"pyramid6 (valences 3, 6)", quadfix::textbookCatmullClark(quadfix::pyramid(6)).mesh, 2});
  out.push_back({"grid (boundary)", quadfix::grid(3, 2), 3});
  out.push_back({"open box (boundary, interior valence 3)", quadfix::openBox(), 2});
  for (size_t i = 0; i < out.size(); ++i) quadfix::jitter(out[i].base, 0.05, unsigned(7 + i));
  return out;
}

std::vector<double> flat(const PolyMesh& m) {
  std::vector<double> x;
  for (auto& p : m.p) x.insert(x.end(), p.begin(), p.end());
  return x;
}

QuadHierarchy split(const PolyMesh& base, int levels) {
  QuadMesh q = quadfix::toQuadMesh(base);
  validateQuadMesh(q);
  return QuadHierarchy::subdivide(q.quads, uint32_t(q.vertexCount()), levels);
}

// Level-l positions (hierarchy numbering) -> the textbook subdivision of the level-l mesh, in
// hierarchy numbering of level l + 1.
std::vector<double> textbookStep(const QuadHierarchy& h, int l, const std::vector<double>& x) {
  PolyMesh m;
  const uint32_t V = h.h.vertexCount[l];
  for (uint32_t v = 0; v < V; ++v) m.p.push_back({x[3 * v], x[3 * v + 1], x[3 * v + 2]});
  const auto& quads = h.quads[l];
  for (size_t f = 0; f < quads.size(); f += 4) m.faces.push_back({quads[f], quads[f + 1], quads[f + 2], quads[f + 3]});
  quadfix::CCResult r = quadfix::textbookCatmullClark(m);
  std::vector<double> out(3 * size_t(h.h.vertexCount[l + 1]), NAN);
  auto put = [&](uint32_t to, uint32_t from) {
    for (int k = 0; k < 3; ++k) out[3 * to + k] = r.mesh.p[from][k];
  };
  for (uint32_t v = 0; v < V; ++v) put(v, v);
  const QuadSplit& s = h.splits[l];
  for (size_t f = 0; f < s.facePoint.size(); ++f) put(s.facePoint[f], r.facePoint[f]);
  for (const auto& e : s.edges) put(e.point, r.edgePoint.at(quadfix::key(e.a, e.b)));
  return out;
}

double maxDiff(const double* a, const double* b, size_t n) {
  double m = 0;
  for (size_t i = 0; i < n; ++i) m = std::max(m, std::fabs(a[i] - b[i]));
  return m;
}

}  // namespace

TEST(QuadCatmullClark, CubeCornerGoesToFiveNinths) {
  QuadHierarchy h = split(quadfix::cube(), 1);
  int lowest = -1;
  WaveletTransform t = catmullClarkTransform(h, &lowest);
  EXPECT_EQ(lowest, 1);  // the cube's first split cannot be analysed
  std::vector<double> x(3 * h.h.fineVertexCount(), 0.0);
  std::vector<double> base = flat(quadfix::cube());
  std::copy(base.begin(), base.end(), x.begin());
  t.synthesizeZeroDetails(x.data(), 0);
  const uint32_t corner = 7;  // (1, 1, 1)
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(x[3 * corner + k], 5.0 / 9.0, 1e-15);
  EXPECT_THROW(catmullClarkLevel(h, 1), Error);
}

TEST(QuadCatmullClark, ZeroDetailSynthesisIsTextbookCatmullClark) {
  std::vector<Case> all = cases();
  all.push_back({"cube", quadfix::cube(), 3});
  for (const Case& c : all) {
    QuadHierarchy h = split(c.base, c.levels);
    WaveletTransform t = catmullClarkTransform(h);
    const size_t N = h.h.fineVertexCount();
    // Level by level, from the textbook result of the level before.
    std::vector<double> level = flat(c.base);
    for (int l = 1; l <= c.levels; ++l) {
      std::vector<double> x(3 * N, 0.0);
      std::copy(level.begin(), level.end(), x.begin());
      for (const auto& step : t.synthesisSteps(l)) step.forward(x.data());
      std::vector<double> expected = textbookStep(h, l - 1, level);
      EXPECT_LT(maxDiff(x.data(), expected.data(), expected.size()), 1e-14) << c.name << " level " << l;
      level = expected;
    }
    // All levels at once, by the fast zero-detail path.
    std::vector<double> x(3 * N, 7.0);  // detail entries are not read
    std::vector<double> base = flat(c.base);
    std::copy(base.begin(), base.end(), x.begin());
    t.synthesizeZeroDetails(x.data(), 0);
    EXPECT_LT(maxDiff(x.data(), level.data(), level.size()), 1e-13) << c.name;
  }
}

TEST(QuadCatmullClark, PerfectReconstruction) {
  std::vector<Case> all = cases();
  all.push_back({"cube", quadfix::cube(), 3});
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (const Case& c : all) {
    QuadHierarchy h = split(c.base, c.levels);
    int lowest = 0;
    WaveletTransform t = catmullClarkTransform(h, &lowest);
    EXPECT_EQ(lowest, std::string(c.name) == "cube" ? 1 : 0) << c.name;
    std::vector<double> x(3 * h.h.fineVertexCount());
    for (double& v : x) v = u(rng);
    for (int e = lowest; e <= c.levels; ++e) {
      std::vector<double> y = x;
      t.analyze(y.data(), e);
      for (double v : y) ASSERT_TRUE(std::isfinite(v)) << c.name;
      t.synthesize(y.data(), e);
      EXPECT_LT(maxDiff(x.data(), y.data(), x.size()), 1e-12) << c.name << " e=" << e;
    }
  }
}

TEST(QuadCatmullClark, TransposedStepsAreAdjoint) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  for (const Case& c : cases()) {
    QuadHierarchy h = split(c.base, c.levels);
    WaveletTransform t = catmullClarkTransform(h);
    const size_t N = h.h.fineVertexCount();
    for (int l = 1; l <= c.levels; ++l)
      for (const auto& step : t.synthesisSteps(l)) {
        std::vector<double> x(3 * N), y(3 * N);
        for (double& v : x) v = u(rng);
        for (double& v : y) v = u(rng);
        std::vector<double> ax = x, aty = y;
        step.forward(ax.data());
        step.transposed(aty.data());
        const double lhs = std::inner_product(ax.begin(), ax.end(), y.begin(), 0.0);
        const double rhs = std::inner_product(x.begin(), x.end(), aty.begin(), 0.0);
        EXPECT_NEAR(lhs, rhs, 1e-12 * (1 + std::fabs(lhs))) << c.name << " level " << l << " " << step.name;
      }
    // The whole adjoint of synthesis.
    std::vector<double> x(3 * N), g(3 * N);
    for (double& v : x) v = u(rng);
    for (double& v : g) v = u(rng);
    std::vector<double> sx = x, stg = g;
    t.synthesize(sx.data(), 0);
    t.synthesisAdjoint(stg.data(), 0);
    EXPECT_NEAR(std::inner_product(sx.begin(), sx.end(), g.begin(), 0.0),
                std::inner_product(x.begin(), x.end(), stg.begin(), 0.0), 1e-10) << c.name;
  }
}

TEST(QuadHierarchyDetect, RecoversSplitsInAnyOrder) {
  std::vector<Case> all = cases();
  all.push_back({"cube", quadfix::cube(), 3});
  std::mt19937 rng(11);
  for (const Case& c : all) {
    QuadHierarchy h = split(c.base, c.levels);
    const uint32_t N = uint32_t(h.h.fineVertexCount());
    // Shuffle the vertices, the quads and each quad's starting corner.
    std::vector<uint32_t> perm(N);
    std::iota(perm.begin(), perm.end(), 0u);
    std::shuffle(perm.begin(), perm.end(), rng);
    QuadMesh fine;
    fine.positions.assign(3 * size_t(N), 0.0);
    std::vector<std::array<uint32_t, 4>> quads;
    for (size_t f = 0; f < h.fineQuads().size(); f += 4) {
      const int r = int(rng() % 4);
      std::array<uint32_t, 4> q;
      for (int i = 0; i < 4; ++i) q[i] = perm[h.fineQuads()[f + (i + r) % 4]];
      quads.push_back(q);
    }
    std::shuffle(quads.begin(), quads.end(), rng);
    for (auto& q : quads) fine.quads.insert(fine.quads.end(), q.begin(), q.end());
    QuadHierarchy d = QuadHierarchy::detect(fine);
    EXPECT_EQ(d.levels(), c.levels) << c.name;
    EXPECT_EQ(d.h.vertexCount, h.h.vertexCount) << c.name;
    // The base vertices found are the base's (forced by the extraordinary or boundary vertices).
    std::vector<uint32_t> found(d.h.inputIndex.begin(), d.h.inputIndex.begin() + d.h.vertexCount[0]);
    std::vector<uint32_t> expected;
    for (uint32_t v = 0; v < h.h.vertexCount[0]; ++v) expected.push_back(perm[v]);
    std::sort(found.begin(), found.end());
    std::sort(expected.begin(), expected.end());
    // (The torus has valence 4 everywhere: another labelling is as valid a base.)
    if (std::string(c.name) != "torus") EXPECT_EQ(found, expected) << c.name;
    // Detection stops at a mesh that is no split.
    EXPECT_EQ(QuadHierarchy::detect(quadfix::toQuadMesh(c.base)).levels(), 0) << c.name;
  }
}

TEST(QuadMeshValidation, NamesWhatIsWrong) {
  QuadMesh m = quadfix::toQuadMesh(quadfix::cube());
  QuadMesh bad = m;
  bad.quads[5] = 99;
  EXPECT_THROW(validateQuadMesh(bad), Error);
  bad = m;
  bad.quads[1] = bad.quads[0];
  try {
    validateQuadMesh(bad);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("quad 0"), std::string::npos) << e.what();
  }
  bad = m;
  std::swap(bad.quads[0], bad.quads[1]);  // flipped quad
  EXPECT_THROW(validateQuadMesh(bad), Error);
  EXPECT_TRUE(validateQuadMesh(m).closed);
}

TEST(QuadVolume, BilinearPatchFormulaMatchesFineTriangulation) {
  // A twisted quad: the cone volume of its bilinear patch against k x k triangulations of it.
  const double p[4][3] = {{0.3, -0.2, 0.1}, {1.2, 0.1, 0.6}, {1.0, 1.3, -0.4}, {-0.1, 0.9, 0.8}};
  QuadMesh q;
  for (auto& c : p) q.positions.insert(q.positions.end(), c, c + 3);
  q.quads = {0, 1, 2, 3};
  const double exact = bilinearPatchForm(q.quads).evaluate(q.positions.data());
  auto at = [&](double s, double t, double* out) {
    for (int k = 0; k < 3; ++k)
      out[k] = (1 - s) * (1 - t) * p[0][k] + s * (1 - t) * p[1][k] + s * t * p[2][k] + (1 - s) * t * p[3][k];
  };
  double previous = 1e300;
  for (int n : {4, 8, 16, 32, 64}) {
    TriangleMesh t;
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        double x[3];
        at(double(i) / n, double(j) / n, x);
        t.positions.insert(t.positions.end(), x, x + 3);
      }
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
        t.faces.insert(t.faces.end(), {a, b, c, a, c, d});
      }
    const double err = std::fabs(meshVolume(t.positions.data(), t.faces.data(), t.faces.size() / 3, Vec3{}) - exact);
    EXPECT_LT(err, previous / 3.5) << n;  // second order: the error falls by about 4 per halving
    previous = err;
  }
  EXPECT_LT(previous, 5e-4 * std::fabs(exact));
  // The cube [-1, 1]^3 (planar quads) encloses 8.
  EXPECT_NEAR(bilinearVolume(quadfix::toQuadMesh(quadfix::cube())), 8.0, 1e-14);
}

TEST(QuadVolume, ThetaGivesTheBilinearVolume) {
  std::vector<Case> all = cases();
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  for (const Case& c : all) {
    const int levels = std::min(c.levels, 2);
    QuadHierarchy h = split(c.base, levels);
    WaveletTransform t = catmullClarkTransform(h);
    const size_t N = h.h.fineVertexCount();
    std::vector<double> x(3 * N, 0.0);
    std::vector<double> base = flat(c.base);
    std::copy(base.begin(), base.end(), x.begin());
    t.synthesizeZeroDetails(x.data(), 0);
    for (double& v : x) v += u(rng);  // details too
    QuadMesh fine;
    fine.positions = x;
    fine.quads = h.fineQuads();
    const Vec3 o = quadReferencePoint(fine);
    for (size_t i = 0; i < N; ++i) x[3 * i] -= o.x, x[3 * i + 1] -= o.y, x[3 * i + 2] -= o.z;
    const double volume = bilinearVolume(fine);
    const FineForm form = bilinearPatchForm(h.fineQuads());
    FormVolume fv(form, uint32_t(N));
    std::vector<double> xe(x);
    xe.resize(3 * (N + 1), 0.0);
    EXPECT_NEAR(fv.value(xe.data(), nullptr), volume, 1e-12 * std::fabs(volume)) << c.name;
    for (int e = 0; e <= levels; ++e) {
      std::vector<double> coeff = x;
      t.analyze(coeff.data(), e);
      VolumeTensor full = computeVolumeTensor(t, e, TensorStorage::Full, form);
      EXPECT_NEAR(full.evaluate(coeff.data()), volume, 1e-10 * std::fabs(volume)) << c.name << " e=" << e;
      if (N <= 200) {
        VolumeTensor direct = computeVolumeTensorDirect(t, e, TensorStorage::Full, form);
        EXPECT_NEAR(direct.evaluate(coeff.data()), volume, 1e-10 * std::fabs(volume)) << c.name << " e=" << e;
      }
    }
  }
}

TEST(QuadVolume, FormVolumeGradientAndCubic) {
  PolyMesh m = quadfix::quadTorus();
  quadfix::jitter(m, 0.1, 3);
  QuadMesh q = quadfix::toQuadMesh(m);
  const FineForm form = bilinearPatchForm(q.quads);
  const uint32_t N = uint32_t(q.vertexCount());
  FormVolume fv(form, N);
  std::vector<double> x = q.positions, d(3 * (N + 1)), g(3 * (N + 1));
  x.resize(3 * (N + 1), 0.0);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1, 1);
  for (size_t i = 0; i < 3 * size_t(N); ++i) d[i] = u(rng);
  const double v0 = fv.value(x.data(), g.data());
  double k[4];
  fv.alongDirection(x.data(), d.data(), k);
  EXPECT_NEAR(k[0], v0, 1e-12);
  EXPECT_NEAR(k[1], std::inner_product(g.begin(), g.end(), d.begin(), 0.0), 1e-10);
  for (double s : {0.3, -0.7}) {
    std::vector<double> y(x);
    for (size_t i = 0; i < y.size(); ++i) y[i] += s * d[i];
    EXPECT_NEAR(fv.value(y.data(), nullptr), k[0] + s * (k[1] + s * (k[2] + s * k[3])), 1e-10);
  }
  // The one-cross-product form of the same volume: value, gradient and cubic equal FormVolume's.
  QuadPatchVolume qv(q.quads, N);
  std::vector<double> g2(3 * (N + 1));
  EXPECT_NEAR(qv.value(x.data(), g2.data()), v0, 1e-12);
  for (size_t i = 0; i < g.size(); ++i) EXPECT_NEAR(g2[i], g[i], 1e-12) << i;
  double k2[4];
  qv.alongDirection(x.data(), d.data(), k2);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(k2[i], k[i], 1e-10) << i;
}

// ---------------------------------------------------------------------------------------------
// The multiresolution mesh and the editor.

#include "mrvol/quad_editor.h"
#include "mrvol/quad_multires_mesh.h"

namespace {
// A subdivided, then perturbed mesh (details at every level), in a shuffled vertex order.
struct Fine {
  QuadMesh mesh;
};
QuadMesh fineMesh(const PolyMesh& base, int levels, unsigned seed, double noise = 0.02) {
  QuadMesh b = quadfix::toQuadMesh(base);
  QuadMultiresMesh s = QuadMultiresMesh::subdivide(b, levels);
  QuadMesh m{s.subdivisionPositions(b.positions), s.quads()};
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-noise, noise);
  for (double& v : m.positions) v += u(rng);
  return m;
}
}  // namespace

TEST(QuadMultires, DetectsAndKeepsTheBilinearVolumeThroughTheta) {
  for (const Case& c : cases()) {
    const int levels = std::min(c.levels, 2);
    QuadMesh m = fineMesh(c.base, levels, 17);
    QuadMultiresMesh mm(m);
    ASSERT_EQ(mm.levels(), levels) << c.name;
    const double volume = bilinearVolume(m);
    EXPECT_DOUBLE_EQ(mm.info(m.positions).volume, volume);
    for (int e = 0; e <= levels; ++e) {
      EXPECT_LT(mm.roundtripError(m.positions, e), 1e-12) << c.name;
      VolumeTensor cage = mm.computeTensor(e, TensorStorage::Cage);
      EXPECT_NEAR(mm.tensorVolume(cage, m.positions), volume, 1e-10 * std::fabs(volume)) << c.name << " e=" << e;
    }
  }
}

TEST(QuadMultires, CubeStopsAnalysisAtLevelOne) {
  QuadMesh m = fineMesh(quadfix::cube(), 2, 5);
  QuadMultiresMesh mm(m);
  EXPECT_EQ(mm.levels(), 2);
  EXPECT_EQ(mm.lowestLevel(), 1);
  EXPECT_THROW(mm.analyze(m.positions, 0), Error);
  EXPECT_LT(mm.roundtripError(m.positions, 1), 1e-12);
  // Subdivision itself works from the cube: the corner goes to 5/9 after one split.
  QuadMesh cube = quadfix::toQuadMesh(quadfix::cube());
  QuadMultiresMesh one = QuadMultiresMesh::subdivide(cube, 1);
  std::vector<double> p = one.subdivisionPositions(cube.positions);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(p[3 * 7 + k], 5.0 / 9.0, 1e-15);
}

TEST(QuadEditor, EditsKeepTheBilinearVolume) {
  std::vector<Case> all = cases();
  for (const Case& c : all) {
    const int levels = 2;
    QuadMesh m = fineMesh(c.base, levels, 23);
    QuadMultiresMesh mm(m);
    for (int e : {0, 1}) {
      for (bool tensor : {false, true}) {
        QuadVolumeEditor ed(mm.hierarchy(), mm.transform(), e, m.positions.data());
        if (tensor) ed.useTensor(mm.computeTensor(e, TensorStorage::Cage));
        const double ref = ed.referenceVolume();
        EXPECT_NEAR(ref, bilinearVolume(m), 1e-12 * std::fabs(ref));
        // Pull one interior cage vertex outwards and hold it.
        std::vector<double> target = ed.cagePositions();
        uint32_t moved = 0;
        while (mm.hierarchy().h.boundary[moved]) ++moved;
        for (int k = 0; k < 3; ++k) target[3 * moved + k] *= 1.4;
        std::vector<uint8_t> held(ed.cageSize(), 0);
        held[moved] = 1;
        EditOptions o;
        EditReport r = ed.deformCage(target, held, o);
        EXPECT_TRUE(r.converged) << c.name << " " << r.message;
        EXPECT_EQ(r.path, tensor ? GradientPath::Tensor : GradientPath::MatrixFree);
        QuadMesh now{ed.positions(), m.quads};
        const double v = bilinearVolume(now);
        EXPECT_LT(std::fabs(v - ref) / std::fabs(ref), 1e-5) << c.name << " e=" << e << (tensor ? " tensor" : " matrix-free");
        EXPECT_NE(std::fabs(r.volumeTarget - ref), 0.0);
        for (int k = 0; k < 3; ++k) EXPECT_EQ(ed.cagePositions()[3 * moved + k], target[3 * moved + k]);
        // Boundary vertices stay where they were.
        std::vector<double> p = ed.positions();
        for (uint32_t h = 0; h < mm.vertexCount(); ++h)
          if (mm.hierarchy().h.boundary[h]) {
            const uint32_t v = mm.hierarchy().h.inputIndex[h];
            for (int k = 0; k < 3; ++k) EXPECT_NEAR(p[3 * v + k], m.positions[3 * v + k], 1e-12) << c.name;
          }
      }
    }
  }
}

// The bilinear patches' centre of mass, from the quad moments (QuadFirstMoment) of the positions.
static Vec3 bilinearCentroid(const QuadMesh& mesh) {
  std::vector<double> x = mesh.positions;
  x.insert(x.end(), {0.0, 0.0, 0.0});
  const uint32_t n = uint32_t(mesh.positions.size() / 3);
  const double v = QuadPatchVolume(mesh.quads, n).value(x.data(), nullptr);
  double c[3];
  for (int k = 0; k < 3; ++k) c[k] = QuadFirstMoment(mesh.quads, n, k).value(x.data(), nullptr) / v;
  return {c[0], c[1], c[2]};
}

TEST(QuadEditor, KeepsTheCentreOfMassOfTheBilinearPatches) {
  int closedCases = 0;
  for (const Case& c : cases()) {
    QuadMesh m = fineMesh(c.base, 2, 29);
    QuadMultiresMesh mm(m);
    if (!mm.hierarchy().h.closed()) continue;  // a closed solid has a centre of mass
    ++closedCases;
    double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
    for (size_t i = 0; i < m.positions.size(); ++i) lo[i % 3] = std::min(lo[i % 3], m.positions[i]), hi[i % 3] = std::max(hi[i % 3], m.positions[i]);
    const double diagonal = std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
    const Vec3 start = bilinearCentroid(m);
    for (bool keep : {true, false}) {
      QuadVolumeEditor ed(mm.hierarchy(), mm.transform(), 1, m.positions.data());
      ed.keepCentroid(keep);
      EXPECT_EQ(ed.keepsCentroid(), keep);
      const Vec3 before = ed.centroid();
      EXPECT_LT(std::hypot(before.x - start.x, before.y - start.y, before.z - start.z), 1e-12 * diagonal) << c.name;
      // Pull one interior cage vertex far out and hold it.
      std::vector<double> target = ed.cagePositions();
      uint32_t moved = 0;
      while (mm.hierarchy().h.boundary[moved]) ++moved;
      for (int k = 0; k < 3; ++k) target[3 * moved + k] += 0.3 * diagonal * (k == 0 ? 1 : 0.5);
      std::vector<uint8_t> held(ed.cageSize(), 0);
      held[moved] = 1;
      EditReport r = ed.deformCage(target, held, EditOptions{});
      ASSERT_TRUE(r.converged) << c.name << ": " << r.message;
      const QuadMesh now{ed.positions(), m.quads};
      EXPECT_LT(std::fabs(bilinearVolume(now) - ed.referenceVolume()) / ed.referenceVolume(), 1e-5) << c.name;
      const Vec3 after = bilinearCentroid(now);
      const double drift = std::hypot(after.x - start.x, after.y - start.y, after.z - start.z) / diagonal;
      if (keep) {
        EXPECT_LT(drift, 1e-6) << c.name << ": the centre of mass moved";
        ASSERT_EQ(r.centroidResult.size(), 3u);
        EXPECT_NEAR(r.centroidResult[0], after.x, 1e-9 * diagonal);
        EXPECT_NEAR(r.centroidReference[0], start.x, 1e-9 * diagonal);
      } else {
        EXPECT_GT(drift, 1e-3) << c.name << ": the move does not test the centre";
        EXPECT_TRUE(r.centroidResult.empty());
      }
    }
  }
  EXPECT_GE(closedCases, 2);
}

#include "mrvol/quad_obj.h"

TEST(QuadObj, KeepsQuadsAndNamesTheLine) {
  QuadMesh m = quadfix::toQuadMesh(quadfix::cube());
  const std::string text = writeObjQuads(m);
  QuadMesh back = readObjQuads(text);
  EXPECT_EQ(back.quads, m.quads);
  EXPECT_EQ(back.positions, m.positions);
  // Other face forms and negative indices.
  QuadMesh forms = readObjQuads("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1/1 2/2/2 3//3 -1\n");
  EXPECT_EQ(forms.quads, (std::vector<uint32_t>{0, 1, 2, 3}));
  try {
    readObjQuads(text + "f 1 2 3\n");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("line 15: a face with 3 corners"), std::string::npos) << e.what();
  }
  EXPECT_THROW(readObjQuads("v 0 0 0\nf 1 2 3 4\n"), Error);
}

TEST(QuadMultires, RefusesASplitTooLargeToOpen) {
  QuadMesh cube = quadfix::toQuadMesh(quadfix::cube());
  try {
    QuadMultiresMesh::subdivide(cube, 12);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("too large"), std::string::npos) << e.what();
  }
}

TEST(QuadHierarchyDetect, CorruptedSplitsFailCleanlyOrDetectConsistently) {
  // Split meshes with one quad flipped, dropped, or a corner replaced: opening them either throws
  // Error or gives a hierarchy whose round trip is exact. Never a crash.
  std::mt19937 rng(29);
  for (const Case& c : cases()) {
    QuadMesh good = fineMesh(c.base, 2, 31);
    const size_t F = good.faceCount();
    for (int trial = 0; trial < 30; ++trial) {
      QuadMesh m = good;
      const size_t q = rng() % F;
      switch (trial % 3) {
        case 0: std::swap(m.quads[4 * q + 1], m.quads[4 * q + 3]); break;      // flipped
        case 1: m.quads.erase(m.quads.begin() + 4 * q, m.quads.begin() + 4 * q + 4); break;  // a hole
        case 2: m.quads[4 * q + rng() % 4] = uint32_t(rng() % m.vertexCount()); break;  // a wrong corner
      }
      try {
        QuadMultiresMesh mm(m);
        EXPECT_LT(mm.roundtripError(m.positions, mm.lowestLevel()), 1e-10) << c.name << " trial " << trial;
      } catch (const Error&) {
      }
    }
  }
}
