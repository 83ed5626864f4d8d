// The first base fixture subdivided (zero details) and its vertices shuffled: a fine mesh whose
// input order is not the hierarchy's, for tests of tables and buffers kept in the caller's order.
#pragma once

#include <algorithm>
#include <vector>

#include "fixtures.h"
#include "mrvol/hierarchy.h"
#include "mrvol/lifting.h"

namespace fixtures {

inline Shuffled shuffledSubdivision(unsigned seed) {
  const Fixture fx = baseFixtures()[0];
  const mrvol::Hierarchy sub = mrvol::Hierarchy::subdivide(fx.base, fx.levels);
  mrvol::TriangleMesh fine{std::vector<double>(3 * sub.fineVertexCount(), 0.0), sub.fineFaces()};
  std::copy(fx.base.positions.begin(), fx.base.positions.end(), fine.positions.begin());
  mrvol::WaveletTransform(sub, mrvol::SchemeOptions{}).synthesize(fine.positions.data(), 0);
  return shuffle(fine, seed);
}

}  // namespace fixtures
