// A volume as a function of a flat array of 3-vectors x (fine positions or level-e coefficients):
// its value, its gradient, and the cubic it is along a line. A volume is a cubic form of the
// positions, so along x + s d it is exactly k0 + k1 s + k2 s^2 + k3 s^3: one expansion replaces
// further linearized iterations of the solver.
//
// Implemented by the cage polynomial (cage_polynomial.h, over the cage coefficients) and, over the
// fine positions, by the volume of all fine triangles (a pass over the edges) and the volume of a
// part of them (a pass over its triangles).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace mrvol {

struct FineForm;

// A scalar of x (3 per vertex) with its gradient: what a constraint row of the solver needs.
class FineFunction {
 public:
  virtual ~FineFunction() = default;
  // Doubles in x, the gradient and a direction (3 per vertex).
  virtual size_t size() const = 0;
  // The value at x and, if `gradient` is not null, its gradient (size() doubles, overwritten).
  virtual double value(const double* x, double* gradient) const = 0;
};

// A volume: a cubic form, so also exactly a cubic along any line.
class VolumeFunction : public FineFunction {
 public:
  // The cubic s -> V(x + s d): k[0] + k[1] s + k[2] s^2 + k[3] s^3. With lowKnown the caller has
  // already put V(x) in k[0] and grad V(x) . d in k[1] (an implementation may still recompute them).
  virtual void alongDirection(const double* x, const double* d, double* k, bool lowKnown = false) const = 0;
};

// The volume enclosed by fine triangles about a reference point, over positions of N + 1 vertices:
// the N mesh vertices (relative to the point) and vertex N at it, which closes boundary loops as
// cones. Vertex N stays at zero (in x and in directions): the pass lists only the mesh's edges.
// One pass over the edges, each edge's b x c serving both its triangles.
class FineEdgeVolume final : public VolumeFunction {
 public:
  // A validated, consistently oriented manifold (closed or bounded) with `vertexCount` vertices.
  FineEdgeVolume(const std::vector<uint32_t>& faces, uint32_t vertexCount);
  size_t size() const override { return 3 * (size_t(vertexCount_) + 1); }
  double value(const double* x, double* gradient) const override;
  void alongDirection(const double* x, const double* d, double* k, bool lowKnown = false) const override;

 private:
  uint32_t vertexCount_;
  // Every edge once, 4 indices each: its ends b, c and the vertices opposite it, a in the triangle
  // (a, b, c) and d in (d, c, b), d = N on the boundary; sorted by the ends, so that the passes
  // over it walk the vertex arrays nearly in order.
  std::vector<uint32_t> edges_;
};

// The volume of some of the fine triangles (a part of the mesh), as cones to the reference point,
// over the same N + 1 positions.
class TriangleSetVolume final : public VolumeFunction {
 public:
  // `faces` (3 per triangle) must outlive this; `triangles` flags the triangles that count.
  TriangleSetVolume(const std::vector<uint32_t>& faces, uint32_t vertexCount, std::vector<uint8_t> triangles);
  size_t size() const override { return 3 * (size_t(vertexCount_) + 1); }
  double value(const double* x, double* gradient) const override;
  void alongDirection(const double* x, const double* d, double* k, bool lowKnown = false) const override;

 private:
  const std::vector<uint32_t>* faces_;
  uint32_t vertexCount_;
  std::vector<uint8_t> triangles_;
};

// A trilinear form of the fine positions as a volume, sum_t w_t det(p_a, p_b, p_c) (FineForm: the
// Loop limit surface's volume, limit_volume.h), over the same N + 1 positions as above (vertex N,
// the reference point, is in no entry). The entries are kept as runs of one pair (a, b): a run
// shares p_a x p_b, and S = sum_c w_c p_c serves its value and its gradient at a and b.
class FormVolume final : public VolumeFunction {
 public:
  // Entries with indices below vertexCount (hierarchy numbering, like the positions).
  FormVolume(const FineForm& form, uint32_t vertexCount);
  size_t size() const override { return 3 * (size_t(vertexCount_) + 1); }
  double value(const double* x, double* gradient) const override;
  void alongDirection(const double* x, const double* d, double* k, bool lowKnown = false) const override;
  size_t entryCount() const { return c_.size(); }

 private:
  uint32_t vertexCount_;
  std::vector<uint32_t> pairA_, pairB_;
  std::vector<uint64_t> runStart_;  // one more than the pairs
  std::vector<uint32_t> c_;
  std::vector<double> weight_;
};

// A first moment of the enclosed solid about a centre q on one axis (FirstMoment for triangles,
// QuadFirstMoment for bilinear patches): the rows that keep a centre of mass.
class MomentFunction : public FineFunction {
 public:
  void setCentre(double q) { centre_ = q; }
  double centre() const { return centre_; }

 protected:
  double centre_ = 0;
};

// One first moment of the enclosed solid about a centre q on axis k (coordinates relative to the
// reference point), M_k - q_k V = sum over triangles det(a, b, c) ((a_k + b_k + c_k) / 24 - q_k / 6):
// each cone's volume times the k-th coordinate of its centroid (a + b + c) / 4, less q_k. With q = 0
// it is V c_k for the centre of mass c; it vanishes when c_k = q_k, whatever the volume. Over the same
// N + 1 positions; boundary loops close as cones, which add nothing here. A quadrilinear form (a
// quartic of the positions) for q fixed.
class FirstMoment final : public MomentFunction {
 public:
  // `faces` (3 per triangle) must outlive this; axis 0, 1 or 2.
  FirstMoment(const std::vector<uint32_t>& faces, uint32_t vertexCount, int axis);
  size_t size() const override { return 3 * (size_t(vertexCount_) + 1); }
  double value(const double* x, double* gradient) const override;

  // The enclosed volume (sum det / 6) and the three first moments about `centre` in one pass over
  // the triangles, where the volume's pass and three value() calls make four: what a centre of mass
  // needs. Summed per fixed block of triangles, the blocks in order: the same sums at any thread count.
  static double volumeAndMoments(const std::vector<uint32_t>& faces, const double* x, const double centre[3], double moments[3]);

  // The three moments `axes` (axis 0, 1 and 2 on the same faces) with their gradients in one pass
  // over the triangles: a triangle's cross products and determinant serve the three, and a corner's
  // nine gradient entries are side by side. `gradients`: 9 per vertex (size() / 3 vertices), axis
  // 0's 3-vector, then axis 1's and axis 2's; overwritten. The values and gradients are those of
  // three value() calls, bit for bit (the same sums in the same order). Returns false, computing
  // nothing, when `axes` are not such a triple.
  static bool valuesWithGradients(const FineFunction* const axes[3], const double* x, double values[3], double* gradients);

 private:
  const std::vector<uint32_t>* faces_;
  uint32_t vertexCount_;
  int axis_;
};

}  // namespace mrvol
