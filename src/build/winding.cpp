// Winding operations, evaluated in the original's float operation order.
#include "build/winding.h"

#include <algorithm>

namespace cmkit::build {

namespace {

/// Windings up to this many points are clipped without heap allocation.
constexpr std::size_t kStackPoints = 64 + 4;

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
  Real distsBuf[kStackPoints];
  WindingSide sidesBuf[kStackPoints];
  std::vector<Real> distsHeap;
  std::vector<WindingSide> sidesHeap;
  Real* dists = distsBuf;
  WindingSide* sides = sidesBuf;
  if (n + 1 > kStackPoints) {
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

  // The clipped winding has at most n + 1 points; small ones are built on
  // the stack and copied back into the existing storage (no allocation).
  Vec3 outBuf[kStackPoints];
  std::vector<Vec3> outHeap;
  Vec3* out = outBuf;
  if (n + 4 > kStackPoints) {
    outHeap.resize(n + 4);
    out = outHeap.data();
  }
  std::size_t numOut = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& p1 = points_[i];
    if (sides[i] == WindingSide::On) {
      out[numOut++] = p1;
      continue;
    }
    if (sides[i] == WindingSide::Front) out[numOut++] = p1;
    if (sides[i + 1] == WindingSide::On || sides[i + 1] == sides[i]) continue;
    const Vec3& p2 = points_[(i + 1) % n];
    out[numOut++] = splitPoint(p1, p2, dists[i], dists[i + 1], plane);
  }
  points_.assign(out, out + numOut);
}

WindingSide Winding::split(Winding& back, const Plane& plane, Real epsilon) {
  const std::size_t n = points_.size();
  Real distsBuf[kStackPoints];
  WindingSide sidesBuf[kStackPoints];
  std::vector<Real> distsHeap;
  std::vector<WindingSide> sidesHeap;
  Real* dists = distsBuf;
  WindingSide* sides = sidesBuf;
  if (n + 1 > kStackPoints) {
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

  Vec3 frontBuf[kStackPoints];
  std::vector<Vec3> frontHeap;
  Vec3* front = frontBuf;
  if (n + 4 > kStackPoints) {
    frontHeap.resize(n + 4);
    front = frontHeap.data();
  }
  std::size_t numFront = 0;
  back.points_.clear();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& p1 = points_[i];
    if (sides[i] == WindingSide::On) {
      front[numFront++] = p1;
      back.points_.push_back(p1);
      continue;
    }
    if (sides[i] == WindingSide::Front) front[numFront++] = p1;
    if (sides[i] == WindingSide::Back) back.points_.push_back(p1);
    if (sides[i + 1] == WindingSide::On || sides[i + 1] == sides[i]) continue;
    const Vec3& p2 = points_[(i + 1) % n];
    const Vec3 mid = splitPoint(p1, p2, dists[i], dists[i + 1], plane);
    front[numFront++] = mid;
    back.points_.push_back(mid);
  }
  points_.assign(front, front + numFront);
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
