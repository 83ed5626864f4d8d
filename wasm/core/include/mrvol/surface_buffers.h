// What a renderer uploads after each edit: the fine positions and area-weighted unit vertex normals
// as float32, 3 per vertex in the caller's vertex order, rewritten in place (a renderer views them in
// WASM memory without copies: three.js BufferAttributes over them). They follow the editor's fine
// positions (doubles, hierarchy order, relative to the reference point; see stencil_table.h), which
// are brought up to date incrementally; this pass converts and reorders them and sums face normals:
// all of them, or, when only the stencils of a few cage vertices moved, the vertices they touched
// and the normals around them.
#pragma once
#include <cstdint>
#include <vector>

#include "mrvol/hierarchy.h"
#include "mrvol/mesh.h"
#include "mrvol/stencil_table.h"

namespace mrvol {

class SurfaceBuffers {
 public:
  explicit SurfaceBuffers(const Hierarchy& hierarchy);

  // Brings the buffers in step with `fine` (3 N doubles, hierarchy order, relative to `origin`),
  // whose version is `version` (nothing is done for the version already written). Normals only when
  // asked (a renderer may compute them itself); asked later, they catch up.
  // `changes`: what changed in `fine` since the previous call (FinePositions::takeChanges).
  void update(const double* fine, Vec3 origin, uint64_t version, const FinePositions::Changes& changes, bool withNormals);

  size_t vertexCount() const { return vertexCount_; }
  const float* positions() const { return positions_.data(); }
  const float* normals() const { return normals_.data(); }
  // Changes whenever the positions written change.
  uint64_t version() const { return writes_; }
  // The caller's vertices [first, end) that the last write of the positions, and of the normals,
  // rewrote (a renderer uploads only those; everything after a move of the whole cage).
  uint32_t positionsFirst() const { return positionsRange_[0]; }
  uint32_t positionsEnd() const { return positionsRange_[1]; }
  uint32_t normalsFirst() const { return normalsRange_[0]; }
  uint32_t normalsEnd() const { return normalsRange_[1]; }

 private:
  void writePositions(const double* fine, Vec3 origin);
  void writeNormals(const double* fine);
  void writeSomeNormals(const double* fine);  // around pendingNormals_
  static void merge(FinePositions::Changes& into, const FinePositions::Changes& changes);

  const Hierarchy* hierarchy_;
  size_t vertexCount_;
  bool callerIsHierarchyOrder_;  // then no reordering (meshes written by our own subdivision)
  std::vector<float> positions_, normals_;
  // The normals' faces (caller's indices, ordered by their last vertex) and scratch, caller's order,
  // 4 floats a vertex (one SIMD register; a 3-float stride is slower: overlapping stores and loads
  // stall): the positions relative to the reference point, the sums of the face cross products.
  std::vector<uint32_t> faces_;
  std::vector<float> relative_, sums_;
  // For updates of a few vertices: the faces around each vertex (CSR, caller's order), a mark per
  // vertex, and the changes not yet written.
  std::vector<uint32_t> vertexFaceStart_, vertexFaces_, mark_, affected_;
  uint32_t markRound_ = 0;
  FinePositions::Changes pendingPositions_, pendingNormals_;
  bool normalsWritten_ = false;
  uint32_t positionsRange_[2] = {0, 0}, normalsRange_[2] = {0, 0};
  uint64_t positionsOf_ = 0, normalsOf_ = 0;  // fine version written (+1; 0: none yet)
  uint64_t writes_ = 0;
};

}  // namespace mrvol
