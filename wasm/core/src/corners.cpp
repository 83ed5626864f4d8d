#include "mrvol/corners.h"

#include <algorithm>

namespace mrvol {

VertexCorners::VertexCorners(const uint32_t* faces, size_t faceCount, size_t vertexCount) {
  offset.assign(vertexCount + 1, 0);
  for (size_t i = 0; i < 3 * faceCount; ++i) ++offset[faces[i] + 1];
  for (size_t v = 0; v < vertexCount; ++v) offset[v + 1] += offset[v];
  next.resize(3 * faceCount);
  prev.resize(3 * faceCount);
  face.resize(3 * faceCount);
  std::vector<uint32_t> fill(offset.begin(), offset.end() - 1);
  for (size_t f = 0; f < faceCount; ++f) {
    const uint32_t* t = faces + 3 * f;
    for (int k = 0; k < 3; ++k) {
      uint32_t c = fill[t[k]]++;
      next[c] = t[(k + 1) % 3];
      prev[c] = t[(k + 2) % 3];
      face[c] = static_cast<uint32_t>(f);
    }
  }
  for (size_t v = 0; v < vertexCount; ++v) {
    if (count(uint32_t(v)) <= kScanLimit) continue;
    if (sortedStart.empty()) sortedStart.assign(vertexCount, kNone);
    sortedStart[v] = uint32_t(sortedCorners.size());
    for (uint32_t c = offset[v]; c < offset[v + 1]; ++c) sortedCorners.push_back(c);
    std::sort(sortedCorners.begin() + sortedStart[v], sortedCorners.end(),
              [&](uint32_t a, uint32_t b) { return next[a] != next[b] ? next[a] < next[b] : a < b; });
  }
}

uint32_t VertexCorners::cornerTo(uint32_t u, uint32_t v) const {
  if (count(u) > kScanLimit) {
    const auto first = sortedCorners.begin() + sortedStart[u], last = first + count(u);
    auto it = std::lower_bound(first, last, v, [&](uint32_t c, uint32_t value) { return next[c] < value; });
    return it != last && next[*it] == v ? *it : kNone;
  }
  for (uint32_t c = offset[u]; c < offset[u + 1]; ++c)
    if (next[c] == v) return c;
  return kNone;
}

uint32_t VertexCorners::oppositeSorted(uint32_t u, uint32_t v) const {
  const uint32_t c = cornerTo(u, v);
  return c == kNone ? kNone : prev[c];
}

void VertexCorners::ring(uint32_t u, std::vector<uint32_t>& out, bool* isBoundary) const {
  out.clear();
  if (count(u) == 0) return;
  // A boundary vertex has a neighbour v with face (u, v, .) but none (u, ., v): start there.
  uint32_t start = next[offset[u]];
  bool boundary = false;
  for (uint32_t c = offset[u]; c < offset[u + 1]; ++c) {
    // next[c] is the prev of some corner of u iff a face (u, x, next[c]) exists, iff the face
    // (next[c], u, x) does: a corner of next[c] towards u.
    if (cornerTo(next[c], u) == kNone) { start = next[c]; boundary = true; break; }
  }
  if (isBoundary) *isBoundary = boundary;
  ringFrom(u, start, out);
}

void VertexCorners::ringFrom(uint32_t u, uint32_t start, std::vector<uint32_t>& out) const {
  out.clear();
  uint32_t v = start;
  const uint32_t limit = count(u) + 1;
  for (uint32_t steps = 0; steps < limit; ++steps) {
    out.push_back(v);
    uint32_t w = opposite(u, v);
    if (w == kNone || w == start) return;
    v = w;
  }
}

}  // namespace mrvol
