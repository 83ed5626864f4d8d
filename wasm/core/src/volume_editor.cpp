#include "mrvol/volume_editor.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "mrvol/error.h"
#include "mrvol/hierarchy.h"

namespace mrvol {

const char* gradientPathName(GradientPath path) { return path == GradientPath::Tensor ? "tensor" : "matrix-free"; }

namespace {
inline void cross(const double* a, const double* b, double* out) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}
inline double dot(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline void axpy(double w, const double* a, double* out) { out[0] += w * a[0], out[1] += w * a[1], out[2] += w * a[2]; }
inline double dotDifference(const double* a, const double* d, const double* w) {
  return (a[0] - d[0]) * w[0] + (a[1] - d[1]) * w[1] + (a[2] - d[2]) * w[2];
}

// A full synthesis after this many incremental updates of the fine positions, so that rounding
// cannot build up.
constexpr int kResyncAfter = 64;
// Moves of at most this many cage vertices update the fine positions through cached basis
// columns; at most kBasisCacheSize columns are kept.
constexpr size_t kSparseMoveLimit = 4, kBasisCacheSize = 8;

// The edge table of VolumeEditor::edges_ for a validated closed or bounded manifold.
std::vector<uint32_t> edgeTable(const std::vector<uint32_t>& faces, uint32_t outside) {
  struct Half { uint64_t key; uint32_t b, c, a; };  // b -> c, with a opposite
  std::vector<Half> halves;
  halves.reserve(faces.size());
  for (size_t f = 0; f < faces.size(); f += 3)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = faces[f + k], b = faces[f + (k + 1) % 3], c = faces[f + (k + 2) % 3];
      halves.push_back({uint64_t(std::min(b, c)) << 32 | std::max(b, c), b, c, a});
    }
  std::sort(halves.begin(), halves.end(), [](const Half& x, const Half& y) { return x.key != y.key ? x.key < y.key : x.b < y.b; });
  std::vector<uint32_t> edges;
  edges.reserve(halves.size() / 2 * 4 + 8);
  for (size_t i = 0; i < halves.size();) {
    const Half& h = halves[i];
    const bool paired = i + 1 < halves.size() && halves[i + 1].key == h.key;
    if (paired && (halves[i + 1].b != h.c || (i + 2 < halves.size() && halves[i + 2].key == h.key)))
      throw Error("edge " + std::to_string(h.b) + "-" + std::to_string(h.c) + " is not a manifold edge of a consistently oriented mesh");
    edges.insert(edges.end(), {h.b, h.c, h.a, paired ? halves[i + 1].a : outside});
    i += paired ? 2 : 1;
  }
  return edges;
}
}  // namespace

double CagePolynomial::evaluate(const double* c, double* g) const {
  double v = constant;
  if (g) std::fill(g, g + 3 * size_t(cageSize), 0.0);
  for (uint32_t i = 0; i < cageSize; ++i) {
    v += dot(&linear[3 * i], c + 3 * i);
    if (g) axpy(1.0, &linear[3 * i], g + 3 * i);
  }
  double t[3];
  for (size_t p = 0; p < pairI.size(); ++p) {
    const double *ci = c + 3 * pairI[p], *cj = c + 3 * pairJ[p], *q = &pairQ[3 * p];
    cross(cj, q, t);
    v += dot(ci, t);
    if (g) {
      axpy(1.0, t, g + 3 * pairI[p]);
      cross(q, ci, t);
      axpy(1.0, t, g + 3 * pairJ[p]);
    }
  }
  // Triples in runs of one (i, j): sum_k T_ijk c_i . (c_j x c_k) = c_i . (c_j x w), w = sum_k T_ijk c_k,
  // and the gradient at k is T_ijk (c_i x c_j): per triple two vector updates, per run the crosses.
  for (size_t p = 0; p < tripleT.size();) {
    const uint32_t i = tripleI[p], j = tripleJ[p];
    size_t end = p + 1;
    while (end < tripleT.size() && tripleI[end] == i && tripleJ[end] == j) ++end;
    double w[3] = {0, 0, 0};
    for (size_t q = p; q < end; ++q) axpy(tripleT[q], c + 3 * tripleK[q], w);
    const double *ci = c + 3 * i, *cj = c + 3 * j;
    cross(cj, w, t);
    v += dot(ci, t);
    if (g) {
      axpy(1.0, t, g + 3 * i);
      cross(w, ci, t);
      axpy(1.0, t, g + 3 * j);
      cross(ci, cj, t);
      for (size_t q = p; q < end; ++q) axpy(tripleT[q], t, g + 3 * tripleK[q]);
    }
    p = end;
  }
  return v;
}

void CagePolynomial::alongDirection(const double* c, const double* g, double* k) const {
  // Expands Theta(c + s g) term by term: (c_i + s g_i) . ((c_j + s g_j) x (c_k + s g_k)).
  k[0] = constant, k[1] = k[2] = k[3] = 0;
  for (uint32_t i = 0; i < cageSize; ++i) k[0] += dot(&linear[3 * i], c + 3 * i), k[1] += dot(&linear[3 * i], g + 3 * i);
  double t[3];
  for (size_t p = 0; p < pairI.size(); ++p) {
    const double *ci = c + 3 * pairI[p], *cj = c + 3 * pairJ[p], *gi = g + 3 * pairI[p], *gj = g + 3 * pairJ[p], *q = &pairQ[3 * p];
    cross(cj, q, t);
    k[0] += dot(ci, t), k[1] += dot(gi, t);
    cross(gj, q, t);
    k[1] += dot(ci, t), k[2] += dot(gi, t);
  }
  // Triples by runs of one (i, j) as in evaluate: (c_i + s g_i) . ((c_j + s g_j) x (wc + s wg)).
  for (size_t p = 0; p < tripleT.size();) {
    const uint32_t i = tripleI[p], j = tripleJ[p];
    size_t end = p + 1;
    while (end < tripleT.size() && tripleI[end] == i && tripleJ[end] == j) ++end;
    double wc[3] = {0, 0, 0}, wg[3] = {0, 0, 0};
    for (size_t q = p; q < end; ++q) axpy(tripleT[q], c + 3 * tripleK[q], wc), axpy(tripleT[q], g + 3 * tripleK[q], wg);
    const double *ci = c + 3 * i, *cj = c + 3 * j, *gi = g + 3 * i, *gj = g + 3 * j;
    cross(cj, wc, t);
    k[0] += dot(ci, t), k[1] += dot(gi, t);
    cross(gj, wc, t);
    k[1] += dot(ci, t), k[2] += dot(gi, t);
    cross(cj, wg, t);
    k[1] += dot(ci, t), k[2] += dot(gi, t);
    cross(gj, wg, t);
    k[2] += dot(ci, t), k[3] += dot(gi, t);
    p = end;
  }
}

VolumeEditor::VolumeEditor(const Hierarchy& hierarchy, const WaveletTransform& transform, int level,
                           const double* positions)
    : hierarchy_(&hierarchy), transform_(&transform), level_(level) {
  if (level < 0 || level > hierarchy.levels)
    throw Error("level " + std::to_string(level) + " is out of range: this mesh has levels 0.." +
                std::to_string(hierarchy.levels));
  cageSize_ = hierarchy.vertexCount[level];
  const size_t n = hierarchy.fineVertexCount();
  TriangleMesh fine;
  fine.positions.resize(3 * n);
  hierarchy.toHierarchyOrder(positions, fine.positions.data());
  for (double v : fine.positions)
    if (!std::isfinite(v)) throw Error("positions must be finite numbers");
  fine.faces = hierarchy.fineFaces();
  origin_ = volumeReferencePoint(fine);
  edges_ = edgeTable(fine.faces, uint32_t(n));
  x_ = std::move(fine.positions);
  transform.analyze(x_.data(), level);
  reference_ = volume();
}

std::vector<uint32_t> VolumeEditor::cageVertices() const {
  return std::vector<uint32_t>(hierarchy_->inputIndex.begin(), hierarchy_->inputIndex.begin() + cageSize_);
}

uint32_t VolumeEditor::cageIndexOf(uint32_t callerVertex) const {
  if (callerVertex >= hierarchy_->hierarchyIndex.size())
    throw Error("vertex " + std::to_string(callerVertex) + " does not exist (the mesh has " +
                std::to_string(hierarchy_->hierarchyIndex.size()) + " vertices)");
  const uint32_t h = hierarchy_->hierarchyIndex[callerVertex];
  if (h >= cageSize_)
    throw Error("vertex " + std::to_string(callerVertex) + " is not a vertex of the level-" + std::to_string(level_) +
                " cage (it is born at level " + std::to_string(hierarchy_->depth(h)) + ")");
  return h;
}

void VolumeEditor::setReferenceVolume(double volume) {
  if (!std::isfinite(volume)) throw Error("the reference volume must be a finite number");
  reference_ = volume;
}

const std::vector<double>& VolumeEditor::fine() const {
  if (fineValid_) return fine_;
  const size_t cage3 = 3 * size_t(cageSize_), n3 = x_.size();
  // Since the last synthesis only the cage moved (and not too often): synthesis is linear, so add
  // the zero-detail synthesis of the move: along the basis functions of a few moved vertices, else
  // by a synthesis of the whole move.
  const bool incremental = fineBaseValid_ && incrementalUpdates_ < kResyncAfter;
  std::vector<uint32_t> moved;
  for (uint32_t c = 0; incremental && c < cageSize_ && moved.size() <= kSparseMoveLimit; ++c)
    if (x_[3 * c] != fineCage_[3 * c] || x_[3 * c + 1] != fineCage_[3 * c + 1] || x_[3 * c + 2] != fineCage_[3 * c + 2])
      moved.push_back(c);
  if (incremental && moved.size() <= kSparseMoveLimit) {
    for (uint32_t c : moved) {
      const double d[3] = {x_[3 * c] - fineCage_[3 * c], x_[3 * c + 1] - fineCage_[3 * c + 1], x_[3 * c + 2] - fineCage_[3 * c + 2]};
      const BasisColumn& column = basisColumn(c);
      for (size_t k = 0; k < column.vertices.size(); ++k) axpy(column.weights[k], d, &fine_[3 * size_t(column.vertices[k])]);
    }
    ++incrementalUpdates_;
  } else if (incremental) {
    fineDelta_.resize(n3);
    for (size_t i = 0; i < cage3; ++i) fineDelta_[i] = x_[i] - fineCage_[i];
    transform_->synthesizeZeroDetails(fineDelta_.data(), level_);
    for (size_t i = 0; i < n3; ++i) fine_[i] += fineDelta_[i];
    ++incrementalUpdates_;
  } else {
    // Synthesis commutes with translations of the cage: shifting the cage before synthesis gives the
    // fine positions relative to origin_ without cancellation.
    fine_.assign(n3 + 3, 0.0);
    std::copy(x_.begin(), x_.end(), fine_.begin());
    for (size_t i = 0; i < cage3; i += 3) fine_[i] -= origin_.x, fine_[i + 1] -= origin_.y, fine_[i + 2] -= origin_.z;
    transform_->synthesize(fine_.data(), level_);
    incrementalUpdates_ = 0;
  }
  fineCage_.assign(x_.begin(), x_.begin() + cage3);
  fineValid_ = fineBaseValid_ = true;
  volumeValid_ = gradientValid_ = false;
  return fine_;
}

const VolumeEditor::BasisColumn& VolumeEditor::basisColumn(uint32_t c) const {
  for (size_t i = 0; i < basisCache_.size(); ++i)
    if (basisCache_[i].cageVertex == c) {
      if (i + 1 != basisCache_.size()) std::rotate(basisCache_.begin() + i, basisCache_.begin() + i + 1, basisCache_.end());
      return basisCache_.back();
    }
  // The scheme acts on each coordinate alike: synthesize the unit x and keep the x components.
  std::vector<double>& u = fineDelta_;
  u.assign(x_.size(), 0.0);
  u[3 * size_t(c)] = 1.0;
  transform_->synthesizeZeroDetails(u.data(), level_);
  BasisColumn column{c, {}, {}};
  for (size_t v = 0; v < u.size() / 3; ++v)
    if (u[3 * v] != 0.0) column.vertices.push_back(uint32_t(v)), column.weights.push_back(u[3 * v]);
  basisCache_.push_back(std::move(column));
  // At most kBasisCacheSize columns and 4 entries per fine vertex in all (coarse levels have wide
  // supports): the oldest go first, the newest always stays.
  size_t entries = 0;
  for (const auto& b : basisCache_) entries += b.vertices.size();
  while (basisCache_.size() > 1 && (basisCache_.size() > kBasisCacheSize || entries > 4 * (x_.size() / 3))) {
    entries -= basisCache_.front().vertices.size();
    basisCache_.erase(basisCache_.begin());
  }
  return basisCache_.back();
}

double VolumeEditor::edgePass(const double* p, double* grad) const {
  // Edge (b, c) enters triangle (a, b, c) as a . (b x c) and triangle (d, c, b) as -d . (b x c):
  // sum (a - d) . (b x c) over the edges is 3 sum over the triangles of their triple products, and
  // b x c / 6 is the share of the volume gradient at a (minus it at d). Half the cross products of
  // a pass over the triangles, and edges in order of their ends read the positions nearly in order.
  const uint32_t* e = edges_.data();
  const size_t m = edges_.size();
  double sum = 0, w[3];
  if (!grad) {
    for (size_t k = 0; k < m; k += 4) {
      cross(p + 3 * size_t(e[k]), p + 3 * size_t(e[k + 1]), w);
      sum += dotDifference(p + 3 * size_t(e[k + 2]), p + 3 * size_t(e[k + 3]), w);
    }
    return sum / 18.0;
  }
  std::fill(grad, grad + x_.size() + 3, 0.0);
  for (size_t k = 0; k < m; k += 4) {
    cross(p + 3 * size_t(e[k]), p + 3 * size_t(e[k + 1]), w);
    w[0] *= 1.0 / 6.0, w[1] *= 1.0 / 6.0, w[2] *= 1.0 / 6.0;
    const size_t a = 3 * size_t(e[k + 2]), d = 3 * size_t(e[k + 3]);
    sum += dotDifference(p + a, p + d, w);
    grad[a] += w[0], grad[a + 1] += w[1], grad[a + 2] += w[2];
    grad[d] -= w[0], grad[d + 1] -= w[1], grad[d + 2] -= w[2];
  }
  return sum / 3.0;
}

double VolumeEditor::maskedVolume(const double* p, double* grad, const std::vector<uint8_t>& mask) const {
  const auto& faces = hierarchy_->fineFaces();
  if (grad) std::fill(grad, grad + x_.size() + 3, 0.0);
  double sum = 0;
  double t[3];
  for (size_t f = 0, tri = 0; f < faces.size(); f += 3, ++tri) {
    if (!mask[tri]) continue;
    const double *a = p + 3 * size_t(faces[f]), *b = p + 3 * size_t(faces[f + 1]), *c = p + 3 * size_t(faces[f + 2]);
    cross(b, c, t);
    sum += dot(a, t);
    if (grad) {
      axpy(1.0 / 6.0, t, grad + 3 * size_t(faces[f]));
      cross(c, a, t);
      axpy(1.0 / 6.0, t, grad + 3 * size_t(faces[f + 1]));
      cross(a, b, t);
      axpy(1.0 / 6.0, t, grad + 3 * size_t(faces[f + 2]));
    }
  }
  return sum / 6.0;
}

double VolumeEditor::fineVolumeAndGradient(std::vector<double>* grad, const std::vector<uint8_t>* mask) const {
  const double* p = fine().data();
  if (grad) grad->resize(x_.size() + 3);
  return mask ? maskedVolume(p, grad ? grad->data() : nullptr, *mask) : edgePass(p, grad ? grad->data() : nullptr);
}

double VolumeEditor::volume() const {
  if (!fineValid_ || !volumeValid_) {
    cachedVolume_ = fineVolumeAndGradient(nullptr, nullptr);
    volumeValid_ = true;
  }
  return cachedVolume_;
}

double VolumeEditor::volumeAndGradient(std::vector<double>& gradient) const {
  if (fineValid_ && gradientValid_) {
    gradient.swap(cachedGradient_);  // handed over once
    gradientValid_ = false;
    return cachedVolume_;
  }
  cachedVolume_ = fineVolumeAndGradient(&gradient, nullptr);
  volumeValid_ = true;
  return cachedVolume_;
}

void VolumeEditor::prepareGradient() const {
  cachedVolume_ = fineVolumeAndGradient(&cachedGradient_, nullptr);
  volumeValid_ = gradientValid_ = true;
}

void VolumeEditor::useTensor(const VolumeTensor& tensor) {
  if (tensor.storage != TensorStorage::Cage || tensor.level != level_ || tensor.vertexCount != x_.size() / 3 ||
      tensor.rowCount != cageSize_)
    throw Error("the tensor is not theta^" + std::to_string(level_) + " with cage storage for this mesh");
  auto poly = std::make_unique<CagePolynomial>();
  poly->cageSize = cageSize_;
  poly->linear.assign(3 * size_t(cageSize_), 0.0);
  const std::vector<double> shifted = shiftedCage();
  const double* x = x_.data();  // details (translation only moves the cage coefficients)
  for (uint32_t i = 0; i < tensor.rowCount; ++i)
    for (uint32_t p = tensor.rowStart[i]; p < tensor.rowStart[i + 1]; ++p) {
      const uint32_t j = tensor.pairJ[p];
      double q[3] = {0, 0, 0};
      for (uint32_t t = tensor.pairStart[p]; t < tensor.pairStart[p + 1]; ++t) {
        const uint32_t k = tensor.kIndex(t);
        if (k < cageSize_) {
          poly->tripleI.push_back(i), poly->tripleJ.push_back(j), poly->tripleK.push_back(k);
          poly->tripleT.push_back(tensor.values[t]);
        } else {  // k is a detail
          axpy(tensor.values[t], x + 3 * size_t(k), q);
        }
      }
      if (j >= cageSize_) {  // a_i += p_j x q
        double t[3];
        cross(x + 3 * size_t(j), q, t);
        axpy(1.0, t, &poly->linear[3 * i]);
      } else if (q[0] != 0 || q[1] != 0 || q[2] != 0) {
        poly->pairI.push_back(i), poly->pairJ.push_back(j);
        poly->pairQ.insert(poly->pairQ.end(), q, q + 3);
      }
    }
  // Entries made of details only fold into the constant.
  poly->constant = volume() - poly->evaluate(shifted.data(), nullptr);
  polynomial_ = std::move(poly);
}

void VolumeEditor::useMatrixFree() { polynomial_.reset(); }

void VolumeEditor::setFreeSet(FreeCage mode, std::vector<uint32_t> list, std::vector<int> detailLevels) {
  for (uint32_t c : list)
    if (c >= cageSize_) throw Error("free-set index " + std::to_string(c) + " is not a cage vertex");
  for (int l : detailLevels)
    if (l < level_ || l >= hierarchy_->levels)
      throw Error("free detail level " + std::to_string(l) + " is out of range " + std::to_string(level_) + ".." +
                  std::to_string(hierarchy_->levels - 1));
  freeMode_ = mode;
  freeCage_ = std::move(list);
  freeDetailLevels_ = std::move(detailLevels);
}

std::vector<uint32_t> VolumeEditor::freeCoefficients(const std::vector<uint8_t>& held) const {
  std::vector<uint32_t> free;
  const auto& boundary = hierarchy_->boundary;
  if (freeMode_ == FreeCage::List) {
    for (uint32_t c : freeCage_)
      if (!boundary[c]) free.push_back(c);
  } else {
    for (uint32_t c = 0; c < cageSize_; ++c)
      if (!boundary[c] && (freeMode_ == FreeCage::All || !(c < held.size() && held[c]))) free.push_back(c);
  }
  for (int l : freeDetailLevels_)
    for (uint32_t v = hierarchy_->vertexCount[l]; v < hierarchy_->vertexCount[l + 1]; ++v)
      if (!boundary[v]) free.push_back(v);
  std::sort(free.begin(), free.end());
  free.erase(std::unique(free.begin(), free.end()), free.end());
  return free;
}

double VolumeEditor::gradientMatrixFree(std::vector<double>& gradient) const {
  double v = fineVolumeAndGradient(&gradient, nullptr);
  transform_->synthesisAdjoint(gradient.data(), level_);
  gradient.resize(x_.size());
  return v;
}

double VolumeEditor::gradientTensor(std::vector<double>& gradient) const {
  if (!polynomial_) throw Error("no tensor is in use");
  gradient.assign(3 * size_t(cageSize_), 0.0);
  return polynomial_->evaluate(shiftedCage().data(), gradient.data());
}

std::vector<double> VolumeEditor::shiftedCage() const {
  std::vector<double> c(x_.begin(), x_.begin() + 3 * size_t(cageSize_));
  for (size_t i = 0; i < c.size(); i += 3) c[i] -= origin_.x, c[i + 1] -= origin_.y, c[i + 2] -= origin_.z;
  return c;
}

void VolumeEditor::solveGlobal(const std::vector<uint32_t>& free, const EditOptions& o, EditReport& report) {
  const bool tensor = polynomial_ && freeDetailLevels_.empty();
  const double scale = std::max(std::fabs(reference_), 1e-300);
  std::vector<double>& g = scratchGradient_;
  std::vector<double>& q = scratchDirection_;
  g.clear();
  const bool detailsFree = !freeDetailLevels_.empty();
  std::vector<double> cage;
  bool cubicValue = false;  // v already holds the exact volume after the last step (its cubic)
  double v = 0;
  for (int it = 0;; ++it) {
    if (tensor) {
      if (!cubicValue || std::fabs(v - reference_) / scale >= o.tolerance) {
        cage = shiftedCage();
        g.resize(3 * size_t(cageSize_));
        v = polynomial_->evaluate(cage.data(), g.data());
      }
    } else if (cubicValue && fineValid_ && volumeValid_ && !gradientValid_) {
      v = cachedVolume_;  // from the cubic of the previous step: no pass needed to check it
      if (std::fabs(v - reference_) / scale >= o.tolerance) v = volumeAndGradient(g);
    } else {
      v = volumeAndGradient(g);
    }
    cubicValue = false;
    report.volumeResult = v;
    report.relativeError = std::fabs(v - reference_) / scale;
    if (report.relativeError < o.tolerance) return;
    if (it == o.maxIterations) {
      report.converged = false;
      report.message = "no convergence in " + std::to_string(o.maxIterations) + " iterations";
      return;
    }
    if (!tensor) transform_->synthesisAdjoint(g.data(), level_, 3, detailsFree);
    double norm2 = 0;
    for (uint32_t i : free) norm2 += dot(&g[3 * size_t(i)], &g[3 * size_t(i)]);
    if (!(norm2 > 0) || free.empty()) {
      report.converged = false;
      report.message = free.empty() ? "the free set is empty: nothing can absorb the volume change"
                                    : "the free coefficients cannot change the volume (their gradients vanish)";
      return;
    }
    // Minimal-norm correction of the linearized constraint: delta_i = r / sum |g|^2 g_i.
    const double step = (reference_ - v) / norm2;
    ++report.iterations;
    if (!o.lineSearch) {
      for (uint32_t i : free) axpy(step, &g[3 * size_t(i)], &x_[3 * size_t(i)]);
      fineValid_ = false;
      fineBaseValid_ = fineBaseValid_ && !detailsFree;
      continue;
    }
    // Along that same direction the volume is a cubic in the step length s: c0 = v and
    // c1 = g_F . g_F are known, one pass gives c2 and c3, and solving the cubic replaces further
    // linearized iterations (each, on the matrix-free path, a synthesis and an adjoint).
    double c[4] = {v, norm2, 0, 0};
    const size_t n3 = x_.size(), cage3 = 3 * size_t(cageSize_);
    if (tensor) {
      q.assign(cage3, 0.0);
      for (uint32_t i : free)
        for (int k = 0; k < 3; ++k) q[3 * size_t(i) + k] = g[3 * size_t(i) + k];
      polynomial_->alongDirection(cage.data(), q.data(), c);
    } else {
      const std::vector<double>& p = fine();
      if (q.size() != n3 + 3) q.assign(n3 + 3, 0.0);  // the last vertex, the origin, stays 0
      std::fill(q.begin(), q.begin() + (detailsFree ? n3 : cage3), 0.0);  // zero-detail synthesis overwrites the rest
      for (uint32_t i : free)
        for (int k = 0; k < 3; ++k) q[3 * size_t(i) + k] = g[3 * size_t(i) + k];
      if (detailsFree) transform_->synthesize(q.data(), level_);
      else transform_->synthesizeZeroDetails(q.data(), level_);
      // Over the edges as in edgePass: c2 = sum (a - d) . (qb x qc) / 6, c3 = sum (qa - qd) . (qb x qc) / 18.
      const uint32_t* e = edges_.data();
      const double* pq = q.data();
      double w[3], c2 = 0, c3 = 0;
      for (size_t k = 0; k < edges_.size(); k += 4) {
        cross(pq + 3 * size_t(e[k]), pq + 3 * size_t(e[k + 1]), w);
        const size_t a = 3 * size_t(e[k + 2]), d = 3 * size_t(e[k + 3]);
        c2 += dotDifference(&p[a], &p[d], w);
        c3 += dotDifference(pq + a, pq + d, w);
      }
      c[2] = c2 / 6.0, c[3] = c3 / 18.0;
    }
    // Newton on c0 + c1 s + c2 s^2 + c3 s^3 = reference, from the linearized step.
    double s = step;
    for (int n = 0; n < 60; ++n) {
      const double f = c[0] + s * (c[1] + s * (c[2] + s * c[3])) - reference_;
      const double df = c[1] + s * (2 * c[2] + 3 * s * c[3]);
      if (!(df != 0) || !std::isfinite(f)) break;
      const double next = s - f / df;
      if (!std::isfinite(next) || std::fabs(next - step) > 4 * std::fabs(step) + 1e-300) break;  // stay near the linear step
      const bool done = std::fabs(next - s) <= 1e-15 * std::fabs(s);
      s = next;
      if (done) break;
    }
    for (uint32_t i : free) axpy(s, &g[3 * size_t(i)], &x_[3 * size_t(i)]);
    v = c[0] + s * (c[1] + s * (c[2] + s * c[3]));
    cubicValue = true;
    if (tensor) {
      fineValid_ = false;
      continue;
    }
    for (size_t i = 0; i < n3; ++i) fine_[i] += s * q[i];  // fine() stays in step with x_
    fineCage_.assign(x_.begin(), x_.begin() + cage3);
    ++incrementalUpdates_;
    cachedVolume_ = v;
    volumeValid_ = true;
    gradientValid_ = false;
    g.clear();
  }
}

void VolumeEditor::setParts(const std::vector<std::vector<uint32_t>>& parts, const std::vector<double>& references) {
  partTriangles_.clear();
  partReference_.clear();
  if (parts.empty()) return;
  if (!references.empty() && references.size() != parts.size())
    throw Error("give one reference volume per part (" + std::to_string(parts.size()) + ")");
  const size_t n = x_.size() / 3;
  // Weight of each part at each fine vertex: synthesis of its cage indicator (partition of unity).
  std::vector<std::vector<double>> weight(parts.size(), std::vector<double>(n, 0.0));
  std::vector<int> owner(cageSize_, -1);
  for (size_t p = 0; p < parts.size(); ++p)
    for (uint32_t c : parts[p]) {
      if (c >= cageSize_) throw Error("part " + std::to_string(p) + " lists " + std::to_string(c) + ", not a cage vertex");
      if (owner[c] >= 0) throw Error("cage vertex " + std::to_string(hierarchy_->inputIndex[c]) + " is in two parts");
      owner[c] = int(p);
      weight[p][c] = 1.0;
    }
  for (auto& w : weight)
    for (int l = level_ + 1; l <= hierarchy_->levels; ++l)
      for (const auto& step : transform_->synthesisSteps(l)) step.forward(w.data(), 1);
  const auto& faces = hierarchy_->fineFaces();
  partTriangles_.assign(parts.size(), std::vector<uint8_t>(faces.size() / 3, 0));
  for (size_t f = 0, tri = 0; f < faces.size(); f += 3, ++tri) {
    double best = 0, total = 0;
    int bestPart = -1;
    for (size_t p = 0; p < parts.size(); ++p) {
      const double w = weight[p][faces[f]] + weight[p][faces[f + 1]] + weight[p][faces[f + 2]];
      total += w;
      if (w > best) best = w, bestPart = int(p);
    }
    if (bestPart >= 0 && best > 3.0 - total) partTriangles_[bestPart][tri] = 1;  // beats the unassigned rest
  }
  partReference_ = references.empty() ? partVolumes() : references;
}

std::vector<double> VolumeEditor::partVolumes() const {
  std::vector<double> v;
  for (const auto& mask : partTriangles_) v.push_back(fineVolumeAndGradient(nullptr, &mask));
  return v;
}

void VolumeEditor::solveParts(const std::vector<uint32_t>& free, const EditOptions& o, EditReport& report) {
  const size_t k = partTriangles_.size(), m = free.size();
  Eigen::MatrixXd J(k, 3 * m);
  Eigen::VectorXd r(k);
  std::vector<double> g;
  for (int it = 0;; ++it) {
    double worst = 0;
    for (size_t p = 0; p < k; ++p) {
      const double v = fineVolumeAndGradient(&g, &partTriangles_[p]);
      r[p] = partReference_[p] - v;
      worst = std::max(worst, std::fabs(r[p]) / std::max(std::fabs(partReference_[p]), 1e-300));
      transform_->synthesisAdjoint(g.data(), level_);
      for (size_t i = 0; i < m; ++i)
        for (int c = 0; c < 3; ++c) J(p, 3 * i + c) = g[3 * size_t(free[i]) + c];
    }
    report.relativeError = worst;
    if (worst < o.tolerance) return;
    if (it == o.maxIterations) {
      report.converged = false;
      report.message = "no convergence in " + std::to_string(o.maxIterations) + " iterations";
      return;
    }
    // delta = J^T (J J^T)^-1 r: the minimal-norm solution of the k linearized constraints.
    Eigen::MatrixXd JJt = J * J.transpose();
    Eigen::FullPivLU<Eigen::MatrixXd> lu(JJt);
    lu.setThreshold(1e-12);
    if (m == 0 || lu.rank() < int(k)) {
      report.converged = false;
      report.message = "the parts' constraints cannot all be met by the free set (some part has no free influence)";
      return;
    }
    Eigen::VectorXd delta = J.transpose() * lu.solve(r);
    for (size_t i = 0; i < m; ++i)
      for (int c = 0; c < 3; ++c) x_[3 * size_t(free[i]) + c] += delta[3 * i + c];
    fineValid_ = false;
    fineBaseValid_ = fineBaseValid_ && freeDetailLevels_.empty();
    ++report.iterations;
  }
}

EditReport VolumeEditor::correct(const std::vector<uint8_t>& held, const EditOptions& o) {
  EditReport report;
  report.path = partTriangles_.empty() && freeDetailLevels_.empty() ? path() : GradientPath::MatrixFree;
  report.volumeReference = reference_;
  report.volumeTarget = volume();
  report.substeps = 1;
  if (o.preserve) {
    const auto free = freeCoefficients(held);
    if (partTriangles_.empty()) solveGlobal(free, o, report);
    else solveParts(free, o, report);
  }
  report.volumeResult = partTriangles_.empty() && o.preserve ? report.volumeResult : volume();
  if (partTriangles_.empty())
    report.relativeError = std::fabs(report.volumeResult - reference_) / std::max(std::fabs(reference_), 1e-300);
  report.partReferences = partReference_;
  report.partVolumes = partVolumes();
  return report;
}

EditReport VolumeEditor::deformCage(const std::vector<double>& target, const std::vector<uint8_t>& held,
                                    const EditOptions& o) {
  if (target.size() != 3 * size_t(cageSize_))
    throw Error("the cage target needs " + std::to_string(3 * size_t(cageSize_)) + " coordinates, got " +
                std::to_string(target.size()));
  if (!(o.tolerance > 0) || o.maxIterations < 1 || o.maxSubsteps < 1)
    throw Error("tolerance must be positive and iteration limits at least 1");
  std::vector<double> move(target.size());
  for (uint32_t c = 0; c < cageSize_; ++c)
    for (int k = 0; k < 3; ++k) {
      const double t = target[3 * c + k];
      if (!std::isfinite(t)) throw Error("the cage target has a non-finite coordinate");
      move[3 * c + k] = t - x_[3 * c + k];
      if (hierarchy_->boundary[c] && move[3 * c + k] != 0.0)
        throw Error("vertex " + std::to_string(hierarchy_->inputIndex[c]) +
                    " is on the boundary: boundary vertices stay fixed so that the volume stays meaningful");
    }
  EditReport report;
  report.path = partTriangles_.empty() && freeDetailLevels_.empty() ? path() : GradientPath::MatrixFree;
  report.volumeReference = reference_;
  std::vector<double> start(x_.begin(), x_.begin() + 3 * size_t(cageSize_));
  // The cage takes the target as given (x + (t - x) need not round to t).
  std::copy(target.begin(), target.end(), x_.begin());
  fineValid_ = false;
  const bool tensor = polynomial_ && freeDetailLevels_.empty() && partTriangles_.empty();
  if (tensor) report.volumeTarget = polynomial_->evaluate(shiftedCage().data(), nullptr);
  else if (o.preserve && partTriangles_.empty()) prepareGradient(), report.volumeTarget = cachedVolume_;
  else report.volumeTarget = volume();
  if (!o.preserve) {
    // x + (t - x) need not round to t: the cage takes the target as given.
    std::copy(target.begin(), target.end(), x_.begin());
    fineValid_ = false;
    report.volumeTarget = tensor ? polynomial_->evaluate(shiftedCage().data(), nullptr) : volume();
    report.volumeResult = report.volumeTarget;
    report.relativeError = std::fabs(report.volumeResult - reference_) / std::max(std::fabs(reference_), 1e-300);
    report.partReferences = partReference_;
    report.partVolumes = partVolumes();
    return report;
  }
  // Large moves are split so that the linearization holds.
  const double rawChange = std::fabs(report.volumeTarget - reference_) / std::max(std::fabs(reference_), 1e-300);
  const int substeps = std::clamp(int(std::ceil(rawChange / o.substepError)), 1, o.maxSubsteps);
  report.substeps = substeps;
  const auto free = freeCoefficients(held);
  if (substeps > 1) {
    for (size_t i = 0; i < move.size(); ++i) x_[i] = start[i];
    fineValid_ = false;
  }
  for (int s = 1; s <= substeps; ++s) {
    if (substeps > 1) {
      for (size_t i = 0; i < move.size(); ++i) x_[i] += move[i] / substeps;
      fineValid_ = false;
    }
    EditReport stepReport;
    if (partTriangles_.empty()) solveGlobal(free, o, stepReport);
    else solveParts(free, o, stepReport);
    report.iterations += stepReport.iterations;
    report.relativeError = stepReport.relativeError;
    report.volumeResult = stepReport.volumeResult;
    if (!stepReport.converged) {
      report.converged = false;
      report.message = stepReport.message;
      break;
    }
  }
  // Held vertices end exactly where the target puts them (sub-steps add up with rounding).
  bool snapped = false;
  for (uint32_t c = 0; c < cageSize_; ++c)
    if (c < held.size() && held[c] && !std::binary_search(free.begin(), free.end(), c))
      for (int k = 0; k < 3; ++k) {
        snapped = snapped || x_[3 * c + k] != target[3 * c + k];
        x_[3 * c + k] = target[3 * c + k];
      }
  if (snapped) {  // rounding of the sub-steps: re-evaluate
    fineValid_ = false;
    report.volumeResult = tensor ? polynomial_->evaluate(shiftedCage().data(), nullptr) : volume();
  }
  if (partTriangles_.empty())
    report.relativeError = std::fabs(report.volumeResult - reference_) / std::max(std::fabs(reference_), 1e-300);
  report.partReferences = partReference_;
  report.partVolumes = partVolumes();
  return report;
}

std::vector<double> VolumeEditor::cagePositions() const {
  return std::vector<double>(x_.begin(), x_.begin() + 3 * size_t(cageSize_));
}

std::vector<double> VolumeEditor::coefficients() const { return x_; }

std::vector<double> VolumeEditor::positions() const {
  std::vector<double> out(x_.size());
  hierarchy_->toInputOrder(fine().data(), out.data());
  for (size_t i = 0; i < out.size(); i += 3) out[i] += origin_.x, out[i + 1] += origin_.y, out[i + 2] += origin_.z;
  return out;
}

}  // namespace mrvol
