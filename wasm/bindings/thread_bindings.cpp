// The core's thread count (wasm/core thread_pool.h): the -pthread module runs its big loops on
// that many threads; the single-thread module reports 1 and keeps it.
#include <emscripten/bind.h>

#include "mrvol/thread_pool.h"

using namespace emscripten;

namespace {
unsigned js_setThreadCount(unsigned count) { return mrvol::setThreadCount(count); }
unsigned js_threadCount() { return mrvol::threadCount(); }
bool js_threadsAvailable() { return mrvol::threadsAvailable(); }
}  // namespace

EMSCRIPTEN_BINDINGS(mrvol_threads) {
  function("_setThreadCount", &js_setThreadCount);
  function("_threadCount", &js_threadCount);
  function("_threadsAvailable", &js_threadsAvailable);
}
