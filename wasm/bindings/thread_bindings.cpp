// The core's thread count (wasm/core thread_pool.h): the -pthread module runs its big loops on
// that many threads; the single-thread module reports 1 and keeps it. Setting it starts threads
// (allocates, may fail): guarded, its error kept for _takeThreadError (guard.h).
#include <emscripten/bind.h>

#include "guard.h"
#include "mrvol/thread_pool.h"

using namespace emscripten;
using namespace mrvol::bindings;

namespace {
ErrorSlot threadErrors("the thread pool");

// 0 (and an error to take) when the pool could not be made.
unsigned js_setThreadCount(unsigned count) { return threadErrors.guarded([&] { return mrvol::setThreadCount(count); }); }
val takeThreadError() { return threadErrors.take(); }
// Neither allocates: they read the pool's count and a constant.
unsigned js_threadCount() { return mrvol::threadCount(); }
bool js_threadsAvailable() { return mrvol::threadsAvailable(); }
}  // namespace

EMSCRIPTEN_BINDINGS(mrvol_threads) {
  function("_setThreadCount", &js_setThreadCount);
  function("_takeThreadError", &takeThreadError);
  function("_threadCount", &js_threadCount);
  function("_threadsAvailable", &js_threadsAvailable);
}
