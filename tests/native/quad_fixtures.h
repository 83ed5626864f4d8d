// Quad-mesh fixtures and an independent, textbook Catmull-Clark subdivision for the quad tests.
#pragma once
#include <array>
#include <cmath>
#include <map>
#include <random>
#include <vector>

#include "mrvol/quad_hierarchy.h"

namespace quadfix {

struct PolyMesh {
  std::vector<std::array<double, 3>> p;
  std::vector<std::vector<uint32_t>> faces;  // counter-clockwise
};

// One step of Catmull-Clark subdivision as in Catmull and Clark (1978): face point = centroid;
// edge point = mean of the ends and the two face points (boundary: midpoint); vertex
// (Q + 2R + (n - 3) S) / n (boundary: (w0 + 6 v + w1) / 8). New vertices: old ones (same
// index), then face points (face order), then edge points (keyed by their ends).
struct CCResult {
  PolyMesh mesh;
  std::vector<uint32_t> facePoint;
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> edgePoint;
};

inline std::pair<uint32_t, uint32_t> key(uint32_t a, uint32_t b) { return a < b ? std::make_pair(a, b) : std::make_pair(b, a); }

inline CCResult textbookCatmullClark(const PolyMesh& m) {
  using P = std::array<double, 3>;
  auto add = [](P& a, const P& b, double w) { for (int k = 0; k < 3; ++k) a[k] += w * b[k]; };
  CCResult r;
  const size_t V = m.p.size();
  std::vector<P> fp(m.faces.size(), P{0, 0, 0});
  for (size_t f = 0; f < m.faces.size(); ++f)
    for (uint32_t v : m.faces[f]) add(fp[f], m.p[v], 1.0 / m.faces[f].size());
  std::map<std::pair<uint32_t, uint32_t>, std::vector<size_t>> edgeFaces;
  for (size_t f = 0; f < m.faces.size(); ++f)
    for (size_t i = 0; i < m.faces[f].size(); ++i)
      edgeFaces[key(m.faces[f][i], m.faces[f][(i + 1) % m.faces[f].size()])].push_back(f);
  std::vector<P> out(m.p);
  for (size_t f = 0; f < m.faces.size(); ++f) r.facePoint.push_back(uint32_t(out.size())), out.push_back(fp[f]);
  std::vector<std::vector<uint32_t>> neighbours(V), facesOf(V);
  std::vector<int> boundary(V, 0);
  for (auto& [e, fs] : edgeFaces) {
    P ep{0, 0, 0};
    if (fs.size() == 1) {
      add(ep, m.p[e.first], 0.5), add(ep, m.p[e.second], 0.5);
      boundary[e.first] = boundary[e.second] = 1;
    } else {
      add(ep, m.p[e.first], 0.25), add(ep, m.p[e.second], 0.25), add(ep, fp[fs[0]], 0.25), add(ep, fp[fs[1]], 0.25);
    }
    r.edgePoint[e] = uint32_t(out.size());
    out.push_back(ep);
    neighbours[e.first].push_back(e.second), neighbours[e.second].push_back(e.first);
  }
  for (size_t f = 0; f < m.faces.size(); ++f)
    for (uint32_t v : m.faces[f]) facesOf[v].push_back(uint32_t(f));
  for (uint32_t v = 0; v < V; ++v) {
    P np{0, 0, 0};
    if (boundary[v]) {
      add(np, m.p[v], 0.75);
      for (uint32_t w : neighbours[v])
        if (edgeFaces[key(v, w)].size() == 1) add(np, m.p[w], 0.125);
    } else {
      const double n = double(neighbours[v].size());
      P Q{0, 0, 0}, R{0, 0, 0};
      for (uint32_t f : facesOf[v]) add(Q, fp[f], 1.0 / facesOf[v].size());
      for (uint32_t w : neighbours[v]) add(R, m.p[v], 0.5 / n), add(R, m.p[w], 0.5 / n);
      add(np, Q, 1.0 / n), add(np, R, 2.0 / n), add(np, m.p[v], (n - 3.0) / n);
    }
    out[v] = np;
  }
  r.mesh.p = out;
  for (size_t f = 0; f < m.faces.size(); ++f) {
    const auto& F = m.faces[f];
    const size_t k = F.size();
    for (size_t i = 0; i < k; ++i) {
      uint32_t v = F[i], next = F[(i + 1) % k], prev = F[(i + k - 1) % k];
      r.mesh.faces.push_back({v, r.edgePoint[key(v, next)], r.facePoint[f], r.edgePoint[key(prev, v)]});
    }
  }
  return r;
}

inline mrvol::QuadMesh toQuadMesh(const PolyMesh& m) {
  mrvol::QuadMesh q;
  for (auto& p : m.p) q.positions.insert(q.positions.end(), p.begin(), p.end());
  for (auto& f : m.faces) q.quads.insert(q.quads.end(), f.begin(), f.end());
  return q;
}

inline PolyMesh fromQuadMesh(const mrvol::QuadMesh& q) {
  PolyMesh m;
  for (size_t i = 0; i < q.positions.size(); i += 3) m.p.push_back({q.positions[i], q.positions[i + 1], q.positions[i + 2]});
  for (size_t f = 0; f < q.quads.size(); f += 4) m.faces.push_back({q.quads[f], q.quads[f + 1], q.quads[f + 2], q.quads[f + 3]});
  return m;
}

inline void jitter(PolyMesh& m, double amount, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-amount, amount);
  for (auto& p : m.p)
    for (double& c : p) c += u(rng);
}

inline PolyMesh cube() {  // [-1, 1]^3, valence 3 everywhere
  PolyMesh m;
  for (int i = 0; i < 8; ++i) m.p.push_back({i & 1 ? 1.0 : -1.0, i & 2 ? 1.0 : -1.0, i & 4 ? 1.0 : -1.0});
  m.faces = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  return m;
}

inline PolyMesh quadTorus(int u = 6, int v = 4, double R = 2.0, double r = 0.7) {
  PolyMesh m;
  for (int i = 0; i < u; ++i)
    for (int j = 0; j < v; ++j) {
      double a = 2 * M_PI * i / u, b = 2 * M_PI * j / v;
      m.p.push_back({(R + r * std::cos(b)) * std::cos(a), (R + r * std::cos(b)) * std::sin(a), r * std::sin(b)});
    }
  auto id = [&](int i, int j) { return uint32_t(((i + u) % u) * v + (j + v) % v); };
  for (int i = 0; i < u; ++i)
    for (int j = 0; j < v; ++j) m.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  return m;
}

// A bipyramid over a k-gon (triangles): apex valence k.
inline PolyMesh bipyramid(int k) {
  PolyMesh m;
  for (int i = 0; i < k; ++i) m.p.push_back({std::cos(2 * M_PI * i / k), std::sin(2 * M_PI * i / k), 0});
  m.p.push_back({0, 0, 1.3});
  m.p.push_back({0, 0, -1.1});
  const uint32_t top = k, bottom = k + 1;
  for (int i = 0; i < k; ++i) {
    uint32_t a = i, b = (i + 1) % k;
    m.faces.push_back({a, b, top});
    m.faces.push_back({b, a, bottom});
  }
  return m;
}

// A pyramid over a k-gon: apex valence k, base face a k-gon.
inline PolyMesh pyramid(int k) {
  PolyMesh m;
  for (int i = 0; i < k; ++i) m.p.push_back({std::cos(2 * M_PI * i / k), std::sin(2 * M_PI * i / k), 0});
  m.p.push_back({0, 0, 1.5});
  std::vector<uint32_t> base;
  for (int i = k - 1; i >= 0; --i) base.push_back(uint32_t(i));
  m.faces.push_back(base);
  for (int i = 0; i < k; ++i) m.faces.push_back({uint32_t(i), uint32_t((i + 1) % k), uint32_t(k)});
  return m;
}

// An open grid of w x h quads (boundary, corners of valence 2).
inline PolyMesh grid(int w, int h) {
  PolyMesh m;
  for (int j = 0; j <= h; ++j)
    for (int i = 0; i <= w; ++i) m.p.push_back({double(i), double(j), 0.1 * std::sin(i + 2.0 * j)});
  auto id = [&](int i, int j) { return uint32_t(j * (w + 1) + i); };
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) m.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  return m;
}

// The cube without its top: an open box whose bottom corners are interior vertices of valence 3.
inline PolyMesh openBox() {
  PolyMesh m = cube();
  m.faces.erase(m.faces.begin() + 1);  // the z = +1 face
  return m;
}

}  // namespace quadfix
