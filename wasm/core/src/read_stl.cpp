// STL: binary (80-byte header, uint32 count, 50 bytes per triangle) and ASCII ("solid ... facet
// normal ... outer loop vertex x y z ... endloop endfacet ... endsolid"). Every triangle has its
// own three vertices: they are welded by exact position.
#include <algorithm>
#include <cstring>
#include <string>

#include "io_common.h"
#include "mrvol/io_formats.h"
#include "position_table.h"

namespace mrvol {

namespace {

using io::count;

// Binary when the size fits the declared count, or when the file does not start like ASCII STL.
bool looksBinary(std::string_view b) {
  if (b.size() >= 84 && b.size() == 84 + 50 * uint64_t(io::load<uint32_t>(b.data() + 80))) return true;
  if (b.substr(0, 5) != "solid") return true;
  // "solid" in a binary header: ASCII STL has only text after it.
  for (char c : b.substr(0, 512)) {
    unsigned char u = static_cast<unsigned char>(c);
    if (u == 0 || (u < 32 && !io::isBlank(c) && c != '\n') || u > 126) return true;
  }
  return false;
}

// The 84-byte header's count checked against the file size; the number of triangles.
uint64_t binaryTriangles(std::string_view b) {
  if (b.size() < 84)
    throw Error("binary STL: the file is " + count(b.size()) +
                " bytes, shorter than the 84-byte header (80 bytes of text and the triangle count)");
  const uint64_t declared = io::load<uint32_t>(b.data() + 80);
  const uint64_t available = (b.size() - 84) / 50;
  if (declared > available)
    throw Error("binary STL: " + count(declared) + " triangles declared, the file holds bytes for " + count(available) +
                " (" + count(b.size()) + " bytes; each triangle takes 50)");
  if (declared == 0) throw Error("binary STL: the file declares 0 triangles");
  return declared;
}

[[noreturn]] void notFinite(uint64_t t, int k) {
  throw Error("binary STL: triangle " + count(t) + " (byte " + count(84 + 50 * t + 12 + 4 * k) + "): coordinate is not finite");
}

// Every corner its own vertex (welded afterwards by weldExactPositions).
void readBinary(std::string_view b, uint64_t declared, ImportedMesh& out) {
  TriangleMesh& m = out.mesh;
  m.positions.resize(9 * declared);
  m.faces.resize(3 * declared);
  const char* p = b.data() + 84;
  for (uint64_t t = 0; t < declared; ++t, p += 50) {
    for (int k = 0; k < 9; ++k) {  // after the 12-byte normal
      double x = io::load<float>(p + 12 + 4 * k);
      if (!std::isfinite(x)) notFinite(t, k);
      m.positions[9 * t + k] = x;
    }
    for (int k = 0; k < 3; ++k) m.faces[3 * t + k] = uint32_t(3 * t + k);
  }
  out.sourceVertices = 3 * declared;
  out.sourceFaces = declared;
  out.welded = weldExactPositions(m, &out.sourceVertex);
}

// The same result read and welded in one pass over the file: each corner's three floats are looked
// up among the positions met so far (equal floats are equal doubles; -0 is made +0 for the lookup,
// the first corner's own value is kept). Output vertices come in the order of their first corner,
// as weldExactPositions numbers them. Gives up (false) when the lookups take more than a few probes
// per corner (positions made to collide in the hash): readBinary then does the work.
bool readBinaryWelded(std::string_view b, uint64_t declared, ImportedMesh& out) {
  const uint64_t corners = 3 * declared;
  // A closed mesh has about one vertex per 6 corners (each vertex in about 6 triangles).
  io::FloatPositionTable table(corners / 6);
  const uint64_t maxProbes = 8 * corners + 1024;
  TriangleMesh& m = out.mesh;
  m.faces.resize(corners);
  m.positions.reserve(3 * (corners / 6 + 16));
  out.sourceVertex.reserve(corners / 6 + 16);
  const char* p = b.data() + 84;
  uint32_t next = 0;
  for (uint64_t t = 0; t < declared; ++t, p += 50) {
    for (int c = 0; c < 3; ++c) {
      uint32_t key[3];
      std::memcpy(key, p + 12 + 12 * c, 12);
      for (int k = 0; k < 3; ++k) {
        if ((key[k] & 0x7f800000u) == 0x7f800000u) notFinite(t, 3 * c + k);
        if (key[k] == 0x80000000u) key[k] = 0;  // -0 == +0
      }
      const uint32_t v = table.findOrAdd(key);
      if (v == next) {
        for (int k = 0; k < 3; ++k) m.positions.push_back(io::load<float>(p + 12 + 12 * c + 4 * k));
        out.sourceVertex.push_back(uint32_t(3 * t + c));
        ++next;
      }
      m.faces[3 * t + c] = v;
    }
    if (table.probes() > maxProbes) return false;
  }
  out.sourceVertices = corners;
  out.sourceFaces = declared;
  out.welded = corners - next;
  return true;
}

void readAscii(std::string_view b, ImportedMesh& out) {
  io::LineReader lines(b);
  std::string_view line, tokens[8];
  TriangleMesh& m = out.mesh;
  int corner = -1;  // -1 outside a loop, else corners read in the current loop
  bool ended = false;
  auto at = [&] { return "ASCII STL line " + count(lines.line()) + ": "; };
  while (lines.next(line)) {
    size_t n = io::tokenize(line, tokens, 8);
    if (n == 0) continue;
    std::string_view key = tokens[0];
    if (ended) {
      if (key == "solid") { ended = false; continue; }  // several solids in one file
      throw Error(at() + "unexpected " + io::quoted(key) + " after 'endsolid'");
    }
    if (key == "solid" || key == "facet" || key == "endfacet") {
      if (corner >= 0) throw Error(at() + io::quoted(key) + " inside an 'outer loop' (missing 'endloop')");
      continue;
    }
    if (key == "outer") {
      if (n < 2 || tokens[1] != "loop") throw Error(at() + "expected 'outer loop'");
      if (corner >= 0) throw Error(at() + "'outer loop' inside another (missing 'endloop')");
      corner = 0;
    } else if (key == "vertex") {
      if (corner < 0) throw Error(at() + "'vertex' outside an 'outer loop'");
      if (n != 4) throw Error(at() + "vertex needs 3 coordinates, found " + std::to_string(n - 1));
      if (corner == 3) throw Error(at() + "a facet with more than 3 vertices (mrvol reads STL triangles)");
      for (int k = 1; k <= 3; ++k) {
        double x;
        if (!io::parseDouble(tokens[k], x)) throw Error(at() + "coordinate " + io::quoted(tokens[k]) + " is not a number");
        if (!io::coordinateOk(x)) throw Error(at() + "coordinate " + io::quoted(tokens[k]) + " " + io::coordinateProblem(x));
        m.positions.push_back(x);
      }
      ++corner;
    } else if (key == "endloop") {
      if (corner != 3)
        throw Error(at() + "a facet with " + std::to_string(std::max(corner, 0)) + " vertices, a triangle needs 3");
      uint32_t v = uint32_t(m.positions.size() / 3);
      m.faces.insert(m.faces.end(), {v - 3, v - 2, v - 1});
      corner = -1;
    } else if (key == "endsolid") {
      if (corner >= 0) throw Error(at() + "'endsolid' inside an 'outer loop'");
      ended = true;
    } else {
      throw Error(at() + "unknown keyword " + io::quoted(key) + " (ASCII STL has solid, facet, outer loop, vertex, "
                  "endloop, endfacet, endsolid)");
    }
  }
  if (corner >= 0) throw Error("ASCII STL: the file ends inside a facet (line " + count(lines.line()) + ")");
  if (m.faces.empty()) throw Error("ASCII STL: no facets in the file");
  out.variant = "ASCII STL";
}

}  // namespace

ImportedMesh readStl(std::string_view bytes) {
  ImportedMesh out;
  out.format = MeshFormat::Stl;
  if (bytes.empty()) throw Error("empty STL file (0 bytes)");
  if (looksBinary(bytes)) {
    const uint64_t declared = binaryTriangles(bytes);
    out.variant = "binary STL";
    if (!readBinaryWelded(bytes, declared, out)) {
      out.mesh = {};
      out.sourceVertex = {};
      readBinary(bytes, declared, out);
    }
    return out;
  }
  readAscii(bytes, out);
  out.sourceVertices = out.mesh.vertexCount();
  out.sourceFaces = out.mesh.faceCount();
  out.welded = weldExactPositions(out.mesh, &out.sourceVertex);
  return out;
}

}  // namespace mrvol
