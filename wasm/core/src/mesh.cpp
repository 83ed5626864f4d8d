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
constexpr size_t kMaxIndex = 0xfffffff0u;

std::string at(size_t line) { return "line " + std::to_string(line) + ": "; }

std::string shorten(std::string_view token) {
  std::string s(token.substr(0, 40));
  for (char& c : s)
    if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126) c = '?';
  if (token.size() > 40) s += "...";
  return "'" + s + "'";
}

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

// Splits one line into whitespace-separated tokens (views into the line).
void tokenize(std::string_view line, std::vector<std::string_view>& tokens) {
  tokens.clear();
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && isSpace(line[i])) ++i;
    size_t j = i;
    while (j < line.size() && !isSpace(line[j])) ++j;
    if (j > i) tokens.push_back(line.substr(i, j - i));
    i = j;
  }
}

double parseCoordinate(std::string_view token, size_t line) {
  char buffer[64];
  if (token.size() >= sizeof buffer)
    throw Error(at(line) + "coordinate " + shorten(token) + " is too long (" + std::to_string(token.size()) +
                " characters; mrvol reads at most " + std::to_string(sizeof buffer - 1) + ")");
  std::copy(token.begin(), token.end(), buffer);
  buffer[token.size()] = '\0';
  char* end = nullptr;
  errno = 0;
  double value = std::strtod(buffer, &end);
  if (end != buffer + token.size() || token.empty())
    throw Error(at(line) + "coordinate " + shorten(token) + " is not a number");
  if (std::isnan(value) || (std::isinf(value) && errno != ERANGE))
    throw Error(at(line) + "coordinate " + shorten(token) + " is not finite");
  if (std::fabs(value) > kMaxCoordinate)  // also a finite literal that overflows a double (ERANGE)
    throw Error(at(line) + "coordinate " + shorten(token) +
                " is too large (mrvol accepts |x| <= 1e100 so that volumes stay finite)");
  return value;
}

// OBJ index: 1-based, or negative relative to the vertices read so far. Returns 0-based.
int64_t parseIndex(std::string_view token, size_t line, size_t verticesSoFar) {
  std::string_view digits = token.substr(0, token.find('/'));
  if (digits.empty()) throw Error(at(line) + "face vertex " + shorten(token) + " has no vertex index");
  bool negative = digits[0] == '-';
  size_t start = (digits[0] == '-' || digits[0] == '+') ? 1 : 0;
  if (start == digits.size()) throw Error(at(line) + "face index " + shorten(token) + " is not an integer");
  int64_t value = 0;
  for (size_t i = start; i < digits.size(); ++i) {
    char c = digits[i];
    if (c < '0' || c > '9') throw Error(at(line) + "face index " + shorten(token) + " is not an integer");
    value = value * 10 + (c - '0');
    if (value > int64_t(kMaxIndex))
      throw Error(at(line) + "face index " + shorten(digits) + " is out of range");
  }
  if (value == 0) throw Error(at(line) + "face index 0 is not valid (OBJ indices start at 1)");
  if (negative) {
    if (size_t(value) > verticesSoFar)
      throw Error(at(line) + "relative face index " + shorten(digits) + " reaches before the first vertex (" +
                  std::to_string(verticesSoFar) + " vertices so far)");
    return int64_t(verticesSoFar) - value;
  }
  return value - 1;
}

}  // namespace

TriangleMesh readObj(std::string_view text, SourceLines* lines) {
  TriangleMesh mesh;
  std::vector<uint32_t> vertexLines;
  std::vector<uint32_t> faceLines;
  std::vector<int64_t> pending;  // 0-based indices, range-checked once all vertices are known
  std::vector<std::string_view> tokens;
  size_t line = 0;
  size_t pos = text.substr(0, 3) == "\xEF\xBB\xBF" ? 3 : 0;  // a UTF-8 byte order mark is no statement
  while (pos < text.size()) {
    size_t eol = text.find('\n', pos);
    if (eol == std::string_view::npos) eol = text.size();
    std::string_view content = text.substr(pos, eol - pos);
    pos = eol + 1;
    ++line;
    size_t carriageReturn = std::string_view::npos;
    for (size_t i = 0; i < content.size(); ++i) {
      unsigned char c = static_cast<unsigned char>(content[i]);
      if (c == 0 || (c < 32 && !isSpace(char(c))))
        throw Error(at(line) + "binary data (byte " + std::to_string(int(c)) + " at column " + std::to_string(i + 1) +
                    "): this is not an OBJ text file");
      if (c == '\r') {
        if (carriageReturn == std::string_view::npos) carriageReturn = i;
      } else if (carriageReturn != std::string_view::npos && !isSpace(char(c))) {
        throw Error(at(line) + "carriage return inside the line (column " + std::to_string(carriageReturn + 1) +
                    "): old Mac line endings (CR only) are not supported; convert the file to LF or CRLF");
      }
    }
    size_t hash = content.find('#');
    if (hash != std::string_view::npos) content = content.substr(0, hash);
    tokenize(content, tokens);
    if (tokens.empty()) continue;
    std::string_view keyword = tokens[0];
    if (keyword == "v") {
      if (tokens.size() < 4)
        throw Error(at(line) + "vertex needs 3 coordinates, found " + std::to_string(tokens.size() - 1));
      if (tokens.size() > 5)  // x y z [w]; colours (x y z r g b) are accepted too
        if (tokens.size() != 7)
          throw Error(at(line) + "vertex has " + std::to_string(tokens.size() - 1) +
                      " values, expected 3 (x y z), 4 (x y z w) or 6 (x y z r g b)");
      for (int k = 1; k <= 3; ++k) mesh.positions.push_back(parseCoordinate(tokens[k], line));
      if (lines) vertexLines.push_back(uint32_t(line));
      for (size_t k = 4; k < tokens.size(); ++k) parseCoordinate(tokens[k], line);
    } else if (keyword == "f") {
      size_t corners = tokens.size() - 1;
      if (corners < 3)
        throw Error(at(line) + "face has " + std::to_string(corners) + " vertices, a triangle needs 3");
      if (corners > 3)
        throw Error(at(line) + "face has " + std::to_string(corners) +
                    " vertices; mrvol reads triangle meshes only (triangulating a polygon would break "
                    "the semi-regular structure)");
      for (int k = 1; k <= 3; ++k) pending.push_back(parseIndex(tokens[k], line, mesh.vertexCount()));
      faceLines.push_back(uint32_t(line));
    } else if (keyword.size() > 16 || !std::all_of(keyword.begin(), keyword.end(), [](char c) {
                 return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
               })) {
      throw Error(at(line) + "unknown statement " + shorten(keyword) + ": this does not look like an OBJ file");
    }
    // Other OBJ statements (vn, vt, o, g, s, usemtl, mtllib, l, p ...) carry nothing mrvol uses.
  }
  if (mesh.positions.empty() && pending.empty()) throw Error("empty input: no vertices and no faces");
  if (pending.empty()) throw Error("no faces: the file has " + std::to_string(mesh.vertexCount()) + " vertices but no 'f' lines");
  mesh.faces.resize(pending.size());
  for (size_t i = 0; i < pending.size(); ++i) {
    if (pending[i] >= int64_t(mesh.vertexCount()))
      throw Error(at(faceLines[i / 3]) + "face refers to vertex " + std::to_string(pending[i] + 1) +
                  " but the file has " + std::to_string(mesh.vertexCount()) + " vertices");
    mesh.faces[i] = uint32_t(pending[i]);
  }
  if (lines) lines->vertex = std::move(vertexLines), lines->face = std::move(faceLines);
  return mesh;
}

std::string writeObj(const TriangleMesh& mesh) {
  std::string out;
  out.reserve(mesh.positions.size() * 24 + mesh.faces.size() * 8);
  char buffer[128];
  for (size_t v = 0; v < mesh.vertexCount(); ++v) {
    int n = std::snprintf(buffer, sizeof buffer, "v %.17g %.17g %.17g\n", mesh.positions[3 * v],
                          mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]);
    out.append(buffer, size_t(n));
  }
  for (size_t f = 0; f < mesh.faceCount(); ++f) {
    int n = std::snprintf(buffer, sizeof buffer, "f %u %u %u\n", mesh.faces[3 * f] + 1, mesh.faces[3 * f + 1] + 1,
                          mesh.faces[3 * f + 2] + 1);
    out.append(buffer, size_t(n));
  }
  return out;
}

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

}  // namespace

MeshTopology validateMesh(const TriangleMesh& mesh, const SourceLines* lines) {
  const Names name{lines};
  auto faceName = [&](size_t f) { return name.face(f); };
  const size_t nv = mesh.vertexCount(), nf = mesh.faceCount();
  if (mesh.positions.size() % 3 != 0) throw Error("positions must hold 3 numbers per vertex");
  if (mesh.faces.size() % 3 != 0) throw Error("faces must hold 3 vertex indices per triangle");
  if (nv == 0) throw Error("the mesh has no vertices");
  if (nf == 0) throw Error("the mesh has no faces");
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    double x = mesh.positions[i];
    if (!std::isfinite(x)) throw Error(name.vertex(i / 3) + " has a non-finite coordinate");
    if (std::fabs(x) > kMaxCoordinate)
      throw Error(name.vertex(i / 3) + " has a coordinate beyond 1e100");
  }
  for (size_t f = 0; f < nf; ++f) {
    const uint32_t* t = &mesh.faces[3 * f];
    for (int k = 0; k < 3; ++k)
      if (t[k] >= nv)
        throw Error(faceName(f) + " refers to vertex " + std::to_string(t[k]) + " but there are " +
                    std::to_string(nv) + " vertices");
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
      throw Error(faceName(f) + " is degenerate: it uses " + name.vertex(t[0] == t[1] || t[0] == t[2] ? t[0] : t[1]) +
                  " twice");
  }
  // Duplicate faces: same three vertices, in either orientation.
  {
    std::vector<std::array<uint32_t, 4>> keys(nf);
    for (size_t f = 0; f < nf; ++f) {
      std::array<uint32_t, 3> t{mesh.faces[3 * f], mesh.faces[3 * f + 1], mesh.faces[3 * f + 2]};
      std::sort(t.begin(), t.end());
      keys[f] = {t[0], t[1], t[2], uint32_t(f)};
    }
    std::sort(keys.begin(), keys.end());
    for (size_t i = 1; i < nf; ++i)
      if (keys[i][0] == keys[i - 1][0] && keys[i][1] == keys[i - 1][1] && keys[i][2] == keys[i - 1][2])
        throw Error(faceName(keys[i - 1][3]) + " and " + faceName(keys[i][3]) + " are duplicates (" +
                    name.vertices({keys[i][0], keys[i][1], keys[i][2]}) + ")");
  }
  // Edges, sorted by their undirected key: each in at most two faces, and two faces sharing one
  // must traverse it in opposite directions (else the orientation is inconsistent).
  std::vector<std::array<uint32_t, 4>> halfEdges(3 * nf);  // min, max, forward?, face
  for (size_t f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      uint32_t u = mesh.faces[3 * f + k], v = mesh.faces[3 * f + (k + 1) % 3];
      halfEdges[3 * f + k] = {std::min(u, v), std::max(u, v), uint32_t(u < v), uint32_t(f)};
    }
  std::sort(halfEdges.begin(), halfEdges.end());
  size_t edges = 0;
  std::vector<std::pair<uint32_t, uint32_t>> boundary;
  for (size_t i = 0; i < halfEdges.size();) {
    size_t j = i;
    while (j < halfEdges.size() && halfEdges[j][0] == halfEdges[i][0] && halfEdges[j][1] == halfEdges[i][1]) ++j;
    const std::string edge = "edge between " + name.vertices({halfEdges[i][0], halfEdges[i][1]});
    if (j - i > 2)
      throw Error("non-manifold " + edge + ": shared by " + std::to_string(j - i) + " faces (" +
                  faceName(halfEdges[i][3]) + ", " + faceName(halfEdges[i + 1][3]) + ", " +
                  faceName(halfEdges[i + 2][3]) + (j - i > 3 ? ", ..." : "") + ")");
    if (j - i == 2 && halfEdges[i][2] == halfEdges[i + 1][2])
      throw Error("inconsistent orientation at " + edge + ": " + faceName(halfEdges[i][3]) + " and " +
                  faceName(halfEdges[i + 1][3]) + " traverse it in the same direction");
    ++edges;
    if (j - i == 1) boundary.emplace_back(halfEdges[i][0], halfEdges[i][1]);
    i = j;
  }
  VertexCorners corners(mesh.faces.data(), nf, nv);
  // Vertices: the faces around each must form one fan (no bow-tie). With manifold edges, every
  // link vertex is at most once a `next` and once a `prev`; a fan is a path or a cycle.
  std::vector<std::pair<uint32_t, uint32_t>> link;  // (next, prev), sorted by next
  for (uint32_t u = 0; u < nv; ++u) {
    if (corners.count(u) == 0) throw Error(name.vertex(u) + " is not used by any face");
    link.clear();
    for (uint32_t c = corners.begin(u); c < corners.end(u); ++c) link.emplace_back(corners.next[c], corners.prev[c]);
    std::sort(link.begin(), link.end());
    auto follow = [&](uint32_t v) -> uint32_t {
      auto it = std::lower_bound(link.begin(), link.end(), std::make_pair(v, 0u));
      return it != link.end() && it->first == v ? it->second : kNone;
    };
    std::vector<uint32_t> prevs;
    prevs.reserve(link.size());
    for (auto& e : link) prevs.push_back(e.second);
    std::sort(prevs.begin(), prevs.end());
    uint32_t start = link[0].first, pathStarts = 0;
    for (auto& e : link)
      if (!std::binary_search(prevs.begin(), prevs.end(), e.first)) ++pathStarts, start = e.first;
    size_t walked = 0;
    for (uint32_t v = start; walked <= link.size();) {
      uint32_t w = follow(v);
      if (w == kNone) break;
      ++walked;
      if (w == start) break;
      v = w;
    }
    if (pathStarts > 1 || walked != link.size())
      throw Error("non-manifold " + name.vertex(u) + ": its faces form more than one fan");
  }
  MeshTopology topo;
  topo.edges = edges;
  topo.boundaryEdges = boundary.size();
  topo.closed = boundary.empty();
  UnionFind components(nv);
  for (size_t f = 0; f < nf; ++f) {
    components.unite(mesh.faces[3 * f], mesh.faces[3 * f + 1]);
    components.unite(mesh.faces[3 * f], mesh.faces[3 * f + 2]);
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
  return topo;
}

Vec3 volumeReferencePoint(const TriangleMesh& mesh) {
  const size_t nv = mesh.vertexCount();
  if (nv == 0) return {};
  // Boundary vertices: endpoints of edges traversed once.
  std::vector<uint64_t> keys;
  keys.reserve(mesh.faces.size());
  for (size_t f = 0; f < mesh.faceCount(); ++f)
    for (int k = 0; k < 3; ++k) {
      uint64_t u = mesh.faces[3 * f + k], v = mesh.faces[3 * f + (k + 1) % 3];
      keys.push_back(std::min(u, v) << 32 | std::max(u, v));
    }
  std::sort(keys.begin(), keys.end());
  std::vector<char> onBoundary(nv, 0);
  for (size_t i = 0; i < keys.size(); ++i) {
    bool single = (i == 0 || keys[i - 1] != keys[i]) && (i + 1 == keys.size() || keys[i + 1] != keys[i]);
    if (single) onBoundary[keys[i] >> 32] = onBoundary[keys[i] & 0xffffffffu] = 1;
  }
  Vec3 sum;
  size_t count = 0;
  for (size_t u = 0; u < nv; ++u)
    if (onBoundary[u]) {
      sum.x += mesh.positions[3 * u], sum.y += mesh.positions[3 * u + 1], sum.z += mesh.positions[3 * u + 2];
      ++count;
    }
  if (count > 0) return {sum.x / count, sum.y / count, sum.z / count};
  double lo[3], hi[3];
  for (int k = 0; k < 3; ++k) lo[k] = hi[k] = mesh.positions[k];
  for (size_t v = 0; v < nv; ++v)
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], mesh.positions[3 * v + k]), hi[k] = std::max(hi[k], mesh.positions[3 * v + k]);
  return {(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
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
