// The fine positions as a linear function of the cage: p = base + S (cage - cage at base), with S the
// zero-detail synthesis (each fine vertex's row: the weights of the cage vertices whose basis
// functions reach it, about a dozen at any level). With the details fixed, a drag (every corrected
// step moves the whole free cage) needs only this sparse product, in float, in the caller's order:
// one sequential pass, no synthesis through the levels; a move of a few cage vertices rewrites only
// the rows of their columns. Built once per editor by carrying sparse rows through the synthesis
// steps (O(N) work and memory, whatever the cage).
// A cage of at most kMaxDenseCage vertices (editing at the base level) is stored as dense rows, 4, 8,
// 12 or 16 weights a row (zeros where the sparse row has no entry): no cage indices to load, the
// cage's deltas held in registers, fewer bytes a row (bench/NOTES-surface-pass.md). Their sums run in
// cage order, a sparse row's in the order of its entries: they may differ in the last bits of float
// (the rows carried here come in cage order: the same bits); each is the same at any thread count.
#pragma once
#include <cstdint>
#include <vector>

#include "mrvol/cage_polynomial_builder.h"
#include "mrvol/lifting.h"

namespace mrvol {

class CageBasisTable {
 public:
  static constexpr uint32_t kMaxCage = 65535;         // cage indices are 16-bit; larger cages: no table (empty())
  static constexpr size_t kMaxEntriesPerVertex = 24;  // longer rows on average: no table
  static constexpr size_t kRowsPerBlock = 16384;      // apply's smallest block for a thread
  static constexpr uint32_t kMaxDenseCage = 16;       // dense rows up to this cage size

  // Row callerIndex[h] is the hierarchy vertex h's (any one-to-one numbering: the caller's vertex
  // order, or the renderer buffers' own).
  CageBasisTable(const WaveletTransform& transform, int level, const uint32_t* callerIndex);
  // The same from rows made already in double (a CagePolynomialBuilder's: the rows are made once per
  // editor), rounded once to float (the constructor above rounds at every step: it may differ in the
  // last bit); weights below float's resolution of the sum are dropped.
  CageBasisTable(const CageBasis& basis, uint32_t cageSize, const uint32_t* callerIndex);
  bool empty() const { return rowStart_.empty(); }
  size_t entryCount() const { return entries_; }
  bool dense() const { return denseWidth_ > 0; }
  size_t vertexCount() const { return rowStart_.empty() ? 0 : rowStart_.size() - 1; }
  uint32_t cageSize() const { return uint32_t(columnStart_.size() - 1); }

  // For every row v: out4[v] = base4[v] + sum over its row of w * delta4[c] (4 floats a row, lane 3
  // zero), and out3[outIndex[v]] = out4[v] + origin (3 floats a vertex: the rows may be in an order of
  // their own, the output in the caller's). On the thread pool's threads (thread_pool.h): the same
  // results at any thread count.
  void apply(const float* base4, const float* delta4, const float origin[3], float* out4, float* out3, const uint32_t* outIndex) const;
  // The same for the listed rows only.
  void applyRows(const uint32_t* vertices, size_t count, const float* base4, const float* delta4, const float origin[3],
                 float* out4, float* out3, const uint32_t* outIndex) const;
  // The fine vertices (caller's order) whose rows read cage vertex c.
  const uint32_t* columnBegin(uint32_t c) const { return columnVertex_.data() + columnStart_[c]; }
  const uint32_t* columnEnd(uint32_t c) const { return columnVertex_.data() + columnStart_[c + 1]; }
  // Row of v, for tests: cage indices and weights.
  void row(uint32_t v, std::vector<uint32_t>& cage, std::vector<float>& weights) const;

 private:
  void setColumns(std::vector<uint32_t> rowStart, uint32_t cage);  // the columns' pattern of the rows (sparse or dense)
  float* startDense(uint32_t cage, size_t rows);  // zero dense rows for a small cage, to be filled

  std::vector<uint32_t> rowStart_;  // N + 1 (the sparse rows' starts; dense rows: the lengths they would have)
  std::vector<uint16_t> cage_;      // cage index of each entry
  std::vector<float> weight_;
  size_t entries_ = 0;
  uint32_t denseWidth_ = 0;  // dense rows: weight_ holds denseWidth_ weights a row, in cage order (0: sparse)
  std::vector<uint32_t> columnStart_{0}, columnVertex_;  // the transpose's pattern (cage + 1, entries)
};

}  // namespace mrvol
