// Internal: a map from 64-bit keys to non-negative ints for the build's edge
// table: open addressing with linear probing in one array, so a lookup
// touches one or two cache lines where a node-based std::unordered_map
// chases pointers. Keys whose high halves are near each other (edges of
// vertices numbered near each other) go to slots near each other, until an
// insertion probes too far (many keys with one high half: a vertex at the
// centre of a large fan); from then on the keys are scattered over the
// table, and a lookup in a table larger than the caches is a cache miss.
// Only where a key lies changes, never what the map holds.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace cmkit::detail {

class IntHashMap {
 public:
  /// No value (a slot without a key).
  static constexpr int kEmpty = -1;

  void clear() {
    slots_.clear();
    size_ = 0;
    scattered_ = false;
  }
  /// Room for `count` keys without growing.
  void reserve(std::size_t count) {
    std::size_t size = 64;
    while (size < 2 * count) size *= 2;
    if (size > slots_.size()) grow(size);
  }
  /// Whether the keys are scattered over the table (see home()).
  bool scattered() const { return scattered_; }
  /// The value of `key`, or kEmpty.
  int find(std::uint64_t key) const {
    if (slots_.empty()) return kEmpty;
    for (std::size_t i = home(key);; i = (i + 1) & mask()) {
      const Slot& s = slots_[i];
      if (s.value == kEmpty) return kEmpty;
      if (s.key == key) return s.value;
    }
  }
  /// The value of `key`, kEmpty when it is new: the caller stores a
  /// non-negative value there (kEmpty left there means no value).
  int& at(std::uint64_t key) {
    if (2 * (size_ + 1) > slots_.size()) grow(slots_.empty() ? 64 : 2 * slots_.size());
    std::size_t probes = 0;
    for (std::size_t i = home(key);; i = (i + 1) & mask()) {
      Slot& s = slots_[i];
      if (s.value == kEmpty) {
        if (probes > kMaxNearProbes && !scattered_) {
          scattered_ = true;  // (the same slots again, every key placed anew)
          grow(slots_.size());
          return at(key);
        }
        s.key = key;
        ++size_;
        return s.value;
      }
      if (s.key == key) return s.value;
      ++probes;
    }
  }

 private:
  struct Slot {
    std::uint64_t key = 0;
    int value = kEmpty;
  };
  std::size_t mask() const { return slots_.size() - 1; }
  /// Probes of an insertion past which the keys are scattered. A mesh's
  /// edges cluster where many polygons meet: lt4's world as triangles (each
  /// polygon a fan) made one insertion probe past 64, the limit before, and
  /// its scattered 4 MB table made the edge lookups the largest part of the
  /// mesh build (docs/performance.md, "Eighth pass"). Still a bound on the
  /// work of a crowd (a vertex at the centre of a fan of thousands:
  /// test_int_hash.cpp).
  static constexpr std::size_t kMaxNearProbes = 256;
  /// Near: eight slots per value of the key's high half, picked among by
  /// the low half's bits mixed. Scattered: Fibonacci hashing of the whole
  /// key.
  std::size_t home(std::uint64_t key) const {
    if (scattered_) return static_cast<std::size_t>((key * 0x9e3779b97f4a7c15ull) >> 32) & mask();
    const std::uint64_t spread = ((key & 0xffffffffull) * 0x9e3779b97f4a7c15ull) >> 61;
    return static_cast<std::size_t>(((key >> 32) << 3) + spread) & mask();
  }
  void grow(std::size_t size) {
    std::vector<Slot> old = std::move(slots_);
    slots_.assign(size, Slot{});
    size_ = 0;
    for (const Slot& s : old) {
      if (s.value != kEmpty) at(s.key) = s.value;
    }
  }

  std::vector<Slot> slots_;  ///< a power of two in size, at most half used
  std::size_t size_ = 0;
  bool scattered_ = false;  ///< see home()
};

}  // namespace cmkit::detail
