// The volume enclosed by the Loop limit surface of a closed triangle mesh (the surface that
// zero-detail Loop synthesis converges to), as an alternating trilinear form of the mesh's own
// vertex positions: V = sum_t w_t det(p_a, p_b, p_c). Its coefficients depend only on the local
// connectivity and Loop's rules: regular faces by exact integration of the quartic box-spline
// patch, faces at an extraordinary vertex by a per-valence fixed point over local subdivision
// (docs/limit-volume.md has every formula and convention).
#pragma once
#include <cstdint>
#include <vector>

#include "mrvol/corners.h"
#include "mrvol/mesh.h"
#include "mrvol/volume_tensor.h"

namespace mrvol {

// Valences the per-valence tables are built for (3 .. kMaxLimitValence).
constexpr int kMaxLimitValence = 64;

// The limit-volume form on the vertices of a closed mesh: entries (a < b < c) with their weights,
// sorted, duplicates merged. faces: 3 * faceCount indices, counter-clockwise seen from outside.
// Throws Error for a mesh with boundary or a vertex of valence beyond kMaxLimitValence. The mesh
// must be a valid oriented 2-manifold (validateMesh).
FineForm limitVolumeForm(const uint32_t* faces, size_t faceCount, size_t vertexCount);

// The enclosed volume of the Loop limit surface of a closed mesh (validated here), evaluated in the
// frame of volumeReferencePoint like meshVolume.
double limitVolume(const TriangleMesh& mesh);

namespace limit_detail {
// The local net of face (a, b, c) (counter-clockwise): a, the ring of a from b (n_a vertices),
// then the three vertices of b's ring after (c, a, ring_a[n-1]), then two of c's ring after
// (a, b, d): n_a + 6 vertices when b and c have valence 6 (with a regular too: the 12-vertex
// box-spline net). Walks the corners, so a small mesh whose net wraps onto itself repeats vertices.
std::vector<uint32_t> patchNet(const VertexCorners& corners, uint32_t a, uint32_t b, uint32_t c);

// The contribution of one face's limit patch to the volume, as entries (s0 < s1 < s2) on the
// slots of its net: valence 6 is the regular (box-spline) face, others a face whose first corner
// has that valence and whose other two are regular. Built on first use and kept.
const FineForm& patchForm(int valence);

// Residual of the per-valence fixed point X = Q + X o A^(x3), relative to |X| (max norms).
double patchFixedPointResidual(int valence);
// The fixed point computed afresh for any valence, 6 included (where it must equal the regular
// face's polynomial integration): for tests.
FineForm fixedPointPatchForm(int valence);
}  // namespace limit_detail

}  // namespace mrvol
