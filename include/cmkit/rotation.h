// rotation.h: a rotation about an arbitrary axis through an arbitrary point.
#pragma once

#include "cmkit/mat3.h"

namespace cmkit {

/// Rotation by `angle` degrees about the line through `origin` along the
/// unit vector `axis`.
///
/// Sign convention (the original engine's, and the query format's): a
/// POSITIVE angle turns points CLOCKWISE when looking down the axis from its
/// tip. About +z by +90 degrees, (100,0,10) goes to (0,-100,10).
struct Rotation {
  /// A point on the rotation axis.
  Vec3 origin;
  /// Unit direction of the axis.
  Vec3 axis{0, 0, 1};
  Real angle = 0;  ///< degrees

  constexpr Rotation() = default;
  /// A rotation about the axis through o along a, by deg degrees.
  constexpr Rotation(const Vec3& o, const Vec3& a, Real deg) : origin(o), axis(a), angle(deg) {}

  /// The matrix M of this rotation for the original's `v * M` convention:
  /// rotatePoint(p) = origin + (p - origin) * M. (M is the right-handed
  /// rotation matrix for +angle; applied as a row vector it turns clockwise.)
  Mat3 matrix() const;
  /// The rotated point.
  Vec3 rotatePoint(const Vec3& p) const { return origin + (p - origin) * matrix(); }
  /// The rotated direction (origin ignored).
  Vec3 rotateVector(const Vec3& v) const { return v * matrix(); }
  /// An orientation after the rotation: axis * M.
  Mat3 rotateAxis(const Mat3& orientation) const { return orientation * matrix(); }
  /// The inverse rotation.
  constexpr Rotation inverse() const { return {origin, axis, -angle}; }
};

}  // namespace cmkit
