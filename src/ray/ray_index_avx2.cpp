// The AVX2 node test of RayIndex: all eight children of a node in one pass.
// This file is compiled with -mavx2 (src/CMakeLists.txt) and only called
// when the processor has AVX2 (RayIndex picks it when built); everything it
// runs is in ray_index_kernel.h, which explains the rules this file keeps:
// no inline functions of other headers, only intrinsics and builtins.
#include "ray/ray_index_kernel.h"

#if defined(CMKIT_AVX2_KERNEL) && !defined(CMKIT_NO_SIMD)
#include <immintrin.h>
#endif

namespace cmkit::detail {

#if defined(CMKIT_AVX2_KERNEL) && !defined(CMKIT_NO_SIMD)
namespace {

/// As enteredChildren in ray_index.cpp, the same arithmetic on all eight
/// children at once.
int enteredChildrenAvx2(const RayLayout::Node& n, const Ray& r, float best, float* entry) {
  const auto* base = reinterpret_cast<const char*>(&n);
  const auto row = [base](std::size_t offset) {
    return _mm256_load_ps(reinterpret_cast<const float*>(base + offset));
  };
  const auto along = [&](int axis, const std::size_t* rows) {
    return _mm256_mul_ps(_mm256_sub_ps(row(rows[axis]), _mm256_set1_ps(r.start[axis])),
                         _mm256_set1_ps(r.inv[axis]));
  };
  const __m256 tNear = _mm256_max_ps(_mm256_max_ps(along(1, r.nearRow), along(0, r.nearRow)),
                                     _mm256_max_ps(along(2, r.nearRow), _mm256_setzero_ps()));
  const __m256 tFar = _mm256_min_ps(_mm256_min_ps(along(1, r.farRow), along(0, r.farRow)),
                                    _mm256_min_ps(along(2, r.farRow), _mm256_set1_ps(best)));
  const __m256i noContents =
      _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_load_si256(reinterpret_cast<const __m256i*>(n.contents)),
                                          _mm256_set1_epi32(int(r.mask))),
                         _mm256_setzero_si256());
  _mm256_store_ps(entry, tNear);
  return _mm256_movemask_ps(
      _mm256_andnot_ps(_mm256_castsi256_ps(noContents), _mm256_cmp_ps(tNear, tFar, _CMP_LE_OQ)));
}

}  // namespace

Crossing castAvx2(const Arrays& index, const Ray& ray) { return walk(index, ray, enteredChildrenAvx2); }

#else  // no AVX2 kernel in this build: never chosen (RayIndex::usesAvx2() is false)
Crossing castAvx2(const Arrays& index, const Ray& ray) { return castBaseline(index, ray); }
#endif

}  // namespace cmkit::detail
