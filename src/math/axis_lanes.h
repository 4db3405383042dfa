// Internal: whether an axis (a placement's, a trace model's) turns
// anything, asked by every query of its placement and by every ray cast.
#pragma once

#include "cmkit/mat3.h"
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

}  // namespace cmkit::detail
