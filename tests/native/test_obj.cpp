// OBJ in every form seen in the wild (polygons, v/vt/vn, colours, CRLF, BOM), the hostile variants
// of those forms, writeObjLike (an edit keeps the file's other lines), and the size guard.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "mrvol/error.h"
#include "mrvol/hierarchy.h"
#include "mrvol/mesh.h"

using namespace mrvol;

namespace {

std::string errorOf(const std::string& text) {
  try {
    readObj(text);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// Area vector (twice the area, oriented) of triangle f.
std::array<double, 3> areaVector(const TriangleMesh& m, size_t f) {
  const double* a = &m.positions[3 * m.faces[3 * f]];
  const double* b = &m.positions[3 * m.faces[3 * f + 1]];
  const double* c = &m.positions[3 * m.faces[3 * f + 2]];
  const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  return {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
}

constexpr uint32_t kNo = ObjExtras::kNoIndex;

}  // namespace

TEST(ObjPolygons, ConvexQuadIsAFanKeepingItsLine) {
  SourceLines lines;
  ObjExtras extras;
  TriangleMesh m = readObj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n", &lines, &extras);
  EXPECT_EQ(m.faces, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
  EXPECT_EQ(lines.face, (std::vector<uint32_t>{5, 5}));
  EXPECT_EQ(extras.polygons, 1u);
  EXPECT_EQ(extras.polygonTriangles, 2u);
  EXPECT_EQ(validateMesh(m).boundaryEdges, 4u);
}

TEST(ObjPolygons, PolygonsStayInFaceOrderBetweenTriangles) {
  SourceLines lines;
  TriangleMesh m = readObj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nf 2 5 3\nf 1 2 3 4\nf 5 2 1\n", &lines);
  EXPECT_EQ(m.faces, (std::vector<uint32_t>{1, 4, 2, 0, 1, 2, 0, 2, 3, 4, 1, 0}));
  EXPECT_EQ(lines.face, (std::vector<uint32_t>{6, 7, 7, 8}));
}

TEST(ObjPolygons, NonConvexPolygonIsEarClippedIntoItsOwnArea) {
  // An L-shaped hexagon (counter-clockwise, area 3) and, reversed, the same clockwise.
  const std::string vertices = "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\n";
  for (const char* face : {"f 1 2 3 4 5 6\n", "f 6 5 4 3 2 1\n", "f 4 5 6 1 2 3\n"}) {
    ObjExtras extras;
    TriangleMesh m = readObj(vertices + face, nullptr, &extras);
    ASSERT_EQ(m.faceCount(), 4u) << face;
    EXPECT_EQ(extras.polygonTriangles, 4u);
    const double sign = face[2] == '6' ? -1.0 : 1.0;
    double area = 0;
    for (size_t f = 0; f < m.faceCount(); ++f) {
      const auto n = areaVector(m, f);
      EXPECT_GT(sign * n[2], 0) << face << " triangle " << f << " is not oriented like the polygon";
      area += sign * n[2] / 2;
    }
    EXPECT_NEAR(area, 3.0, 1e-12) << face;
    EXPECT_NO_THROW(validateMesh(m)) << face;
  }
}

TEST(ObjPolygons, CubeOfQuadsIsClosedWithUnitVolume) {
  const std::string cube =
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n"
      "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
  ObjExtras extras;
  TriangleMesh m = readObj(cube, nullptr, &extras);
  EXPECT_EQ(extras.polygons, 6u);
  EXPECT_EQ(m.faceCount(), 12u);
  MeshTopology t = validateMesh(m);
  EXPECT_TRUE(t.closed);
  EXPECT_EQ(t.genus, 0);
  EXPECT_NEAR(meshVolume(m), 1.0, 1e-15);
  EXPECT_EQ(Hierarchy::detect(m).levels, 0);  // readable, but no 1-to-4 split
}

TEST(ObjPolygons, HugeConvexPolygonIsFannedAndHugeNonConvexOneRefused) {
  const int k = 100000;
  std::string text;
  for (int i = 0; i < k; ++i) {
    const double a = 2 * M_PI * i / k;  // a circle: convex
    char line[96];
    std::snprintf(line, sizeof line, "v %.17g %.17g 0\n", std::cos(a), std::sin(a));
    text += line;
  }
  std::string face = "f";
  for (int i = 1; i <= k; ++i) face += " " + std::to_string(i);
  TriangleMesh m = readObj(text + face + "\n");
  EXPECT_EQ(m.faceCount(), size_t(k - 2));
  std::string star;
  for (int i = 0; i < 5000; ++i) {
    const double a = 2 * M_PI * i / 5000, r = (i % 2 == 0) ? 1.0 : 0.5;
    star += "v " + std::to_string(r * std::cos(a)) + " " + std::to_string(r * std::sin(a)) + " 0\n";
  }
  face = "f";
  for (int i = 1; i <= 5000; ++i) face += " " + std::to_string(i);
  EXPECT_EQ(errorOf(star + face + "\n"),
            "line 5001: non-convex polygon with 5000 vertices is too large to triangulate (mrvol ear-clips "
            "non-convex polygons of at most 4096 vertices)");
}

TEST(ObjPolygons, HostileVariants) {
  const std::string square = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";
  EXPECT_EQ(errorOf(square + "f 1 2\n"), "line 5: face has 2 vertices, a triangle needs 3");
  EXPECT_EQ(errorOf(square + "f 1 2 3 0\n"), "line 5: face index 0 is not valid (OBJ indices start at 1)");
  EXPECT_EQ(errorOf("f -1 -2 -3 -4\n" + square),
            "line 1: relative face index '-1' reaches before the first vertex (0 vertices so far)");
  EXPECT_EQ(errorOf(square + "f 1 2 1 3 4\n"), "line 5: polygon with 5 vertices uses vertex 1 more than once");
  // A repeat of the corner before ("f 1 2 3 3": a triangle padded to a quad; the last closing on the
  // first) is left out, as PLY and OFF read it: the triangle, the square.
  EXPECT_EQ(errorOf(square + "f 1 2 3 4 1\n"), "");
  EXPECT_EQ(errorOf(square + "f 1 2 3 3\nf 1 3 4 4\nf 2 2\n"), "line 7: face has 2 vertices, a triangle needs 3");
  const TriangleMesh padded = readObj(square + "f 1 2 3 3\nf 1 1 3 4\nf 3 3 3 3\n");
  EXPECT_EQ(padded.faces, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
  EXPECT_EQ(errorOf(square + "f 1 2 3 4 5\n"), "line 5: face refers to vertex 5 but the file has 4 vertices");
  EXPECT_EQ(errorOf(square + "\xEF\xBB\xBF" "f 1 2 3\n"),
            "line 5: unknown statement '???f': this does not look like an OBJ file");
  EXPECT_EQ(errorOf(square + "f 1/a 2 3 4\n"), "line 5: face texture index '1/a' is not an integer");
  EXPECT_EQ(errorOf(square + "f 1//b 2 3 4\n"), "line 5: face normal index '1//b' is not an integer");
  EXPECT_EQ(errorOf("v 0 0 0 1 1\n"), "line 1: vertex has 5 values, expected 3 (x y z), 4 (x y z w) or 6 (x y z r g b)");
  EXPECT_EQ(errorOf(square + "vt\n"), "line 5: texture coordinate needs 1 to 3 values, found 0");
  EXPECT_EQ(errorOf(square + "vn 0 1\n"), "line 5: normal needs 3 values, found 2");
  EXPECT_EQ(errorOf(square + "vn 0 1 nan\n"), "line 5: coordinate 'nan' is not finite");
}

TEST(ObjAttributes, TexCoordsNormalsAndColoursAreKept) {
  const std::string text =
      "\xEF\xBB\xBF# exported\r\nmtllib a.mtl\r\no thing\r\ng part\r\nusemtl red\r\ns 1\r\n"
      "v 0 0 0 1 0 0\r\nv 1 0 0 0 1 0\r\nv 1 1 0 0 0 1\r\nv 0 1 0 1 1 1\r\n"
      "vt 0 0\r\nvt 1 0 0\r\nvt 1 1\r\nvt 0 1\r\nvn 0 0 1\r\n"
      "f 1/1/1 2/2/1 3/3/1\r\nf 1/-4/-1 3/-2/-1 4/-1/-1\r\n";
  ObjExtras extras;
  SourceLines lines;
  TriangleMesh m = readObj(text, &lines, &extras);
  EXPECT_EQ(m.faces, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
  EXPECT_EQ(lines.vertex, (std::vector<uint32_t>{7, 8, 9, 10}));
  EXPECT_EQ(extras.texCoords, (std::vector<double>{0, 0, 1, 0, 1, 1, 0, 1}));
  EXPECT_EQ(extras.normals, (std::vector<double>{0, 0, 1}));
  EXPECT_EQ(extras.colors, (std::vector<double>{1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1}));
  EXPECT_EQ(extras.cornerTexCoords, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
  EXPECT_EQ(extras.cornerNormals, (std::vector<uint32_t>(6, 0)));
}

TEST(ObjAttributes, PolygonCornersKeepTheirTexCoords) {
  ObjExtras extras;
  TriangleMesh m = readObj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n",
                           nullptr, &extras);
  ASSERT_EQ(extras.cornerTexCoords.size(), m.faces.size());
  for (size_t i = 0; i < m.faces.size(); ++i) EXPECT_EQ(extras.cornerTexCoords[i], m.faces[i]);
  EXPECT_EQ(extras.cornerNormals, (std::vector<uint32_t>(6, kNo)));
}

TEST(ObjAttributes, ReferencesToNoTexCoordAreDroppedNotRefused) {
  ObjExtras extras;
  TriangleMesh m = readObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/7 3/-5\n", nullptr, &extras);
  EXPECT_EQ(m.faceCount(), 1u);
  EXPECT_TRUE(extras.cornerTexCoords.empty());  // 7 is beyond the one vt line
  EXPECT_EQ(extras.texCoords.size(), 2u);
  EXPECT_EQ(extras.dropped, "texture coordinates left out: face corners refer to vt 7, and the file has 1 vt line");
  // both, said in one sentence; nothing said when nothing is left out
  ObjExtras both;
  readObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nvn 0 0 1\nf 1/2/3 2/1/1 3/1/1\n", nullptr, &both);
  EXPECT_EQ(both.dropped, "texture coordinates left out: face corners refer to vt 2, and the file has 1 vt line; "
                          "normals left out: face corners refer to vn 3, and the file has 2 vn lines");
  ObjExtras none;
  readObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\n", nullptr, &none);
  EXPECT_EQ(none.dropped, "");
  // Colours on some vertices only: none kept.
  readObj("v 0 0 0 1 1 1\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", nullptr, &extras);
  EXPECT_TRUE(extras.colors.empty());
}

TEST(WriteObjLike, KeepsEveryOtherLineAndUnchangedSpellings) {
  const std::string original =
      "# head\r\nmtllib a.mtl\r\nv 0 0 0 0.5 0.5 0.5 # red\r\nv +1.0 0 0\r\nv 0 1e0 0\r\nv 0 0 1\r\n"
      "vt 0.25 0.75\r\nvn 0 0 1\r\ng side\r\nusemtl m\r\nf 1/1/1 3/1/1 2/1/1\r\nf 1 2 4\r\nf 1 4 3\r\nf 2 3 4\r\n";
  TriangleMesh m = readObj(original);
  EXPECT_EQ(writeObjLike(original, m.positions.data(), m.vertexCount()), original);
  std::vector<double> moved = m.positions;
  moved[0] = 0.1;   // vertex 0 x
  moved[11] = 2.5;  // vertex 3 z
  const std::string edited = writeObjLike(original, moved.data(), m.vertexCount());
  EXPECT_EQ(edited,
            "# head\r\nmtllib a.mtl\r\nv 0.1 0 0 0.5 0.5 0.5 # red\r\nv +1.0 0 0\r\nv 0 1e0 0\r\nv 0 0 2.5\r\n"
            "vt 0.25 0.75\r\nvn 0 0 1\r\ng side\r\nusemtl m\r\nf 1/1/1 3/1/1 2/1/1\r\nf 1 2 4\r\nf 1 4 3\r\nf 2 3 4\r\n");
  TriangleMesh back = readObj(edited);
  EXPECT_EQ(back.positions, moved);
  EXPECT_EQ(back.faces, m.faces);
  // Exact doubles survive (shortest spelling that reads back).
  moved[1] = 1.0 / 3.0;
  EXPECT_EQ(readObj(writeObjLike(original, moved.data(), 4)).positions[1], 1.0 / 3.0);
  try {
    writeObjLike(original, moved.data(), 3);
    FAIL() << "a count mismatch was accepted";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "the original OBJ has 4 vertices but 3 positions were given");
  }
}

// An exporter's split vertices (three.js's OBJExporter: three v lines per triangle, with vt / vn):
// welded by position, lines and colours kept from each vertex's first v line; writeObjLike writes
// every v line of a welded vertex with its position, every other byte as it was.
TEST(WeldObjVertices, WeldsSplitVerticesAndWriteObjLikeMapsThemBack) {
  const std::string original =
      "# two triangles, each with its own three vertices\n"
      "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\n"
      "v 1 0 0 0.5 0.5 0.5\nv 1 1 0 1 1 1\nv 0 1 0 0 0 0\n"
      "vt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\n"
      "f 1/1 2/2 3/3\nf 4/2 5/4 6/3\n";
  SourceLines lines;
  ObjExtras extras;
  TriangleMesh m = readObj(original, &lines, &extras);
  ASSERT_EQ(m.vertexCount(), 6u);
  std::vector<uint32_t> first;
  EXPECT_EQ(weldObjVertices(m, &lines, &extras, &first), 2u);
  EXPECT_EQ(m.positions, (std::vector<double>{0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0}));
  EXPECT_EQ(m.faces, (std::vector<uint32_t>{0, 1, 2, 1, 3, 2}));
  EXPECT_EQ(first, (std::vector<uint32_t>{0, 1, 2, 4}));
  EXPECT_EQ(lines.vertex, (std::vector<uint32_t>{2, 3, 4, 6}));  // 1-based lines of the first v of each
  EXPECT_EQ(lines.face, (std::vector<uint32_t>{12, 13}));
  EXPECT_EQ(extras.colors, (std::vector<double>{1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1}));
  EXPECT_EQ(extras.cornerTexCoords, (std::vector<uint32_t>{0, 1, 2, 1, 3, 2}));  // per corner: unchanged

  // The welded positions moved, written back into the file's six v lines.
  std::vector<double> moved = m.positions;
  moved[3] = 2;  // vertex 1 (v lines 2 and 4)
  const std::string written = writeObjLike(original, moved.data(), 4);
  EXPECT_EQ(written,
            "# two triangles, each with its own three vertices\n"
            "v 0 0 0 1 0 0\nv 2 0 0 0 1 0\nv 0 1 0 0 0 1\n"
            "v 2 0 0 0.5 0.5 0.5\nv 1 1 0 1 1 1\nv 0 1 0 0 0 0\n"
            "vt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\n"
            "f 1/1 2/2 3/3\nf 4/2 5/4 6/3\n");
  // Six positions (one per v line) still write as before; a count that is neither is refused in words.
  TriangleMesh asRead = readObj(original);
  EXPECT_EQ(writeObjLike(original, asRead.positions.data(), 6), original);
  try {
    writeObjLike(original, moved.data(), 3);
    FAIL() << "a count mismatch was accepted";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "the original OBJ has 6 vertices (4 once those at one position are welded) but 3 positions were given");
  }
  // A weld that would give a triangle two equal corners is not made: the mesh stays as read, and its
  // checks name its own problem (every vertex at one point).
  TriangleMesh point = readObj("v 1 1 1\nv 1 1 1\nv 1 1 1\nv 1 1 1\nf 1 2 3\nf 1 4 2\nf 2 4 3\nf 3 4 1\n");
  const TriangleMesh pointAsRead = point;
  EXPECT_EQ(weldObjVertices(point, nullptr, nullptr, &first), 0u);
  EXPECT_EQ(point.faces, pointAsRead.faces);
  EXPECT_EQ(point.vertexCount(), 4u);
  EXPECT_EQ(first, (std::vector<uint32_t>{0, 1, 2, 3}));
  // Nothing at one position: nothing changes (0 welded, first = identity).
  TriangleMesh tetra = readObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n");
  const TriangleMesh before = tetra;
  EXPECT_EQ(weldObjVertices(tetra, nullptr, nullptr, &first), 0u);
  EXPECT_EQ(tetra.positions, before.positions);
  EXPECT_EQ(tetra.faces, before.faces);
  EXPECT_EQ(first, (std::vector<uint32_t>{0, 1, 2, 3}));
}

// A vertex continued over lines ("v 0 0 \\" then "0"): unchanged, its lines are kept; moved, it is
// written on one line with what followed its coordinates.
TEST(WriteObjLike, ContinuedVertexLines) {
  const std::string original =
      "v 0 \\\r\n0 0 0.5 \\\r\n0.5 0.5\r\nv 1 0 0\r\nv 0 1 0\r\nv 0 0 \\\n1\nf 1 3 2\nf 1 2 \\\n4\nf 1 4 3\nf 2 3 4";
  TriangleMesh m = readObj(original);
  ASSERT_EQ(m.vertexCount(), 4u);
  EXPECT_EQ(writeObjLike(original, m.positions.data(), m.vertexCount()), original);
  std::vector<double> moved = m.positions;
  moved[1] = 0.25;  // vertex 0 y
  moved[11] = 2;    // vertex 3 z
  const std::string edited = writeObjLike(original, moved.data(), m.vertexCount());
  EXPECT_EQ(edited, "v 0 0.25 0 0.5  0.5 0.5\r\nv 1 0 0\r\nv 0 1 0\r\nv 0 0 2\nf 1 3 2\nf 1 2 \\\n4\nf 1 4 3\nf 2 3 4");
  TriangleMesh back = readObj(edited);
  EXPECT_EQ(back.positions, moved);
  EXPECT_EQ(back.faces, m.faces);
}

TEST(ObjSize, TooLargeForMemoryIsRefusedBeforeAllocating) {
  EXPECT_NO_THROW(checkMeshSize(2'700'000, 5'400'000));
  try {
    checkMeshSize(20'000'000, 40'000'000);
    FAIL() << "20 million vertices were accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("the mesh is too large to open: 20000000 vertices and 40000000 triangles"),
              std::string::npos)
        << e.what();
  }
}

TEST(ValidateMesh, HubOfValence30000IsLinear) {
  // A double cone: two apexes joined to every vertex of a 30,000-gon (closed, genus 0).
  const uint32_t k = 30000;
  TriangleMesh m;
  for (uint32_t i = 0; i < k; ++i) m.positions.insert(m.positions.end(), {std::cos(2 * M_PI * i / k), std::sin(2 * M_PI * i / k), 0.0});
  m.positions.insert(m.positions.end(), {0, 0, 1, 0, 0, -1});
  for (uint32_t i = 0; i < k; ++i) {
    const uint32_t j = (i + 1) % k;
    m.faces.insert(m.faces.end(), {k, i, j, k + 1, j, i});
  }
  MeshTopology t = validateMesh(m);
  EXPECT_TRUE(t.closed);
  EXPECT_EQ(t.genus, 0);
  EXPECT_EQ(t.edges, size_t(3 * k));
  EXPECT_EQ(Hierarchy::detect(m, 16, true).levels, 0);
  // The same with one apex face flipped: named like the ordered check names it.
  std::swap(m.faces[1], m.faces[2]);
  try {
    validateMesh(m);
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "inconsistent orientation at edge between vertices 0, 1: face 0 and face 1 traverse it in the same direction");
  }
}
