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
  for (size_t p = 0; p < tripleT.size(); ++p) {
    const double *ci = c + 3 * tripleI[p], *cj = c + 3 * tripleJ[p], *ck = c + 3 * tripleK[p];
    const double T = tripleT[p];
    cross(cj, ck, t);
    v += T * dot(ci, t);
    if (g) {
      axpy(T, t, g + 3 * tripleI[p]);
      cross(ck, ci, t);
      axpy(T, t, g + 3 * tripleJ[p]);
      cross(ci, cj, t);
      axpy(T, t, g + 3 * tripleK[p]);
    }
  }
  return v;
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
  if (!fineValid_) {
    fine_ = x_;
    transform_->synthesize(fine_.data(), level_);
    fineValid_ = true;
    volumeValid_ = gradientValid_ = false;
  }
  return fine_;
}

double VolumeEditor::passVolume(const std::vector<double>& p, std::vector<double>* grad,
                                const std::vector<uint8_t>* mask) const {
  const auto& faces = hierarchy_->fineFaces();
  if (grad) grad->assign(p.size(), 0.0);
  const double o[3] = {origin_.x, origin_.y, origin_.z};
  double sum = 0;
  double t[3];
  for (size_t f = 0, tri = 0; f < faces.size(); f += 3, ++tri) {
    if (mask && !(*mask)[tri]) continue;
    const double *pa = &p[3 * size_t(faces[f])], *pb = &p[3 * size_t(faces[f + 1])], *pc = &p[3 * size_t(faces[f + 2])];
    const double a[3] = {pa[0] - o[0], pa[1] - o[1], pa[2] - o[2]};
    const double b[3] = {pb[0] - o[0], pb[1] - o[1], pb[2] - o[2]};
    const double c[3] = {pc[0] - o[0], pc[1] - o[1], pc[2] - o[2]};
    cross(b, c, t);
    sum += dot(a, t);
    if (grad) {
      axpy(1.0 / 6.0, t, &(*grad)[3 * size_t(faces[f])]);
      cross(c, a, t);
      axpy(1.0 / 6.0, t, &(*grad)[3 * size_t(faces[f + 1])]);
      cross(a, b, t);
      axpy(1.0 / 6.0, t, &(*grad)[3 * size_t(faces[f + 2])]);
    }
  }
  return sum / 6.0;
}

double VolumeEditor::fineVolumeAndGradient(std::vector<double>* grad, const std::vector<uint8_t>* mask) const {
  return passVolume(fine(), grad, mask);
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
  for (int it = 0;; ++it) {
    double v;
    std::vector<double> cage;
    if (tensor) {
      cage = shiftedCage();
      g.resize(3 * size_t(cageSize_));
      v = polynomial_->evaluate(cage.data(), g.data());
    } else if (fineValid_ && volumeValid_ && !gradientValid_ && it > 0) {
      v = cachedVolume_;  // from the cubic of the previous step: no pass needed to check it
      if (std::fabs(v - reference_) / scale >= o.tolerance) v = volumeAndGradient(g);
    } else {
      v = volumeAndGradient(g);
    }
    report.volumeResult = v;
    report.relativeError = std::fabs(v - reference_) / scale;
    if (report.relativeError < o.tolerance) return;
    if (it == o.maxIterations) {
      report.converged = false;
      report.message = "no convergence in " + std::to_string(o.maxIterations) + " iterations";
      return;
    }
    if (!tensor) {
      if (g.size() != x_.size()) v = volumeAndGradient(g);  // checked on the cubic's value: gradient now
      transform_->synthesisAdjoint(g.data(), level_, 3, detailsFree);
    }
    double norm2 = 0;
    for (uint32_t i : free) norm2 += dot(&g[3 * size_t(i)], &g[3 * size_t(i)]);
    if (!(norm2 > 0) || free.empty()) {
      report.converged = false;
      report.message = free.empty() ? "the free set is empty: nothing can absorb the volume change"
                                    : "the free coefficients cannot change the volume (their gradients vanish)";
      return;
    }
    // Minimal-norm correction of the linearized constraint: delta_i = r / sum |g|^2 g_i.
    double step = (reference_ - v) / norm2;
    ++report.iterations;
    if (!o.lineSearch) {
      for (uint32_t i : free) axpy(step, &g[3 * size_t(i)], &x_[3 * size_t(i)]);
      fineValid_ = false;
      continue;
    }
    if (tensor) {
      // Along the same direction, Newton on phi(s) = Theta(c + s g_F), each evaluation a few
      // hundred flops: the same root the matrix-free path finds on its cubic.
      std::vector<double> trial(cage.size()), gt(cage.size());
      double s = step;
      for (int n = 0; n < 60; ++n) {
        trial = cage;
        for (uint32_t i : free) axpy(s, &g[3 * size_t(i)], &trial[3 * size_t(i)]);
        const double f = polynomial_->evaluate(trial.data(), gt.data()) - reference_;
        double df = 0;
        for (uint32_t i : free) df += dot(&gt[3 * size_t(i)], &g[3 * size_t(i)]);
        if (!(df != 0) || !std::isfinite(f)) break;
        const double next = s - f / df;
        if (!std::isfinite(next) || std::fabs(next - step) > 4 * std::fabs(step) + 1e-300) break;
        const bool done = std::fabs(next - s) <= 1e-15 * std::fabs(s);
        s = next;
        if (done) break;
      }
      for (uint32_t i : free) axpy(s, &g[3 * size_t(i)], &x_[3 * size_t(i)]);
      fineValid_ = false;
      continue;
    }
    // Matrix-free: along that same direction the volume is a cubic in the step length, whose
    // coefficients one pass over the triangles gives; solving it exactly replaces the further
    // linearized iterations (each a synthesis and an adjoint).
    const std::vector<double>& p = fine();
    q.assign(x_.size(), 0.0);
    for (uint32_t i : free)
      for (int k = 0; k < 3; ++k) q[3 * size_t(i) + k] = g[3 * size_t(i) + k];
    if (freeDetailLevels_.empty()) transform_->synthesizeZeroDetails(q.data(), level_);
    else transform_->synthesize(q.data(), level_);
    // c0 = v and c1 = g_F . g_F (the derivative along the direction) are known; one pass gives
    // c2 = sum a.(qb x qd) + qa.(b x qd + qb x d) and c3 = sum qa.(qb x qd), over 6.
    double c[4] = {v * 6.0, norm2 * 6.0, 0, 0};
    const auto& faces = hierarchy_->fineFaces();
    const double org[3] = {origin_.x, origin_.y, origin_.z};
    double t[3], u[3];
    for (size_t f = 0; f < faces.size(); f += 3) {
      const size_t ia = 3 * size_t(faces[f]), ib = 3 * size_t(faces[f + 1]), id = 3 * size_t(faces[f + 2]);
      const double *qa = &q[ia], *qb = &q[ib], *qd = &q[id];
      const double a[3] = {p[ia] - org[0], p[ia + 1] - org[1], p[ia + 2] - org[2]};
      const double b[3] = {p[ib] - org[0], p[ib + 1] - org[1], p[ib + 2] - org[2]};
      const double d[3] = {p[id] - org[0], p[id + 1] - org[1], p[id + 2] - org[2]};
      cross(qb, qd, t);
      c[3] += dot(qa, t);
      c[2] += dot(a, t);
      cross(b, qd, t);
      cross(qb, d, u);
      c[2] += qa[0] * (t[0] + u[0]) + qa[1] * (t[1] + u[1]) + qa[2] * (t[2] + u[2]);
    }
    for (double& k : c) k /= 6.0;
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
    for (size_t i = 0; i < q.size(); ++i) fine_[i] += s * q[i];  // fine() stays in step with x_
    cachedVolume_ = c[0] + s * (c[1] + s * (c[2] + s * c[3]));
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
  return out;
}

}  // namespace mrvol
