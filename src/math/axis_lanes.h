// Internal: whether an axis (a placement's, a trace model's) turns
// anything, asked by every query of its placement and by every ray cast.
#pragma once

#include <cstddef>

#include "cmkit/mat3.h"
#include "cmkit/query.h"
#include "util/simd.h"

namespace cmkit::detail {

/// True when the axis differs from the identity: !axis.isIdentity(), where
/// the lanes are there in two four-lane compares (Mat3::isIdentity's ~26
/// instructions were a twentieth of a ray cast's and of lt4's point
/// contents queries). The same answer: == on each element, so an
/// off-diagonal -0 counts as 0 and a NaN anywhere as a turn.
inline bool isRotated(const Mat3& axis) {
#ifdef CMKIT_FLOAT_LANES
  static_assert(sizeof(Mat3) == 9 * sizeof(float));
  using simd::F4;
  const float* m = &axis.rows[0].x;
  const F4 identityRow = F4::lanes(1, 0, 0, 0);  // a.x a.y a.z b.x, then b.y b.z c.x c.y
  const F4 same = (F4::loadUnaligned(m) == identityRow) & (F4::loadUnaligned(m + 4) == identityRow);
  return simd::bits(same) != 0xFu || !(m[8] == 1.0f);
#else
  return !axis.isIdentity();
#endif
}

/// isRotated of a placement's axis, its loads placed for a Placement
/// written just before as a whole (origin and axis, 48 bytes, in 16-byte
/// stores from the origin): the two four-lane loads at the placement's bytes
/// 16 and 32 (the axis's elements 1-4 and 5-8) and the first element alone
/// each read within one such store, so the processor forwards them from it
/// instead of waiting for the stores to reach the cache. The same answer.
inline bool isRotated(const Placement& placement) {
#ifdef CMKIT_FLOAT_LANES
  static_assert(sizeof(Placement) == 12 * sizeof(float) && offsetof(Placement, axis) == 3 * sizeof(float));
  using simd::F4;
  const float* m = &placement.axis.rows[0].x;
  const F4 identityTail = F4::lanes(0, 0, 0, 1);  // a.y a.z b.x b.y, then b.z c.x c.y c.z
  const F4 same = (F4::loadUnaligned(m + 1) == identityTail) & (F4::loadUnaligned(m + 5) == identityTail);
  return simd::bits(same) != 0xFu || !(m[0] == 1.0f);
#else
  return !placement.axis.isIdentity();
#endif
}

}  // namespace cmkit::detail
