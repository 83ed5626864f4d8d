// Fixture models for the native tests: small base meshes of every kind the core must handle
// (closed genus 0 with valences 3..6, genus 1, open), and the sample files in public/models.
#pragma once
#include <algorithm>
#include <cmath>
#include <fstream>
#include <numeric>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "mrvol/lifting.h"
#include "mrvol/mesh.h"

namespace fixtures {

using mrvol::TriangleMesh;

inline TriangleMesh icosahedron() {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  TriangleMesh m;
  m.positions = {-1, t, 0, 1, t, 0, -1, -t, 0, 1, -t, 0, 0, -1, t, 0, 1, t,
                 0, -1, -t, 0, 1, -t, t, 0, -1, t, 0, 1, -t, 0, -1, -t, 0, 1};
  m.faces = {0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4, 11, 10, 2, 10, 7, 6, 7, 1, 8,
             3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8, 3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8, 1};
  return m;
}

inline TriangleMesh tetrahedron() {  // valence 3 everywhere
  TriangleMesh m;
  m.positions = {1, 1, 1, -1, -1, 1, -1, 1, -1, 1, -1, -1};
  m.faces = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};
  return m;
}

inline TriangleMesh octahedron() {  // valence 4
  TriangleMesh m;
  m.positions = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
  m.faces = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
  return m;
}

// A torus of u x v quads split into triangles: genus 1, all valence 6.
inline TriangleMesh torus(int u = 6, int v = 4, double R = 2.0, double r = 0.7) {
  TriangleMesh m;
  for (int i = 0; i < u; ++i)
    for (int j = 0; j < v; ++j) {
      double a = 2 * M_PI * i / u, b = 2 * M_PI * j / v;
      m.positions.insert(m.positions.end(), {(R + r * std::cos(b)) * std::cos(a), (R + r * std::cos(b)) * std::sin(a), r * std::sin(b)});
    }
  auto id = [&](int i, int j) { return uint32_t(((i + u) % u) * v + (j + v) % v); };
  for (int i = 0; i < u; ++i)
    for (int j = 0; j < v; ++j) {
      uint32_t a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      m.faces.insert(m.faces.end(), {a, b, c, a, c, d});
    }
  return m;
}

// An open patch: a hexagon fan around a centre plus an outer ring (boundary of 12 vertices).
inline TriangleMesh openPatch() {
  TriangleMesh m;
  m.positions = {0, 0, 0.3};
  for (int k = 0; k < 6; ++k) m.positions.insert(m.positions.end(), {std::cos(k * M_PI / 3), std::sin(k * M_PI / 3), 0.1 * k});
  for (int k = 0; k < 12; ++k) m.positions.insert(m.positions.end(), {2 * std::cos(k * M_PI / 6), 2 * std::sin(k * M_PI / 6), -0.05 * k});
  for (uint32_t k = 0; k < 6; ++k) m.faces.insert(m.faces.end(), {0, 1 + k, 1 + (k + 1) % 6});
  for (uint32_t k = 0; k < 6; ++k) {
    uint32_t in0 = 1 + k, in1 = 1 + (k + 1) % 6;
    uint32_t o0 = 7 + 2 * k, o1 = 7 + 2 * k + 1, o2 = 7 + (2 * k + 2) % 12;
    m.faces.insert(m.faces.end(), {in0, o0, o1, in0, o1, in1, in1, o1, o2});
  }
  return m;
}

struct Fixture {
  std::string name;
  TriangleMesh base;
  int levels;
};

inline std::vector<Fixture> baseFixtures() {
  return {{"icosahedron", icosahedron(), 3}, {"tetrahedron", tetrahedron(), 3}, {"octahedron", octahedron(), 3},
          {"torus", torus(), 2}, {"open-patch", openPatch(), 2}};
}

// Every scheme the tests run over: Loop (stabilized and plain), Butterfly, linear.
inline std::vector<mrvol::SchemeOptions> allSchemes() {
  mrvol::SchemeOptions loop, plain, butterfly, linear;
  plain.alpha = plain.beta = 0;
  butterfly.kind = mrvol::SchemeKind::Butterfly;
  linear.kind = mrvol::SchemeKind::Linear;
  return {loop, plain, butterfly, linear};
}

inline std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

#ifdef MRVOL_SOURCE_DIR  // the test build defines it; the fuzz targets use the meshes only
inline std::string sourcePath(const std::string& relative) { return std::string(MRVOL_SOURCE_DIR) + "/" + relative; }
#endif

// Random positions scaled like the fixtures; seeded.
inline std::vector<double> randomVector(size_t n, unsigned seed, double scale = 1.0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-scale, scale);
  std::vector<double> x(n);
  for (auto& v : x) v = u(rng);
  return x;
}

inline double maxAbs(const std::vector<double>& v) {
  double m = 0;
  for (double x : v) m = std::max(m, std::fabs(x));
  return m;
}

inline double maxDiff(const std::vector<double>& a, const std::vector<double>& b) {
  double m = 0;
  for (size_t i = 0; i < a.size(); ++i) m = std::max(m, std::fabs(a[i] - b[i]));
  return m;
}

// A scheme's name for messages: "loop (plain)" for Loop without the update weights.
inline std::string label(const mrvol::SchemeOptions& o) {
  return std::string(mrvol::schemeName(o.kind)) + (o.kind == mrvol::SchemeKind::Loop && o.alpha == 0 ? " (plain)" : "");
}

// A mesh in hierarchy order rewritten with a random vertex order; faces shuffled and rotated too
// (orientation kept). perm[v] = the new index of hierarchy vertex v.
struct Shuffled {
  TriangleMesh mesh;
  std::vector<uint32_t> perm;
};

inline Shuffled shuffle(const TriangleMesh& m, unsigned seed) {
  std::mt19937 rng(seed);
  Shuffled s;
  const size_t nv = m.vertexCount(), nf = m.faceCount();
  s.perm.resize(nv);
  std::iota(s.perm.begin(), s.perm.end(), 0u);
  std::shuffle(s.perm.begin(), s.perm.end(), rng);
  s.mesh.positions.resize(m.positions.size());
  for (size_t v = 0; v < nv; ++v)
    for (int k = 0; k < 3; ++k) s.mesh.positions[3 * s.perm[v] + k] = m.positions[3 * v + k];
  std::vector<size_t> order(nf);
  std::iota(order.begin(), order.end(), size_t(0));
  std::shuffle(order.begin(), order.end(), rng);
  for (size_t f : order) {
    int r = int(rng() % 3);
    for (int k = 0; k < 3; ++k) s.mesh.faces.push_back(s.perm[m.faces[3 * f + (k + r) % 3]]);
  }
  return s;
}

}  // namespace fixtures
