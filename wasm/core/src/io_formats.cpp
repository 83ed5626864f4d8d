// Format names, detection by extension and content, the dispatcher, and exact-position welding.
#include "mrvol/io_formats.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <numeric>
#include <utility>

#include "io_common.h"
#include "mrvol/error.h"

namespace mrvol {

namespace io {

std::string looksLike(std::string_view b) {
  auto starts = [&](std::string_view magic) { return b.substr(0, magic.size()) == magic; };
  const char* what = nullptr;
  if (starts("PK\x03\x04") || starts("PK\x05\x06")) what = "a ZIP archive";
  else if (starts("\x1f\x8b")) what = "a gzip-compressed file";
  else if (starts("\x89PNG")) what = "a PNG image";
  else if (starts("\xff\xd8\xff")) what = "a JPEG image";
  else if (starts("\x7f" "ELF")) what = "an executable (ELF)";
  else if (starts("%PDF")) what = "a PDF document";
  else if (starts("Kaydara FBX Binary")) what = "an FBX file";
  else if (starts("BLENDER")) what = "a Blender file: export the model as OBJ, STL, PLY or glTF";
  else if (starts("glTF")) what = "a GLB file";
  else if (starts("ply\n") || starts("ply\r\n")) what = "a PLY file";
  else if (starts("solid ") && b.find("facet") != std::string_view::npos) what = "an ASCII STL file";
  else {
    size_t i = 0;
    while (i < b.size() && std::isspace(static_cast<unsigned char>(b[i]))) ++i;
    std::string_view rest = b.substr(i);
    if (rest.substr(0, 1) == "<") what = "an HTML or XML document";
    else if (rest.substr(0, 1) == "{") what = "a JSON document";
  }
  return what ? std::string(" (looks like ") + what + ")" : std::string();
}

}  // namespace io

namespace {

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = char(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

std::string extensionOf(std::string_view name) {
  size_t slash = name.find_last_of("/\\");
  if (slash != std::string_view::npos) name = name.substr(slash + 1);
  size_t dot = name.rfind('.');
  return dot == std::string_view::npos ? std::string() : lower(name.substr(dot + 1));
}

bool knownExtension(const std::string& ext) {
  return ext == "obj" || ext == "stl" || ext == "ply" || ext == "off" || ext == "gltf" || ext == "glb";
}

// The first token of a text file after blank lines and '#' comments (OFF headers).
std::string_view firstToken(std::string_view b) {
  size_t i = 0;
  if (b.substr(0, 3) == "\xEF\xBB\xBF") i = 3;
  while (i < b.size()) {
    while (i < b.size() && std::isspace(static_cast<unsigned char>(b[i]))) ++i;
    if (i < b.size() && b[i] == '#') {
      while (i < b.size() && b[i] != '\n') ++i;
      continue;
    }
    size_t j = i;
    while (j < b.size() && !std::isspace(static_cast<unsigned char>(b[j])) && j - i < 16) ++j;
    return b.substr(i, j - i);
  }
  return {};
}

bool isOffKeyword(std::string_view t) {
  if (t.size() < 3 || t.substr(t.size() - 3) != "OFF") return false;
  std::string_view prefix = t.substr(0, t.size() - 3);
  // [ST][C][N][4][n]OFF: texture, colour, normal, 4D, n-dimensional
  return prefix.find_first_not_of("STCN4n") == std::string_view::npos;
}

// "ply" and the line's end (blanks before it tolerated).
bool plyStart(std::string_view t) {
  if (t.substr(0, 3) != "ply") return false;
  size_t i = 3;
  while (i < t.size() && io::isBlank(t[i])) ++i;
  return i < t.size() && t[i] == '\n';
}

// "solid" (any case, after blank lines) and a facet soon after it.
bool asciiStlStart(std::string_view t) {
  if (!io::startsWithWord(t, "solid")) return false;
  std::string_view head = t.substr(0, 4096);
  for (size_t i = 0; i + 5 <= head.size(); ++i)
    if (io::equalsWord(head.substr(i, 5), "facet")) return true;
  return false;
}


// A format identified from the content alone, or false.
bool signature(std::string_view b, MeshFormat& format) {
  if (b.substr(0, 4) == "glTF") return format = MeshFormat::Glb, true;
  // Text formats after a UTF-8 byte order mark: PLY's and ASCII STL's signatures as without it.
  const std::string_view text = io::hasByteOrderMark(b) ? b.substr(3) : b;
  if (plyStart(text)) return format = MeshFormat::Ply, true;
  std::string_view token = firstToken(b);
  if (isOffKeyword(token)) return format = MeshFormat::Off, true;
  if (token.substr(0, 1) == "{" && b.find("\"asset\"") != std::string_view::npos) return format = MeshFormat::Gltf, true;
  // Binary STL by its size (a header may start with "solid": SolidWorks writes one; its triangles are no text).
  if (b.size() >= 84) {
    uint32_t n = io::load<uint32_t>(b.data() + 80);
    if (b.size() == 84 + 50 * uint64_t(n) && n > 0 && (!asciiStlStart(b) || io::hasBinaryBytes(b.substr(84, 512))))
      return format = MeshFormat::Stl, true;
  }
  if (asciiStlStart(text)) return format = MeshFormat::Stl, true;
  return false;
}

const char* articleName(MeshFormat f) {
  switch (f) {
    case MeshFormat::Obj: return "an OBJ";
    case MeshFormat::Stl: return "an STL";
    case MeshFormat::Ply: return "a PLY";
    case MeshFormat::Off: return "an OFF";
    case MeshFormat::Gltf: return "a glTF";
    case MeshFormat::Glb: return "a GLB";
  }
  return "a mesh";
}

std::string upperName(MeshFormat f) {
  std::string s = formatName(f);
  if (f == MeshFormat::Gltf) return "glTF";
  for (char& c : s) c = char(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

const char* formatName(MeshFormat format) {
  switch (format) {
    case MeshFormat::Obj: return "obj";
    case MeshFormat::Stl: return "stl";
    case MeshFormat::Ply: return "ply";
    case MeshFormat::Off: return "off";
    case MeshFormat::Gltf: return "gltf";
    case MeshFormat::Glb: return "glb";
  }
  return "unknown";
}

MeshFormat parseFormatName(std::string_view name) {
  std::string n = lower(name);
  if (!n.empty() && n[0] == '.') n.erase(0, 1);
  if (n == "obj") return MeshFormat::Obj;
  if (n == "stl") return MeshFormat::Stl;
  if (n == "ply") return MeshFormat::Ply;
  if (n == "off") return MeshFormat::Off;
  if (n == "gltf") return MeshFormat::Gltf;
  if (n == "glb") return MeshFormat::Glb;
  throw Error("unknown mesh format " + io::quoted(name) + " (mrvol reads obj, stl, ply, off, gltf, glb)");
}

MeshFormat detectFormat(std::string_view bytes, std::string_view name) {
  const std::string ext = extensionOf(name);
  MeshFormat byContent;
  const bool known = knownExtension(ext);
  if (bytes.empty()) {
    if (known) throw Error("empty " + upperName(parseFormatName(ext)) + " file (0 bytes)");
    throw Error("empty file (0 bytes)");
  }
  if (signature(bytes, byContent)) return byContent;
  // A material library (an OBJ's .mtl): not the mesh.
  if (ext == "mtl" || (!known && io::startsWithWord(bytes, "newmtl")))
    throw Error("this is a material library (.mtl) that an OBJ refers to, not a mesh: open the .obj file");
  if (!known) {
    // No signature: text is taken for OBJ (its reader says what is wrong), anything else is refused.
    std::string like = io::looksLike(bytes);
    if (!like.empty())
      throw Error("unknown mesh format" + (ext.empty() ? std::string() : " ." + ext) + like +
                  "; mrvol reads obj, stl, ply, off, gltf and glb");
    return MeshFormat::Obj;
  }
  MeshFormat expected = parseFormatName(ext);
  std::string like = io::looksLike(bytes);
  if (!like.empty() && expected != MeshFormat::Obj) {
    std::string head;
    for (char c : bytes.substr(0, 4)) {
      unsigned char u = static_cast<unsigned char>(c);
      char hex[8];
      std::snprintf(hex, sizeof hex, u >= 32 && u < 127 ? "%c" : "\\x%02x", u);
      head += hex;
    }
    throw Error(std::string("not ") + articleName(expected) + " file: it starts with '" + head + "'" + like);
  }
  return expected;
}

ImportedMesh readMeshFile(std::string_view bytes, MeshFormat format, const GltfResources& resources) {
  if (bytes.empty()) throw Error("empty " + upperName(format) + " file (0 bytes)");
  switch (format) {
    case MeshFormat::Stl: return readStl(bytes);
    case MeshFormat::Ply: return readPly(bytes);
    case MeshFormat::Off: return readOff(bytes);
    case MeshFormat::Gltf: return readGltf(bytes, resources);
    case MeshFormat::Glb: return readGlb(bytes, resources);
    case MeshFormat::Obj: break;
  }
  ImportedMesh out;
  out.format = MeshFormat::Obj;
  out.variant = "OBJ";
  out.mesh = readObj(bytes, &out.objLines);
  out.sourceVertices = out.mesh.vertexCount();
  out.sourceFaces = out.mesh.faceCount();
  out.welded = weldObjVertices(out.mesh, &out.objLines, nullptr, &out.sourceVertex);
  return out;
}

ImportedMesh readMeshFile(std::string_view bytes, std::string_view name, const GltfResources& resources) {
  return readMeshFile(bytes, detectFormat(bytes, name), resources);
}

namespace {

// The first (smallest) vertex at each vertex's exact position, by sorting: the vertices ordered by
// (x, y, z, index) with a stable radix sort on x (its bits made to sort like the doubles, -0 as
// +0), then each run of equal x sorted by (y, z, index). Equal positions end up adjacent, their
// first source vertex first. O(n log n) whatever the positions.
std::vector<uint32_t> firstAtPositionSorted(const double* p, size_t n) {
  auto keyOf = [](double x) {
    uint64_t u;
    x = x == 0 ? 0.0 : x;
    std::memcpy(&u, &x, 8);
    return (u >> 63) ? ~u : u | (uint64_t(1) << 63);
  };
  // The keys travel with the indices (sequential reads, no gather per pass); a 16-bit digit that
  // is the same for every key (common in the high bits) costs no pass.
  std::vector<uint64_t> key(n), keyScratch(n);
  for (size_t v = 0; v < n; ++v) key[v] = keyOf(p[3 * v]);
  std::vector<uint32_t> order(n), scratch(n);
  std::iota(order.begin(), order.end(), 0u);
  std::vector<uint32_t> counts(4 * 65536, 0u);
  for (size_t v = 0; v < n; ++v)
    for (int d = 0; d < 4; ++d) ++counts[d * 65536 + ((key[v] >> (16 * d)) & 0xffff)];
  for (int d = 0; d < 4; ++d) {
    uint32_t* c = counts.data() + d * 65536;
    const int shift = 16 * d;
    if (n == 0 || c[(key[0] >> shift) & 0xffff] == n) continue;
    uint32_t sum = 0;
    for (size_t i = 0; i < 65536; ++i) sum += std::exchange(c[i], sum);
    for (size_t i = 0; i < n; ++i) {
      const uint32_t at = c[(key[i] >> shift) & 0xffff]++;
      keyScratch[at] = key[i];
      scratch[at] = order[i];
    }
    order.swap(scratch);
    key.swap(keyScratch);
  }
  for (size_t i = 0; i < n;) {
    size_t j = i + 1;
    while (j < n && key[j] == key[i]) ++j;
    if (j - i > 1)
      std::sort(order.begin() + i, order.begin() + j, [&](uint32_t a, uint32_t b) {
        if (p[3 * a + 1] != p[3 * b + 1]) return p[3 * a + 1] < p[3 * b + 1];
        if (p[3 * a + 2] != p[3 * b + 2]) return p[3 * a + 2] < p[3 * b + 2];
        return a < b;
      });
    i = j;
  }
  scratch = {};
  keyScratch = {};
  std::vector<uint32_t> representative(n);
  for (size_t i = 0; i < n; ++i) {
    const uint32_t v = order[i], u = i > 0 ? order[i - 1] : 0;
    const bool same = i > 0 && p[3 * v] == p[3 * u] && p[3 * v + 1] == p[3 * u + 1] && p[3 * v + 2] == p[3 * u + 2];
    representative[v] = same ? representative[u] : v;
  }
  key = {};
  order = {};
  return representative;
}

uint64_t positionHash(const double* q) {
  auto bitsOf = [](double x) {
    uint64_t u;
    x = x == 0 ? 0.0 : x;  // -0 == +0
    std::memcpy(&u, &x, 8);
    return u;
  };
  // Each coordinate mixed in before the next: a sum of one product per coordinate would give
  // positions that differ in signs only (a mesh symmetric about planes through the origin) the
  // same hash.
  uint64_t h = bitsOf(q[0]) * 0x9E3779B97F4A7C15ull;
  h = (h ^ (h >> 32) ^ bitsOf(q[1])) * 0xC2B2AE3D27D4EB4Full;
  h = (h ^ (h >> 32) ^ bitsOf(q[2])) * 0x165667B19E3779F9ull;
  h ^= h >> 29;
  h *= 0xBF58476D1CE4E5B9ull;
  return h ^ (h >> 32);
}

// The same by hashing the positions, as a list: the vertices that are not the first at their
// position, each with that first one (most files have none, and then nothing per vertex is
// written). First a filter: each vertex sets one bit of its hash in a bitmap of about 8 bits per
// vertex (small enough to stay in the CPU's cache, where a table of the vertices would miss on
// every lookup); vertices at one position set the same bit, so only the vertices whose bit was set
// more than once (a few percent when all positions differ) can have a duplicate. Those alone are
// looked up in a table (linear probing; visiting them in order makes the first one met the
// smallest). Gives up (returns false) when the probes exceed a few per vertex, as positions made to
// collide would make it quadratic: the sort then does the work.
bool duplicatesHashed(const double* p, size_t n, std::vector<std::pair<uint32_t, uint32_t>>& duplicates) {
  constexpr uint32_t kNaN = 0xffffffffu;  // NaN equals nothing: no bit
  size_t bits = 1024;
  int shift = 64 - 10;
  while (bits < 8 * n && bits < (size_t(1) << 31)) bits *= 2, --shift;
  std::vector<uint64_t> seen(bits / 64, 0), shared(bits / 64, 0);
  std::vector<uint32_t> bitOf(n);
  for (size_t v = 0; v < n; ++v) {
    const double* q = p + 3 * v;
    if (std::isnan(q[0]) || std::isnan(q[1]) || std::isnan(q[2])) {
      bitOf[v] = kNaN;
      continue;
    }
    const uint32_t b = uint32_t(positionHash(q) >> shift);
    bitOf[v] = b;
    const uint64_t m = uint64_t(1) << (b & 63);
    shared[b >> 6] |= seen[b >> 6] & m;
    seen[b >> 6] |= m;
  }
  seen = {};
  std::vector<uint32_t> candidates;
  for (size_t v = 0; v < n; ++v)
    if (bitOf[v] != kNaN && (shared[bitOf[v] >> 6] >> (bitOf[v] & 63) & 1)) candidates.push_back(uint32_t(v));
  bitOf = {};
  shared = {};
  size_t capacity = 16;
  while (capacity < 2 * candidates.size()) capacity *= 2;
  const size_t mask = capacity - 1;
  constexpr uint32_t kEmpty = 0xffffffffu;
  std::vector<uint32_t> table(capacity, kEmpty);
  uint64_t probes = 0;
  const uint64_t maxProbes = 8 * uint64_t(candidates.size()) + 1024;
  for (const uint32_t v : candidates) {
    const double* q = p + 3 * size_t(v);
    for (size_t slot = size_t(positionHash(q)) & mask;; slot = (slot + 1) & mask) {
      if (++probes > maxProbes) return false;
      const uint32_t u = table[slot];
      if (u == kEmpty) {
        table[slot] = v;
        break;
      }
      const double* r = p + 3 * size_t(u);
      if (r[0] == q[0] && r[1] == q[1] && r[2] == q[2]) {
        duplicates.emplace_back(v, u);
        break;
      }
    }
  }
  return true;
}

}  // namespace

size_t weldExactPositions(TriangleMesh& mesh, std::vector<uint32_t>* firstSource, std::vector<uint32_t>* outputOfSource,
                          bool unlessAFaceCollapses) {
  const size_t n = mesh.vertexCount();
  const double* p = mesh.positions.data();
  auto unchanged = [&] {  // every vertex is its own output vertex: nothing to renumber
    if (firstSource) {
      firstSource->resize(n);
      std::iota(firstSource->begin(), firstSource->end(), 0u);
    }
    if (outputOfSource) {
      outputOfSource->resize(n);
      std::iota(outputOfSource->begin(), outputOfSource->end(), 0u);
    }
    return size_t(0);
  };
  std::vector<uint32_t> representative;
  std::vector<std::pair<uint32_t, uint32_t>> duplicates;
  if (!duplicatesHashed(p, n, duplicates)) {
    representative = firstAtPositionSorted(p, n);
  } else if (duplicates.empty()) {
    return unchanged();
  } else {
    representative.resize(n);
    std::iota(representative.begin(), representative.end(), 0u);
    for (const auto& [v, u] : duplicates) representative[v] = u;
    duplicates = {};
  }
  // (the representative is the first vertex at each position: equal ones, equal positions)
  if (unlessAFaceCollapses)
    for (size_t i = 0; i + 2 < mesh.faces.size(); i += 3) {
      const uint32_t a = representative[mesh.faces[i]], b = representative[mesh.faces[i + 1]], c = representative[mesh.faces[i + 2]];
      if (a == b || b == c || a == c) return unchanged();
    }
  // Output numbering in the order of first occurrence.
  std::vector<uint32_t> output(n);
  std::vector<uint32_t> first;
  first.reserve(n);
  size_t kept = 0;
  for (size_t v = 0; v < n; ++v) {
    if (representative[v] == v) {
      output[v] = uint32_t(kept);
      if (kept != v)
        for (int k = 0; k < 3; ++k) mesh.positions[3 * kept + k] = mesh.positions[3 * v + k];
      first.push_back(uint32_t(v));
      ++kept;
    } else {
      output[v] = output[representative[v]];
    }
  }
  if (kept < n) {  // else every vertex is its own output vertex: nothing to renumber
    mesh.positions.resize(3 * kept);
    for (uint32_t& i : mesh.faces) i = output[i];
  }
  if (firstSource) *firstSource = std::move(first);
  if (outputOfSource) *outputOfSource = std::move(output);
  return n - kept;
}

}  // namespace mrvol
