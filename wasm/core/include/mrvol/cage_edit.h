// What both editing sessions (VolumeEditor on triangle meshes, QuadVolumeEditor on quad meshes) do
// alike around the solver: check a cage target, choose the free coefficients, split a large move
// into sub-steps, and put the held vertices exactly at their target afterwards.
#pragma once
#include <cstdint>
#include <vector>

#include "mrvol/coefficient_volumes.h"
#include "mrvol/hierarchy.h"
#include "mrvol/volume_solver.h"

namespace mrvol {

// Which cage vertices may absorb a correction: those not held in a deformation, all of them, or a
// list (cage order).
enum class FreeCage { MinusHeld, All, List };

// A free set: the cage part and the details of chosen levels (e <= l < n: d^l, the vertices born
// at level l + 1). Boundary vertices are never free.
struct FreeSet {
  FreeCage mode = FreeCage::MinusHeld;
  std::vector<uint32_t> list;
  std::vector<int> detailLevels;
  // Throws Error naming an index that is no cage vertex or a level out of range.
  void check(const Hierarchy& h, int level) const;
  // The free coefficients, hierarchy order, ascending.
  std::vector<uint32_t> coefficients(const Hierarchy& h, int level, const std::vector<uint8_t>& held) const;
};

// target - current cage (3 * cageSize doubles, cage order) after checking the target: its size,
// finite coordinates, boundary vertices where they are.
std::vector<double> checkedCageMove(const Hierarchy& h, const SessionCoefficients& session, const std::vector<double>& target);

// How many sub-steps a move whose raw relative change is `change` gets (the linearization holds
// for changes up to options.substepError).
int substepCount(double change, const EditOptions& options);

// From the cage `start`, `substeps` equal parts of `move`, each solved; the report gets the
// iterations, the last volume and error, and the first failure.
void solveInSubsteps(SessionCoefficients& session, const std::vector<double>& start, const std::vector<double>& move,
                     int substeps, VolumeSolver& solver, const EditOptions& options, EditReport& report);

// Held cage vertices outside the free set go exactly to the target (the sub-steps add up with
// rounding). Returns whether any moved (then the fine positions are marked changed).
bool snapHeldToTarget(SessionCoefficients& session, const std::vector<double>& target, const std::vector<uint8_t>& held,
                      const std::vector<uint32_t>& free);

}  // namespace mrvol
