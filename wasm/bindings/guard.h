// The error slot every embind file keeps: a core error never crosses into JS as an exception. A
// call runs guarded: what it throws becomes a message in the file's slot and the call returns
// an empty value; the JS side takes the message after each call (_takeError, _takeIoError,
// _takeQuadError) and throws MrvolError. Nothing may leave a call uncaught: JS would get an opaque
// WebAssembly.Exception and, in the threaded module, the thread would keep the exception dispatch
// lock (wasm/toolchain/landing_pad_context.cpp), so that the next throw on a pool thread would hang.
#pragma once
#include <emscripten/val.h>

#include <exception>
#include <new>
#include <stdexcept>
#include <string>

namespace mrvol::bindings {

template <class T>
T emptyResult() { return T{}; }
template <>
inline emscripten::val emptyResult<emscripten::val>() { return emscripten::val::undefined(); }

class ErrorSlot {
 public:
  // what: the input's name in the out-of-memory message ("the input", "the file").
  explicit ErrorSlot(const char* what) : outOfMemory_(std::string("out of memory: ") + what + " is too large for this WebAssembly module") {}

  template <class F>
  auto guarded(F&& f) -> decltype(f()) {
    try {
      return f();
    } catch (const std::bad_alloc&) {
      keep(nullptr);
    } catch (const std::length_error&) {
      keep(nullptr);
    } catch (const std::exception& e) {
      keep(e.what());
    } catch (...) {
      keep("unknown error");
    }
    return emptyResult<decltype(f())>();
  }

  // The message as a JS string ("" for none), made without allocating in WASM; the slot empties.
  emscripten::val take() {
    emscripten::val out(outOfMemoryKept_ ? outOfMemory_.c_str() : message_.c_str());
    outOfMemoryKept_ = false;
    message_.clear();
    return out;
  }

 private:
  // text: null for out of memory. Copying a message may itself fail on a full heap: then the
  // out-of-memory message (made up front) stands for it, and nothing leaves the guard.
  void keep(const char* text) noexcept {
    outOfMemoryKept_ = text == nullptr;
    message_.clear();
    if (text) try {
        message_ = text;
      } catch (...) {
        outOfMemoryKept_ = true;
      }
  }

  std::string message_;
  std::string outOfMemory_;
  bool outOfMemoryKept_ = false;
};

}  // namespace mrvol::bindings
