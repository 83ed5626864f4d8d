// A multiresolution mesh's description for JS, the same for triangle and quad meshes
// (bindings.cpp, quad_bindings.cpp): info() and the depth of every vertex.
#pragma once
#include <emscripten/val.h>

#include <cstdint>
#include <vector>

#include "mrvol/hierarchy.h"
#include "mrvol/multires_mesh.h"
#include "typed_arrays.h"

namespace mrvol::bindings {

inline emscripten::val meshInfoToJs(const MeshInfo& i) {
  emscripten::val out = emscripten::val::object();
  out.set("vertices", double(i.vertices));
  out.set("faces", double(i.faces));
  out.set("levels", i.levels);
  out.set("baseVertices", double(i.baseVertices));
  out.set("baseVertexIndices", toTyped(i.baseVertexIndices));
  out.set("closed", i.closed);
  out.set("boundaryEdges", double(i.boundaryEdges));
  out.set("genus", double(i.genus));
  out.set("components", double(i.components));
  out.set("volume", i.volume);
  return out;
}

// The level where each vertex is born, caller's vertex order.
inline emscripten::val depthsToJs(const Hierarchy& h) {
  std::vector<uint8_t> d(h.fineVertexCount());
  for (uint32_t v = 0; v < d.size(); ++v) d[h.inputIndex[v]] = uint8_t(h.depth(v));
  return toTyped(d);
}

}  // namespace mrvol::bindings
