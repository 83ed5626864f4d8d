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
// target, duplicate sources merged) or a scaling step.
struct StepBuilder {
  struct Triplet { uint32_t t, s; double w; };
  std::vector<Triplet> triplets;
  bool compiled = false;
  void add(uint32_t t, uint32_t s, double w) { triplets.push_back({t, s, w}); compiled = false; }
  void touch(uint32_t t) { triplets.push_back({t, kNone, 0.0}); compiled = false; }
  // Sorted by (target, source), duplicates summed in insertion order (as the std::map did).
  void compile() {
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
    // Added by ascending target already (the usual case: the schemes walk the targets in order):
    // only each row by source.
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
    compile();
    LiftingStep st;
    st.name = name;
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
