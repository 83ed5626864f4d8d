// Mesh files other than OBJ: STL (binary and ASCII), PLY (ASCII, binary little and big endian),
// OFF (and COFF / NOFF / CNOFF / STOFF), glTF 2.0 (.gltf with data: URIs or sidecar buffers, and
// GLB); format detection; GLB export. Every reader returns the same TriangleMesh as readObj, so
// validation, hierarchy detection and remeshing apply unchanged.
//
// Errors (mrvol::Error) name the file part and the offset or element: "binary STL: 1,000
// triangles declared, the file holds bytes for 312", "PLY line 14: ...", "GLB chunk 1 length
// 9,999,999 runs past the end (file is 2,048 bytes)". Counts are checked against the bytes there
// before anything is allocated.
#pragma once
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "mrvol/mesh.h"

namespace mrvol {

enum class MeshFormat { Obj, Stl, Ply, Off, Gltf, Glb };

// "obj", "stl", "ply", "off", "gltf", "glb".
const char* formatName(MeshFormat format);
// The inverse of formatName, also for a file name's extension (case-insensitive); throws Error.
MeshFormat parseFormatName(std::string_view name);

// The format of a file from its name (extension) and content. A clear signature of a format
// mrvol reads (the GLB magic, a PLY or OFF header, glTF JSON) wins over the extension; otherwise
// the extension decides and the content must fit it: a ZIP archive named .glb is refused as
// "not a GLB file: ... (looks like a ZIP archive)". `name` may be empty (content only).
MeshFormat detectFormat(std::string_view bytes, std::string_view name);

// What a reader returns: the mesh plus what it did to get there.
struct ImportedMesh {
  TriangleMesh mesh;
  MeshFormat format = MeshFormat::Obj;
  std::string variant;  // "binary STL", "ASCII PLY", "binary big-endian PLY", "COFF", "GLB", ...
  // For each output vertex, its first source vertex: the file's vertex index (PLY, OFF), the
  // triangle corner 3 t + k (STL), the running index over the scene's primitives' POSITION
  // accessors, in scene order (glTF).
  std::vector<uint32_t> sourceVertex;
  size_t sourceVertices = 0;  // vertices in the file (STL: 3 per triangle)
  size_t sourceFaces = 0;     // faces in the file (polygons, or glTF triangles after strips and fans)
  size_t welded = 0;          // source vertices merged into an earlier one at the same position
  size_t triangulated = 0;    // polygons of more than 3 corners split into triangles (fans)
  SourceLines objLines;       // OBJ only: the line of each vertex and face (see readObj)
};

// Extra files a .gltf refers to by relative URI (sidecar .bin buffers), by that URI.
using GltfResources = std::vector<std::pair<std::string, std::string_view>>;

ImportedMesh readStl(std::string_view bytes);
ImportedMesh readPly(std::string_view bytes);
ImportedMesh readOff(std::string_view bytes);
ImportedMesh readGltf(std::string_view json, const GltfResources& resources = {});
ImportedMesh readGlb(std::string_view bytes, const GltfResources& resources = {});

// Detects the format (detectFormat) and reads it; OBJ through readObj.
ImportedMesh readMeshFile(std::string_view bytes, std::string_view name, const GltfResources& resources = {});
ImportedMesh readMeshFile(std::string_view bytes, MeshFormat format, const GltfResources& resources = {});

// Merges vertices at exactly the same position (hashed; sorted when positions collide in the
// hash) and renumbers the faces. Output
// vertices keep the order of their first source vertex; `firstSource` (optional) receives it,
// `outputOfSource` (optional) the output vertex of every source vertex.
// Returns the number of vertices merged away. With `unlessAFaceCollapses`, a weld that would give a
// face two equal corners (a triangle with coincident corners) is not made: nothing changes, 0.
size_t weldExactPositions(TriangleMesh& mesh, std::vector<uint32_t>* firstSource = nullptr,
                          std::vector<uint32_t>* outputOfSource = nullptr, bool unlessAFaceCollapses = false);

// A GLB file (glTF 2.0 binary) of the mesh: one node, one triangle primitive with float32
// POSITION (the doubles rounded), area-weighted vertex NORMAL, uint32 indices.
std::string writeGlb(const TriangleMesh& mesh);

// A GLB of a glTF or GLB source file with new positions for the mesh read from it (the same
// triangles as readGltf / readGlb gave, positions moved): the source's JSON, buffers, materials,
// textures and other attributes are kept, each primitive's POSITION is replaced (in its node's
// local frame) and its NORMAL, where present, recomputed (area-weighted; creases the source split
// stay split). All buffers go into the one BIN chunk. Throws Error when the triangles differ from
// the source's, or when an accessor shared by several nodes would need different local positions.
std::string writeGlbKeeping(std::string_view source, MeshFormat sourceFormat, const GltfResources& resources,
                            const TriangleMesh& edited);

}  // namespace mrvol
