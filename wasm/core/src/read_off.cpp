// OFF (Object File Format, Geomview) and its variants COFF (colours), NOFF (normals), CNOFF,
// STOFF (texture coordinates): header keyword, "vertices faces edges", one vertex per line (x y z
// first, then the variant's extra values), one face per line ("n i0 ... i(n-1)" then an optional
// colour). '#' starts a comment. Polygons are split into fans. nOFF of dimension 3 is read; 4OFF, other
// dimensions and binary OFF are refused.
#include <string>
#include <vector>

#include "io_common.h"
#include "mrvol/io_formats.h"

namespace mrvol {

namespace {

using io::count;

// The next line with a token (comments and blank lines skipped); its tokens in `tokens`.
bool nextTokens(io::LineReader& lines, std::vector<std::string_view>& tokens, size_t& n) {
  std::string_view line;
  while (lines.next(line)) {
    size_t hash = line.find('#');
    if (hash != std::string_view::npos) line = line.substr(0, hash);
    n = io::tokenize(line, tokens.data(), tokens.size());
    if (n > tokens.size()) {
      tokens.resize(n);
      io::tokenize(line, tokens.data(), tokens.size());
    }
    if (n > 0) return true;
  }
  return false;
}

}  // namespace

ImportedMesh readOff(std::string_view bytes) {
  ImportedMesh out;
  out.format = MeshFormat::Off;
  if (bytes.empty()) throw Error("empty OFF file (0 bytes)");
  size_t start = bytes.substr(0, 3) == "\xEF\xBB\xBF" ? 3 : 0;
  io::LineReader lines(bytes, start);
  std::vector<std::string_view> tokens(32);
  size_t n = 0;
  auto at = [&] { return "OFF line " + count(lines.line()) + ": "; };
  if (!nextTokens(lines, tokens, n)) throw Error("OFF: the file has no header (only comments or blank lines)");
  std::string_view keyword = tokens[0];
  if (keyword.size() < 3 || keyword.substr(keyword.size() - 3) != "OFF")
    throw Error("not an OFF file: the first keyword is " + io::quoted(keyword) + ", expected OFF, COFF, NOFF, CNOFF or STOFF" +
                io::looksLike(bytes));
  std::string_view prefix = keyword.substr(0, keyword.size() - 3);
  if (prefix.find('4') != std::string_view::npos)
    throw Error(at() + io::quoted(keyword) + ": mrvol reads 3D OFF files only (4OFF has 4 coordinates a vertex)");
  if (prefix.find_first_not_of("STCNn") != std::string_view::npos)
    throw Error(at() + "unknown OFF variant " + io::quoted(keyword));
  if (n > 1 && tokens[1] == "BINARY") throw Error(at() + "binary OFF is not supported; write it as text");
  out.variant = std::string(keyword);
  // What follows the keyword (its dimension for nOFF, then the counts) may be on its line or the next ones.
  size_t first = 1;
  auto nextHeaderLine = [&](const char* what) {
    if (first < n) return;
    if (!nextTokens(lines, tokens, n)) throw Error(std::string("OFF: the file ends before the ") + what);
    first = 0;
  };
  if (prefix.find('n') != std::string_view::npos) {
    // nOFF: "nOFF", then the dimension; mrvol reads 3.
    nextHeaderLine("dimension of its nOFF vertices");
    uint64_t dimension;
    if (!io::parseUnsigned(tokens[first], 1000, dimension))
      throw Error(at() + "nOFF dimension " + io::quoted(tokens[first]) + " is not an integer");
    if (dimension != 3)
      throw Error(at() + io::quoted(keyword) + " of dimension " + count(dimension) + ": mrvol reads 3D OFF files only");
    ++first;
  }
  nextHeaderLine("vertex and face counts");
  if (n - first < 2) throw Error(at() + "expected the counts 'vertices faces [edges]'");
  uint64_t nv, nf;
  if (!io::parseUnsigned(tokens[first], 0xfffffff0u, nv))
    throw Error(at() + "vertex count " + io::quoted(tokens[first]) + " is not an integer in 0..4,294,967,280");
  if (!io::parseUnsigned(tokens[first + 1], 0xffffffffu, nf))
    throw Error(at() + "face count " + io::quoted(tokens[first + 1]) + " is not an integer in 0..4,294,967,295");
  // Sizes before allocating: a vertex line takes at least 6 bytes ("0 0 0\n"), a face 8 ("3 0 1 2\n").
  const uint64_t rest = lines.remaining();
  if (nv > rest / 6 + 1 || nf > rest / 8 + 1 || 6 * nv + 8 * nf > rest + 14)
    throw Error(at() + count(nv) + " vertices and " + count(nf) + " faces declared, the file holds bytes for far fewer (" +
                count(rest) + " bytes after the counts)");
  if (nf == 0) throw Error(at() + "no faces (0 declared)");
  TriangleMesh& m = out.mesh;
  m.positions.reserve(3 * nv);
  for (uint64_t v = 0; v < nv; ++v) {
    if (!nextTokens(lines, tokens, n))
      throw Error("OFF: the file ends after " + count(v) + " of " + count(nv) + " vertices (line " + count(lines.line()) + ")");
    if (n < 3) throw Error(at() + "vertex " + count(v) + " needs 3 coordinates, found " + std::to_string(n));
    for (int k = 0; k < 3; ++k) {
      double x;
      if (!io::parseDouble(tokens[k], x)) throw Error(at() + "coordinate " + io::quoted(tokens[k]) + " is not a number");
      if (!io::coordinateOk(x)) throw Error(at() + "coordinate " + io::quoted(tokens[k]) + " " + io::coordinateProblem(x));
      m.positions.push_back(x);
    }
  }
  std::vector<uint32_t> polygon;
  for (uint64_t f = 0; f < nf; ++f) {
    if (!nextTokens(lines, tokens, n))
      throw Error("OFF: the file ends after " + count(f) + " of " + count(nf) + " faces (line " + count(lines.line()) + ")");
    uint64_t corners;
    if (!io::parseUnsigned(tokens[0], 0xffffffffu, corners))
      throw Error(at() + "face " + count(f) + ": vertex count " + io::quoted(tokens[0]) + " is not an integer");
    if (corners < 3) throw Error(at() + "face " + count(f) + " has " + count(corners) + " vertices, a polygon needs at least 3");
    if (corners > n - 1)
      throw Error(at() + "face " + count(f) + " declares " + count(corners) + " vertices but the line has " +
                  std::to_string(n - 1) + " values");
    polygon.clear();
    for (size_t k = 1; k <= corners; ++k) {
      uint64_t i;
      if (!io::parseUnsigned(tokens[k], 0xffffffffu, i))
        throw Error(at() + "face " + count(f) + ": vertex index " + io::quoted(tokens[k]) + " is not a non-negative integer");
      if (i >= nv)
        throw Error(at() + "face " + count(f) + " refers to vertex " + count(i) + " but the file has " + count(nv) +
                    " vertices (indices start at 0)");
      polygon.push_back(uint32_t(i));
    }
    io::dropRepeatedCorners(polygon);  // "a b c c": the triangle a b c (fewer than 3 left: no area, left out)
    for (size_t k = 1; k + 1 < polygon.size(); ++k) m.faces.insert(m.faces.end(), {polygon[0], polygon[k], polygon[k + 1]});
    if (polygon.size() > 3) ++out.triangulated;
  }
  if (m.faces.empty())
    throw Error("OFF: no face has 3 distinct vertices (" + io::eachFaceRepeats(nf) + ": no area)");
  out.sourceVertices = nv;
  out.sourceFaces = nf;
  out.welded = weldExactPositions(out.mesh, &out.sourceVertex);
  return out;
}

}  // namespace mrvol
