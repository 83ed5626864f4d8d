// The volume functions over the fine positions: all triangles (by edges) and a part of them.
#include <algorithm>
#include <memory>
#include <string>

#include "mrvol/error.h"
#include "mrvol/vector3.h"
#include "mrvol/volume_function.h"

namespace mrvol {

namespace {
// The edge table of FineEdgeVolume for a validated closed or bounded manifold.
std::vector<uint32_t> edgeTable(const std::vector<uint32_t>& faces, uint32_t outside) {
  // Half-edge b -> c (a opposite) in the bucket of its smaller end: key = 2 x the larger end + 1
  // when b is the larger (reversed), and a (8 bytes a half: the pass is memory-bound).
  struct Half { uint32_t key, a; };
  if (outside > 0x7fffffffu) throw Error("the edge table holds at most 2^31 vertices, got " + std::to_string(outside));
  // Sorted by (smaller end, larger end, reversed), i.e. by (key, b): a counting sort by the smaller
  // end, then each bucket (a few halves) by insertion (linear time; no key is repeated more than
  // twice on a valid mesh).
  for (uint32_t v : faces)
    if (v >= outside) throw Error("face vertex " + std::to_string(v) + " is out of range (" + std::to_string(outside) + " vertices)");
  std::vector<uint32_t> start(size_t(outside) + 2, 0);
  for (size_t f = 0; f < faces.size(); f += 3)
    for (int k = 0; k < 3; ++k) ++start[size_t(std::min(faces[f + (k + 1) % 3], faces[f + (k + 2) % 3])) + 1];
  for (size_t v = 1; v < start.size(); ++v) start[v] += start[v - 1];
  // Every half is written below: no zeroing pass first.
  const std::unique_ptr<Half[]> halves(new Half[faces.size()]);
  for (size_t f = 0; f < faces.size(); f += 3)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = faces[f + k], b = faces[f + (k + 1) % 3], c = faces[f + (k + 2) % 3];
      halves[start[std::min(b, c)]++] = {2 * std::max(b, c) + uint32_t(b > c), a};
    }
  for (size_t v = start.size() - 1; v > 0; --v) start[v] = start[v - 1];  // back to the buckets' starts
  start[0] = 0;
  size_t edgeCount = 0;  // counted while each bucket is in the cache: the table is sized once
  for (size_t v = 0; v + 1 < start.size(); ++v) {
    for (uint32_t i = start[v] + 1; i < start[v + 1]; ++i) {
      const Half x = halves[i];
      uint32_t j = i;
      for (; j > start[v] && x.key < halves[j - 1].key; --j) halves[j] = halves[j - 1];
      halves[j] = x;
    }
    for (uint32_t i = start[v]; i < start[v + 1]; ++edgeCount)
      i += i + 1 < start[v + 1] && halves[i + 1].key >> 1 == halves[i].key >> 1 ? 2 : 1;
  }
  std::vector<uint32_t> edges(4 * edgeCount);
  uint32_t* out = edges.data();
  for (uint32_t v = 0; v + 1 < start.size(); ++v)
    for (uint32_t i = start[v]; i < start[v + 1];) {
      const Half& h = halves[i];
      const uint32_t other = h.key >> 1;
      const bool reversed = h.key & 1;
      const uint32_t b = reversed ? other : v, c = reversed ? v : other;
      const bool paired = i + 1 < start[v + 1] && halves[i + 1].key >> 1 == other;
      if (paired && (halves[i + 1].key == h.key || (i + 2 < start[v + 1] && halves[i + 2].key >> 1 == other)))
        throw Error("edge " + std::to_string(b) + "-" + std::to_string(c) + " is not a manifold edge of a consistently oriented mesh");
      out[0] = b, out[1] = c, out[2] = h.a, out[3] = paired ? halves[i + 1].a : outside;
      out += 4;
      i += paired ? 2 : 1;
    }
  return edges;
}
}  // namespace

FineEdgeVolume::FineEdgeVolume(const std::vector<uint32_t>& faces, uint32_t vertexCount)
    : vertexCount_(vertexCount), edges_(edgeTable(faces, vertexCount)) {}

double FineEdgeVolume::value(const double* p, double* grad) const {
  // Edge (b, c) enters triangle (a, b, c) as a . (b x c) and triangle (d, c, b) as -d . (b x c):
  // sum (a - d) . (b x c) over the edges is 3 sum over the triangles of their triple products, and
  // b x c / 6 is the share of the volume gradient at a (minus it at d). Half the cross products of
  // a pass over the triangles, and edges in order of their ends read the positions nearly in order.
  const uint32_t* e = edges_.data();
  const size_t m = edges_.size();
  double sum = 0, w[3];
  if (!grad) {
    for (size_t k = 0; k < m; k += 4) {
      cross(p + 3 * size_t(e[k]), p + 3 * size_t(e[k + 1]), w);
      sum += dotDifference(p + 3 * size_t(e[k + 2]), p + 3 * size_t(e[k + 3]), w);
    }
    return sum / 18.0;
  }
  std::fill(grad, grad + size(), 0.0);
  for (size_t k = 0; k < m; k += 4) {
    cross(p + 3 * size_t(e[k]), p + 3 * size_t(e[k + 1]), w);
    w[0] *= 1.0 / 6.0, w[1] *= 1.0 / 6.0, w[2] *= 1.0 / 6.0;
    const size_t a = 3 * size_t(e[k + 2]), d = 3 * size_t(e[k + 3]);
    sum += dotDifference(p + a, p + d, w);
    grad[a] += w[0], grad[a + 1] += w[1], grad[a + 2] += w[2];
    grad[d] -= w[0], grad[d + 1] -= w[1], grad[d + 2] -= w[2];
  }
  return sum / 3.0;
}

void FineEdgeVolume::alongDirection(const double* p, const double* q, double* k, bool lowKnown) const {
  // Per triangle the s^2 term of (a + s qa) . ((b + s qb) x (c + s qc)) is the cyclic sum
  // a . (qb x qc) + b . (qc x qa) + c . (qa x qb): over the edges as in value(),
  // k2 = sum (a - d) . (qb x qc) / 6 and k3 = sum (qa - qd) . (qb x qc) / 18; likewise
  // k0 = sum (a - d) . (b x c) / 18 and k1 = sum (qa - qd) . (b x c) / 6.
  const uint32_t* e = edges_.data();
  const size_t m = edges_.size();
  double w[3], c0 = 0, c1 = 0, c2 = 0, c3 = 0;
  if (lowKnown) {
    for (size_t i = 0; i < m; i += 4) {
      cross(q + 3 * size_t(e[i]), q + 3 * size_t(e[i + 1]), w);
      const size_t a = 3 * size_t(e[i + 2]), d = 3 * size_t(e[i + 3]);
      c2 += dotDifference(p + a, p + d, w);
      c3 += dotDifference(q + a, q + d, w);
    }
  } else {
    double wp[3];
    for (size_t i = 0; i < m; i += 4) {
      const size_t b = 3 * size_t(e[i]), c = 3 * size_t(e[i + 1]), a = 3 * size_t(e[i + 2]), d = 3 * size_t(e[i + 3]);
      cross(p + b, p + c, wp);
      cross(q + b, q + c, w);
      c0 += dotDifference(p + a, p + d, wp);
      c1 += dotDifference(q + a, q + d, wp);
      c2 += dotDifference(p + a, p + d, w);
      c3 += dotDifference(q + a, q + d, w);
    }
    k[0] = c0 / 18.0, k[1] = c1 / 6.0;
  }
  k[2] = c2 / 6.0, k[3] = c3 / 18.0;
}

TriangleSetVolume::TriangleSetVolume(const std::vector<uint32_t>& faces, uint32_t vertexCount,
                                     std::vector<uint8_t> triangles)
    : faces_(&faces), vertexCount_(vertexCount), triangles_(std::move(triangles)) {
  if (triangles_.size() != faces.size() / 3)
    throw Error("a triangle set needs one flag per triangle (" + std::to_string(faces.size() / 3) + "), got " +
                std::to_string(triangles_.size()));
}

double TriangleSetVolume::value(const double* p, double* grad) const {
  const auto& faces = *faces_;
  if (grad) std::fill(grad, grad + size(), 0.0);
  double sum = 0;
  double t[3];
  for (size_t f = 0, tri = 0; f < faces.size(); f += 3, ++tri) {
    if (!triangles_[tri]) continue;
    const double *a = p + 3 * size_t(faces[f]), *b = p + 3 * size_t(faces[f + 1]), *c = p + 3 * size_t(faces[f + 2]);
    cross(b, c, t);
    sum += dot(a, t);
    if (grad) {
      axpy(1.0 / 6.0, t, grad + 3 * size_t(faces[f]));
      cross(c, a, t);
      axpy(1.0 / 6.0, t, grad + 3 * size_t(faces[f + 1]));
      cross(a, b, t);
      axpy(1.0 / 6.0, t, grad + 3 * size_t(faces[f + 2]));
    }
  }
  return sum / 6.0;
}

void TriangleSetVolume::alongDirection(const double* p, const double* q, double* k, bool) const {
  // (a + s qa) . ((b + s qb) x (c + s qc)) term by term, per triangle.
  const auto& faces = *faces_;
  double c0 = 0, c1 = 0, c2 = 0, c3 = 0, bc[3], qbqc[3], mixed[3], t[3];
  for (size_t f = 0, tri = 0; f < faces.size(); f += 3, ++tri) {
    if (!triangles_[tri]) continue;
    const size_t ia = 3 * size_t(faces[f]), ib = 3 * size_t(faces[f + 1]), ic = 3 * size_t(faces[f + 2]);
    cross(p + ib, p + ic, bc);
    cross(q + ib, q + ic, qbqc);
    cross(q + ib, p + ic, mixed);
    cross(p + ib, q + ic, t);
    mixed[0] += t[0], mixed[1] += t[1], mixed[2] += t[2];
    c0 += dot(p + ia, bc);
    c1 += dot(q + ia, bc) + dot(p + ia, mixed);
    c2 += dot(q + ia, mixed) + dot(p + ia, qbqc);
    c3 += dot(q + ia, qbqc);
  }
  k[0] = c0 / 6.0, k[1] = c1 / 6.0, k[2] = c2 / 6.0, k[3] = c3 / 6.0;
}

}  // namespace mrvol
