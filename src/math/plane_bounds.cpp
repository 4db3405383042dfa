// Plane and Bounds operations that are not inline.
#include <algorithm>
#include <cmath>

#include "cmkit/bounds.h"
#include "cmkit/plane.h"

namespace cmkit {

std::optional<Plane> Plane::fromPoints(const Vec3& p1, const Vec3& p2, const Vec3& p3) {
  Vec3 n = (p1 - p2).cross(p3 - p2);
  if (n.normalize() == 0) return std::nullopt;
  return Plane{n, n.dot(p2)};
}

namespace {
// Makes an exactly-axial or exactly-unit-component normal exact (the
// original's FixDegenerateNormal). Returns true when it changed.
bool fixDegenerateNormal(Vec3& n) {
  auto makeAxial = [&](Real& c) {
    const Real target = c > 0 ? Real(1) : Real(-1);
    if (c == target) return false;
    c = target;
    return true;
  };
  if (n.x == 0) {
    if (n.y == 0) return makeAxial(n.z);
    if (n.z == 0) return makeAxial(n.y);
  } else if (n.y == 0 && n.z == 0) {
    return makeAxial(n.x);
  }
  if (std::fabs(n.x) == 1) {
    if (n.y != 0 || n.z != 0) {
      n.y = n.z = 0;
      return true;
    }
    return false;
  }
  if (std::fabs(n.y) == 1) {
    if (n.x != 0 || n.z != 0) {
      n.x = n.z = 0;
      return true;
    }
    return false;
  }
  if (std::fabs(n.z) == 1) {
    if (n.x != 0 || n.y != 0) {
      n.x = n.y = 0;
      return true;
    }
  }
  return false;
}
}  // namespace

bool Plane::fixDegeneracies(Real distEpsilon) {
  const bool fixed = fixDegenerateNormal(normal);
  if (fixed) {
    // The original stores d = -dist and rounds d with floor(d + 0.5).
    const Real d = -dist;
    const Real rounded = std::floor(d + Real(0.5));
    if (std::fabs(d - rounded) < distEpsilon) dist = -rounded;
  }
  return fixed;
}

bool Bounds::intersectsSegment(const Vec3& start, const Vec3& end) const {
  const Real t = rayEntry(start, end - start);
  return t >= 0 && t <= 1;
}

Real Bounds::rayEntry(const Vec3& start, const Vec3& dir) const {
  if (isCleared()) return -1;
  Real tMin = 0;
  Real tMax = tol::kBoundsInfinity;
  for (int i = 0; i < 3; ++i) {
    if (dir[i] == 0) {
      if (start[i] < min[i] || start[i] > max[i]) return -1;
      continue;
    }
    Real t0 = (min[i] - start[i]) / dir[i];
    Real t1 = (max[i] - start[i]) / dir[i];
    if (t0 > t1) std::swap(t0, t1);
    tMin = std::max(tMin, t0);
    tMax = std::min(tMax, t1);
    if (tMin > tMax) return -1;
  }
  return tMin;
}

}  // namespace cmkit
