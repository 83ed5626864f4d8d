// The first moments of the enclosed solid (FirstMoment, volume_function.h).
#include <algorithm>
#include <string>

#include "mrvol/error.h"
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

}  // namespace mrvol
