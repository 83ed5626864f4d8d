// libFuzzer target: the theta-file reader (mrvol::readThetaFile). A mutated file almost never
// keeps its checksum, so with the first byte odd the harness recomputes it (the same word-wise
// hash as theta_file.cpp) and the structural checks behind it are reached too. A file that reads
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

// theta_file.cpp's checksum (splitmix64-finalized word-wise hash), copied to fix up inputs.
uint64_t mix(uint64_t h) {
  h ^= h >> 30, h *= 0xbf58476d1ce4e5b9ull;
  h ^= h >> 27, h *= 0x94d049bb133111ebull;
  return h ^ (h >> 31);
}
uint64_t hashBytes(const char* data, size_t size) {
  uint64_t h = 0x6d72766f6c746874ull ^ size;
  size_t i = 0;
  for (; i + 8 <= size; i += 8) {
    uint64_t w;
    std::memcpy(&w, data + i, 8);
    h = (h ^ w) * 0x100000001b3ull;
    h ^= h >> 29;
  }
  uint64_t tail = 0;
  std::memcpy(&tail, data + i, size - i);
  return mix(h ^ tail);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  std::string bytes(reinterpret_cast<const char*>(data) + 1, size - 1);
  if ((data[0] & 1) && bytes.size() >= 8) {
    const uint64_t sum = hashBytes(bytes.data(), bytes.size() - 8);
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
