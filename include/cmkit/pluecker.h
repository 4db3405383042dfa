// pluecker.h: Plücker coordinates of lines.
//
// The exact translation tests ask on which side one line passes another.
// With Plücker coordinates that is the sign of one "permuted inner product":
// for lines s1->e1 and s2->e2, a.permutedInnerProduct(b) equals
// ((e1 - s1) x (e2 - s2)) . (s2 - s1): zero when the lines are coplanar
// (they meet or are parallel); its sign says which way one passes the other.
// The coordinates and the product are evaluated exactly as the original does,
// because some tests look only at sign bits.
#pragma once

#include "cmkit/vec3.h"

namespace cmkit {

/// A line in Plücker coordinates (6 numbers; the original's layout).
struct Pluecker {
  /// The six coordinates.
  Real p[6] = {0, 0, 0, 0, 0, 0};

  /// The line through start and end, directed start -> end.
  static constexpr Pluecker fromLine(const Vec3& s, const Vec3& e) {
    Pluecker l;
    l.p[0] = s.x * e.y - e.x * s.y;
    l.p[1] = s.x * e.z - e.x * s.z;
    l.p[2] = s.x - e.x;
    l.p[3] = s.y * e.z - e.y * s.z;
    l.p[4] = s.z - e.z;
    l.p[5] = e.y - s.y;
    return l;
  }
  /// The line through start with direction dir (the line start -> start+dir).
  static constexpr Pluecker fromRay(const Vec3& s, const Vec3& dir) {
    Pluecker l;
    l.p[0] = s.x * dir.y - s.y * dir.x;
    l.p[1] = s.x * dir.z - s.z * dir.x;
    l.p[2] = -dir.x;
    l.p[3] = s.y * dir.z - s.z * dir.y;
    l.p[4] = -dir.z;
    l.p[5] = dir.y;
    return l;
  }

  /// Coordinate i.
  constexpr Real operator[](int i) const { return p[i]; }
  /// Coordinate i.
  constexpr Real& operator[](int i) { return p[i]; }

  /// The permuted inner product (see the file comment), in the original's
  /// evaluation order: a0 b4 + a1 b5 + a2 b3 + a4 b0 + a5 b1 + a3 b2.
  constexpr Real permutedInnerProduct(const Pluecker& b) const {
    return p[0] * b.p[4] + p[1] * b.p[5] + p[2] * b.p[3] + p[4] * b.p[0] + p[5] * b.p[1] + p[3] * b.p[2];
  }
  /// The direction of the line (end - start).
  constexpr Vec3 direction() const { return {-p[2], p[5], -p[4]}; }
};

}  // namespace cmkit
