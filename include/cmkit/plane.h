// plane.h: planes as normal + distance.
#pragma once

#include <optional>

#include "cmkit/vec3.h"

namespace cmkit {

/// Which side of a plane (or of a plane, for a box) something is on.
enum class Side : int { Front = 0, Back = 1, On = 2, Cross = 3 };

/// The plane n.p = dist. distance(p) = n.p - dist is positive in front (the
/// side the normal points to). Brush planes point out of the brush; polygon
/// planes out of the solid. ("dist" in .cm files and results is this dist.)
struct Plane {
  /// Unit normal.
  Vec3 normal;
  /// normal . p = dist for points p on the plane.
  Real dist = 0;

  constexpr Plane() = default;
  /// The plane n.p = d.
  constexpr Plane(const Vec3& n, Real d) : normal(n), dist(d) {}

  /// The plane through three points, normal = (p1 - p2) x (p3 - p2)
  /// normalised (so p1, p2, p3 run clockwise seen from the front, as in the
  /// original's map brushes). nullopt when the points are collinear.
  static std::optional<Plane> fromPoints(const Vec3& p1, const Vec3& p2, const Vec3& p3);

  /// Signed distance of p (n.p - dist), evaluated as the original does.
  constexpr Real distance(const Vec3& p) const { return normal.dot(p) - dist; }
  /// Front, Back or On (|distance| <= epsilon).
  Side side(const Vec3& p, Real epsilon = tol::kPlaneSideEpsilon) const {
    const Real d = distance(p);
    if (d > epsilon) return Side::Front;
    if (d < -epsilon) return Side::Back;
    return Side::On;
  }
  /// The same plane facing the other way.
  constexpr Plane flipped() const { return {-normal, -dist}; }
  /// Exactly equal.
  constexpr bool operator==(const Plane& o) const { return normal == o.normal && dist == o.dist; }
  /// The same plane through `point` (normal kept, dist recomputed).
  void fitThroughPoint(const Vec3& point) { dist = normal.dot(point); }

  /// The original's FixDegeneracies: a normal with two exactly-zero
  /// components becomes exactly axial (+-1); one with a component of exactly
  /// +-1 gets exact zeros elsewhere. Only if the normal changed, dist is
  /// rounded to the nearest integer when within distEpsilon of it. Returns
  /// true when the normal changed.
  bool fixDegeneracies(Real distEpsilon);
};

}  // namespace cmkit
