// A polygon's signed edge numbers while its model is built (BPolygon::edges).
#pragma once

#include <cstdint>
#include <cstring>
#include <new>
#include <span>

#include "util/assert.h"

namespace cmkit::detail {

/// The signed edge numbers of a polygon being built: up to kInline of them
/// inside the list (triangles, quads and most merged polygons), more on the
/// heap. A mesh of many triangles made one heap block per polygon with a
/// std::vector, freed again when the builder is done, and every pass that
/// reads a polygon's edges (merging, internal edges, flattening) went to
/// that block somewhere else in memory.
class EdgeList {
 public:
  /// Edges held in place (the list is 32 bytes, as a std::vector's 24 plus
  /// one word).
  static constexpr std::uint32_t kInline = 6;

  EdgeList() = default;
  EdgeList(const EdgeList& other) { assign(other.data(), other.size_); }
  EdgeList(EdgeList&& other) noexcept { take(other); }
  EdgeList& operator=(const EdgeList& other) {
    if (this != &other) {
      size_ = 0;
      assign(other.data(), other.size_);
    }
    return *this;
  }
  EdgeList& operator=(EdgeList&& other) noexcept {
    if (this != &other) {
      release();
      take(other);
    }
    return *this;
  }
  ~EdgeList() { release(); }

  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  int* data() { return onHeap() ? heap_ : inline_; }
  const int* data() const { return onHeap() ? heap_ : inline_; }
  int* begin() { return data(); }
  int* end() { return data() + size_; }
  const int* begin() const { return data(); }
  const int* end() const { return data() + size_; }
  int& operator[](std::size_t i) {
    CMKIT_ASSERT(i < size_);
    return data()[i];
  }
  int operator[](std::size_t i) const {
    CMKIT_ASSERT(i < size_);
    return data()[i];
  }
  operator std::span<const int>() const { return {data(), size_}; }

  void push_back(int e) {
    if (size_ == capacity_) grow(2 * capacity_);
    data()[size_++] = e;
  }
  /// Keeps the room (a polygon's list emptied when it is freed).
  void clear() { size_ = 0; }
  /// Shortens the list (n <= size()).
  void truncate(std::size_t n) {
    CMKIT_ASSERT(n <= size_);
    size_ = static_cast<std::uint32_t>(n);
  }
  void reserve(std::size_t n) {
    if (n > capacity_) grow(static_cast<std::uint32_t>(n));
  }

 private:
  bool onHeap() const { return capacity_ > kInline; }
  void grow(std::uint32_t capacity) {
    int* more = new int[capacity];
    if (size_ != 0) std::memcpy(more, data(), size_ * sizeof(int));
    release();
    heap_ = more;
    capacity_ = capacity;
  }
  void assign(const int* edges, std::uint32_t n) {
    reserve(n);
    if (n != 0) std::memcpy(data(), edges, n * sizeof(int));
    size_ = n;
  }
  void take(EdgeList& other) {
    size_ = other.size_;
    capacity_ = other.capacity_;
    if (other.onHeap()) {
      heap_ = other.heap_;
    } else {
      std::memcpy(inline_, other.inline_, sizeof inline_);  // (whole: no call for a size known late)
    }
    other.size_ = 0;
    other.capacity_ = kInline;
  }
  void release() {
    if (onHeap()) delete[] heap_;
    capacity_ = kInline;
  }

  std::uint32_t size_ = 0;
  std::uint32_t capacity_ = kInline;
  union {
    int inline_[kInline] = {};  // (all set: a move copies the whole array)
    int* heap_;
  };
};

}  // namespace cmkit::detail
