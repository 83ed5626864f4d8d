// PLY (Stanford polygon file): ASCII, binary little-endian and binary big-endian. The vertex
// element's x, y, z (any numeric type) and the face element's index list (any count and index
// type, named vertex_indices or vertex_index) are read; other properties and elements are skipped.
// Polygons are split into fans. Vertices are welded by exact position (files split them at
// normal or texture seams).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "io_common.h"
#include "mrvol/io_formats.h"

namespace mrvol {

namespace {

using io::count;

enum class Type { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

bool parseType(std::string_view s, Type& t) {
  if (s == "char" || s == "int8") t = Type::Int8;
  else if (s == "uchar" || s == "uint8") t = Type::UInt8;
  else if (s == "short" || s == "int16") t = Type::Int16;
  else if (s == "ushort" || s == "uint16") t = Type::UInt16;
  else if (s == "int" || s == "int32") t = Type::Int32;
  else if (s == "uint" || s == "uint32") t = Type::UInt32;
  else if (s == "float" || s == "float32") t = Type::Float32;
  else if (s == "double" || s == "float64") t = Type::Float64;
  else return false;
  return true;
}

size_t sizeOf(Type t) {
  switch (t) {
    case Type::Int8: case Type::UInt8: return 1;
    case Type::Int16: case Type::UInt16: return 2;
    case Type::Int32: case Type::UInt32: case Type::Float32: return 4;
    case Type::Float64: return 8;
  }
  return 1;
}

bool isInteger(Type t) { return t != Type::Float32 && t != Type::Float64; }

double loadValue(const char* p, Type t, bool big) {
  switch (t) {
    case Type::Int8: return io::load<int8_t>(p, big);
    case Type::UInt8: return io::load<uint8_t>(p, big);
    case Type::Int16: return io::load<int16_t>(p, big);
    case Type::UInt16: return io::load<uint16_t>(p, big);
    case Type::Int32: return io::load<int32_t>(p, big);
    case Type::UInt32: return io::load<uint32_t>(p, big);
    case Type::Float32: return io::load<float>(p, big);
    case Type::Float64: return io::load<double>(p, big);
  }
  return 0;
}

struct Property {
  std::string name;
  Type type = Type::Float32;
  bool list = false;
  Type countType = Type::UInt8;
};

struct Element {
  std::string name;
  uint64_t count = 0;
  std::vector<Property> properties;
  size_t headerLine = 0;
  // Roles, as property indices (-1: none).
  int x = -1, y = -1, z = -1, indices = -1;
  bool isVertex() const { return name == "vertex"; }
  bool isFace() const { return name == "face"; }
  // Bytes one item takes at least: scalars, and the count of each list.
  size_t minBinaryBytes() const {
    size_t n = 0;
    for (const Property& p : properties) n += p.list ? sizeOf(p.countType) : sizeOf(p.type);
    return n;
  }
};

enum class Encoding { Ascii, Little, Big };

struct Header {
  Encoding encoding = Encoding::Ascii;
  std::vector<Element> elements;
  size_t dataStart = 0;
  size_t dataLine = 0;  // line of the first data line (ASCII)
};

Header parseHeader(std::string_view b) {
  Header h;
  io::LineReader lines(b);
  std::string_view line;
  std::vector<std::string_view> tokens(8);
  bool haveFormat = false, ended = false;
  auto at = [&] { return "PLY header line " + count(lines.line()) + ": "; };
  // "ply", blanks after it tolerated (some writers leave one)
  if (!lines.next(line) || line.substr(0, 3) != "ply" || line.substr(3).find_first_not_of(" \t\r") != std::string_view::npos)
    throw Error("not a PLY file: the first line must be 'ply'" + io::looksLike(b));
  while (!ended && lines.next(line)) {
    size_t n = io::tokenize(line, tokens.data(), tokens.size());
    if (n == 0) continue;
    std::string_view key = tokens[0];
    if (key == "comment" || key == "obj_info") continue;
    if (key == "format") {
      if (n != 3) throw Error(at() + "expected 'format ascii|binary_little_endian|binary_big_endian 1.0'");
      if (tokens[1] == "ascii") h.encoding = Encoding::Ascii;
      else if (tokens[1] == "binary_little_endian") h.encoding = Encoding::Little;
      else if (tokens[1] == "binary_big_endian") h.encoding = Encoding::Big;
      else throw Error(at() + "unknown format " + io::quoted(tokens[1]));
      if (tokens[2] != "1.0" && tokens[2] != "1") throw Error(at() + "unsupported PLY version " + io::quoted(tokens[2]));
      haveFormat = true;
    } else if (key == "element") {
      uint64_t c;
      if (n != 3) throw Error(at() + "expected 'element NAME COUNT'");
      if (!io::parseUnsigned(tokens[2], 0xffffffffu, c))
        throw Error(at() + "element count " + io::quoted(tokens[2]) + " is not an integer in 0..4,294,967,295");
      Element e;
      e.name = std::string(tokens[1]);
      e.count = c;
      e.headerLine = lines.line();
      h.elements.push_back(std::move(e));
    } else if (key == "property") {
      if (h.elements.empty()) throw Error(at() + "'property' before any 'element'");
      Property p;
      if (n >= 2 && tokens[1] == "list") {
        if (n != 5) throw Error(at() + "expected 'property list COUNT_TYPE INDEX_TYPE NAME'");
        if (!parseType(tokens[2], p.countType)) throw Error(at() + "unknown type " + io::quoted(tokens[2]));
        if (!parseType(tokens[3], p.type)) throw Error(at() + "unknown type " + io::quoted(tokens[3]));
        if (!isInteger(p.countType)) throw Error(at() + "list count type " + io::quoted(tokens[2]) + " is not an integer type");
        p.list = true;
        p.name = std::string(tokens[4]);
      } else {
        if (n != 3) throw Error(at() + "expected 'property TYPE NAME'");
        if (!parseType(tokens[1], p.type)) throw Error(at() + "unknown type " + io::quoted(tokens[1]));
        p.name = std::string(tokens[2]);
      }
      h.elements.back().properties.push_back(std::move(p));
    } else if (key == "end_header") {
      ended = true;
    } else {
      throw Error(at() + "unknown header keyword " + io::quoted(key));
    }
  }
  if (!ended) throw Error("PLY: the header has no 'end_header' line");
  if (!haveFormat) throw Error("PLY: the header has no 'format' line");
  h.dataStart = lines.offset();
  h.dataLine = lines.line() + 1;
  const size_t dataBytes = b.size() - std::min(b.size(), h.dataStart);
  for (Element& e : h.elements) {
    for (size_t i = 0; i < e.properties.size(); ++i) {
      const Property& p = e.properties[i];
      if (e.isVertex() && !p.list) {
        if (p.name == "x") e.x = int(i);
        if (p.name == "y") e.y = int(i);
        if (p.name == "z") e.z = int(i);
      }
      if (e.isFace() && p.list && (p.name == "vertex_indices" || p.name == "vertex_index")) e.indices = int(i);
    }
    const std::string where = "PLY header line " + count(e.headerLine) + ": element '" + e.name + "'";
    if (e.count > 0 && e.properties.empty()) throw Error(where + " has " + count(e.count) + " items but no properties");
    // Sizes before allocating: an ASCII item takes at least 2 bytes per property ("0 "), a
    // binary one its scalars and list counts.
    const size_t minBytes = h.encoding == Encoding::Ascii ? 2 * e.properties.size() : e.minBinaryBytes();
    if (minBytes > 0 && e.count > dataBytes / minBytes + (h.encoding == Encoding::Ascii ? 1 : 0))
      throw Error(where + " declares " + count(e.count) + " items, the file holds bytes for at most " +
                  count(dataBytes / minBytes) + " (" + count(dataBytes) + " bytes after the header)");
  }
  return h;
}

struct Builder {
  ImportedMesh& out;
  // The PLY face of each triangle (for index errors): the first `identityTriangles` triangles are
  // faces 0, 1, 2, ... (files of triangles: nothing stored), faceOf holds the rest.
  std::vector<uint32_t> faceOf;
  std::vector<int64_t> polygon;
  uint64_t vertexCount = 0;
  size_t identityTriangles = 0;
  // Face indices from the start already checked against the vertices read (the common layout's
  // fast path checks them as it reads): the final check starts after them.
  size_t checkedIndices = 0;

  uint64_t faceOfTriangle(size_t t) const { return t < identityTriangles ? t : faceOf[t - identityTriangles]; }

  // `where` makes the message prefix only when there is an error (a string per face would cost
  // more than reading it).
  template <class Where>
  void addPolygon(const Where& where) {
    if (polygon.size() < 3)
      throw Error(where() + "has " + std::to_string(polygon.size()) + " vertices, a polygon needs at least 3");
    io::dropRepeatedCorners(polygon);
    if (polygon.size() < 3) {  // all its corners one or two vertices: no area, left out
      ++out.sourceFaces;
      return;
    }
    for (size_t k = 1; k + 1 < polygon.size(); ++k) {
      out.mesh.faces.push_back(uint32_t(polygon[0]));
      out.mesh.faces.push_back(uint32_t(polygon[k]));
      out.mesh.faces.push_back(uint32_t(polygon[k + 1]));
      faceOf.push_back(uint32_t(out.sourceFaces));
    }
    if (polygon.size() > 3) ++out.triangulated;
    ++out.sourceFaces;
  }
  template <class Where>
  void addIndex(double value, const Where& where) {
    if (value < 0 || value != std::floor(value) || value > 0xfffffff0u) {
      // Cast to an integer only within int64's range (beyond, and for NaN, the cast is undefined).
      char shown[32];
      if (std::fabs(value) < 9e18) std::snprintf(shown, sizeof shown, "%lld", static_cast<long long>(value));
      else std::snprintf(shown, sizeof shown, "%g", value);
      throw Error(where() + "vertex index " + shown + " is not valid");
    }
    polygon.push_back(int64_t(value));
  }
};

// Fast path for a vertex element of scalars only with float or double x, y, z: fixed stride,
// coordinates at fixed offsets. Returns the items read (all, or none when the element does not fit
// this shape or the file is too short, then the general loop reads it and names the problem).
template <class T>
uint64_t readFixedVertices(std::string_view b, const Element& e, size_t pos, bool big, TriangleMesh& m) {
  size_t stride = 0, offset[3] = {0, 0, 0};
  for (size_t pi = 0; pi < e.properties.size(); ++pi) {
    const Property& p = e.properties[pi];
    if (p.list) return 0;
    for (int k = 0; k < 3; ++k)
      if (int(pi) == (k == 0 ? e.x : k == 1 ? e.y : e.z)) {
        if (sizeOf(p.type) != sizeof(T) || isInteger(p.type)) return 0;
        offset[k] = stride;
      }
    stride += sizeOf(p.type);
  }
  if (stride == 0 || e.count > (b.size() - pos) / stride) return 0;
  const size_t first = m.positions.size();
  m.positions.resize(first + 3 * e.count);
  double* out = m.positions.data() + first;
  const char* item = b.data() + pos;
  for (uint64_t v = 0; v < e.count; ++v, item += stride)
    for (int k = 0; k < 3; ++k) {
      const double x = io::load<T>(item + offset[k], big);
      if (!io::coordinateOk(x))
        throw Error("binary PLY: vertex " + count(v) + ": coordinate " + "xyz"[k] + " " + io::coordinateProblem(x));
      out[3 * v + k] = x;
    }
  return e.count;
}

// Fast path for a face element whose only property is a 1-byte-counted list of 4-byte integer
// indices: triangles are read straight from the bytes, each index checked against the vertices
// read so far when the vertex element came first. Stops at the first item that is not a triangle
// or not plainly valid (the general loop takes over there and names the problem); returns the
// items read.
uint64_t readTriangleFaces(std::string_view b, const Element& e, size_t& pos, bool big, Builder& build) {
  if (e.properties.size() != 1) return 0;
  const Property& p = e.properties[0];
  if (!p.list || sizeOf(p.countType) != 1 || (p.type != Type::Int32 && p.type != Type::UInt32)) return 0;
  std::vector<uint32_t>& faces = build.out.mesh.faces;
  const size_t firstIndex = faces.size(), firstTriangle = firstIndex / 3;
  // Triangles so far are faces 0, 1, ... with no faceOf entries: these stay so.
  const bool identity =
      build.faceOf.empty() && build.identityTriangles == firstTriangle && build.out.sourceFaces == firstTriangle;
  // An index below the vertices read so far is below the final count too (0xfffffff0: the
  // general loop's bound, when the vertices come later).
  const uint64_t vertices = build.out.mesh.vertexCount();
  const bool checked = vertices > 0 && build.checkedIndices == firstIndex;
  // An int32 read as unsigned: a negative one is above 0x7fffffff.
  const uint64_t bound = std::min<uint64_t>(p.type == Type::Int32 ? 0x7fffffffu : 0xfffffff0u, 0xfffffff0u);
  const uint32_t limit = uint32_t(checked ? std::min<uint64_t>(vertices - 1, bound) : bound);
  // Written in place (the arrays sized for every item, cut back to those read).
  const size_t items = size_t(std::min<uint64_t>(e.count, (b.size() - pos) / 13));
  faces.resize(firstIndex + 3 * items);
  if (!identity) build.faceOf.resize(build.faceOf.size() + items);
  uint32_t* out = faces.data() + firstIndex;
  uint32_t* faceOf = identity ? nullptr : build.faceOf.data() + build.faceOf.size() - items;
  const char* at = b.data() + pos;
  size_t item = 0;
  if (!big) {
    for (; item < items && uint8_t(at[0]) == 3; ++item, at += 13) {
      const uint32_t i0 = io::load<uint32_t>(at + 1), i1 = io::load<uint32_t>(at + 5), i2 = io::load<uint32_t>(at + 9);
      if ((i0 > limit) | (i1 > limit) | (i2 > limit)) break;
      out[3 * item] = i0, out[3 * item + 1] = i1, out[3 * item + 2] = i2;
    }
  } else {
    for (; item < items && uint8_t(at[0]) == 3; ++item, at += 13) {
      uint32_t index[3];
      for (int k = 0; k < 3; ++k) index[k] = io::load<uint32_t>(at + 1 + 4 * k, true);
      if ((index[0] > limit) | (index[1] > limit) | (index[2] > limit)) break;
      for (int k = 0; k < 3; ++k) out[3 * item + k] = index[k];
    }
  }
  if (identity) {
    build.identityTriangles += item;
  } else {
    for (size_t i = 0; i < item; ++i) faceOf[i] = uint32_t(build.out.sourceFaces + i);
    build.faceOf.resize(build.faceOf.size() - (items - item));
  }
  build.out.sourceFaces += item;
  if (checked) build.checkedIndices += 3 * item;
  pos += 13 * item;
  faces.resize(firstIndex + 3 * item);
  return item;
}

void readBinaryData(std::string_view b, const Header& h, Builder& build) {
  const bool big = h.encoding == Encoding::Big;
  size_t pos = h.dataStart;
  TriangleMesh& m = build.out.mesh;
  for (const Element& e : h.elements) {
    const bool vertex = e.isVertex(), face = e.isFace() && e.indices >= 0;
    uint64_t item = 0;
    if (vertex && e.x >= 0 && e.y >= 0 && e.z >= 0) {
      const Type t = e.properties[e.x].type;
      item = t == Type::Float32 ? readFixedVertices<float>(b, e, pos, big, m)
           : t == Type::Float64 ? readFixedVertices<double>(b, e, pos, big, m) : 0;
      if (item > 0) pos += size_t(item) * e.minBinaryBytes();
    } else if (face) {
      item = readTriangleFaces(b, e, pos, big, build);
    }
    for (; item < e.count; ++item) {
      auto where = [&] { return "binary PLY: " + e.name + " " + count(item) + " (byte " + count(pos) + "): "; };
      if (face) build.polygon.clear();
      double xyz[3] = {0, 0, 0};
      for (size_t pi = 0; pi < e.properties.size(); ++pi) {
        const Property& p = e.properties[pi];
        if (!p.list) {
          if (b.size() - pos < sizeOf(p.type))
            throw Error(where() + "the file ends (" + count(b.size()) + " bytes); " + count(e.count) + " " + e.name +
                        " items declared");
          if (vertex) {
            if (int(pi) == e.x) xyz[0] = loadValue(b.data() + pos, p.type, big);
            if (int(pi) == e.y) xyz[1] = loadValue(b.data() + pos, p.type, big);
            if (int(pi) == e.z) xyz[2] = loadValue(b.data() + pos, p.type, big);
          }
          pos += sizeOf(p.type);
          continue;
        }
        if (b.size() - pos < sizeOf(p.countType))
          throw Error(where() + "the file ends (" + count(b.size()) + " bytes); " + count(e.count) + " " + e.name +
                      " items declared");
        const double n = loadValue(b.data() + pos, p.countType, big);
        if (n < 0) throw Error(where() + "list '" + p.name + "' has a negative length");
        pos += sizeOf(p.countType);
        const uint64_t bytes = uint64_t(n) * sizeOf(p.type);
        if (bytes > b.size() - pos)
          throw Error(where() + "list '" + p.name + "' of " + count(uint64_t(n)) + " values runs past the end of the file (" +
                      count(b.size()) + " bytes)");
        if (face && int(pi) == e.indices) {
          const size_t listStart = pos;
          auto at = [&] { return "binary PLY: face " + count(item) + " (byte " + count(listStart) + ") "; };
          for (uint64_t k = 0; k < uint64_t(n); ++k)
            build.addIndex(loadValue(b.data() + pos + k * sizeOf(p.type), p.type, big), at);
          build.addPolygon(at);
        }
        pos += size_t(bytes);
      }
      if (vertex) {
        for (int k = 0; k < 3; ++k)
          if (!io::coordinateOk(xyz[k]))
            throw Error("binary PLY: vertex " + count(item) + ": coordinate " + "xyz"[k] + " " + io::coordinateProblem(xyz[k]));
        m.positions.insert(m.positions.end(), xyz, xyz + 3);
      }
    }
  }
}

void readAsciiData(std::string_view b, const Header& h, Builder& build) {
  io::LineReader lines(b, h.dataStart, h.dataLine);
  std::string_view line;
  std::vector<std::string_view> tokens(64);
  TriangleMesh& m = build.out.mesh;
  for (const Element& e : h.elements) {
    const bool vertex = e.isVertex(), face = e.isFace() && e.indices >= 0;
    for (uint64_t item = 0; item < e.count; ++item) {
      size_t n;
      do {
        if (!lines.next(line))
          throw Error("ASCII PLY: the file ends at line " + count(lines.line()) + " after " + count(item) + " of " +
                      count(e.count) + " " + e.name + " items");
        n = io::tokenize(line, tokens.data(), tokens.size());
        if (n > tokens.size()) {
          tokens.resize(n);
          io::tokenize(line, tokens.data(), tokens.size());
        }
      } while (n == 0);
      auto at = [&] { return "PLY line " + count(lines.line()) + ": " + e.name + " " + count(item) + " "; };
      size_t t = 0;
      auto value = [&](const char* what) {
        if (t >= n) throw Error(at() + "has " + std::to_string(n) + " values, too few for the header's properties");
        double x;
        if (!io::parseDouble(tokens[t], x)) throw Error(at() + what + " " + io::quoted(tokens[t]) + " is not a number");
        ++t;
        return x;
      };
      double xyz[3] = {0, 0, 0};
      if (face) build.polygon.clear();
      for (size_t pi = 0; pi < e.properties.size(); ++pi) {
        const Property& p = e.properties[pi];
        if (!p.list) {
          double x = value("value");
          if (vertex) {
            if (int(pi) == e.x) xyz[0] = x;
            if (int(pi) == e.y) xyz[1] = x;
            if (int(pi) == e.z) xyz[2] = x;
          }
          continue;
        }
        double len = value("list length");
        if (len < 0 || len != std::floor(len) || len > double(n - t))
 throw Error(at() + "list '" + p.name + "' length " + io::quoted(tokens[t - 1]) + " does not fit the " +
                      std::to_string(n - t) + " values after it");
        for (size_t k = 0; k < size_t(len); ++k) {
          double x = value("list value");
          if (face && int(pi) == e.indices) build.addIndex(x, at);
        }
        if (face && int(pi) == e.indices) build.addPolygon(at);
      }
 if (t != n) throw Error(at() + "has " + std::to_string(n) + " values, the header's properties take " + std::to_string(t));
      if (vertex) {
        for (int k = 0; k < 3; ++k)
          if (!io::coordinateOk(xyz[k]))
            throw Error(at() + "coordinate " + "xyz"[k] + " " + io::coordinateProblem(xyz[k]));
        m.positions.insert(m.positions.end(), xyz, xyz + 3);
      }
    }
  }
}

}  // namespace

ImportedMesh readPly(std::string_view bytes) {
  ImportedMesh out;
  out.format = MeshFormat::Ply;
  if (bytes.empty()) throw Error("empty PLY file (0 bytes)");
  // A UTF-8 byte order mark before "ply" (the header is text): skipped.
  if (io::hasByteOrderMark(bytes)) bytes.remove_prefix(3);
  const Header h = parseHeader(bytes);
  const Element* vertex = nullptr;
  const Element* face = nullptr;
  for (const Element& e : h.elements) {
    if (e.isVertex()) vertex = &e;
    if (e.isFace()) face = &e;
  }
  if (!vertex) throw Error("PLY: the header declares no 'vertex' element");
  if (vertex->x < 0 || vertex->y < 0 || vertex->z < 0)
    throw Error("PLY header line " + count(vertex->headerLine) + ": the vertex element lacks property x, y or z");
  if (!face || face->count == 0) throw Error("PLY: no faces (the file declares no 'face' items: a point cloud?)");
  if (face->indices < 0)
    throw Error("PLY header line " + count(face->headerLine) + ": the face element has no list 'vertex_indices'");
  out.mesh.positions.reserve(3 * vertex->count);
  Builder build{out, {}, {}, vertex->count};
  if (h.encoding == Encoding::Ascii) readAsciiData(bytes, h, build), out.variant = "ASCII PLY";
  else {
    readBinaryData(bytes, h, build);
    out.variant = h.encoding == Encoding::Little ? "binary little-endian PLY" : "binary big-endian PLY";
  }
  const uint64_t nv = out.mesh.vertexCount();
  for (size_t i = build.checkedIndices; i < out.mesh.faces.size(); ++i)
    if (out.mesh.faces[i] >= nv)
      throw Error("PLY: face " + count(build.faceOfTriangle(i / 3)) + " refers to vertex " + count(out.mesh.faces[i]) +
                  " but the file has " + count(nv) + " vertices (indices start at 0)");
  if (out.mesh.faces.empty())
    throw Error("PLY: no face has 3 distinct vertices (" + io::eachFaceRepeats(face->count) + ": no area)");
  out.sourceVertices = nv;
  out.welded = weldExactPositions(out.mesh, &out.sourceVertex);
  return out;
}

}  // namespace mrvol
