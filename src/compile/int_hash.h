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
    if (!scattered_ && (key >> 32) >= slots_.size() / kSlotsPerHigh) growToHome(key >> 32);
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
  /// edges crowd where many polygons meet, and a run of such vertices
  /// numbered one after another makes a cluster of about a hundred slots
  /// in lt4's world as triangles (each polygon a fan); with a limit of 64,
  /// before, its table was scattered and every edge lookup a cache miss
  /// (docs/performance.md, "Eighth pass"). A scan of a cluster reads
  /// neighbouring lines; the bound is for a crowd (a vertex at the centre
  /// of a fan of thousands: test_int_hash.cpp), whose insertions would
  /// otherwise probe ever longer.
  static constexpr std::size_t kMaxNearProbes = 1024;
  /// Near: the keys of high half h start probing at slot 8 h plus one of
  /// eight picked by the low half's bits mixed (kSlotsPerHigh). Scattered:
  /// Fibonacci hashing of the whole key.
  std::size_t home(std::uint64_t key) const {
    if (scattered_) return static_cast<std::size_t>((key * 0x9e3779b97f4a7c15ull) >> 32) & mask();
    const std::uint64_t spread = ((key & 0xffffffffull) * 0x9e3779b97f4a7c15ull) >> 61;
    return static_cast<std::size_t>((key >> 32) * kSlotsPerHigh + spread) & mask();
  }
  /// Grows the table (a power of two) to kSlotsPerHigh slots a high half up
  /// to h, so that the homes do not wrap round it: wrapped, the high halves
  /// at its two ends share their homes and crowd them (lt4's world as
  /// triangles in the double build, a half-full table, was scattered so:
  /// IntHashMap.KeepsTheEdgesOfLt4AsTrianglesNear). Not past
  /// kMaxSlotsPerKey slots a key: keys with high halves far apart (few of
  /// them) wrap instead.
  void growToHome(std::uint64_t h) {
    std::size_t size = slots_.size();
    while (size / kSlotsPerHigh <= h && size < kMaxSlotsPerKey * (size_ + 1)) size *= 2;
    if (size > slots_.size()) grow(size);
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
  /// The slots of one high half's home (see home()).
  static constexpr std::size_t kSlotsPerHigh = 8;
  /// How sparse growToHome may make the table. A mesh's vertex has a few
  /// edge keys (lt4's world as triangles: about 3.4), so eight slots a
  /// vertex is about 2.4 slots a key, near the two to four of the load
  /// rule; the cap stops a few keys with high halves far apart from
  /// growing it further.
  static constexpr std::size_t kMaxSlotsPerKey = 8;
};

}  // namespace cmkit::detail
