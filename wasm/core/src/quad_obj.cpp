#include "mrvol/quad_obj.h"

#include <charconv>
#include <cstdio>

#include "mrvol/error.h"
#include "mrvol/mesh.h"
#include "number_text.h"

namespace mrvol {

namespace {
bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r'; }
}  // namespace

QuadMesh readObjQuads(std::string_view text) {
  QuadMesh mesh;
  mesh.positions = readObj(text).positions;  // vertices, with readObj's checks
  size_t vertices = 0, lineNo = 0;
  for (size_t at = 0; at <= text.size();) {
    size_t end = text.find('\n', at);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(at, end - at);
    at = end + 1;
    ++lineNo;
    if (lineNo == 1 && line.size() >= 3 && line.substr(0, 3) == "\xEF\xBB\xBF") line.remove_prefix(3);
    if (size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    size_t i = 0;
    while (i < line.size() && isSpace(line[i])) ++i;
    if (i + 1 < line.size() && line[i] == 'v' && isSpace(line[i + 1])) {
      ++vertices;
      continue;
    }
    if (!(i + 1 < line.size() && line[i] == 'f' && isSpace(line[i + 1]))) continue;
    i += 2;
    uint32_t corners[4];
    int count = 0;
    while (true) {
      while (i < line.size() && isSpace(line[i])) ++i;
      if (i >= line.size()) break;
      size_t tokenEnd = i;
      while (tokenEnd < line.size() && !isSpace(line[tokenEnd])) ++tokenEnd;
      long long index = 0;
      auto [ptr, ec] = std::from_chars(line.data() + i, line.data() + tokenEnd, index);
      if (ec != std::errc() || (ptr != line.data() + tokenEnd && *ptr != '/') || index == 0)
        throw Error("line " + std::to_string(lineNo) + ": bad vertex index '" + std::string(line.substr(i, tokenEnd - i)) + "'");
      const long long resolved = index < 0 ? (long long)vertices + index : index - 1;
      if (resolved < 0 || resolved >= (long long)vertices)
        throw Error("line " + std::to_string(lineNo) + ": face refers to vertex " + std::to_string(index) + " but " +
                    std::to_string(vertices) + " vertices precede it");
      if (count < 4) corners[count] = uint32_t(resolved);
      ++count;
      i = tokenEnd;
    }
    if (count != 4)
      throw Error("line " + std::to_string(lineNo) + ": a face with " + std::to_string(count) +
                  " corners: the catmull-clark scheme needs a mesh made of quads only");
    mesh.quads.insert(mesh.quads.end(), corners, corners + 4);
  }
  if (mesh.quads.empty()) throw Error("the file has no faces");
  return mesh;
}

std::string writeObjQuads(const QuadMesh& mesh) {
  std::string out;
  // a line at most: "v " + 3 x 24 characters + "\n"; "f " + 4 x 11
  out.resize(mesh.vertexCount() * 80 + mesh.quads.size() / 4 * 50);
  char* at = out.data();
  for (size_t v = 0; v < mesh.vertexCount(); ++v) {
    *at++ = 'v';
    for (int k = 0; k < 3; ++k) {
      *at++ = ' ';
      at = text::writeShortest(at, mesh.positions[3 * v + k]);
    }
    *at++ = '\n';
  }
  for (size_t f = 0; f < mesh.quads.size(); f += 4) {
    *at++ = 'f';
    for (int k = 0; k < 4; ++k) {
      *at++ = ' ';
      at = text::writeUnsigned(at, mesh.quads[f + k] + 1);
    }
    *at++ = '\n';
  }
  out.resize(size_t(at - out.data()));
  return out;
}

}  // namespace mrvol
