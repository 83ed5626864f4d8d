// Mesh files other than OBJ (mrvol/io_formats.h): every format and variant in tests/data/good
// reads to the same mesh as octahedron.obj (same positions, same triangles up to vertex
// numbering and rotation); welding, fans, strips, node transforms; GLB export read back; format
// detection; the hostile files of tests/data/bad/expected-formats.json fail with their messages.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "fixtures.h"
#include "mrvol/error.h"
#include "mrvol/io_formats.h"
#include "mrvol/mesh.h"
#include "mrvol/multires_mesh.h"
#include "mrvol/thread_pool.h"
#include "../../wasm/core/src/position_table.h"

using namespace mrvol;
namespace fs = std::filesystem;

namespace {

const std::string kGood = fixtures::sourcePath("tests/data/good");
const std::string kBad = fixtures::sourcePath("tests/data/bad");

using Triangle = std::array<std::array<double, 3>, 3>;

// The triangles as position triples, each rotated to start at its smallest corner, sorted:
// equal for two meshes with the same triangles whatever their vertex numbering.
std::vector<Triangle> canonicalTriangles(const TriangleMesh& m) {
  std::vector<Triangle> out;
  for (size_t f = 0; f < m.faceCount(); ++f) {
    Triangle t;
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) t[k][c] = m.positions[3 * m.faces[3 * f + k] + c];
    auto smallest = std::min_element(t.begin(), t.end()) - t.begin();
    std::rotate(t.begin(), t.begin() + smallest, t.end());
    out.push_back(t);
  }
  std::sort(out.begin(), out.end());
  return out;
}

void expectSameMesh(const TriangleMesh& expected, const TriangleMesh& actual, const std::string& what) {
  EXPECT_EQ(actual.vertexCount(), expected.vertexCount()) << what;
  EXPECT_EQ(canonicalTriangles(actual), canonicalTriangles(expected)) << what;
}

TriangleMesh octahedronObj() { return readObj(fixtures::readFile(kGood + "/octahedron.obj")); }

ImportedMesh readGood(const std::string& name, const GltfResources& resources = {}) {
  return readMeshFile(fixtures::readFile(kGood + "/" + name), name, resources);
}

}  // namespace

TEST(ReadFormats, EveryVariantReadsLikeTheObj) {
  const TriangleMesh reference = octahedronObj();
  const std::map<std::string, std::pair<MeshFormat, std::string>> files = {
      {"octahedron-ascii.stl", {MeshFormat::Stl, "ASCII STL"}},
      {"octahedron-binary.stl", {MeshFormat::Stl, "binary STL"}},
      {"octahedron-binary-solid-header.stl", {MeshFormat::Stl, "binary STL"}},
      {"octahedron-ascii.ply", {MeshFormat::Ply, "ASCII PLY"}},
      {"octahedron-binary-le.ply", {MeshFormat::Ply, "binary little-endian PLY"}},
      {"octahedron-binary-be.ply", {MeshFormat::Ply, "binary big-endian PLY"}},
      {"octahedron.off", {MeshFormat::Off, "OFF"}},
      {"octahedron.coff", {MeshFormat::Off, "COFF"}},
      {"octahedron.noff", {MeshFormat::Off, "NOFF"}},
      {"octahedron-embedded.gltf", {MeshFormat::Gltf, "glTF"}},
      {"octahedron.glb", {MeshFormat::Glb, "GLB"}},
      {"octahedron-soup-and-fan.glb", {MeshFormat::Glb, "GLB"}},
  };
  for (const auto& [name, expected] : files) {
    SCOPED_TRACE(name);
    ImportedMesh m = readGood(name);
    EXPECT_EQ(m.format, expected.first);
    EXPECT_EQ(m.variant, expected.second);
    expectSameMesh(reference, m.mesh, name);
    EXPECT_NO_THROW(validateMesh(m.mesh));
    EXPECT_DOUBLE_EQ(meshVolume(m.mesh), 4.0 / 3.0);
    EXPECT_EQ(m.sourceVertex.size(), m.mesh.vertexCount());
    EXPECT_EQ(m.welded + m.mesh.vertexCount(), m.sourceVertices);
  }
  // The indexed formats keep the file's vertex order when nothing is welded: identical arrays.
  for (const char* name : {"octahedron-ascii.ply", "octahedron-binary-be.ply", "octahedron.off", "octahedron.glb"}) {
    ImportedMesh m = readGood(name);
    EXPECT_EQ(m.mesh.positions, reference.positions) << name;
    EXPECT_EQ(m.mesh.faces, reference.faces) << name;
    EXPECT_EQ(m.welded, 0u) << name;
  }
}

TEST(ReadFormats, StlTrianglesAreWeldedAndRecordTheirFirstCorner) {
  ImportedMesh m = readGood("octahedron-binary.stl");
  EXPECT_EQ(m.sourceVertices, 24u);  // 8 triangles x 3 corners
  EXPECT_EQ(m.welded, 18u);
  ASSERT_EQ(m.mesh.vertexCount(), 6u);
  // Each output vertex's first corner has its position; the first corners are increasing.
  const std::string bytes = fixtures::readFile(kGood + "/octahedron-binary.stl");
  for (size_t v = 0; v < 6; ++v) {
    const uint32_t corner = m.sourceVertex[v];
    for (int k = 0; k < 3; ++k) {
      float x;
      std::memcpy(&x, bytes.data() + 84 + 50 * (corner / 3) + 12 + 12 * (corner % 3) + 4 * k, 4);
      EXPECT_EQ(m.mesh.positions[3 * v + k], double(x));
    }
    if (v > 0) EXPECT_GT(m.sourceVertex[v], m.sourceVertex[v - 1]);
  }
  // The OBJ's numbering is the order of first appearance: corner 0 (vertex 0), 1 (vertex 2), 2 (vertex 4), ...
  EXPECT_EQ(m.sourceVertex[0], 0u);
}

TEST(ReadFormats, WeldIsExactWithMinusZeroAsZero) {
  TriangleMesh m;
  // Two triangles sharing an edge, with the shared vertices repeated; one near-duplicate stays apart.
  m.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, /**/ 1, 0, 0, 1, 1, 0, 0, 1, 0, /**/ 1e-300, 0, 0};
  m.faces = {0, 1, 2, 3, 4, 5, 6, 1, 2};
  std::vector<uint32_t> first;
  EXPECT_EQ(weldExactPositions(m, &first), 2u);
  EXPECT_EQ(m.vertexCount(), 5u);
  EXPECT_EQ(first, (std::vector<uint32_t>{0, 1, 2, 4, 6}));
  EXPECT_EQ(m.faces, (std::vector<uint32_t>{0, 1, 2, 1, 3, 2, 4, 1, 2}));
  // -0.0 and 0.0 are the same position.
  TriangleMesh z;
  z.positions = {0.0, 0, 0, -0.0, 0, 0};
  z.faces = {0, 1, 1};
  EXPECT_EQ(weldExactPositions(z), 1u);
}

// Expected weld by brute force: the first vertex at each exact position (-0 as +0).
std::vector<uint32_t> firstAtEachPosition(const std::vector<double>& p) {
  std::map<std::array<double, 3>, uint32_t> first;
  std::vector<uint32_t> out;
  for (size_t v = 0; v < p.size() / 3; ++v)
    out.push_back(first.emplace(std::array<double, 3>{p[3 * v] + 0.0, p[3 * v + 1] + 0.0, p[3 * v + 2] + 0.0}, uint32_t(v)).first->second);
  return out;
}

void expectWeldLikeBruteForce(const std::vector<double>& positions) {
  TriangleMesh m;
  m.positions = positions;
  for (uint32_t v = 0; v + 2 < positions.size() / 3; v += 3) m.faces.insert(m.faces.end(), {v, v + 1, v + 2});
  const std::vector<uint32_t> expected = firstAtEachPosition(positions);
  std::vector<uint32_t> first, outputOf;
  const size_t merged = weldExactPositions(m, &first, &outputOf);
  std::vector<uint32_t> expectedFirst;
  for (uint32_t v = 0; v < expected.size(); ++v)
    if (expected[v] == v) expectedFirst.push_back(v);
  EXPECT_EQ(first, expectedFirst);
  EXPECT_EQ(merged, expected.size() - expectedFirst.size());
  for (size_t v = 0; v < expected.size(); ++v) ASSERT_EQ(first[outputOf[v]], expected[v]) << "vertex " << v;
}

TEST(ReadFormats, WeldMatchesBruteForceOnDuplicatesInAnyOrder) {
  std::vector<double> p;
  uint32_t seed = 7;
  auto next = [&] { return seed = seed * 1103515245u + 12345u; };
  for (int i = 0; i < 3000; ++i) p.insert(p.end(), {double(next() % 50), double(next() % 50) * 0.25, double(next() % 3) - 1.0});
  for (int i = 0; i < 600; ++i) p.insert(p.end(), {-0.0, 0.0, -0.0});
  expectWeldLikeBruteForce(p);
}

// Positions made to share one hash (the welder's own mix, inverted): the hashed weld gives up and
// the sort must give the same answer.
TEST(ReadFormats, WeldOfPositionsCollidingInTheHashFallsBackToTheSort) {
  const uint64_t k1 = 0x9E3779B97F4A7C15ull, k2 = 0xC2B2AE3D27D4EB4Full, k3 = 0x165667B19E3779F9ull;
  uint64_t inverse = k3;
  for (int i = 0; i < 6; ++i) inverse *= 2 - k3 * inverse;
  // The hash mixes x, then y (here +0: bits 0), then z in; z is chosen so that the value after z is
  // the same for every x (the steps after it are one-to-one).
  const uint64_t target = 0x3ff0000000000000ull * k3;
  std::vector<double> p;
  for (int i = 1; p.size() < 3 * 4000; ++i) {
    double x = i, z;
    uint64_t xb, zb;
    std::memcpy(&xb, &x, 8);
    uint64_t h = xb * k1;
    h = (h ^ (h >> 32)) * k2;
    zb = (target * inverse) ^ h ^ (h >> 32);
    std::memcpy(&z, &zb, 8);
    if (std::isnan(z) || z == 0) continue;
    p.insert(p.end(), {x, 0.0, z});
  }
  for (size_t v = 0; v < 1000; ++v) p.insert(p.end(), {p[3 * (999 - v)], p[3 * (999 - v) + 1], p[3 * (999 - v) + 2]});
  expectWeldLikeBruteForce(p);
}

// Positions that differ in signs only (a mesh symmetric about the coordinate planes), with
// duplicates among them.
TEST(ReadFormats, WeldOfSignSymmetricPositionsMatchesBruteForce) {
  std::vector<double> p;
  for (int i = 0; i < 2000; ++i)
    for (int signs = 0; signs < 8; ++signs)
      p.insert(p.end(), {(signs & 1 ? -1 : 1) * (1 + i * 0.125), (signs & 2 ? -1 : 1) * (2 + (i % 7) * 0.5),
                         (signs & 4 ? -1 : 1) * (3 + (i % 13) * 0.25)});
  for (int i = 0; i < 500; ++i) p.insert(p.end(), {p[3 * (7 * i)], p[3 * (7 * i) + 1], p[3 * (7 * i) + 2]});
  expectWeldLikeBruteForce(p);
}

/** A GLB of the document and the binary chunk `bin` (its length a multiple of 4). */
std::string glbOf(const nlohmann::json& doc, const std::string& bin) {
  std::string json = doc.dump();
  while (json.size() % 4) json += ' ';
  std::string glb = "glTF";
  auto u32 = [&](uint32_t v) { glb.append(reinterpret_cast<const char*>(&v), 4); };
  u32(2), u32(uint32_t(12 + 8 + json.size() + 8 + bin.size())), u32(uint32_t(json.size())), u32(0x4E4F534A);
  glb += json;
  u32(uint32_t(bin.size())), u32(0x004E4942);
  glb += bin;
  return glb;
}

// What readMeshFile says of a file: its error message, or "read".
std::string messageOf(const std::string& bytes, const char* name) {
  try {
    readMeshFile(bytes, name, {});
  } catch (const Error& e) {
    return e.what();
  }
  return "read";
}

// A binary STL of the given corners (3 per triangle, normals zero).
std::string binaryStl(const std::vector<float>& corners) {
  const uint32_t n = uint32_t(corners.size() / 9);
  std::string b(84 + 50 * size_t(n), '\0');
  std::memcpy(&b[80], &n, 4);
  for (uint32_t t = 0; t < n; ++t) std::memcpy(&b[84 + 50 * size_t(t) + 12], &corners[9 * size_t(t)], 36);
  return b;
}

// readStl welds while it reads: the same result as every corner read as its own vertex, then
// weldExactPositions (positions bit for bit, the first corner's -0 kept).
void expectStlLikeReadThenWeld(const std::vector<float>& corners) {
  const ImportedMesh m = readStl(binaryStl(corners));
  TriangleMesh reference;
  for (float x : corners) reference.positions.push_back(x);
  for (uint32_t i = 0; i < corners.size() / 3; ++i) reference.faces.push_back(i);
  std::vector<uint32_t> first;
  const size_t merged = weldExactPositions(reference, &first);
  EXPECT_EQ(m.variant, "binary STL");
  EXPECT_EQ(m.welded, merged);
  EXPECT_EQ(m.sourceVertices, corners.size() / 3);
  EXPECT_EQ(m.sourceFaces, corners.size() / 9);
  EXPECT_EQ(m.sourceVertex, first);
  EXPECT_EQ(m.mesh.faces, reference.faces);
  ASSERT_EQ(m.mesh.positions.size(), reference.positions.size());
  EXPECT_EQ(std::memcmp(m.mesh.positions.data(), reference.positions.data(), 8 * reference.positions.size()), 0);
}

// A count of 0 in the header (a writer that never filled it in): the triangles after it are read;
// with none after it, the message says so.
TEST(ReadFormats, StlWithZeroCountReadsTheTrianglesItHolds) {
  const std::vector<float> corners = {0, 0, 0, 0, 1, 0, 1, 0, 0,  0, 0, 0, 1, 0, 0, 0, 0, 1,
                                      1, 0, 0, 0, 1, 0, 0, 0, 1,  0, 0, 0, 0, 0, 1, 0, 1, 0};
  std::string file = binaryStl(corners);
  const ImportedMesh declared = readStl(file);
  std::memset(&file[80], 0, 4);
  const ImportedMesh zero = readStl(file);
  EXPECT_EQ(zero.mesh.faces, declared.mesh.faces);
  EXPECT_EQ(zero.mesh.positions, declared.mesh.positions);
  EXPECT_EQ(zero.sourceFaces, 4u);
  try {
    readStl(file.substr(0, 84));
    FAIL() << "a header alone was read";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "binary STL: the file declares 0 triangles and holds none");
  }
}

TEST(ReadFormats, StlWeldedWhileReadMatchesReadThenWeld) {
  // Many more distinct positions than a closed mesh's corners / 6 (the table grows), repeats in
  // any order, -0 and +0 mixed.
  std::vector<float> corners;
  uint32_t seed = 11;
  auto next = [&] { return seed = seed * 1103515245u + 12345u; };
  auto coordinate = [&] { const uint32_t r = (next() >> 8) % 40; return r < 4 ? (r % 2 ? -0.0f : 0.0f) : float(r) * 0.5f; };
  for (int i = 0; i < 9 * 4000; ++i) corners.push_back(coordinate());
  expectStlLikeReadThenWeld(corners);
}

// Positions made to share their home slot in the reader's table (the table's own hash, searched):
// the lookups exceed their budget and the reader falls back to read-then-weld, same result.
TEST(ReadFormats, StlOfPositionsCollidingInTheHashIsWeldedAllTheSame) {
  auto bits = [](float x) { uint32_t u; std::memcpy(&u, &x, 4); return u; };
  std::vector<float> keys;
  uint64_t home = 0;
  for (uint32_t i = 1; keys.size() < 3 * 400; ++i) {
    const uint32_t key[3] = {bits(float(i)), bits(1.0f), bits(2.0f)};
    const uint64_t h = io::FloatPositionTable::hash(key) >> 52;  // the same slot in any table up to 4,096 slots
    if (keys.empty()) home = h;
    if (h == home) keys.insert(keys.end(), {float(i), 1.0f, 2.0f});
  }
  std::vector<float> corners = keys;  // 400 corners: 133 triangles and one corner
  for (size_t i = 0; corners.size() < 9 * 1000; i = (i + 7) % 400) corners.insert(corners.end(), &keys[3 * i], &keys[3 * i + 3]);
  corners.resize(9 * 1000);
  // The table sized for this file (1,000 triangles) probes beyond the reader's budget.
  io::FloatPositionTable table(3000 / 6);
  for (size_t c = 0; c < 400; ++c) {
    const uint32_t key[3] = {bits(keys[3 * c]), bits(keys[3 * c + 1]), bits(keys[3 * c + 2])};
    table.findOrAdd(key);
  }
  EXPECT_GT(table.probes(), 8u * 3000 + 1024);
  expectStlLikeReadThenWeld(corners);
}

// The pool set to `count` threads and cut to small blocks: a binary STL of a few thousand
// triangles is welded in `count` blocks at once.
struct StlThreads {
  explicit StlThreads(unsigned count) {
    setThreadCount(count);
    setGrainCap(16);
  }
  ~StlThreads() {
    setGrainCap(0);
    setThreadCount(1);
  }
};

// Random corners among few positions (most repeat in several blocks), -0 and +0 mixed.
std::vector<float> randomStlCorners(uint32_t seed, int triangles) {
  std::vector<float> corners;
  auto next = [&] { return seed = seed * 1103515245u + 12345u; };
  auto coordinate = [&] { const uint32_t r = (next() >> 8) % 40; return r < 4 ? (r % 2 ? -0.0f : 0.0f) : float(r) * 0.5f; };
  for (int i = 0; i < 9 * triangles; ++i) corners.push_back(coordinate());
  return corners;
}

// Welded in blocks on several threads: the same numbers as in one pass (vertices in the order of
// their first corner, the first corner's -0 kept), 2 to 16 blocks.
TEST(ReadFormats, StlWeldedInBlocksMatchesReadThenWeld) {
  for (unsigned threads : {2u, 3u, 16u}) {
    StlThreads pool(threads);
    SCOPED_TRACE(threads);
    expectStlLikeReadThenWeld(randomStlCorners(11, 4000));
    // A strip whose later triangles come back to the first ones' positions (vertices first met in
    // a later block, then in earlier and later ones again).
    std::vector<float> strip;
    for (int t = 0; t < 3000; ++t) {
      const int a = (t * 7) % 1500, b = (t * 7 + 1) % 1500, c = t % 2 ? t : 1;
      strip.insert(strip.end(), {float(a), 0.0f, -0.0f, float(b), 1.0f, 0.0f, float(c), 2.0f, t % 3 ? 0.0f : -0.0f});
    }
    expectStlLikeReadThenWeld(strip);
  }
}

// A non-finite coordinate in several blocks: the message names the first in the file, as one pass does.
TEST(ReadFormats, StlWeldedInBlocksReportsTheFirstNonFiniteCoordinate) {
  std::vector<float> corners = randomStlCorners(5, 4000);
  corners[9 * 3500 + 4] = std::numeric_limits<float>::quiet_NaN();
  corners[9 * 1200 + 7] = std::numeric_limits<float>::infinity();
  corners[9 * 2100 + 1] = -std::numeric_limits<float>::infinity();
  const std::string file = binaryStl(corners);
  auto message = [&] {
    try {
      readStl(file);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string expected = message();
  EXPECT_NE(expected.find("triangle 1,200 "), std::string::npos) << expected;
  for (unsigned threads : {2u, 4u, 16u}) {
    StlThreads pool(threads);
    EXPECT_EQ(message(), expected) << threads << " threads";
  }
}

// Positions made to collide, welded in blocks: the blocks give up as one pass does, same result.
TEST(ReadFormats, StlOfCollidingPositionsInBlocksIsWeldedAllTheSame) {
  auto bits = [](float x) { uint32_t u; std::memcpy(&u, &x, 4); return u; };
  std::vector<float> keys;
  uint64_t home = 0;
  for (uint32_t i = 1; keys.size() < 3 * 400; ++i) {
    const uint32_t key[3] = {bits(float(i)), bits(1.0f), bits(2.0f)};
    const uint64_t h = io::FloatPositionTable::hash(key) >> 52;
    if (keys.empty()) home = h;
    if (h == home) keys.insert(keys.end(), {float(i), 1.0f, 2.0f});
  }
  std::vector<float> corners;
  for (size_t i = 0; corners.size() < 9 * 2000; i = (i + 7) % 400) corners.insert(corners.end(), &keys[3 * i], &keys[3 * i + 3]);
  corners.resize(9 * 2000);
  for (unsigned threads : {2u, 4u}) {
    StlThreads pool(threads);
    expectStlLikeReadThenWeld(corners);
  }
}

TEST(ReadFormats, PolygonsAreSplitIntoFans) {
  for (const char* name : {"cube-quads.ply", "cube-quads.off"}) {
    ImportedMesh m = readGood(name);
    EXPECT_EQ(m.triangulated, 6u) << name;
    EXPECT_EQ(m.sourceFaces, 6u) << name;
    EXPECT_EQ(m.mesh.faceCount(), 12u) << name;
    MeshTopology t = validateMesh(m.mesh);
    EXPECT_TRUE(t.closed) << name;
    EXPECT_DOUBLE_EQ(meshVolume(m.mesh), 1.0) << name;
  }
  expectSameMesh(readGood("cube-quads.ply").mesh, readGood("cube-quads.off").mesh, "cube");
}

TEST(ReadFormats, GltfSidecarBufferIsPassedByTheCaller) {
  const std::string bin = fixtures::readFile(kGood + "/octahedron-sidecar.bin");
  ImportedMesh m = readGood("octahedron-sidecar.gltf", {{"octahedron-sidecar.bin", bin}});
  expectSameMesh(octahedronObj(), m.mesh, "sidecar");
  try {
    readGood("octahedron-sidecar.gltf");
    FAIL() << "no error without the sidecar";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "glTF buffer 0 refers to the file 'octahedron-sidecar.bin', which was not given (pass it beside the .gltf)");
  }
}

TEST(ReadFormats, GltfNodeTransformsAreApplied) {
  ImportedMesh m = readGood("octahedron-transforms.glb");
  const TriangleMesh o = octahedronObj();
  // Node 0: translation (1, 2, 3), 90 degrees about z, scale 2: p -> 2 (-y, x, z) + t. Node 1, its
  // child: x -> -x + 10, then node 0's transform. The mirror turns the winding around.
  TriangleMesh expected;
  const double s = std::sqrt(0.5);
  const double c = 1 - 2 * s * s;  // cos 90 degrees as the quaternion gives it (rounding included)
  auto place = [&](double x, double y, double z) {
    const double r00 = c, r01 = -2 * s * s, r10 = 2 * s * s, r11 = c;
    expected.positions.insert(expected.positions.end(),
                              {2 * (r00 * x + r01 * y) + 1, 2 * (r10 * x + r11 * y) + 2, 2 * z + 3});
  };
  for (size_t v = 0; v < 6; ++v) place(o.positions[3 * v], o.positions[3 * v + 1], o.positions[3 * v + 2]);
  for (size_t v = 0; v < 6; ++v) place(-o.positions[3 * v] + 10, o.positions[3 * v + 1], o.positions[3 * v + 2]);
  for (size_t f = 0; f < 8; ++f) expected.faces.insert(expected.faces.end(), {o.faces[3 * f], o.faces[3 * f + 1], o.faces[3 * f + 2]});
  for (size_t f = 0; f < 8; ++f) expected.faces.insert(expected.faces.end(), {o.faces[3 * f] + 6, o.faces[3 * f + 2] + 6, o.faces[3 * f + 1] + 6});
  ASSERT_EQ(m.mesh.vertexCount(), 12u);
  for (size_t i = 0; i < expected.positions.size(); ++i) EXPECT_NEAR(m.mesh.positions[i], expected.positions[i], 1e-12) << i;
  EXPECT_EQ(m.mesh.faces, expected.faces);
  MeshTopology t = validateMesh(m.mesh);
  EXPECT_EQ(t.components, 2u);
  EXPECT_NEAR(meshVolume(m.mesh), 2 * 8 * 4.0 / 3.0, 1e-12);  // both outward: the mirrored copy flipped back
}

TEST(ReadFormats, GltfStripsDropTheirJoiningTriangles) {
  // A strip 0 1 2 3 over a unit square, written in a GLB by hand: triangles (0 1 2) and (1 3 2).
  nlohmann::json doc = {
      {"asset", {{"version", "2.0"}}},
      {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}, {"mode", 5}}}}}}},
      {"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}},
                     {{"bufferView", 1}, {"componentType", 5121}, {"count", 6}, {"type", "SCALAR"}}}},
      {"bufferViews", {{{"buffer", 0}, {"byteLength", 48}}, {{"buffer", 0}, {"byteOffset", 48}, {"byteLength", 6}}}},
      {"buffers", {{{"byteLength", 54}}}},
  };
  const float p[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
  const uint8_t strip[6] = {0, 1, 2, 3, 3, 3};  // the repeated 3s make degenerate triangles
  std::string bin(reinterpret_cast<const char*>(p), 48);
  bin.append(reinterpret_cast<const char*>(strip), 6);
  bin.append(2, '\0');
  const std::string glb = glbOf(doc, bin);
  ImportedMesh m = readGlb(glb);
  EXPECT_EQ(m.mesh.faces, (std::vector<uint32_t>{0, 1, 2, 1, 3, 2}));  // glTF: odd i gives (i, i + 2, i + 1)
  EXPECT_EQ(m.sourceFaces, 2u);
}

TEST(ReadFormats, GltfIndicesOfASignedTypeAreRefused) {
  // Index -1 as a signed short (componentType 5122): glTF indices are unsigned (found by fuzz_gltf).
  nlohmann::json doc = {
      {"asset", {{"version", "2.0"}}},
      {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}}}}}},
      {"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"count", 3}, {"type", "VEC3"}},
                     {{"bufferView", 1}, {"componentType", 5122}, {"count", 3}, {"type", "SCALAR"}}}},
      {"bufferViews", {{{"buffer", 0}, {"byteLength", 36}}, {{"buffer", 0}, {"byteOffset", 36}, {"byteLength", 6}}}},
      {"buffers", {{{"byteLength", 44}}}},
  };
  const float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const int16_t index[3] = {0, 1, -1};
  std::string bin(reinterpret_cast<const char*>(p), 36);
  bin.append(reinterpret_cast<const char*>(index), 6);
  bin.append(2, '\0');
  const std::string glb = glbOf(doc, bin);
  try {
    readGlb(glb);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "GLB accessor 1 (indices of mesh 0 primitive 0): componentType 5122, indices must be unsigned "
                           "integers (5121, 5123 or 5125)");
  }
}

// A tetrahedron's 4 triangles with indices of each unsigned type (read as uint32 straight from the
// bytes), with sparse indices on top, and an index past the last vertex: the same faces and
// messages as the double path gives.
TEST(ReadFormats, GltfIndicesOfEachUnsignedTypeReadAlike) {
  const std::vector<uint32_t> faces = {0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2};
  auto glbWith = [&](uint64_t type, std::vector<uint32_t> index, bool normalized, bool sparse) {
    const size_t size = type == 5121 ? 1 : type == 5123 ? 2 : 4;
    nlohmann::json indices = {{"bufferView", 1}, {"componentType", type}, {"count", index.size()}, {"type", "SCALAR"}};
    if (normalized) indices["normalized"] = true;
    if (sparse)  // index 4 (the second triangle's second corner) set to 1 again, read from bufferView 2
      indices["sparse"] = {{"count", 1}, {"indices", {{"bufferView", 2}, {"componentType", 5125}}},
                           {"values", {{"bufferView", 2}, {"byteOffset", 4}}}};
    const float p[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    std::string bin(reinterpret_cast<const char*>(p), 48);
    for (uint32_t i : index) bin.append(reinterpret_cast<const char*>(&i), size);  // little-endian: the low bytes
    bin.append((4 - bin.size() % 4) % 4, '\0');
    const size_t sparseAt = bin.size();
    const uint32_t sparseData[2] = {4, 1};
    bin.append(reinterpret_cast<const char*>(sparseData), 8);
    nlohmann::json doc = {
        {"asset", {{"version", "2.0"}}},
        {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}}}}}},
        {"accessors", {{{"bufferView", 0}, {"componentType", 5126}, {"count", 4}, {"type", "VEC3"}}, indices}},
        {"bufferViews", {{{"buffer", 0}, {"byteLength", 48}},
                         {{"buffer", 0}, {"byteOffset", 48}, {"byteLength", size * index.size()}},
                         {{"buffer", 0}, {"byteOffset", sparseAt}, {"byteLength", 8}}}},
        {"buffers", {{{"byteLength", bin.size()}}}},
    };
    return glbOf(doc, bin);
  };
  for (uint64_t type : {5121u, 5123u, 5125u}) {
    EXPECT_EQ(readGlb(glbWith(type, faces, false, false)).mesh.faces, faces) << type;
    std::vector<uint32_t> changed = faces;
    changed[4] = 7;  // past the 4 vertices, but the sparse value puts 1 back
    EXPECT_EQ(readGlb(glbWith(type, changed, false, true)).mesh.faces, faces) << type;
    changed[5] = 4;
    try {
      readGlb(glbWith(type, changed, false, true));
      FAIL() << "no error for type " << type;
    } catch (const Error& e) {
      EXPECT_STREQ(e.what(), "GLB mesh 0 primitive 0: index 5 is 4 but POSITION has 4 vertices") << type;
    }
  }
  // Normalized indices (not valid glTF) go the double way: values 0..1, truncated to vertex 0 or 1.
  std::vector<uint32_t> mapped;
  for (uint32_t i : faces) mapped.push_back(i == 0 ? 0 : 255);
  const ImportedMesh m = readGlb(glbWith(5121, mapped, true, false));
  EXPECT_EQ(m.sourceFaces, 4u);
  EXPECT_EQ(m.mesh.faces, (std::vector<uint32_t>{0, 1, 1, 0, 1, 1, 1, 1, 1, 0, 1, 1}));
}

// A face index beyond int64's range, or NaN, is named in the message without an undefined cast
// (found by fuzz_ply: tests/fuzz/regressions/fuzz_ply/ascii-index-beyond-int64.ply).
TEST(ReadFormats, PlyIndexBeyondInt64IsNamed) {
  const std::string head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                           "element face 1\nproperty list uchar uint vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n";
  auto errorOf = [](const std::string& file) {
    try {
      readPly(file);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(errorOf(head + "3 0 1 1e30\n"), "PLY line 13: face 0 vertex index 1e+30 is not valid");
  EXPECT_EQ(errorOf(head + "3 0 1 -1e30\n"), "PLY line 13: face 0 vertex index -1e+30 is not valid");
  EXPECT_EQ(errorOf(head + "3 0 1 -2\n"), "PLY line 13: face 0 vertex index -2 is not valid");
  EXPECT_EQ(errorOf(head + "3 0 1 nan\n"), "PLY line 13: face 0 vertex index nan is not valid");
}

TEST(ReadFormats, GlbExportReadsBackToTheSameMesh) {
  // A subdivided mesh: 642 vertices; coordinates rounded to float32 by the format.
  const MultiresMesh mr = MultiresMesh::subdivide(fixtures::icosahedron(), 3);
  const TriangleMesh mesh{mr.subdivisionPositions(fixtures::icosahedron().positions, SchemeOptions{}), mr.faces()};
  TriangleMesh rounded = mesh;
  for (double& x : rounded.positions) x = double(float(x));
  ImportedMesh back = readGlb(writeGlb(mesh));
  EXPECT_EQ(back.mesh.positions, rounded.positions);
  EXPECT_EQ(back.mesh.faces, mesh.faces);
  EXPECT_EQ(back.welded, 0u);
  EXPECT_EQ(MultiresMesh(std::move(back.mesh)).levels(), 3);
  EXPECT_THROW(writeGlb(TriangleMesh{}), Error);
}

// Text written by editors on Windows starts with a UTF-8 byte order mark: ASCII STL and PLY (ASCII
// and binary: its header is text) read as without it, found by content with no name too. An ASCII
// STL with one was taken for binary ("binary STL: 1,702,130,277 triangles declared"), a PLY refused
// ("the first line must be 'ply'").
TEST(ReadFormats, ByteOrderMarkBeforeTextHeaders) {
  const TriangleMesh reference = octahedronObj();
  const std::string bom = "\xEF\xBB\xBF";
  for (const char* name : {"octahedron-ascii.stl", "octahedron-ascii.ply", "octahedron-binary-le.ply", "octahedron-binary-be.ply"}) {
    SCOPED_TRACE(name);
    const std::string bytes = bom + fixtures::readFile(kGood + "/" + name);
    const ImportedMesh plain = readGood(name);
    for (const std::string given : {std::string(name), std::string()}) {
      ImportedMesh m = readMeshFile(bytes, given, {});
      EXPECT_EQ(m.format, plain.format);
      EXPECT_EQ(m.variant, plain.variant);
      EXPECT_EQ(m.mesh.positions, plain.mesh.positions);
      EXPECT_EQ(m.mesh.faces, plain.mesh.faces);
      expectSameMesh(reference, m.mesh, name);
    }
  }
  // A binary STL whose 80-byte header happens to start with those bytes is still binary (its size
  // fits its count).
  std::string binary = fixtures::readFile(kGood + "/octahedron-binary.stl");
  binary.replace(0, 3, bom);
  ImportedMesh m = readMeshFile(binary, "x.stl", {});
  EXPECT_EQ(m.variant, "binary STL");
  expectSameMesh(reference, m.mesh, "binary STL with a BOM-like header");
}

// ASCII STL as tools write it: keywords in capitals (SOLID, FACET NORMAL, OUTER LOOP), blank lines
// before 'solid', a name in UTF-8 or Latin-1. Each was taken for binary ("807,416,096 triangles
// declared"). A binary STL whose header starts with "solid" (SolidWorks) stays binary, found by
// content too; text that is not STL says so; "ply " with a blank after it is PLY.
TEST(ReadFormats, AsciiStlAsToolsWriteIt) {
  const TriangleMesh reference = octahedronObj();
  const std::string ascii = fixtures::readFile(kGood + "/octahedron-ascii.stl");
  std::string upper = ascii;
  for (char& c : upper) c = char(std::toupper(static_cast<unsigned char>(c)));
  const std::string body = ascii.substr(ascii.find('\n'));  // after the 'solid NAME' line
  for (const std::string& bytes : {upper, "\n\n  " + ascii, "solid Teil \xC3\x98" "20 \xE2\x80\x93 Geh\xC3\xA4use" + body,
                                   "solid Pi\xE8" "ce \xB0" "C" + body}) {
    SCOPED_TRACE(bytes.substr(0, 30));
    for (const std::string given : {std::string("x.stl"), std::string()}) {
      ImportedMesh m = readMeshFile(bytes, given, {});
      EXPECT_EQ(m.variant, "ASCII STL");
      expectSameMesh(reference, m.mesh, "ASCII STL");
    }
  }
  std::string solidHeader = fixtures::readFile(kGood + "/octahedron-binary.stl");
  const std::string header = "solid cube exported by SolidWorks";
  solidHeader.replace(0, header.size(), header);
  for (const std::string given : {std::string("x.stl"), std::string()}) {
    ImportedMesh m = readMeshFile(solidHeader, given, {});
    EXPECT_EQ(m.variant, "binary STL");
    expectSameMesh(reference, m.mesh, "binary STL with a 'solid' header");
  }
  try {
    readMeshFile("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "mesh.stl", {});
    FAIL() << "OBJ text read as STL";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "STL: the file is text but not ASCII STL, which starts with 'solid' (its first line: 'v 0 0 0')");
  }
  std::string ply = fixtures::readFile(kGood + "/octahedron-ascii.ply");
  ply.insert(3, " ");
  for (const std::string given : {std::string("x.ply"), std::string()}) expectSameMesh(reference, readMeshFile(ply, given, {}).mesh, "'ply '");
}

// glTF as scenes hold it: a mesh's edges or markers as LINES / POINTS primitives beside its
// triangles (left out, as an OBJ's l and p lines are: the scene was refused), Draco data beside the
// uncompressed accessors (extension used, not required: the accessors are read), a required
// extension that leaves the geometry alone (materials) read, an unknown one refused by name.
TEST(ReadFormats, GltfScenesAsToolsWriteThem) {
  const TriangleMesh reference = octahedronObj();
  const nlohmann::json doc = nlohmann::json::parse(fixtures::readFile(kGood + "/octahedron-embedded.gltf"));
  auto read = [](const nlohmann::json& d) { return readMeshFile(d.dump(), "x.gltf", {}); };
  nlohmann::json lines = doc;
  nlohmann::json edges = doc["meshes"][0]["primitives"][0];
  edges["mode"] = 1;
  edges.erase("indices");
  lines["meshes"][0]["primitives"].push_back(edges);
  edges["mode"] = 0;
  lines["meshes"][0]["primitives"].insert(lines["meshes"][0]["primitives"].begin(), edges);
  expectSameMesh(reference, read(lines).mesh, "triangles beside lines and points");
  nlohmann::json draco = doc;
  draco["extensionsUsed"] = {"KHR_draco_mesh_compression"};
  draco["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"] = {{"bufferView", 0}, {"attributes", {{"POSITION", 0}}}};
  expectSameMesh(reference, read(draco).mesh, "Draco beside the accessors");
  nlohmann::json materials = doc;
  materials["extensionsRequired"] = {"KHR_materials_unlit"};
  expectSameMesh(reference, read(materials).mesh, "a required materials extension");
  nlohmann::json unknown = doc;
  unknown["extensionsRequired"] = {"EXT_foo_bar"};
  try {
    read(unknown);
    FAIL() << "an unknown required extension was read past";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "glTF file requires the extension 'EXT_foo_bar', which mrvol does not know (export the model without it)");
  }
}

// Triangles written as quads with a repeated corner ("3 4 a b c c", as some writers pad them), in
// PLY and OFF: the triangles, not a degenerate one beside each (a 12-triangle octahedron read as 16).
TEST(ReadFormats, PolygonsWithARepeatedCornerAreTheirTriangles) {
  const TriangleMesh reference = octahedronObj();
  std::string ply = "ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\nproperty float y\nproperty float z\n"
                    "element face 8\nproperty list uchar int vertex_indices\nend_header\n";
  std::string off = "OFF\n6 8 0\n";
  for (size_t v = 0; v < 6; ++v) {
    std::string line;
    for (int k = 0; k < 3; ++k) line += (k ? " " : "") + std::to_string(reference.positions[3 * v + k]);
    ply += line + "\n";
    off += line + "\n";
  }
  for (size_t f = 0; f < 8; ++f) {
    const uint32_t* c = &reference.faces[3 * f];
    // the repeat in a different place each time, the wrap-around (a b c a) too
    const std::array<uint32_t, 4> quad = f % 3 == 0 ? std::array<uint32_t, 4>{c[0], c[1], c[2], c[2]}
                                       : f % 3 == 1 ? std::array<uint32_t, 4>{c[0], c[0], c[1], c[2]}
                                                    : std::array<uint32_t, 4>{c[0], c[1], c[2], c[0]};
    std::string line = "4";
    for (uint32_t i : quad) line += " " + std::to_string(i);
    ply += line + "\n";
    off += line + "\n";
  }
  for (const auto& [bytes, name] : {std::pair{ply, "x.ply"}, std::pair{off, "x.off"}}) {
    SCOPED_TRACE(name);
    ImportedMesh m = readMeshFile(bytes, name, {});
    EXPECT_EQ(m.mesh.faceCount(), 8u);
    expectSameMesh(reference, m.mesh, name);
  }
  // Every face collapsing (found by fuzz_off: the reader returned no faces): said so.
  EXPECT_EQ(messageOf("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 1 0\n", "x.off"),
            "OFF: no face has 3 distinct vertices (its one face repeats a vertex: no area)");
  EXPECT_EQ(messageOf("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 1 0\n3 2 2 1\n", "x.off"),
            "OFF: no face has 3 distinct vertices (each of its 2 faces repeats a vertex: no area)");
  EXPECT_EQ(messageOf("v 0 0 0\nv 1 0 0\nf 1 2 2 1\n", "x.obj"),
            "no faces: its one 'f' line repeats a vertex (fewer than 3 distinct: no area)");
}

// nOFF names its dimension after the keyword (Geomview's OFF): 3 reads as OFF, others are named.
TEST(ReadFormats, OffOfDimensionThreeReadsAndOthersAreNamed) {
  const std::string body = "4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  const ImportedMesh plain = readMeshFile("OFF\n" + body, "x.off");
  for (const std::string header : {"nOFF\n3\n", "nOFF 3\n", "CnOFF\n# dimension\n3 ", "nOFF 3 "}) {
    SCOPED_TRACE(header);
    std::string bytes = header + body;
    if (header == "CnOFF\n# dimension\n3 ") {
      bytes = header + "4 4 6\n0 0 0 1 0 0 1\n1 0 0 1 0 0 1\n0 1 0 1 0 0 1\n0 0 1 1 0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    }
    const ImportedMesh m = readMeshFile(bytes, "x.off");
    expectSameMesh(plain.mesh, m.mesh, header);
  }
  EXPECT_EQ(messageOf("nOFF\n4\n" + body, "x.off"), "OFF line 2: 'nOFF' of dimension 4: mrvol reads 3D OFF files only");
  EXPECT_EQ(messageOf("nOFF\nx\n" + body, "x.off"), "OFF line 2: nOFF dimension 'x' is not an integer");
  EXPECT_EQ(messageOf("nOFF\n", "x.off"), "OFF: the file ends before the dimension of its nOFF vertices");
  EXPECT_EQ(messageOf("4OFF\n" + body, "x.off"), "OFF line 1: '4OFF': mrvol reads 3D OFF files only (4OFF has 4 coordinates a vertex)");
}

// Files a user picks by mistake beside a mesh: an OBJ's material library, a .blend.
TEST(ReadFormats, NotAMeshSaysWhatItIs) {
  EXPECT_EQ(messageOf("# Blender MTL File\nnewmtl Material\nKd 0.8 0.8 0.8\n", "model.mtl"),
            "this is a material library (.mtl) that an OBJ refers to, not a mesh: open the .obj file");
  EXPECT_EQ(messageOf("newmtl Material\nKd 0.8 0.8 0.8\n", ""),
            "this is a material library (.mtl) that an OBJ refers to, not a mesh: open the .obj file");
  EXPECT_EQ(messageOf(std::string("BLENDER-v300REND\0\0\0", 19), "scene.blend"),
            "unknown mesh format .blend (looks like a Blender file: export the model as OBJ, STL, PLY or glTF); "
            "mrvol reads obj, stl, ply, off, gltf and glb");
}

TEST(ReadFormats, DetectionByContentAndExtension) {
  auto file = [](const char* name) { return fixtures::readFile(kGood + "/" + name); };
  // Content wins over a misleading or missing name.
  EXPECT_EQ(detectFormat(file("octahedron.glb"), "model.obj"), MeshFormat::Glb);
  EXPECT_EQ(detectFormat(file("octahedron-ascii.ply"), ""), MeshFormat::Ply);
  EXPECT_EQ(detectFormat(file("octahedron.off"), "x.stl"), MeshFormat::Off);
  EXPECT_EQ(detectFormat(file("octahedron-embedded.gltf"), ""), MeshFormat::Gltf);
  EXPECT_EQ(detectFormat(file("octahedron-binary.stl"), ""), MeshFormat::Stl);
  EXPECT_EQ(detectFormat(file("octahedron-ascii.stl"), ""), MeshFormat::Stl);
  EXPECT_EQ(detectFormat(file("octahedron.obj"), ""), MeshFormat::Obj);
  // A binary STL with "solid" in its header has no signature: the extension decides.
  EXPECT_EQ(detectFormat(file("octahedron-binary-solid-header.stl"), "A.STL"), MeshFormat::Stl);
  EXPECT_EQ(parseFormatName(".Glb"), MeshFormat::Glb);
  EXPECT_THROW(parseFormatName("fbx"), Error);
  try {
    detectFormat(std::string("PK\x03\x04rest", 8), "");
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "unknown mesh format (looks like a ZIP archive); mrvol reads obj, stl, ply, off, gltf and glb");
  }
}

TEST(ReadFormats, HostileFilesFailWithTheirMessages) {
  const nlohmann::json manifest = nlohmann::json::parse(fixtures::readFile(kBad + "/expected-formats.json"));
  const auto& files = manifest.at("files");
  size_t checked = 0;
  for (const auto& entry : fs::directory_iterator(kBad)) {
    const std::string name = entry.path().filename().string();
    const std::string ext = entry.path().extension().string();
    if (ext == ".obj" || ext == ".json" || ext == ".mjs") continue;
    SCOPED_TRACE(name);
    ASSERT_TRUE(files.contains(name)) << name << " is not listed in expected-formats.json";
    std::string message;
    try {
      ImportedMesh m = readMeshFile(fixtures::readFile(entry.path().string()), name);
      validateMesh(m.mesh);
    } catch (const Error& e) {
      message = e.what();
    }
    size_t from = 0;
    for (const auto& part : files.at(name).at("error")) {
      const size_t at = message.find(part.get<std::string>(), from);
      EXPECT_NE(at, std::string::npos) << "message: " << message << "\nexpected: " << part;
      if (at != std::string::npos) from = at;
    }
    ++checked;
  }
  EXPECT_EQ(checked, files.size());
}

TEST(WriteGlbKeeping, KeepsTheSourceAndReplacesPositionsAndNormals) {
  const MultiresMesh mr = MultiresMesh::subdivide(fixtures::icosahedron(), 2);
  const std::string source =
      writeGlb(TriangleMesh{mr.subdivisionPositions(fixtures::icosahedron().positions, SchemeOptions{}), mr.faces()});  // has NORMAL
  ImportedMesh read = readGlb(source);
  TriangleMesh edited = read.mesh;
  for (size_t i = 0; i < edited.positions.size(); ++i) edited.positions[i] *= 1 + 0.01 * double(i % 7);
  const std::string out = writeGlbKeeping(source, MeshFormat::Glb, {}, edited);
  ImportedMesh back = readGlb(out);
  EXPECT_EQ(back.mesh.faces, edited.faces);
  for (size_t i = 0; i < edited.positions.size(); ++i) EXPECT_EQ(back.mesh.positions[i], double(float(edited.positions[i]))) << i;
  // The normals are what writeGlb computes for the edited mesh (same area-weighted sums).
  const std::string fresh = writeGlb(edited);
  auto normalsOf = [](const std::string& glb) {
    const uint32_t jsonLength = *reinterpret_cast<const uint32_t*>(glb.data() + 12);
    auto doc = nlohmann::json::parse(glb.substr(20, jsonLength));
    const auto& accessor = doc["accessors"][doc["meshes"][0]["primitives"][0]["attributes"]["NORMAL"].get<size_t>()];
    const auto& view = doc["bufferViews"][accessor["bufferView"].get<size_t>()];
    const size_t offset = 20 + jsonLength + 8 + view.value("byteOffset", size_t(0)) + accessor.value("byteOffset", size_t(0));
    return glb.substr(offset, 12 * accessor["count"].get<size_t>());
  };
  EXPECT_EQ(normalsOf(out), normalsOf(fresh));
  // Other triangles are refused.
  TriangleMesh other = edited;
  std::swap(other.faces[0], other.faces[1]);
  EXPECT_THROW(writeGlbKeeping(source, MeshFormat::Glb, {}, other), Error);
}

TEST(WriteGlbKeeping, NodeFramesAndSharedAccessors) {
  const std::string source = fixtures::readFile(kGood + "/octahedron-transforms.glb");
  ImportedMesh read = readGlb(source);
  // Unchanged positions go back through the inverse node transforms.
  ImportedMesh same = readGlb(writeGlbKeeping(source, MeshFormat::Glb, {}, read.mesh));
  ASSERT_EQ(same.mesh.faces, read.mesh.faces);
  for (size_t i = 0; i < read.mesh.positions.size(); ++i) EXPECT_NEAR(same.mesh.positions[i], read.mesh.positions[i], 1e-5);
  // Both nodes instance mesh 0: moving one copy alone cannot be written into the shared accessor.
  TriangleMesh moved = read.mesh;
  moved.positions[0] += 0.5;
  try {
    writeGlbKeeping(source, MeshFormat::Glb, {}, moved);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("is shared by nodes the edit moves differently"), std::string::npos) << e.what();
  }
  // A .gltf with a sidecar buffer becomes one GLB with everything in its BIN chunk.
  const std::string gltf = fixtures::readFile(kGood + "/octahedron-sidecar.gltf");
  const std::string bin = fixtures::readFile(kGood + "/octahedron-sidecar.bin");
  ImportedMesh sidecar = readGltf(gltf, {{"octahedron-sidecar.bin", bin}});
  sidecar.mesh.positions[2] = 2;  // vertex 0 up
  ImportedMesh glb = readGlb(writeGlbKeeping(gltf, MeshFormat::Gltf, {{"octahedron-sidecar.bin", bin}}, sidecar.mesh));
  EXPECT_EQ(glb.mesh.positions, sidecar.mesh.positions);
  EXPECT_EQ(glb.mesh.faces, sidecar.mesh.faces);
}
