// Exact float32 positions numbered in the order they are first met: the table a binary STL is
// welded through while it is read (one lookup per triangle corner).
#pragma once
#include <cstdint>
#include <vector>

namespace mrvol::io {

// Keys are the three coordinates' bit patterns, which the caller makes equal for -0 and +0 (NaN
// never reaches it: readers refuse non-finite coordinates). Most lookups find a position met a
// few triangles earlier: a small direct-mapped cache of recent keys (64 KB) answers those without
// visiting the large table. The large table (open addressing, linear probing) holds 16-byte
// slots, the key beside its number, so that a lookup reads one cache line (a slot and a separate
// array of keys would be two misses for a key met before); it doubles when three quarters full.
class FloatPositionTable {
 public:
  // Sized for `expected` positions (more are fine: it grows).
  explicit FloatPositionTable(size_t expected) : recent_(kRecent, Entry{{0, 0, 0}, kNone}) {
    size_t capacity = 64;
    while (3 * capacity < 4 * expected) capacity *= 2;
    resize(capacity);
  }

  // The number of the key: its place among the distinct keys in the order of their first lookup
  // (a new key gets size() - 1).
  uint32_t findOrAdd(const uint32_t (&key)[3]) {
    const uint64_t h = hash(key);
    Entry& recent = recent_[h & (kRecent - 1)];
    if (recent.number != kNone && same(recent.key, key)) return recent.number;
    size_t s = size_t(h >> shift_);
    for (;; s = (s + 1) & mask_) {
      ++probes_;
      const Entry& slot = slots_[s];
      if (slot.number == kNone) break;
      if (same(slot.key, key)) {
        recent = slot;
        return slot.number;
      }
    }
    const Entry entry = {{key[0], key[1], key[2]}, uint32_t(size_)};
    slots_[s] = entry;
    recent = entry;
    if (4 * ++size_ > 3 * slots_.size()) resize(2 * slots_.size());
    return entry.number;
  }

  // The number of a key already added, or kNone; reads only (several threads may look up at once).
  uint32_t find(const uint32_t (&key)[3], uint64_t& probes) const {
    for (size_t s = size_t(hash(key) >> shift_);; s = (s + 1) & mask_) {
      ++probes;
      const Entry& slot = slots_[s];
      if (slot.number == kNone || same(slot.key, key)) return slot.number;
    }
  }

  size_t size() const { return size_; }
  // Every key added is in one of the slots [0, capacity()): entry() gives it and its number (false:
  // an empty slot).
  size_t capacity() const { return slots_.size(); }
  bool entry(size_t slot, uint32_t (&key)[3], uint32_t& number) const {
    const Entry& e = slots_[slot];
    key[0] = e.key[0], key[1] = e.key[1], key[2] = e.key[2], number = e.number;
    return e.number != kNone;
  }
  // The key's 64-bit mix: its high bits choose the home slot, its low bits the cache entry.
  static uint64_t hash(const uint32_t (&key)[3]) {
    uint64_t h = ((uint64_t(key[0]) << 32) | key[1]) * 0x9E3779B97F4A7C15ull;
    return (h ^ (h >> 29) ^ uint64_t(key[2]) * 0xC2B2AE3D27D4EB4Full) * 0xBF58476D1CE4E5B9ull;
  }
  // Slots of the large table visited so far: about one per lookup that the cache did not answer,
  // unless keys were made to collide.
  uint64_t probes() const { return probes_; }

  static constexpr uint32_t kNone = 0xffffffffu;  // numbers stay below 2^32 - 1

 private:
  static constexpr size_t kRecent = 4096;
  struct Entry {
    uint32_t key[3];
    uint32_t number;
  };

  static bool same(const uint32_t (&a)[3], const uint32_t (&b)[3]) { return a[0] == b[0] && a[1] == b[1] && a[2] == b[2]; }

  void resize(size_t capacity) {
    std::vector<Entry> old(capacity, Entry{{0, 0, 0}, kNone});
    old.swap(slots_);
    mask_ = capacity - 1;
    shift_ = 64;
    for (size_t c = capacity; c > 1; c /= 2) --shift_;
    for (const Entry& entry : old) {
      if (entry.number == kNone) continue;
      size_t s = size_t(hash(entry.key) >> shift_);
      while (slots_[s].number != kNone) s = (s + 1) & mask_;
      slots_[s] = entry;
    }
  }

  std::vector<Entry> recent_;
  std::vector<Entry> slots_;
  size_t size_ = 0;
  size_t mask_ = 0;
  int shift_ = 64;
  uint64_t probes_ = 0;
};

}  // namespace mrvol::io
