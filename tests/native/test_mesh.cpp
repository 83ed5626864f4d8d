// Meshes: the OBJ forms readObj accepts, the writeObj -> readObj round trip (order and exact
// coordinates), the topology validateMesh reports, and meshVolume on known solids.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "fixtures.h"
#include "mrvol/error.h"
#include "mrvol/mesh.h"

using namespace mrvol;

namespace {

// Unit right tetrahedron (0, e_x, e_y, e_z), counter-clockwise seen from outside: volume 1/6.
TriangleMesh unitTetrahedron() {
  TriangleMesh m;
  m.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  m.faces = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
  return m;
}

// Axis-aligned cube [x0, x0 + s]^3 ... made of 12 triangles, outward orientation.
TriangleMesh cube(double s, double x0 = 0, double y0 = 0, double z0 = 0) {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i)
    m.positions.insert(m.positions.end(), {x0 + s * (i & 1), y0 + s * ((i >> 1) & 1), z0 + s * ((i >> 2) & 1)});
  // Vertex i = (x, y, z) bits. Each quad listed counter-clockwise from outside, then split.
  const uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (auto& q : quads) m.faces.insert(m.faces.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
  return m;
}

TriangleMesh flipped(TriangleMesh m) {
  for (size_t f = 0; f < m.faceCount(); ++f) std::swap(m.faces[3 * f + 1], m.faces[3 * f + 2]);
  return m;
}

TriangleMesh translated(TriangleMesh m, double dx, double dy, double dz) {
  for (size_t v = 0; v < m.vertexCount(); ++v) m.positions[3 * v] += dx, m.positions[3 * v + 1] += dy, m.positions[3 * v + 2] += dz;
  return m;
}

TriangleMesh twoTetrahedra() {
  TriangleMesh a = unitTetrahedron(), b = translated(unitTetrahedron(), 5, 0, 0);
  for (double x : b.positions) a.positions.push_back(x);
  for (uint32_t i : b.faces) a.faces.push_back(i + 4);
  return a;
}

const char* kSquareObj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

}  // namespace

// ---- reading ------------------------------------------------------------------------------------

TEST(ReadObj, PlainTriangles) {
  TriangleMesh m = readObj(std::string(kSquareObj) + "f 1 2 3\nf 1 3 4\n");
  ASSERT_EQ(m.vertexCount(), 4u);
  ASSERT_EQ(m.faceCount(), 2u);
  EXPECT_EQ(m.faces, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
  EXPECT_EQ(m.positions, (std::vector<double>{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}));
}

TEST(ReadObj, SlashForms) {
  const std::vector<uint32_t> expected{0, 1, 2, 0, 2, 3};
  for (const char* faces : {"f 1/1/1 2/2/2 3/3/3\nf 1/1/1 3/3/3 4/4/4\n", "f 1//1 2//2 3//3\nf 1//1 3//3 4//4\n",
                            "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n", "f 1/7/9 2//4 3\nf 1 3/2 4/5/6\n"}) {
    TriangleMesh m = readObj(std::string(kSquareObj) + "vt 0 0\nvt 1 0\nvn 0 0 1\n" + faces);
    EXPECT_EQ(m.faces, expected) << faces;
  }
}

TEST(ReadObj, NegativeIndicesAreRelativeToVerticesSoFar) {
  // -1 is the last vertex read before the face line.
  TriangleMesh m = readObj("v 0 0 0\nv 1 0 0\nv 1 1 0\nf -3 -2 -1\nv 0 1 0\nf -4/-1/-1 -2//-1 -1\nf -1 1 -2\n");
  ASSERT_EQ(m.faceCount(), 3u);
  EXPECT_EQ(m.faces, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3, 3, 0, 2}));
}

TEST(ReadObj, CommentsBlankLinesAndOtherStatementsAreSkipped) {
  const std::string text =
      "# a comment\n"
      "mtllib x.mtl\n"
      "o square\n"
      "g group one\n"
      "s 1\n"
      "\n"
      "   \t\n"
      "v 0 0 0 # trailing comment\n"
      "v 1 0 0\n"
      "vn 0 0 1\n"
      "vt 0.5 0.5\n"
      "v 1 1 0\n"
      "usemtl red\n"
      "v 0 1 0\n"
      "#f 9 9 9\n"
      "f 1 2 3 # first\n"
      "l 1 2\n"
      "f 1 3 4\n";
  TriangleMesh m = readObj(text);
  EXPECT_EQ(m.vertexCount(), 4u);
  EXPECT_EQ(m.faces, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
}

TEST(ReadObj, CrLfLineEndingsAndTabs) {
  TriangleMesh m = readObj("v 0 0 0\r\nv\t1 0 0\r\nv 1 1 0\r\nv 0 1 0\r\nf 1 2 3\r\nf\t1\t3\t4\r\n");
  EXPECT_EQ(m.faces, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
  EXPECT_EQ(m.positions[3], 1.0);
  // No newline at the end of the file.
  TriangleMesh n = readObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3");
  EXPECT_EQ(n.faceCount(), 1u);
}

TEST(ReadObj, FourthCoordinateWAndColoursAreIgnored) {
  TriangleMesh m = readObj("v 0 0 0 1\nv 1 0 0 0.5\nv 0 1 0 1 0.2 0.3\nf 1 2 3\n");
  EXPECT_EQ(m.positions, (std::vector<double>{0, 0, 0, 1, 0, 0, 0, 1, 0}));
}

TEST(ReadObj, NumberFormats) {
  TriangleMesh m = readObj("v 1e-3 -2.5E+2 +0.125\nv .5 -0 1.\nv 0.25 7 3\nf 1 2 3\n");
  EXPECT_EQ(m.positions[0], 1e-3);
  EXPECT_EQ(m.positions[1], -250.0);
  EXPECT_EQ(m.positions[2], 0.125);
  EXPECT_EQ(m.positions[3], 0.5);
  EXPECT_EQ(m.positions[5], 1.0);
}

// Polygons, attributes and their hostile variants: test_obj.cpp.

// ---- writing and the round trip -----------------------------------------------------------------

TEST(WriteObj, Format) {
  TriangleMesh m;
  m.positions = {0.1, -2, 3e-20, 1, 0, 0, 0, 1, 0};
  m.faces = {0, 1, 2};
  // the shortest spelling that reads back as the same double
  EXPECT_EQ(writeObj(m), "v 0.1 -2 3e-20\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  m.positions = {0.1 + 0.2, -0.0, 1e300, 5e-324, 123456789012345680, 1.0 / 3, 0, 1, 0};
  m.faces = {0, 1, 2, 4294967294u, 9, 10};
  EXPECT_EQ(writeObj(m), "v 0.30000000000000004 -0 1e+300\nv 5e-324 1.2345678901234568e+17 0.3333333333333333\nv 0 1 0\n"
                         "f 1 2 3\nf 4294967295 10 11\n");
}

TEST(WriteObj, RoundTripKeepsVertexOrderAndExactCoordinates) {
  for (const auto& fx : fixtures::baseFixtures()) {
    TriangleMesh m = fx.base;
    // Awkward coordinates: thirds, random digits, tiny, huge, subnormal, negative zero.
    auto r = fixtures::randomVector(m.positions.size(), 17, 1e3);
    for (size_t i = 0; i < m.positions.size(); ++i) m.positions[i] = m.positions[i] / 3.0 + r[i] * 1e-7;
    m.positions[0] = 1e-300;
    m.positions[1] = 1e100;
    m.positions[2] = std::numeric_limits<double>::denorm_min();
    m.positions[3] = -0.0;
    m.positions[4] = std::nextafter(1.0, 2.0);
    m.positions[5] = -std::numeric_limits<double>::min();
    TriangleMesh back = readObj(writeObj(m));
    ASSERT_EQ(back.positions.size(), m.positions.size()) << fx.name;
    for (size_t i = 0; i < m.positions.size(); ++i)
      ASSERT_EQ(back.positions[i], m.positions[i]) << fx.name << " coordinate " << i;
    EXPECT_TRUE(std::signbit(back.positions[3]));
    EXPECT_EQ(back.faces, m.faces) << fx.name;
    EXPECT_EQ(writeObj(back), writeObj(m)) << fx.name;
  }
}

// ---- validation: topology -----------------------------------------------------------------------

TEST(ValidateMesh, IcosahedronIsClosedGenus0) {
  MeshTopology t = validateMesh(fixtures::icosahedron());
  EXPECT_TRUE(t.closed);
  EXPECT_EQ(t.boundaryEdges, 0u);
  EXPECT_EQ(t.edges, 30u);
  EXPECT_EQ(t.components, 1u);
  EXPECT_EQ(t.genus, 0);
}

TEST(ValidateMesh, TetrahedronAndOctahedron) {
  MeshTopology t = validateMesh(fixtures::tetrahedron());
  EXPECT_TRUE(t.closed);
  EXPECT_EQ(t.edges, 6u);
  EXPECT_EQ(t.genus, 0);
  MeshTopology o = validateMesh(fixtures::octahedron());
  EXPECT_TRUE(o.closed);
  EXPECT_EQ(o.edges, 12u);
  EXPECT_EQ(o.genus, 0);
  EXPECT_EQ(validateMesh(unitTetrahedron()).genus, 0);
  EXPECT_TRUE(validateMesh(cube(2)).closed);
}

TEST(ValidateMesh, TorusIsGenus1) {
  MeshTopology t = validateMesh(fixtures::torus());
  EXPECT_TRUE(t.closed);
  EXPECT_EQ(t.boundaryEdges, 0u);
  EXPECT_EQ(t.edges, 72u);  // 6 x 4 quads, 3 edges per quad
  EXPECT_EQ(t.components, 1u);
  EXPECT_EQ(t.genus, 1);
  EXPECT_EQ(validateMesh(fixtures::torus(8, 5)).genus, 1);
}

TEST(ValidateMesh, OpenPatchHasItsBoundary) {
  MeshTopology t = validateMesh(fixtures::openPatch());
  EXPECT_FALSE(t.closed);
  EXPECT_EQ(t.boundaryEdges, 12u);  // the outer ring of 12 vertices
  EXPECT_EQ(t.components, 1u);
  EXPECT_EQ(t.genus, 0);
  // 6 inner spokes + 6 inner ring + 12 outer ring + 18 between the rings.
  EXPECT_EQ(t.edges, 42u);
}

TEST(ValidateMesh, SingleTriangleAndSquare) {
  TriangleMesh tri = readObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  MeshTopology t = validateMesh(tri);
  EXPECT_FALSE(t.closed);
  EXPECT_EQ(t.boundaryEdges, 3u);
  EXPECT_EQ(t.genus, 0);
  MeshTopology s = validateMesh(readObj(std::string(kSquareObj) + "f 1 2 3\nf 1 3 4\n"));
  EXPECT_EQ(s.boundaryEdges, 4u);
  EXPECT_EQ(s.edges, 5u);
}

TEST(ValidateMesh, TwoDisjointTetrahedraAreTwoComponents) {
  MeshTopology t = validateMesh(twoTetrahedra());
  EXPECT_TRUE(t.closed);
  EXPECT_EQ(t.components, 2u);
  EXPECT_EQ(t.edges, 12u);
  EXPECT_EQ(t.genus, 0);
}

TEST(ValidateMesh, FlippedFaceIsInconsistentOrientation) {
  TriangleMesh m = fixtures::icosahedron();
  std::swap(m.faces[4], m.faces[5]);
  try {
    validateMesh(m);
    FAIL() << "a flipped face was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("orientation"), std::string::npos) << e.what();
  }
  // Flipping every face is consistent again.
  EXPECT_TRUE(validateMesh(flipped(fixtures::icosahedron())).closed);
}

// ---- volume ------------------------------------------------------------------------------------

TEST(MeshVolume, UnitTetrahedron) { EXPECT_NEAR(meshVolume(unitTetrahedron()), 1.0 / 6.0, 1e-15); }

TEST(MeshVolume, CubeIsSideCubed) {
  for (double s : {1.0, 2.0, 0.3, 7.5}) EXPECT_NEAR(meshVolume(cube(s, -1, 2, 0.5)), s * s * s, 1e-12 * s * s * s) << s;
}

TEST(MeshVolume, RegularSolids) {
  // Tetrahedron with vertices (+-1, +-1, +-1), even sign count: volume 8/3. The fixture's faces are
  // clockwise seen from outside, so its signed volume is negative.
  EXPECT_NEAR(meshVolume(fixtures::tetrahedron()), -8.0 / 3.0, 1e-14);
  EXPECT_NEAR(meshVolume(flipped(fixtures::tetrahedron())), 8.0 / 3.0, 1e-14);
  // Octahedron |x| + |y| + |z| <= 1: volume 4/3.
  EXPECT_NEAR(meshVolume(fixtures::octahedron()), 4.0 / 3.0, 1e-14);
  // Icosahedron of edge 2: 5/12 (3 + sqrt5) a^3.
  EXPECT_NEAR(meshVolume(fixtures::icosahedron()), 5.0 / 12.0 * (3 + std::sqrt(5.0)) * 8, 1e-12);
}

TEST(MeshVolume, InvariantUnderLargeTranslationForClosedMeshes) {
  std::vector<TriangleMesh> meshes{unitTetrahedron(), cube(1.7), fixtures::icosahedron(), fixtures::torus(),
                                   fixtures::octahedron(), twoTetrahedra(), fixtures::tetrahedron()};
  for (size_t i = 0; i < meshes.size(); ++i) {
    double v = meshVolume(meshes[i]);
    ASSERT_GT(std::fabs(v), 0.1) << i;
    for (auto d : {std::vector<double>{1e6, 0, 0}, {0, -1e6, 0}, {1e6, 1e6, 1e6}, {-3e6, 2e6, 1e6}}) {
      double w = meshVolume(translated(meshes[i], d[0], d[1], d[2]));
      EXPECT_NEAR(w, v, 1e-9 * std::fabs(v)) << "mesh " << i << " moved by " << d[0] << " " << d[1] << " " << d[2];
    }
  }
}

TEST(MeshVolume, SignFlipsWithOrientation) {
  for (const TriangleMesh& m : {unitTetrahedron(), cube(2), fixtures::icosahedron(), fixtures::torus()}) {
    double v = meshVolume(m);
    EXPECT_GT(v, 0);
    EXPECT_NEAR(meshVolume(flipped(m)), -v, 1e-14 * std::fabs(v));
  }
}

TEST(MeshVolume, TorusApproachesItsAnalyticVolumeFromBelow) {
  // Inscribed polyhedra: below 2 pi^2 R r^2, and close to it for a fine tessellation.
  const double exact = 2 * M_PI * M_PI * 2.0 * 0.7 * 0.7;
  double coarse = meshVolume(fixtures::torus()), fine = meshVolume(fixtures::torus(200, 100));
  EXPECT_LT(coarse, fine);
  EXPECT_LT(fine, exact);
  EXPECT_NEAR(fine, exact, 2e-3 * exact);
}

TEST(MeshVolume, OpenMeshUsesTheBoundaryCentroid) {
  // A flat patch: every cone to a point of its plane has zero volume.
  TriangleMesh square = readObj(std::string(kSquareObj) + "f 1 2 3\nf 1 3 4\n");
  EXPECT_NEAR(meshVolume(square), 0.0, 1e-15);
  Vec3 o = volumeReferencePoint(square);
  EXPECT_DOUBLE_EQ(o.x, 0.5);
  EXPECT_DOUBLE_EQ(o.y, 0.5);
  EXPECT_DOUBLE_EQ(o.z, 0.0);
  // The unit tetrahedron without its face on z = 0... the cone to the centroid of the boundary
  // (the three base vertices) closes it: volume 1/6 still.
  TriangleMesh open = unitTetrahedron();
  open.faces.erase(open.faces.begin(), open.faces.begin() + 3);
  EXPECT_NEAR(meshVolume(open), 1.0 / 6.0, 1e-15);
  // Translation invariance holds for open meshes too (the reference point moves with the mesh).
  EXPECT_NEAR(meshVolume(translated(open, 1e6, -1e6, 5e5)), 1.0 / 6.0, 1e-9 / 6);
}
