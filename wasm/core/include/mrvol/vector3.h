// Small operations on 3-vectors stored as three consecutive doubles in flat arrays (positions,
// coefficients, gradients): the core's hot loops index such arrays directly.
#pragma once

namespace mrvol {

inline void cross(const double* a, const double* b, double* out) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}
inline double dot(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
// out += w a
inline void axpy(double w, const double* a, double* out) { out[0] += w * a[0], out[1] += w * a[1], out[2] += w * a[2]; }
// (a - d) . w
inline double dotDifference(const double* a, const double* d, const double* w) {
  return (a[0] - d[0]) * w[0] + (a[1] - d[1]) * w[1] + (a[2] - d[2]) * w[2];
}

}  // namespace mrvol
