#include "mrvol/limit_volume.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>

#include "mrvol/corners.h"
#include "mrvol/error.h"

namespace mrvol {

namespace {

using SparseRow = std::vector<std::pair<uint32_t, double>>;

// Loop's even weight (method section 2): beta_n = (5/8 - eta^2) / n, eta = 3/8 + cos(2 pi / n) / 4.
double loopBeta(int n) {
  const double eta = 3.0 / 8.0 + std::cos(2.0 * M_PI / n) / 4.0;
  return (5.0 / 8.0 - eta * eta) / n;
}

// One Loop subdivision of a triangle mesh (possibly open: the model patches are discs) as rows of
// the subdivision matrix. Even vertices keep their index, the odd vertex of edge e is V + e.
// Face f gives children 4f .. 4f+3: (a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca).
// tainted: vertices whose rule reads outside the mesh (boundary) or a tainted vertex.
struct Subdivision {
  size_t vertexCount = 0;
  std::vector<uint32_t> faces;
  std::vector<SparseRow> rows;
  std::vector<uint8_t> tainted;
};

Subdivision loopSubdivide(const std::vector<uint32_t>& faces, size_t vertexCount, const std::vector<uint8_t>& tainted) {
  const VertexCorners corners(faces.data(), faces.size() / 3, vertexCount);
  std::unordered_map<uint64_t, uint32_t> edgeIndex;
  std::vector<std::pair<uint32_t, uint32_t>> edges;
  auto edgeOf = [&](uint32_t u, uint32_t v) {
    const uint64_t key = (uint64_t(std::min(u, v)) << 32) | std::max(u, v);
    auto [it, added] = edgeIndex.emplace(key, uint32_t(edges.size()));
    if (added) edges.emplace_back(u, v);
    return uint32_t(vertexCount) + it->second;
  };
  Subdivision s;
  s.faces.reserve(4 * faces.size());
  for (size_t f = 0; f < faces.size(); f += 3) {
    const uint32_t a = faces[f], b = faces[f + 1], c = faces[f + 2];
    const uint32_t ab = edgeOf(a, b), bc = edgeOf(b, c), ca = edgeOf(c, a);
    for (uint32_t v : {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca}) s.faces.push_back(v);
  }
  s.vertexCount = vertexCount + edges.size();
  s.rows.resize(s.vertexCount);
  s.tainted.assign(s.vertexCount, 0);
  std::vector<uint32_t> ring;
  for (uint32_t v = 0; v < vertexCount; ++v) {
    bool boundary = false;
    corners.ring(v, ring, &boundary);
    const int n = int(ring.size());
    bool bad = boundary || n < 3 || tainted[v];
    if (n >= 3) {
      const double beta = loopBeta(n);
      s.rows[v].emplace_back(v, 1.0 - n * beta);
      for (uint32_t r : ring) s.rows[v].emplace_back(r, beta), bad = bad || tainted[r];
    }
    s.tainted[v] = bad;
  }
  for (size_t e = 0; e < edges.size(); ++e) {
    const auto [u, v] = edges[e];
    const uint32_t wing1 = corners.opposite(u, v), wing2 = corners.opposite(v, u);
    SparseRow& row = s.rows[vertexCount + e];
    row = {{u, 3.0 / 8.0}, {v, 3.0 / 8.0}};
    bool bad = tainted[u] || tainted[v] || wing1 == kNone || wing2 == kNone;
    if (wing1 != kNone) row.emplace_back(wing1, 1.0 / 8.0), bad = bad || tainted[wing1];
    if (wing2 != kNone) row.emplace_back(wing2, 1.0 / 8.0), bad = bad || tainted[wing2];
    s.tainted[vertexCount + e] = bad;
  }
  return s;
}

// Dense alternating 3-form on K slots, stored as the full antisymmetric K^3 array F with
// V(P) = (1/6) sum_{abc} F_abc det(P_a, P_b, P_c) = sum_{a<b<c} F_abc det(P_a, P_b, P_c).
struct DenseForm {
  int K = 0;
  std::vector<double> F;
  explicit DenseForm(int k = 0) : K(k), F(size_t(k) * k * k, 0.0) {}
  double& at(int a, int b, int c) { return F[(size_t(a) * K + b) * K + c]; }
  double at(int a, int b, int c) const { return F[(size_t(a) * K + b) * K + c]; }
  DenseForm& operator+=(const DenseForm& o) {
    for (size_t i = 0; i < F.size(); ++i) F[i] += o.F[i];
    return *this;
  }
};

using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// The form X o B: (X o B)(P) = X(B P), with B mapping K0 old slots to X.K new slots (rows new).
// Three mode products, skipping the zeros of B.
DenseForm pullback(const DenseForm& X, const Matrix& B) {
  const int K1 = X.K, K0 = int(B.cols());
  std::vector<double> t1(size_t(K0) * K1 * K1, 0.0), t2(size_t(K0) * K0 * K1, 0.0);
  for (int a = 0; a < K1; ++a)
    for (int p = 0; p < K0; ++p) {
      const double w = B(a, p);
      if (w == 0.0) continue;
      const double* src = &X.F[size_t(a) * K1 * K1];
      double* dst = &t1[size_t(p) * K1 * K1];
      for (int bc = 0; bc < K1 * K1; ++bc) dst[bc] += w * src[bc];
    }
  for (int p = 0; p < K0; ++p)
    for (int b = 0; b < K1; ++b)
      for (int q = 0; q < K0; ++q) {
        const double w = B(b, q);
        if (w == 0.0) continue;
        const double* src = &t1[(size_t(p) * K1 + b) * K1];
        double* dst = &t2[(size_t(p) * K0 + q) * K1];
        for (int c = 0; c < K1; ++c) dst[c] += w * src[c];
      }
  DenseForm G(K0);
  for (size_t pq = 0; pq < size_t(K0) * K0; ++pq)
    for (int c = 0; c < K1; ++c) {
      const double v = t2[pq * K1 + c];
      if (v == 0.0) continue;
      double* dst = &G.F[pq * K0];
      for (int r = 0; r < K0; ++r) dst[r] += v * B(c, r);
    }
  return G;
}

double maxAbs(const DenseForm& X) {
  double m = 0;
  for (double v : X.F) m = std::max(m, std::abs(v));
  return m;
}

FineForm entriesOf(const DenseForm& X) {
  FineForm out;
  for (int a = 0; a < X.K; ++a)
    for (int b = a + 1; b < X.K; ++b)
      for (int c = b + 1; c < X.K; ++c)
        if (X.at(a, b, c) != 0.0) {
          out.corners.insert(out.corners.end(), {uint32_t(a), uint32_t(b), uint32_t(c)});
          out.weights.push_back(X.at(a, b, c));
        }
  return out;
}

// A cone of n sectors of the regular triangle lattice glued around a centre of valence n, `rings`
// lattice rings deep: vertex (i, j) of sector s (i + j <= rings) sits at i u_s + j u_{s+1}, with
// u_s the unit vector at angle 60 s degrees (a true plane for n = 6); (0, j) of sector s is
// (j, 0) of sector s + 1. Face f0 = (centre, (1,0)_0, (0,1)_0) is the face studied.
struct ConeModel {
  int valence = 0;
  std::vector<uint32_t> faces;
  std::vector<std::array<double, 2>> planar;  // meaningful for n = 6 only
  uint32_t centre = 0, p = 0, q = 0;
  size_t vertexCount() const { return planar.size(); }
};

ConeModel coneModel(int n, int rings) {
  ConeModel m;
  m.valence = n;
  // ids[s][i][j] for i >= 1 (i = 0 is the next sector's i-axis) and the centre.
  std::vector<std::vector<std::vector<uint32_t>>> ids(n, std::vector<std::vector<uint32_t>>(rings + 1, std::vector<uint32_t>(rings + 1, kNone)));
  m.planar.push_back({0.0, 0.0});
  auto dir = [](int s) { return std::array<double, 2>{std::cos(M_PI * s / 3.0), std::sin(M_PI * s / 3.0)}; };
  for (int s = 0; s < n; ++s)
    for (int i = 1; i <= rings; ++i)
      for (int j = 0; i + j <= rings; ++j) {
        ids[s][i][j] = uint32_t(m.planar.size());
        const auto u = dir(s), w = dir(s + 1);
        m.planar.push_back({i * u[0] + j * w[0], i * u[1] + j * w[1]});
      }
  auto id = [&](int s, int i, int j) -> uint32_t {
    if (i == 0 && j == 0) return 0;
    if (i == 0) return ids[(s + 1) % n][j][0];
    return ids[s][i][j];
  };
  for (int s = 0; s < n; ++s)
    for (int i = 0; i < rings; ++i)
      for (int j = 0; i + j < rings; ++j) {
        m.faces.insert(m.faces.end(), {id(s, i, j), id(s, i + 1, j), id(s, i, j + 1)});
        if (i + j + 2 <= rings) m.faces.insert(m.faces.end(), {id(s, i + 1, j), id(s, i + 1, j + 1), id(s, i, j + 1)});
      }
  m.centre = 0;
  m.p = id(0, 1, 0);
  m.q = id(0, 0, 1);
  return m;
}

// Rows of a subdivision restricted to a net's slots: B(r, s) = weight of old net vertex s in new
// net vertex r. Throws if a row reads outside the old net or a tainted vertex (a model too small).
Matrix restrictRows(const Subdivision& sub, const std::vector<uint32_t>& newNet, const std::vector<uint32_t>& oldNet) {
  std::unordered_map<uint32_t, int> slot;
  for (size_t s = 0; s < oldNet.size(); ++s) slot.emplace(oldNet[s], int(s));
  Matrix B = Matrix::Zero(Eigen::Index(newNet.size()), Eigen::Index(oldNet.size()));
  for (size_t r = 0; r < newNet.size(); ++r) {
    if (sub.tainted[newNet[r]]) throw Error("internal: limit-volume model patch too small");
    for (auto [v, w] : sub.rows[newNet[r]]) {
      auto it = slot.find(v);
      if (it == slot.end()) throw Error("internal: a child net reads outside its parent net");
      B(Eigen::Index(r), it->second) += w;
    }
  }
  return B;
}

// The regular face: the limit patch of a face whose corners have valence 6 is a quartic
// polynomial p(u, w) over the face (u along a -> b, w along a -> c). It is fixed by its values at
// the 15 points (i/4, j/4), which are vertices after two subdivisions, where the limit position
// is Loop's regular limit mask (1/2 the vertex, 1/12 each neighbour). Then
// V_face = 1/3 integral det(p, p_u, p_w) du dw, integrated exactly on monomials.
DenseForm regularPatch() {
  const ConeModel m = coneModel(6, 5);
  const VertexCorners corners0(m.faces.data(), m.faces.size() / 3, m.vertexCount());
  const std::vector<uint32_t> net = limit_detail::patchNet(corners0, m.centre, m.p, m.q);
  const std::vector<uint8_t> clean(m.vertexCount(), 0);
  const Subdivision s1 = loopSubdivide(m.faces, m.vertexCount(), clean);
  const Subdivision s2 = loopSubdivide(s1.faces, s1.vertexCount, s1.tainted);
  // Parameter positions: odd vertices at their edge midpoints (the children's lattice).
  auto refine = [](const std::vector<std::array<double, 2>>& xy, const Subdivision& s, size_t oldCount) {
    std::vector<std::array<double, 2>> out(s.vertexCount);
    for (size_t v = 0; v < s.vertexCount; ++v) {
      if (v < oldCount) { out[v] = xy[v]; continue; }
      const auto& row = s.rows[v];  // ends first (3/8 each)
      out[v] = {(xy[row[0].first][0] + xy[row[1].first][0]) / 2, (xy[row[0].first][1] + xy[row[1].first][1]) / 2};
    }
    return out;
  };
  const auto xy1 = refine(m.planar, s1, m.vertexCount());
  const auto xy2 = refine(xy1, s2, s1.vertexCount);
  const VertexCorners corners2(s2.faces.data(), s2.faces.size() / 3, s2.vertexCount);
  const auto P = m.planar[m.p], Q = m.planar[m.q];
  std::unordered_map<uint32_t, int> slot;
  for (size_t s = 0; s < net.size(); ++s) slot.emplace(net[s], int(s));

  constexpr int kPoints = 15;
  Matrix values = Matrix::Zero(kPoints, 12), vandermonde(kPoints, kPoints);
  std::vector<std::pair<int, int>> monomials;  // (power of u, power of w)
  for (int d = 0; d <= 4; ++d)
    for (int a = d; a >= 0; --a) monomials.emplace_back(a, d - a);
  std::vector<uint32_t> ring;
  int point = 0;
  for (int i = 0; i <= 4; ++i)
    for (int j = 0; i + j <= 4; ++j, ++point) {
      const double u = i / 4.0, w = j / 4.0;
      const double x = u * P[0] + w * Q[0], y = u * P[1] + w * Q[1];
      uint32_t v = kNone;
      for (uint32_t k = 0; k < s2.vertexCount; ++k)
        if (std::abs(xy2[k][0] - x) < 1e-9 && std::abs(xy2[k][1] - y) < 1e-9) v = k;
      if (v == kNone || s2.tainted[v]) throw Error("internal: regular patch lattice point missing");
      corners2.ring(v, ring);
      // limit mask -> level 2 -> level 1 -> level 0
      std::map<uint32_t, double> level2{{v, 0.5}}, level1, level0;
      for (uint32_t r : ring) level2[r] += 1.0 / 12.0;
      for (auto [x2, w2] : level2) {
        if (s2.tainted[x2]) throw Error("internal: regular patch model too small");
        for (auto [x1, w1] : s2.rows[x2]) level1[x1] += w2 * w1;
      }
      for (auto [x1, w1] : level1)
        for (auto [x0, w0] : s1.rows[x1]) level0[x0] += w1 * w0;
      for (auto [x0, w0] : level0) {
        if (std::abs(w0) < 1e-14) continue;  // sums that cancel exactly in rationals, to round-off
        auto it = slot.find(x0);
        if (it == slot.end()) throw Error("internal: regular limit point reads outside the 12-vertex net");
        values(point, it->second) += w0;
      }
      for (int k = 0; k < kPoints; ++k)
        vandermonde(point, k) = std::pow(u, monomials[k].first) * std::pow(w, monomials[k].second);
    }
  const Matrix coefficients = Eigen::FullPivLU<Matrix>(vandermonde).solve(values);  // 15 x 12

  // Basis polynomials and their derivatives as dense (power u, power w) arrays, degree <= 4.
  using Poly = std::array<std::array<double, 5>, 5>;
  std::vector<Poly> basis(12), du(12), dw(12);
  for (int b = 0; b < 12; ++b) {
    basis[b] = du[b] = dw[b] = Poly{};
    for (int k = 0; k < kPoints; ++k) {
      const auto [pu, pw] = monomials[k];
      const double c = coefficients(k, b);
      basis[b][pu][pw] += c;
      if (pu > 0) du[b][pu - 1][pw] += pu * c;
      if (pw > 0) dw[b][pu][pw - 1] += pw * c;
    }
  }
  // integral over the unit triangle of u^p w^q = p! q! / (p + q + 2)!
  double fact[16] = {1};
  for (int k = 1; k < 16; ++k) fact[k] = fact[k - 1] * k;
  auto integral = [&](int p, int q) { return fact[p] * fact[q] / fact[p + q + 2]; };
  // T_abc = 1/3 integral B_a (d_u B_b) (d_w B_c); F = its antisymmetrization.
  std::vector<double> T(12 * 12 * 12, 0.0);
  for (int a = 0; a < 12; ++a)
    for (int b = 0; b < 12; ++b) {
      double prod[8][8] = {};
      for (int i = 0; i <= 4; ++i)
        for (int j = 0; i + j <= 4; ++j)
          if (basis[a][i][j] != 0.0)
            for (int k = 0; k <= 3; ++k)
              for (int l = 0; k + l <= 3; ++l) prod[i + k][j + l] += basis[a][i][j] * du[b][k][l];
      for (int c = 0; c < 12; ++c) {
        double sum = 0;
        for (int i = 0; i < 8; ++i)
          for (int j = 0; i + j < 8; ++j)
            if (prod[i][j] != 0.0)
              for (int k = 0; k <= 3; ++k)
                for (int l = 0; k + l <= 3; ++l)
                  if (dw[c][k][l] != 0.0) sum += prod[i][j] * dw[c][k][l] * integral(i + k, j + l);
        T[(a * 12 + b) * 12 + c] = sum / 3.0;
      }
    }
  DenseForm X(12);
  auto t = [&](int a, int b, int c) { return T[(a * 12 + b) * 12 + c]; };
  for (int a = 0; a < 12; ++a)
    for (int b = 0; b < 12; ++b)
      for (int c = 0; c < 12; ++c)
        X.at(a, b, c) = t(a, b, c) + t(b, c, a) + t(c, a, b) - t(b, a, c) - t(a, c, b) - t(c, b, a);
  return X;
}

// A face whose first corner has valence n (the others regular): one local subdivision splits it
// into three regular children and a corner child of the same kind, whose net is A times the
// parent's: X = Q + X o A with Q the three regular children's forms pulled back. The series
// X = sum_k Q o A^k converges like lambda^2 (lambda the subdominant eigenvalue of A; products of
// three distinct eigenvalues of A are at most 1 * lambda * lambda), summed by repeated squaring.
struct ExtraordinaryPatch {
  DenseForm X;
  double residual = 0;
};

ExtraordinaryPatch extraordinaryPatch(int n, const DenseForm& regular) {
  const ConeModel m = coneModel(n, 4);
  const VertexCorners corners0(m.faces.data(), m.faces.size() / 3, m.vertexCount());
  const std::vector<uint32_t> net0 = limit_detail::patchNet(corners0, m.centre, m.p, m.q);
  const Subdivision s1 = loopSubdivide(m.faces, m.vertexCount(), std::vector<uint8_t>(m.vertexCount(), 0));
  const VertexCorners corners1(s1.faces.data(), s1.faces.size() / 3, s1.vertexCount);
  // The children of f0 are faces 4 f0 .. 4 f0 + 3 of the subdivision.
  size_t f0 = m.faces.size();
  for (size_t f = 0; f < m.faces.size(); f += 3)
    if (m.faces[f] == m.centre && m.faces[f + 1] == m.p && m.faces[f + 2] == m.q) f0 = f / 3;
  if (f0 == m.faces.size()) throw Error("internal: limit-volume model has no face f0");
  const uint32_t* child = &s1.faces[12 * f0];
  const Matrix A = restrictRows(s1, limit_detail::patchNet(corners1, child[0], child[1], child[2]), net0);
  DenseForm Q(int(net0.size()));
  for (int c = 1; c < 4; ++c) {
    const uint32_t* t = child + 3 * c;
    Q += pullback(regular, restrictRows(s1, limit_detail::patchNet(corners1, t[0], t[1], t[2]), net0));
  }
  ExtraordinaryPatch out;
  DenseForm X = Q;
  Matrix power = A;
  for (int doubling = 0; doubling < 8; ++doubling) {  // 256 terms: lambda^512 < 1e-100
    X += pullback(X, power);
    power = power * power;
  }
  DenseForm check = Q;
  check += pullback(X, A);
  double diff = 0;
  for (size_t i = 0; i < X.F.size(); ++i) diff = std::max(diff, std::abs(check.F[i] - X.F[i]));
  out.residual = diff / maxAbs(X);
  out.X = std::move(X);
  return out;
}

struct PatchTables {
  std::mutex mutex;
  std::unique_ptr<DenseForm> regular;
  std::map<int, FineForm> forms;
  std::map<int, double> residuals;
};

PatchTables& tables() {
  static PatchTables t;
  return t;
}

const FineForm& patchFormLocked(PatchTables& t, int valence) {
  auto it = t.forms.find(valence);
  if (it != t.forms.end()) return it->second;
  if (!t.regular) t.regular = std::make_unique<DenseForm>(regularPatch());
  if (valence == 6) return t.forms[6] = entriesOf(*t.regular);
  ExtraordinaryPatch e = extraordinaryPatch(valence, *t.regular);
  t.residuals[valence] = e.residual;
  return t.forms[valence] = entriesOf(e.X);
}

// Key of a sorted triple (a < b < c), 21 bits each.
inline uint64_t packTriple(uint32_t a, uint32_t b, uint32_t c) { return (uint64_t(a) << 42) | (uint64_t(b) << 21) | c; }

inline double sortWithSign(uint32_t& a, uint32_t& b, uint32_t& c) {
  double s = 1;
  if (a > b) std::swap(a, b), s = -s;
  if (b > c) std::swap(b, c), s = -s;
  if (a > b) std::swap(a, b), s = -s;
  return s;
}

}  // namespace

namespace limit_detail {

std::vector<uint32_t> patchNet(const VertexCorners& corners, uint32_t a, uint32_t b, uint32_t c) {
  std::vector<uint32_t> net{a}, ring;
  corners.ringFrom(a, b, ring);
  net.insert(net.end(), ring.begin(), ring.end());
  corners.ringFrom(b, c, ring);  // c, a, ring_a[n-1], then three outer vertices
  if (ring.size() != 6) throw Error("internal: patch net corner b is not regular");
  net.insert(net.end(), ring.begin() + 3, ring.end());
  corners.ringFrom(c, a, ring);  // a, b, d (already in), then two outer vertices, ring_a[2]
  if (ring.size() != 6) throw Error("internal: patch net corner c is not regular");
  net.insert(net.end(), ring.begin() + 3, ring.begin() + 5);
  return net;
}

const FineForm& patchForm(int valence) {
  if (valence < 3 || valence > kMaxLimitValence)
    throw Error("limit volume: valence " + std::to_string(valence) + " is outside 3.." + std::to_string(kMaxLimitValence));
  PatchTables& t = tables();
  std::lock_guard<std::mutex> lock(t.mutex);
  return patchFormLocked(t, valence);
}

FineForm fixedPointPatchForm(int valence) {
  if (valence < 3 || valence > kMaxLimitValence)
    throw Error("limit volume: valence " + std::to_string(valence) + " is outside 3.." + std::to_string(kMaxLimitValence));
  PatchTables& t = tables();
  std::lock_guard<std::mutex> lock(t.mutex);
  if (!t.regular) t.regular = std::make_unique<DenseForm>(regularPatch());
  return entriesOf(extraordinaryPatch(valence, *t.regular).X);
}

double patchFixedPointResidual(int valence) {
  patchForm(valence);
  PatchTables& t = tables();
  std::lock_guard<std::mutex> lock(t.mutex);
  auto it = t.residuals.find(valence);
  return it == t.residuals.end() ? 0.0 : it->second;
}

}  // namespace limit_detail

FineForm limitVolumeForm(const uint32_t* faces, size_t faceCount, size_t vertexCount) {
  if (vertexCount >= (size_t(1) << 21)) throw Error("limit volume: meshes of more than 2 million vertices are not supported");
  const VertexCorners corners(faces, faceCount, vertexCount);
  for (size_t f = 0; f < faceCount; ++f)
    for (int k = 0; k < 3; ++k)
      if (corners.opposite(faces[3 * f + (k + 1) % 3], faces[3 * f + k]) == kNone)
        throw Error("limit volume needs a closed mesh: edge between vertices " + std::to_string(faces[3 * f + k]) +
                    " and " + std::to_string(faces[3 * f + (k + 1) % 3]) + " (face " + std::to_string(f) +
                    ") is on the boundary (Loop's boundary rules are not part of the limit form)");
  for (uint32_t v = 0; v < vertexCount; ++v)
    if (corners.count(v) > uint32_t(kMaxLimitValence))
      throw Error("limit volume: vertex " + std::to_string(v) + " has valence " + std::to_string(corners.count(v)) +
                  ", above the supported " + std::to_string(kMaxLimitValence));

  struct Term {
    uint64_t key;
    double value;
  };
  std::vector<Term> terms;
  // Sorts the terms and sums the repeated ones in place. A face adds ~220 terms of which ~57 per
  // face stay distinct: merging whenever the list has doubled since the last merge keeps the peak
  // near twice the merged form (large meshes: 163k vertices fit the WASM module's memory).
  size_t mergeAt = size_t(1) << 22, merged = 0;  // terms[0, merged) are sorted, keys distinct
  auto merge = [&]() {
    const auto byKey = [](const Term& x, const Term& y) { return x.key < y.key; };
    std::sort(terms.begin() + merged, terms.end(), byKey);
    std::inplace_merge(terms.begin(), terms.begin() + merged, terms.end(), byKey);
    size_t out = 0;
    for (size_t i = 0; i < terms.size();) {
      const uint64_t key = terms[i].key;
      double sum = 0;
      while (i < terms.size() && terms[i].key == key) sum += terms[i++].value;
      terms[out++] = {key, sum};
    }
    terms.resize(out);
    merged = out;
    mergeAt = std::max(mergeAt, 2 * out);
  };
  // Adds a face's patch form whose net slot s is the combination rows[s] of the mesh's vertices.
  auto addFace = [&](const FineForm& form, const std::vector<const SparseRow*>& rows) {
    if (terms.size() >= mergeAt) merge();
    for (size_t t = 0; t < form.weights.size(); ++t) {
      const SparseRow& ra = *rows[form.corners[3 * t]];
      const SparseRow& rb = *rows[form.corners[3 * t + 1]];
      const SparseRow& rc = *rows[form.corners[3 * t + 2]];
      for (auto [a0, wa] : ra)
        for (auto [b0, wb] : rb) {
          if (a0 == b0) continue;
          for (auto [c0, wc] : rc) {
            uint32_t a = a0, b = b0, c = c0;
            if (c == a || c == b) continue;  // det with a repeated point vanishes
            const double s = sortWithSign(a, b, c);
            terms.push_back({packTriple(a, b, c), s * form.weights[t] * wa * wb * wc});
          }
        }
    }
  };
  // A face with at most one extraordinary corner, that corner first: (a, b, c) rotated.
  auto classify = [](const VertexCorners& cs, const uint32_t* t, uint32_t out[3]) -> int {
    int irregular = 0, first = 0;
    for (int k = 0; k < 3; ++k)
      if (cs.count(t[k]) != 6) ++irregular, first = k;
    for (int k = 0; k < 3; ++k) out[k] = t[(first + k) % 3];
    return irregular;
  };

  std::vector<SparseRow> unit(vertexCount);
  for (uint32_t v = 0; v < vertexCount; ++v) unit[v] = {{v, 1.0}};
  std::vector<size_t> deferred;
  std::vector<const SparseRow*> rows;
  for (size_t f = 0; f < faceCount; ++f) {
    uint32_t t[3];
    if (classify(corners, faces + 3 * f, t) > 1) { deferred.push_back(f); continue; }
    const std::vector<uint32_t> net = limit_detail::patchNet(corners, t[0], t[1], t[2]);
    rows.clear();
    for (uint32_t v : net) rows.push_back(&unit[v]);
    addFace(limit_detail::patchForm(int(corners.count(t[0]))), rows);
  }
  // Faces with two or three extraordinary corners: one global subdivision isolates them; the four
  // children of such a face are pulled back through the subdivision rows.
  if (!deferred.empty()) {
    const std::vector<uint32_t> faceList(faces, faces + 3 * faceCount);
    const Subdivision s = loopSubdivide(faceList, vertexCount, std::vector<uint8_t>(vertexCount, 0));
    const VertexCorners corners1(s.faces.data(), s.faces.size() / 3, s.vertexCount);
    for (size_t f : deferred)
      for (int k = 0; k < 4; ++k) {
        uint32_t t[3];
        classify(corners1, &s.faces[12 * f + 3 * k], t);
        const std::vector<uint32_t> net = limit_detail::patchNet(corners1, t[0], t[1], t[2]);
        rows.clear();
        for (uint32_t v : net) rows.push_back(&s.rows[v]);
        addFace(limit_detail::patchForm(int(corners1.count(t[0]))), rows);
      }
  }
  merge();
  FineForm out;
  out.corners.reserve(3 * terms.size());
  out.weights.reserve(terms.size());
  constexpr uint64_t kMask = (uint64_t(1) << 21) - 1;
  for (size_t i = 0; i < terms.size();) {
    const uint64_t key = terms[i].key;
    double sum = 0;
    while (i < terms.size() && terms[i].key == key) sum += terms[i++].value;
    if (sum == 0.0) continue;
    out.corners.insert(out.corners.end(), {uint32_t(key >> 42), uint32_t((key >> 21) & kMask), uint32_t(key & kMask)});
    out.weights.push_back(sum);
  }
  return out;
}

double limitVolume(const TriangleMesh& mesh) {
  const MeshTopology topology = validateMesh(mesh);
  if (!topology.closed)
    throw Error("limit volume needs a closed mesh: this one has " + std::to_string(topology.boundaryEdges) +
                " boundary edges (Loop's boundary rules are not part of the limit form)");
  const FineForm form = limitVolumeForm(mesh.faces.data(), mesh.faceCount(), mesh.vertexCount());
  return form.evaluate(mesh.positions.data(), volumeReferencePoint(mesh));
}

}  // namespace mrvol
