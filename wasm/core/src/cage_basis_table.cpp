#include "mrvol/cage_basis_table.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "mrvol/thread_pool.h"

#ifdef __wasm_simd128__
#include <wasm_simd128.h>
#endif

namespace mrvol {

CageBasisTable::CageBasisTable(const WaveletTransform& transform, int level, const uint32_t* caller) {
  const Hierarchy& hierarchy = transform.hierarchy();
  if (level < 0 || level >= hierarchy.levels) return;
  const uint32_t cage = hierarchy.vertexCount[level];
  const size_t n = hierarchy.fineVertexCount();
  if (cage > kMaxCage) return;
  const size_t limit = kMaxEntriesPerVertex * n;
  // The zero-detail synthesis run on rows instead of coordinates: each vertex carries its row (the
  // cage weights of its value), a lift x_t += sum w x_s merges rows, a scaling scales one, and the
  // lifts that read only details (zero rows) are skipped, as synthesizeZeroDetails skips them.
  // Rows live in a pool: vertex h's is [begin[h], begin[h] + length[h]); a lift appends its
  // targets' new rows (its sources are other vertices, whose rows stay put while it reads them); the
  // pool is compacted after each level. Weights below float's resolution of the sum are dropped.
  std::vector<uint32_t> begin(n, 0), length(n, 0);
  std::vector<uint16_t> index;
  std::vector<float> weight;
  for (uint32_t c = 0; c < cage; ++c) begin[c] = c, length[c] = 1, index.push_back(uint16_t(c)), weight.push_back(1.0f);
  std::vector<double> sum(cage, 0.0);
  std::vector<uint8_t> seen(cage, 0);
  std::vector<uint16_t> touched;
  const auto kept = [](double w) { return std::abs(w) >= 1e-9; };
  for (int l = level + 1; l <= hierarchy.levels; ++l) {
    for (const LiftingStep& step : transform.synthesisSteps(l)) {
      if (step.readsOnlyDetails) continue;
      if (step.scaling) {
        for (size_t r = 0; r < step.targets.size(); ++r) {
          const uint32_t t = step.targets[r];
          for (uint32_t k = begin[t]; k < begin[t] + length[t]; ++k) weight[k] = float(weight[k] * step.weights[r]);
        }
        continue;
      }
      for (size_t r = 0; r < step.targets.size(); ++r) {
        const uint32_t t = step.targets[r];
        touched.clear();
        const auto add = [&](uint32_t h, double f) {
          for (uint32_t k = begin[h], end = begin[h] + length[h]; k < end; ++k) {
            const uint16_t c = index[k];
            if (!seen[c]) seen[c] = 1, touched.push_back(c);
            sum[c] += f * weight[k];
          }
        };
        add(t, 1.0);
        for (uint32_t k = step.offsets[r]; k < step.offsets[r + 1]; ++k) add(step.sources[k], step.weights[k]);
        begin[t] = uint32_t(index.size()), length[t] = 0;
        for (uint16_t c : touched) {
          if (kept(sum[c])) index.push_back(c), weight.push_back(float(sum[c])), ++length[t];
          sum[c] = 0.0, seen[c] = 0;
        }
      }
      if (index.size() > 2 * limit) return;
    }
    size_t live = 0;
    for (uint32_t h = 0; h < hierarchy.vertexCount[l]; ++h) live += length[h];
    if (live > limit) return;
    std::vector<uint16_t> compactIndex;
    std::vector<float> compactWeight;
    compactIndex.reserve(live + live / 2), compactWeight.reserve(live + live / 2);
    for (uint32_t h = 0; h < hierarchy.vertexCount[l]; ++h) {
      const uint32_t b = begin[h];
      begin[h] = uint32_t(compactIndex.size());
      compactIndex.insert(compactIndex.end(), index.begin() + b, index.begin() + b + length[h]);
      compactWeight.insert(compactWeight.end(), weight.begin() + b, weight.begin() + b + length[h]);
    }
    index = std::move(compactIndex), weight = std::move(compactWeight);
  }
  // Rows in the caller's order, then the columns' pattern (each column in increasing vertex order).
  std::vector<uint32_t> start(n + 1, 0);
  for (size_t h = 0; h < n; ++h) start[caller[h] + 1] = length[h];
  for (size_t v = 0; v < n; ++v) start[v + 1] += start[v];
  if (cage <= kMaxDenseCage) {
    float* dense = startDense(cage, n);
    for (size_t h = 0; h < n; ++h)
      for (uint32_t k = begin[h]; k < begin[h] + length[h]; ++k) dense[size_t(denseWidth_) * caller[h] + index[k]] += weight[k];
  } else {
    cage_.resize(start[n]);
    weight_.resize(start[n]);
    for (size_t h = 0; h < n; ++h) {
      std::copy(index.begin() + begin[h], index.begin() + begin[h] + length[h], cage_.begin() + start[caller[h]]);
      std::copy(weight.begin() + begin[h], weight.begin() + begin[h] + length[h], weight_.begin() + start[caller[h]]);
    }
  }
  index = {}, weight = {}, begin = {}, length = {};
  setColumns(std::move(start), cage);
}

CageBasisTable::CageBasisTable(const CageBasis& basis, uint32_t cage, const uint32_t* caller) {
  const size_t n = basis.offset.size() - 1;
  if (cage > kMaxCage || basis.index.size() > kMaxEntriesPerVertex * n) return;
  const auto kept = [](double w) { return std::abs(w) >= 1e-9; };
  // Rows in the caller's order, then the columns' pattern (each column in increasing vertex order).
  std::vector<uint32_t> start(n + 1, 0);
  for (size_t h = 0; h < n; ++h) {
    uint32_t length = 0;
    for (uint64_t p = basis.offset[h]; p < basis.offset[h + 1]; ++p) length += kept(basis.value[p]);
    start[caller[h] + 1] = length;
  }
  for (size_t v = 0; v < n; ++v) start[v + 1] += start[v];
  if (cage <= kMaxDenseCage) {
    float* dense = startDense(cage, n);
    for (size_t h = 0; h < n; ++h)
      for (uint64_t p = basis.offset[h]; p < basis.offset[h + 1]; ++p)
        if (kept(basis.value[p])) dense[size_t(denseWidth_) * caller[h] + basis.index[p]] += float(basis.value[p]);
  } else {
    cage_.resize(start[n]);
    weight_.resize(start[n]);
    for (size_t h = 0; h < n; ++h) {
      uint32_t k = start[caller[h]];
      for (uint64_t p = basis.offset[h]; p < basis.offset[h + 1]; ++p)
        if (kept(basis.value[p])) cage_[k] = uint16_t(basis.index[p]), weight_[k++] = float(basis.value[p]);
    }
  }
  setColumns(std::move(start), cage);
}

void CageBasisTable::setColumns(std::vector<uint32_t> start, uint32_t cage) {
  const size_t n = start.size() - 1;
  // Each entry of row v in order: f(cage index); a dense row's are its nonzero weights.
  const auto forEachEntry = [&](uint32_t v, auto&& f) {
    if (denseWidth_) {
      const float* w = weight_.data() + size_t(denseWidth_) * v;
      for (uint32_t c = 0; c < cage; ++c)
        if (w[c] != 0.0f) f(c);
    } else {
      for (uint32_t k = start[v]; k < start[v + 1]; ++k) f(uint32_t(cage_[k]));
    }
  };
  columnStart_.assign(size_t(cage) + 1, 0);
  for (uint32_t v = 0; v < n; ++v) forEachEntry(v, [&](uint32_t c) { ++columnStart_[c + 1]; });
  for (uint32_t c = 0; c < cage; ++c) columnStart_[c + 1] += columnStart_[c];
  entries_ = columnStart_[cage];
  columnVertex_.resize(entries_);
  std::vector<uint32_t> next(columnStart_.begin(), columnStart_.end() - 1);
  for (uint32_t v = 0; v < n; ++v) forEachEntry(v, [&](uint32_t c) { columnVertex_[next[c]++] = v; });
  rowStart_ = std::move(start);
}

float* CageBasisTable::startDense(uint32_t cage, size_t rows) {
  denseWidth_ = std::max<uint32_t>(4, (cage + 3) / 4 * 4);  // a width applyDense is made for
  weight_.assign(rows * denseWidth_, 0.0f);
  return weight_.data();
}

void CageBasisTable::row(uint32_t v, std::vector<uint32_t>& cage, std::vector<float>& weights) const {
  if (denseWidth_) {
    cage.clear(), weights.clear();
    const float* w = weight_.data() + size_t(denseWidth_) * v;
    for (uint32_t c = 0; c < cageSize(); ++c)
      if (w[c] != 0.0f) cage.push_back(c), weights.push_back(w[c]);
    return;
  }
  cage.assign(cage_.begin() + rowStart_[v], cage_.begin() + rowStart_[v + 1]);
  weights.assign(weight_.begin() + rowStart_[v], weight_.begin() + rowStart_[v + 1]);
}

namespace {

#ifdef __wasm_simd128__
inline v128_t rowSum(const float* base4, const float* delta4, const uint16_t* c, const float* w, uint32_t k, uint32_t end, size_t v) {
  v128_t p = wasm_v128_load(base4 + 4 * v);
  for (; k < end; ++k) p = wasm_f32x4_add(p, wasm_f32x4_mul(wasm_f32x4_splat(w[k]), wasm_v128_load(delta4 + 4 * size_t(c[k]))));
  return p;
}
#else
inline void rowSum(const float* base4, const float* delta4, const uint16_t* c, const float* w, uint32_t k, uint32_t end, size_t v,
                   float p[3]) {
  p[0] = base4[4 * v], p[1] = base4[4 * v + 1], p[2] = base4[4 * v + 2];
  for (; k < end; ++k) {
    const float* d = delta4 + 4 * size_t(c[k]);
    p[0] += w[k] * d[0], p[1] += w[k] * d[1], p[2] += w[k] * d[2];
  }
}
#endif

// Dense rows of W weights (cage order; zeros past the cage, whose deltas are taken as zero): rows
// [first, end), or the rows listed at rows[first, end). Each row's sum: base, then the cage vertices in
// order (a zero weight adds a zero: the value unchanged).
template <uint32_t W>
void applyDense(const float* weights, uint32_t cage, const float* base4, const float* delta4, const float origin[3], float* out4,
                float* out3, const uint32_t* outIndex, const uint32_t* rows, size_t first, size_t end) {
#ifdef __wasm_simd128__
  v128_t d[W];
  for (uint32_t j = 0; j < W; ++j) d[j] = j < cage ? wasm_v128_load(delta4 + 4 * size_t(j)) : wasm_f32x4_splat(0.0f);
  const v128_t o = wasm_f32x4_make(origin[0], origin[1], origin[2], 0.0f);
  for (size_t i = first; i < end; ++i) {
    const size_t v = rows ? rows[i] : i;
    const float* w = weights + size_t(W) * v;
    v128_t p = wasm_v128_load(base4 + 4 * v);
    for (uint32_t j = 0; j < W; ++j) p = wasm_f32x4_add(p, wasm_f32x4_mul(wasm_v128_load32_splat(w + j), d[j]));
    wasm_v128_store(out4 + 4 * v, p);
    float q[4];
    wasm_v128_store(q, wasm_f32x4_add(p, o));
    std::memcpy(out3 + 3 * size_t(outIndex[v]), q, 3 * sizeof(float));
  }
#else
  float d[W][3];
  for (uint32_t j = 0; j < W; ++j)
    for (int k = 0; k < 3; ++k) d[j][k] = j < cage ? delta4[4 * size_t(j) + k] : 0.0f;
  for (size_t i = first; i < end; ++i) {
    const size_t v = rows ? rows[i] : i;
    const float* w = weights + size_t(W) * v;
    float p[3] = {base4[4 * v], base4[4 * v + 1], base4[4 * v + 2]};
    for (uint32_t j = 0; j < W; ++j) p[0] += w[j] * d[j][0], p[1] += w[j] * d[j][1], p[2] += w[j] * d[j][2];
    out4[4 * v] = p[0], out4[4 * v + 1] = p[1], out4[4 * v + 2] = p[2], out4[4 * v + 3] = 0.0f;
    float* q = out3 + 3 * size_t(outIndex[v]);
    q[0] = p[0] + origin[0], q[1] = p[1] + origin[1], q[2] = p[2] + origin[2];
  }
#endif
}

using DenseApply = void (*)(const float*, uint32_t, const float*, const float*, const float*, float*, float*, const uint32_t*,
                            const uint32_t*, size_t, size_t);
DenseApply denseApply(uint32_t width) {
  switch (width) {
    case 4: return applyDense<4>;
    case 8: return applyDense<8>;
    case 12: return applyDense<12>;
    default: return applyDense<16>;
  }
}

}  // namespace

void CageBasisTable::apply(const float* base4, const float* delta4, const float origin[3], float* out4, float* out3,
                           const uint32_t* outIndex) const {
  const size_t n = rowStart_.size() - 1;
  const uint32_t* start = rowStart_.data();
  const uint16_t* c = cage_.data();
  const float* w = weight_.data();
  if (denseWidth_) {
    const DenseApply rows = denseApply(denseWidth_);
    const uint32_t cage = cageSize();
    parallelFor(0, n, kRowsPerBlock, [&](size_t first, size_t end) {
      rows(w, cage, base4, delta4, origin, out4, out3, outIndex, nullptr, first, end);
    });
    return;
  }
  // Rows are independent (each writes its own out4 and out3 entries): blocks of them on the pool's threads.
  parallelFor(0, n, kRowsPerBlock, [&](size_t first, size_t end) {
#ifdef __wasm_simd128__
    const v128_t o = wasm_f32x4_make(origin[0], origin[1], origin[2], 0.0f);
    for (size_t v = first; v < end; ++v) {
      const v128_t p = rowSum(base4, delta4, c, w, start[v], start[v + 1], v);
      wasm_v128_store(out4 + 4 * v, p);
      float q[4];
      wasm_v128_store(q, wasm_f32x4_add(p, o));
      std::memcpy(out3 + 3 * size_t(outIndex[v]), q, 3 * sizeof(float));
    }
#else
    for (size_t v = first; v < end; ++v) {
      float p[3];
      rowSum(base4, delta4, c, w, start[v], start[v + 1], v, p);
      out4[4 * v] = p[0], out4[4 * v + 1] = p[1], out4[4 * v + 2] = p[2], out4[4 * v + 3] = 0.0f;
      float* q = out3 + 3 * size_t(outIndex[v]);
      q[0] = p[0] + origin[0], q[1] = p[1] + origin[1], q[2] = p[2] + origin[2];
    }
#endif
  });
}

void CageBasisTable::applyRows(const uint32_t* vertices, size_t count, const float* base4, const float* delta4, const float origin[3],
                               float* out4, float* out3, const uint32_t* outIndex) const {
  const uint32_t* start = rowStart_.data();
  const uint16_t* c = cage_.data();
  const float* w = weight_.data();
  if (denseWidth_) return denseApply(denseWidth_)(w, cageSize(), base4, delta4, origin, out4, out3, outIndex, vertices, 0, count);
  for (size_t i = 0; i < count; ++i) {
    const uint32_t v = vertices[i];
    float p[4];
#ifdef __wasm_simd128__
    wasm_v128_store(p, rowSum(base4, delta4, c, w, start[v], start[v + 1], v));
#else
    rowSum(base4, delta4, c, w, start[v], start[v + 1], v, p);
    p[3] = 0.0f;
#endif
    std::copy(p, p + 4, out4 + 4 * size_t(v));
    float* q = out3 + 3 * size_t(outIndex[v]);
    q[0] = p[0] + origin[0], q[1] = p[1] + origin[1], q[2] = p[2] + origin[2];
  }
}

}  // namespace mrvol
