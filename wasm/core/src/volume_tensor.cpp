#include "mrvol/volume_tensor.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <unordered_map>

#include "mrvol/corners.h"
#include "mrvol/error.h"
#include "mrvol/vector3.h"

namespace mrvol {

namespace {

// One tensor entry in flight: T_ijk with i < j < k packed into a key that sorts like (i, j, k).
struct Term {
  uint64_t key;
  double value;
};

struct KeyPacking {
  int bits;
  uint64_t mask;
  explicit KeyPacking(uint32_t n) : bits(1), mask(0) {
    while ((uint64_t(1) << bits) < n) ++bits;
    mask = (uint64_t(1) << bits) - 1;
  }
  uint64_t pack(uint32_t i, uint32_t j, uint32_t k) const {
    return (uint64_t(i) << (2 * bits)) | (uint64_t(j) << bits) | k;
  }
  uint32_t i(uint64_t key) const { return uint32_t(key >> (2 * bits)); }
  uint32_t j(uint64_t key) const { return uint32_t((key >> bits) & mask); }
  uint32_t k(uint64_t key) const { return uint32_t(key & mask); }
};

// Sorts three distinct indices, returning the sign of the permutation.
inline double sortWithSign(uint32_t& a, uint32_t& b, uint32_t& c) {
  double s = 1;
  if (a > b) std::swap(a, b), s = -s;
  if (b > c) std::swap(b, c), s = -s;
  if (a > b) std::swap(a, b), s = -s;
  return s;
}

// LSD radix sort by key, 11-bit digits, only as many passes as the key has bits.
void radixSort(std::vector<Term>& a, std::vector<Term>& scratch, int keyBits) {
  constexpr int kDigit = 11, kBuckets = 1 << kDigit;
  scratch.resize(a.size());
  std::vector<size_t> count(kBuckets);
  for (int shift = 0; shift < keyBits; shift += kDigit) {
    std::fill(count.begin(), count.end(), 0);
    for (const Term& t : a) ++count[(t.key >> shift) & (kBuckets - 1)];
    size_t sum = 0;
    for (auto& c : count) { size_t n = c; c = sum; sum += n; }
    for (const Term& t : a) scratch[count[(t.key >> shift) & (kBuckets - 1)]++] = t;
    a.swap(scratch);
  }
}

// Sums runs of equal keys in a sorted array, in place.
void sumDuplicates(std::vector<Term>& a) {
  size_t out = 0;
  for (size_t i = 0; i < a.size();) {
    Term t = a[i++];
    while (i < a.size() && a[i].key == t.key) t.value += a[i++].value;
    a[out++] = t;
  }
  a.resize(out);
}

// Merges two sorted, duplicate-free arrays summing equal keys; drops exact zeros.
void mergeSum(const std::vector<Term>& a, const std::vector<Term>& b, std::vector<Term>& out,
              const std::vector<uint8_t>* reach, const KeyPacking& kp) {
  out.clear();
  out.reserve(a.size() + b.size());
  size_t i = 0, j = 0;
  while (i < a.size() || j < b.size()) {
    Term t;
    if (j == b.size() || (i < a.size() && a[i].key < b[j].key)) t = a[i++];
    else if (i == a.size() || b[j].key < a[i].key) t = b[j++];
    else t = {a[i].key, a[i].value + b[j].value}, ++i, ++j;
    if (t.value == 0.0) continue;
    if (reach && !(*reach)[kp.i(t.key)] && !(*reach)[kp.j(t.key)] && !(*reach)[kp.k(t.key)]) continue;
    out.push_back(t);
  }
}

// Outwards application of a lift step along the three axes: every index t that the step targets
// becomes t + sum_s w_ts s (e_t -> e_t + W^T ...). Appends the new terms (all but the identity).
// reach (optional): indices that can still reach a cage coefficient after this step; a new term
// none of whose indices can is dropped (Cage storage would drop it at the end anyway).
void expandLift(const std::vector<Term>& active, const LiftingStep& step, const std::vector<int32_t>& rowOf,
                const KeyPacking& kp, const std::vector<uint8_t>* reach, std::vector<Term>& delta,
                uint64_t maxTerms) {
  uint32_t idx[3][64];
  double w[3][64];
  int count[3];
  for (const Term& t : active) {
    const uint32_t ijk[3] = {kp.i(t.key), kp.j(t.key), kp.k(t.key)};
    bool any = false;
    for (int a = 0; a < 3; ++a) {
      idx[a][0] = ijk[a];
      w[a][0] = 1.0;
      count[a] = 1;
      int32_t r = ijk[a] < rowOf.size() ? rowOf[ijk[a]] : -1;
      if (r < 0) continue;
      any = true;
      for (uint32_t s = step.offsets[r]; s < step.offsets[r + 1] && count[a] < 64; ++s) {
        idx[a][count[a]] = step.sources[s];
        w[a][count[a]] = step.weights[s];
        ++count[a];
      }
    }
    if (!any) continue;
    for (int a = 0; a < count[0]; ++a)
      for (int b = 0; b < count[1]; ++b) {
        const double wab = t.value * w[0][a] * w[1][b];
        const uint32_t p0 = idx[0][a], q0 = idx[1][b];
        if (p0 == q0) continue;
        for (int c = (a == 0 && b == 0) ? 1 : 0; c < count[2]; ++c) {
          uint32_t p = p0, q = q0, r = idx[2][c];
          if (r == p || r == q) continue;
          if (reach && !(*reach)[p] && !(*reach)[q] && !(*reach)[r]) continue;
          double s = sortWithSign(p, q, r);
          delta.push_back({kp.pack(p, q, r), s * wab * w[2][c]});
        }
      }
    if (delta.size() > maxTerms)
      throw Error("the volume tensor needs more than " + std::to_string(maxTerms) +
                  " terms in flight at this level; use the matrix-free gradient or a finer level");
  }
}

double nowMs() {
  using namespace std::chrono;
  return duration<double, std::milli>(steady_clock::now().time_since_epoch()).count();
}

// Packs sorted terms whose first index is below rowCount into the CSR layout.
VolumeTensor compact(const std::vector<Term>& terms, const KeyPacking& kp, uint32_t n, uint32_t rowCount) {
  VolumeTensor t;
  t.vertexCount = n;
  t.rowCount = rowCount;
  const bool narrow = n <= 65536;
  t.rowStart.assign(rowCount + 1, 0);
  t.pairStart.push_back(0);
  uint64_t lastPair = ~uint64_t(0);
  for (const Term& term : terms) {
    uint32_t i = kp.i(term.key);
    if (i >= rowCount) break;
    uint64_t pair = term.key >> kp.bits;
    if (pair != lastPair) {
      if (lastPair != ~uint64_t(0)) t.pairStart.push_back(uint32_t(t.values.size()));
      t.pairJ.push_back(kp.j(term.key));
      ++t.rowStart[i + 1];
      lastPair = pair;
    }
    if (narrow) t.k16.push_back(uint16_t(kp.k(term.key)));
    else t.k32.push_back(kp.k(term.key));
    t.values.push_back(term.value);
  }
  if (!t.pairJ.empty()) t.pairStart.push_back(uint32_t(t.values.size()));
  for (uint32_t i = 0; i < rowCount; ++i) t.rowStart[i + 1] += t.rowStart[i];
  return t;
}

}  // namespace

size_t VolumeTensor::bytes() const {
  return rowStart.size() * 4 + pairJ.size() * 4 + pairStart.size() * 4 + k16.size() * 2 + k32.size() * 4 +
         values.size() * 8;
}

namespace {

// The recursion on sparse terms: theta^n from the triangles, then every transposed step of levels
// n..e+1 expands each entry along the three axes; duplicates are merged by sorting.
VolumeTensor sparseRecursion(const WaveletTransform& wt, int level, TensorStorage storage, const FineForm& fine,
                             const TensorProgress& progress, uint64_t maxTerms) {
  const Hierarchy& h = wt.hierarchy();
  const int n = h.levels;
  if (level < 0 || level > n)
    throw Error("level " + std::to_string(level) + " is out of range 0.." + std::to_string(n));
  const uint32_t N = uint32_t(h.fineVertexCount());
  if (N >= (1u << 21)) throw Error("meshes of more than 2 million vertices are not supported by the volume tensor");
  const KeyPacking kp(N);
  const int keyBits = 3 * kp.bits;

  // theta^n: the fine form's weights (+-1/6 for every fine triangle), by the parity of the sorting.
  std::vector<Term> active, delta, scratch, merged;
  active.reserve(fine.size());
  for (size_t f = 0; f < fine.size(); ++f) {
    uint32_t a = fine.corners[3 * f], b = fine.corners[3 * f + 1], c = fine.corners[3 * f + 2];
    if (a == b || b == c || a == c) continue;
    double s = sortWithSign(a, b, c);
    active.push_back({kp.pack(a, b, c), s * fine.weights[f]});
  }
  radixSort(active, scratch, keyBits);
  sumDuplicates(active);

  uint64_t dropped = 0;
  std::vector<std::vector<Term>> finished;  // Full storage: entries made only of finished details
  // Entries whose smallest index is >= limit are final: no later step touches them.
  auto retire = [&](uint32_t limit) {
    auto first = std::lower_bound(active.begin(), active.end(), kp.pack(limit, 0, 0),
                                  [](const Term& t, uint64_t key) { return t.key < key; });
    if (first == active.end()) return;
    dropped += uint64_t(active.end() - first);
    if (storage == TensorStorage::Full) finished.emplace_back(first, active.end());
    active.erase(first, active.end());
  };

  // Cage storage keeps only entries with an index below V_e at the end. reachAfter[s][t]: index t,
  // after step s (in application order), still maps into the cage through the remaining steps.
  std::vector<const LiftingStep*> order;
  for (int l = n; l > level; --l) {
    const auto& steps = wt.synthesisSteps(l);
    for (auto it = steps.rbegin(); it != steps.rend(); ++it) order.push_back(&*it);
  }
  std::vector<std::vector<uint8_t>> reachAfter(order.size());
  if (storage == TensorStorage::Cage) {
    std::vector<uint8_t> reach(N, 0);
    std::fill(reach.begin(), reach.begin() + h.vertexCount[level], 1);
    for (size_t s = order.size(); s-- > 0;) {
      reachAfter[s] = reach;
      const LiftingStep& step = *order[s];
      if (step.scaling) continue;
      for (size_t r = 0; r < step.targets.size(); ++r)
        for (uint32_t k = step.offsets[r]; k < step.offsets[r + 1]; ++k)
          if (reachAfter[s][step.sources[k]]) reach[step.targets[r]] = 1;
    }
  }
  size_t stepIndex = 0;

  size_t totalSteps = 0, doneSteps = 0;
  for (int l = n; l > level; --l) totalSteps += wt.synthesisSteps(l).size();
  std::vector<int32_t> rowOf;
  for (int l = n; l > level; --l) {
    retire(h.vertexCount[l]);
    const auto& steps = wt.synthesisSteps(l);
    for (auto it = steps.rbegin(); it != steps.rend(); ++it) {
      const LiftingStep& step = *it;
      const double stepStart = nowMs();
      rowOf.assign(h.vertexCount[l], -1);
      for (size_t r = 0; r < step.targets.size(); ++r) rowOf[step.targets[r]] = int32_t(r);
      if (step.scaling) {
        for (Term& t : active) {
          const uint32_t ijk[3] = {kp.i(t.key), kp.j(t.key), kp.k(t.key)};
          for (uint32_t v : ijk)
            if (v < rowOf.size() && rowOf[v] >= 0) t.value *= step.weights[rowOf[v]];
        }
      } else {
        delta.clear();
        const std::vector<uint8_t>* reach = storage == TensorStorage::Cage ? &reachAfter[stepIndex] : nullptr;
        expandLift(active, step, rowOf, kp, reach, delta, maxTerms);
        const size_t raw = delta.size();
        radixSort(delta, scratch, keyBits);
        sumDuplicates(delta);
        mergeSum(active, delta, merged, reach, kp);
        if (std::getenv("MRVOL_TENSOR_TRACE"))
          std::fprintf(stderr, "level %d step %s: active %zu raw %zu delta %zu -> %zu (%.1f ms)\n", l,
                       step.name.c_str(), active.size(), raw, delta.size(), merged.size(), nowMs() - stepStart);
        active.swap(merged);
      }
      ++doneSteps;
      ++stepIndex;
      if (progress.callback && !progress.callback(double(doneSteps) / double(totalSteps), progress.user))
        throw Error("cancelled");
    }
  }
  retire(h.vertexCount[level]);
  std::vector<Term>().swap(delta);
  std::vector<Term>().swap(scratch);
  std::vector<Term>().swap(merged);

  uint64_t stored = active.size();
  VolumeTensor tensor;
  if (storage == TensorStorage::Full) {
    for (auto it = finished.rbegin(); it != finished.rend(); ++it) active.insert(active.end(), it->begin(), it->end());
    tensor = compact(active, kp, N, N);
  } else {
    tensor = compact(active, kp, N, h.vertexCount[level]);
  }
  (void)stored;
  tensor.level = level;
  tensor.storage = storage;
  // With Cage storage, pruned entries were never formed: the full count is unknown.
  tensor.nnzFull = storage == TensorStorage::Full ? 6 * uint64_t(tensor.storedCount()) : 0;
  (void)dropped;
  return tensor;
}

}  // namespace

namespace {

// Kernels of the dense patch transform, kept out of line: V8 compiles WebAssembly first with a
// baseline compiler and swaps in optimized code only at the next call of a function, so hot loops
// must sit in functions that are called often, not in one long call.
struct PatchOp {
  uint32_t t, s;
  double w;
};

__attribute__((noinline)) void patchRowOps(double* dense, size_t m, const PatchOp* ops, size_t count,
                                           uint8_t* rowLive) {
  for (size_t o = 0; o < count; ++o) {  // A[s, :] += w A[t, :]
    const double* src = dense + size_t(ops[o].t) * m;
    double* dst = dense + size_t(ops[o].s) * m;
    const double w = ops[o].w;
    for (size_t x = 0; x < m; ++x) dst[x] += w * src[x];
    rowLive[ops[o].s] = 1;
  }
}

__attribute__((noinline)) void patchColumnOps(double* row, const PatchOp* ops, size_t count) {
  for (size_t o = 0; o < count; ++o) row[ops[o].s] += ops[o].w * row[ops[o].t];  // A[r, s] += w A[r, t]
}

__attribute__((noinline)) void patchScale(double* dense, size_t m, size_t v, double f) {
  for (size_t x = 0; x < m; ++x) dense[v * m + x] *= f;
  for (size_t x = 0; x < m; ++x) dense[x * m + v] *= f;
}

// The patch of a cage vertex c: phi_c = R e_c (the fine values of c's basis function), the corners
// of the triangles (the fine form's triples) where it is non-zero, grown through the transposed steps by the sources of every
// target it holds: all indices the 2-form theta(phi_c, ., .) can reach on its way to level e.
struct PatchFinder {
  const WaveletTransform& wt;
  int level;
  uint32_t n;
  VertexCorners corners;
  std::vector<const LiftingStep*> order;  // transposed application order
  std::vector<double> phi;
  std::vector<uint8_t> inPatch;
  std::vector<uint32_t> patch;  // ascending

  PatchFinder(const WaveletTransform& wt, int level, const FineForm& fine)
      : wt(wt), level(level), n(uint32_t(wt.hierarchy().fineVertexCount())),
        corners(fine.corners.data(), fine.size(), n), phi(n), inPatch(n) {
    for (int l = wt.hierarchy().levels; l > level; --l) {
      const auto& steps = wt.synthesisSteps(l);
      for (auto it = steps.rbegin(); it != steps.rend(); ++it) order.push_back(&*it);
    }
  }

  void find(uint32_t c) {
    std::fill(phi.begin(), phi.end(), 0.0);
    phi[c] = 1.0;
    for (int l = level + 1; l <= wt.hierarchy().levels; ++l)
      for (const auto& step : wt.synthesisSteps(l)) step.forward(phi.data(), 1);
    std::fill(inPatch.begin(), inPatch.end(), 0);
    for (uint32_t v = 0; v < n; ++v)
      if (phi[v] != 0.0)
        for (uint32_t k = corners.begin(v); k < corners.end(v); ++k)
          inPatch[v] = inPatch[corners.next[k]] = inPatch[corners.prev[k]] = 1;
    for (const LiftingStep* step : order) {
      if (step->scaling) continue;
      for (size_t r = 0; r < step->targets.size(); ++r)
        if (inPatch[step->targets[r]])
          for (uint32_t k = step->offsets[r]; k < step->offsets[r + 1]; ++k) inPatch[step->sources[k]] = 1;
    }
    patch.clear();
    for (uint32_t v = 0; v < n; ++v)
      if (inPatch[v]) patch.push_back(v);
  }
};

// Cage rows one cage vertex c at a time: row c holds the 2-form A^c(j, k) = theta^e(e_c, e_j, e_k)
// = theta^n(phi_c, R e_j, R e_k), with phi_c = R e_c the fine values of c's basis function. At the
// fine level, A^c is a sparse 2-form on the edges of the triangles where phi_c is non-zero; the
// transposed steps along the two remaining axes are row and column operations on a dense matrix
// over the patch of indices it can reach. Returns false (nothing computed) when a patch would not
// fit in maxDenseBytes: the caller falls back to the sparse recursion.
bool cageRowsByPatches(const WaveletTransform& wt, int level, const FineForm& fine, const TensorProgress& progress,
                       size_t maxDenseBytes, VolumeTensor& out) {
  const Hierarchy& h = wt.hierarchy();
  const uint32_t N = uint32_t(h.fineVertexCount());
  const uint32_t cage = h.vertexCount[level];
  PatchFinder patches(wt, level, fine);
  const auto& order = patches.order;
  const auto& faces = fine.corners;

  VolumeTensor t;
  t.vertexCount = N;
  t.rowCount = cage;
  t.rowStart.assign(cage + 1, 0);
  t.pairStart.push_back(0);
  const bool narrow = N <= 65536;

  std::vector<double> dense;
  std::vector<uint32_t> local(N, kNone);
  std::vector<uint8_t> rowLive;
  std::vector<PatchOp> ops;
  // One cage vertex per call (see the kernels above for why it is not inlined).
  std::function<bool(uint32_t)> cageRow = [&](uint32_t c) -> bool {
    patches.find(c);
    const std::vector<double>& phi = patches.phi;
    const std::vector<uint8_t>& inPatch = patches.inPatch;
    const std::vector<uint32_t>& patch = patches.patch;
    for (uint32_t i = 0; i < patch.size(); ++i) local[patch[i]] = i;
    const size_t m = patch.size();
    if (m * m * sizeof(double) > maxDenseBytes) return false;
    dense.assign(m * m, 0.0);
    rowLive.assign(m, 0);
    // A^c at the fine level: theta^n(phi, u, v) = sum over triples (a, b, d) of weight w
    // w (phi_a [b, d] + phi_b [d, a] + phi_d [a, b]), with [x, y] the antisymmetric pair
    // (w = 1/6 for the triangles).
    auto add = [&](uint32_t x, uint32_t y, double v) {
      const size_t lx = local[x], ly = local[y];
      dense[lx * m + ly] += v;
      dense[ly * m + lx] -= v;
      rowLive[lx] = rowLive[ly] = 1;
    };
    for (size_t f = 0; f < faces.size(); f += 3) {
      const uint32_t a = faces[f], b = faces[f + 1], d = faces[f + 2];
      const double w = fine.weights[f / 3];
      if (phi[a] != 0.0) add(b, d, phi[a] * w);
      if (phi[b] != 0.0) add(d, a, phi[b] * w);
      if (phi[d] != 0.0) add(a, b, phi[d] * w);
    }
    for (size_t s = 0; s < order.size(); ++s) {
      const LiftingStep& step = *order[s];
      if (step.scaling) {
        for (size_t r = 0; r < step.targets.size(); ++r) {
          const uint32_t v = step.targets[r];
          if (!inPatch[v]) continue;
          patchScale(dense.data(), m, local[v], step.weights[r]);
        }
        continue;
      }
      ops.clear();
      for (size_t r = 0; r < step.targets.size(); ++r) {
        const uint32_t v = step.targets[r];
        if (!inPatch[v] || !rowLive[local[v]]) continue;
        for (uint32_t k = step.offsets[r]; k < step.offsets[r + 1]; ++k)
          ops.push_back({local[v], local[step.sources[k]], step.weights[k]});
      }
      if (ops.empty()) continue;
      // Rows (M^T A), then columns (. M), one row at a time so that each row stays in cache.
      patchRowOps(dense.data(), m, ops.data(), ops.size(), rowLive.data());
      for (size_t r = 0; r < m; ++r)
        if (rowLive[r]) patchColumnOps(&dense[r * m], ops.data(), ops.size());
    }
    // Row c of the tensor: entries (c, j, k) with c < j < k.
    for (size_t lj = local[c] + 1; lj < m; ++lj) {
      const double* row = &dense[lj * m];
      bool pairOpen = false;
      for (size_t lk = lj + 1; lk < m; ++lk) {
        const double v = row[lk];
        if (v == 0.0) continue;
        if (!pairOpen) {
          t.pairJ.push_back(patch[lj]);
          ++t.rowStart[c + 1];
          pairOpen = true;
        }
        if (narrow) t.k16.push_back(uint16_t(patch[lk]));
        else t.k32.push_back(patch[lk]);
        t.values.push_back(v);
      }
      if (pairOpen) t.pairStart.push_back(uint32_t(t.values.size()));
    }
    for (uint32_t v : patch) local[v] = kNone;
    return true;
  };
  for (uint32_t c = 0; c < cage; ++c) {
    if (!cageRow(c)) return false;
    if (progress.callback && !progress.callback(double(c + 1) / double(cage), progress.user))
      throw Error("cancelled");
  }
  for (uint32_t i = 0; i < cage; ++i) t.rowStart[i + 1] += t.rowStart[i];
  t.level = level;
  t.storage = TensorStorage::Cage;
  t.nnzFull = 0;  // unknown: the detail-only entries are never formed
  out = std::move(t);
  return true;
}

}  // namespace

FineForm triangleForm(const std::vector<uint32_t>& faces) {
  FineForm form;
  form.corners = faces;
  form.weights.assign(faces.size() / 3, 1.0 / 6.0);
  return form;
}

double FineForm::evaluate(const double* x, Vec3 o) const {
  double total = 0;
  for (size_t t = 0; t < size(); ++t) {
    const double* a = x + 3 * size_t(corners[3 * t]);
    const double* b = x + 3 * size_t(corners[3 * t + 1]);
    const double* c = x + 3 * size_t(corners[3 * t + 2]);
    const double ax = a[0] - o.x, ay = a[1] - o.y, az = a[2] - o.z;
    const double bx = b[0] - o.x, by = b[1] - o.y, bz = b[2] - o.z;
    const double cx = c[0] - o.x, cy = c[1] - o.y, cz = c[2] - o.z;
    total += weights[t] * (ax * (by * cz - bz * cy) + ay * (bz * cx - bx * cz) + az * (bx * cy - by * cx));
  }
  return total;
}

namespace {
// Where exact arithmetic cancels to zero, floating point leaves residues of round-off: on the
// spiky ball (Loop, e = 0) they are at most 1e-15 of the largest entry, the true entries at least
// 1e-11 of it. Entries below this fraction of the largest are dropped once the tensor is built.
constexpr double kResidueFraction = 1e-13;

void dropResidues(VolumeTensor& t) {
  double largest = 0;
  for (double v : t.values) largest = std::max(largest, std::fabs(v));
  const double floor = kResidueFraction * largest;
  const bool narrow = !t.k16.empty();
  size_t kept = 0, pairs = 0;
  uint32_t pairsBefore = 0;  // pairs of the rows before i, as stored on input
  for (uint32_t i = 0; i < t.rowCount; ++i) {
    const uint32_t rowPairs = t.rowStart[i + 1] - pairsBefore;
    uint32_t keptPairs = 0;
    for (uint32_t p = pairsBefore; p < pairsBefore + rowPairs; ++p) {
      const size_t first = kept;
      for (uint32_t e = t.pairStart[p]; e < t.pairStart[p + 1]; ++e) {
        if (!(std::fabs(t.values[e]) >= floor)) continue;
        t.values[kept] = t.values[e];
        if (narrow) t.k16[kept] = t.k16[e];
        else t.k32[kept] = t.k32[e];
        ++kept;
      }
      if (kept == first) continue;
      t.pairJ[pairs] = t.pairJ[p];
      t.pairStart[pairs] = uint32_t(first);
      ++pairs, ++keptPairs;
    }
    pairsBefore += rowPairs;
    t.rowStart[i + 1] = t.rowStart[i] + keptPairs;
  }
  t.pairJ.resize(pairs);
  t.pairStart.resize(pairs + 1);
  t.pairStart[pairs] = uint32_t(kept);
  t.values.resize(kept);
  (narrow ? t.k16.resize(kept) : t.k32.resize(kept));
  if (t.storage == TensorStorage::Full) t.nnzFull = 6 * uint64_t(kept);
}
}  // namespace

VolumeTensor computeVolumeTensor(const WaveletTransform& wt, int level, TensorStorage storage,
                                 const TensorProgress& progress, uint64_t maxTerms) {
  return computeVolumeTensor(wt, level, storage, triangleForm(wt.hierarchy().fineFaces()), progress, maxTerms);
}

VolumeTensor computeVolumeTensor(const WaveletTransform& wt, int level, TensorStorage storage, const FineForm& fine,
                                 const TensorProgress& progress, uint64_t maxTerms) {
  const Hierarchy& h = wt.hierarchy();
  if (level < 0 || level > h.levels)
    throw Error("level " + std::to_string(level) + " is out of range 0.." + std::to_string(h.levels));
  for (uint32_t v : fine.corners)
    if (v >= h.fineVertexCount())
      throw Error("fine form refers to vertex " + std::to_string(v) + " of " + std::to_string(h.fineVertexCount()));
  VolumeTensor t;
  if (storage != TensorStorage::Cage || !cageRowsByPatches(wt, level, fine, progress, size_t(1) << 30, t))
    t = sparseRecursion(wt, level, storage, fine, progress, maxTerms);
  dropResidues(t);
  return t;
}

TensorEstimate estimateCageTensor(const WaveletTransform& wt, int level, int samples) {
  const Hierarchy& h = wt.hierarchy();
  if (level < 0 || level > h.levels)
    throw Error("level " + std::to_string(level) + " is out of range 0.." + std::to_string(h.levels));
  TensorEstimate e;
  e.cageSize = h.vertexCount[level];
  PatchFinder patches(wt, level, triangleForm(h.fineFaces()));
  const uint32_t count = std::min<uint32_t>(e.cageSize, uint32_t(std::max(samples, 1)));
  double sumSquares = 0;
  for (uint32_t s = 0; s < count; ++s) {
    const uint32_t c = uint32_t(uint64_t(s) * e.cageSize / count);
    patches.find(c);
    const double m = double(patches.patch.size());
    sumSquares += m * m;
    e.maxPatch = std::max(e.maxPatch, uint32_t(m));
  }
  const double total = sumSquares / count * e.cageSize;  // sum over the cage of m_c^2
  // Measured on icospheres and the spiky ball: stored entries are 0.2 to 0.53 of sum m^2 / 2 (the
  // upper end is used), about 10 bytes each, and the dense work about 10 to 18 ns per m^2 natively.
  e.entries = uint64_t(0.53 * total / 2);
  e.bytes = e.entries * 10;
  e.denseBytes = uint64_t(e.maxPatch) * e.maxPatch * 8;
  e.milliseconds = 2e-5 * total;
  return e;
}

VolumeTensor computeVolumeTensorDirect(const WaveletTransform& wt, int level, TensorStorage storage) {
  return computeVolumeTensorDirect(wt, level, storage, triangleForm(wt.hierarchy().fineFaces()));
}

VolumeTensor computeVolumeTensorDirect(const WaveletTransform& wt, int level, TensorStorage storage,
                                       const FineForm& fine) {
  const Hierarchy& h = wt.hierarchy();
  const uint32_t N = uint32_t(h.fineVertexCount());
  if (N > 5000) throw Error("the direct construction is for small test meshes");
  // Column c of the synthesis operator R: synthesis of the unit coefficient vector e_c.
  std::vector<std::vector<std::pair<uint32_t, double>>> rows(N);
  std::vector<double> x(N);
  for (uint32_t c = 0; c < N; ++c) {
    std::fill(x.begin(), x.end(), 0.0);
    x[c] = 1.0;
    for (int l = level + 1; l <= h.levels; ++l)
      for (const auto& step : wt.synthesisSteps(l)) step.forward(x.data(), 1);
    for (uint32_t a = 0; a < N; ++a)
      if (x[a] != 0.0) rows[a].emplace_back(c, x[a]);
  }
  const KeyPacking kp(N);
  std::unordered_map<uint64_t, double> acc;
  const auto& faces = fine.corners;
  for (size_t f = 0; f < faces.size(); f += 3)
    for (auto [p0, wa] : rows[faces[f]])
      for (auto [q0, wb] : rows[faces[f + 1]])
        for (auto [r0, wc] : rows[faces[f + 2]]) {
          uint32_t p = p0, q = q0, r = r0;
          if (p == q || q == r || p == r) continue;
          double s = sortWithSign(p, q, r);
          acc[kp.pack(p, q, r)] += s * wa * wb * wc * fine.weights[f / 3];
        }
  std::vector<Term> terms;
  for (auto& [key, value] : acc)
    if (value != 0.0) terms.push_back({key, value});
  std::sort(terms.begin(), terms.end(), [](const Term& a, const Term& b) { return a.key < b.key; });
  uint32_t rowCount = storage == TensorStorage::Full ? N : h.vertexCount[level];
  VolumeTensor t = compact(terms, kp, N, rowCount);
  t.level = level;
  t.storage = storage;
  t.nnzFull = 6 * terms.size();
  dropResidues(t);
  return t;
}

// ---------------------------------------------------------------------------------------------
// Evaluation: Theta = sum_{i<j<k} T_ijk p_i . (p_j x p_k); per pair (i, j), q = sum_k T_ijk p_k.

VolumeTensor::Entries VolumeTensor::entries() const {
  Entries out;
  const size_t n = storedCount();
  out.i.reserve(n), out.j.reserve(n), out.k.reserve(n);
  for (uint32_t i = 0; i < rowCount; ++i)
    for (uint32_t p = rowStart[i]; p < rowStart[i + 1]; ++p)
      for (uint32_t t = pairStart[p]; t < pairStart[p + 1]; ++t) {
        out.i.push_back(i);
        out.j.push_back(pairJ[p]);
        out.k.push_back(kIndex(t));
      }
  out.values = values;
  return out;
}

double VolumeTensor::evaluate(const double* x) const { return evaluateWithGradient(x, nullptr, 0); }

double VolumeTensor::evaluateWithGradient(const double* x, double* grad, uint32_t limit) const {
  if (limit > 0) std::fill(grad, grad + 3 * size_t(limit), 0.0);
  double total = 0;
  for (uint32_t i = 0; i < rowCount; ++i) {
    const double* pi = x + 3 * size_t(i);
    for (uint32_t p = rowStart[i]; p < rowStart[i + 1]; ++p) {
      const uint32_t j = pairJ[p];
      const double* pj = x + 3 * size_t(j);
      double q[3] = {0, 0, 0}, ij[3];
      cross(pi, pj, ij);
      for (uint32_t t = pairStart[p]; t < pairStart[p + 1]; ++t) {
        const uint32_t k = kIndex(t);
        const double* pk = x + 3 * size_t(k);
        const double v = values[t];
        q[0] += v * pk[0], q[1] += v * pk[1], q[2] += v * pk[2];
        if (k < limit) {  // d/dp_k of v p_k . (p_i x p_j)
          double* g = grad + 3 * size_t(k);
          g[0] += v * ij[0], g[1] += v * ij[1], g[2] += v * ij[2];
        }
      }
      double jq[3];
      cross(pj, q, jq);
      total += pi[0] * jq[0] + pi[1] * jq[1] + pi[2] * jq[2];
      if (i < limit) {  // d/dp_i = p_j x q
        double* g = grad + 3 * size_t(i);
        g[0] += jq[0], g[1] += jq[1], g[2] += jq[2];
      }
      if (j < limit) {  // d/dp_j = q x p_i
        double qi[3];
        cross(q, pi, qi);
        double* g = grad + 3 * size_t(j);
        g[0] += qi[0], g[1] += qi[1], g[2] += qi[2];
      }
    }
  }
  return total;
}

double VolumeTensor::evaluateInvolving(const double* x, const std::vector<uint8_t>& moving) const {
  double total = 0;
  for (uint32_t i = 0; i < rowCount; ++i) {
    const double* pi = x + 3 * size_t(i);
    for (uint32_t p = rowStart[i]; p < rowStart[i + 1]; ++p) {
      const uint32_t j = pairJ[p];
      const bool pairMoves = moving[i] || moving[j];
      const double* pj = x + 3 * size_t(j);
      double q[3] = {0, 0, 0};
      for (uint32_t t = pairStart[p]; t < pairStart[p + 1]; ++t) {
        const uint32_t k = kIndex(t);
        if (!pairMoves && !moving[k]) continue;
        const double* pk = x + 3 * size_t(k);
        const double v = values[t];
        q[0] += v * pk[0], q[1] += v * pk[1], q[2] += v * pk[2];
      }
      double jq[3];
      cross(pj, q, jq);
      total += pi[0] * jq[0] + pi[1] * jq[1] + pi[2] * jq[2];
    }
  }
  return total;
}

}  // namespace mrvol
