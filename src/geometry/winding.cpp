// Winding operations, evaluated in the original's float operation order.
#include "geometry/winding.h"

#include <algorithm>

namespace cmkit::detail {

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

Side classify(Real d, Real epsilon) {
  if (d > epsilon) return Side::Front;
  if (d < -epsilon) return Side::Back;
  return Side::On;
}

/// A scratch array of up to kStackPoints values on the stack, else on the
/// heap (windings are small; clipping them must not allocate).
template <class T>
class ScratchArray {
 public:
  explicit ScratchArray(std::size_t n) {
    if (n > kStackPoints) {
      heap_.resize(n);
      data_ = heap_.data();
    }
  }
  ScratchArray(const ScratchArray&) = delete;
  ScratchArray& operator=(const ScratchArray&) = delete;
  T& operator[](std::size_t i) { return data_[i]; }
  T* data() { return data_; }

 private:
  T stack_[kStackPoints];
  std::vector<T> heap_;
  T* data_ = stack_;
};

/// Every point's distance to the plane and side, with the first repeated
/// after the last (entry n), and how many points lie on each side.
struct PointSides {
  PointSides(const std::vector<Vec3>& points, const Plane& plane, Real epsilon)
      : dists(points.size() + 1), sides(points.size() + 1) {
    const std::size_t n = points.size();
    for (std::size_t i = 0; i < n; ++i) {
      dists[i] = plane.distance(points[i]);
      sides[i] = classify(dists[i], epsilon);
      counts[static_cast<int>(sides[i])]++;
    }
    if (n > 0) {
      sides[n] = sides[0];
      dists[n] = dists[0];
    }
  }
  int count(Side side) const { return counts[static_cast<int>(side)]; }

  ScratchArray<Real> dists;
  ScratchArray<Side> sides;
  int counts[3] = {0, 0, 0};
};

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
  PointSides ps(points_, plane, epsilon);
  if (ps.count(Side::Front) == 0) {
    points_.clear();
    return;
  }
  if (ps.count(Side::Back) == 0) return;

  // The clipped winding has at most n + 1 points; small ones are built on
  // the stack and copied back into the existing storage (no allocation).
  ScratchArray<Vec3> out(n + 4);
  std::size_t numOut = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& p1 = points_[i];
    if (ps.sides[i] == Side::On) {
      out[numOut++] = p1;
      continue;
    }
    if (ps.sides[i] == Side::Front) out[numOut++] = p1;
    if (ps.sides[i + 1] == Side::On || ps.sides[i + 1] == ps.sides[i]) continue;
    const Vec3& p2 = points_[(i + 1) % n];
    out[numOut++] = splitPoint(p1, p2, ps.dists[i], ps.dists[i + 1], plane);
  }
  points_.assign(out.data(), out.data() + numOut);
}

Side Winding::split(Winding& back, const Plane& plane, Real epsilon) {
  const std::size_t n = points_.size();
  PointSides ps(points_, plane, epsilon);
  if (ps.count(Side::Back) == 0) return ps.count(Side::Front) == 0 ? Side::On : Side::Front;
  if (ps.count(Side::Front) == 0) return Side::Back;

  ScratchArray<Vec3> front(n + 4);
  std::size_t numFront = 0;
  back.points_.clear();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& p1 = points_[i];
    if (ps.sides[i] == Side::On) {
      front[numFront++] = p1;
      back.points_.push_back(p1);
      continue;
    }
    if (ps.sides[i] == Side::Front) front[numFront++] = p1;
    if (ps.sides[i] == Side::Back) back.points_.push_back(p1);
    if (ps.sides[i + 1] == Side::On || ps.sides[i + 1] == ps.sides[i]) continue;
    const Vec3& p2 = points_[(i + 1) % n];
    const Vec3 mid = splitPoint(p1, p2, ps.dists[i], ps.dists[i + 1], plane);
    front[numFront++] = mid;
    back.points_.push_back(mid);
  }
  points_.assign(front.data(), front.data() + numFront);
  return Side::Cross;
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

}  // namespace cmkit::detail
