// Numbers between JS arrays and std::vector, for every embind file: a missing argument is an error
// naming it; results are copies (a view of WASM memory would go stale when it grows).
#pragma once
#include <emscripten/val.h>

#include <string>
#include <vector>

#include "mrvol/error.h"

namespace mrvol::bindings {

template <class T>
std::vector<T> toVector(const emscripten::val& v, const char* what) {
  if (v.isUndefined() || v.isNull()) throw Error(std::string(what) + " is missing");
  return emscripten::convertJSArrayToNumberVector<T>(v);
}

template <class T>
emscripten::val toTyped(const std::vector<T>& v) {
  return emscripten::val(emscripten::typed_memory_view(v.size(), v.data())).call<emscripten::val>("slice");
}

}  // namespace mrvol::bindings
