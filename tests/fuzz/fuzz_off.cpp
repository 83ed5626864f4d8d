// libFuzzer target: arbitrary bytes through the OFF reader (mrvol::readOff), then the checks of
// mesh_file_checks.h (well-formed result, welding complete, validation answers, GLB round trip).
//
//   build/fuzz/fuzz_off build/fuzz/corpus-fuzz_off
#include "mesh_file_checks.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return fuzzing::runReader(data, size, [](std::string_view bytes) { return mrvol::readOff(bytes); });
}
