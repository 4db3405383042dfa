// Winding operations, evaluated in the original's float operation order.
#include "build/winding.h"

#include <algorithm>

namespace cmkit::build {

namespace {

// The split point between p1 and p2 on the plane; coordinates along an
// exactly axial normal are set to the plane distance (avoids round-off).
Vec3 splitPoint(const Vec3& p1, const Vec3& p2, Real d1, Real d2, const Plane& plane) {
  const Real dot = d1 / (d1 - d2);
  Vec3 mid;
  for (int j = 0; j < 3; ++j) {
    if (plane.normal[j] == Real(1)) {
      mid[j] = plane.dist;
    } else if (plane.normal[j] == Real(-1)) {
      mid[j] = -plane.dist;
    } else {
      mid[j] = p1[j] + dot * (p2[j] - p1[j]);
    }
  }
  return mid;
}

WindingSide classify(Real d, Real epsilon) {
  if (d > epsilon) return WindingSide::Front;
  if (d < -epsilon) return WindingSide::Back;
  return WindingSide::On;
}

}  // namespace

Winding Winding::baseForPlane(const Plane& plane) {
  const Vec3 org = plane.normal * plane.dist;
  Vec3 vup;
  Vec3 vright;
  normalVectors(plane.normal, vup, vright);
  vup *= tol::kMaxWorldSize;
  vright *= tol::kMaxWorldSize;
  Winding w;
  w.points_.reserve(8);
  w.points_.push_back(org - vright + vup);
  w.points_.push_back(org + vright + vup);
  w.points_.push_back(org + vright - vup);
  w.points_.push_back(org - vright - vup);
  return w;
}

void Winding::clipInPlace(const Plane& plane, Real epsilon) {
  const std::size_t n = points_.size();
  if (n == 0) return;
  Real distsBuf[64 + 4];
  WindingSide sidesBuf[64 + 4];
  std::vector<Real> distsHeap;
  std::vector<WindingSide> sidesHeap;
  Real* dists = distsBuf;
  WindingSide* sides = sidesBuf;
  if (n + 1 > 64 + 4) {
    distsHeap.resize(n + 1);
    sidesHeap.resize(n + 1);
    dists = distsHeap.data();
    sides = sidesHeap.data();
  }
  int counts[3] = {0, 0, 0};
  for (std::size_t i = 0; i < n; ++i) {
    dists[i] = plane.distance(points_[i]);
    sides[i] = classify(dists[i], epsilon);
    counts[static_cast<int>(sides[i])]++;
  }
  sides[n] = sides[0];
  dists[n] = dists[0];
  if (counts[static_cast<int>(WindingSide::Front)] == 0) {
    points_.clear();
    return;
  }
  if (counts[static_cast<int>(WindingSide::Back)] == 0) return;

  std::vector<Vec3> out;
  out.reserve(n + 4);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& p1 = points_[i];
    if (sides[i] == WindingSide::On) {
      out.push_back(p1);
      continue;
    }
    if (sides[i] == WindingSide::Front) out.push_back(p1);
    if (sides[i + 1] == WindingSide::On || sides[i + 1] == sides[i]) continue;
    const Vec3& p2 = points_[(i + 1) % n];
    out.push_back(splitPoint(p1, p2, dists[i], dists[i + 1], plane));
  }
  points_.swap(out);
}

WindingSide Winding::split(Winding& back, const Plane& plane, Real epsilon) {
  const std::size_t n = points_.size();
  Real distsBuf[64 + 4];
  WindingSide sidesBuf[64 + 4];
  std::vector<Real> distsHeap;
  std::vector<WindingSide> sidesHeap;
  Real* dists = distsBuf;
  WindingSide* sides = sidesBuf;
  if (n + 1 > 64 + 4) {
    distsHeap.resize(n + 1);
    sidesHeap.resize(n + 1);
    dists = distsHeap.data();
    sides = sidesHeap.data();
  }
  int counts[3] = {0, 0, 0};
  for (std::size_t i = 0; i < n; ++i) {
    dists[i] = plane.distance(points_[i]);
    sides[i] = classify(dists[i], epsilon);
    counts[static_cast<int>(sides[i])]++;
  }
  if (counts[static_cast<int>(WindingSide::Back)] == 0) {
    return counts[static_cast<int>(WindingSide::Front)] == 0 ? WindingSide::On : WindingSide::Front;
  }
  if (counts[static_cast<int>(WindingSide::Front)] == 0) return WindingSide::Back;
  sides[n] = sides[0];
  dists[n] = dists[0];

  std::vector<Vec3> front;
  front.reserve(n + 4);
  back.points_.clear();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& p1 = points_[i];
    if (sides[i] == WindingSide::On) {
      front.push_back(p1);
      back.points_.push_back(p1);
      continue;
    }
    if (sides[i] == WindingSide::Front) front.push_back(p1);
    if (sides[i] == WindingSide::Back) back.points_.push_back(p1);
    if (sides[i + 1] == WindingSide::On || sides[i + 1] == sides[i]) continue;
    const Vec3& p2 = points_[(i + 1) % n];
    const Vec3 mid = splitPoint(p1, p2, dists[i], dists[i + 1], plane);
    front.push_back(mid);
    back.points_.push_back(mid);
  }
  points_.swap(front);
  return WindingSide::Cross;
}

void Winding::reverse() { std::reverse(points_.begin(), points_.end()); }

Bounds Winding::bounds() const {
  Bounds b;
  for (const Vec3& p : points_) b.addPoint(p);
  return b;
}

bool Winding::isHuge() const {
  for (const Vec3& p : points_) {
    for (int j = 0; j < 3; ++j) {
      if (p[j] <= -tol::kMaxWorldCoord || p[j] >= tol::kMaxWorldCoord) return true;
    }
  }
  return false;
}

}  // namespace cmkit::build
