// STL: binary (80-byte header, uint32 count, 50 bytes per triangle) and ASCII ("solid ... facet
// normal ... outer loop vertex x y z ... endloop endfacet ... endsolid"). Every triangle has its
// own three vertices: they are welded by exact position.
#include <algorithm>
#include <atomic>
#include <cstring>
#include <memory>
#include <string>

#include "io_common.h"
#include "mrvol/io_formats.h"
#include "mrvol/thread_pool.h"
#include "position_table.h"

namespace mrvol {

namespace {

using io::count;

// Binary when the size fits the declared count, or when the file does not start like ASCII STL.
bool looksBinary(std::string_view b) {
  if (b.size() >= 84 && b.size() == 84 + 50 * uint64_t(io::load<uint32_t>(b.data() + 80))) return true;
  // ASCII STL: "solid" in any case, maybe after blank lines.
  if (!io::startsWithWord(b, "solid")) return true;
  // "solid" in a binary header: ASCII STL has only text after it (its name may be UTF-8 or Latin-1).
  return io::hasBinaryBytes(b.substr(0, 512));
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
  // A count of 0 with triangles after it: a writer that streamed the triangles and never came back
  // to fill the count in; the whole triangles the file holds are read.
  if (declared == 0 && available > 0) return available;
  if (declared == 0) throw Error("binary STL: the file declares 0 triangles and holds none");
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

// The lookup key of corner c of the triangle at p (its three floats' bits, -0 made +0); false at
// a coordinate that is not finite (its place 3 c + k in `bad`).
bool cornerKey(const char* p, int c, uint32_t (&key)[3], int& bad) {
  std::memcpy(key, p + 12 + 12 * c, 12);
  for (int k = 0; k < 3; ++k) {
    if ((key[k] & 0x7f800000u) == 0x7f800000u) {
      bad = 3 * c + k;
      return false;
    }
    if (key[k] == 0x80000000u) key[k] = 0;  // -0 == +0
  }
  return true;
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
      int bad = 0;
      if (!cornerKey(p, c, key, bad)) notFinite(t, bad);
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

// Triangles [from, to) welded on their own: each block's own table stays small enough for one
// core's caches, and the blocks run on the pool's threads at once.
struct WeldedBlock {
  uint64_t from = 0, to = 0;
  std::unique_ptr<io::FloatPositionTable> table;
  // Of each of the block's vertices, in its own numbering: its first corner, its position.
  std::vector<uint32_t> firstCorner;
  std::vector<double> positions;
  // One bit per hash value of the block's keys (about 8 bits per vertex, in L2): a key of a later
  // block whose bit is not set is not looked up in this block's table, a miss there being a miss in
  // memory too.
  std::vector<uint64_t> seen;
  std::vector<uint32_t> globalOf;     // the output number of each vertex (blocks after the first)
  uint64_t badTriangle = UINT64_MAX;  // where the block's first non-finite coordinate is
  int badCoordinate = 0;
  bool gaveUp = false;                // more probes than the budget (keys made to collide)
};

// The bit of a key in WeldedBlock::seen (bits below the table's home-slot bits).
size_t seenBit(const uint32_t (&key)[3], size_t bits) { return size_t(io::FloatPositionTable::hash(key) >> 20) & (bits - 1); }
bool wasSeen(const std::vector<uint64_t>& seen, size_t bit) { return seen[bit >> 6] >> (bit & 63) & 1; }

// The block's numbers written to its corners' faces (the same lookup as readBinaryWelded's); stops
// at a non-finite coordinate or beyond the probe budget (the caller decides what is reported).
void weldBlock(const char* triangles, size_t expectedVertices, size_t seenBits, WeldedBlock& block, uint32_t* faces) {
  const uint64_t corners = 3 * (block.to - block.from);
  block.table = std::make_unique<io::FloatPositionTable>(corners / 6);
  io::FloatPositionTable& table = *block.table;
  const uint64_t maxProbes = 8 * corners + 1024;
  block.firstCorner.reserve(expectedVertices);
  block.positions.reserve(3 * expectedVertices);
  block.seen.assign(seenBits / 64, 0);
  const char* p = triangles + 50 * block.from;
  for (uint64_t t = block.from; t < block.to; ++t, p += 50) {
    for (int c = 0; c < 3; ++c) {
      uint32_t key[3];
      if (!cornerKey(p, c, key, block.badCoordinate)) {
        block.badTriangle = t;
        return;
      }
      const uint32_t v = table.findOrAdd(key);
      if (v == block.firstCorner.size()) {
        block.firstCorner.push_back(uint32_t(3 * t + c));
        for (int k = 0; k < 3; ++k) block.positions.push_back(io::load<float>(p + 12 + 12 * c + 4 * k));
        const size_t bit = seenBit(key, seenBits);
        block.seen[bit >> 6] |= uint64_t(1) << (bit & 63);
      }
      faces[3 * t + c] = v;
    }
    if (table.probes() > maxProbes) {
      block.gaveUp = true;
      return;
    }
  }
}

// readBinaryWelded's result (the same numbers, bit for bit) from `count` blocks of triangles
// welded at once on the pool's threads. The first block's numbers are the output's; each later
// block's vertices are looked up among the vertices of the blocks before it (its new ones are
// numbered in its own order, which is the order of their first corners), then its corners are
// renumbered. Gives up (false) as readBinaryWelded does.
bool readBinaryWeldedInBlocks(std::string_view b, uint64_t declared, size_t count, ImportedMesh& out) {
  const char* triangles = b.data() + 84;
  const uint64_t corners = 3 * declared;
  const size_t expectedVertices = corners / 6 + 16;  // as readBinaryWelded: about 6 corners per vertex
  size_t seenBits = 1024;
  while (seenBits < 8 * expectedVertices && seenBits < (size_t(1) << 31)) seenBits *= 2;
  TriangleMesh& m = out.mesh;
  m.faces.resize(corners);
  std::vector<WeldedBlock> blocks(count);
  for (size_t k = 0; k < count; ++k) blocks[k].from = declared * k / count, blocks[k].to = declared * (k + 1) / count;
  parallelFor(0, count, 1, [&](size_t first, size_t end) {
    for (size_t k = first; k < end; ++k)  // the first block's vectors become the output's: room for all
      weldBlock(triangles, k == 0 ? expectedVertices : expectedVertices / count + 16, seenBits, blocks[k], m.faces.data());
  });
  for (const WeldedBlock& block : blocks)
    if (block.gaveUp) return false;
  for (const WeldedBlock& block : blocks)  // the first one in the file, as one pass would meet it
    if (block.badTriangle != UINT64_MAX) notFinite(block.badTriangle, block.badCoordinate);

  // The blocks merged so far: their vertices (numbered as the output), their bits.
  io::FloatPositionTable& merged = *blocks[0].table;
  std::vector<uint64_t>& mergedSeen = blocks[0].seen;
  std::vector<uint32_t>& first = out.sourceVertex;
  first = std::move(blocks[0].firstCorner);
  m.positions = std::move(blocks[0].positions);
  std::atomic<uint64_t> probes{0};  // of the lookups among the merged blocks
  const uint64_t maxProbes = 8 * corners + 1024;
  for (size_t k = 1; k < count; ++k) {
    WeldedBlock& block = blocks[k];
    const io::FloatPositionTable& table = *block.table;
    block.globalOf.resize(block.firstCorner.size());
    std::atomic<size_t> added{0};
    parallelFor(0, table.capacity(), 1 << 14, [&](size_t from, size_t to) {
      uint64_t visited = 0;
      size_t absent = 0;
      for (size_t s = from; s < to; ++s) {
        uint32_t key[3], local;
        if (!table.entry(s, key, local)) continue;
        const uint32_t v = wasSeen(mergedSeen, seenBit(key, seenBits)) ? merged.find(key, visited) : io::FloatPositionTable::kNone;
        block.globalOf[local] = v;
        absent += v == io::FloatPositionTable::kNone;
      }
      probes += visited;
      added += absent;
    });
    // The block's new vertices after those merged, in its order (resized once: a push per vertex is slow in WASM).
    size_t next = first.size();
    first.resize(next + added);
    m.positions.resize(3 * (next + added));
    const bool last = k + 1 == count;
    for (size_t i = 0; i < block.globalOf.size(); ++i) {
      if (block.globalOf[i] != io::FloatPositionTable::kNone) continue;
      block.globalOf[i] = uint32_t(next);
      first[next] = block.firstCorner[i];
      std::memcpy(&m.positions[3 * next], &block.positions[3 * i], 3 * sizeof(double));
      ++next;
      if (last) continue;
      uint32_t key[3];
      int bad;
      cornerKey(triangles + 50 * size_t(first[next - 1] / 3), int(first[next - 1] % 3), key, bad);
      merged.findOrAdd(key);  // numbered next - 1, as the table and `first` grow together
    }
    if (!last)
      for (size_t w = 0; w < mergedSeen.size(); ++w) mergedSeen[w] |= block.seen[w];
    block.table.reset();
    if (probes + merged.probes() > maxProbes) return false;
  }
  blocks[0].table.reset();

  parallelFor(3 * blocks[0].to, corners, 1 << 16, [&](size_t from, size_t to) {
    size_t k = 1;
    for (size_t c = from; c < to; ++c) {
      while (c >= 3 * blocks[k].to) ++k;
      m.faces[c] = blocks[k].globalOf[m.faces[c]];
    }
  });
  out.sourceVertices = corners;
  out.sourceFaces = declared;
  out.welded = corners - first.size();
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
      if (io::equalsWord(key, "solid")) { ended = false; continue; }  // several solids in one file
      throw Error(at() + "unexpected " + io::quoted(key) + " after 'endsolid'");
    }
    if (io::equalsWord(key, "solid") || io::equalsWord(key, "facet") || io::equalsWord(key, "endfacet")) {
      if (corner >= 0) throw Error(at() + io::quoted(key) + " inside an 'outer loop' (missing 'endloop')");
      continue;
    }
    if (io::equalsWord(key, "outer")) {
      if (n < 2 || !io::equalsWord(tokens[1], "loop")) throw Error(at() + "expected 'outer loop'");
      if (corner >= 0) throw Error(at() + "'outer loop' inside another (missing 'endloop')");
      corner = 0;
    } else if (io::equalsWord(key, "vertex")) {
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
    } else if (io::equalsWord(key, "endloop")) {
      if (corner != 3)
        throw Error(at() + "a facet with " + std::to_string(std::max(corner, 0)) + " vertices, a triangle needs 3");
      uint32_t v = uint32_t(m.positions.size() / 3);
      m.faces.insert(m.faces.end(), {v - 3, v - 2, v - 1});
      corner = -1;
    } else if (io::equalsWord(key, "endsolid")) {
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
  // A UTF-8 byte order mark before ASCII STL's "solid" (editors on Windows write one): skipped,
  // unless the file is binary by its size (a binary header may start with any bytes).
  if (io::hasByteOrderMark(bytes) && !looksBinary(bytes.substr(3)) &&
      !(bytes.size() >= 84 && bytes.size() == 84 + 50 * uint64_t(io::load<uint32_t>(bytes.data() + 80))))
    bytes.remove_prefix(3);
  if (looksBinary(bytes)) {
    // Text that is not ASCII STL (an OBJ named .stl, say): said so, not read as a binary count.
    const bool exactSize = bytes.size() >= 84 && bytes.size() == 84 + 50 * uint64_t(io::load<uint32_t>(bytes.data() + 80));
    if (!exactSize && !io::hasBinaryBytes(bytes.substr(0, 4096)))
      throw Error("STL: the file is text but not ASCII STL, which starts with 'solid' (its first line: " +
                  io::quoted(bytes.substr(0, bytes.find('\n'))) + ")" + io::looksLike(bytes));
    const uint64_t declared = binaryTriangles(bytes);
    out.variant = "binary STL";
    // Blocks big enough that merging them costs little beside welding them.
    const size_t blocks = parallelBlocks(declared, 1 << 15);
    const bool welded = blocks > 1 ? readBinaryWeldedInBlocks(bytes, declared, blocks, out) : readBinaryWelded(bytes, declared, out);
    if (!welded) {
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
