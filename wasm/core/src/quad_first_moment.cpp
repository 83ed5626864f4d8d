// The first moments of the solid enclosed by bilinear patches (QuadFirstMoment, quad_volume.h).
#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "mrvol/error.h"
#include "mrvol/quad_volume.h"
#include "mrvol/vector3.h"

namespace mrvol {

namespace {
// The 2 x 2 Gauss points of [0, 1]^2 (weight 1/4 each): the corners' bilinear weights N_i and
// their derivatives along u and v, corners in patch order p0 (0,0), p1 (1,0), p2 (1,1), p3 (0,1).
struct PatchPoint {
  double n[4], nu[4], nv[4];
};

std::array<PatchPoint, 4> gaussPoints() {
  const double lo = 0.5 - 0.5 / std::sqrt(3.0), hi = 0.5 + 0.5 / std::sqrt(3.0);
  std::array<PatchPoint, 4> points;
  const double uv[4][2] = {{lo, lo}, {hi, lo}, {lo, hi}, {hi, hi}};
  for (int g = 0; g < 4; ++g) {
    const double u = uv[g][0], v = uv[g][1];
    points[g] = {{(1 - u) * (1 - v), u * (1 - v), u * v, (1 - u) * v},
                 {-(1 - v), 1 - v, v, -v},
                 {-(1 - u), -u, u, 1 - u}};
  }
  return points;
}
}  // namespace

QuadFirstMoment::QuadFirstMoment(const std::vector<uint32_t>& quads, uint32_t vertexCount, int axis)
    : quads_(&quads), vertexCount_(vertexCount), axis_(axis) {
  if (axis < 0 || axis > 2) throw Error("a first moment's axis is 0, 1 or 2, got " + std::to_string(axis));
}

double QuadFirstMoment::value(const double* x, double* grad) const {
  // At a Gauss point, with D = det(p, p_u, p_v): f = D (p_k / 4 - q_k / 3), and at corner i
  // df/dp_i = N_i D / 4 e_k + (p_k / 4 - q_k / 3) (N_i (p_u x p_v) + N_i,u (p_v x p) + N_i,v (p x p_u)).
  static const std::array<PatchPoint, 4> points = gaussPoints();
  const std::vector<uint32_t>& q = *quads_;
  const int k = axis_;
  if (grad) std::fill(grad, grad + size(), 0.0);
  double sum = 0;
  for (size_t f = 0; f < q.size(); f += 4) {
    const double* corner[4];
    for (int i = 0; i < 4; ++i) corner[i] = x + 3 * size_t(q[f + i]);
    for (const PatchPoint& g : points) {
      double p[3] = {0, 0, 0}, pu[3] = {0, 0, 0}, pv[3] = {0, 0, 0};
      for (int i = 0; i < 4; ++i) {
        axpy(g.n[i], corner[i], p);
        axpy(g.nu[i], corner[i], pu);
        axpy(g.nv[i], corner[i], pv);
      }
      double uxv[3];
      cross(pu, pv, uxv);
      const double d = dot(p, uxv), w = p[k] / 4.0 - centre_ / 3.0;
      sum += 0.25 * d * w;  // Gauss weight 1/4
      if (!grad) continue;
      double vxp[3], pxu[3];
      cross(pv, p, vxp);
      cross(p, pu, pxu);
      for (int i = 0; i < 4; ++i) {
        double* gi = grad + 3 * size_t(q[f + i]);
        for (int c = 0; c < 3; ++c) gi[c] += 0.25 * w * (g.n[i] * uxv[c] + g.nu[i] * vxp[c] + g.nv[i] * pxu[c]);
        gi[k] += 0.25 * g.n[i] * d / 4.0;
      }
    }
  }
  return sum;
}

}  // namespace mrvol
