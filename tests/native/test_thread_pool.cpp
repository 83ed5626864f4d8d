// The thread pool (thread_pool.h): every index of a parallelFor runs once, in blocks that do not
// depend on timing; errors come back to the caller; nested loops run inline. And the passes that
// use it (the renderer's buffers) give the same bits on 1, 2 and 3 threads.
#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <string>
#include <vector>

#include "shuffled_subdivision.h"
#include "mrvol/cage_polynomial.h"
#include "mrvol/cage_polynomial_builder.h"
#include "mrvol/hierarchy.h"
#include "mrvol/lifting.h"
#include "mrvol/surface_buffers.h"
#include "mrvol/thread_pool.h"
#include "mrvol/volume_editor.h"

using namespace mrvol;

namespace {

// Restores one thread and no grain cap when a test ends, whatever happens in it.
struct Threads {
  explicit Threads(unsigned count, size_t grainCap = 0) {
    setThreadCount(count);
    setGrainCap(grainCap);
  }
  ~Threads() {
    setGrainCap(0);
    setThreadCount(1);
  }
};

}  // namespace

TEST(ThreadPool, RunsEveryIndexOnceInContiguousBlocks) {
  for (unsigned threads : {1u, 2u, 3u, 5u}) {
    Threads t(threads);
    EXPECT_EQ(threadCount(), threads);
    for (size_t n : {size_t(0), size_t(1), size_t(7), size_t(1000), size_t(100003)})
      for (size_t grain : {size_t(1), size_t(64), size_t(50000)}) {
        std::vector<std::atomic<int>> hits(n);
        std::atomic<int> blocks{0};
        parallelFor(3, 3 + n, grain, [&](size_t first, size_t end) {
          ASSERT_LE(3u, first);
          ASSERT_LE(end, 3 + n);
          ASSERT_LT(first, end);
          ++blocks;
          for (size_t i = first; i < end; ++i) ++hits[i - 3];
        });
        for (size_t i = 0; i < n; ++i) ASSERT_EQ(hits[i].load(), 1) << threads << " threads, n " << n << ", index " << i;
        const size_t most = std::max<size_t>(1, std::min<size_t>(threads, n / grain));
        if (n > 0) EXPECT_EQ(size_t(blocks.load()), most) << threads << " threads, n " << n << ", grain " << grain;
      }
  }
}

TEST(ThreadPool, ErrorsReachTheCallerAndNestedLoopsRunInline) {
  Threads t(3);
  EXPECT_THROW(parallelFor(0, 300, 1, [](size_t first, size_t) {
                 if (first > 0) throw std::runtime_error("block failed");
               }),
               std::runtime_error);
  // The pool still works after an error, and a loop inside a loop is one block.
  std::atomic<int> inner{0};
  std::atomic<size_t> sum{0};
  parallelFor(0, 300, 1, [&](size_t first, size_t end) {
    parallelFor(first, end, 1, [&](size_t a, size_t b) {
      ++inner;
      for (size_t i = a; i < b; ++i) sum += i;
    });
  });
  EXPECT_EQ(inner.load(), 3);
  EXPECT_EQ(sum.load(), size_t(299 * 300 / 2));
  EXPECT_EQ(setThreadCount(0), 1u);
  EXPECT_EQ(setThreadCount(1000), kMaxThreads);
}

// Drags a shuffled subdivided mesh at the coarsest level (a cage basis table) and at the finest (the
// fine positions) and keeps every buffer the renderer reads after each step.
std::vector<std::vector<float>> dragBuffers(unsigned threads) {
  Threads t(threads, 97);  // small blocks: this mesh has a few thousand vertices
  const fixtures::Shuffled shuffled = fixtures::shuffledSubdivision(11);
  const Hierarchy h = Hierarchy::detect(shuffled.mesh);
  std::vector<std::vector<float>> out;
  for (int level : {0, h.levels - 1}) {
    WaveletTransform wt(h, SchemeOptions{});
    VolumeEditor editor(h, wt, level, shuffled.mesh.positions.data());
    editor.usePolynomial();
    SurfaceBuffers buffers(h);
    std::vector<uint8_t> held(editor.cageSize(), 0);
    for (int drag = 0; drag < 6; ++drag) {
      std::vector<double> target = editor.cagePositions();
      const uint32_t c = uint32_t(drag * 5 + 1) % editor.cageSize();
      target[3 * c] += 0.04, target[3 * c + 1] -= 0.02;
      std::fill(held.begin(), held.end(), 0), held[c] = 1;
      EditOptions options;
      options.preserve = true;
      editor.deformCage(target, held, options);
      if (level == 0) {
        buffers.update(editor, true);
      } else {
        FinePositions::Changes changes;
        editor.takeFinePositionChanges(changes);
        buffers.update(editor.finePositions().data(), editor.referencePoint(), editor.finePositionsVersion(), changes, true);
      }
      const size_t n = 3 * buffers.vertexCount();
      out.emplace_back(buffers.positions(), buffers.positions() + n);
      out.emplace_back(buffers.normals(), buffers.normals() + n);
    }
  }
  return out;
}

TEST(ThreadPool, SurfaceBuffersAreTheSameOnAnyThreadCount) {
  const std::vector<std::vector<float>> one = dragBuffers(1);
  ASSERT_FALSE(one.empty());
  for (unsigned threads : {2u, 3u}) {
    const std::vector<std::vector<float>> many = dragBuffers(threads);
    ASSERT_EQ(many.size(), one.size());
    for (size_t k = 0; k < one.size(); ++k) EXPECT_EQ(many[k], one[k]) << threads << " threads, buffer " << k;
  }
}

// The editor's set-up on the pool: the Loop transform's levels, the cage basis columns and the
// polynomial's regions give the same steps and the same polynomial, bit for bit, on any thread count.
TEST(ThreadPool, EditorSetUpIsTheSameOnAnyThreadCount) {
  const fixtures::Shuffled shuffled = fixtures::shuffledSubdivision(11);
  const Hierarchy h = Hierarchy::detect(shuffled.mesh);
  auto setUp = [&](unsigned threads, int level) {
    Threads t(threads, 7);
    WaveletTransform wt(h, SchemeOptions{});
    std::vector<double> x = shuffled.mesh.positions;
    std::vector<double> coefficients(x.size());
    h.toHierarchyOrder(x.data(), coefficients.data());
    wt.analyze(coefficients.data(), level);
    CagePolynomialBuilder builder(wt, level);
    std::vector<std::vector<double>> steps;
    for (int l = 1; l <= h.levels; ++l)
      for (const LiftingStep& s : wt.synthesisSteps(l)) {
        steps.push_back(s.weights);
        steps.emplace_back(s.sources.begin(), s.sources.end());
      }
    const CagePolynomial p = builder.build(coefficients.data());
    steps.push_back(p.linear), steps.push_back(p.pairQ), steps.push_back(p.tripleT), steps.push_back({p.constant});
    steps.emplace_back(p.tripleK.begin(), p.tripleK.end());
    return steps;
  };
  for (int level : {0, 1, h.levels - 2}) {
    const auto one = setUp(1, level);
    for (unsigned threads : {2u, 3u}) {
      const auto many = setUp(threads, level);
      ASSERT_EQ(many.size(), one.size());
      for (size_t k = 0; k < one.size(); ++k) EXPECT_EQ(many[k], one[k]) << threads << " threads, level " << level << ", array " << k;
    }
  }
}

// A polynomial with triples enough for the pool (2^19 and more): its value, gradient and cubic along
// a direction have the same bits on one thread, on two with the sweeps on the pool or inline, and on two after
// chooseSweepThreads kept whichever was faster.
TEST(ThreadPool, PolynomialSweepsAreTheSameWhicheverWayTheyRun) {
  CagePolynomial p;
  p.cageSize = 3000;
  uint64_t state = 12345;
  auto next = [&] { return state = state * 6364136223846793005ull + 1442695040888963407ull, state >> 33; };
  auto unit = [&] { return double(next() % 2000001) / 1e6 - 1.0; };
  p.linear.resize(3 * size_t(p.cageSize));
  for (double& a : p.linear) a = unit();
  for (uint32_t i = 0; p.tripleT.size() < 600000; i = (i + 1) % (p.cageSize - 2))
    for (uint32_t j = i + 1, n = 0; n < 3 && j < p.cageSize - 1; ++n, j += 1 + uint32_t(next() % 5))
      for (uint32_t run = 12 + uint32_t(next() % 40), t = 0; t < run; ++t) {
        p.tripleI.push_back(i), p.tripleJ.push_back(j);
        p.tripleK.push_back(j + 1 + uint32_t(next() % (p.cageSize - j - 1)));
        p.tripleT.push_back(unit());
      }
  p.indexRuns();
  std::vector<double> cage(3 * size_t(p.cageSize)), direction(cage.size());
  for (double& c : cage) c = unit();
  for (double& d : direction) d = unit();
  auto step = [&](const CagePolynomial& q) {
    std::vector<double> out(cage.size() + 5);
    out[0] = q.evaluate(cage.data(), out.data() + 5);
    q.alongDirection(cage.data(), direction.data(), out.data() + 1);
    return out;
  };
  const std::vector<double> one = step(p);
  Threads two(2);
  const CagePolynomial onPool = p;
  EXPECT_EQ(step(onPool), one);
  const CagePolynomial chosen = p;
  chosen.chooseSweepThreads(cage.data());
  EXPECT_EQ(step(chosen), one);
  CagePolynomial inlineOnly = p;
  inlineOnly.setSweepsInline(true);
  EXPECT_EQ(step(inlineOnly), one);
}
