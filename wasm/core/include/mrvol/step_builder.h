// Building lifting steps from (target, source, weight) triplets: shared by the triangle schemes
// (lifting.cpp) and Catmull-Clark (quad_lifting.cpp), so that every scheme's steps are compiled by
// the same loops (rows by target, sources ascending, duplicates summed, zero weights dropped).
#pragma once
#include <algorithm>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "mrvol/lifting.h"
#include "mrvol/corners.h"

namespace mrvol {

// Collects (target, source, weight) triplets and compiles them into a lift step (rows sorted by
// target, duplicate sources merged) or a scaling step. While the targets come in ascending order
// (the usual case: the schemes walk the targets in order) the rows are built as they come, each
// kept sorted by source with a duplicate added to its entry (the same sums in the same order as
// the sort and merge of the triplets, and no triplet array: the step's arrays are the only copy);
// the first target out of order turns the rows into triplets and the general path takes over.
struct StepBuilder {
  struct Triplet { uint32_t t, s; double w; };
  std::vector<Triplet> triplets;  // the general path (targets out of order)
  bool compiled = false;
  // Room for `rows` targets and `entries` sources at once (a hint).
  void reserve(size_t rows, size_t entries) {
    rowTarget_.reserve(rows), rowStart_.reserve(rows + 1), rowSource_.reserve(entries), rowWeight_.reserve(entries);
  }
  void add(uint32_t t, uint32_t s, double w) {
    if (inRows_ && rowFor(t)) return addToRow(s, w);
    triplets.push_back({t, s, w});
    compiled = false;
  }
  void touch(uint32_t t) {
    if (inRows_ && rowFor(t)) return;
    triplets.push_back({t, kNone, 0.0});
    compiled = false;
  }
  // Sorted by (target, source), duplicates summed in insertion order (as the std::map did).
  void compile() {
    leaveRows();
    if (compiled) return;
    sortStably();
    size_t out = 0;
    for (size_t i = 0; i < triplets.size();) {
      Triplet acc = triplets[i];
      size_t j = i + 1;
      if (acc.s == kNone) acc.w = 0.0;
      for (; j < triplets.size() && triplets[j].t == acc.t && triplets[j].s == acc.s; ++j) acc.w += triplets[j].w;
      triplets[out++] = acc;
      i = j;
    }
    triplets.resize(out);
    compiled = true;
  }
  // As std::stable_sort by (target, source), in linear time: a counting sort by target (stable),
  // then each row (a few triplets) by source, stably.
  void sortStably() {
    if (triplets.empty()) return;
    // Added by ascending target already: only each row by source.
    bool byTarget = true;
    for (size_t i = 1; i < triplets.size() && byTarget; ++i) byTarget = triplets[i - 1].t <= triplets[i].t;
    if (byTarget) {
      for (size_t i = 1; i < triplets.size(); ++i) {
        if (triplets[i].t != triplets[i - 1].t || triplets[i - 1].s <= triplets[i].s) continue;
        const Triplet x = triplets[i];
        size_t j = i;
        for (; j > 0 && triplets[j - 1].t == x.t && triplets[j - 1].s > x.s; --j) triplets[j] = triplets[j - 1];
        triplets[j] = x;
      }
      return;
    }
    uint32_t low = triplets[0].t, high = low;
    for (const Triplet& x : triplets) low = std::min(low, x.t), high = std::max(high, x.t);
    if (high - low > 4 * triplets.size()) {  // sparse targets: the buckets would cost more
      std::stable_sort(triplets.begin(), triplets.end(), [](const Triplet& a, const Triplet& b) {
        return a.t != b.t ? a.t < b.t : a.s < b.s;
      });
      return;
    }
    std::vector<uint32_t> start(size_t(high - low) + 2, 0);
    for (const Triplet& x : triplets) ++start[size_t(x.t - low) + 1];
    for (size_t t = 1; t < start.size(); ++t) start[t] += start[t - 1];
    std::vector<Triplet> sorted(triplets.size());
    {
      std::vector<uint32_t> fill(start.begin(), start.end() - 1);
      for (const Triplet& x : triplets) sorted[fill[x.t - low]++] = x;
    }
    for (size_t t = 0; t + 1 < start.size(); ++t)
      for (uint32_t i = start[t] + 1; i < start[t + 1]; ++i) {
        const Triplet x = sorted[i];
        uint32_t j = i;
        for (; j > start[t] && sorted[j - 1].s > x.s; --j) sorted[j] = sorted[j - 1];
        sorted[j] = x;
      }
    triplets = std::move(sorted);
  }
  template <class F> void forEach(F&& f) {
    compile();
    for (auto& x : triplets) if (x.s != kNone) f(x.t, x.s, x.w);
  }
  LiftingStep lift(const std::string& name) {
    LiftingStep st;
    st.name = name;
    if (inRows_) {
      // The rows as they are, less the sources whose weights summed to zero (and the touches').
      rowStart_.push_back(uint32_t(rowSource_.size()));
      size_t out = 0;
      for (size_t r = 0; r + 1 < rowStart_.size(); ++r) {
        const uint32_t begin = rowStart_[r], end = rowStart_[r + 1];
        rowStart_[r] = uint32_t(out);
        for (uint32_t i = begin; i < end; ++i)
          if (rowWeight_[i] != 0.0) rowSource_[out] = rowSource_[i], rowWeight_[out++] = rowWeight_[i];
      }
      rowStart_.back() = uint32_t(out);
      rowSource_.resize(out), rowWeight_.resize(out);
      st.targets = std::move(rowTarget_), st.offsets = std::move(rowStart_);
      st.sources = std::move(rowSource_), st.weights = std::move(rowWeight_);
      st.offsets.shrink_to_fit(), st.targets.shrink_to_fit();  // beyond the hint's room: given back
      *this = StepBuilder();
      return st;
    }
    compile();
    st.offsets.reserve(triplets.size() + 1), st.targets.reserve(triplets.size());
    st.sources.reserve(triplets.size()), st.weights.reserve(triplets.size());
    st.offsets.push_back(0);
    for (size_t i = 0; i < triplets.size();) {
      uint32_t t = triplets[i].t;
      st.targets.push_back(t);
      for (; i < triplets.size() && triplets[i].t == t; ++i)
        if (triplets[i].s != kNone && triplets[i].w != 0.0) st.sources.push_back(triplets[i].s), st.weights.push_back(triplets[i].w);
      st.offsets.push_back(uint32_t(st.sources.size()));
    }
    st.offsets.shrink_to_fit(), st.targets.shrink_to_fit();  // rows of several triplets: room to give back
    return st;
  }

 private:
  // The rows while the targets ascend: row r is target rowTarget_[r], its sources (ascending) and
  // summed weights in [rowStart_[r], rowStart_[r + 1]) (the last row's end is the arrays' end).
  bool inRows_ = true;
  std::vector<uint32_t> rowTarget_, rowStart_, rowSource_;
  std::vector<double> rowWeight_;

  // Makes t the current row (a new one when it is above the last target): false, and the rows
  // turned into triplets, when t is below it.
  bool rowFor(uint32_t t) {
    if (!rowTarget_.empty() && rowTarget_.back() == t) return true;
    if (!rowTarget_.empty() && t < rowTarget_.back()) {
      leaveRows();
      return false;
    }
    rowTarget_.push_back(t), rowStart_.push_back(uint32_t(rowSource_.size()));
    return true;
  }
  // Into the current row, sorted by source; a source already there takes the weight added to its
  // sum (duplicates summed in the order they came, as compile() does).
  void addToRow(uint32_t s, double w) {
    if (s == kNone) return;  // a touch's weight (compile() zeroes and drops it)
    const size_t begin = rowStart_.back(), end = rowSource_.size();
    size_t j = end;
    while (j > begin && rowSource_[j - 1] > s) --j;
    if (j > begin && rowSource_[j - 1] == s) {
      rowWeight_[j - 1] += w;
      return;
    }
    // Appended, then moved down to its place (a row holds a few sources).
    rowSource_.push_back(s), rowWeight_.push_back(w);
    uint32_t* source = rowSource_.data();
    double* weight = rowWeight_.data();
    for (size_t i = end; i > j; --i) source[i] = source[i - 1], weight[i] = weight[i - 1];
    source[j] = s, weight[j] = w;
  }
  // The rows as compiled triplets (a row without sources as a touch), for the general path.
  void leaveRows() {
    if (!inRows_) return;
    inRows_ = false;
    if (rowTarget_.empty()) return;
    std::vector<Triplet> rows;
    rows.reserve(rowSource_.size() + rowTarget_.size());
    rowStart_.push_back(uint32_t(rowSource_.size()));
    for (size_t r = 0; r < rowTarget_.size(); ++r) {
      if (rowStart_[r] == rowStart_[r + 1]) rows.push_back({rowTarget_[r], kNone, 0.0});
      for (uint32_t i = rowStart_[r]; i < rowStart_[r + 1]; ++i) rows.push_back({rowTarget_[r], rowSource_[i], rowWeight_[i]});
    }
    rows.insert(rows.end(), triplets.begin(), triplets.end());
    triplets = std::move(rows);
    compiled = false;
    rowTarget_ = {}, rowStart_ = {}, rowSource_ = {}, rowWeight_ = {};
  }
};

inline LiftingStep scalingStep(const std::string& name, std::vector<std::pair<uint32_t, double>> factors) {
  LiftingStep st;
  st.name = name;
  st.scaling = true;
  std::sort(factors.begin(), factors.end());
  for (auto& [t, f] : factors) st.targets.push_back(t), st.weights.push_back(f);
  return st;
}

}  // namespace mrvol
