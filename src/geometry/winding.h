// Internal: convex polygons as point lists while building collision models
// (the original's idFixedWinding operations the model builder uses).
#pragma once

#include <vector>

#include "cmkit/math.h"

namespace cmkit::detail {

/// A convex polygon as a list of points (order defines the facing).
class Winding {
 public:
  Winding() = default;

  /// A huge square on the plane (normal * dist as origin, half size
  /// tol::kMaxWorldSize), wound so that its normal is the plane's.
  static Winding baseForPlane(const Plane& plane);

  int size() const { return static_cast<int>(points_.size()); }
  bool empty() const { return points_.empty(); }
  const Vec3& operator[](int i) const { return points_[static_cast<std::size_t>(i)]; }
  const std::vector<Vec3>& points() const { return points_; }
  void clear() { points_.clear(); }
  void add(const Vec3& p) { points_.push_back(p); }

  /// Keeps the part in front of the plane (distance > -epsilon side), the
  /// original's ClipInPlace without keepOn: a winding with no point in front
  /// becomes empty, one with no point behind is kept whole.
  void clipInPlace(const Plane& plane, Real epsilon);

  /// Splits by the plane: returns Front/Back/On when the winding is not cut
  /// (then neither it nor `back` changes), else Cross with this winding
  /// replaced by the front part and `back` set to the back part.
  Side split(Winding& back, const Plane& plane, Real epsilon);

  /// Reverses the point order (the facing).
  void reverse();
  Bounds bounds() const;
  /// True when a coordinate is at or beyond +-tol::kMaxWorldCoord.
  bool isHuge() const;

 private:
  std::vector<Vec3> points_;
};

}  // namespace cmkit::detail
