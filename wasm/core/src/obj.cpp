// OBJ text in and out. One pass over the bytes with pointers: no line or token copies, numbers
// parsed in place by fast_float (no allocation, no locale), arrays sized from a first counting pass
// so that a file too large to open is refused before anything large is allocated.
#include <algorithm>
#include <cstdint>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "fast_float.h"
#include "io_common.h"
#include "number_text.h"
#include "mrvol/error.h"
#include "mrvol/io_formats.h"
#include "mrvol/mesh.h"
#include "mrvol/obj_reader.h"

namespace mrvol {

namespace {

// Coordinates beyond this would overflow the volume's triple products (|x|^3 must stay finite).
constexpr double kMaxCoordinate = 1e100;
constexpr size_t kMaxIndex = 0xfffffff0u;
// Non-convex polygons are ear-clipped in O(k^2); beyond this many corners that would stall.
constexpr size_t kMaxEarClippedCorners = 4096;

std::string at(size_t line) { return "line " + std::to_string(line) + ": "; }

std::string shorten(std::string_view token) {
  std::string s(token.substr(0, 40));
  for (char& c : s)
    if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126) c = '?';
  if (token.size() > 40) s += "...";
  return "'" + s + "'";
}

// Byte classes for the tokenizer: one table lookup per byte.
enum : uint8_t { kText = 0, kBlank = 1, kHash = 2 };
struct ByteClasses {
  uint8_t of[256] = {};
  constexpr ByteClasses() {
    for (unsigned char c : {' ', '\t', '\r', '\f', '\v'}) of[c] = kBlank;
    of[static_cast<unsigned char>('#')] = kHash;
  }
};
constexpr ByteClasses kClasses;
inline uint8_t classOf(char c) { return kClasses.of[static_cast<unsigned char>(c)]; }
inline bool isSpace(char c) { return classOf(c) == kBlank; }

// The next whitespace-separated token of [p, end), or an empty view at the end; a `#` ends the
// content (a comment), also inside a token.
inline std::string_view nextToken(const char*& p, const char*& end) {
  while (p < end && classOf(*p) == kBlank) ++p;
  const char* start = p;
  while (p < end && classOf(*p) == kText) ++p;
  if (p < end && *p == '#') end = p;
  return std::string_view(start, size_t(p - start));
}

// True when one of the 8 bytes is below 32 (a newline, a tab, a control byte): the usual
// "has a byte less than n" word trick, exact for n <= 128.
inline bool hasControlByte(const char* p) {
  uint64_t w;
  std::memcpy(&w, p, 8);
  return ((w - 0x2020202020202020ull) & ~w & 0x8080808080808080ull) != 0;
}

// strtod's forms for a coordinate: an optional sign ('+' too), decimal with optional exponent;
// inf / nan words are recognised only to be refused as not finite. No allocation.
double parseCoordinate(std::string_view token, size_t line) {
  constexpr size_t kMaxLength = 63;
  if (token.size() > kMaxLength)
    throw Error(at(line) + "coordinate " + shorten(token) + " is too long (" + std::to_string(token.size()) +
                " characters; mrvol reads at most " + std::to_string(kMaxLength) + ")");
  const char* first = token.data();
  const char* last = first + token.size();
  if (first < last && *first == '+') ++first;  // fast_float (like from_chars) takes no '+'; strtod does
  const char* digits = first + (first < last && *first == '-');
  double value = 0;
  auto result = fast_float::from_chars(first, last, value);
  if (result.ec != std::errc() || result.ptr != last || digits == last || (first != token.data() && digits != first))
    throw Error(at(line) + "coordinate " + shorten(token) + " is not a number");
  const bool numeral = (*digits >= '0' && *digits <= '9') || *digits == '.';
  if (!numeral)  // inf, infinity, nan (any case)
    throw Error(at(line) + "coordinate " + shorten(token) + " is not finite");
  if (!(std::fabs(value) <= kMaxCoordinate))  // also a numeral that overflows a double (1e400)
    throw Error(at(line) + "coordinate " + shorten(token) +
                " is too large (mrvol accepts |x| <= 1e100 so that volumes stay finite)");
  return value;
}

// An OBJ index: 1-based, or negative relative to the `soFar` elements read. Returns 0-based, or
// kNoIndex for an empty field (`f 1//2`'s texture index). `what`: "face", "texture", "normal".
uint32_t parseIndex(std::string_view digits, std::string_view token, size_t line, size_t soFar, const char* what) {
  constexpr uint32_t kNoIndex = ObjExtras::kNoIndex;
  const bool vertex = what[0] == 'f';
  if (digits.empty()) {
    if (vertex) throw Error(at(line) + "face vertex " + shorten(token) + " has no vertex index");
    return kNoIndex;
  }
  const bool negative = digits[0] == '-';
  const size_t start = (digits[0] == '-' || digits[0] == '+') ? 1 : 0;
  // Built for a message only: this runs for every corner of every face.
  auto prefix = [&] { return vertex ? std::string("face index ") : std::string("face ") + what + " index "; };
  if (start == digits.size()) throw Error(at(line) + prefix() + shorten(token) + " is not an integer");
  uint64_t value = 0;
  for (size_t i = start; i < digits.size(); ++i) {
    const unsigned digit = unsigned(digits[i]) - '0';
    if (digit > 9) throw Error(at(line) + prefix() + shorten(token) + " is not an integer");
    value = value * 10 + digit;
    if (value > kMaxIndex) throw Error(at(line) + prefix() + shorten(digits) + " is out of range");
  }
  // A texture or normal reference that points nowhere is dropped, not refused: mrvol needs the
  // positions, and files in the wild carry such references.
  if (value == 0) {
    if (!vertex) return kNoIndex;
    throw Error(at(line) + prefix() + "0 is not valid (OBJ indices start at 1)");
  }
  if (negative) {
    if (value > soFar) {
      if (!vertex) return kNoIndex;
      throw Error(at(line) + "relative " + prefix() + shorten(digits) + " reaches before the first vertex (" +
                  std::to_string(soFar) + " vertices so far)");
    }
    return uint32_t(soFar - value);
  }
  return uint32_t(value - 1);
}

// One line of the text: [begin, end) without its newline; the scan also refuses binary bytes and
// a carriage return that does not end the line, with the same messages as always.
struct LineScanner {
  const char* p;
  const char* end;
  size_t line = 0;

  bool next(const char*& begin, const char*& stop) {
    if (p >= end) return false;
    ++line;
    begin = p;
    for (;;) {
      // Printable bytes (and UTF-8) 8 at a time; anything below 32 is looked at.
      while (end - p >= 8 && !hasControlByte(p)) p += 8;
      while (p < end && static_cast<unsigned char>(*p) >= 32) ++p;
      if (p == end || *p == '\n') {
        stop = p;
        if (p < end) ++p;
        return true;
      }
      const unsigned char c = static_cast<unsigned char>(*p);
      if (c == '\r') {
        const char* q = p + 1;
        while (q < end && isSpace(*q)) ++q;
        if (q == end || *q == '\n') {  // CRLF (trailing blanks allowed)
          stop = p;
          p = q < end ? q + 1 : q;
          return true;
        }
        if (static_cast<unsigned char>(*q) < 32) binary(q, begin);
        throw Error(at(line) + "carriage return inside the line (column " + std::to_string(p - begin + 1) +
                    "): old Mac line endings (CR only) are not supported; convert the file to LF or CRLF");
      }
      if (!isSpace(char(c))) binary(p, begin);
      ++p;
    }
  }
  [[noreturn]] void binary(const char* q, const char* begin) const {
    throw Error(at(line) + "binary data (byte " + std::to_string(int(static_cast<unsigned char>(*q))) +
                " at column " + std::to_string(q - begin + 1) + "): this is not an OBJ text file");
  }
};

// Whether the line [begin, stop) (its newline excluded) ends in OBJ's continuation mark: a '\\' as
// its last byte but blanks and a CR. Not in a comment ("# C:\\models\\" goes on to the next line).
bool continuesLine(const char* begin, const char* stop) {
  while (begin < stop && isSpace(*begin)) ++begin;
  if (begin == stop || *begin == '#') return false;
  while (stop > begin && (isSpace(stop[-1]) || stop[-1] == '\r')) --stop;
  return stop > begin && stop[-1] == '\\';
}

// The start of the line that ends at `eol` (its '\n'), looking no further back than `lo`.
const char* lineStart(const char* lo, const char* eol) {
  while (eol > lo && eol[-1] != '\n') --eol;
  return eol;
}

bool isKeyword(std::string_view keyword) {
  return keyword.size() <= 16 && std::all_of(keyword.begin(), keyword.end(), [](char c) {
           return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
         });
}

// Counts of `v`, `f`, `vt`, `vn` lines: a cheap first pass that sizes the arrays (and refuses a file
// too large for memory before allocating). Lines are counted by their first byte, so a malformed
// line only makes the counts an overestimate; the reading pass says what is wrong with it.
struct LineCounts {
  size_t v = 0, f = 0, vt = 0, vn = 0;
};

LineCounts countLines(std::string_view text) {
  LineCounts counts;
  const char* p = text.data();
  const char* end = p + text.size();
  while (p < end) {
    while (p < end && (*p == ' ' || *p == '\t')) ++p;
    if (end - p >= 2 && (p[1] == ' ' || p[1] == '\t')) {
      counts.v += *p == 'v';
      counts.f += *p == 'f';
    } else if (end - p >= 3 && p[0] == 'v' && (p[2] == ' ' || p[2] == '\t')) {
      counts.vt += p[1] == 't';
      counts.vn += p[1] == 'n';
    }
    const void* eol = std::memchr(p, '\n', size_t(end - p));
    p = eol ? static_cast<const char*>(eol) + 1 : end;
  }
  return counts;
}

// Polygon triangulation: a fan when the polygon is convex, else ear clipping in the plane of its
// Newell normal. `corners` are vertex indices; appends (k - 2) triangles to `out`.
struct Vec2 { double x, y; };
double cross2(Vec2 o, Vec2 a, Vec2 b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }

void triangulatePolygon(const uint32_t* corners, size_t k, const std::vector<double>& positions, size_t line,
                        uint32_t* out) {
  auto fan = [&](const uint32_t* c, size_t n, uint32_t* o) {
    for (size_t i = 1; i + 1 < n; ++i) *o++ = c[0], *o++ = c[i], *o++ = c[i + 1];
  };
  // Newell normal, and the projection that drops its largest component.
  double n[3] = {0, 0, 0};
  for (size_t i = 0; i < k; ++i) {
    const double* a = &positions[3 * size_t(corners[i])];
    const double* b = &positions[3 * size_t(corners[(i + 1) % k])];
    n[0] += (a[1] - b[1]) * (a[2] + b[2]);
    n[1] += (a[2] - b[2]) * (a[0] + b[0]);
    n[2] += (a[0] - b[0]) * (a[1] + b[1]);
  }
  const int drop = std::fabs(n[0]) >= std::fabs(n[1]) && std::fabs(n[0]) >= std::fabs(n[2]) ? 0
                   : std::fabs(n[1]) >= std::fabs(n[2])                                     ? 1
                                                                                            : 2;
  const int ax = (drop + 1) % 3, ay = (drop + 2) % 3;
  const double orientation = n[drop] >= 0 ? 1.0 : -1.0;  // counter-clockwise in the projection
  std::vector<Vec2> p(k);
  for (size_t i = 0; i < k; ++i) {
    const double* x = &positions[3 * size_t(corners[i])];
    p[i] = {x[ax], orientation * x[ay]};
  }
  bool convex = n[drop] != 0;
  for (size_t i = 0; i < k && convex; ++i) convex = cross2(p[(i + k - 1) % k], p[i], p[(i + 1) % k]) >= 0;
  if (convex) return fan(corners, k, out);
  if (k > kMaxEarClippedCorners)
    throw Error(at(line) + "non-convex polygon with " + std::to_string(k) +
                " vertices is too large to triangulate (mrvol ear-clips non-convex polygons of at most " +
                std::to_string(kMaxEarClippedCorners) + " vertices)");
  // Ear clipping: a convex corner whose triangle holds no other remaining corner is cut off.
  std::vector<uint32_t> remaining(k);
  for (size_t i = 0; i < k; ++i) remaining[i] = uint32_t(i);
  auto inside = [&](Vec2 a, Vec2 b, Vec2 c, Vec2 q) {
    return cross2(a, b, q) >= 0 && cross2(b, c, q) >= 0 && cross2(c, a, q) >= 0;
  };
  while (remaining.size() > 3) {
    const size_t m = remaining.size();
    size_t ear = m;
    for (size_t i = 0; i < m && ear == m; ++i) {
      const uint32_t a = remaining[(i + m - 1) % m], b = remaining[i], c = remaining[(i + 1) % m];
      if (cross2(p[a], p[b], p[c]) <= 0) continue;
      bool empty = true;
      for (size_t j = 0; j < m && empty; ++j) {
        const uint32_t q = remaining[j];
        if (q != a && q != b && q != c) empty = !inside(p[a], p[b], p[c], p[q]);
      }
      if (empty) ear = i;
    }
    if (ear == m) break;  // self-intersecting or degenerate: the rest as a fan
    const uint32_t a = remaining[(ear + m - 1) % m], b = remaining[ear], c = remaining[(ear + 1) % m];
    *out++ = corners[a], *out++ = corners[b], *out++ = corners[c];
    remaining.erase(remaining.begin() + ptrdiff_t(ear));
  }
  std::vector<uint32_t> rest(remaining.size());
  for (size_t i = 0; i < remaining.size(); ++i) rest[i] = corners[remaining[i]];
  fan(rest.data(), rest.size(), out);
}

// A polygon waiting for the positions (its vertices may come later in the file).
}  // namespace

void checkMeshSize(size_t vertices, size_t triangles, size_t inputBytes) {
  // Bytes per vertex and per triangle while reading and opening, from bench/scale.mjs's WASM heap
  // (about 255 bytes per vertex at 655k vertices, file text included) with headroom; the text of
  // the file is in the heap while it is read. The budget leaves the rest of the 4 GB to what comes
  // next (transforms, editors, theta) and to the caller's copies.
  const double estimate = 100.0 * double(vertices) + 60.0 * double(triangles) + double(inputBytes);
  constexpr double kBudget = 2.5e9;
  constexpr double kTypicalBytesPerVertex = 100 + 2 * 60 + 110;  // two triangles and ~110 bytes of text each
  if (estimate > kBudget || vertices > kMaxIndex || triangles > kMaxIndex / 3) {
    char gb[32];
    std::snprintf(gb, sizeof gb, "%.1f", estimate / 1e9);
    throw Error("the mesh is too large to open: " + std::to_string(vertices) + " vertices and " +
                std::to_string(triangles) + " triangles need about " + gb +
                " GB of WebAssembly memory, more than the " + std::to_string(int(kBudget / 1e8) / 10.0).substr(0, 3) +
                " GB mrvol allows itself of the 4 GB maximum (it opens up to about " +
                std::to_string(int(kBudget / kTypicalBytesPerVertex / 1e6)) + " million vertices)");
  }
}

// The reading state of one OBJ file: fed whole lines (in any number of segments), it keeps the
// arrays and counts; finish() resolves the polygons and forward references. Shared by readObj (the
// whole text at once) and ObjStreamReader (chunks as they come).
struct ObjReader::Parser {
  static constexpr uint32_t kNoIndex = ObjExtras::kNoIndex;
  // A polygon waiting for the positions (its vertices may come later in the file).
  struct PendingPolygon {
    size_t cornerStart, cornerCount, firstTriangle, line;
    size_t written = 0;  // corners on its line (repeats of the one before left out of cornerCount)
  };
  bool keepLines, keepExtras;
  size_t line = 0;  // lines read so far
  TriangleMesh mesh;
  std::vector<uint32_t> vertexLines, faceLines;
  std::vector<double> texCoords, normals, colors;
  std::vector<uint32_t> cornerTex, cornerNormal;  // filled lazily: empty until a face names one
  size_t vtCount = 0, vnCount = 0, coloredVertices = 0;
  std::vector<uint32_t> polygonCorners, polygonTex, polygonNormal;
  std::vector<PendingPolygon> polygons;
  size_t collapsedPolygons = 0;  // polygons of fewer than 3 distinct corners, left out
  std::vector<std::string_view> cornerTokens;
  std::string joined;  // a statement continued over lines, joined

  Parser(bool lines, bool extras) : keepLines(lines), keepExtras(extras) {}

  // Room for `v` more vertices and `f` more triangles (amortised: never one reallocation per chunk).
  void reserve(size_t v, size_t f) {
    auto grow = [](auto& vec, size_t more) {
      if (vec.size() + more > vec.capacity()) vec.reserve(std::max(vec.size() + more, vec.capacity() + vec.capacity() / 2));
    };
    grow(mesh.positions, 3 * v);
    grow(mesh.faces, 3 * f);
    if (keepLines) grow(vertexLines, v);
    grow(faceLines, f);
  }

  // Every whole line of [p, end): `end` is the end of the text or just after a '\n'. The common
  // lines are read straight from the text (wholeLine), without the scanner's pass over their bytes.
  void scan(const char* p, const char* end) {
    LineScanner scanner{p, end, line};
    const char* begin;
    const char* stop;
    for (;;) {
      if (wholeLine(scanner.p, end, scanner.line + 1)) {
        ++scanner.line;
        continue;
      }
      if (!scanner.next(begin, stop)) break;
      if (continuesLine(begin, stop)) {
        continued(scanner, begin, stop);
        continue;
      }
      statement(begin, stop, scanner.line);
    }
    line = scanner.line;
  }

  // A statement continued over several lines ("f 1 2 \\" then "3"): its lines joined, each mark
  // a blank, and read as one line, numbered by its first. The callers hand over whole statements.
  void continued(LineScanner& scanner, const char* begin, const char* stop) {
    const size_t first = scanner.line;
    joined.clear();
    for (;;) {
      const bool more = continuesLine(begin, stop);
      if (!more) {
        joined.append(begin, stop);
        break;
      }
      const char* mark = stop;
      while (*--mark != '\\') {}
      joined.append(begin, mark);
      joined.push_back(' ');
      if (!scanner.next(begin, stop)) break;  // the file's last line ends in the mark
    }
    statement(joined.data(), joined.data() + joined.size(), first);
  }

  // A "v x y z" or "f a b c" line at p whose bytes are only the statement's (numbers, spaces and
  // tabs: nothing the scanner would refuse), ended by "\n", "\r\n" or the text's end: read, and p
  // moved past it. Anything else (and every error) returns false having changed nothing; the
  // scanner and statement() then read the line as always.
  bool wholeLine(const char*& p, const char* end, size_t line) {
    if (end - p < 2 || (p[1] != ' ' && p[1] != '\t') || (p[0] != 'v' && p[0] != 'f')) return false;
    const auto blank = [](char c) { return c == ' ' || c == '\t'; };
    const char* q = p + 2;
    const bool vertex = p[0] == 'v';
    double x[3];
    uint32_t v[3];
    if (vertex) {
      for (double& value : x) {
        while (q < end && blank(*q)) ++q;
        const char* digits = q + (q < end && *q == '-');
        if (digits >= end || !((*digits >= '0' && *digits <= '9') || *digits == '.')) return false;
        const auto result = fast_float::from_chars(q, end, value);
        if (result.ec != std::errc() || result.ptr == digits || result.ptr - q > 63 ||
            (result.ptr < end && !blank(*result.ptr) && *result.ptr != '\n' && *result.ptr != '\r') ||
            !(std::fabs(value) <= kMaxCoordinate))
          return false;
        q = result.ptr;
      }
    } else {
      for (uint32_t& index : v) {
        while (q < end && blank(*q)) ++q;
        const char* first = q;
        uint32_t value = 0;
        for (unsigned digit; q < end && q - first < 9 && (digit = unsigned(*q) - '0') <= 9; ++q) value = value * 10 + digit;
        if (value == 0 || (q < end && !blank(*q) && *q != '\n' && *q != '\r')) return false;  // also no digits
        index = value - 1;
      }
    }
    while (q < end && blank(*q)) ++q;
    if (q < end && *q == '\r') ++q;  // CRLF (the scanner allows blanks after the CR too: it reads those)
    if (q < end && *q != '\n') return false;
    p = q < end ? q + 1 : q;
    if (vertex)
      addVertex(x, line);
    else
      addTriangle(v, line);
    return true;
  }

  // A plain line's vertex or triangle (its 3 corners without attributes), as the general path adds them.
  void addVertex(const double* x, size_t line) {
    mesh.positions.insert(mesh.positions.end(), x, x + 3);
    if (keepLines) vertexLines.push_back(uint32_t(line));
  }
  void addTriangle(const uint32_t* v, size_t line) {
    mesh.faces.insert(mesh.faces.end(), v, v + 3);
    faceLines.push_back(uint32_t(line));
    if (keepExtras && !cornerTex.empty()) {  // as the general path: no attributes at these corners
      cornerTex.insert(cornerTex.end(), 3, kNoIndex);
      cornerNormal.insert(cornerNormal.end(), 3, kNoIndex);
    }
  }

  // The common lines, "v x y z" and "f a b c" with plain indices, read in one pass over their
  // bytes (fast_float parses in place, no tokens first). Any other form, and every error, returns
  // false having changed nothing: the general path below then reads (or refuses) the line.
  bool plainVertex(const char* p, const char* stop, size_t line) {
    double x[3];
    for (double& value : x) {
      while (p < stop && classOf(*p) == kBlank) ++p;
      const char* digits = p + (p < stop && *p == '-');
      if (digits >= stop || !((*digits >= '0' && *digits <= '9') || *digits == '.')) return false;
      const auto result = fast_float::from_chars(p, stop, value);
      if (result.ec != std::errc() || result.ptr == digits || result.ptr - p > 63 ||
          (result.ptr < stop && classOf(*result.ptr) != kBlank) || !(std::fabs(value) <= kMaxCoordinate))
        return false;
      p = result.ptr;
    }
    while (p < stop && classOf(*p) == kBlank) ++p;
    if (p != stop) return false;
    addVertex(x, line);
    return true;
  }

  bool plainTriangle(const char* p, const char* stop, size_t line) {
    uint32_t v[3];
    for (uint32_t& index : v) {
      while (p < stop && classOf(*p) == kBlank) ++p;
      const char* first = p;
      uint32_t value = 0;
      for (unsigned digit; p < stop && p - first < 9 && (digit = unsigned(*p) - '0') <= 9; ++p)
        value = value * 10 + digit;
      if (value == 0 || (p < stop && classOf(*p) != kBlank)) return false;  // also no digits
      index = value - 1;
    }
    while (p < stop && classOf(*p) == kBlank) ++p;
    if (p != stop) return false;
    addTriangle(v, line);
    return true;
  }

  void statement(const char* begin, const char* stop, size_t line) {
    if (stop - begin >= 2 && classOf(begin[1]) == kBlank) {
      if (begin[0] == 'v' && plainVertex(begin + 2, stop, line)) return;
      if (begin[0] == 'f' && plainTriangle(begin + 2, stop, line)) return;
    }
    std::string_view tokens[8];
    const bool extras = keepExtras;
    const char* p = begin;
    std::string_view keyword = nextToken(p, stop);
    if (keyword.empty()) return;
    if (keyword == "v" || keyword == "vt" || keyword == "vn") {
      size_t count = 0;
      for (std::string_view t = nextToken(p, stop); !t.empty(); t = nextToken(p, stop)) {
        if (count < 8) tokens[count] = t;
        ++count;
      }
      if (keyword == "v") {
        if (count < 3) throw Error(at(line) + "vertex needs 3 coordinates, found " + std::to_string(count));
        if (count > 4 && count != 6)  // x y z [w]; colours (x y z r g b) are accepted too
          throw Error(at(line) + "vertex has " + std::to_string(count) +
                      " values, expected 3 (x y z), 4 (x y z w) or 6 (x y z r g b)");
        for (int k = 0; k < 3; ++k) mesh.positions.push_back(parseCoordinate(tokens[k], line));
        if (keepLines) vertexLines.push_back(uint32_t(line));
        for (size_t k = 3; k < count; ++k) {
          const double x = parseCoordinate(tokens[k], line);
          if (count == 6 && extras) colors.push_back(x);
        }
        coloredVertices += count == 6;
      } else {
        const size_t want = keyword == "vt" ? 1 : 3, most = 3;
        if (count < want || count > most)
          throw Error(at(line) + (keyword == "vt" ? "texture coordinate needs 1 to 3 values, found "
                                                  : "normal needs 3 values, found ") +
                      std::to_string(count));
        double x[3] = {0, 0, 0};
        for (size_t k = 0; k < count; ++k) x[k] = parseCoordinate(tokens[k], line);
        if (keyword == "vt") {
          ++vtCount;
          if (extras) texCoords.insert(texCoords.end(), x, x + 2);
        } else {
          ++vnCount;
          if (extras) normals.insert(normals.end(), x, x + 3);
        }
      }
    } else if (keyword == "f") {
      // Most faces are triangles: read the first three corners straight into the arrays.
      cornerTokens.clear();
      for (std::string_view t = nextToken(p, stop); !t.empty(); t = nextToken(p, stop)) cornerTokens.push_back(t);
      const size_t corners = cornerTokens.size();
      if (corners < 3)
        throw Error(at(line) + "face has " + std::to_string(corners) + " vertices, a triangle needs 3");
      const size_t vertices = mesh.vertexCount();
      uint32_t v[3], vt[3], vn[3];
      bool hasTex = false, hasNormal = false;
      auto corner = [&](std::string_view token, uint32_t& vi, uint32_t& ti, uint32_t& ni) {
        // The common form, a plain index of at most 9 digits (no sign, no slash), in one loop;
        // anything else (and every error) goes the general way below.
        if (token.size() <= 9) {
          uint32_t value = 0;
          size_t i = 0;
          for (; i < token.size(); ++i) {
            const unsigned digit = unsigned(token[i]) - '0';
            if (digit > 9) break;
            value = value * 10 + digit;
          }
          if (i == token.size() && value != 0) {
            vi = value - 1;
            ti = ni = kNoIndex;
            return;
          }
        }
        const size_t slash = token.find('/');
        vi = parseIndex(token.substr(0, slash), token, line, vertices, "face");
        ti = ni = kNoIndex;
        if (slash == std::string_view::npos) return;
        const std::string_view rest = token.substr(slash + 1);
        const size_t slash2 = rest.find('/');
        ti = parseIndex(rest.substr(0, slash2), token, line, vtCount, "texture");
        if (slash2 != std::string_view::npos)
          ni = parseIndex(rest.substr(slash2 + 1), token, line, vnCount, "normal");
        hasTex |= ti != kNoIndex;
        hasNormal |= ni != kNoIndex;
      };
      const size_t firstTriangle = mesh.faceCount();
      if (corners == 3) {
        for (int k = 0; k < 3; ++k) corner(cornerTokens[k], v[k], vt[k], vn[k]);
        mesh.faces.insert(mesh.faces.end(), v, v + 3);
        faceLines.push_back(uint32_t(line));
      } else {
        PendingPolygon polygon{polygonCorners.size(), corners, firstTriangle, line};
        for (size_t k = 0; k < corners; ++k) {
          uint32_t a, b, c;
          corner(cornerTokens[k], a, b, c);
          // A corner repeating the one before it ("f a b c c": a triangle padded to a quad, as
          // PLY and OFF read it too) is left out; the last against the first as well.
          if (k > 0 && a == polygonCorners.back()) continue;
          polygonCorners.push_back(a);
          if (extras) polygonTex.push_back(b), polygonNormal.push_back(c);
        }
        size_t kept = polygonCorners.size() - polygon.cornerStart;
        while (kept > 1 && polygonCorners.back() == polygonCorners[polygon.cornerStart]) {
          polygonCorners.pop_back();
          if (extras) polygonTex.pop_back(), polygonNormal.pop_back();
          --kept;
        }
        if (kept < 3) {  // one or two distinct corners: no area, no face
          ++collapsedPolygons;
          polygonCorners.resize(polygon.cornerStart);
          if (extras) polygonTex.resize(polygon.cornerStart), polygonNormal.resize(polygon.cornerStart);
          return;
        }
        polygon.cornerCount = kept;
        polygon.written = corners;
        polygons.push_back(polygon);
        mesh.faces.resize(mesh.faces.size() + 3 * (kept - 2), 0);  // filled once positions are known
        faceLines.resize(faceLines.size() + kept - 2, uint32_t(line));
      }
      if (extras && (hasTex || hasNormal || !cornerTex.empty())) {
        // Corner attributes: per triangle corner (polygons get theirs when triangulated).
        if (cornerTex.empty()) cornerTex.assign(3 * firstTriangle, kNoIndex), cornerNormal.assign(3 * firstTriangle, kNoIndex);
        if (corners == 3) {
          cornerTex.insert(cornerTex.end(), vt, vt + 3);
          cornerNormal.insert(cornerNormal.end(), vn, vn + 3);
        } else {
          cornerTex.resize(3 * mesh.faceCount(), kNoIndex);
          cornerNormal.resize(3 * mesh.faceCount(), kNoIndex);
        }
      }
    } else if (!isKeyword(keyword)) {
      throw Error(at(line) + "unknown statement " + shorten(keyword) + ": this does not look like an OBJ file");
    }
    // Other OBJ statements (o, g, s, usemtl, mtllib, l, p ...) carry nothing mrvol uses.
  }

  TriangleMesh finish(SourceLines* lines, ObjExtras* extras) {
  if (mesh.positions.empty() && mesh.faces.empty()) throw Error("empty input: no vertices and no faces");
  if (mesh.faces.empty() && collapsedPolygons > 0)
    throw Error("no faces: " + io::eachFaceRepeats(collapsedPolygons, "'f' lines") + " (fewer than 3 distinct: no area)");
  if (mesh.faces.empty())
    throw Error("no faces: the file has " + std::to_string(mesh.vertexCount()) + " vertices but no 'f' lines");
  // Indices may point forwards: checked once every vertex is known, in face order.
  const uint32_t nv = uint32_t(mesh.vertexCount());
  auto refuse = [&](size_t line, uint32_t index) {
    throw Error(at(line) + "face refers to vertex " + std::to_string(size_t(index) + 1) + " but the file has " +
                std::to_string(nv) + " vertices");
  };
  size_t nextPolygon = 0;
  for (size_t f = 0; f < mesh.faceCount(); ++f) {
    if (nextPolygon < polygons.size() && polygons[nextPolygon].firstTriangle == f) {
      const PendingPolygon& polygon = polygons[nextPolygon++];
      const uint32_t* c = &polygonCorners[polygon.cornerStart];
      for (size_t k = 0; k < polygon.cornerCount; ++k)
        if (c[k] >= nv) refuse(polygon.line, c[k]);
      f += polygon.cornerCount - 3;
      continue;
    }
    for (int k = 0; k < 3; ++k)
      if (mesh.faces[3 * f + k] >= nv) refuse(faceLines[f], mesh.faces[3 * f + k]);
  }
  std::vector<uint32_t> sorted;
  for (const PendingPolygon& polygon : polygons) {
    const uint32_t* c = &polygonCorners[polygon.cornerStart];
    sorted.assign(c, c + polygon.cornerCount);
    std::sort(sorted.begin(), sorted.end());
    auto twice = std::adjacent_find(sorted.begin(), sorted.end());
    if (twice != sorted.end())
      throw Error(at(polygon.line) + "polygon with " + std::to_string(polygon.written) + " vertices uses vertex " +
                  std::to_string(size_t(*twice) + 1) + " more than once");
    uint32_t* out = &mesh.faces[3 * polygon.firstTriangle];
    triangulatePolygon(c, polygon.cornerCount, mesh.positions, polygon.line, out);
    if (extras && !cornerTex.empty()) {
      // The triangles use the polygon's corners (all distinct): map each back to its vt / vn.
      std::vector<std::pair<uint32_t, uint32_t>> cornerOf(polygon.cornerCount);
      for (size_t k = 0; k < polygon.cornerCount; ++k) cornerOf[k] = {c[k], uint32_t(k)};
      std::sort(cornerOf.begin(), cornerOf.end());
      for (size_t i = 0; i < 3 * (polygon.cornerCount - 2); ++i) {
        const size_t k = std::lower_bound(cornerOf.begin(), cornerOf.end(), std::make_pair(out[i], 0u))->second;
        cornerTex[3 * polygon.firstTriangle + i] = polygonTex[polygon.cornerStart + k];
        cornerNormal[3 * polygon.firstTriangle + i] = polygonNormal[polygon.cornerStart + k];
      }
    }
  }
  if (extras) {
    // References beyond the file's vt / vn lines: the attributes are inconsistent, drop them (and say so).
    auto dropOutside = [&](std::vector<uint32_t>& refs, size_t count, const char* what, const char* statement) {
      uint32_t largest = 0;
      bool outside = false;
      for (uint32_t r : refs)
        if (r != kNoIndex && r >= count) outside = true, largest = std::max(largest, r);
      if (!outside) return;
      refs.clear();
      extras->dropped += std::string(extras->dropped.empty() ? "" : "; ") + what + " left out: face corners refer to " + statement +
                         " " + std::to_string(size_t(largest) + 1) + ", and the file has " + std::to_string(count) + " " + statement +
                         (count == 1 ? " line" : " lines");
    };
    dropOutside(cornerTex, vtCount, "texture coordinates", "vt");
    dropOutside(cornerNormal, vnCount, "normals", "vn");
    extras->polygons = polygons.size();
    extras->polygonTriangles = 0;
    for (const PendingPolygon& polygon : polygons) extras->polygonTriangles += polygon.cornerCount - 2;
    extras->texCoords = std::move(texCoords);
    extras->normals = std::move(normals);
    extras->colors = coloredVertices == nv ? std::move(colors) : std::vector<double>();
    extras->cornerTexCoords = std::move(cornerTex);
    extras->cornerNormals = std::move(cornerNormal);
  }
  if (lines) lines->vertex = std::move(vertexLines), lines->face = std::move(faceLines);
  return std::move(mesh);
  }
};

TriangleMesh readObj(std::string_view text, SourceLines* lines, ObjExtras* extras) {
  const std::string_view bom = "\xEF\xBB\xBF";  // a UTF-8 byte order mark is no statement
  if (text.substr(0, 3) == bom) text.remove_prefix(3);
  const LineCounts counts = countLines(text);
  checkMeshSize(counts.v, counts.f, text.size());
  ObjReader::Parser parser(lines != nullptr, extras != nullptr);
  parser.reserve(counts.v, counts.f);
  parser.scan(text.data(), text.data() + text.size());
  return parser.finish(lines, extras);
}

ObjReader::ObjReader(size_t expectedBytes) : parser_(std::make_unique<Parser>(true, true)), expected_(expectedBytes) {}
ObjReader::~ObjReader() = default;

void ObjReader::feed(std::string_view chunk) {
  if (finished_) throw Error("the OBJ reader has already finished");
  seen_ += chunk.size();
  // A byte order mark is looked for once the file's first 3 bytes are in (they may come one by one).
  if (!bomChecked_) {
    partial_.append(chunk.data(), chunk.size());
    if (partial_.size() < 3) return;
    bomChecked_ = true;
    if (partial_.compare(0, 3, "\xEF\xBB\xBF") == 0) partial_.erase(0, 3);
    std::string head;
    head.swap(partial_);
    take(head);
    return;
  }
  take(chunk);
}

void ObjReader::take(std::string_view chunk) {
  const char* p = chunk.data();
  const char* end = p + chunk.size();
  // The line the last chunk left unfinished: completed from this one's first line.
  // (A statement continued over lines, "f 1 2 \\", counts as one line here: it waits whole.)
  if (!partial_.empty()) {
    for (;;) {
      const void* eol = std::memchr(p, '\n', size_t(end - p));
      if (!eol) {
        partial_.append(p, size_t(end - p));
        return;
      }
      const char* after = static_cast<const char*>(eol) + 1;
      const size_t lineAt = partial_.rfind('\n') == std::string::npos ? 0 : partial_.rfind('\n') + 1;
      partial_.append(p, size_t(after - p));
      p = after;
      const char* text = partial_.data();
      if (!continuesLine(text + lineAt, text + partial_.size() - 1)) break;
    }
    parser_->scan(partial_.data(), partial_.data() + partial_.size());
    partial_.clear();
  }
  // Whole lines in place; the tail after the last '\n' waits for the next chunk.
  const char* last = end;
  while (last > p && last[-1] != '\n') --last;
  while (last > p && continuesLine(lineStart(p, last - 1), last - 1)) last = lineStart(p, last - 1);
  if (last > p) {
    const LineCounts counts = countLines(std::string_view(p, size_t(last - p)));
    checkMeshSize(parser_->mesh.vertexCount() + counts.v, parser_->mesh.faceCount() + counts.f);
    // Room for this chunk's lines; reserve() grows by half the capacity at least, so the arrays
    // reallocate a logarithmic number of times. (No extrapolation from the file's size: OBJ files
    // put their v lines first, so a first chunk's density says nothing of the faces to come.)
    parser_->reserve(counts.v, counts.f);
    parser_->scan(p, last);
  }
  partial_.append(last, size_t(end - last));
  // Only a line longer than any chunk keeps growing this: bounded by the file (the parser refuses
  // long tokens, but a comment line may be long).
}

TriangleMesh ObjReader::finish(SourceLines* lines, ObjExtras* extras) {
  if (finished_) throw Error("the OBJ reader has already finished");
  if (!bomChecked_) {
    bomChecked_ = true;
    if (partial_.compare(0, 3, "\xEF\xBB\xBF") == 0) partial_.erase(0, 3);
  }
  finished_ = true;
  if (!partial_.empty()) parser_->scan(partial_.data(), partial_.data() + partial_.size());
  std::string().swap(partial_);
  return parser_->finish(lines, extras);
}

namespace {

using text::writeShortest;

void appendShortest(std::string& out, double x) {
  char buffer[32];
  out.append(buffer, size_t(writeShortest(buffer, x) - buffer));
}

// Whether a v line's three coordinate tokens read back as x exactly (its spelling is then kept).
bool readsAs(const std::string_view (&xyz)[3], const double* x) {
  for (int k = 0; k < 3; ++k) {
    double value = 0;
    const char* first = xyz[k].data() + (xyz[k][0] == '+');
    auto r = fast_float::from_chars(first, xyz[k].data() + xyz[k].size(), value);
    if (r.ec != std::errc() || value != x[k] || std::signbit(value) != std::signbit(x[k])) return false;
  }
  return true;
}

// [begin, end) with its three coordinate tokens (inside it) spelt anew from x.
void appendReplaced(std::string& out, const char* begin, const std::string_view (&xyz)[3], const double* x, const char* end) {
  out.append(begin, size_t(xyz[0].data() - begin));
  for (int k = 0; k < 3; ++k) {
    if (k) out += ' ';
    appendShortest(out, x[k]);
  }
  const char* rest = xyz[2].data() + xyz[2].size();
  out.append(rest, size_t(end - rest));
}

}  // namespace

std::string writeObj(const TriangleMesh& mesh) {
  std::string out;
  // a line at most: "v " + 3 x 24 characters + "\n"; "f " + 3 x 11
  out.resize(mesh.vertexCount() * 80 + mesh.faceCount() * 40);
  char* at = out.data();
  for (size_t v = 0; v < mesh.vertexCount(); ++v) {
    *at++ = 'v';
    for (int k = 0; k < 3; ++k) {
      *at++ = ' ';
      at = writeShortest(at, mesh.positions[3 * v + k]);
    }
    *at++ = '\n';
  }
  for (size_t f = 0; f < mesh.faceCount(); ++f) {
    *at++ = 'f';
    for (int k = 0; k < 3; ++k) {
      *at++ = ' ';
      at = text::writeUnsigned(at, mesh.faces[3 * f + k] + 1);
    }
    *at++ = '\n';
  }
  out.resize(size_t(at - out.data()));
  return out;
}

namespace {

// The writer: v line i takes positions[map ? map[i] : i]. False when the file has more v lines
// than `lines` (positions, or the map's entries), before writing them all.
bool writeReplaced(std::string& out, std::string_view original, const double* positions, size_t vertexCount,
                   const std::vector<uint32_t>* map) {
  const size_t lines = map ? map->size() : vertexCount;
  out.clear();
  out.reserve(original.size() + original.size() / 4);
  const char* p = original.data();
  const char* end = p + original.size();
  size_t vertex = 0;
  std::string joined;  // a statement continued over lines ("v 1 2 \\" then "3"), joined
  while (p < end) {
    const void* eol = std::memchr(p, '\n', size_t(end - p));
    const char* lineEnd = eol ? static_cast<const char*>(eol) + 1 : end;
    const char* contentEnd = eol ? static_cast<const char*>(eol) : end;
    if (continuesLine(p, contentEnd)) {
      // Its lines as one ("v 1 2 3" after the edit is written on one line); kept as they were if it
      // is not a vertex or the vertex did not move.
      joined.clear();
      const char* line = p;
      for (;;) {
        const char* stop = contentEnd;
        if (!continuesLine(line, stop)) {
          while (stop > line && stop[-1] == '\r') --stop;
          joined.append(line, stop);
          break;
        }
        const char* mark = stop;
        while (*--mark != '\\') {}
        joined.append(line, mark);
        joined.push_back(' ');
        if (lineEnd == end) break;
        line = lineEnd;
        eol = std::memchr(line, '\n', size_t(end - line));
        lineEnd = eol ? static_cast<const char*>(eol) + 1 : end;
        contentEnd = eol ? static_cast<const char*>(eol) : end;
      }
      const char* j = joined.data();
      const char* jEnd = j + joined.size();
      std::string_view keyword = nextToken(j, jEnd);
      std::string_view xyz[3];
      bool isVertex = keyword == "v" || (p == original.data() && keyword == "\xEF\xBB\xBFv");
      for (int k = 0; k < 3 && isVertex; ++k) isVertex = !(xyz[k] = nextToken(j, jEnd)).empty();
      if (isVertex) {
        if (vertex >= lines) return false;
        const double* x = positions + 3 * size_t(map ? (*map)[vertex] : vertex);
        ++vertex;
        if (!readsAs(xyz, x)) {
          appendReplaced(out, joined.data(), xyz, x, jEnd);
          out += contentEnd > p && contentEnd[-1] == '\r' ? "\r\n" : "\n";
          p = lineEnd;
          continue;
        }
      }
      out.append(p, size_t(lineEnd - p));
      p = lineEnd;
      continue;
    }
    const char* q = p;
    std::string_view keyword = nextToken(q, contentEnd);
    std::string_view xyz[3];
    bool isVertex = keyword == "v" || (p == original.data() && keyword == "\xEF\xBB\xBFv");
    for (int k = 0; k < 3 && isVertex; ++k) isVertex = !(xyz[k] = nextToken(q, contentEnd)).empty();
    if (!isVertex) {
      out.append(p, size_t(lineEnd - p));
      p = lineEnd;
      continue;
    }
    if (vertex >= lines) return false;
    const double* x = positions + 3 * size_t(map ? (*map)[vertex] : vertex);
    ++vertex;
    if (readsAs(xyz, x)) out.append(p, size_t(lineEnd - p));
    else appendReplaced(out, p, xyz, x, lineEnd);
    p = lineEnd;
  }
  if (vertex != lines)
    throw Error("the original OBJ has " + std::to_string(vertex) + " vertices but " + std::to_string(lines) +
                " positions were given");
  return true;
}

}  // namespace

std::string writeObjLike(std::string_view original, const double* positions, size_t vertexCount) {
  std::string out;
  if (writeReplaced(out, original, positions, vertexCount, nullptr)) return out;
  // More v lines than positions: the positions may be those of the file's vertices welded, as the
  // readers give them (weldObjVertices). Each v line then takes its welded vertex's position.
  TriangleMesh read = readObj(original);
  const size_t lines = read.vertexCount();
  std::vector<uint32_t> outputOf;
  weldExactPositions(read, nullptr, &outputOf, /*unlessAFaceCollapses=*/true);
  if (read.vertexCount() != vertexCount)
    throw Error("the original OBJ has " + std::to_string(lines) + " vertices" +
                (read.vertexCount() < lines ? " (" + std::to_string(read.vertexCount()) + " once those at one position are welded)" : "") +
                " but " + std::to_string(vertexCount) + " positions were given");
  writeReplaced(out, original, positions, vertexCount, &outputOf);
  return out;
}

size_t weldObjVertices(TriangleMesh& mesh, SourceLines* lines, ObjExtras* extras, std::vector<uint32_t>* firstSource) {
  std::vector<uint32_t> first;
  const size_t welded = weldExactPositions(mesh, &first, nullptr, /*unlessAFaceCollapses=*/true);
  if (welded > 0) {
    // A welded vertex keeps its first v line's line number and colour (first[v] >= v: copied
    // forwards in place).
    auto keepFirst = [&](auto& perVertex, size_t width) {
      if (perVertex.empty()) return;
      for (size_t v = 0; v < first.size(); ++v)
        for (size_t k = 0; k < width; ++k) perVertex[width * v + k] = perVertex[width * size_t(first[v]) + k];
      perVertex.resize(width * first.size());
    };
    if (lines) keepFirst(lines->vertex, 1);
    if (extras) keepFirst(extras->colors, 3);
  }
  if (firstSource) *firstSource = std::move(first);
  return welded;
}

}  // namespace mrvol
