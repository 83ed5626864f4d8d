#include "mrvol/surface_buffers.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#ifdef __wasm_simd128__
#include <wasm_simd128.h>
#endif

namespace mrvol {

SurfaceBuffers::SurfaceBuffers(const Hierarchy& hierarchy)
    : hierarchy_(&hierarchy), vertexCount_(hierarchy.fineVertexCount()) {
  callerIsHierarchyOrder_ = true;
  for (size_t h = 0; h < vertexCount_ && callerIsHierarchyOrder_; ++h) callerIsHierarchyOrder_ = hierarchy.inputIndex[h] == h;
  positions_.assign(3 * vertexCount_, 0.0f);
  normals_.assign(3 * vertexCount_, 0.0f);
}

void SurfaceBuffers::merge(FinePositions::Changes& into, const FinePositions::Changes& changes) {
  if (into.whole) return;
  if (changes.whole) {
    into = FinePositions::Changes{};
    return;
  }
  into.vertices.insert(into.vertices.end(), changes.vertices.begin(), changes.vertices.end());
}

void SurfaceBuffers::update(const double* fine, Vec3 origin, uint64_t version, const FinePositions::Changes& changes,
                            bool withNormals) {
  merge(pendingPositions_, changes);
  merge(pendingNormals_, changes);
  const size_t n = vertexCount_;
  if (pendingPositions_.whole || pendingPositions_.vertices.size() > n / 8) pendingPositions_ = FinePositions::Changes{};
  if (pendingNormals_.whole || pendingNormals_.vertices.size() > n / 8) pendingNormals_ = FinePositions::Changes{};
  if (positionsOf_ != version + 1) {
    writePositions(fine, origin);
    positionsOf_ = version + 1;
    ++writes_;
  }
  pendingPositions_ = FinePositions::Changes{false, {}};
  if (withNormals && normalsOf_ != version + 1) {
    if (pendingNormals_.whole || !normalsWritten_) writeNormals(fine);
    else writeSomeNormals(fine);
    normalsWritten_ = true;
    normalsOf_ = version + 1;
    pendingNormals_ = FinePositions::Changes{false, {}};
  }
}

void SurfaceBuffers::writePositions(const double* fine, Vec3 o) {
  float* out = positions_.data();
  const size_t n = vertexCount_;
  const uint32_t* caller = hierarchy_->inputIndex.data();
  if (!pendingPositions_.whole) {  // the vertices the stencils touched
    uint32_t first = UINT32_MAX, end = 0;
    for (uint32_t h : pendingPositions_.vertices) {
      const uint32_t v = caller[h];
      float* p = out + 3 * size_t(v);
      p[0] = float(fine[3 * size_t(h)] + o.x), p[1] = float(fine[3 * size_t(h) + 1] + o.y), p[2] = float(fine[3 * size_t(h) + 2] + o.z);
      first = std::min(first, v), end = std::max(end, v + 1);
    }
    positionsRange_[0] = first == UINT32_MAX ? 0 : first, positionsRange_[1] = end;
    return;
  }
  positionsRange_[0] = 0, positionsRange_[1] = uint32_t(n);
  if (callerIsHierarchyOrder_) {
    for (size_t i = 0; i < n; ++i) {  // contiguous: the compiler vectorizes it
      out[3 * i] = float(fine[3 * i] + o.x);
      out[3 * i + 1] = float(fine[3 * i + 1] + o.y);
      out[3 * i + 2] = float(fine[3 * i + 2] + o.z);
    }
    return;
  }
  for (size_t h = 0; h < n; ++h) {
    float* p = out + 3 * size_t(caller[h]);
    p[0] = float(fine[3 * h] + o.x), p[1] = float(fine[3 * h + 1] + o.y), p[2] = float(fine[3 * h + 2] + o.z);
  }
}

void SurfaceBuffers::writeSomeNormals(const double* fine) {
  const size_t n = vertexCount_;
  const uint32_t* caller = hierarchy_->inputIndex.data();
  if (vertexFaceStart_.empty()) {  // once: the faces around each vertex
    vertexFaceStart_.assign(n + 1, 0);
    for (uint32_t v : faces_) ++vertexFaceStart_[v + 1];
    for (size_t v = 0; v < n; ++v) vertexFaceStart_[v + 1] += vertexFaceStart_[v];
    vertexFaces_.resize(faces_.size());
    std::vector<uint32_t> next(vertexFaceStart_.begin(), vertexFaceStart_.end() - 1);
    for (size_t c = 0; c < faces_.size(); ++c) vertexFaces_[next[faces_[c]]++] = uint32_t(c / 3);
    mark_.assign(n, 0);
  }
  if (++markRound_ == 0) std::fill(mark_.begin(), mark_.end(), 0), markRound_ = 1;
  // The moved vertices' relative positions, then every vertex of a face around them is affected.
  float* r = relative_.data();
  for (uint32_t h : pendingNormals_.vertices) {
    float* p = r + 4 * size_t(caller[h]);
    p[0] = float(fine[3 * size_t(h)]), p[1] = float(fine[3 * size_t(h) + 1]), p[2] = float(fine[3 * size_t(h) + 2]);
  }
  affected_.clear();
  for (uint32_t h : pendingNormals_.vertices) {
    const uint32_t v = caller[h];
    for (uint32_t k = vertexFaceStart_[v]; k < vertexFaceStart_[v + 1]; ++k)
      for (int c = 0; c < 3; ++c) {
        const uint32_t w = faces_[3 * size_t(vertexFaces_[k]) + c];
        if (mark_[w] != markRound_) mark_[w] = markRound_, affected_.push_back(w);
      }
  }
  // Each affected vertex's sum again from its faces (in doubles of the float positions), normalized.
  uint32_t first = UINT32_MAX, end = 0;
  for (uint32_t v : affected_) {
    double sum[3] = {0, 0, 0};
    for (uint32_t k = vertexFaceStart_[v]; k < vertexFaceStart_[v + 1]; ++k) {
      const uint32_t* f = &faces_[3 * size_t(vertexFaces_[k])];
      const float* a = r + 4 * size_t(f[0]);
      const float* b = r + 4 * size_t(f[1]);
      const float* c = r + 4 * size_t(f[2]);
      const float ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
      const float vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
      sum[0] += uy * vz - uz * vy, sum[1] += uz * vx - ux * vz, sum[2] += ux * vy - uy * vx;
    }
    const double length = std::sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
    const double scale = length > 0 ? 1.0 / length : 0.0;
    float* o = normals_.data() + 3 * size_t(v);
    o[0] = float(sum[0] * scale), o[1] = float(sum[1] * scale), o[2] = float(sum[2] * scale);
    first = std::min(first, v), end = std::max(end, v + 1);
  }
  normalsRange_[0] = first == UINT32_MAX ? 0 : first, normalsRange_[1] = end;
}

void SurfaceBuffers::writeNormals(const double* fine) {
  // All in the caller's order, which the output has: a pass in another order would need two
  // permutations, each a cache miss per vertex (measured slower than the face pass they save).
  const size_t n = vertexCount_;
  const uint32_t* caller = hierarchy_->inputIndex.data();
  if (faces_.empty()) {  // once: the faces in the caller's indices, by their last vertex (nearby memory in turn)
    const std::vector<uint32_t>& fineFaces = hierarchy_->fineFaces();
    const size_t m = fineFaces.size() / 3;
    std::vector<uint32_t> order(m), last(m);
    for (size_t t = 0; t < m; ++t) {
      order[t] = uint32_t(t);
      last[t] = std::max({caller[fineFaces[3 * t]], caller[fineFaces[3 * t + 1]], caller[fineFaces[3 * t + 2]]});
    }
    std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return last[a] < last[b]; });
    faces_.resize(fineFaces.size());
    for (size_t t = 0; t < m; ++t)
      for (int k = 0; k < 3; ++k) faces_[3 * t + k] = caller[fineFaces[3 * size_t(order[t]) + k]];
  }
  // Relative to the reference point (inside the mesh): no cancellation in float.
  relative_.resize(4 * n);
  sums_.assign(4 * n, 0.0f);
  float* r = relative_.data();
  for (size_t h = 0; h < n; ++h) {
    float* p = r + 4 * size_t(callerIsHierarchyOrder_ ? uint32_t(h) : caller[h]);
    p[0] = float(fine[3 * h]), p[1] = float(fine[3 * h + 1]), p[2] = float(fine[3 * h + 2]), p[3] = 0.0f;
  }
  // Each face's cross product (twice its area times its normal) added at its corners.
  float* sum = sums_.data();
  const uint32_t* f = faces_.data();
  const size_t end = faces_.size();
#ifdef __wasm_simd128__
  for (size_t t = 0; t < end; t += 3) {
    float* sa = sum + 4 * size_t(f[t]);
    float* sb = sum + 4 * size_t(f[t + 1]);
    float* sc = sum + 4 * size_t(f[t + 2]);
    const v128_t a = wasm_v128_load(r + 4 * size_t(f[t]));
    const v128_t u = wasm_f32x4_sub(wasm_v128_load(r + 4 * size_t(f[t + 1])), a);
    const v128_t v = wasm_f32x4_sub(wasm_v128_load(r + 4 * size_t(f[t + 2])), a);
    // u x v = u.yzx * v.zxy - u.zxy * v.yzx (lane 3 stays 0)
    const v128_t cross = wasm_f32x4_sub(
        wasm_f32x4_mul(wasm_i32x4_shuffle(u, u, 1, 2, 0, 3), wasm_i32x4_shuffle(v, v, 2, 0, 1, 3)),
        wasm_f32x4_mul(wasm_i32x4_shuffle(u, u, 2, 0, 1, 3), wasm_i32x4_shuffle(v, v, 1, 2, 0, 3)));
    wasm_v128_store(sa, wasm_f32x4_add(wasm_v128_load(sa), cross));
    wasm_v128_store(sb, wasm_f32x4_add(wasm_v128_load(sb), cross));
    wasm_v128_store(sc, wasm_f32x4_add(wasm_v128_load(sc), cross));
  }
#else
  for (size_t t = 0; t < end; t += 3) {
    const float* a = r + 4 * size_t(f[t]);
    const float* b = r + 4 * size_t(f[t + 1]);
    const float* c = r + 4 * size_t(f[t + 2]);
    const float ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
    const float vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
    const float nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
    for (int k = 0; k < 3; ++k) {
      float* s = sum + 4 * size_t(f[t + k]);
      s[0] += nx, s[1] += ny, s[2] += nz;
    }
  }
#endif
  // Unit length (a vertex of no area keeps zero, as three.js's computeVertexNormals leaves it).
  normalsRange_[0] = 0, normalsRange_[1] = uint32_t(n);
  float* out = normals_.data();
  for (size_t v = 0; v < n; ++v) {
    const float x = sum[4 * v], y = sum[4 * v + 1], z = sum[4 * v + 2];
    const float length = std::sqrt(x * x + y * y + z * z);
    const float scale = length > 0.0f ? 1.0f / length : 0.0f;
    out[3 * v] = x * scale, out[3 * v + 1] = y * scale, out[3 * v + 2] = z * scale;
  }
}

}  // namespace mrvol
