// Shared by the glTF reader (read_gltf.cpp) and the GLB writer that keeps a source file's data
// (write_glb_keeping.cpp): a parsed document with its buffers, and where each primitive's
// vertices went when the scene was read. Private to the core.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "mrvol/io_formats.h"

namespace mrvol::gltf {

using nlohmann::json;
using Matrix = std::array<double, 16>;  // column-major, as glTF stores it

// A readable glTF document: the JSON and the bytes of each buffer.
struct Document {
  json root;
  std::vector<std::string_view> buffers;
  std::vector<std::string> decoded;  // storage of base64 data: URIs (reserved: views stay valid)
  uint64_t totalBytes = 0;           // file and resources: bounds what the scene may expand to
  const char* kind = "glTF";
};

// Parses a .gltf (JSON) or a GLB and finds its buffers; throws Error as the readers do.
Document openGltf(std::string_view text, const GltfResources& resources);
Document openGlb(std::string_view bytes, const GltfResources& resources);

// One primitive of one node of the scene, as read.
struct PrimitiveUse {
  size_t mesh = 0, primitive = 0, positionAccessor = 0;
  long normalAccessor = -1;          // its NORMAL accessor, if any
  Matrix world{};                    // the node's world matrix
  std::vector<uint32_t> outputOf;    // accessor vertex -> vertex of SceneGeometry::mesh (UINT32_MAX: unused)
  std::vector<uint32_t> triangles;   // local (accessor) vertex triples, before any winding flip
};

// The scene's triangles before welding, and where they came from.
struct SceneGeometry {
  TriangleMesh mesh;
  std::vector<PrimitiveUse> uses;
  std::vector<uint32_t> sourceOfVertex;  // running POSITION index of each vertex
  size_t sourceFaces = 0;
};
SceneGeometry collectScene(const Document& d);

// Accessor `index` as doubles, `components` per element (normalized integers mapped to [-1, 1]).
std::vector<double> readAccessor(const Document& d, size_t index, size_t components, const std::string& role);

// A GLB file: the JSON (padded with spaces) and the BIN chunk (padded with zeros).
std::string glbContainer(std::string json, std::string_view bin);

}  // namespace mrvol::gltf
