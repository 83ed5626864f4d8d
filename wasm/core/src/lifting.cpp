#include "mrvol/lifting.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <map>
#include <memory>

#include "mrvol/corners.h"
#include "mrvol/error.h"
#include "mrvol/step_builder.h"
#include "mrvol/thread_pool.h"

namespace mrvol {

// ---------------------------------------------------------------------------------------------
// The three loops every scheme runs through.

namespace {

template <int S>
void liftRows(const LiftingStep& st, double* x, double sign) {
  const size_t rows = st.targets.size();
  for (size_t r = 0; r < rows; ++r) {
    double acc[S] = {};
    for (uint32_t k = st.offsets[r]; k < st.offsets[r + 1]; ++k) {
      const double w = st.weights[k];
      const double* p = x + size_t(S) * st.sources[k];
      for (int c = 0; c < S; ++c) acc[c] += w * p[c];
    }
    double* t = x + size_t(S) * st.targets[r];
    for (int c = 0; c < S; ++c) t[c] += sign * acc[c];
  }
}

// x_t = W x_s: a lift whose targets held zeros (the first prediction of a zero-detail synthesis).
void assignRows(const LiftingStep& st, double* x) {
  const size_t rows = st.targets.size();
  for (size_t r = 0; r < rows; ++r) {
    double acc[3] = {};
    for (uint32_t k = st.offsets[r]; k < st.offsets[r + 1]; ++k) {
      const double w = st.weights[k];
      const double* p = x + 3 * size_t(st.sources[k]);
      acc[0] += w * p[0], acc[1] += w * p[1], acc[2] += w * p[2];
    }
    double* t = x + 3 * size_t(st.targets[r]);
    t[0] = acc[0], t[1] = acc[1], t[2] = acc[2];
  }
}

template <int S>
void liftRowsTransposed(const LiftingStep& st, double* x) {
  const size_t rows = st.targets.size();
  for (size_t r = 0; r < rows; ++r) {
    double t[S];
    for (int c = 0; c < S; ++c) t[c] = x[size_t(S) * st.targets[r] + c];
    for (uint32_t k = st.offsets[r]; k < st.offsets[r + 1]; ++k) {
      const double w = st.weights[k];
      double* p = x + size_t(S) * st.sources[k];
      for (int c = 0; c < S; ++c) p[c] += w * t[c];
    }
  }
}

void scaleRows(const LiftingStep& st, double* x, int stride, bool invert) {
  for (size_t r = 0; r < st.targets.size(); ++r) {
    const double f = invert ? 1.0 / st.weights[r] : st.weights[r];
    double* t = x + size_t(stride) * st.targets[r];
    for (int c = 0; c < stride; ++c) t[c] *= f;
  }
}

template <class F>
void byStride(int stride, F&& f) {
  switch (stride) {
    case 1: f(std::integral_constant<int, 1>{}); break;
    case 3: f(std::integral_constant<int, 3>{}); break;
    case 9: f(std::integral_constant<int, 9>{}); break;  // three 3-vectors per vertex (the centre of mass's rows)
    default: throw Error("unsupported stride " + std::to_string(stride));
  }
}

}  // namespace

void LiftingStep::forward(double* x, int stride) const {
  if (scaling) return scaleRows(*this, x, stride, false);
  byStride(stride, [&](auto s) { liftRows<decltype(s)::value>(*this, x, 1.0); });
}

void LiftingStep::inverse(double* x, int stride) const {
  if (scaling) return scaleRows(*this, x, stride, true);
  byStride(stride, [&](auto s) { liftRows<decltype(s)::value>(*this, x, -1.0); });
}

void LiftingStep::transposed(double* x, int stride) const {
  if (scaling) return scaleRows(*this, x, stride, false);
  byStride(stride, [&](auto s) { liftRowsTransposed<decltype(s)::value>(*this, x); });
}

// ---------------------------------------------------------------------------------------------
// Mask weights.

double loopEta(int n) { return 3.0 / 8.0 + std::cos(2.0 * M_PI / n) / 4.0; }
double loopK(int n) { return 8.0 / 5.0 * loopEta(n) * loopEta(n); }
double loopMu(int n) { return (1.0 - loopK(n)) / n; }

const char* schemeName(SchemeKind kind) {
  switch (kind) {
    case SchemeKind::Loop: return "loop";
    case SchemeKind::Butterfly: return "butterfly";
    case SchemeKind::Linear: return "linear";
    case SchemeKind::CatmullClark: return "catmull-clark";
  }
  return "?";
}

SchemeKind parseSchemeName(const std::string& name) {
  if (name == "loop") return SchemeKind::Loop;
  if (name == "butterfly") return SchemeKind::Butterfly;
  if (name == "linear") return SchemeKind::Linear;
  if (name == "catmull-clark") return SchemeKind::CatmullClark;
  throw Error("unknown scheme '" + name + "' (expected loop, butterfly or linear)");
}

// ---------------------------------------------------------------------------------------------
// Building the steps of one level from the hierarchy.

namespace {

// Local connectivity of level l seen from the coarse level l-1.
struct LevelView {
  const Hierarchy& h;
  int l;
  uint32_t evenCount, fineCount;
  VertexCorners coarse, fine;
  std::vector<uint32_t> ring;

  LevelView(const Hierarchy& h, int l)
      : h(h), l(l), evenCount(h.vertexCount[l - 1]), fineCount(h.vertexCount[l]),
        coarse(h.faces[l - 1].data(), h.faces[l - 1].size() / 3, h.vertexCount[l - 1]),
        fine(h.faces[l].data(), h.faces[l].size() / 3, h.vertexCount[l]) {}

  bool isBoundaryOdd(uint32_t e) const { return h.wings[2 * e + 1] == kNone; }
  bool isBoundaryEven(uint32_t v) const { return h.boundary[v] != 0; }
  // E_inc(v): odd vertices on coarse edges at v, counter-clockwise (open ring at a boundary).
  const std::vector<uint32_t>& incident(uint32_t v) {
    fine.ring(v, ring);
    return ring;
  }
  // E_link(v): odd vertices on the link edges of v (one per coarse triangle at v), in linkRing
  // (kept between vertices: no allocation per vertex).
  std::vector<uint32_t> linkRing;
  const std::vector<uint32_t>& link(uint32_t v) {
    linkRing.clear();
    for (uint32_t c = fine.begin(v); c < fine.end(v); ++c) {
      uint32_t m1 = fine.next[c], m2 = fine.prev[c];
      uint32_t x = fine.opposite(m2, m1);  // centre face (m2, m1, x) of the split triangle
      if (x != kNone) linkRing.push_back(x);
    }
    return linkRing;
  }
  // Boundary neighbours of a boundary even vertex at level l-1 (two for a manifold boundary).
  std::vector<uint32_t> boundaryNeighbours(uint32_t v) const {
    std::vector<uint32_t> out;
    for (uint32_t c = coarse.begin(v); c < coarse.end(v); ++c) {
      if (coarse.opposite(coarse.next[c], v) == kNone) out.push_back(coarse.next[c]);
      if (coarse.opposite(v, coarse.prev[c]) == kNone) out.push_back(coarse.prev[c]);
    }
    return out;
  }
  // The odd vertex on the coarse edge (a, b) (a common fine neighbour whose ends are a, b).
  uint32_t oddOn(uint32_t a, uint32_t b) const {
    for (uint32_t c = fine.begin(a); c < fine.end(a); ++c) {
      uint32_t m = fine.next[c];
      if (m >= evenCount && ((h.ends[2 * m] == a && h.ends[2 * m + 1] == b) || (h.ends[2 * m] == b && h.ends[2 * m + 1] == a)))
        return m;
    }
    return kNone;
  }
  int coarseValence(uint32_t v) const {
    // Number of coarse neighbours: corners, plus one for an open (boundary) fan.
    return int(coarse.count(v)) + (isBoundaryEven(v) ? 1 : 0);
  }
};

// The odd vertices of level l around each even vertex, from the odd vertices' ends and wings (no
// corner lists of the fine level): E_inc(v), the odds whose ends hold v (one per coarse edge at v),
// and E_link(v), the odds whose wings hold v (one per coarse triangle at v), each ascending. Rows
// of a lift are sorted by source, so the order within a set does not reach the steps.
struct OddsAround {
  std::vector<uint32_t> incStart, inc, linkStart, link;
  OddsAround(const Hierarchy& h, uint32_t evenCount, uint32_t fineCount) {
    const auto bucket = [&](const std::vector<uint32_t>& of, std::vector<uint32_t>& start, std::vector<uint32_t>& out) {
      start.assign(size_t(evenCount) + 1, 0);
      for (size_t i = 2 * size_t(evenCount); i < 2 * size_t(fineCount); ++i)
        if (of[i] < evenCount) ++start[of[i] + 1];
      for (size_t v = 0; v < evenCount; ++v) start[v + 1] += start[v];
      out.resize(start[evenCount]);
      std::vector<uint32_t> fill(start.begin(), start.end() - 1);
      for (uint32_t e = evenCount; e < fineCount; ++e)
        for (int k = 0; k < 2; ++k)
          if (of[2 * size_t(e) + k] < evenCount) out[fill[of[2 * size_t(e) + k]]++] = e;
    };
    bucket(h.ends, incStart, inc);
    bucket(h.wings, linkStart, link);
  }
};

std::vector<LiftingStep> loopLevel(const Hierarchy& h, int l, const SchemeOptions& o) {
  const uint32_t evenCount = h.vertexCount[l - 1], fineCount = h.vertexCount[l];
  const OddsAround around(h, evenCount, fineCount);
  const auto isBoundaryOdd = [&](uint32_t e) { return h.wings[2 * e + 1] == kNone; };
  // Boundary neighbours of a boundary even vertex at level l-1, from the coarse corners (built only
  // when the mesh has a boundary).
  std::unique_ptr<VertexCorners> coarse;
  const auto boundaryNeighbours = [&](uint32_t v) {
    if (!coarse) coarse = std::make_unique<VertexCorners>(h.faces[l - 1].data(), h.faces[l - 1].size() / 3, evenCount);
    std::vector<uint32_t> out;
    for (uint32_t c = coarse->begin(v); c < coarse->end(v); ++c) {
      if (coarse->opposite(coarse->next[c], v) == kNone) out.push_back(coarse->next[c]);
      if (coarse->opposite(v, coarse->prev[c]) == kNone) out.push_back(coarse->prev[c]);
    }
    return out;
  };
  StepBuilder update, oddPredict, evenPredict;
  std::vector<std::pair<uint32_t, double>> normalize;
  // Room for the triplets at once: about 2 + 2 per corner of an even vertex (its incident and link
  // odds, its P_e), 4 per odd vertex (the boundary's few extra grow the vectors).
  const size_t fineCorners = h.faces[l].size();
  update.triplets.reserve(fineCorners / 2 + evenCount);
  evenPredict.triplets.reserve(fineCorners / 3 + evenCount);
  oddPredict.triplets.reserve(4 * size_t(fineCount - evenCount));
  normalize.reserve(evenCount);
  for (uint32_t v = 0; v < evenCount; ++v) {
    const uint32_t *inc = around.inc.data() + around.incStart[v], *incEnd = around.inc.data() + around.incStart[v + 1];
    const int n = int(incEnd - inc);
    if (h.boundary[v]) {
      // Synthesis of the boundary even rule c = 2 (x - (x_e1 + x_e2) / 4): x = c / 2 + (x_e1 + x_e2) / 4.
      normalize.emplace_back(v, 0.5);
      update.touch(v);
      for (const uint32_t* e = inc; e < incEnd; ++e)
        if (isBoundaryOdd(*e)) evenPredict.add(v, *e, 0.25);
      continue;
    }
    // U: c_v += alpha / n sum_{E_inc} d + beta / n sum_{E_link} d
    for (const uint32_t* e = inc; e < incEnd; ++e) update.add(v, *e, o.alpha / n);
    for (uint32_t k = around.linkStart[v]; k < around.linkStart[v + 1]; ++k) update.add(v, around.link[k], o.beta / n);
    // N: c_v *= K(n);  P_e: x_v = c_v + mu(n) sum_{E_inc} x_e
    normalize.emplace_back(v, loopK(n));
    for (const uint32_t* e = inc; e < incEnd; ++e) evenPredict.add(v, *e, loopMu(n));
  }
  for (uint32_t e = evenCount; e < fineCount; ++e) {
    uint32_t a = h.ends[2 * e], b = h.ends[2 * e + 1];
    if (isBoundaryOdd(e)) {
      // Boundary odd: x_e = d_e + (c_a + c_b) / 2; boundary update on the ends and one beyond each.
      oddPredict.add(e, a, 0.5);
      oddPredict.add(e, b, 0.5);
      update.add(a, e, kLoopBoundaryUpdateEnd);
      update.add(b, e, kLoopBoundaryUpdateEnd);
      for (uint32_t end : {a, b}) {
        uint32_t other = end == a ? b : a;
        for (uint32_t w : boundaryNeighbours(end))
          if (w != other) update.add(w, e, kLoopBoundaryUpdateBeyond);
      }
      continue;
    }
    // P_o: x_e = d_e + 3/8 (c_a + c_b) + 1/8 (c_c + c_d)
    oddPredict.add(e, a, 3.0 / 8.0);
    oddPredict.add(e, b, 3.0 / 8.0);
    oddPredict.add(e, h.wings[2 * e], 1.0 / 8.0);
    oddPredict.add(e, h.wings[2 * e + 1], 1.0 / 8.0);
  }
  std::vector<LiftingStep> steps;  // moved in (a braced list would copy every table)
  steps.reserve(4);
  steps.push_back(update.lift("U"));
  steps.push_back(oddPredict.lift("P_o"));
  steps.push_back(scalingStep("N", std::move(normalize)));
  steps.push_back(evenPredict.lift("P_e"));
  return steps;
}

// Modified Butterfly prediction weights for the odd vertex e (sources in level l-1 numbering).
void butterflyPrediction(LevelView& view, uint32_t e, StepBuilder& predict) {
  const Hierarchy& h = view.h;
  uint32_t a = h.ends[2 * e], b = h.ends[2 * e + 1];
  if (view.isBoundaryOdd(e)) {
    // 4-point rule along the boundary: (-1/16, 9/16, 9/16, -1/16).
    auto beyond = [&](uint32_t end, uint32_t other) {
      for (uint32_t w : view.boundaryNeighbours(end))
        if (w != other) return w;
      return other;
    };
    predict.add(e, a, 9.0 / 16.0);
    predict.add(e, b, 9.0 / 16.0);
    predict.add(e, beyond(a, b), -1.0 / 16.0);
    predict.add(e, beyond(b, a), -1.0 / 16.0);
    return;
  }
  const bool aInterior = !view.isBoundaryEven(a), bInterior = !view.isBoundaryEven(b);
  if (!aInterior && !bInterior) {  // an interior edge between two boundary vertices: midpoint
    predict.add(e, a, 0.5);
    predict.add(e, b, 0.5);
    return;
  }
  // Stencil of an (interior) end using only its 1-ring, ring index 0 at the other end.
  auto ringStencil = [&](uint32_t centre, uint32_t other, double share) {
    std::vector<uint32_t> ring;
    view.coarse.ringFrom(centre, other, ring);
    const int K = int(ring.size());
    predict.add(e, centre, share * 0.75);
    for (int j = 0; j < K; ++j) {
      double s;
      if (K == 3) s = j == 0 ? 5.0 / 12.0 : -1.0 / 12.0;
      else if (K == 4) s = j == 0 ? 3.0 / 8.0 : j == 2 ? -1.0 / 8.0 : 0.0;
      else s = (0.25 + std::cos(2.0 * M_PI * j / K) + 0.5 * std::cos(4.0 * M_PI * j / K)) / K;
      predict.add(e, ring[j], share * s);
    }
  };
  const int va = aInterior ? view.coarseValence(a) : -1, vb = bInterior ? view.coarseValence(b) : -1;
  uint32_t c = h.wings[2 * e], d = h.wings[2 * e + 1];
  if (va == 6 && vb == 6) {
    // Ten-point stencil; the four vertices across the wing edges must exist.
    // Wing c closes face (a, b, c), wing d face (b, a, d); across their outer edges:
    uint32_t across[4] = {view.coarse.opposite(a, c), view.coarse.opposite(c, b), view.coarse.opposite(d, a),
                          view.coarse.opposite(b, d)};
    if (std::find(std::begin(across), std::end(across), kNone) == std::end(across)) {
      predict.add(e, a, 0.5);
      predict.add(e, b, 0.5);
      predict.add(e, c, 1.0 / 8.0);
      predict.add(e, d, 1.0 / 8.0);
      for (uint32_t x : across) predict.add(e, x, -1.0 / 16.0);
      return;
    }
  }
  // Extraordinary ends (or a regular end whose stencil meets the boundary): the interior ends'
  // 1-ring stencils, averaged when there are two.
  const bool useA = aInterior && (va != 6 || vb == 6 || !bInterior);
  const bool useB = bInterior && (vb != 6 || va == 6 || !aInterior);
  const double share = useA && useB ? 0.5 : 1.0;
  if (useA) ringStencil(a, b, share);
  if (useB) ringStencil(b, a, share);
}

// Interpolating schemes (Butterfly, linear): U with weights -s_{k,m} = -I_m / (2 I_k) for
// Butterfly, -3 / (4 n_k) for linear; then P.
std::vector<std::vector<LiftingStep>> interpolatingLevels(const Hierarchy& h, SchemeKind kind) {
  const int n = h.levels;
  std::vector<StepBuilder> predicts(n + 1);
  for (int l = 1; l <= n; ++l) {
    LevelView view(h, l);
    for (uint32_t e = view.evenCount; e < view.fineCount; ++e) {
      if (kind == SchemeKind::Butterfly) butterflyPrediction(view, e, predicts[l]);
      else predicts[l].add(e, h.ends[2 * e], 0.5), predicts[l].add(e, h.ends[2 * e + 1], 0.5);
    }
  }
  std::vector<std::vector<LiftingStep>> levels(n);
  for (int l = 1; l <= n; ++l) levels[l - 1].resize(2);
  if (kind == SchemeKind::Butterfly) {
    // Geometry-independent integrals: I = 1 at the finest level, I^{l-1}_k = I^l_k + sum_m p_mk I^l_m.
    std::vector<double> integral(h.fineVertexCount(), 1.0);
    for (int l = n; l >= 1; --l) {
      std::vector<double> coarse(integral.begin(), integral.begin() + h.vertexCount[l - 1]);
      predicts[l].forEach([&](uint32_t m, uint32_t k, double p) { coarse[k] += p * integral[m]; });
      StepBuilder update;
      for (uint32_t m = h.vertexCount[l - 1]; m < h.vertexCount[l]; ++m)
        for (int j = 0; j < 2; ++j) {
          uint32_t k = h.ends[2 * m + j];
          update.add(k, m, -integral[m] / (2.0 * coarse[k]));
        }
      levels[l - 1][0] = update.lift("U");
      integral = std::move(coarse);
    }
  } else {
    for (int l = 1; l <= n; ++l) {
      StepBuilder update;
      LevelView view(h, l);
      for (uint32_t v = 0; v < view.evenCount; ++v) {
        const std::vector<uint32_t>& inc = view.incident(v);
        for (uint32_t m : inc) update.add(v, m, -3.0 / (4.0 * inc.size()));
      }
      levels[l - 1][0] = update.lift("U");
    }
  }
  for (int l = 1; l <= n; ++l) levels[l - 1][1] = predicts[l].lift("P");
  return levels;
}

}  // namespace

WaveletTransform::WaveletTransform(const Hierarchy& hierarchy, const SchemeOptions& options)
    : hierarchy_(&hierarchy), options_(options) {
  if (!std::isfinite(options.alpha) || !std::isfinite(options.beta))
    throw Error("Loop update weights alpha and beta must be finite numbers");
  if (options.kind == SchemeKind::CatmullClark)
    throw Error("the catmull-clark scheme works on quad meshes; this mesh is made of triangles");
  if (options.kind == SchemeKind::Loop) {
    // Levels are independent: on the pool's threads, the finest (most of the work) first so that
    // it has a block of its own; an error is the coarsest failing level's, as in a loop.
    const int levels = hierarchy.levels;
    steps_.resize(size_t(levels));
    std::vector<std::exception_ptr> errors(static_cast<size_t>(levels));
    parallelFor(0, size_t(levels), 1, [&](size_t first, size_t end) {
      for (size_t task = first; task < end; ++task) {
        const int l = task == 0 ? levels : int(task);
        try {
          steps_[size_t(l - 1)] = loopLevel(hierarchy, l, options);
        } catch (...) {
          errors[size_t(l - 1)] = std::current_exception();
        }
      }
    });
    for (const auto& e : errors)
      if (e) std::rethrow_exception(e);
  } else {
    steps_ = interpolatingLevels(hierarchy, options.kind);
  }
  prepare();
}

WaveletTransform::WaveletTransform(const Hierarchy& hierarchy, const SchemeOptions& options,
                                   std::vector<std::vector<LiftingStep>> steps)
    : hierarchy_(&hierarchy), options_(options), steps_(std::move(steps)) {
  if (int(steps_.size()) != hierarchy.levels)
    throw Error("a transform needs the steps of " + std::to_string(hierarchy.levels) + " levels, got " +
                std::to_string(steps_.size()));
  prepare();
}

void WaveletTransform::prepare() {
  const Hierarchy& hierarchy = *hierarchy_;
  for (int l = 1; l <= hierarchy.levels; ++l) {
    const uint32_t evens = hierarchy.vertexCount[l - 1];
    bool oddWritten = false;
    for (auto& step : steps_[l - 1]) {
      step.readsOnlyDetails = !step.scaling && !oddWritten &&
                              std::all_of(step.sources.begin(), step.sources.end(), [&](uint32_t s) { return s >= evens; });
      oddWritten = oddWritten || std::any_of(step.targets.begin(), step.targets.end(), [&](uint32_t t) { return t >= evens; });
    }
    // The first step a zero-detail synthesis runs can assign instead of add when it is a lift that
    // writes every vertex born at level l from older ones: the details then need no zeroing.
    const uint32_t odds = hierarchy.vertexCount[l] - evens;
    int assign = -1;
    const auto& steps = steps_[l - 1];
    for (size_t k = 0; k < steps.size(); ++k) {
      if (steps[k].readsOnlyDetails) continue;
      const auto& st = steps[k];
      std::vector<uint8_t> seen(odds, 0);
      bool ok = !st.scaling && st.targets.size() == odds &&
                std::all_of(st.sources.begin(), st.sources.end(), [&](uint32_t s) { return s < evens; });
      for (size_t r = 0; ok && r < st.targets.size(); ++r) {
        const uint32_t t = st.targets[r];
        ok = t >= evens && t - evens < odds && !seen[t - evens];
        if (ok) seen[t - evens] = 1;
      }
      if (ok) assign = int(k);
      break;
    }
    zeroDetailAssign_.push_back(assign);
  }
}

void WaveletTransform::synthesizeZeroDetails(double* x, int fromLevel) const {
  if (fromLevel < 0 || fromLevel > levels())
    throw Error("level " + std::to_string(fromLevel) + " is out of range 0.." + std::to_string(levels()));
  const auto& count = hierarchy_->vertexCount;
  for (int l = fromLevel + 1; l <= levels(); ++l) {
    const auto& steps = steps_[l - 1];
    const int assign = zeroDetailAssign_[l - 1];
    if (assign < 0) std::fill(x + 3 * size_t(count[l - 1]), x + 3 * size_t(count[l]), 0.0);
    for (size_t k = 0; k < steps.size(); ++k) {
      if (int(k) == assign) assignRows(steps[k], x);
      else if (!steps[k].readsOnlyDetails) steps[k].forward(x);
    }
  }
}

void WaveletTransform::analyze(double* x, int toLevel) const {
  if (toLevel < 0 || toLevel > levels())
    throw Error("level " + std::to_string(toLevel) + " is out of range 0.." + std::to_string(levels()));
  for (int l = levels(); l > toLevel; --l) {
    const auto& steps = steps_[l - 1];
    for (auto it = steps.rbegin(); it != steps.rend(); ++it) it->inverse(x);
  }
}

void WaveletTransform::synthesize(double* x, int fromLevel) const {
  if (fromLevel < 0 || fromLevel > levels())
    throw Error("level " + std::to_string(fromLevel) + " is out of range 0.." + std::to_string(levels()));
  for (int l = fromLevel + 1; l <= levels(); ++l)
    for (const auto& step : steps_[l - 1]) step.forward(x);
}

void WaveletTransform::synthesisAdjoint(double* g, int toLevel, int stride, bool details) const {
  if (toLevel < 0 || toLevel > levels())
    throw Error("level " + std::to_string(toLevel) + " is out of range 0.." + std::to_string(levels()));
  for (int l = levels(); l > toLevel; --l) {
    const auto& steps = steps_[l - 1];
    for (auto it = steps.rbegin(); it != steps.rend(); ++it)
      if (details || !it->readsOnlyDetails) it->transposed(g, stride);
  }
}

}  // namespace mrvol
