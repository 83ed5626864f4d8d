#include "mrvol/cage_edit.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "mrvol/error.h"

namespace mrvol {

void FreeSet::check(const Hierarchy& h, int level) const {
  for (uint32_t c : list)
    if (c >= h.vertexCount[level]) throw Error("free-set index " + std::to_string(c) + " is not a cage vertex");
  for (int l : detailLevels)
    if (l < level || l >= h.levels)
      throw Error("free detail level " + std::to_string(l) + " is out of range " + std::to_string(level) + ".." +
                  std::to_string(h.levels - 1));
}

std::vector<uint32_t> FreeSet::coefficients(const Hierarchy& h, int level, const std::vector<uint8_t>& held) const {
  std::vector<uint32_t> free;
  const auto& boundary = h.boundary;
  const uint32_t cageSize = h.vertexCount[level];
  if (mode == FreeCage::List) {
    for (uint32_t c : list)
      if (!boundary[c]) free.push_back(c);
  } else {
    for (uint32_t c = 0; c < cageSize; ++c)
      if (!boundary[c] && (mode == FreeCage::All || !(c < held.size() && held[c]))) free.push_back(c);
  }
  for (int l : detailLevels)
    for (uint32_t v = h.vertexCount[l]; v < h.vertexCount[l + 1]; ++v)
      if (!boundary[v]) free.push_back(v);
  std::sort(free.begin(), free.end());
  free.erase(std::unique(free.begin(), free.end()), free.end());
  return free;
}

std::vector<double> checkedCageMove(const Hierarchy& h, const SessionCoefficients& session, const std::vector<double>& target) {
  const size_t cage3 = 3 * size_t(session.cageSize);
  if (target.size() != cage3)
    throw Error("the cage target needs " + std::to_string(cage3) + " coordinates, got " + std::to_string(target.size()));
  std::vector<double> move(cage3);
  for (uint32_t c = 0; c < session.cageSize; ++c)
    for (int k = 0; k < 3; ++k) {
      const double t = target[3 * c + k];
      if (!std::isfinite(t)) throw Error("the cage target has a non-finite coordinate");
      move[3 * c + k] = t - session.x[3 * c + k];
      if (h.boundary[c] && move[3 * c + k] != 0.0)
        throw Error("vertex " + std::to_string(h.inputIndex[c]) +
                    " is on the boundary: boundary vertices stay fixed so that the volume stays meaningful");
    }
  return move;
}

int substepCount(double change, const EditOptions& o) {
  return std::clamp(int(std::ceil(change / o.substepError)), 1, o.maxSubsteps);
}

void solveInSubsteps(SessionCoefficients& session, const std::vector<double>& start, const std::vector<double>& move,
                     int substeps, VolumeSolver& solve, const EditOptions& o, EditReport& report) {
  if (substeps > 1) {
    std::copy(start.begin(), start.end(), session.x.begin());
    session.fine.cageChanged();
  }
  for (int s = 1; s <= substeps; ++s) {
    if (substeps > 1) {
      for (size_t i = 0; i < move.size(); ++i) session.x[i] += move[i] / substeps;
      session.fine.cageChanged();
    }
    EditReport step;
    solve.solve(o, step);
    report.iterations += step.iterations;
    report.relativeError = step.relativeError;
    report.volumeResult = step.volumeResult;
    if (!step.converged) {
      report.converged = false;
      report.message = step.message;
      break;
    }
  }
}

bool snapHeldToTarget(SessionCoefficients& session, const std::vector<double>& target, const std::vector<uint8_t>& held,
                      const std::vector<uint32_t>& free) {
  bool snapped = false;
  for (uint32_t c = 0; c < session.cageSize; ++c)
    if (c < held.size() && held[c] && !std::binary_search(free.begin(), free.end(), c))
      for (int k = 0; k < 3; ++k) {
        snapped = snapped || session.x[3 * c + k] != target[3 * c + k];
        session.x[3 * c + k] = target[3 * c + k];
      }
  if (snapped) session.fine.cageChanged();
  return snapped;
}

}  // namespace mrvol
