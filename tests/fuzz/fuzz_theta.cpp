// libFuzzer target: the theta-file reader (mrvol::readThetaFile). A mutated file almost never
// keeps its checksum, so with the first byte odd the harness recomputes it (with the
// core's thetaFileChecksum) and the structural checks behind it are reached too. A file that reads
// must write back to a file that reads to the same tensor.
//
//   build/fuzz/fuzz_theta build/fuzz/corpus-fuzz_theta
#include <cstdint>
#include <cstring>
#include <new>
#include <string>

#include "mrvol/error.h"
#include "mrvol/volume_tensor.h"

namespace {

void check(bool ok) {
  if (!ok) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  std::string bytes(reinterpret_cast<const char*>(data) + 1, size - 1);
  if ((data[0] & 1) && bytes.size() >= 8) {
    const uint64_t sum = mrvol::thetaFileChecksum(bytes.data(), bytes.size() - 8);
    std::memcpy(&bytes[bytes.size() - 8], &sum, 8);
  }
  try {
    mrvol::ThetaFileHeader header;
    mrvol::VolumeTensor tensor = mrvol::readThetaFile(bytes, &header);
    mrvol::ThetaFileHeader again;
    mrvol::VolumeTensor back = mrvol::readThetaFile(mrvol::writeThetaFile(tensor, header), &again);
    check(again.vertexCount == header.vertexCount && again.nnzStored == header.nnzStored &&
          again.fingerprint == header.fingerprint && again.level == header.level && again.levels == header.levels);
    check(back.values.size() == tensor.values.size() &&
          std::memcmp(back.values.data(), tensor.values.data(), 8 * tensor.values.size()) == 0);
  } catch (const mrvol::Error&) {
  } catch (const std::bad_alloc&) {
  }
  return 0;
}
