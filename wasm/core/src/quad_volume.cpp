#include "mrvol/quad_volume.h"

#include <algorithm>
#include <string>

#include "mrvol/error.h"

namespace mrvol {

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

RegionForm bilinearPatchRegions(const QuadHierarchy& q, int level) {
  if (level < 0 || level > q.levels())
    throw Error("level " + std::to_string(level) + " is out of range: this mesh has levels 0.." + std::to_string(q.levels()));
  RegionForm out;
  out.form = bilinearPatchForm(q.fineQuads());
  const int shift = 2 * (q.levels() - level);
  out.regionCount = q.quads[level].size() / 4;
  out.region.resize(out.form.size());
  for (size_t t = 0; t < out.region.size(); ++t) out.region[t] = uint32_t((t / 4) >> shift);
  // (b, c, d) -> (c, d, b): the face point carries it, orientation kept.
  for (size_t t = 3; t < out.region.size(); t += 4) std::rotate(&out.form.corners[3 * t], &out.form.corners[3 * t + 1], &out.form.corners[3 * t + 3]);
  return out;
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

// f = s . (u x w), s = a + b + c + d, u = c - a, w = d - b; the volume is f / 24.
double QuadPatchVolume::value(const double* x, double* gradient) const {
  const std::vector<uint32_t>& q = *quads_;
  double sum = 0;
  if (gradient) std::fill(gradient, gradient + size(), 0.0);
  for (size_t f = 0; f < q.size(); f += 4) {
    const double *a = x + 3 * size_t(q[f]), *b = x + 3 * size_t(q[f + 1]), *c = x + 3 * size_t(q[f + 2]),
                 *d = x + 3 * size_t(q[f + 3]);
    double s[3], u[3], w[3], n[3];
    for (int k = 0; k < 3; ++k) s[k] = a[k] + b[k] + c[k] + d[k], u[k] = c[k] - a[k], w[k] = d[k] - b[k];
    n[0] = u[1] * w[2] - u[2] * w[1], n[1] = u[2] * w[0] - u[0] * w[2], n[2] = u[0] * w[1] - u[1] * w[0];
    sum += s[0] * n[0] + s[1] * n[1] + s[2] * n[2];
    if (gradient) {
      // df/da = n - w x s, df/dc = n + w x s, df/db = n - s x u, df/dd = n + s x u.
      double ws[3], su[3];
      ws[0] = w[1] * s[2] - w[2] * s[1], ws[1] = w[2] * s[0] - w[0] * s[2], ws[2] = w[0] * s[1] - w[1] * s[0];
      su[0] = s[1] * u[2] - s[2] * u[1], su[1] = s[2] * u[0] - s[0] * u[2], su[2] = s[0] * u[1] - s[1] * u[0];
      double *ga = gradient + 3 * size_t(q[f]), *gb = gradient + 3 * size_t(q[f + 1]),
             *gc = gradient + 3 * size_t(q[f + 2]), *gd = gradient + 3 * size_t(q[f + 3]);
      for (int k = 0; k < 3; ++k) {
        ga[k] += (n[k] - ws[k]) / 24.0;
        gc[k] += (n[k] + ws[k]) / 24.0;
        gb[k] += (n[k] - su[k]) / 24.0;
        gd[k] += (n[k] + su[k]) / 24.0;
      }
    }
  }
  return sum / 24.0;
}

void QuadPatchVolume::alongDirection(const double* x, const double* dir, double* k, bool) const {
  const std::vector<uint32_t>& q = *quads_;
  auto triple = [](const double* s, const double* u, const double* w) {
    return s[0] * (u[1] * w[2] - u[2] * w[1]) + s[1] * (u[2] * w[0] - u[0] * w[2]) + s[2] * (u[0] * w[1] - u[1] * w[0]);
  };
  double k0 = 0, k1 = 0, k2 = 0, k3 = 0;
  for (size_t f = 0; f < q.size(); f += 4) {
    const size_t ia = 3 * size_t(q[f]), ib = 3 * size_t(q[f + 1]), ic = 3 * size_t(q[f + 2]), id = 3 * size_t(q[f + 3]);
    double s0[3], u0[3], w0[3], s1[3], u1[3], w1[3];
    for (int j = 0; j < 3; ++j) {
      s0[j] = x[ia + j] + x[ib + j] + x[ic + j] + x[id + j], u0[j] = x[ic + j] - x[ia + j], w0[j] = x[id + j] - x[ib + j];
      s1[j] = dir[ia + j] + dir[ib + j] + dir[ic + j] + dir[id + j], u1[j] = dir[ic + j] - dir[ia + j],
      w1[j] = dir[id + j] - dir[ib + j];
    }
    k0 += triple(s0, u0, w0);
    k1 += triple(s1, u0, w0) + triple(s0, u1, w0) + triple(s0, u0, w1);
    k2 += triple(s0, u1, w1) + triple(s1, u1, w0) + triple(s1, u0, w1);
    k3 += triple(s1, u1, w1);
  }
  k[0] = k0 / 24.0, k[1] = k1 / 24.0, k[2] = k2 / 24.0, k[3] = k3 / 24.0;
}

}  // namespace mrvol
