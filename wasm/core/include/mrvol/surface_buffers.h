// What a renderer uploads after each edit: the fine positions and area-weighted unit vertex normals
// as float32, 3 per vertex in the caller's vertex order, rewritten in place (a renderer views them in
// WASM memory without copies: three.js BufferAttributes over them). They follow the editor's fine
// positions (doubles, hierarchy order, relative to the reference point; see stencil_table.h), which
// are brought up to date incrementally; this pass converts and reorders them and sums face normals.
#pragma once
#include <cstdint>
#include <vector>

#include "mrvol/hierarchy.h"
#include "mrvol/mesh.h"

namespace mrvol {

class SurfaceBuffers {
 public:
  explicit SurfaceBuffers(const Hierarchy& hierarchy);

  // Brings the buffers in step with `fine` (3 N doubles, hierarchy order, relative to `origin`),
  // whose version is `version` (nothing is done for the version already written). Normals only when
  // asked (a renderer may compute them itself); asked later, they catch up.
  void update(const double* fine, Vec3 origin, uint64_t version, bool withNormals);

  size_t vertexCount() const { return vertexCount_; }
  const float* positions() const { return positions_.data(); }
  const float* normals() const { return normals_.data(); }
  // Changes whenever the positions written change.
  uint64_t version() const { return writes_; }

 private:
  void writePositions(const double* fine, Vec3 origin);
  void writeNormals(const double* fine);

  const Hierarchy* hierarchy_;
  size_t vertexCount_;
  bool callerIsHierarchyOrder_;  // then no reordering (meshes written by our own subdivision)
  std::vector<float> positions_, normals_;
  // The normals' faces (caller's indices, ordered by their last vertex) and scratch, caller's order,
  // 4 floats a vertex (one SIMD register; a 3-float stride is slower: overlapping stores and loads
  // stall): the positions relative to the reference point, the sums of the face cross products.
  std::vector<uint32_t> faces_;
  std::vector<float> relative_, sums_;
  uint64_t positionsOf_ = 0, normalsOf_ = 0;  // fine version written (+1; 0: none yet)
  uint64_t writes_ = 0;
};

}  // namespace mrvol
