// The volume of a quad mesh whose quads are bilinear patches (docs/catmull-clark.md, section 4):
// the cone volume of the patch through p0 p1 p2 p3 is exactly
//   (det(p0,p1,p2) + det(p0,p2,p3) + det(p0,p1,p3) + det(p1,p2,p3)) / 12,
// the mean of its two triangulations: a trilinear form of the corners, so theta^n stays a
// trilinear tensor (a FineForm of four weighted triangles per quad). The same sum is
// (p0 + p1 + p2 + p3) . ((p2 - p0) x (p3 - p1)) / 24: a third of the centroid against the vector
// area, one cross product per quad (QuadPatchVolume, the matrix-free path's pass).
#pragma once
#include <cstdint>
#include <vector>

#include "mrvol/cage_polynomial_builder.h"
#include "mrvol/mesh.h"
#include "mrvol/quad_hierarchy.h"
#include "mrvol/volume_function.h"
#include "mrvol/volume_tensor.h"

namespace mrvol {

// The four triangles of weight 1/12 of every quad: (a, b, c), (a, c, d), (a, b, d), (b, c, d).
FineForm bilinearPatchForm(const std::vector<uint32_t>& quads);

// The fine quads' bilinearPatchForm grouped by level-e quad, for CagePolynomialBuilder: the fine
// quads of level-e quad r are 4^(n-e) r .. 4^(n-e) (r + 1) - 1 (the splits keep child quads
// together). Carried by the fine quads' corner 0 (born before the last split) and, for the term
// without it, corner 2 (the face point): about half the vertices carry terms.
RegionForm bilinearPatchRegions(const QuadHierarchy& hierarchy, int level);

// The reference point of volumeReferencePoint for the quads' triangulation (bounding-box centre of
// a closed mesh, centroid of the boundary vertices otherwise).
Vec3 quadReferencePoint(const QuadMesh& mesh);
// Signed volume enclosed by the bilinear patches (cone volume to the reference point when open).
double bilinearVolume(const QuadMesh& mesh);

// The bilinear patches' volume over N + 1 positions (as FormVolume), one cross product per quad.
class QuadPatchVolume final : public VolumeFunction {
 public:
  // `quads` (4 per face) must outlive this; its indices are in [0, vertexCount).
  QuadPatchVolume(const std::vector<uint32_t>& quads, uint32_t vertexCount) : quads_(&quads), vertexCount_(vertexCount) {}
  size_t size() const override { return 3 * (size_t(vertexCount_) + 1); }
  double value(const double* x, double* gradient) const override;
  void alongDirection(const double* x, const double* d, double* k, bool lowKnown = false) const override;

 private:
  const std::vector<uint32_t>* quads_;
  uint32_t vertexCount_;
};

// The first moment along axis k of the solid enclosed by the bilinear patches, about a centre q
// (FirstMoment's for quads): over each patch p(u, v) the cone to the origin has the moment
//   (1/4) int p_k det(p, p_u, p_v) du dv - (q_k / 3) int det(p, p_u, p_v) du dv,
// the second integral being three times the patch's cone volume (QuadPatchVolume). The integrand
// is of degree 3 in u and in v, so 2 x 2 Gauss points give it exactly. Over the same N + 1
// positions; with q = 0 it is V c_k for the centre of mass c.
class QuadFirstMoment final : public MomentFunction {
 public:
  // `quads` (4 per face) must outlive this; axis 0, 1 or 2.
  QuadFirstMoment(const std::vector<uint32_t>& quads, uint32_t vertexCount, int axis);
  size_t size() const override { return 3 * (size_t(vertexCount_) + 1); }
  double value(const double* x, double* gradient) const override;

 private:
  const std::vector<uint32_t>* quads_;
  uint32_t vertexCount_;
  int axis_;
};

}  // namespace mrvol
