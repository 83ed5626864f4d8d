#include "mrvol/cage_basis_table.h"

#include <cmath>

#ifdef __wasm_simd128__
#include <wasm_simd128.h>
#endif

namespace mrvol {

CageBasisTable::CageBasisTable(const WaveletTransform& transform, int level, const uint32_t* caller) {
  const Hierarchy& hierarchy = transform.hierarchy();
  const uint32_t cage = hierarchy.vertexCount[level];
  const size_t n = hierarchy.fineVertexCount();
  if (cage > kMaxCage || level >= hierarchy.levels) return;
  // Synthesis acts on each coordinate alike: three cage vertices at once, one per coordinate. Two
  // rounds of the same syntheses (count the rows, then fill them) keep the build's memory at the
  // table's own.
  std::vector<double> scratch(3 * n);
  const auto synthesizeGroup = [&](uint32_t first) {
    std::fill(scratch.begin(), scratch.begin() + 3 * size_t(cage), 0.0);
    for (uint32_t k = 0; k < 3 && first + k < cage; ++k) scratch[3 * size_t(first + k) + k] = 1.0;
    transform.synthesizeZeroDetails(scratch.data(), level);
    return first + 3 <= cage ? 3u : cage - first;
  };
  const auto kept = [](double w) { return std::abs(w) >= 1e-9; };  // below float's resolution of the sum
  std::vector<uint32_t> start(n + 1, 0);
  size_t total = 0;
  for (uint32_t first = 0; first < cage; first += 3) {
    const uint32_t lanes = synthesizeGroup(first);
    for (size_t h = 0; h < n; ++h)
      for (uint32_t k = 0; k < lanes; ++k)
        if (kept(scratch[3 * h + k])) ++start[caller[h] + 1], ++total;
    if (total > kMaxEntriesPerVertex * n) return;
  }
  for (size_t v = 0; v < n; ++v) start[v + 1] += start[v];
  cage_.resize(total);
  weight_.resize(total);
  std::vector<uint32_t> next(start.begin(), start.end() - 1);
  for (uint32_t first = 0; first < cage; first += 3) {
    const uint32_t lanes = synthesizeGroup(first);
    for (size_t h = 0; h < n; ++h)
      for (uint32_t k = 0; k < lanes; ++k)
        if (kept(scratch[3 * h + k])) {
          const uint32_t at = next[caller[h]]++;
          cage_[at] = uint16_t(first + k), weight_[at] = float(scratch[3 * h + k]);
        }
  }
  rowStart_ = std::move(start);
}

void CageBasisTable::apply(const float* base4, const float* delta4, const float origin[3], float* out4, float* out3) const {
  const size_t n = rowStart_.size() - 1;
  const uint32_t* start = rowStart_.data();
  const uint16_t* c = cage_.data();
  const float* w = weight_.data();
#ifdef __wasm_simd128__
  const v128_t o = wasm_f32x4_make(origin[0], origin[1], origin[2], 0.0f);
  for (size_t v = 0; v < n; ++v) {
    v128_t p = wasm_v128_load(base4 + 4 * v);
    for (uint32_t k = start[v], end = start[v + 1]; k < end; ++k)
      p = wasm_f32x4_add(p, wasm_f32x4_mul(wasm_f32x4_splat(w[k]), wasm_v128_load(delta4 + 4 * size_t(c[k]))));
    wasm_v128_store(out4 + 4 * v, p);
    wasm_v128_store(out3 + 3 * v, wasm_f32x4_add(p, o));  // lane 3 is overwritten by the next vertex
  }
#else
  for (size_t v = 0; v < n; ++v) {
    float p[3] = {base4[4 * v], base4[4 * v + 1], base4[4 * v + 2]};
    for (uint32_t k = start[v], end = start[v + 1]; k < end; ++k) {
      const float* d = delta4 + 4 * size_t(c[k]);
      p[0] += w[k] * d[0], p[1] += w[k] * d[1], p[2] += w[k] * d[2];
    }
    out4[4 * v] = p[0], out4[4 * v + 1] = p[1], out4[4 * v + 2] = p[2], out4[4 * v + 3] = 0.0f;
    out3[3 * v] = p[0] + origin[0], out3[3 * v + 1] = p[1] + origin[1], out3[3 * v + 2] = p[2] + origin[2];
  }
#endif
}

}  // namespace mrvol
