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

// What an OBJ file carried besides the triangles (readObj fills it when asked).
//   polygons:          faces with more than 3 corners, triangulated (fan if convex, else ear clipping)
//   polygonTriangles:  the triangles they gave
//   texCoords:         2 per `vt` line (u v; a third value w is dropped), in file order
//   normals:           3 per `vn` line
//   colors:            3 per vertex (r g b) when every `v` line has them, else empty
//   cornerTexCoords,
//   cornerNormals:     per triangle corner (3 * #F), the 0-based vt / vn index or kNoIndex; empty
//                      when no face refers to any vt / vn, or one refers outside the file's
//                      (such references are dropped, not refused)
struct ObjExtras {
  static constexpr uint32_t kNoIndex = 0xffffffffu;
  size_t polygons = 0, polygonTriangles = 0;
  std::vector<double> texCoords, normals, colors;
  std::vector<uint32_t> cornerTexCoords, cornerNormals;
  // What was left out, in words (empty: nothing): face corners that refer to vt or vn lines the
  // file does not have make those attributes inconsistent, so they are dropped (the mesh is read).
  std::string dropped;
};

// Reads OBJ text (bytes; UTF-8 or ASCII): `v x y z [w]` and `v x y z r g b`, `vt`, `vn`, and `f`
// lines in every form (`f a`, `f a/b`, `f a//c`, `f a/b/c`, negative indices relative to the
// elements read so far), polygons of any size (triangulated where they stand in face order; each
// triangle keeps the polygon's line), `#` comments, CRLF, a UTF-8 byte order mark; other
// statements (o, g, s, usemtl, mtllib, l, p ...) are skipped.
// Throws Error("line L: ...") for malformed numbers, bad indices, NaN/Inf, empty input, and before
// allocating anything large, for a file too big to open (checkObjSize).
// With `lines`, also records the line of every vertex and face; with `extras`, what else it had.
// One vertex per v line: the file's own numbering (readObjQuads' quads index it); the readers users
// call (readMeshFile, the API's readObj and ObjReader's chunks) then weld with weldObjVertices.
TriangleMesh readObj(std::string_view text, SourceLines* lines = nullptr, ObjExtras* extras = nullptr);

// Vertices at exactly the same position welded into one (numbered in the order of their first v
// line), as STL's and glTF's readers do: exporters split vertices where their attributes differ
// (three.js's OBJExporter writes three per triangle of a non-indexed geometry). `lines->vertex` and
// `extras->colors` keep the first v line's; `firstSource` (when given) gets each vertex's first v
// line index. Not made where it would give a triangle two equal corners (coincident ones: the
// checks then name that mesh's own problem, e.g. "all 4 vertices at one point"). Returns how many
// vertices were welded away (0: the mesh is unchanged).
size_t weldObjVertices(TriangleMesh& mesh, SourceLines* lines = nullptr, ObjExtras* extras = nullptr,
                       std::vector<uint32_t>* firstSource = nullptr);

// The largest mesh mrvol opens: what opening it needs (positions, faces, validation, hierarchy
// detection, the caller's copies) must fit the 4 GB a WebAssembly module can address.
// Throws Error naming the counts and the estimate when `vertices` / `triangles` exceed it.
void checkMeshSize(size_t vertices, size_t triangles, size_t inputBytes = 0);

// Writes `v` then `f` lines, vertex order kept, coordinates with 17 significant digits.
std::string writeObj(const TriangleMesh& mesh);

// Writes `original` (the OBJ text readObj read) with its vertex positions replaced by `positions`
// (3 per vertex: one per v line, or one per vertex of the file welded as weldObjVertices welds it,
// each v line then taking its vertex's): every other line (vt, vn, f, groups, materials, comments) and every
// other byte of the v lines (w, colours, spacing, line endings) is kept; a coordinate whose value
// is unchanged keeps its original spelling. For edits that keep the connectivity.
std::string writeObjLike(std::string_view original, const double* positions, size_t vertexCount);

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
// The same, handing over the corner lists it built (corners.h) to a caller that needs them next
// (hierarchy detection), instead of building them again.
struct VertexCorners;
MeshTopology validateMesh(const TriangleMesh& mesh, const SourceLines* lines, VertexCorners* keepCorners);

// Signed volume enclosed by a closed mesh: sum over triangles of det(a - o, b - o, c - o) / 6.
// The point o changes nothing for a closed mesh but keeps digits when it is far from the origin:
// the bounding-box centre. A mesh with boundary has the signed volume of the cone to o, and o is
// then the centroid of its boundary vertices, which editing keeps fixed.
struct Vec3 { double x = 0, y = 0, z = 0; };
Vec3 volumeReferencePoint(const TriangleMesh& mesh);
// The same point from boundary flags the caller already has (onBoundary[v], 1 for a boundary
// vertex), so that a large mesh needs no corner lists and no copy of its arrays for it.
Vec3 volumeReferencePoint(const double* positions, size_t vertexCount, const std::vector<char>& onBoundary);
double meshVolume(const TriangleMesh& mesh);
double meshVolume(const double* positions, const uint32_t* faces, size_t faceCount, Vec3 origin);

}  // namespace mrvol
