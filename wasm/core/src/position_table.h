// Exact float32 positions numbered in the order they are first met: the table a binary STL is
// welded through while it is read (one lookup per triangle corner).
#pragma once
#include <cstdint>
#include <vector>

namespace mrvol::io {

// Keys are the three coordinates' bit patterns, which the caller makes equal for -0 and +0 (NaN
// never reaches it: readers refuse non-finite coordinates). Most lookups find a position met a
// few triangles earlier: a small direct-mapped cache of recent keys (64 KB) answers those without
// visiting the large table. The large table (open addressing, linear probing) holds 8-byte slots,
// the key's number beside 32 bits of its hash, so that a probe reads the key itself only when the
// hash bits agree; it doubles when three quarters full.
class FloatPositionTable {
 public:
  // Sized for `expected` positions (more are fine: it grows).
  explicit FloatPositionTable(size_t expected) : recent_(kRecent, Recent{{0, 0, 0}, kNone}) {
    size_t capacity = 64;
    while (3 * capacity < 4 * expected) capacity *= 2;
    keys_.reserve(expected);
    resize(capacity);
  }

  // The number of the key: its place among the distinct keys in the order of their first lookup
  // (a new key gets size() - 1).
  uint32_t findOrAdd(const uint32_t (&key)[3]) {
    const uint64_t h = hash(key);
    Recent& recent = recent_[h & (kRecent - 1)];
    if (recent.number != kNone && same(recent.key, key)) return recent.number;
    const uint32_t tag = uint32_t(h);
    size_t s = size_t(h >> shift_);
    for (;; s = (s + 1) & mask_) {
      ++probes_;
      const uint64_t slot = slots_[s];
      if (slot == kEmpty) break;
      if (uint32_t(slot >> 32) == tag && same(keys_[uint32_t(slot)].xyz, key)) {
        recent = {{key[0], key[1], key[2]}, uint32_t(slot)};
        return uint32_t(slot);
      }
    }
    const uint32_t number = uint32_t(keys_.size());
    keys_.push_back({{key[0], key[1], key[2]}});
    slots_[s] = (uint64_t(tag) << 32) | number;
    if (4 * keys_.size() > 3 * slots_.size()) resize(2 * slots_.size());
    recent = {{key[0], key[1], key[2]}, number};
    return number;
  }

  size_t size() const { return keys_.size(); }
  // The key's 64-bit mix: its high bits choose the home slot, its low bits the cache entry.
  static uint64_t hash(const uint32_t (&key)[3]) {
    uint64_t h = ((uint64_t(key[0]) << 32) | key[1]) * 0x9E3779B97F4A7C15ull;
    return (h ^ (h >> 29) ^ uint64_t(key[2]) * 0xC2B2AE3D27D4EB4Full) * 0xBF58476D1CE4E5B9ull;
  }
  // Slots of the large table visited so far: about one per lookup that the cache did not answer,
  // unless keys were made to collide.
  uint64_t probes() const { return probes_; }

 private:
  static constexpr uint32_t kNone = 0xffffffffu;
  static constexpr uint64_t kEmpty = ~uint64_t(0);  // numbers stay below 2^32 - 1
  static constexpr size_t kRecent = 4096;
  struct Key {
    uint32_t xyz[3];
  };
  struct Recent {
    uint32_t key[3];
    uint32_t number;
  };

  static bool same(const uint32_t (&a)[3], const uint32_t (&b)[3]) { return a[0] == b[0] && a[1] == b[1] && a[2] == b[2]; }


  void resize(size_t capacity) {
    slots_.assign(capacity, kEmpty);
    mask_ = capacity - 1;
    shift_ = 64;
    for (size_t c = capacity; c > 1; c /= 2) --shift_;
    for (uint32_t number = 0; number < keys_.size(); ++number) {
      const uint64_t h = hash(keys_[number].xyz);
      size_t s = size_t(h >> shift_);
      while (slots_[s] != kEmpty) s = (s + 1) & mask_;
      slots_[s] = (uint64_t(uint32_t(h)) << 32) | number;
    }
  }

  std::vector<Recent> recent_;
  std::vector<Key> keys_;
  std::vector<uint64_t> slots_;
  size_t mask_ = 0;
  int shift_ = 64;
  uint64_t probes_ = 0;
};

}  // namespace mrvol::io
