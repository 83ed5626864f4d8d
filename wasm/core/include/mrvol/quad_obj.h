// OBJ text for quad meshes: readObj triangulates polygons, these keep the quads.
#pragma once
#include <string>
#include <string_view>

#include "mrvol/quad_hierarchy.h"

namespace mrvol {

// Positions as readObj reads them (same checks and messages); every `f` line must have exactly
// 4 corners (any of the forms a, a/b, a//c, a/b/c, negative indices), else Error("line L: ...").
QuadMesh readObjQuads(std::string_view text);

// `v` then `f a b c d` lines, vertex order kept, coordinates with 17 significant digits.
std::string writeObjQuads(const QuadMesh& mesh);

}  // namespace mrvol
