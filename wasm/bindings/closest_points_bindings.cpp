// embind layer for closest points on a mesh (mrvol/closest_points.h) and three-mesh-bvh's tree built
// in the core (mrvol/bvh_build.h): converts types, nothing else.
// Queries go through buffers that live in the module's memory (their addresses are handed to JS,
// which reads and writes them through HEAPF64 / HEAPU32), so a query allocates nothing; lib/
// closest-points.mjs wraps it. Errors are kept in this file's slot (_takeClosestPointsError).
#include <emscripten/bind.h>
#include <emscripten/val.h>

#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "mrvol/bvh_build.h"
#include "mrvol/closest_points.h"
#include "guard.h"
#include "typed_arrays.h"

using emscripten::val;
using namespace mrvol;
using namespace mrvol::bindings;

namespace {

ErrorSlot closestPointsErrors("the mesh");

class JsClosestPoints {
 public:
  explicit JsClosestPoints(ClosestPoints tree) : tree_(std::move(tree)) { reserve(1); }

  size_t triangleCount() const { return tree_.triangleCount(); }

  // Room for n queries: in: 3n coordinates then n bounds; out: 3n coordinates then n squared
  // distances, and n triangles. The addresses change: take them after each reserve.
  void reserve(size_t n) {
    if (n > in_.max_size() / 4) throw std::length_error("closest points: too many queries");  // 4n would wrap
    if (4 * n > in_.size()) in_.resize(4 * n), out_.resize(4 * n), triangles_.resize(n);
    capacity_ = in_.size() / 4;
  }
  size_t capacity() const { return capacity_; }
  size_t inAddress() const { return reinterpret_cast<size_t>(in_.data()); }
  size_t outAddress() const { return reinterpret_cast<size_t>(out_.data()); }
  size_t trianglesAddress() const { return reinterpret_cast<size_t>(triangles_.data()); }

  // One query (bound: a distance, Infinity for none); the hit in out[0..3], triangles[0]. Returns
  // the squared distance, or -1 if nothing lies within the bound.
  double one(double x, double y, double z, double bound) {
    const double p[3] = {x, y, z};
    ClosestHit hit{};
    if (!tree_.closest(p, bound < std::numeric_limits<double>::infinity() ? bound * bound : bound, hit)) return -1;
    out_[0] = hit.point[0], out_[1] = hit.point[1], out_[2] = hit.point[2], out_[3] = hit.distanceSquared;
    triangles_[0] = hit.triangle;
    return hit.distanceSquared;
  }

  // n queries from the in buffer (with its bounds or without), into the out buffer.
  void many(size_t n, bool withBounds) {
    if (n > capacity_) throw Error("closest points: " + std::to_string(n) + " queries but room for " + std::to_string(capacity_));
    tree_.closestMany(in_.data(), n, withBounds ? in_.data() + 3 * n : nullptr, out_.data(), out_.data() + 3 * n,
                      triangles_.data());
  }

  double sampledDistanceFrom(const val& positions, const val& triangles, double maxSamples) {
    return tree_.sampledDistanceFrom(toVector<double>(positions, "positions"), toVector<uint32_t>(triangles, "faces"),
                                     maxSamples >= 1 ? static_cast<size_t>(maxSamples) : 1);
  }

 private:
  ClosestPoints tree_;
  std::vector<double> in_, out_;
  std::vector<uint32_t> triangles_;
  size_t capacity_ = 0;
};

JsClosestPoints* makeClosestPoints(val positions, val triangles) {
  return closestPointsErrors.guarded([&]() -> JsClosestPoints* {
    return new JsClosestPoints(ClosestPoints(toVector<double>(positions, "positions"), toVector<uint32_t>(triangles, "faces")));
  });
}
JsClosestPoints* makeClosestPointsWithTree(val positions, val triangles, val bounds, val first, val count) {
  return closestPointsErrors.guarded([&]() -> JsClosestPoints* {
    return new JsClosestPoints(ClosestPoints(toVector<double>(positions, "positions"), toVector<uint32_t>(triangles, "faces"),
                                             toVector<double>(bounds, "tree bounds"), toVector<uint32_t>(first, "tree firsts"),
                                             toVector<uint32_t>(count, "tree counts")));
  });
}
bool reserveGuarded(JsClosestPoints& c, size_t n) { return closestPointsErrors.guarded([&] { c.reserve(n); return true; }); }
bool manyGuarded(JsClosestPoints& c, size_t n, bool withBounds) {
  return closestPointsErrors.guarded([&] { c.many(n, withBounds); return true; });
}
double sampledGuarded(JsClosestPoints& c, val positions, val triangles, double maxSamples) {
  return closestPointsErrors.guarded([&] { return c.sampledDistanceFrom(positions, triangles, maxSamples); });
}
val takeClosestPointsError() { return closestPointsErrors.take(); }

// positions: Float32Array; index: Uint32Array. Returns { nodes: Uint32Array (8 words a node),
// index: Uint32Array (reordered) }, or undefined with the error kept.
val buildBvh(val positions, val index) {
  return closestPointsErrors.guarded([&] {
    std::vector<uint32_t> order = toVector<uint32_t>(index, "index");
    const std::vector<uint32_t> nodes = buildThreeMeshBvh(toVector<float>(positions, "positions"), order);
    val out = val::object();
    out.set("nodes", toTyped(nodes));
    out.set("index", toTyped(order));
    return out;
  });
}

}  // namespace

// Guarded: the factories, reserve, many, sampledDistanceFrom. Unguarded: the getters and one()
// (a walk of the tree on the stack, into the buffers reserve made): they neither allocate nor throw.
EMSCRIPTEN_BINDINGS(mrvol_closest_points) {
  emscripten::class_<JsClosestPoints>("_ClosestPoints")
      .function("triangleCount", &JsClosestPoints::triangleCount)
      .function("reserve", &reserveGuarded)
      .function("capacity", &JsClosestPoints::capacity)
      .function("inAddress", &JsClosestPoints::inAddress)
      .function("outAddress", &JsClosestPoints::outAddress)
      .function("trianglesAddress", &JsClosestPoints::trianglesAddress)
      .function("one", &JsClosestPoints::one)
      .function("many", &manyGuarded)
      .function("sampledDistanceFrom", &sampledGuarded);
  emscripten::function("_closestPoints", &makeClosestPoints, emscripten::allow_raw_pointers());
  emscripten::function("_closestPointsWithTree", &makeClosestPointsWithTree, emscripten::allow_raw_pointers());
  emscripten::function("_takeClosestPointsError", &takeClosestPointsError);
  emscripten::function("_buildBvh", &buildBvh);
}
