// A small pool of worker threads for the big per-vertex loops (the surface passes, a correction's
// sweeps): parallelFor splits [begin, end) into one contiguous block per thread, the same blocks for
// the same thread count, and runs them at once, the caller taking the first. Loops whose iterations
// write disjoint outputs give the same results at any thread count; the pool never reduces.
// One pool for the process (set by setThreadCount; 1, the default: everything runs inline, no thread
// is started). Plain std::thread: the native build and a -pthread WASM build use it alike; a WASM
// build without threads keeps 1.
#pragma once
#include <cstddef>
#include <functional>

namespace mrvol {

// Threads for parallelFor (the caller included), clamped to [1, kMaxThreads]; returns the count set.
// Not to be called while a parallelFor runs.
unsigned setThreadCount(unsigned count);
unsigned threadCount();
constexpr unsigned kMaxThreads = 16;
// Whether this build can run threads at all (false: setThreadCount keeps 1).
bool threadsAvailable();

// Caps every loop's grain (0: no cap): tests cut small meshes into blocks for several threads.
void setGrainCap(size_t cap);

// Runs fn(blockBegin, blockEnd) over [begin, end) cut into at most threadCount() contiguous blocks
// of at least `grain` iterations; returns when all are done. Inline (one block) with one thread,
// for short ranges, and when called from inside another parallelFor. An exception thrown by fn is
// rethrown here (the first one) after every block has finished.
template <class F>
void parallelFor(size_t begin, size_t end, size_t grain, F&& fn);

// How many blocks parallelFor cuts n iterations of this grain into (1 when it runs them inline):
// for loops that keep one state per block.
size_t parallelBlocks(size_t n, size_t grain);

// Whether parallelFor runs n iterations of this grain inline (no std::function is made then: a
// small sweep of a drag's step costs a call).
bool runsInline(size_t n, size_t grain);
void parallelForOnPool(size_t begin, size_t end, size_t grain, const std::function<void(size_t, size_t)>& fn);

template <class F>
void parallelFor(size_t begin, size_t end, size_t grain, F&& fn) {
  if (end <= begin) return;
  if (runsInline(end - begin, grain)) {
    fn(begin, end);
    return;
  }
  parallelForOnPool(begin, end, grain, fn);
}

}  // namespace mrvol
