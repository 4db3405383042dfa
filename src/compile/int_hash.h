// Internal: a map from 64-bit keys to non-negative ints for the build's edge
// table: open addressing with linear probing in one array, so a lookup
// touches one or two cache lines where a node-based std::unordered_map
// chases pointers.
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
  }
  /// Room for `count` keys without growing.
  void reserve(std::size_t count) {
    std::size_t size = 64;
    while (size < 2 * count) size *= 2;
    if (size > slots_.size()) grow(size);
  }
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
    for (std::size_t i = home(key);; i = (i + 1) & mask()) {
      Slot& s = slots_[i];
      if (s.value == kEmpty) {
        s.key = key;
        ++size_;
        return s.value;
      }
      if (s.key == key) return s.value;
    }
  }

 private:
  struct Slot {
    std::uint64_t key = 0;
    int value = kEmpty;
  };
  std::size_t mask() const { return slots_.size() - 1; }
  /// Fibonacci hashing: the key's bits mixed into the table's index bits.
  std::size_t home(std::uint64_t key) const {
    return static_cast<std::size_t>((key * 0x9e3779b97f4a7c15ull) >> 32) & mask();
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
};

}  // namespace cmkit::detail
