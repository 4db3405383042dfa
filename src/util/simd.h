// Internal: the library's one SIMD layer. Algorithms that work four floats
// at a time use F4 (four float lanes) and U4 (four 32-bit integer lanes),
// two doubles at a time D2 (two double lanes), and the functions below,
// never intrinsics; this header is the only one of the query and ray code
// that includes them (the AVX2 ray kernel, ray/ray_index_avx2.cpp, keeps its
// own: it is compiled for another instruction set).
//
// One guard: CMKIT_SIMD_SSE2 is defined where SSE2 is there (every x86-64)
// and the build does not ask for the portable code (-DCMKIT_NO_SIMD);
// CMKIT_FLOAT_LANES where, in addition, Real is float (not a CMKIT_DOUBLE
// build), the lanes being float. Code that uses the lanes keeps a portable
// path doing the same arithmetic one value at a time for the other builds.
//
// Every function is one instruction (or a fixed sequence of them) with the
// operand order of the intrinsic: min(a, b) and max(a, b) return b when a
// lane of either is NaN, as _mm_min_ps / _mm_max_ps do, so code moved onto
// them keeps its results bit for bit.
#pragma once

#if defined(__SSE2__) && !defined(CMKIT_NO_SIMD)
#define CMKIT_SIMD_SSE2 1
#include <emmintrin.h>
#endif

#include "cmkit/config.h"

#if defined(CMKIT_SIMD_SSE2) && !CMKIT_DOUBLE
#define CMKIT_FLOAT_LANES 1
#endif

#ifdef CMKIT_SIMD_SSE2

#include <cstdint>

namespace cmkit::detail::simd {

/// Four float lanes. A comparison gives a mask: all bits of a lane set where true.
struct F4 {
  __m128 v;

  /// Four floats from 16-byte aligned memory.
  static F4 load(const float* p) { return {_mm_load_ps(p)}; }
  /// Four floats from any address.
  static F4 loadUnaligned(const float* p) { return {_mm_loadu_ps(p)}; }
  /// The same value in every lane.
  static F4 all(float x) { return {_mm_set1_ps(x)}; }
  /// 0 in every lane.
  static F4 zero() { return {_mm_setzero_ps()}; }
  /// Lanes 0..3 set to a, b, c, d.
  static F4 lanes(float a, float b, float c, float d) { return {_mm_setr_ps(a, b, c, d)}; }
  /// Three floats (x, y, z of a vector, which may end an array) in lanes
  /// 0-2, 0 in lane 3: read as 8 + 4 bytes, never past the third.
  static F4 loadXyz(const float* p) {
    const __m128 xy = _mm_loadl_pi(_mm_setzero_ps(), reinterpret_cast<const __m64*>(p));
    return {_mm_movelh_ps(xy, _mm_load_ss(p + 2))};
  }
  /// Stores the lanes to 16-byte aligned memory.
  void store(float* p) const { _mm_store_ps(p, v); }
};

inline F4 operator+(F4 a, F4 b) { return {_mm_add_ps(a.v, b.v)}; }
inline F4 operator-(F4 a, F4 b) { return {_mm_sub_ps(a.v, b.v)}; }
inline F4 operator*(F4 a, F4 b) { return {_mm_mul_ps(a.v, b.v)}; }
inline F4 operator/(F4 a, F4 b) { return {_mm_div_ps(a.v, b.v)}; }
inline F4 operator|(F4 a, F4 b) { return {_mm_or_ps(a.v, b.v)}; }
inline F4 operator&(F4 a, F4 b) { return {_mm_and_ps(a.v, b.v)}; }
inline F4 operator^(F4 a, F4 b) { return {_mm_xor_ps(a.v, b.v)}; }
/// ~a & b, bit by bit.
inline F4 andNot(F4 a, F4 b) { return {_mm_andnot_ps(a.v, b.v)}; }
/// Lane by lane: a < b ? a : b (b when either is NaN).
inline F4 min(F4 a, F4 b) { return {_mm_min_ps(a.v, b.v)}; }
/// Lane by lane: a > b ? a : b (b when either is NaN).
inline F4 max(F4 a, F4 b) { return {_mm_max_ps(a.v, b.v)}; }
inline F4 sqrt(F4 a) { return {_mm_sqrt_ps(a.v)}; }
/// |a|: the sign bit cleared.
inline F4 abs(F4 a) { return {_mm_and_ps(a.v, _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff)))}; }
/// -a: the sign bit flipped.
inline F4 negate(F4 a) { return {_mm_xor_ps(a.v, _mm_castsi128_ps(_mm_set1_epi32(int(0x80000000u))))}; }

inline F4 operator<(F4 a, F4 b) { return {_mm_cmplt_ps(a.v, b.v)}; }
inline F4 operator<=(F4 a, F4 b) { return {_mm_cmple_ps(a.v, b.v)}; }
inline F4 operator>(F4 a, F4 b) { return {_mm_cmpgt_ps(a.v, b.v)}; }
inline F4 operator>=(F4 a, F4 b) { return {_mm_cmpge_ps(a.v, b.v)}; }
inline F4 operator==(F4 a, F4 b) { return {_mm_cmpeq_ps(a.v, b.v)}; }
/// A mask of the lanes where neither a nor b is NaN.
inline F4 ordered(F4 a, F4 b) { return {_mm_cmpord_ps(a.v, b.v)}; }
/// A mask of the lanes whose bits are the same (-0 and 0 differ; NaNs by their bits).
inline F4 sameBits(F4 a, F4 b) {
  return {_mm_castsi128_ps(_mm_cmpeq_epi32(_mm_castps_si128(a.v), _mm_castps_si128(b.v)))};
}
/// Lane by lane: mask ? a : b (mask lanes all set or all clear).
inline F4 select(F4 mask, F4 a, F4 b) {
  return {_mm_or_ps(_mm_and_ps(mask.v, a.v), _mm_andnot_ps(mask.v, b.v))};
}

/// One bit per lane (bit j: lane j's sign bit, i.e. lane j of a mask is set).
inline unsigned bits(F4 mask) { return unsigned(_mm_movemask_ps(mask.v)); }
/// The smallest lane (min over the lanes, pairwise as min()).
inline float lowest(F4 a) {
  __m128 v = _mm_min_ps(a.v, _mm_shuffle_ps(a.v, a.v, _MM_SHUFFLE(1, 0, 3, 2)));
  return _mm_cvtss_f32(_mm_min_ps(v, _mm_shuffle_ps(v, v, _MM_SHUFFLE(2, 3, 0, 1))));
}
/// The largest lane (max over the lanes, pairwise as max()).
inline float highest(F4 a) {
  __m128 v = _mm_max_ps(a.v, _mm_shuffle_ps(a.v, a.v, _MM_SHUFFLE(1, 0, 3, 2)));
  return _mm_cvtss_f32(_mm_max_ps(v, _mm_shuffle_ps(v, v, _MM_SHUFFLE(2, 3, 0, 1))));
}
/// Transposes four rows of four lanes in place (row k lane j <-> row j lane k).
inline void transpose(F4& r0, F4& r1, F4& r2, F4& r3) { _MM_TRANSPOSE4_PS(r0.v, r1.v, r2.v, r3.v); }

/// Four 32-bit integer lanes.
struct U4 {
  __m128i v;

  /// Four values from 16-byte aligned memory.
  static U4 load(const std::uint32_t* p) { return {_mm_load_si128(reinterpret_cast<const __m128i*>(p))}; }
  /// The same value in every lane.
  static U4 all(std::uint32_t x) { return {_mm_set1_epi32(int(x))}; }
};

/// A float mask of the lanes where a & b is 0.
inline F4 noCommonBits(U4 a, U4 b) {
  return {_mm_castsi128_ps(_mm_cmpeq_epi32(_mm_and_si128(a.v, b.v), _mm_setzero_si128()))};
}

/// Two double lanes (for double arithmetic done two values at a time).
struct D2 {
  __m128d v;

  /// Two doubles from 16-byte aligned memory.
  static D2 load(const double* p) { return {_mm_load_pd(p)}; }
  /// Lane 0.
  double low() const { return _mm_cvtsd_f64(v); }
  /// Lane 1.
  double high() const { return _mm_cvtsd_f64(_mm_unpackhi_pd(v, v)); }
};

inline D2 operator+(D2 a, D2 b) { return {_mm_add_pd(a.v, b.v)}; }
inline D2 operator*(D2 a, D2 b) { return {_mm_mul_pd(a.v, b.v)}; }

}  // namespace cmkit::detail::simd

#endif  // CMKIT_SIMD_SSE2
