// Internal: the library's one double-precision 3-vector, for the few
// computations that need more than Real's precision from Real inputs
// (rotation equations, the convex hull, Gram-Schmidt, mass properties).
// Each operation computes its components in the written order, so code
// moved onto it keeps its results bit for bit.
#pragma once

#include <cmath>

#include "cmkit/vec3.h"

namespace cmkit::detail {

/// A vector of three doubles.
struct DVec3 {
  double x = 0, y = 0, z = 0;

  DVec3() = default;
  DVec3(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}
  explicit DVec3(const Vec3& v) : x(v.x), y(v.y), z(v.z) {}

  DVec3 operator+(const DVec3& o) const { return {x + o.x, y + o.y, z + o.z}; }
  DVec3 operator-(const DVec3& o) const { return {x - o.x, y - o.y, z - o.z}; }
  DVec3 operator*(double s) const { return {x * s, y * s, z * s}; }
  DVec3& operator+=(const DVec3& o) {
    x += o.x, y += o.y, z += o.z;
    return *this;
  }
  DVec3& operator-=(const DVec3& o) {
    x -= o.x, y -= o.y, z -= o.z;
    return *this;
  }
  DVec3& operator/=(double s) {
    x /= s, y /= s, z /= s;
    return *this;
  }
  /// Component k (0: x, 1: y, 2: z).
  double operator[](int k) const { return k == 0 ? x : k == 1 ? y : z; }
  double& operator[](int k) { return k == 0 ? x : k == 1 ? y : z; }

  double dot(const DVec3& o) const { return x * o.x + y * o.y + z * o.z; }
  DVec3 cross(const DVec3& o) const { return {y * o.z - z * o.y, z * o.x - x * o.z, x * o.y - y * o.x}; }
  double length() const { return std::sqrt(dot(*this)); }
  /// Rounded to Real.
  Vec3 toVec3() const { return {Real(x), Real(y), Real(z)}; }
};

}  // namespace cmkit::detail
