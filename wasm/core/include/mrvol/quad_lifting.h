// The lifted Catmull-Clark filter bank of a quad hierarchy (docs/catmull-clark.md): per level, the
// synthesis steps whose zero-detail run is Catmull-Clark subdivision with its original rules.
#pragma once
#include <vector>

#include "mrvol/lifting.h"
#include "mrvol/quad_hierarchy.h"

namespace mrvol {

// Synthesis steps of level l (1 <= l <= n), in the order they apply:
//   "P_f"  face points from their quad's corners
//   "P_e"  edge points from their ends and face points
//   "N_3k", "P_3k" (k = K..1) interior valence-3 vertices of layer k (scaling, then lift)
//   "N_v", "P_v"  the other old vertices (scaling, then lift)
// A connected component of the level-(l-1) mesh that is closed with every vertex of valence 3 (a
// cube) loses information in Catmull-Clark subdivision: no filter bank that reproduces it can be
// inverted. Without `invertible` that throws Error; with it, *invertible becomes false and the
// level gets the plain vertex rule there (a scaling by 0): synthesis only.
std::vector<LiftingStep> catmullClarkLevel(const QuadHierarchy& hierarchy, int level, bool* invertible = nullptr);

// The transform of a quad hierarchy (SchemeKind::CatmullClark); the hierarchy must outlive it.
// lowestLevel: the lowest level analysis can reach (1 when level 1 is not invertible, else 0).
WaveletTransform catmullClarkTransform(const QuadHierarchy& hierarchy, int* lowestLevel = nullptr);

}  // namespace mrvol
