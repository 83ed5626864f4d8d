// Semi-regular quad meshes: n Catmull-Clark 1-to-4 splits of a base quad mesh (every quad gets a
// face point, every edge an edge point). The connectivity of every level, built once, in the
// same numbering as the triangle hierarchies (base vertices first, then those born at level 1 ...).
#pragma once
#include <cstdint>
#include <vector>

#include "mrvol/hierarchy.h"
#include "mrvol/mesh.h"

namespace mrvol {

// A quad mesh as flat arrays, in the caller's vertex order.
//   positions: 3 * #V doubles;  quads: 4 * #F vertex indices, counter-clockwise seen from outside
struct QuadMesh {
  std::vector<double> positions;
  std::vector<uint32_t> quads;
  size_t vertexCount() const { return positions.size() / 3; }
  size_t faceCount() const { return quads.size() / 4; }
};

// Two triangles per quad (a, b, c), (a, c, d): what triangle code (validation, reference point,
// rendering) sees of a quad mesh.
std::vector<uint32_t> triangulateQuads(const std::vector<uint32_t>& quads);

// Checks that the quads form an oriented 2-manifold (possibly with boundary): indices in range,
// four distinct corners per quad, finite coordinates, every vertex used, manifold edges and
// vertices, consistent orientation. Throws Error naming the quad or vertex; returns the topology.
MeshTopology validateQuadMesh(const QuadMesh& mesh);

// One split, from level l-1 to level l (hierarchy numbering).
struct QuadSplit {
  struct Edge {
    uint32_t a, b;      // ends (level l-1 vertices)
    uint32_t point;     // its edge point (born at level l)
    uint32_t face0, face1;  // face points of the quads beside it; face1 = kNone on the boundary
  };
  std::vector<uint32_t> facePoint;  // per level-(l-1) quad, its face point
  std::vector<Edge> edges;          // every level-(l-1) edge once
};

struct QuadHierarchy {
  // levels, vertexCount, inputIndex / hierarchyIndex and boundary as for triangles; faces[l] are
  // the level-l quads triangulated (triangulateQuads); ends are the ends of edge points (kNone
  // for face points and base vertices); wings are unused (kNone).
  Hierarchy h;
  std::vector<std::vector<uint32_t>> quads;  // quads[l]: 4 * F_l, hierarchy numbering
  std::vector<QuadSplit> splits;             // splits[l - 1]: from level l-1 to level l

  int levels() const { return h.levels; }
  const std::vector<uint32_t>& fineQuads() const { return quads.back(); }

  // n splits of a validated base quad mesh; its vertices keep their indices, the new ones follow
  // (per level: the face points in quad order, then the edge points in order of first use).
  static QuadHierarchy subdivide(const std::vector<uint32_t>& baseQuads, uint32_t baseVertexCount, int levels);
  // Recovers the splits of a validated quad mesh whatever its vertex order: as many levels as
  // there are, at most maxLevels. A mesh that is no split gives 0 levels. Base vertices are
  // numbered in ascending caller order.
  static QuadHierarchy detect(const QuadMesh& fine, int maxLevels = 16);
};

}  // namespace mrvol
