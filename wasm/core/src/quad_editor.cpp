#include "mrvol/quad_editor.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "mrvol/error.h"

namespace mrvol {

namespace {
SessionCoefficients startSession(const QuadHierarchy& h, const WaveletTransform& transform, int level,
                                 const double* positions) {
  QuadMesh fine;
  fine.positions.resize(3 * h.h.fineVertexCount());
  h.h.toHierarchyOrder(positions, fine.positions.data());
  for (double v : fine.positions)
    if (!std::isfinite(v)) throw Error("positions must be finite numbers");
  fine.quads = h.fineQuads();
  const Vec3 origin = quadReferencePoint(fine);
  transform.analyze(fine.positions.data(), level);
  for (double v : fine.positions)
    if (!std::isfinite(v))
      throw Error("analysis cannot reach level " + std::to_string(level) +
                  " of this mesh (a cube's first Catmull-Clark split is not invertible): edit at level 1 or above");
  return SessionCoefficients{std::move(fine.positions), FinePositions(transform, level, origin), origin,
                             h.h.vertexCount[level]};
}

}  // namespace

QuadVolumeEditor::QuadVolumeEditor(const QuadHierarchy& hierarchy, const WaveletTransform& transform, int level,
                                   const double* positions)
    : CageEditor(hierarchy.h, transform, checkedLevel(hierarchy.h, level),
                 startSession(hierarchy, transform, checkedLevel(hierarchy.h, level), positions)),
      quadHierarchy_(&hierarchy),
      fineVolume_(hierarchy.fineQuads(), uint32_t(hierarchy.h.fineVertexCount())) {
  for (int k = 0; k < 3; ++k)
    moments_.push_back(std::make_unique<QuadFirstMoment>(hierarchy.fineQuads(), uint32_t(hierarchy.h.fineVertexCount()), k));
  configureFineRows();
  reference_ = volume();
}

bool QuadVolumeEditor::usePolynomial(uint64_t maxTerms) {
  std::unique_ptr<CagePolynomialBuilder> builder;
  try {
    builder = std::make_unique<CagePolynomialBuilder>(*transform_, level_, bilinearPatchRegions(*quadHierarchy_, level_), maxTerms);
  } catch (const Error&) {  // too many cage triples: no faster than the fine mesh
    useMatrixFree();
    return false;
  }
  polynomial_.useBuilder(std::move(builder), volume());
  solver_.reset();
  return true;
}

}  // namespace mrvol
