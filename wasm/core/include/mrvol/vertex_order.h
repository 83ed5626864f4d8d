// A local numbering of a mesh's vertices for the passes that query vertex corners (validation,
// hierarchy detection): vertices in order of first appearance in the faces, so that the corner
// lists of a face's neighbours sit near each other in memory. On a large mesh in an arbitrary (or
// level-by-level) vertex order these queries are mostly cache misses; in this order they cut
// validation and detection time by a third. The caller's numbering is restored afterwards: nothing
// outside sees the local one.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace mrvol {

// Renumbers `faces` in place into the local numbering and returns local -> caller index (unused
// vertices last, in the caller's order). Leaves `faces` as they are and returns an empty vector
// when an index is out of range (validation names it).
std::vector<uint32_t> renumberByFirstAppearance(std::vector<uint32_t>& faces, size_t vertexCount);
// Back to the caller's numbering.
void restoreNumbering(std::vector<uint32_t>& faces, const std::vector<uint32_t>& localToCaller);

}  // namespace mrvol
