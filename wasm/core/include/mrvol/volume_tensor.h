// The volume tensor theta^e (method section 6): the enclosed volume as an alternating trilinear
// form of the level-e coefficients, Theta = sum_{i<j<k} T_ijk det(p_i, p_j, p_k), computed from
// the fine triangles by the transposed synthesis steps applied along the three axes.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "mrvol/lifting.h"

namespace mrvol {

// theta^n, the volume as a trilinear form of the fine positions: Theta = sum_t weights[t]
// det(p_a, p_b, p_c) with (a, b, c) = corners[3t .. 3t+2] (hierarchy numbering when it enters the
// tensor). The fine triangles with weight 1/6 are the mesh's own volume (triangleForm); the Loop
// limit surface's volume is another such form (limit_volume.h).
struct FineForm {
  std::vector<uint32_t> corners;
  std::vector<double> weights;
  size_t size() const { return weights.size(); }
  // sum_t w_t det(p_a - o, p_b - o, p_c - o); x: 3 per vertex.
  double evaluate(const double* x, Vec3 origin = {}) const;
};
FineForm triangleForm(const std::vector<uint32_t>& faces);

// Which entries are kept. Cage: only rows whose smallest index is a level-e coarse vertex (the
// cage), which is all the gradient with respect to the cage needs; entries made of details only
// fold into a constant that depends on the (fixed) details. Full: every entry, for teaching views.
enum class TensorStorage : uint8_t { Cage = 0, Full = 1 };

// Compact static layout, rows by first index i, then pairs (i, j), then entries k (i < j < k):
//   pairs of row i:  [rowStart[i], rowStart[i+1]),  pair p has j = pairJ[p]
//   entries of p:    [pairStart[p], pairStart[p+1]), entry t has k = kIndex(t), value = values[t]
// k is stored in 16 bits when N <= 65536 (10 bytes per entry plus the pair table), else 32.
class VolumeTensor {
 public:
  int level = 0;
  TensorStorage storage = TensorStorage::Cage;
  uint32_t vertexCount = 0;  // N (all coefficients at level e, hierarchy numbering)
  uint32_t rowCount = 0;     // V_e for Cage, N for Full
  uint64_t nnzFull = 0;      // non-zeros of the whole N^3 tensor (all orderings); 0 = unknown (Cage)
  std::vector<uint32_t> rowStart, pairJ, pairStart;
  std::vector<uint16_t> k16;
  std::vector<uint32_t> k32;
  std::vector<double> values;

  size_t storedCount() const { return values.size(); }
  size_t bytes() const;  // memory of the arrays above
  uint32_t kIndex(size_t t) const { return k16.empty() ? k32[t] : k16[t]; }

  // The stored entries as coordinate lists, in storage order: i < j < k in hierarchy numbering
  // (for teaching views and checks; the CSR arrays stay the storage).
  struct Entries {
    std::vector<uint32_t> i, j, k;
    std::vector<double> values;
  };
  Entries entries() const;

  // Theta(x) over the stored entries; x: 3 * N level-e coefficients in hierarchy order.
  double evaluate(const double* x) const;
  // Theta(x) and its gradient for the coefficients [0, gradientLimit) (Theta_tau(i), 3 per index);
  // grad must hold 3 * gradientLimit doubles, it is overwritten.
  double evaluateWithGradient(const double* x, double* grad, uint32_t gradientLimit) const;
  // Terms of Theta that involve at least one of the coefficients flagged in `moving`
  // (size N): the volume change when only those move is the difference of this before and after.
  double evaluateInvolving(const double* x, const std::vector<uint8_t>& moving) const;
};

struct TensorProgress {
  // Called between steps with a fraction in [0, 1]; return false to cancel (throws Error "cancelled").
  bool (*callback)(double fraction, void* user) = nullptr;
  void* user = nullptr;
};

// theta^e by the recursion theta^{l-1} = theta^l transformed by the transposed synthesis of level l
// along each axis. Throws Error when the work would exceed maxTerms terms in flight.
VolumeTensor computeVolumeTensor(const WaveletTransform& transform, int level, TensorStorage storage,
                                 const TensorProgress& progress = {}, uint64_t maxTerms = 400'000'000);
// The same transposed lifting started from any fine form instead of the fine triangles.
VolumeTensor computeVolumeTensor(const WaveletTransform& transform, int level, TensorStorage storage,
                                 const FineForm& fine, const TensorProgress& progress = {},
                                 uint64_t maxTerms = 400'000'000);

// What computing the cage rows of theta^e would take, from the patches of a few sampled cage
// vertices (a synthesis each, no tensor work): the editor uses the tensor when this fits.
struct TensorEstimate {
  uint32_t cageSize = 0, maxPatch = 0;
  uint64_t entries = 0, bytes = 0, denseBytes = 0;
  double milliseconds = 0;
  // The policy of "tensor when it fits": at most 512 MB stored, a 1 GB working patch, ~15 s.
  bool fits() const { return bytes <= (uint64_t(512) << 20) && denseBytes <= (uint64_t(1) << 30) && milliseconds <= 15000; }
};
TensorEstimate estimateCageTensor(const WaveletTransform& transform, int level, int samples = 16);

// The same tensor built directly as sum over fine triangles (a, b, c) of alt(R_a x R_b x R_c) / 6
// with R the synthesis operator from level e (rows assembled by synthesis of unit vectors).
// O(N^2) memory: for tests on small meshes only.
VolumeTensor computeVolumeTensorDirect(const WaveletTransform& transform, int level, TensorStorage storage);
VolumeTensor computeVolumeTensorDirect(const WaveletTransform& transform, int level, TensorStorage storage,
                                       const FineForm& fine);

// Theta files: a versioned binary header (magic, format version, scheme and parameters, n, e,
// storage mode, connectivity fingerprint, counts), the arrays, then a checksum of all before it.
constexpr uint32_t kThetaFormatVersion = 1;

struct ThetaFileHeader {
  uint32_t formatVersion = kThetaFormatVersion;
  SchemeOptions scheme;
  int levels = 0;
  int level = 0;
  TensorStorage storage = TensorStorage::Cage;
  uint64_t fingerprint = 0;
  uint32_t vertexCount = 0;
  uint64_t nnzFull = 0, nnzStored = 0;
  bool limitSurface = false;  // theta of the Loop limit surface's volume (limit_volume.h), not the mesh's
};

// A tensor with the header that identifies what it was computed for.
struct Theta {
  VolumeTensor tensor;
  ThetaFileHeader header;
};

// 64-bit fingerprint of connectivity: vertex count and faces, in the caller's order.
uint64_t connectivityFingerprint(const std::vector<uint32_t>& faces, size_t vertexCount);

std::string writeThetaFile(const VolumeTensor& tensor, const ThetaFileHeader& header);
// Reads and checks a theta file (magic, version, checksum, structure). Throws Error naming the
// problem: truncated, corrupt, future version ...
VolumeTensor readThetaFile(const std::string& bytes, ThetaFileHeader* header = nullptr);
// Header only (cheap), with the same checks on the header bytes.
ThetaFileHeader readThetaHeader(const std::string& bytes);
// The checksum a theta file ends with: a word-wise hash of all bytes before it.
uint64_t thetaFileChecksum(const char* data, size_t size);

}  // namespace mrvol
