#include "mrvol/hierarchy_transfer.h"

#include <string>

#include "mrvol/corners.h"
#include "mrvol/error.h"

namespace mrvol {

MultiresMesh MultiresMesh::fromParts(std::vector<uint32_t> faces, MeshTopology topology, Hierarchy hierarchy) {
  MultiresMesh m;
  m.faces_ = std::move(faces);
  m.topology_ = topology;
  m.hierarchy_ = std::move(hierarchy);
  return m;
}

HierarchyArrays hierarchyArrays(const MultiresMesh& mesh) {
  const Hierarchy& h = mesh.hierarchy();
  HierarchyArrays a;
  a.levels = h.levels;
  a.vertexCount = h.vertexCount;
  for (int l = 0; l < h.levels; ++l) a.coarseFaces.insert(a.coarseFaces.end(), h.faces[l].begin(), h.faces[l].end());
  a.ends = h.ends;
  a.wings = h.wings;
  a.boundary = h.boundary;
  a.inputIndex = h.inputIndex;
  a.topology = mesh.topology();
  return a;
}

namespace {

[[noreturn]] void mismatch(const std::string& what) { throw Error("the hierarchy arrays do not fit the mesh: " + what); }

// Every index of `values` below `bound` (or kNone where allowed).
void checkIndices(const uint32_t* values, size_t count, uint32_t bound, bool noneAllowed, const char* what) {
  for (size_t i = 0; i < count; ++i)
    if (values[i] >= bound && !(noneAllowed && values[i] == kNone))
      mismatch(std::string(what) + " index " + std::to_string(values[i]) + " at " + std::to_string(i) +
               " is out of range (" + std::to_string(bound) + " vertices)");
}

}  // namespace

MultiresMesh multiresFromArrays(std::vector<uint32_t> faces, HierarchyArrays a) {
  if (a.levels < 0 || a.levels > 16) mismatch("levels " + std::to_string(a.levels) + " is outside 0..16");
  if (a.vertexCount.size() != size_t(a.levels) + 1) mismatch("expected " + std::to_string(a.levels + 1) + " vertex counts");
  for (int l = 1; l <= a.levels; ++l)
    if (a.vertexCount[l] < a.vertexCount[l - 1]) mismatch("the vertex counts decrease at level " + std::to_string(l));
  const uint32_t n = a.vertexCount.back();
  if (a.inputIndex.size() != n || a.ends.size() != 2 * size_t(n) || a.wings.size() != 2 * size_t(n) || a.boundary.size() != n)
    mismatch("expected per-vertex arrays for " + std::to_string(n) + " vertices");
  if (faces.size() % 3 != 0) mismatch("the faces are not triangles");
  // Each level splits every triangle of the one before into four.
  const size_t fine = faces.size() / 3;
  size_t base = fine;
  for (int l = 0; l < a.levels; ++l) {
    if (base % 4 != 0) mismatch("the face count does not divide by 4 at level " + std::to_string(a.levels - l));
    base /= 4;
  }
  if (a.coarseFaces.size() != 3 * base * ((size_t(1) << (2 * a.levels)) - 1) / 3)
    mismatch("expected the faces of levels 0.." + std::to_string(a.levels - 1));

  Hierarchy h;
  h.levels = a.levels;
  h.vertexCount = std::move(a.vertexCount);
  h.hierarchyIndex.assign(n, kNone);
  for (uint32_t v = 0; v < n; ++v) {
    const uint32_t input = a.inputIndex[v];
    if (input >= n || h.hierarchyIndex[input] != kNone) mismatch("the vertex order is not a permutation");
    h.hierarchyIndex[input] = v;
  }
  h.inputIndex = std::move(a.inputIndex);
  size_t at = 0, count = 3 * base;
  for (int l = 0; l < h.levels; ++l, count *= 4) {
    checkIndices(a.coarseFaces.data() + at, count, h.vertexCount[l], false, "level face");
    h.faces.emplace_back(a.coarseFaces.begin() + at, a.coarseFaces.begin() + at + count);
    at += count;
  }
  checkIndices(faces.data(), faces.size(), n, false, "face");
  std::vector<uint32_t> fineFaces(faces.size());
  for (size_t i = 0; i < faces.size(); ++i) fineFaces[i] = h.hierarchyIndex[faces[i]];
  h.faces.push_back(std::move(fineFaces));
  // A vertex born at level l sits between vertices of level l - 1 (base vertices have none).
  for (int l = 0; l <= h.levels; ++l) {
    const uint32_t first = l == 0 ? 0 : h.vertexCount[l - 1], bound = first;
    checkIndices(a.ends.data() + 2 * size_t(first), 2 * size_t(h.vertexCount[l] - first), bound, l == 0, "end");
    checkIndices(a.wings.data() + 2 * size_t(first), 2 * size_t(h.vertexCount[l] - first), bound, true, "wing");
  }
  h.ends = std::move(a.ends);
  h.wings = std::move(a.wings);
  h.boundary = std::move(a.boundary);
  return MultiresMesh::fromParts(std::move(faces), a.topology, std::move(h));
}

}  // namespace mrvol
