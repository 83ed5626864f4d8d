// Per-vertex corner lists: the faces around each vertex, a compact substitute for a half-edge
// structure. Built once in O(#F) by a counting sort; every query reads a vertex's few corners.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace mrvol {

constexpr uint32_t kNone = 0xffffffffu;

// For vertex u, each face (u, v, w) (rotated so that u comes first, orientation kept) gives a
// corner with next = v, prev = w. Edge u->v is traversed by that face; w is opposite the edge.
struct VertexCorners {
  std::vector<uint32_t> offset;  // #V + 1
  std::vector<uint32_t> next, prev, face;
  // Vertices of valence above kScanLimit also keep their corners sorted by next, so that opposite()
  // is a binary search there: a hub of valence k then costs O(k log k) to walk, not O(k^2).
  static constexpr uint32_t kScanLimit = 24;
  std::vector<uint32_t> sortedStart;  // per vertex: start of its block in sortedCorners (empty: no hub)
  std::vector<uint32_t> sortedCorners;

  VertexCorners() = default;
  VertexCorners(const uint32_t* faces, size_t faceCount, size_t vertexCount);

  uint32_t begin(uint32_t u) const { return offset[u]; }
  uint32_t end(uint32_t u) const { return offset[u + 1]; }
  uint32_t count(uint32_t u) const { return offset[u + 1] - offset[u]; }

  // w with (u, v, w) a face, or kNone.
  uint32_t opposite(uint32_t u, uint32_t v) const {
    if (offset[u + 1] - offset[u] > kScanLimit) return oppositeSorted(u, v);
    for (uint32_t c = offset[u]; c < offset[u + 1]; ++c)
      if (next[c] == v) return prev[c];
    return kNone;
  }
  // Corner of u whose next is v (the face u -> v), or kNone.
  uint32_t cornerTo(uint32_t u, uint32_t v) const;
  // Neighbours of u in counter-clockwise order. For a boundary vertex the ring starts at the
  // boundary neighbour v for which u->v has a face and v->u does not, and is open.
  // Assumes a validated manifold.
  void ring(uint32_t u, std::vector<uint32_t>& out, bool* isBoundary = nullptr) const;
  // Ring starting at a given neighbour (for stencils indexed from an edge's other end).
  void ringFrom(uint32_t u, uint32_t start, std::vector<uint32_t>& out) const;

 private:
  uint32_t oppositeSorted(uint32_t u, uint32_t v) const;
};

}  // namespace mrvol
