// A trilinear form of the fine positions as a volume function (FormVolume, volume_function.h).
#include <algorithm>
#include <numeric>
#include <string>

#include "mrvol/error.h"
#include "mrvol/vector3.h"
#include "mrvol/volume_function.h"
#include "mrvol/volume_tensor.h"

namespace mrvol {

FormVolume::FormVolume(const FineForm& form, uint32_t vertexCount) : vertexCount_(vertexCount) {
  const size_t m = form.size();
  for (uint32_t v : form.corners)
    if (v >= vertexCount) throw Error("a form entry names vertex " + std::to_string(v) + " of " + std::to_string(vertexCount));
  // Entries in order of their pair (a, b): each run shares one cross product.
  std::vector<size_t> order(m);
  std::iota(order.begin(), order.end(), size_t(0));
  auto key = [&](size_t t) { return uint64_t(form.corners[3 * t]) << 32 | form.corners[3 * t + 1]; };
  std::stable_sort(order.begin(), order.end(), [&](size_t x, size_t y) { return key(x) < key(y); });
  c_.reserve(m);
  weight_.reserve(m);
  for (size_t i = 0; i < m; ++i) {
    const size_t t = order[i];
    if (i == 0 || key(t) != key(order[i - 1])) {
      pairA_.push_back(form.corners[3 * t]);
      pairB_.push_back(form.corners[3 * t + 1]);
      runStart_.push_back(c_.size());
    }
    c_.push_back(form.corners[3 * t + 2]);
    weight_.push_back(form.weights[t]);
  }
  runStart_.push_back(c_.size());
}

double FormVolume::value(const double* p, double* grad) const {
  // Per pair (a, b): S = sum_c w_c p_c; the run adds (p_a x p_b) . S, and its gradient is
  // p_b x S at a, S x p_a at b and w_c p_a x p_b at each c.
  if (grad) std::fill(grad, grad + size(), 0.0);
  double sum = 0, ab[3], t[3];
  for (size_t r = 0; r < pairA_.size(); ++r) {
    const double *a = p + 3 * size_t(pairA_[r]), *b = p + 3 * size_t(pairB_[r]);
    double S[3] = {0, 0, 0};
    for (uint64_t e = runStart_[r]; e < runStart_[r + 1]; ++e) axpy(weight_[e], p + 3 * size_t(c_[e]), S);
    cross(a, b, ab);
    sum += dot(ab, S);
    if (!grad) continue;
    for (uint64_t e = runStart_[r]; e < runStart_[r + 1]; ++e) axpy(weight_[e], ab, grad + 3 * size_t(c_[e]));
    cross(b, S, t);
    axpy(1.0, t, grad + 3 * size_t(pairA_[r]));
    cross(S, a, t);
    axpy(1.0, t, grad + 3 * size_t(pairB_[r]));
  }
  return sum;
}

void FormVolume::alongDirection(const double* p, const double* q, double* k, bool) const {
  // Per pair: (a + s qa) x (b + s qb) = A0 + s A1 + s^2 A2 against S + s T (T the run's sum of w_c q_c).
  double c0 = 0, c1 = 0, c2 = 0, c3 = 0, A0[3], A1[3], A2[3], t[3];
  for (size_t r = 0; r < pairA_.size(); ++r) {
    const size_t ia = 3 * size_t(pairA_[r]), ib = 3 * size_t(pairB_[r]);
    double S[3] = {0, 0, 0}, T[3] = {0, 0, 0};
    for (uint64_t e = runStart_[r]; e < runStart_[r + 1]; ++e) {
      axpy(weight_[e], p + 3 * size_t(c_[e]), S);
      axpy(weight_[e], q + 3 * size_t(c_[e]), T);
    }
    cross(p + ia, p + ib, A0);
    cross(q + ia, p + ib, A1);
    cross(p + ia, q + ib, t);
    A1[0] += t[0], A1[1] += t[1], A1[2] += t[2];
    cross(q + ia, q + ib, A2);
    c0 += dot(A0, S);
    c1 += dot(A0, T) + dot(A1, S);
    c2 += dot(A1, T) + dot(A2, S);
    c3 += dot(A2, T);
  }
  k[0] = c0, k[1] = c1, k[2] = c2, k[3] = c3;
}

}  // namespace mrvol
