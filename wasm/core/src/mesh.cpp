#include "mrvol/mesh.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <initializer_list>
#include <numeric>
#include <string>

#include "mrvol/corners.h"
#include "mrvol/error.h"

namespace mrvol {

namespace {

// Coordinates beyond this would overflow the volume's triple products (|x|^3 must stay finite).
constexpr double kMaxCoordinate = 1e100;

}  // namespace

namespace {

// Names of vertices and faces in messages: the index, and the OBJ line when known.
struct Names {
  const SourceLines* lines;
  static std::string at(const std::vector<uint32_t>* l, size_t i) {
    return l && i < l->size() ? " (line " + std::to_string((*l)[i]) + ")" : "";
  }
  std::string vertex(size_t v) const { return "vertex " + std::to_string(v) + at(lines ? &lines->vertex : nullptr, v); }
  std::string face(size_t f) const { return "face " + std::to_string(f) + at(lines ? &lines->face : nullptr, f); }
  std::string vertices(std::initializer_list<size_t> vs) const {  // "vertices 1 (line 3), 2 (line 4)"
    std::string out = "vertices ";
    for (size_t v : vs) out += (out.size() > 9 ? ", " : "") + std::to_string(v) + at(lines ? &lines->vertex : nullptr, v);
    return out;
  }
};

struct UnionFind {
  std::vector<uint32_t> parent;
  explicit UnionFind(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  uint32_t find(uint32_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  }
  void unite(uint32_t a, uint32_t b) { parent[find(a)] = find(b); }
};

// Stable counting sort of `items` by key(item) in [0, range): one radix pass. `scratch` and `count`
// are reused between passes so that sorting allocates nothing per pass.
template <class Key>
void countingSortBy(std::vector<uint32_t>& items, std::vector<uint32_t>& scratch, std::vector<uint32_t>& count,
                    size_t range, Key key) {
  count.assign(range + 1, 0);
  for (uint32_t item : items) ++count[key(item) + 1];
  for (size_t k = 0; k < range; ++k) count[k + 1] += count[k];
  scratch.resize(items.size());
  for (uint32_t item : items) scratch[count[key(item)]++] = item;
  items.swap(scratch);
}

// The ordered edge checks: duplicate faces, then edges in (min, max) order, each in at most two
// faces traversed in opposite directions. Throws the message for the first problem; called only
// when the fast checks found one, so that messages name the same faces whatever the path.
[[noreturn]] void refuseEdges(const TriangleMesh& mesh, const Names& name) {
  auto faceName = [&](size_t f) { return name.face(f); };
  const size_t nv = mesh.vertexCount(), nf = mesh.faceCount();
  const uint32_t* faces = mesh.faces.data();
  // Linear time and flat arrays throughout: radix sorts (counting sorts by vertex index) instead of
  // comparison sorts or hash maps, so that millions of faces validate in well under a second.
  std::vector<uint32_t> order, scratch, count;
  // Duplicate faces: same three vertices, in either orientation. Faces sorted by their sorted
  // triple (a < b < c), face index last: the first equal neighbours are the ones reported.
  {
    auto sortedCorner = [&](uint32_t f, int rank) {
      uint32_t a = faces[3 * f], b = faces[3 * f + 1], c = faces[3 * f + 2];
      if (a > b) std::swap(a, b);
      if (b > c) std::swap(b, c);
      if (a > b) std::swap(a, b);
      return rank == 0 ? a : rank == 1 ? b : c;
    };
    order.resize(nf);
    std::iota(order.begin(), order.end(), 0u);
    for (int rank = 2; rank >= 0; --rank)
      countingSortBy(order, scratch, count, nv, [&](uint32_t f) { return sortedCorner(f, rank); });
    for (size_t i = 1; i < nf; ++i) {
      const uint32_t f = order[i - 1], g = order[i];
      if (sortedCorner(f, 0) == sortedCorner(g, 0) && sortedCorner(f, 1) == sortedCorner(g, 1) &&
          sortedCorner(f, 2) == sortedCorner(g, 2))
        throw Error(faceName(f) + " and " + faceName(g) + " are duplicates (" +
                    name.vertices({sortedCorner(f, 0), sortedCorner(f, 1), sortedCorner(f, 2)}) + ")");
    }
  }
  // Half-edges h = 3 f + k (from faces[h] to the next corner), sorted by their undirected key
  // (min, max): each edge in at most two faces, and two faces sharing one must traverse it in
  // opposite directions (else the orientation is inconsistent).
  auto from = [&](uint32_t h) { return faces[h]; };
  auto to = [&](uint32_t h) { return faces[h % 3 == 2 ? h - 2 : h + 1]; };
  auto lo = [&](uint32_t h) { return std::min(from(h), to(h)); };
  auto hi = [&](uint32_t h) { return std::max(from(h), to(h)); };
  auto forward = [&](uint32_t h) { return from(h) < to(h); };
  order.resize(3 * nf);
  std::iota(order.begin(), order.end(), 0u);
  countingSortBy(order, scratch, count, nv, hi);
  countingSortBy(order, scratch, count, nv, lo);
  std::vector<uint32_t>().swap(scratch);
  std::vector<uint32_t>().swap(count);
  for (size_t i = 0; i < order.size();) {
    const uint32_t u = lo(order[i]), v = hi(order[i]);
    size_t j = i + 1;
    while (j < order.size() && lo(order[j]) == u && hi(order[j]) == v) ++j;
    if (j - i > 2 || (j - i == 2 && forward(order[i]) == forward(order[i + 1]))) {
      // Messages list the faces backward ones first, then by face index (within one direction
      // the half-edges are already in face order).
      std::stable_partition(order.begin() + ptrdiff_t(i), order.begin() + ptrdiff_t(j),
                            [&](uint32_t h) { return !forward(h); });
      const std::string edge = "edge between " + name.vertices({u, v});
      auto face = [&](size_t r) { return faceName(order[i + r] / 3); };
      if (j - i > 2)
        throw Error("non-manifold " + edge + ": shared by " + std::to_string(j - i) + " faces (" + face(0) + ", " +
                    face(1) + ", " + face(2) + (j - i > 3 ? ", ..." : "") + ")");
      throw Error("inconsistent orientation at " + edge + ": " + face(0) + " and " + face(1) +
                  " traverse it in the same direction");
    }
    i = j;
  }
  throw Error("the mesh is not an oriented 2-manifold");  // unreachable: the fast checks agree
}

}  // namespace

MeshTopology validateMesh(const TriangleMesh& mesh, const SourceLines* lines) {
  return validateMesh(mesh, lines, nullptr);
}

MeshTopology validateMesh(const TriangleMesh& mesh, const SourceLines* lines, VertexCorners* keepCorners) {
  const Names name{lines};
  auto faceName = [&](size_t f) { return name.face(f); };
  const size_t nv = mesh.vertexCount(), nf = mesh.faceCount();
  if (mesh.positions.size() % 3 != 0) throw Error("positions must hold 3 numbers per vertex");
  if (mesh.faces.size() % 3 != 0) throw Error("faces must hold 3 vertex indices per triangle");
  if (nv == 0) throw Error("the mesh has no vertices");
  if (nf == 0) throw Error("the mesh has no faces");
  checkMeshSize(nv, nf);
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    double x = mesh.positions[i];
    if (!std::isfinite(x)) throw Error(name.vertex(i / 3) + " has a non-finite coordinate");
    if (std::fabs(x) > kMaxCoordinate)
      throw Error(name.vertex(i / 3) + " has a coordinate beyond 1e100");
  }
  const uint32_t* faces = mesh.faces.data();
  for (size_t f = 0; f < nf; ++f) {
    const uint32_t* t = &faces[3 * f];
    for (int k = 0; k < 3; ++k)
      if (t[k] >= nv)
        throw Error(faceName(f) + " refers to vertex " + std::to_string(t[k]) + " but there are " +
                    std::to_string(nv) + " vertices");
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
      throw Error(faceName(f) + " is degenerate: it uses " + name.vertex(t[0] == t[1] || t[0] == t[2] ? t[0] : t[1]) +
                  " twice");
  }
  // The fast path: every check from the per-vertex corner lists (VertexCorners, built by a
  // counting sort), O(1) per corner at ordinary vertices and O(log valence) at hubs. Only when it
  // finds a problem does refuseEdges() sort the edges to name the same one the ordered checks name.
  VertexCorners corners(faces, nf, nv);
  size_t edges = 0;
  std::vector<std::pair<uint32_t, uint32_t>> boundary;
  bool edgesValid = true;
  // Vertices: the faces around each must form one fan (no bow-tie). With manifold edges, each
  // neighbour v is at most once a corner's next and once a corner's prev, so the corners form
  // paths and cycles: one fan is one path (a boundary vertex) or one cycle (an interior vertex).
  // A path starts at a next v with no face (v, u, .): the edge checks' own query, so the fans are
  // checked in the same pass (one query of another vertex's corners per corner, not two). The
  // first vertex that fails is kept and named only once every edge has passed, as the separate
  // passes did. Queries cost O(1) at ordinary vertices and O(log valence) at hubs (VertexCorners
  // keeps their corners sorted).
  uint32_t firstBadVertex = kNone;
  for (uint32_t u = 0; u < nv && edgesValid; ++u) {
    const uint32_t begin = corners.begin(u), end = corners.end(u);
    uint32_t start = begin < end ? corners.next[begin] : kNone, pathStarts = 0;
    for (uint32_t c = begin; c < end && edgesValid; ++c) {
      const uint32_t v = corners.next[c];
      // Each directed edge once (twice: duplicate faces, a non-manifold edge or a flipped face).
      if (corners.cornerTo(u, v) != c) edgesValid = false;
      // A face (u, v, w) and its reverse (u, w, v): duplicates that pair every edge.
      if (corners.opposite(u, corners.prev[c]) == v) edgesValid = false;
      if (corners.cornerTo(v, u) == kNone) {
        boundary.emplace_back(std::min(u, v), std::max(u, v)), ++edges;
        ++pathStarts, start = v;
      } else {
        edges += u < v;
      }
    }
    if (firstBadVertex != kNone || !edgesValid) continue;
    const uint32_t k = end - begin;
    uint32_t walked = 0;
    for (uint32_t v = start; k > 0 && pathStarts <= 1 && walked <= k;) {
      const uint32_t w = corners.opposite(u, v);
      if (w == kNone) break;
      ++walked;
      if (w == start) break;
      v = w;
    }
    if (k == 0 || pathStarts > 1 || walked != k) firstBadVertex = u;
  }
  if (!edgesValid) refuseEdges(mesh, name);
  if (firstBadVertex != kNone) {
    if (corners.count(firstBadVertex) == 0) throw Error(name.vertex(firstBadVertex) + " is not used by any face");
    throw Error("non-manifold " + name.vertex(firstBadVertex) + ": its faces form more than one fan");
  }
  MeshTopology topo;
  topo.edges = edges;
  topo.boundaryEdges = boundary.size();
  topo.closed = boundary.empty();
  UnionFind components(nv);
  for (size_t f = 0; f < nf; ++f) {
    components.unite(faces[3 * f], faces[3 * f + 1]);
    components.unite(faces[3 * f], faces[3 * f + 2]);
  }
  for (uint32_t v = 0; v < nv; ++v) topo.components += components.find(v) == v;
  // Boundary loops: manifold boundary vertices have two boundary edges each, so loops are cycles.
  UnionFind loops(nv);
  std::vector<char> onBoundary(nv, 0);
  for (auto [u, v] : boundary) loops.unite(u, v), onBoundary[u] = onBoundary[v] = 1;
  size_t boundaryLoops = 0;
  for (uint32_t u = 0; u < nv; ++u) boundaryLoops += onBoundary[u] && loops.find(u) == u;
  long chi = long(nv) - long(edges) + long(nf);
  topo.genus = (2 * long(topo.components) - chi - long(boundaryLoops)) / 2;
  if (keepCorners) *keepCorners = std::move(corners);
  return topo;
}

Vec3 volumeReferencePoint(const double* positions, size_t nv, const std::vector<char>& onBoundary) {
  if (nv == 0) return {};
  Vec3 sum;
  size_t count = 0;
  for (size_t u = 0; u < nv; ++u)
    if (onBoundary[u]) {
      sum.x += positions[3 * u], sum.y += positions[3 * u + 1], sum.z += positions[3 * u + 2];
      ++count;
    }
  if (count > 0) return {sum.x / count, sum.y / count, sum.z / count};
  double lo[3], hi[3];
  for (int k = 0; k < 3; ++k) lo[k] = hi[k] = positions[k];
  for (size_t v = 0; v < nv; ++v)
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], positions[3 * v + k]), hi[k] = std::max(hi[k], positions[3 * v + k]);
  return {(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
}

Vec3 volumeReferencePoint(const TriangleMesh& mesh) {
  const size_t nv = mesh.vertexCount();
  if (nv == 0) return {};
  // Boundary vertices: endpoints of an edge u -> v with no face v -> u (linear: corner lists).
  const VertexCorners corners(mesh.faces.data(), mesh.faceCount(), nv);
  std::vector<char> onBoundary(nv, 0);
  for (uint32_t u = 0; u < nv; ++u)
    for (uint32_t c = corners.begin(u); c < corners.end(u); ++c)
      if (corners.cornerTo(corners.next[c], u) == kNone) onBoundary[u] = onBoundary[corners.next[c]] = 1;
  return volumeReferencePoint(mesh.positions.data(), nv, onBoundary);
}

double meshVolume(const double* p, const uint32_t* faces, size_t faceCount, Vec3 o) {
  double sum = 0;
  for (size_t f = 0; f < faceCount; ++f) {
    const double* a = p + 3 * faces[3 * f];
    const double* b = p + 3 * faces[3 * f + 1];
    const double* c = p + 3 * faces[3 * f + 2];
    double ax = a[0] - o.x, ay = a[1] - o.y, az = a[2] - o.z;
    double bx = b[0] - o.x, by = b[1] - o.y, bz = b[2] - o.z;
    double cx = c[0] - o.x, cy = c[1] - o.y, cz = c[2] - o.z;
    sum += ax * (by * cz - bz * cy) + ay * (bz * cx - bx * cz) + az * (bx * cy - by * cx);
  }
  return sum / 6.0;
}

double meshVolume(const TriangleMesh& mesh) {
  return meshVolume(mesh.positions.data(), mesh.faces.data(), mesh.faceCount(), volumeReferencePoint(mesh));
}

}  // namespace mrvol
