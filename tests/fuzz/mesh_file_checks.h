// Shared by the mesh file fuzz targets: what every reader's result must satisfy, and the one
// way a target refuses an input (mrvol::Error; std::bad_alloc for absurd sizes).
#pragma once
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <new>
#include <string>
#include <string_view>
#include <vector>

#include "mrvol/error.h"
#include "mrvol/io_formats.h"
#include "mrvol/mesh.h"

namespace fuzzing {

inline void check(bool ok) {
  if (!ok) __builtin_trap();
}

// A reader's result is well formed: triples, indices in range, finite bounded coordinates, the
// bookkeeping adds up, and welding it again merges nothing (no two vertices at one position).
inline void checkImported(mrvol::ImportedMesh& m) {
  const mrvol::TriangleMesh& mesh = m.mesh;
  check(mesh.positions.size() % 3 == 0 && mesh.faces.size() % 3 == 0 && !mesh.faces.empty());
  for (uint32_t i : mesh.faces) check(i < mesh.vertexCount());
  for (double x : mesh.positions) check(std::isfinite(x) && std::fabs(x) <= 1e100);
  check(m.sourceVertex.size() == mesh.vertexCount());
  check(m.welded + mesh.vertexCount() == m.sourceVertices || m.format == mrvol::MeshFormat::Gltf ||
        m.format == mrvol::MeshFormat::Glb);
  for (size_t v = 1; v < m.sourceVertex.size(); ++v) check(m.sourceVertex[v] > m.sourceVertex[v - 1]);
  mrvol::TriangleMesh again = mesh;
  check(mrvol::weldExactPositions(again) == 0 && again.faces == mesh.faces);
  // What validation says is an answer, not a crash; a valid mesh has a finite volume.
  try {
    mrvol::validateMesh(mesh);
    check(std::isfinite(mrvol::meshVolume(mesh)));
  } catch (const mrvol::Error&) {
  }
  // GLB export reads back to the same triangles and the float32-rounded positions (when every
  // vertex is used: glTF reading keeps only those, and rounding may make two positions equal).
  mrvol::ImportedMesh back = mrvol::readGlb(mrvol::writeGlb(mesh));
  check(back.mesh.faceCount() == mesh.faceCount());
  std::vector<char> used(mesh.vertexCount(), 0);
  for (uint32_t i : mesh.faces) used[i] = 1;
  bool allUsed = true;
  for (char u : used) allUsed = allUsed && u;
  if (allUsed && back.welded == 0) {
    check(back.mesh.faces == mesh.faces);
    for (size_t i = 0; i < mesh.positions.size(); ++i) check(back.mesh.positions[i] == double(float(mesh.positions[i])));
  }
}

template <class Read>
int runReader(const uint8_t* data, size_t size, Read read) {
  try {
    mrvol::ImportedMesh m = read(std::string_view(reinterpret_cast<const char*>(data), size));
    checkImported(m);
  } catch (const mrvol::Error&) {
    // The documented way to refuse an input.
  } catch (const std::bad_alloc&) {
    // Absurd sizes only; -rss_limit_mb reports real blow-ups.
  }
  return 0;
}

}  // namespace fuzzing
