// A detected hierarchy as flat arrays, to open the same mesh in another instance of the core
// without validating it and finding its hierarchy again: the web app's worker reads, validates and
// detects; the page rebuilds the MultiresMesh from these arrays in a few linear passes.
#pragma once
#include <cstdint>
#include <vector>

#include "mrvol/multires_mesh.h"

namespace mrvol {

struct HierarchyArrays {
  int levels = 0;
  std::vector<uint32_t> vertexCount;  // V_0 .. V_n
  std::vector<uint32_t> coarseFaces;  // the faces of levels 0 .. n-1 one after the other, hierarchy indices
  std::vector<uint32_t> ends, wings;  // 2 per vertex, hierarchy indices (kNone where none)
  std::vector<uint8_t> boundary;      // 1 per vertex, hierarchy order
  std::vector<uint32_t> inputIndex;   // hierarchy index -> caller's vertex index
  MeshTopology topology;              // of the fine mesh, as validation found it
};

HierarchyArrays hierarchyArrays(const MultiresMesh& mesh);

// The MultiresMesh of the caller's fine `faces` with the hierarchy in `arrays` (as hierarchyArrays
// gave them for these faces). Checks that the arrays fit together (sizes, index ranges, a
// permutation) and throws Error naming the first part that does not; the mesh is not validated
// again (the arrays say it was).
MultiresMesh multiresFromArrays(std::vector<uint32_t> faces, HierarchyArrays arrays);

}  // namespace mrvol
