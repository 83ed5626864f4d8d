// Edit options, reports and free-set modes between JS and the core, for both editors' bindings
// (bindings.cpp: triangle meshes, quad_bindings.cpp: quad meshes), so that their JS surfaces agree.
#pragma once
#include <emscripten/val.h>

#include <string>

#include "mrvol/cage_edit.h"
#include "mrvol/error.h"
#include "mrvol/volume_solver.h"
#include "typed_arrays.h"

namespace mrvol::bindings {

using emscripten::val;

inline EditOptions toEditOptions(const val& o) {
  EditOptions opts;
  if (o.isUndefined() || o.isNull()) return opts;
  if (!o["tolerance"].isUndefined()) opts.tolerance = o["tolerance"].as<double>();
  if (!o["maxIterations"].isUndefined()) opts.maxIterations = o["maxIterations"].as<int>();
  if (!o["maxSubsteps"].isUndefined()) opts.maxSubsteps = o["maxSubsteps"].as<int>();
  if (!o["preserve"].isUndefined()) opts.preserve = o["preserve"].as<bool>();
  return opts;
}

inline val reportToJs(const EditReport& r) {
  val out = val::object();
  out.set("volumeReference", r.volumeReference);
  out.set("volumeTarget", r.volumeTarget);
  out.set("volumeResult", r.volumeResult);
  out.set("relativeError", r.relativeError);
  out.set("iterations", r.iterations);
  out.set("substeps", r.substeps);
  out.set("converged", r.converged);
  out.set("message", r.message);
  out.set("path", std::string(gradientPathName(r.path)));
  out.set("partVolumes", toTyped(r.partVolumes));
  out.set("partReferences", toTyped(r.partReferences));
  if (!r.centroidResult.empty()) {
    out.set("centroidReference", toTyped(r.centroidReference));
    out.set("centroidResult", toTyped(r.centroidResult));
  }
  return out;
}

// 'minus-held', 'all' or 'list'.
inline FreeCage freeCageMode(const std::string& mode) {
  if (mode == "minus-held") return FreeCage::MinusHeld;
  if (mode == "all") return FreeCage::All;
  if (mode == "list") return FreeCage::List;
  throw Error("unknown free-set mode '" + mode + "'");
}

}  // namespace mrvol::bindings
