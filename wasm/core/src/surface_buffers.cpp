#include "mrvol/surface_buffers.h"

#include <algorithm>
#include <cmath>

namespace mrvol {

SurfaceBuffers::SurfaceBuffers(const Hierarchy& hierarchy)
    : hierarchy_(&hierarchy), vertexCount_(hierarchy.fineVertexCount()) {
  callerIsHierarchyOrder_ = true;
  for (size_t h = 0; h < vertexCount_ && callerIsHierarchyOrder_; ++h) callerIsHierarchyOrder_ = hierarchy.inputIndex[h] == h;
  positions_.assign(3 * vertexCount_, 0.0f);
  normals_.assign(3 * vertexCount_, 0.0f);
}

void SurfaceBuffers::update(const double* fine, Vec3 origin, uint64_t version, bool withNormals) {
  if (positionsOf_ != version + 1) {
    writePositions(fine, origin);
    positionsOf_ = version + 1;
    ++writes_;
  }
  if (withNormals && normalsOf_ != version + 1) {
    writeNormals(fine);
    normalsOf_ = version + 1;
  }
}

void SurfaceBuffers::writePositions(const double* fine, Vec3 o) {
  float* out = positions_.data();
  const size_t n = vertexCount_;
  if (callerIsHierarchyOrder_) {
    for (size_t i = 0; i < n; ++i) {  // contiguous: the compiler vectorizes it
      out[3 * i] = float(fine[3 * i] + o.x);
      out[3 * i + 1] = float(fine[3 * i + 1] + o.y);
      out[3 * i + 2] = float(fine[3 * i + 2] + o.z);
    }
    return;
  }
  const uint32_t* caller = hierarchy_->inputIndex.data();
  for (size_t h = 0; h < n; ++h) {
    float* p = out + 3 * size_t(caller[h]);
    p[0] = float(fine[3 * h] + o.x), p[1] = float(fine[3 * h + 1] + o.y), p[2] = float(fine[3 * h + 2] + o.z);
  }
}

void SurfaceBuffers::writeNormals(const double* fine) {
  // Sum of the faces' cross products (twice their area times their normal) at each corner. The edges
  // come from the positions relative to the reference point in doubles: no cancellation in float.
  float* sum = callerIsHierarchyOrder_ ? normals_.data() : (sums_.resize(3 * vertexCount_), sums_.data());
  std::fill(sum, sum + 3 * vertexCount_, 0.0f);
  const std::vector<uint32_t>& faces = hierarchy_->fineFaces();
  const uint32_t* f = faces.data();
  for (size_t t = 0, end = faces.size(); t < end; t += 3) {
    const double* a = fine + 3 * size_t(f[t]);
    const double* b = fine + 3 * size_t(f[t + 1]);
    const double* c = fine + 3 * size_t(f[t + 2]);
    const double ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
    const double vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
    const float nx = float(uy * vz - uz * vy), ny = float(uz * vx - ux * vz), nz = float(ux * vy - uy * vx);
    for (int k = 0; k < 3; ++k) {
      float* s = sum + 3 * size_t(f[t + k]);
      s[0] += nx, s[1] += ny, s[2] += nz;
    }
  }
  // Unit length (a vertex of no area keeps zero, as three.js's computeVertexNormals leaves it).
  const uint32_t* caller = hierarchy_->inputIndex.data();
  float* out = normals_.data();
  for (size_t h = 0; h < vertexCount_; ++h) {
    const float x = sum[3 * h], y = sum[3 * h + 1], z = sum[3 * h + 2];
    const float length = std::sqrt(x * x + y * y + z * z);
    const float scale = length > 0.0f ? 1.0f / length : 0.0f;
    float* n = out + 3 * size_t(callerIsHierarchyOrder_ ? h : caller[h]);
    n[0] = x * scale, n[1] = y * scale, n[2] = z * scale;
  }
}

}  // namespace mrvol
