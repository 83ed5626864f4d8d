// What a renderer uploads after each edit: the fine positions and area-weighted unit vertex normals
// as float32, 3 per vertex in the caller's vertex order, rewritten in place (a renderer views them in
// WASM memory without copies: three.js BufferAttributes over them). They follow the editor's fine
// positions (doubles, hierarchy order, relative to the reference point; see stencil_table.h), which
// are brought up to date incrementally; this pass converts and reorders them and sums face normals:
// all of them, or, when only the stencils of a few cage vertices moved, the vertices they touched
// and the normals around them. From an editor, the positions come straight from the cage through a
// CageBasisTable: base + S (cage - cage at base), one sequential pass (or the rows of a few moved
// cage vertices' columns), the editor's fine positions untouched.
// Normals: each vertex sums the cross products of its faces (a gather: no scattered adds, no
// clearing, written in order).
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "mrvol/cage_basis_table.h"
#include "mrvol/hierarchy.h"
#include "mrvol/mesh.h"
#include "mrvol/stencil_table.h"

namespace mrvol {

class VolumeEditor;

class SurfaceBuffers {
 public:
  // The whole passes (positions, relative positions, normals) run on the thread pool's threads
  // (thread_pool.h), in blocks of at least this many vertices; the same results at any thread count.
  static constexpr size_t kVerticesPerBlock = 16384;

  explicit SurfaceBuffers(const Hierarchy& hierarchy);

  // Brings the buffers in step with the editor (one editor per buffers): from its cage through a
  // CageBasisTable (built on the first call), else (no table: too many entries) from its fine positions.
  void update(const VolumeEditor& editor, bool withNormals);

  // Brings the buffers in step with `fine` (3 N doubles, hierarchy order, relative to `origin`),
  // whose version is `version` (nothing is done for the version already written). Normals only when
  // asked (a renderer may compute them itself); asked later, they catch up.
  // `changes`: what changed in `fine` since the previous call (FinePositions::takeChanges).
  void update(const double* fine, Vec3 origin, uint64_t version, const FinePositions::Changes& changes, bool withNormals);

  size_t vertexCount() const { return vertexCount_; }
  // Whether the buffers work in the caller's order (it is local) rather than an order of their own
  // (known after the first update; for tests).
  bool inCallerOrder() const { return inCallerOrder_; }
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
  void writeRelative(const double* fine);  // relative_ from fine
  void writeNormals(const double* fine);
  void writeSomeNormals(const double* fine);  // around pendingNormals_
  void gatherSomeNormals(const std::vector<uint32_t>& moved);  // around these (caller's order), from relative_
  void writeTableNormals();  // the cage path's: all (normalsStale_) or around pendingRows_
  void buildRing();  // ring_ and the local order
  void layOut();     // order_, slot_, and the rings in that order
  void gatherNormals();  // every vertex's, from relative_
  static void merge(FinePositions::Changes& into, const FinePositions::Changes& changes);

  const Hierarchy* hierarchy_;
  size_t vertexCount_;
  bool callerIsHierarchyOrder_;  // then no reordering (meshes written by our own subdivision)
  std::vector<float> positions_, normals_;
  // The buffers' own vertex order, local (neighbours near each other: the normals' gather stays in
  // cache): order_[i] is the caller's vertex in slot i, slot_ its inverse. Everything below except
  // the output buffers is in slots.
  std::vector<uint32_t> order_, slot_;
  bool inCallerOrder_ = false;
  // The positions relative to the reference point, 4 floats a slot (one SIMD register; lane 3 zero).
  std::vector<float> relative_;
  // The faces around each vertex v (CSR, by slot, neighbours named by slot): when its fan is closed (closedRing_), its
  // neighbors in order (face i: v, ring i, ring i + 1), else for each face (v, a, b) in its
  // orientation the pair a, b. A face's cross product (a - v) x (b - v) is twice its area times its normal.
  std::vector<uint32_t> ringStart_, ring_;
  std::vector<uint8_t> closedRing_;
  // For updates of a few vertices: a mark per slot, and the changes not yet written.
  std::vector<uint32_t> mark_, affected_;
  uint32_t markRound_ = 0;
  FinePositions::Changes pendingPositions_, pendingNormals_;
  bool normalsWritten_ = false;
  uint32_t positionsRange_[2] = {0, 0}, normalsRange_[2] = {0, 0};
  uint64_t positionsOf_ = 0, normalsOf_ = 0;  // fine version written (+1; 0: none yet)
  uint64_t writes_ = 0;
  // The cage path: the table (null: none, tableTried_: looked for), the base (relative positions and
  // the cage and details they are of), the cage last written, scratch.
  std::unique_ptr<CageBasisTable> table_;
  bool tableTried_ = false, haveBase_ = false, normalsStale_ = true;
  // pendingRows_: the vertices whose positions the cage path rewrote since the normals were written
  // (normalsStale_: all of them).
  std::vector<float> base_, delta_;
  std::vector<double> baseCage_, writtenCage_;
  std::vector<uint32_t> moved_, rows_, pendingRows_;
  uint64_t baseDetails_ = 0;
};

}  // namespace mrvol
