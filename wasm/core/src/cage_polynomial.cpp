#include "mrvol/cage_polynomial.h"

#include <algorithm>
#include <chrono>

#include "mrvol/thread_pool.h"
#include "mrvol/vector3.h"

#ifdef __wasm_simd128__
#include <wasm_simd128.h>
#endif

namespace mrvol {

namespace {
// The triples' inner loops: w += sum over [p, end) of T_q v_{k_q} (a gather), and v_{k_q} += T_q t
// (a scatter). With SIMD x and y go in one register (each lane multiplies and adds as the scalar
// code does: the same results to the bit).
inline void gatherRun(const double* tt, const uint32_t* tk, size_t p, size_t end, const double* v, double* w) {
#ifdef __wasm_simd128__
  v128_t xy = wasm_f64x2_make(w[0], w[1]);
  double z = w[2];
  for (size_t q = p; q < end; ++q) {
    const double* vk = v + 3 * size_t(tk[q]);
    xy = wasm_f64x2_add(xy, wasm_f64x2_mul(wasm_f64x2_splat(tt[q]), wasm_v128_load(vk)));
    z += tt[q] * vk[2];
  }
  w[0] = wasm_f64x2_extract_lane(xy, 0), w[1] = wasm_f64x2_extract_lane(xy, 1), w[2] = z;
#else
  for (size_t q = p; q < end; ++q) axpy(tt[q], v + 3 * size_t(tk[q]), w);
#endif
}
inline void scatterRun(const double* tt, const uint32_t* tk, size_t p, size_t end, const double* t, double* v) {
#ifdef __wasm_simd128__
  const v128_t xy = wasm_v128_load(t);
  for (size_t q = p; q < end; ++q) {
    double* vk = v + 3 * size_t(tk[q]);
    wasm_v128_store(vk, wasm_f64x2_add(wasm_v128_load(vk), wasm_f64x2_mul(wasm_f64x2_splat(tt[q]), xy)));
    vk[2] += tt[q] * t[2];
  }
#else
  for (size_t q = p; q < end; ++q) axpy(tt[q], t, v + 3 * size_t(tk[q]));
#endif
}
}  // namespace

void CagePolynomial::indexRuns() {
  runStart.clear(), runI.clear(), runJ.clear();
  runSumsValid_ = false;
  for (size_t p = 0; p < tripleT.size(); ++p)
    if (p == 0 || tripleI[p] != tripleI[p - 1] || tripleJ[p] != tripleJ[p - 1])
      runStart.push_back(uint32_t(p)), runI.push_back(tripleI[p]), runJ.push_back(tripleJ[p]);
  runStart.push_back(uint32_t(tripleT.size()));
  // Scatter blocks: at most kMaxScatterBlocks, each of at least 8 partial gradients' worth of
  // triples (zeroing and adding a partial stays small against its scatter).
  const size_t triples = tripleT.size(), runs = runI.size();
  const size_t blocks = std::clamp<size_t>(triples / std::max<size_t>(1, 8 * 3 * size_t(cageSize)), 1, kMaxScatterBlocks);
  scatterRun_.assign(1, 0);
  for (size_t b = 1, r = 0; b < blocks; ++b) {
    const size_t cut = triples * b / blocks;
    while (r < runs && runStart[r] < cut) ++r;
    scatterRun_.push_back(uint32_t(r));
  }
  scatterRun_.push_back(uint32_t(runs));
  // Each block's partial gradient covers only its triples' k (from the least one on): block b's
  // entries [3 low, 3 cageSize) live at partials_[scatterBase_[b] + 3 low ...], after block b - 1's.
  scatterLow_.clear(), scatterBase_.clear();
  size_t end = 0;
  for (size_t b = 0; b + 1 < scatterRun_.size(); ++b) {
    uint32_t low = cageSize;
    for (size_t p = runStart[scatterRun_[b]]; p < runStart[scatterRun_[b + 1]]; ++p) low = std::min(low, tripleK[p]);
    low = std::min(low, cageSize);
    const size_t base = b == 0 ? 0 : end - 3 * size_t(low);  // end >= 3 cageSize from block 0 on
    scatterLow_.push_back(low), scatterBase_.push_back(base);
    end = base + 3 * size_t(cageSize);
  }
  scatterEnd_ = end;
}

void CagePolynomial::gatherRuns(const double* v, double* sums) const {
  const uint32_t* tk = tripleK.data();
  const double* tt = tripleT.data();
  const uint32_t* start = runStart.data();
  // Blocks of at least kTriplesPerBlock triples: a smaller sweep runs inline (a hand-off to the
  // pool costs more than it saves on it).
  const size_t runs = runI.size(), triples = tripleT.size();
  const size_t grain = sweepsInline_ ? std::max<size_t>(runs, 1)
                                     : std::max<size_t>(kRunsPerBlock, triples > 0 ? runs * kTriplesPerBlock / triples : runs);
  parallelFor(0, runs, grain, [&](size_t first, size_t end) {
    for (size_t r = first; r < end; ++r) {
      double* w = sums + 3 * r;
      w[0] = w[1] = w[2] = 0;
      gatherRun(tt, tk, start[r], start[r + 1], v, w);
    }
  });
}

template <class F>
void CagePolynomial::forEachRun(F&& f) const {
  if (!runI.empty() && runStart.size() == runI.size() + 1 && runStart.back() == tripleT.size()) {
    for (size_t r = 0; r < runI.size(); ++r) f(runI[r], runJ[r], size_t(runStart[r]), size_t(runStart[r + 1]));
    return;
  }
  for (size_t p = 0; p < tripleT.size();) {
    const uint32_t i = tripleI[p], j = tripleJ[p];
    size_t end = p + 1;
    while (end < tripleT.size() && tripleI[end] == i && tripleJ[end] == j) ++end;
    f(i, j, p, end);
    p = end;
  }
}

const double* CagePolynomial::runSums(const double* cage) const {
  if (!runSumsValid_ || runsAtCage_.size() != 3 * size_t(cageSize) || runSums_.size() != 3 * runI.size()) return nullptr;
  return std::equal(runsAtCage_.begin(), runsAtCage_.end(), cage) ? runSums_.data() : nullptr;
}

void CagePolynomial::keepRunSums(const double* cage) const {
  runsAtCage_.assign(cage, cage + 3 * size_t(cageSize));
  runSumsValid_ = true;
}

double CagePolynomial::evaluate(const double* c, double* g) const {
  double v = constant;
  if (g) std::fill(g, g + 3 * size_t(cageSize), 0.0);
  for (uint32_t i = 0; i < cageSize; ++i) {
    v += dot(&linear[3 * i], c + 3 * i);
    if (g) axpy(1.0, &linear[3 * i], g + 3 * i);
  }
  double t[3];
  for (size_t p = 0; p < pairI.size(); ++p) {
    const double *ci = c + 3 * pairI[p], *cj = c + 3 * pairJ[p], *q = &pairQ[3 * p];
    cross(cj, q, t);
    v += dot(ci, t);
    if (g) {
      axpy(1.0, t, g + 3 * pairI[p]);
      cross(q, ci, t);
      axpy(1.0, t, g + 3 * pairJ[p]);
    }
  }
  // Triples in runs of one (i, j): sum_k T_ijk c_i . (c_j x c_k) = c_i . (c_j x w), w = sum_k T_ijk c_k,
  // and the gradient at k is T_ijk (c_i x c_j): per triple two vector updates, per run the crosses.
  const uint32_t* tk = tripleK.data();
  const double* tt = tripleT.data();
  const bool indexed = runStart.size() == runI.size() + 1 && !runI.empty() && runStart.back() == tripleT.size();
  if (indexed && scatterRun_.size() >= 2 && scatterRun_.back() == runI.size()) {
    // The runs' sums (gathered on the pool's threads unless formed at this cage), then the value and
    // the runs' crosses in run order, then the gradient's scatter in fixed blocks.
    const double* sums = runSums(c);
    if (!sums) {
      runSums_.resize(3 * runI.size());
      gatherRuns(c, runSums_.data());
      keepRunSums(c);
      sums = runSums_.data();
    }
    for (size_t r = 0; r < runI.size(); ++r) {
      const double *ci = c + 3 * runI[r], *cj = c + 3 * runJ[r], *w = sums + 3 * r;
      cross(cj, w, t);
      v += dot(ci, t);
      if (g) {
        axpy(1.0, t, g + 3 * runI[r]);
        cross(w, ci, t);
        axpy(1.0, t, g + 3 * runJ[r]);
      }
    }
    if (!g) return v;
    const size_t blocks = scatterRun_.size() - 1, m3 = 3 * size_t(cageSize);
    partials_.resize(scatterEnd_);
    // On the pool's threads only when each gets kTriplesPerBlock triples (the blocks stay the same:
    // the same bits either way).
    const size_t grain =
        sweepsInline_ ? blocks : std::max<size_t>(1, blocks * kTriplesPerBlock / std::max<size_t>(1, tripleT.size()));
    parallelFor(0, blocks, grain, [&](size_t first, size_t end) {
      for (size_t b = first; b < end; ++b) {
        double* partial = partials_.data() + scatterBase_[b];
        std::fill(partial + 3 * size_t(scatterLow_[b]), partial + m3, 0.0);
        for (size_t r = scatterRun_[b]; r < scatterRun_[b + 1]; ++r) {
          double u[3];
          cross(c + 3 * runI[r], c + 3 * runJ[r], u);
          scatterRun(tt, tk, runStart[r], runStart[r + 1], u, partial);
        }
      }
    });
    for (size_t b = 0; b < blocks; ++b) {
      const double* partial = partials_.data() + scatterBase_[b];
      for (size_t i = 3 * size_t(scatterLow_[b]); i < m3; ++i) g[i] += partial[i];
    }
    return v;
  }
  const double* sums = indexed ? runSums(c) : nullptr;
  double* fill = nullptr;
  if (indexed && !sums) runSums_.resize(3 * runI.size()), fill = runSums_.data();
  size_t run = 0;
  forEachRun([&](uint32_t i, uint32_t j, size_t p, size_t end) {
    double w[3] = {0, 0, 0};
    if (sums) {
      std::copy(sums + 3 * run, sums + 3 * run + 3, w);
    } else {
      gatherRun(tt, tk, p, end, c, w);
      if (fill) std::copy(w, w + 3, fill + 3 * run);
    }
    ++run;
    const double *ci = c + 3 * i, *cj = c + 3 * j;
    cross(cj, w, t);
    v += dot(ci, t);
    if (g) {
      axpy(1.0, t, g + 3 * i);
      cross(w, ci, t);
      axpy(1.0, t, g + 3 * j);
      cross(ci, cj, t);
      scatterRun(tt, tk, p, end, t, g);
    }
  });
  if (fill) keepRunSums(c);
  return v;
}

// One run's part of the cubic along g: (c_i + s g_i) . ((c_j + s g_j) x (wc + s wg)), its coefficients added to k.
static inline void addRunCubic(const double* ci, const double* cj, const double* gi, const double* gj,
                               const double* wc, const double* wg, double* k) {
  double t[3];
  cross(cj, wc, t);
  k[0] += dot(ci, t), k[1] += dot(gi, t);
  cross(gj, wc, t);
  k[1] += dot(ci, t), k[2] += dot(gi, t);
  cross(cj, wg, t);
  k[1] += dot(ci, t), k[2] += dot(gi, t);
  cross(gj, wg, t);
  k[2] += dot(ci, t), k[3] += dot(gi, t);
}

void CagePolynomial::alongDirection(const double* c, const double* g, double* k) const {
  // Expands Theta(c + s g) term by term: (c_i + s g_i) . ((c_j + s g_j) x (c_k + s g_k)).
  k[0] = constant, k[1] = k[2] = k[3] = 0;
  for (uint32_t i = 0; i < cageSize; ++i) k[0] += dot(&linear[3 * i], c + 3 * i), k[1] += dot(&linear[3 * i], g + 3 * i);
  double t[3];
  for (size_t p = 0; p < pairI.size(); ++p) {
    const double *ci = c + 3 * pairI[p], *cj = c + 3 * pairJ[p], *gi = g + 3 * pairI[p], *gj = g + 3 * pairJ[p], *q = &pairQ[3 * p];
    cross(cj, q, t);
    k[0] += dot(ci, t), k[1] += dot(gi, t);
    cross(gj, q, t);
    k[1] += dot(ci, t), k[2] += dot(gi, t);
  }
  // Triples by runs of one (i, j) as in evaluate: (c_i + s g_i) . ((c_j + s g_j) x (wc + s wg)).
  const uint32_t* tk = tripleK.data();
  const double* tt = tripleT.data();
  const double* sums = runSums(c);  // the runs' sums over c when the value was taken at c
  const bool indexed = runStart.size() == runI.size() + 1 && !runI.empty() && runStart.back() == tripleT.size();
  if (indexed) {
    // The runs' sums over g (and over c unless formed) on the pool's threads, then the terms in run order.
    const size_t runs = runI.size();
    directionSums_.resize(3 * runs * (sums ? 1 : 2));
    gatherRuns(g, directionSums_.data());
    if (!sums) gatherRuns(c, directionSums_.data() + 3 * runs);
    const double* cSums = sums ? sums : directionSums_.data() + 3 * runs;
    for (size_t r = 0; r < runs; ++r) {
      const double *wc = cSums + 3 * r, *wg = directionSums_.data() + 3 * r;
      const double *ci = c + 3 * runI[r], *cj = c + 3 * runJ[r], *gi = g + 3 * runI[r], *gj = g + 3 * runJ[r];
      addRunCubic(ci, cj, gi, gj, wc, wg, k);
    }
    return;
  }
  size_t run = 0;
  forEachRun([&](uint32_t i, uint32_t j, size_t p, size_t end) {
    double wc[3] = {0, 0, 0}, wg[3] = {0, 0, 0};
    if (sums) {
      std::copy(sums + 3 * run, sums + 3 * run + 3, wc);
      gatherRun(tt, tk, p, end, g, wg);
    } else {
      gatherRun(tt, tk, p, end, c, wc), gatherRun(tt, tk, p, end, g, wg);
    }
    ++run;
    const double *ci = c + 3 * i, *cj = c + 3 * j, *gi = g + 3 * i, *gj = g + 3 * j;
    addRunCubic(ci, cj, gi, gj, wc, wg, k);
  });
}

void CagePolynomial::chooseSweepThreads(const double* cage) const {
  sweepsInline_ = false;
  const bool indexed = runStart.size() == runI.size() + 1 && !runI.empty() && runStart.back() == tripleT.size();
  if (threadCount() <= 1 || !indexed || tripleT.size() < 2 * kTriplesPerBlock) return;  // inline anyway
  std::vector<double> gradient(3 * size_t(cageSize));
  double k[4];
  auto timedStep = [&](bool inlineSweeps) {
    sweepsInline_ = inlineSweeps;
    runSumsValid_ = false;  // the step's three sweeps: gather at the cage, scatter, gather along
    const auto start = std::chrono::steady_clock::now();
    evaluate(cage, gradient.data());
    alongDirection(cage, gradient.data(), k);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  // The least of three each, interleaved (another process's turn spoils one, not a whole side).
  double onPool = 1e300, inlineOnly = 1e300;
  for (int round = 0; round < 3; ++round) {
    onPool = std::min(onPool, timedStep(false));
    inlineOnly = std::min(inlineOnly, timedStep(true));
  }
  sweepsInline_ = inlineOnly <= onPool;
  runSumsValid_ = false;
}

CagePolynomial contractCageRows(const VolumeTensor& tensor, const double* x) {
  CagePolynomial poly;
  const uint32_t cageSize = tensor.rowCount;
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
        } else {  // k is a detail
          axpy(tensor.values[t], x + 3 * size_t(k), q);
        }
      }
      if (j >= cageSize) {  // a_i += p_j x q
        double t[3];
        cross(x + 3 * size_t(j), q, t);
        axpy(1.0, t, &poly.linear[3 * i]);
      } else if (q[0] != 0 || q[1] != 0 || q[2] != 0) {
        poly.pairI.push_back(i), poly.pairJ.push_back(j);
        poly.pairQ.insert(poly.pairQ.end(), q, q + 3);
      }
    }
  return poly;
}

}  // namespace mrvol
