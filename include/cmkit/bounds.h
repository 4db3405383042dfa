// bounds.h: axis-aligned bounding boxes.
#pragma once

#include "cmkit/plane.h"
#include "cmkit/vec3.h"

namespace cmkit {

/// An axis-aligned box [min, max]. A cleared box has min = +infinity-ish and
/// max = -infinity-ish (tol::kBoundsInfinity), so adding a point makes it that
/// point; isCleared() tells such an empty box.
struct Bounds {
  /// Smallest corner (+infinity on every axis when cleared).
  Vec3 min{tol::kBoundsInfinity, tol::kBoundsInfinity, tol::kBoundsInfinity};
  /// Largest corner (-infinity on every axis when cleared).
  Vec3 max{-tol::kBoundsInfinity, -tol::kBoundsInfinity, -tol::kBoundsInfinity};

  constexpr Bounds() = default;
  /// Bounds from their two corners.
  constexpr Bounds(const Vec3& mn, const Vec3& mx) : min(mn), max(mx) {}
  /// The box around one point.
  static constexpr Bounds ofPoint(const Vec3& p) { return {p, p}; }

  /// 0: min, 1: max.
  constexpr const Vec3& operator[](int i) const { return i == 0 ? min : max; }
  /// 0: min, 1: max.
  constexpr Vec3& operator[](int i) { return i == 0 ? min : max; }
  /// Same corners, exactly.
  constexpr bool operator==(const Bounds& o) const { return min == o.min && max == o.max; }

  /// Back to the cleared (empty) state.
  constexpr void clear() { *this = Bounds{}; }
  /// True when max < min on some axis (nothing added yet, or inverted).
  constexpr bool isCleared() const { return min.x > max.x || min.y > max.y || min.z > max.z; }

  /// Grows the bounds to hold p. (Selects, not branches: the compiler makes
  /// each a min / max instruction, with the same result for every input,
  /// NaN included: a coordinate that compares false leaves the corner as it
  /// was.)
  constexpr void addPoint(const Vec3& p) {
    min.x = p.x < min.x ? p.x : min.x;
    max.x = p.x > max.x ? p.x : max.x;
    min.y = p.y < min.y ? p.y : min.y;
    max.y = p.y > max.y ? p.y : max.y;
    min.z = p.z < min.z ? p.z : min.z;
    max.z = p.z > max.z ? p.z : max.z;
  }
  /// Grows the bounds to hold b.
  constexpr void addBounds(const Bounds& b) {
    addPoint(b.min);
    addPoint(b.max);
  }
  /// Grown by d on every side (shrunk for negative d).
  constexpr Bounds expanded(Real d) const {
    return {{min.x - d, min.y - d, min.z - d}, {max.x + d, max.y + d, max.z + d}};
  }
  /// The bounds moved by t.
  constexpr Bounds translated(const Vec3& t) const { return {min + t, max + t}; }
  /// The middle point.
  constexpr Vec3 center() const { return (min + max) * Real(0.5); }
  /// max - min on every axis.
  constexpr Vec3 size() const { return max - min; }

  /// True when the boxes overlap or touch (closed intervals).
  constexpr bool intersects(const Bounds& b) const {
    return !(b.max.x < min.x || b.max.y < min.y || b.max.z < min.z || b.min.x > max.x || b.min.y > max.y ||
             b.min.z > max.z);
  }
  /// The common part (cleared when there is none).
  constexpr Bounds intersection(const Bounds& b) const {
    Bounds r{cmkit::max(min, b.min), cmkit::min(max, b.max)};
    if (r.isCleared()) r.clear();
    return r;
  }
  /// True when p is inside or on the box.
  constexpr bool containsPoint(const Vec3& p) const {
    return !(p.x < min.x || p.y < min.y || p.z < min.z || p.x > max.x || p.y > max.y || p.z > max.z);
  }
  /// True when b lies inside these bounds (touching counts).
  constexpr bool containsBounds(const Bounds& b) const {
    return containsPoint(b.min) && containsPoint(b.max);
  }

  /// Side of the plane the whole box is on, as the original computes it:
  /// Front if the box is farther than epsilon in front, Back if farther than
  /// epsilon behind, else Cross.
  /// (Inline: the queries' polygon culls ask it of most polygons they meet.)
  Side planeSide(const Plane& plane, Real epsilon = tol::kOnEpsilon) const {
    const Vec3 c = center();
    const Real d1 = plane.distance(c);
    const Real d2 = std::fabs((max.x - c.x) * plane.normal.x) + std::fabs((max.y - c.y) * plane.normal.y) +
                    std::fabs((max.z - c.z) * plane.normal.z);
    if (d1 - d2 > epsilon) return Side::Front;
    if (d1 + d2 < -epsilon) return Side::Back;
    return Side::Cross;
  }

  /// Does the segment start->end touch the box? (slab test, closed box)
  bool intersectsSegment(const Vec3& start, const Vec3& end) const;
  /// Where the ray start + t*dir (t >= 0) enters the box: the smallest such
  /// t, or a negative value when the ray misses. t = 0 when start is inside.
  Real rayEntry(const Vec3& start, const Vec3& dir) const;
};

}  // namespace cmkit
