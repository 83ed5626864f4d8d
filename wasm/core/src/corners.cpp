#include "mrvol/corners.h"

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
}

void VertexCorners::ring(uint32_t u, std::vector<uint32_t>& out, bool* isBoundary) const {
  out.clear();
  if (count(u) == 0) return;
  // A boundary vertex has a neighbour v with face (u, v, .) but none (u, ., v): start there.
  uint32_t start = next[offset[u]];
  bool boundary = false;
  for (uint32_t c = offset[u]; c < offset[u + 1]; ++c) {
    bool isPrevOfSome = false;
    for (uint32_t d = offset[u]; d < offset[u + 1]; ++d)
      if (prev[d] == next[c]) { isPrevOfSome = true; break; }
    if (!isPrevOfSome) { start = next[c]; boundary = true; break; }
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
