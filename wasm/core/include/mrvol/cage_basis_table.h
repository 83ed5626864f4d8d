// The fine positions as a linear function of a small cage: p = base + S (cage - cage at base), with
// S the zero-detail synthesis (each fine vertex's row: the weights of the cage vertices whose basis
// functions reach it). With the details fixed, a drag of a coarse cage (e = 0: every step moves the
// whole cage) needs only this sparse product, in float, in the caller's order: one sequential pass,
// no synthesis through the levels. Built once per editor, only for small cages (each row is short
// and the build takes cage / 3 zero-detail syntheses).
#pragma once
#include <cstdint>
#include <vector>

#include "mrvol/lifting.h"

namespace mrvol {

class CageBasisTable {
 public:
  static constexpr uint32_t kMaxCage = 48;         // larger cages: no table (empty())
  static constexpr size_t kMaxEntriesPerVertex = 24;  // longer rows on average: no table

  // Rows in the caller's vertex order (callerIndex: hierarchy index -> caller's index).
  CageBasisTable(const WaveletTransform& transform, int level, const uint32_t* callerIndex);
  bool empty() const { return rowStart_.empty(); }
  size_t entryCount() const { return weight_.size(); }

  // For every fine vertex v (caller's order): out4[v] = base4[v] + sum over its row of w * delta4[c]
  // (4 floats a vertex, lane 3 zero), and out3[v] = out4[v] + origin (3 floats a vertex; out3 has
  // one float more than 3 N: a vector store per vertex runs over by one).
  void apply(const float* base4, const float* delta4, const float origin[3], float* out4, float* out3) const;

 private:
  std::vector<uint32_t> rowStart_;  // N + 1
  std::vector<uint16_t> cage_;      // cage index of each entry
  std::vector<float> weight_;
};

}  // namespace mrvol
