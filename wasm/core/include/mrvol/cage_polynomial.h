// The volume as a cubic polynomial of the level-e cage coefficients, the details fixed: the tensor
// path of the editor. Evaluating it costs nothing like a pass over the mesh.
#pragma once
#include <cstdint>
#include <vector>

#include "mrvol/volume_function.h"
#include "mrvol/volume_tensor.h"

namespace mrvol {

// The volume as a cubic polynomial of the cage coefficients c (details fixed), contracted once from
// the cage rows of theta^e:  Theta(c) = constant + sum_i a_i . c_i + sum_{i<j} c_i . (c_j x q_ij)
// + sum_{i<j<k} T_ijk c_i . (c_j x c_k). Evaluating it costs nothing like a pass over the mesh.
struct CagePolynomial {
  uint32_t cageSize = 0;
  double constant = 0;
  std::vector<double> linear;                          // a_i, 3 per cage vertex
  std::vector<uint32_t> pairI, pairJ;                  // cage pairs with a quadratic term
  std::vector<double> pairQ;                           // q_ij, 3 per pair
  std::vector<uint32_t> tripleI, tripleJ, tripleK;     // cage triples, in runs of one (i, j) (any order is
                                                       // correct; runs share their cross products)
  std::vector<double> tripleT;
  // The runs of one (i, j) among the triples, found once by indexRuns() (evaluation then reads only
  // k and T per triple): run r is (runI[r], runJ[r]) over triples [runStart[r], runStart[r + 1]).
  // Without them (or after the triples changed) evaluation finds the runs as it goes.
  std::vector<uint32_t> runStart, runI, runJ;
  void indexRuns();
  double evaluate(const double* cage, double* gradient /* 3 * cageSize or null */) const;
  // The cubic s -> Theta(cage + s direction): its coefficients k[0] + k[1] s + k[2] s^2 + k[3] s^3.
  void alongDirection(const double* cage, const double* direction, double* k) const;
  // With more than one thread and triples enough for the pool, times a solver step's sweeps (value
  // and gradient, then the cubic along the gradient, at `cage`) on the pool and inline, and keeps the
  // faster for every later sweep: a hand-off and the threaded build's slower code can cost more than
  // the split saves. Either way gives the same bits (the blocks stay the same).
  void chooseSweepThreads(const double* cage) const;
  bool sweepsInline() const { return sweepsInline_; }
  void setSweepsInline(bool inlineOnly) const { sweepsInline_ = inlineOnly; }

 private:
  template <class F>
  void forEachRun(F&& f) const;  // f(i, j, first triple, end)
  // The sums w = sum_k T_ijk c_k of each run (3 per run) at the cage they were formed for: a
  // solver step evaluates the value, the gradient and the cubic along a direction at one cage, and
  // the triples' pass over c is then made once (the passes after it read only T and k once more).
  // Valid while runsAtCage_ equals the cage (runs indexed only).
  const double* runSums(const double* cage) const;  // null: not formed for this cage
  void keepRunSums(const double* cage) const;       // marks runSums_ (just filled) as formed for cage
  mutable std::vector<double> runSums_, runsAtCage_;
  mutable bool runSumsValid_ = false;
  // The triples' passes on the thread pool (thread_pool.h), with the same bits on any thread count:
  // the gathers (one sum per run) in blocks of runs; the gradient's scatter into one partial
  // gradient per scatter block, the blocks fixed by the triples (scatterRun_: their first runs, cut
  // by indexRuns at equal triple counts; fewer blocks for a cage large against its triples), the
  // partials added in block order.
  void gatherRuns(const double* v, double* sums) const;  // indexed runs: sums[3 r] = sum_k T c_k of run r
  static constexpr size_t kRunsPerBlock = 2048;
  static constexpr size_t kTriplesPerBlock = size_t(1) << 18;  // a sweep's least work per thread
  static constexpr size_t kMaxScatterBlocks = 8;
  std::vector<uint32_t> scatterRun_;
  std::vector<uint32_t> scatterLow_;   // per scatter block: the least k of its triples
  std::vector<size_t> scatterBase_;    // where its partial (indices 3 low .. 3 cageSize) lies in partials_
  size_t scatterEnd_ = 0;
  mutable std::vector<double> partials_, directionSums_;
  mutable bool sweepsInline_ = false;  // chosen by chooseSweepThreads
};

// Contracts the cage rows of theta^e (Cage storage) with the details of `coefficients` (level-e
// coefficients, hierarchy order, 3 per vertex; the cage part is not read). The constant is left 0:
// the detail-only entries were never formed, so the caller sets it from a known volume.
CagePolynomial contractCageRows(const VolumeTensor& tensor, const double* coefficients);

// The polynomial as a VolumeFunction of the cage coefficients (3 * cageSize doubles).
class CagePolynomialVolume final : public VolumeFunction {
 public:
  explicit CagePolynomialVolume(CagePolynomial polynomial) : polynomial_(std::move(polynomial)) { polynomial_.indexRuns(); }
  const CagePolynomial& polynomial() const { return polynomial_; }
  size_t size() const override { return 3 * size_t(polynomial_.cageSize); }
  double value(const double* cage, double* gradient) const override { return polynomial_.evaluate(cage, gradient); }
  // Always computes all four coefficients (the expansion gives k[0] and k[1] for free).
  void alongDirection(const double* cage, const double* d, double* k, bool = false) const override {
    polynomial_.alongDirection(cage, d, k);
  }

 private:
  CagePolynomial polynomial_;
};

}  // namespace mrvol
