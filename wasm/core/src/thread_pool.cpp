#include "mrvol/thread_pool.h"

#include <algorithm>
#include <condition_variable>
#include <exception>
#include <memory>
#include <mutex>
#include <vector>

#if defined(__EMSCRIPTEN__) && !defined(__EMSCRIPTEN_PTHREADS__)
#define MRVOL_NO_THREADS 1
#else
#include <thread>
#endif

namespace mrvol {

namespace {

thread_local bool insideParallelFor = false;
size_t grainCap = 0;

#ifndef MRVOL_NO_THREADS
// Workers 1 .. count - 1 wait for a job generation; each runs its block, then counts itself done.
class Pool {
 public:
  explicit Pool(unsigned count) : count_(count) {
    for (unsigned k = 1; k < count; ++k) workers_.emplace_back([this, k] { work(k); });
  }
  ~Pool() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    start_.notify_all();
    for (std::thread& t : workers_) t.join();
  }
  unsigned count() const { return count_; }

  void run(unsigned blocks, const std::function<void(unsigned)>& block) {
    std::lock_guard<std::mutex> one(runMutex_);  // one job at a time (callers from several threads wait)
    {
      std::lock_guard<std::mutex> lock(mutex_);
      job_ = &block, blocks_ = blocks, pending_ = blocks - 1, error_ = nullptr;
      ++generation_;
    }
    start_.notify_all();
    runBlock(0);
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [this] { return pending_ == 0; });
    job_ = nullptr;
    if (error_) std::rethrow_exception(error_);
  }

 private:
  void runBlock(unsigned k) {
    insideParallelFor = true;
    try {
      (*job_)(k);
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!error_) error_ = std::current_exception();
    }
    insideParallelFor = false;
  }
  void work(unsigned k) {
    unsigned long seen = 0;
    for (;;) {
      {
        std::unique_lock<std::mutex> lock(mutex_);
        start_.wait(lock, [&] { return stop_ || generation_ != seen; });
        if (stop_) return;
        seen = generation_;
        if (k >= blocks_) continue;  // fewer blocks than threads this time
      }
      runBlock(k);
      std::lock_guard<std::mutex> lock(mutex_);
      if (--pending_ == 0) done_.notify_one();
    }
  }

  unsigned count_;
  std::vector<std::thread> workers_;
  std::mutex runMutex_, mutex_;
  std::condition_variable start_, done_;
  const std::function<void(unsigned)>* job_ = nullptr;
  unsigned blocks_ = 0, pending_ = 0;
  unsigned long generation_ = 0;
  bool stop_ = false;
  std::exception_ptr error_;
};

std::unique_ptr<Pool>& pool() {
  static std::unique_ptr<Pool> p;
  return p;
}
#endif

}  // namespace

bool threadsAvailable() {
#ifdef MRVOL_NO_THREADS
  return false;
#else
  return true;
#endif
}

unsigned setThreadCount(unsigned count) {
#ifdef MRVOL_NO_THREADS
  (void)count;
  return 1;
#else
  count = std::clamp(count, 1u, kMaxThreads);
  if (threadCount() == count) return count;
  pool().reset();
  if (count > 1) pool() = std::make_unique<Pool>(count);
  return count;
#endif
}

unsigned threadCount() {
#ifdef MRVOL_NO_THREADS
  return 1;
#else
  return pool() ? pool()->count() : 1;
#endif
}

void setGrainCap(size_t cap) { grainCap = cap; }

namespace {
size_t blockCount(size_t n, size_t grain) {
  if (grainCap > 0) grain = std::min(grain, grainCap);
  return std::min<size_t>(threadCount(), n / std::max<size_t>(grain, 1));
}
}  // namespace

size_t parallelBlocks(size_t n, size_t grain) { return insideParallelFor ? 1 : std::max<size_t>(blockCount(n, grain), 1); }

bool runsInline(size_t n, size_t grain) { return insideParallelFor || blockCount(n, grain) <= 1; }

void parallelForOnPool(size_t begin, size_t end, size_t grain, const std::function<void(size_t, size_t)>& fn) {
  if (end <= begin) return;
  const size_t n = end - begin;
  const size_t blocks = blockCount(n, grain);
  if (blocks <= 1 || insideParallelFor) {
    fn(begin, end);
    return;
  }
#ifndef MRVOL_NO_THREADS
  // Equal blocks (the first ones one longer): the same cut for the same count.
  const size_t size = n / blocks, extra = n % blocks;
  pool()->run(unsigned(blocks), [&](unsigned k) {
    const size_t from = begin + k * size + std::min<size_t>(k, extra);
    fn(from, from + size + (k < extra ? 1 : 0));
  });
#endif
}

}  // namespace mrvol
