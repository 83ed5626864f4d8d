// One level's lifting phases through MultiresMesh, in the caller's vertex order (shuffled meshes):
// all steps are one level of synthesis, zero steps change nothing, analysis phase by phase is the
// exact reverse, and the steps in caller indices are the hierarchy's steps renumbered, so that
// applying them to caller-ordered data gives the same phases. Every bad argument is refused.
#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

#include "fixtures.h"
#include "mrvol/error.h"
#include "mrvol/multires_mesh.h"

using namespace mrvol;
using fixtures::allSchemes;
using fixtures::label;
using fixtures::maxAbs;
using fixtures::maxDiff;

namespace {

// A fixture's subdivision with random fine positions, its vertices shuffled, opened as the caller would.
struct Case {
  std::string name;
  MultiresMesh mesh;
  std::vector<double> positions;
};

std::vector<Case> shuffledCases() {
  std::vector<Case> out;
  unsigned seed = 3;
  for (const auto& fx : fixtures::baseFixtures()) {
    const int n = std::min(fx.levels, 2);
    Hierarchy h = Hierarchy::subdivide(fx.base, n);
    TriangleMesh fine;
    fine.faces = h.fineFaces();
    fine.positions = fixtures::randomVector(3 * h.fineVertexCount(), ++seed);
    fixtures::Shuffled s = fixtures::shuffle(fine, ++seed);
    out.push_back({fx.name, MultiresMesh(s.mesh, n), s.mesh.positions});
  }
  return out;
}

std::string where(const Case& c, const SchemeOptions& scheme, int level, int steps = -1) {
  return c.name + " " + label(scheme) + " l=" + std::to_string(level) + (steps >= 0 ? " k=" + std::to_string(steps) : "");
}

std::string messageOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST(LiftingPhases, AllStepsOfEachLevelAreSynthesisAndTheirInversesAnalysis) {
  for (const auto& c : shuffledCases())
    for (const auto& scheme : allSchemes()) {
      const int n = c.mesh.levels();
      ASSERT_GE(n, 1) << c.name;
      auto coefficients = c.mesh.analyze(c.positions, 0, scheme);
      // Synthesis level by level, all the steps of each: the same operations as synthesize.
      auto x = coefficients;
      for (int l = 1; l <= n; ++l) x = c.mesh.synthesizeSteps(x, l, c.mesh.liftingStepCount(l, scheme), scheme);
      EXPECT_EQ(x, c.mesh.synthesize(coefficients, 0, scheme)) << c.name << " " << label(scheme);
      // Analysis level by level, all the steps undone: the same as analyze.
      auto y = c.positions;
      for (int l = n; l >= 1; --l) {
        y = c.mesh.analyzeSteps(y, l, c.mesh.liftingStepCount(l, scheme), scheme);
        EXPECT_EQ(y, c.mesh.analyze(c.positions, l - 1, scheme)) << where(c, scheme, l);
      }
    }
}

TEST(LiftingPhases, ZeroStepsChangeNothing) {
  for (const auto& c : shuffledCases())
    for (const auto& scheme : allSchemes())
      for (int l = 1; l <= c.mesh.levels(); ++l) {
        EXPECT_EQ(c.mesh.synthesizeSteps(c.positions, l, 0, scheme), c.positions) << where(c, scheme, l);
        EXPECT_EQ(c.mesh.analyzeSteps(c.positions, l, 0, scheme), c.positions) << where(c, scheme, l);
      }
}

TEST(LiftingPhases, AnalysisPhaseByPhaseIsTheExactReverseOfSynthesis) {
  for (const auto& c : shuffledCases())
    for (const auto& scheme : allSchemes())
      for (int l = 1; l <= c.mesh.levels(); ++l) {
        const int count = c.mesh.liftingStepCount(l, scheme);
        EXPECT_EQ(count, scheme.kind == SchemeKind::Loop ? 4 : 2) << where(c, scheme, l);
        const auto start = c.mesh.analyze(c.positions, l - 1, scheme);
        const auto end = c.mesh.synthesizeSteps(start, l, count, scheme);
        for (int k = 0; k <= count; ++k) {
          const auto forward = c.mesh.synthesizeSteps(start, l, k, scheme);
          const auto backward = c.mesh.analyzeSteps(end, l, count - k, scheme);
          EXPECT_LT(maxDiff(forward, backward), 1e-12 * maxAbs(c.positions)) << where(c, scheme, l, k);
          // A step changes only its targets, and a phase that writes something changes the data.
          if (k > 0) {
            const auto before = c.mesh.synthesizeSteps(start, l, k - 1, scheme);
            const LiftingStep step = c.mesh.liftingSteps(l, scheme)[k - 1];
            std::vector<uint8_t> target(c.positions.size() / 3, 0);
            for (uint32_t t : step.targets) target[t] = 1;
            for (size_t v = 0; v < target.size(); ++v)
              if (!target[v])
                for (int d = 0; d < 3; ++d) ASSERT_EQ(forward[3 * v + d], before[3 * v + d]) << where(c, scheme, l, k);
          }
        }
      }
}

// The steps in caller indices: the hierarchy's steps with every vertex renumbered, and applied to
// caller-ordered data they are the phases synthesizeSteps runs.
TEST(LiftingPhases, CallerIndexStepsAreTheHierarchyStepsRenumbered) {
  for (const auto& c : shuffledCases())
    for (const auto& scheme : allSchemes())
      for (int l = 1; l <= c.mesh.levels(); ++l) {
        const Hierarchy& h = c.mesh.hierarchy();
        const auto& own = c.mesh.transform(scheme).synthesisSteps(l);
        const auto steps = c.mesh.liftingSteps(l, scheme);
        ASSERT_EQ(steps.size(), own.size()) << where(c, scheme, l);
        auto x = c.mesh.analyze(c.positions, l - 1, scheme);
        for (size_t k = 0; k < steps.size(); ++k) {
          const LiftingStep& a = steps[k];
          const LiftingStep& b = own[k];
          EXPECT_EQ(a.name, b.name);
          EXPECT_EQ(a.scaling, b.scaling);
          EXPECT_EQ(a.readsOnlyDetails, b.readsOnlyDetails);
          EXPECT_EQ(a.offsets, b.offsets);
          EXPECT_EQ(a.weights, b.weights);
          ASSERT_EQ(a.targets.size(), b.targets.size());
          ASSERT_EQ(a.sources.size(), b.sources.size());
          for (size_t r = 0; r < a.targets.size(); ++r) EXPECT_EQ(a.targets[r], h.inputIndex[b.targets[r]]);
          for (size_t s = 0; s < a.sources.size(); ++s) EXPECT_EQ(a.sources[s], h.inputIndex[b.sources[s]]);
          // Targets are vertices of M^l; a lift's sources too, never its own targets.
          for (uint32_t t : a.targets) EXPECT_LE(h.depth(h.hierarchyIndex[t]), l);
          for (uint32_t s : a.sources) EXPECT_LE(h.depth(h.hierarchyIndex[s]), l);
          a.forward(x.data());
          EXPECT_EQ(x, c.mesh.synthesizeSteps(c.mesh.analyze(c.positions, l - 1, scheme), l, int(k) + 1, scheme))
              << where(c, scheme, l, int(k) + 1);
        }
        if (scheme.kind == SchemeKind::Loop) {
          std::vector<std::string> names;
          for (const auto& s : steps) names.push_back(s.name);
          EXPECT_EQ(names, (std::vector<std::string>{"U", "P_o", "N", "P_e"}));
          EXPECT_TRUE(steps[2].scaling);
        }
      }
}

TEST(LiftingPhases, BadArgumentsAreRefusedWithTheirReason) {
  Case c = std::move(shuffledCases().front());
  const SchemeOptions loop;
  const int n = c.mesh.levels();
  const auto& x = c.positions;
  EXPECT_EQ(messageOf([&] { c.mesh.liftingSteps(0, loop); }),
            "level 0 is out of range for lifting steps: level l builds M^l from M^(l-1), l = 1.." + std::to_string(n));
  EXPECT_NE(messageOf([&] { c.mesh.liftingSteps(n + 1, loop); }).find("level " + std::to_string(n + 1) + " is out of range"),
            std::string::npos);
  EXPECT_NE(messageOf([&] { c.mesh.liftingStepCount(-1, loop); }).find("level -1 is out of range"), std::string::npos);
  EXPECT_EQ(messageOf([&] { c.mesh.synthesizeSteps(x, 1, 5, loop); }),
            "steps 5 is out of range: the loop scheme has 4 lifting steps per level (0..4)");
  EXPECT_EQ(messageOf([&] { c.mesh.analyzeSteps(x, 1, -1, loop); }),
            "steps -1 is out of range: the loop scheme has 4 lifting steps per level (0..4)");
  SchemeOptions linear;
  linear.kind = SchemeKind::Linear;
  EXPECT_EQ(messageOf([&] { c.mesh.synthesizeSteps(x, 1, 3, linear); }),
            "steps 3 is out of range: the linear scheme has 2 lifting steps per level (0..2)");
  std::vector<double> shorter(x.begin(), x.end() - 1);
  EXPECT_EQ(messageOf([&] { c.mesh.synthesizeSteps(shorter, 1, 1, loop); }),
            "expected " + std::to_string(x.size()) + " coefficients, got " + std::to_string(shorter.size()));
  EXPECT_EQ(messageOf([&] { c.mesh.analyzeSteps(shorter, 1, 1, loop); }),
            "expected " + std::to_string(x.size()) + " coefficients, got " + std::to_string(shorter.size()));
  // A mesh that is no subdivision has no steps at all.
  MultiresMesh flat(fixtures::octahedron());
  ASSERT_EQ(flat.levels(), 0);
  EXPECT_EQ(messageOf([&] { flat.liftingSteps(1, loop); }), "this mesh has no subdivision level, so no lifting steps");
  EXPECT_EQ(messageOf([&] { flat.synthesizeSteps(fixtures::octahedron().positions, 1, 0, loop); }),
            "this mesh has no subdivision level, so no lifting steps");
  // After all that, the mesh works.
  EXPECT_EQ(c.mesh.synthesizeSteps(x, 1, 0, loop), x);
}

TEST(LiftingPhases, TransposedStepsAreTheAdjointOfTheLastPhases) {
  // <S(a), b> = <x_k, T_k(b)> with x_k the first S - k phases of a and T_k the transposes of the
  // last k: the outwards application (paper Figure 5) is the adjoint, phase by phase.
  auto dot = [](const std::vector<double>& u, const std::vector<double>& v) {
    double s = 0;
    for (size_t i = 0; i < u.size(); ++i) s += u[i] * v[i];
    return s;
  };
  for (const auto& c : shuffledCases())
    for (const auto& scheme : allSchemes())
      for (int l = 1; l <= c.mesh.levels(); ++l) {
        const int count = c.mesh.liftingStepCount(l, scheme);
        const auto a = c.mesh.analyze(c.positions, l - 1, scheme);
        auto b = fixtures::randomVector(a.size(), 99);
        const double whole = dot(c.mesh.synthesizeSteps(a, l, count, scheme), b);
        for (int k = 0; k <= count; ++k) {
          const double split = dot(c.mesh.synthesizeSteps(a, l, count - k, scheme), c.mesh.transposeSteps(b, l, k, scheme));
          EXPECT_NEAR(split, whole, 1e-11 * (std::fabs(whole) + 1)) << where(c, scheme, l, k);
        }
        EXPECT_EQ(c.mesh.transposeSteps(b, l, 0, scheme), b) << where(c, scheme, l);
      }
  const auto cases = shuffledCases();
  const std::string message = messageOf([&] { cases.front().mesh.transposeSteps({1, 2, 3}, 1, 1, SchemeOptions{}); });
  EXPECT_NE(message.find("covector"), std::string::npos) << message;
}
