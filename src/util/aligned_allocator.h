// Internal: an allocator of memory aligned to `Align` bytes, for arrays whose
// elements' offsets must fall on cache lines (std::allocator aligns to the
// element type's own alignment only).
#pragma once

#include <cstddef>
#include <new>

namespace cmkit::detail {

template <class T, std::size_t Align>
struct AlignedAllocator {
  static_assert(Align >= alignof(T) && (Align & (Align - 1)) == 0);
  using value_type = T;
  template <class U>
  struct rebind {
    using other = AlignedAllocator<U, Align>;
  };
  AlignedAllocator() noexcept = default;
  template <class U>
  AlignedAllocator(const AlignedAllocator<U, Align>&) noexcept {}
  T* allocate(std::size_t n) {
    return static_cast<T*>(::operator new (n * sizeof(T), std::align_val_t{Align}));
  }
  // (The unsized aligned delete: Clang declares the sized one only with
  // -fsized-deallocation.)
  void deallocate(T* p, std::size_t) noexcept { ::operator delete (p, std::align_val_t{Align}); }
  friend bool operator==(const AlignedAllocator&, const AlignedAllocator&) noexcept { return true; }
};

}  // namespace cmkit::detail
