// Triangle meshes: plain arrays, OBJ text in and out, validation with precise messages.
#pragma once
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace mrvol {

// A triangle mesh as flat arrays, in the caller's vertex order.
//   positions: 3 * #V doubles (x0 y0 z0 x1 ...)
//   faces:     3 * #F vertex indices, counter-clockwise seen from outside
struct TriangleMesh {
  std::vector<double> positions;
  std::vector<uint32_t> faces;
  size_t vertexCount() const { return positions.size() / 3; }
  size_t faceCount() const { return faces.size() / 3; }
};

// Where the vertices and faces of a mesh read from OBJ text stand: the (1-based) line of each.
// Messages about a mesh name vertices and faces by their 0-based index in the arrays and, when
// these lines are known, by their line too ("vertex 4 (line 6)").
struct SourceLines {
  std::vector<uint32_t> vertex, face;
};

// Reads OBJ text: `v x y z [w]` and `f` lines (`f a`, `f a/b`, `f a//c`, `f a/b/c`, negative
// indices, `#` comments); other statements (vn, vt, o, g, s, usemtl, mtllib, l ...) are skipped.
// Faces must be triangles: a polygon is refused with its line number, because triangulating it
// would break the semi-regular structure the rest of mrvol relies on.
// Throws Error("line L: ...") for malformed numbers, bad indices, NaN/Inf, empty input.
// With `lines`, also records the line of every vertex and face.
TriangleMesh readObj(std::string_view text, SourceLines* lines = nullptr);

// Writes `v` then `f` lines, vertex order kept, coordinates with 17 significant digits.
std::string writeObj(const TriangleMesh& mesh);

// Facts about a valid mesh.
struct MeshTopology {
  size_t boundaryEdges = 0;
  size_t edges = 0;
  size_t components = 0;
  bool closed = false;
  long genus = 0;  // from the Euler characteristic, for a single closed component
};

// Checks that the mesh is an oriented 2-manifold (possibly with boundary) and says where it is
// not: index out of range, degenerate or duplicate face, non-manifold edge or vertex, inconsistent
// orientation, non-finite coordinates, unused vertices. Throws Error; returns the topology.
// `lines` (optional, as readObj gave them) add the OBJ line of each vertex and face named.
MeshTopology validateMesh(const TriangleMesh& mesh, const SourceLines* lines = nullptr);

// Signed volume enclosed by a closed mesh: sum over triangles of det(a - o, b - o, c - o) / 6.
// The point o changes nothing for a closed mesh but keeps digits when it is far from the origin:
// the bounding-box centre. A mesh with boundary has the signed volume of the cone to o, and o is
// then the centroid of its boundary vertices, which editing keeps fixed.
struct Vec3 { double x = 0, y = 0, z = 0; };
Vec3 volumeReferencePoint(const TriangleMesh& mesh);
double meshVolume(const TriangleMesh& mesh);
double meshVolume(const double* positions, const uint32_t* faces, size_t faceCount, Vec3 origin);

}  // namespace mrvol
