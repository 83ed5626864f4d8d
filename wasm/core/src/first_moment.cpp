// The first moments of the enclosed solid (FirstMoment, volume_function.h).
#include <algorithm>
#include <array>
#include <string>

#include "mrvol/error.h"
#include "mrvol/thread_pool.h"
#include "mrvol/vector3.h"
#include "mrvol/volume_function.h"

namespace mrvol {

FirstMoment::FirstMoment(const std::vector<uint32_t>& faces, uint32_t vertexCount, int axis)
    : faces_(&faces), vertexCount_(vertexCount), axis_(axis) {
  if (axis < 0 || axis > 2) throw Error("a first moment's axis is 0, 1 or 2, got " + std::to_string(axis));
}

double FirstMoment::value(const double* p, double* grad) const {
  // Per triangle det(a, b, c) w with w = (a_k + b_k + c_k) / 24 - q_k / 6: at a the gradient is
  // (b x c) w + det / 24 e_k (likewise at b and c, cyclically).
  const auto& faces = *faces_;
  const int k = axis_;
  const double shift = centre_ / 6.0;
  if (grad) std::fill(grad, grad + size(), 0.0);
  double sum = 0, bc[3], t[3];
  for (size_t f = 0; f < faces.size(); f += 3) {
    const size_t ia = 3 * size_t(faces[f]), ib = 3 * size_t(faces[f + 1]), ic = 3 * size_t(faces[f + 2]);
    const double *a = p + ia, *b = p + ib, *c = p + ic;
    cross(b, c, bc);
    const double det = dot(a, bc), w = (a[k] + b[k] + c[k]) / 24.0 - shift;
    sum += det * w;
    if (!grad) continue;
    axpy(w, bc, grad + ia);
    cross(c, a, t);
    axpy(w, t, grad + ib);
    cross(a, b, t);
    axpy(w, t, grad + ic);
    const double e = det / 24.0;
    grad[ia + k] += e, grad[ib + k] += e, grad[ic + k] += e;
  }
  return sum;
}

bool FirstMoment::valuesWithGradients(const FineFunction* const axes[3], const double* p, double values[3], double* grad) {
  const FirstMoment* m[3];
  for (int k = 0; k < 3; ++k) {
    m[k] = dynamic_cast<const FirstMoment*>(axes[k]);
    if (!m[k] || m[k]->axis_ != k || m[k]->faces_ != m[0]->faces_ || m[k]->vertexCount_ != m[0]->vertexCount_) return false;
  }
  const auto& faces = *m[0]->faces_;
  const double shift[3] = {m[0]->centre_ / 6.0, m[1]->centre_ / 6.0, m[2]->centre_ / 6.0};
  std::fill(grad, grad + 3 * m[0]->size(), 0.0);
  double sum[3] = {0, 0, 0}, bc[3], ca[3], ab[3];
  for (size_t f = 0; f < faces.size(); f += 3) {
    const size_t ia = 3 * size_t(faces[f]), ib = 3 * size_t(faces[f + 1]), ic = 3 * size_t(faces[f + 2]);
    const double *a = p + ia, *b = p + ib, *c = p + ic;
    cross(b, c, bc);
    cross(c, a, ca);
    cross(a, b, ab);
    const double det = dot(a, bc), e = det / 24.0;
    double *ga = grad + 3 * ia, *gb = grad + 3 * ib, *gc = grad + 3 * ic;
    for (int k = 0; k < 3; ++k) {  // as value() for axis k
      const double w = (a[k] + b[k] + c[k]) / 24.0 - shift[k];
      sum[k] += det * w;
      axpy(w, bc, ga + 3 * k);
      axpy(w, ca, gb + 3 * k);
      axpy(w, ab, gc + 3 * k);
      ga[3 * k + k] += e, gb[3 * k + k] += e, gc[3 * k + k] += e;
    }
  }
  for (int k = 0; k < 3; ++k) values[k] = sum[k];
  return true;
}

double FirstMoment::volumeAndMoments(const std::vector<uint32_t>& faces, const double* p, const double centre[3],
                                     double moments[3]) {
  // Per triangle det(a, b, c), and det (a_k + b_k + c_k) per axis: M_k - q_k V = S_k / 24 - q_k D / 6.
  constexpr size_t kTrianglesPerBlock = size_t(1) << 15;
  const size_t triangles = faces.size() / 3, blocks = (triangles + kTrianglesPerBlock - 1) / kTrianglesPerBlock;
  std::vector<std::array<double, 4>> partial(blocks);
  parallelFor(0, blocks, 1, [&](size_t first, size_t end) {
    for (size_t block = first; block < end; ++block) {
      double d = 0, s0 = 0, s1 = 0, s2 = 0, bc[3];
      const size_t last = 3 * std::min(triangles, (block + 1) * kTrianglesPerBlock);
      for (size_t f = 3 * block * kTrianglesPerBlock; f < last; f += 3) {
        const double *a = p + 3 * size_t(faces[f]), *b = p + 3 * size_t(faces[f + 1]), *c = p + 3 * size_t(faces[f + 2]);
        cross(b, c, bc);
        const double det = dot(a, bc);
        d += det, s0 += det * (a[0] + b[0] + c[0]), s1 += det * (a[1] + b[1] + c[1]), s2 += det * (a[2] + b[2] + c[2]);
      }
      partial[block] = {d, s0, s1, s2};
    }
  });
  double sum[4] = {0, 0, 0, 0};
  for (const auto& block : partial)
    for (int k = 0; k < 4; ++k) sum[k] += block[k];
  for (int k = 0; k < 3; ++k) moments[k] = sum[k + 1] / 24.0 - centre[k] * sum[0] / 6.0;
  return sum[0] / 6.0;
}

}  // namespace mrvol
