// Theta files: header, arrays, checksum. Little-endian throughout (x86 and WebAssembly alike).
#include <cmath>
#include <cstring>

#include "mrvol/error.h"
#include "mrvol/volume_tensor.h"

namespace mrvol {

namespace {

uint64_t mix(uint64_t h) {  // splitmix64 finalizer
  h ^= h >> 30, h *= 0xbf58476d1ce4e5b9ull;
  h ^= h >> 27, h *= 0x94d049bb133111ebull;
  return h ^ (h >> 31);
}

constexpr char kMagic[8] = {'M', 'R', 'V', 'O', 'L', 'T', 'H', 'T'};
constexpr size_t kHeaderBytes = 96;

template <class T>
void put(std::string& out, const T& value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof value);
}
template <class T>
void putArray(std::string& out, const std::vector<T>& v) {
  if (!v.empty()) out.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}
void pad8(std::string& out) {
  while (out.size() % 8) out.push_back('\0');
}

template <class T>
T get(const std::string& in, size_t offset) {
  T value;
  std::memcpy(&value, in.data() + offset, sizeof value);
  return value;
}

const char* storageName(TensorStorage s) { return s == TensorStorage::Full ? "full" : "cage"; }

}  // namespace

// Word-wise hash of a byte range (tail bytes folded in).
uint64_t thetaFileChecksum(const char* data, size_t size) {
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

uint64_t connectivityFingerprint(const std::vector<uint32_t>& faces, size_t vertexCount) {
  uint64_t h = mix(0x636f6e6e65637469ull ^ vertexCount);
  for (uint32_t v : faces) h = mix(h ^ v) + 0x9e3779b97f4a7c15ull;
  return h;
}

std::string writeThetaFile(const VolumeTensor& t, const ThetaFileHeader& header) {
  std::string out;
  const uint8_t indexBytes = t.k16.empty() && !t.k32.empty() ? 4 : 2;
  out.append(kMagic, 8);
  put<uint32_t>(out, kThetaFormatVersion);
  put<uint32_t>(out, uint32_t(kHeaderBytes));
  put<uint8_t>(out, uint8_t(header.scheme.kind));
  put<uint8_t>(out, uint8_t(t.storage));
  put<uint8_t>(out, indexBytes);
  put<uint8_t>(out, header.limitSurface ? 1 : 0);  // the surface: 0 the mesh, 1 its Loop limit
  put<uint32_t>(out, uint32_t(header.levels));
  put<uint32_t>(out, uint32_t(t.level));
  put<uint32_t>(out, t.vertexCount);
  put<double>(out, header.scheme.alpha);
  put<double>(out, header.scheme.beta);
  put<uint64_t>(out, header.fingerprint);
  put<uint64_t>(out, t.nnzFull);
  put<uint64_t>(out, t.rowCount);
  put<uint64_t>(out, t.pairJ.size());
  put<uint64_t>(out, t.values.size());
  put<uint64_t>(out, 0);
  putArray(out, t.rowStart);
  putArray(out, t.pairJ);
  putArray(out, t.pairStart);
  if (indexBytes == 2) putArray(out, t.k16);
  else putArray(out, t.k32);
  pad8(out);
  putArray(out, t.values);
  put<uint64_t>(out, thetaFileChecksum(out.data(), out.size()));
  return out;
}

ThetaFileHeader readThetaHeader(const std::string& in) {
  if (in.size() < 8 || std::memcmp(in.data(), kMagic, 8) != 0)
    throw Error("not a theta file (the first bytes are not the mrvol theta magic)");
  if (in.size() < 12) throw Error("theta file is truncated: " + std::to_string(in.size()) + " bytes");
  const uint32_t version = get<uint32_t>(in, 8);
  if (version > kThetaFormatVersion)
    throw Error("theta file format version " + std::to_string(version) + " is newer than this mrvol reads (" +
                std::to_string(kThetaFormatVersion) + "); recompute it or update mrvol");
  if (version == 0) throw Error("theta file has an invalid format version 0");
  if (in.size() < kHeaderBytes + 8) throw Error("theta file is truncated: " + std::to_string(in.size()) + " bytes");
  if (get<uint32_t>(in, 12) != kHeaderBytes) throw Error("theta file header is corrupt (header size)");
  ThetaFileHeader h;
  h.formatVersion = version;
  const uint8_t kind = get<uint8_t>(in, 16), storage = get<uint8_t>(in, 17);
  if (kind > uint8_t(SchemeKind::CatmullClark)) throw Error("theta file header is corrupt (scheme " + std::to_string(kind) + ")");
  if (storage > 1) throw Error("theta file header is corrupt (storage mode " + std::to_string(storage) + ")");
  const uint8_t surface = get<uint8_t>(in, 19);
  if (surface > 1) throw Error("theta file header is corrupt (surface " + std::to_string(surface) + ")");
  h.limitSurface = surface == 1;
  h.scheme.kind = SchemeKind(kind);
  h.storage = TensorStorage(storage);
  h.levels = int(get<uint32_t>(in, 20));
  h.level = int(get<uint32_t>(in, 24));
  h.vertexCount = get<uint32_t>(in, 28);
  h.scheme.alpha = get<double>(in, 32);
  h.scheme.beta = get<double>(in, 40);
  h.fingerprint = get<uint64_t>(in, 48);
  h.nnzFull = get<uint64_t>(in, 56);
  h.nnzStored = get<uint64_t>(in, 80);
  if (h.level > h.levels || h.levels > 16) throw Error("theta file header is corrupt (levels)");
  return h;
}

VolumeTensor readThetaFile(const std::string& in, ThetaFileHeader* headerOut) {
  ThetaFileHeader h = readThetaHeader(in);
  const uint8_t indexBytes = get<uint8_t>(in, 18);
  const uint64_t rowCount = get<uint64_t>(in, 64), pairs = get<uint64_t>(in, 72), entries = get<uint64_t>(in, 80);
  if ((indexBytes != 2 && indexBytes != 4) || rowCount > h.vertexCount || pairs > (uint64_t(1) << 32) ||
      entries > (uint64_t(1) << 32))
    throw Error("theta file header is corrupt (counts)");
  uint64_t size = kHeaderBytes + 4 * (rowCount + 1) + 4 * pairs + 4 * (pairs + 1) + indexBytes * entries;
  size = (size + 7) / 8 * 8 + 8 * entries + 8;
  if (in.size() < size)
    throw Error("theta file is truncated: expected " + std::to_string(size) + " bytes, found " + std::to_string(in.size()));
  if (in.size() > size)
    throw Error("theta file is corrupt: expected " + std::to_string(size) + " bytes, found " + std::to_string(in.size()));
  if (get<uint64_t>(in, size - 8) != thetaFileChecksum(in.data(), size - 8))
    throw Error("theta file checksum does not match: the file is damaged");
  VolumeTensor t;
  t.level = h.level;
  t.storage = h.storage;
  t.vertexCount = h.vertexCount;
  t.rowCount = uint32_t(rowCount);
  t.nnzFull = h.nnzFull;
  size_t at = kHeaderBytes;
  auto take = [&](auto& v, size_t count) {
    using T = typename std::decay_t<decltype(v)>::value_type;
    v.resize(count);
    if (count) std::memcpy(v.data(), in.data() + at, count * sizeof(T));
    at += count * sizeof(T);
  };
  take(t.rowStart, rowCount + 1);
  take(t.pairJ, pairs);
  take(t.pairStart, pairs + 1);
  if (indexBytes == 2) take(t.k16, entries);
  else take(t.k32, entries);
  at = (at + 7) / 8 * 8;
  take(t.values, entries);
  // Structure: offsets ascending and consistent, indices i < j < k < N, values finite.
  if (t.rowStart[0] != 0 || t.rowStart[rowCount] != pairs || t.pairStart[0] != 0 || t.pairStart[pairs] != entries)
    throw Error("theta file is corrupt (offsets)");
  // Ascending offsets between fixed ends stay in range: checked before any is used as an index
  // (a row running past `pairs` and coming back would otherwise be read first; found by fuzz_theta).
  for (uint32_t i = 0; i < rowCount; ++i)
    if (t.rowStart[i] > t.rowStart[i + 1]) throw Error("theta file is corrupt (row offsets)");
  for (uint64_t p = 0; p < pairs; ++p)
    if (t.pairStart[p] > t.pairStart[p + 1]) throw Error("theta file is corrupt (pair " + std::to_string(p) + ")");
  for (uint32_t i = 0; i < rowCount; ++i) {
    uint32_t lastJ = i;
    for (uint32_t p = t.rowStart[i]; p < t.rowStart[i + 1]; ++p) {
      const uint32_t j = t.pairJ[p];
      if (j <= lastJ || j >= t.vertexCount || t.pairStart[p] >= t.pairStart[p + 1])
        throw Error("theta file is corrupt (pair " + std::to_string(p) + ")");
      lastJ = j;
      uint32_t lastK = j;
      for (uint32_t e = t.pairStart[p]; e < t.pairStart[p + 1]; ++e) {
        const uint32_t k = t.kIndex(e);
        if (k <= lastK || k >= t.vertexCount || !std::isfinite(t.values[e]))
          throw Error("theta file is corrupt (entry " + std::to_string(e) + ")");
        lastK = k;
      }
    }
  }
  if (headerOut) *headerOut = h;
  (void)storageName;
  return t;
}

}  // namespace mrvol
