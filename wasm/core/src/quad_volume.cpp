#include "mrvol/quad_volume.h"

#include <algorithm>

namespace mrvol {

namespace {
inline double det3(const double* a, const double* b, const double* c) {
  return a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
}
inline void crossAdd(const double* b, const double* c, double w, double* out) {
  out[0] += w * (b[1] * c[2] - b[2] * c[1]);
  out[1] += w * (b[2] * c[0] - b[0] * c[2]);
  out[2] += w * (b[0] * c[1] - b[1] * c[0]);
}
}  // namespace

FineForm bilinearPatchForm(const std::vector<uint32_t>& quads) {
  FineForm form;
  form.corners.reserve(quads.size() * 3);
  form.weights.reserve(quads.size());
  for (size_t q = 0; q + 3 < quads.size(); q += 4) {
    const uint32_t a = quads[q], b = quads[q + 1], c = quads[q + 2], d = quads[q + 3];
    form.corners.insert(form.corners.end(), {a, b, c, a, c, d, a, b, d, b, c, d});
    form.weights.insert(form.weights.end(), 4, 1.0 / 12.0);
  }
  return form;
}

Vec3 quadReferencePoint(const QuadMesh& mesh) {
  TriangleMesh t;
  t.positions = mesh.positions;
  t.faces = triangulateQuads(mesh.quads);
  return volumeReferencePoint(t);
}

double bilinearVolume(const QuadMesh& mesh) {
  return bilinearPatchForm(mesh.quads).evaluate(mesh.positions.data(), quadReferencePoint(mesh));
}

double FormVolume::value(const double* x, double* gradient) const {
  const FineForm& f = *form_;
  double sum = 0;
  if (gradient) std::fill(gradient, gradient + size(), 0.0);
  for (size_t t = 0; t < f.size(); ++t) {
    const double* a = x + 3 * size_t(f.corners[3 * t]);
    const double* b = x + 3 * size_t(f.corners[3 * t + 1]);
    const double* c = x + 3 * size_t(f.corners[3 * t + 2]);
    const double w = f.weights[t];
    sum += w * det3(a, b, c);
    if (gradient) {
      crossAdd(b, c, w, gradient + 3 * size_t(f.corners[3 * t]));
      crossAdd(c, a, w, gradient + 3 * size_t(f.corners[3 * t + 1]));
      crossAdd(a, b, w, gradient + 3 * size_t(f.corners[3 * t + 2]));
    }
  }
  return sum;
}

void FormVolume::alongDirection(const double* x, const double* d, double* k, bool) const {
  // det(a + sA, b + sB, c + sC) expanded by multilinearity.
  const FineForm& f = *form_;
  double k0 = 0, k1 = 0, k2 = 0, k3 = 0;
  for (size_t t = 0; t < f.size(); ++t) {
    const size_t ia = 3 * size_t(f.corners[3 * t]), ib = 3 * size_t(f.corners[3 * t + 1]),
                 ic = 3 * size_t(f.corners[3 * t + 2]);
    const double *a = x + ia, *b = x + ib, *c = x + ic, *A = d + ia, *B = d + ib, *C = d + ic;
    const double w = f.weights[t];
    k0 += w * det3(a, b, c);
    k1 += w * (det3(A, b, c) + det3(a, B, c) + det3(a, b, C));
    k2 += w * (det3(a, B, C) + det3(A, b, C) + det3(A, B, c));
    k3 += w * det3(A, B, C);
  }
  k[0] = k0, k[1] = k1, k[2] = k2, k[3] = k3;
}

}  // namespace mrvol
