// Typed catch clauses in the -pthread WASM build (-fwasm-exceptions) made with clang 14 and
// emscripten 3.1.6 (Debian's pair). A landing pad hands the personality function its frame's
// landing-pad index and LSDA through __wasm_lpad_context and reads back the selector (which clause
// matched). Emscripten 3.1.6's libunwind defines that variable thread_local, as LLVM 15 addresses
// it; clang 14 addresses it as a plain global (absolute address). With threads the pads and the
// personality then use different memory and every typed catch misses (catch (...) still catches).
//
// Linked with --wrap=_Unwind_CallPersonality, the pads' call lands here and the personality gets
// the plain global the pads wrote. That global is one for all threads, so exception dispatches are
// made one at a time: a thread holds a lock from its throw (_Unwind_RaiseException: throw,
// rethrow, rethrow_exception) to the handler that takes it (__cxa_begin_catch); a throw on another
// thread waits for it. An exception that left WASM uncaught would keep the lock on its thread (a
// throw on another thread would then wait for ever): the bindings catch what the core throws
// (wasm/bindings/guard.h). tests/wasm/typed_catch_threads.cpp checks typed catches on four threads.
#include <unwind.h>

#include <atomic>
#include <cstdint>

namespace {

struct LandingPadContext {
  uintptr_t lpadIndex;
  uintptr_t lsda;
  uintptr_t selector;
};

std::atomic<uintptr_t> dispatchOwner{0};
thread_local unsigned dispatchDepth = 0;  // throws in flight on this thread (nested: a destructor's own)

uintptr_t thisThread() { return reinterpret_cast<uintptr_t>(&dispatchDepth); }

void beginDispatch() {
  if (dispatchDepth++ > 0) return;
  uintptr_t free = 0;
  while (!dispatchOwner.compare_exchange_weak(free, thisThread(), std::memory_order_acquire)) free = 0;
}

void endDispatch() {
  // A catch of a foreign (JS) exception did not start a dispatch here.
  if (dispatchDepth == 0 || --dispatchDepth > 0) return;
  dispatchOwner.store(0, std::memory_order_release);
}

}  // namespace

extern "C" {

// Where clang 14's landing pads write (declared plain here, as they address it).
extern LandingPadContext __wasm_lpad_context;

_Unwind_Reason_Code __gxx_personality_wasm0(int version, _Unwind_Action actions, uint64_t exceptionClass,
                                            _Unwind_Exception* exception, _Unwind_Context* context);
_Unwind_Reason_Code __real__Unwind_RaiseException(_Unwind_Exception* exception);
void* __real___cxa_begin_catch(void* exception);

_Unwind_Reason_Code __wrap__Unwind_CallPersonality(void* exceptionPointer) {
  auto* exception = static_cast<_Unwind_Exception*>(exceptionPointer);
  __wasm_lpad_context.selector = 0;
  // WASM unwinds in one phase: the cleanup phase only (as libunwind's own call does).
  return __gxx_personality_wasm0(1, _UA_CLEANUP_PHASE, exception->exception_class, exception,
                                 reinterpret_cast<_Unwind_Context*>(&__wasm_lpad_context));
}

_Unwind_Reason_Code __wrap__Unwind_RaiseException(_Unwind_Exception* exception) {
  beginDispatch();
  return __real__Unwind_RaiseException(exception);
}

void* __wrap___cxa_begin_catch(void* exception) {
  endDispatch();
  return __real___cxa_begin_catch(exception);
}

}  // extern "C"
