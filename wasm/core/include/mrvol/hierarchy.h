// The semi-regular hierarchy: connectivity of every level of n 1-to-4 splits of a base mesh.
// Built once; positions, coefficients and tensors are arrays beside it, indexed in its numbering.
#pragma once
#include <cstdint>
#include <vector>

#include "mrvol/mesh.h"

namespace mrvol {

// Hierarchy numbering: the base vertices first, then the vertices born at level 1, then level 2 ...
// so that the level-l mesh uses exactly the indices [0, vertexCount[l]). A vertex's *depth* is the
// level where it is born. An odd vertex (depth >= 1) sits on the coarse edge between its two *ends*
// and has one *wing* on each side (the third vertices of the coarse triangles; kNone on a boundary).
struct Hierarchy {
  int levels = 0;                               // n
  std::vector<uint32_t> vertexCount;            // V_0 .. V_n
  std::vector<std::vector<uint32_t>> faces;     // faces[l]: 3 * F_l indices, level-l triangles
  std::vector<uint32_t> ends;                   // 2 per vertex (kNone for base vertices)
  std::vector<uint32_t> wings;                  // 2 per vertex (kNone where missing)
  std::vector<uint8_t> boundary;                // 1 for vertices on the boundary of the mesh
  std::vector<uint32_t> inputIndex;             // hierarchy index -> caller's vertex index
  std::vector<uint32_t> hierarchyIndex;         // caller's vertex index -> hierarchy index

  size_t fineVertexCount() const { return vertexCount.back(); }
  const std::vector<uint32_t>& fineFaces() const { return faces.back(); }
  int depth(uint32_t v) const;
  bool closed() const;

  // n splits of a base mesh (validated by the caller). New vertices are numbered after the base's
  // own, whose order is kept, so input order equals hierarchy order.
  static Hierarchy subdivide(const TriangleMesh& base, int levels);

  // Recovers the hierarchy of a mesh whose connectivity is 1-to-4 splits of a base mesh, whatever
  // its vertex order (quadrisection detection). Finds as many levels as there are, at most
  // maxLevels. A mesh that is no split at all gives a hierarchy with 0 levels. Validates the mesh
  // unless the caller already has (`validated`: validateMesh passed on these very arrays).
  static Hierarchy detect(const TriangleMesh& fine, int maxLevels = 16, bool validated = false);
  // The same on a validated mesh given by its faces and vertex count (positions play no part);
  // `fineCorners`, when given, are the fine faces' corner lists (validateMesh's), taken over.
  // `localToCaller`, when given: the faces (and corners) are in a local numbering of the caller's
  // vertices (vertex_order.h), local -> caller index; the hierarchy returned is the very one the
  // caller's numbering gives (indices, order, ends).
  static Hierarchy detectValidated(const std::vector<uint32_t>& fineFaces, size_t vertexCount, int maxLevels,
                                   VertexCorners* fineCorners = nullptr,
                                   const std::vector<uint32_t>* localToCaller = nullptr);

  // Reorders per-vertex 3-vectors between the caller's order and the hierarchy's.
  void toHierarchyOrder(const double* input, double* out) const;
  void toInputOrder(const double* hierarchyOrdered, double* out) const;
};

}  // namespace mrvol
