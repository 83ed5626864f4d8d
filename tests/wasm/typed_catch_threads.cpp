// Typed catch clauses on several threads at once in a -pthread -fwasm-exceptions build (the
// threaded module's exception set-up, wasm/toolchain/landing_pad_context.cpp): threads throw
// exceptions of four types in a loop, each caught two frames up by the clause of its type (the
// inner frame's clauses take two of them, the outer frame's the other two). Prints how many were
// caught by the right clause and how many were not; tests/node/threads.test.mjs runs it.
// Without the dispatch lock (landing pads of all threads sharing one context) about 1 in 10^4 of
// these exceptions landed in another clause.
#include <atomic>
#include <cstdio>
#include <stdexcept>
#include <thread>
#include <vector>

namespace {

struct InnerError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
struct OuterError : std::logic_error {
  using std::logic_error::logic_error;
};

constexpr int kThreads = 4, kThrowsPerThread = 20000;

// Throws the type of k % 4; noinline keeps the throw in a frame of its own.
__attribute__((noinline)) void throwKind(int k) {
  switch (k % 4) {
    case 0: throw InnerError("inner");
    case 1: throw OuterError("outer");
    case 2: throw std::out_of_range("out of range");
    default: throw k;
  }
}

__attribute__((noinline)) int innerCatch(int k) {
  try {
    throwKind(k);
  } catch (const InnerError&) {
    return 0;
  } catch (const std::out_of_range&) {
    return 2;
  }
  return -1;
}

// The kind whose clause caught k's exception (-1, -2: none, or the wrong value).
__attribute__((noinline)) int caughtKind(int k) {
  try {
    return innerCatch(k);
  } catch (const OuterError&) {
    return 1;
  } catch (int value) {
    return value == k ? 3 : -2;
  }
}

}  // namespace

int main() {
  std::atomic<long> right{0}, wrong{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t)
    threads.emplace_back([t, &right, &wrong] {
      for (int i = 0; i < kThrowsPerThread; ++i) (caughtKind(i + t) == (i + t) % 4 ? right : wrong)++;
    });
  for (std::thread& thread : threads) thread.join();
  std::printf("caught by the right clause: %ld, by another or none: %ld\n", right.load(), wrong.load());
  return wrong == 0 && right == long(kThreads) * kThrowsPerThread ? 0 : 1;
}
