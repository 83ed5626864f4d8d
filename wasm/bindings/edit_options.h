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

// The property names as JS strings made once (on the one thread that calls the bindings): a name
// given as a C string is decoded from WASM memory on every call, which on the threaded build's
// shared memory checks for memory growth at every byte (a drag's step paid more for it than for
// its correction at e = 0).
struct EditNames {
  val tolerance{"tolerance"}, maxIterations{"maxIterations"}, maxSubsteps{"maxSubsteps"}, preserve{"preserve"};
  val volumeReference{"volumeReference"}, volumeTarget{"volumeTarget"}, volumeResult{"volumeResult"};
  val relativeError{"relativeError"}, iterations{"iterations"}, substeps{"substeps"}, converged{"converged"};
  val message{"message"}, path{"path"}, partVolumes{"partVolumes"}, partReferences{"partReferences"};
  val centroidReference{"centroidReference"}, centroidResult{"centroidResult"};
  val pathNames[3] = {val(gradientPathName(GradientPath::Tensor)), val(gradientPathName(GradientPath::Polynomial)),
                      val(gradientPathName(GradientPath::MatrixFree))};
};
inline const EditNames& editNames() {
  static const EditNames names;
  return names;
}

inline EditOptions toEditOptions(const val& o) {
  EditOptions opts;
  if (o.isUndefined() || o.isNull()) return opts;
  const EditNames& n = editNames();
  if (const val v = o[n.tolerance]; !v.isUndefined()) opts.tolerance = v.as<double>();
  if (const val v = o[n.maxIterations]; !v.isUndefined()) opts.maxIterations = v.as<int>();
  if (const val v = o[n.maxSubsteps]; !v.isUndefined()) opts.maxSubsteps = v.as<int>();
  if (const val v = o[n.preserve]; !v.isUndefined()) opts.preserve = v.as<bool>();
  return opts;
}

inline val reportToJs(const EditReport& r) {
  const EditNames& n = editNames();
  val out = val::object();
  out.set(n.volumeReference, r.volumeReference);
  out.set(n.volumeTarget, r.volumeTarget);
  out.set(n.volumeResult, r.volumeResult);
  out.set(n.relativeError, r.relativeError);
  out.set(n.iterations, r.iterations);
  out.set(n.substeps, r.substeps);
  out.set(n.converged, r.converged);
  out.set(n.message, r.message);
  const size_t path = size_t(r.path);
  out.set(n.path, path < 3 ? n.pathNames[path] : val(gradientPathName(r.path)));
  out.set(n.partVolumes, toTyped(r.partVolumes));
  out.set(n.partReferences, toTyped(r.partReferences));
  if (!r.centroidResult.empty()) {
    out.set(n.centroidReference, toTyped(r.centroidReference));
    out.set(n.centroidResult, toTyped(r.centroidResult));
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
