// The error slot every embind file keeps: a core error never crosses into JS as an exception (an
// exception across embind would abort the module with -fwasm-exceptions' default handling). A
// call runs guarded: what it throws becomes a message in the file's slot and the call returns
// an empty value; the JS side takes the message after each call (_takeError, _takeIoError,
// _takeQuadError) and throws MrvolError.
#pragma once
#include <emscripten/val.h>

#include <exception>
#include <new>
#include <stdexcept>
#include <string>
#include <utility>

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
      message_ = outOfMemory_;
    } catch (const std::length_error&) {
      message_ = outOfMemory_;
    } catch (const std::exception& e) {
      message_ = e.what();
    } catch (...) {
      message_ = "unknown error";
    }
    return emptyResult<decltype(f())>();
  }

  std::string take() { return std::exchange(message_, std::string()); }

 private:
  std::string message_;
  std::string outOfMemory_;
};

}  // namespace mrvol::bindings
