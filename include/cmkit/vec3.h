// vec3.h: 3-component vector, and the guarded scalar helpers.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

#include "cmkit/config.h"
#include "cmkit/tolerances.h"

namespace cmkit {

/// True when the sign bit of x is set (also for -0.0f). Several original
/// tests look only at sign bits, so +0 and -0 behave differently.
inline bool signBitSet(float x) {
  std::uint32_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  return (bits >> 31) != 0;
}
inline bool signBitSet(double x) { return std::signbit(x); }

/// The raw IEEE-754 bit pattern of a float.
inline std::uint32_t floatBits(float x) {
  std::uint32_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  return bits;
}

/// a / b, or `fallback` when |b| is too small for the quotient to be
/// meaningful (never produces Inf or NaN from finite inputs).
inline Real safeDivide(Real a, Real b, Real fallback = 0) {
  return std::fabs(b) < tol::kMinDivisor ? fallback : a / b;
}

/// The original engine's reciprocal square root: a 512-entry table seed and
/// two Newton steps in double. cmkit uses it wherever the original
/// normalises, so that plane normals and lengths match it bit for bit.
/// Defined for x > 0; returns a large finite value for x == 0.
float compatInvSqrt(float x);

/// A 3-component vector of Real.
struct Vec3 {
  /// Coordinates.
  ///@{
  Real x = 0, y = 0, z = 0;
  ///@}

  constexpr Vec3() = default;
  /// A vector from its coordinates.
  constexpr Vec3(Real x_, Real y_, Real z_) : x(x_), y(y_), z(z_) {}

  // (The member's address is chosen, not its value: compilers select
  // addresses without a branch, and the tree walks index by a node's
  // split axis, which is unpredictable.)
  /// Coordinate i (0: x, 1: y, 2: z).
  constexpr Real operator[](int i) const { return *(i == 0 ? &x : (i == 1 ? &y : &z)); }
  /// Coordinate i (0: x, 1: y, 2: z).
  constexpr Real& operator[](int i) { return *(i == 0 ? &x : (i == 1 ? &y : &z)); }

  /// The opposite vector.
  constexpr Vec3 operator-() const { return {-x, -y, -z}; }
  /// Sum.
  constexpr Vec3 operator+(const Vec3& o) const { return {x + o.x, y + o.y, z + o.z}; }
  /// Difference.
  constexpr Vec3 operator-(const Vec3& o) const { return {x - o.x, y - o.y, z - o.z}; }
  /// Scaled by s.
  constexpr Vec3 operator*(Real s) const { return {x * s, y * s, z * s}; }
  /// Adds o.
  constexpr Vec3& operator+=(const Vec3& o) {
    x += o.x;
    y += o.y;
    z += o.z;
    return *this;
  }
  /// Subtracts o.
  constexpr Vec3& operator-=(const Vec3& o) {
    x -= o.x;
    y -= o.y;
    z -= o.z;
    return *this;
  }
  /// Scales by s.
  constexpr Vec3& operator*=(Real s) {
    x *= s;
    y *= s;
    z *= s;
    return *this;
  }
  /// Exactly equal.
  constexpr bool operator==(const Vec3& o) const { return x == o.x && y == o.y && z == o.z; }
  /// Not exactly equal.
  constexpr bool operator!=(const Vec3& o) const { return !(*this == o); }

  /// Dot product, evaluated x, y, z in that order (as the original does).
  constexpr Real dot(const Vec3& o) const { return x * o.x + y * o.y + z * o.z; }
  /// Cross product (this x o).
  constexpr Vec3 cross(const Vec3& o) const {
    return {y * o.z - z * o.y, z * o.x - x * o.z, x * o.y - y * o.x};
  }
  /// Squared length.
  constexpr Real lengthSquared() const { return x * x + y * y + z * z; }
  /// Length, computed as the original does (|v|^2 * InvSqrt(|v|^2)).
  Real length() const {
    const Real sq = lengthSquared();
    return sq < tol::kMinNormalizeLengthSquared ? Real(0) : sq * invSqrt(sq);
  }
  /// Normalises in place and returns the previous length. A vector too short
  /// to have a direction becomes (0,0,0) and 0 is returned: no NaN, no Inf.
  Real normalize() {
    const Real sq = lengthSquared();
    if (!(sq >= tol::kMinNormalizeLengthSquared) || !std::isfinite(sq)) {
      *this = Vec3{};
      return 0;
    }
    const Real inv = invSqrt(sq);
    x *= inv;
    y *= inv;
    z *= inv;
    return sq * inv;
  }
  /// A normalised copy (zero vector when there is no direction).
  Vec3 normalized() const {
    Vec3 v = *this;
    v.normalize();
    return v;
  }
  /// Every coordinate is finite.
  bool isFinite() const { return std::isfinite(x) && std::isfinite(y) && std::isfinite(z); }
  /// Exactly (0, 0, 0).
  bool isZero() const { return x == 0 && y == 0 && z == 0; }

  /// The reciprocal square root used by length() and normalize(): the
  /// original's table method for float, 1/sqrt for other scalar types.
  static Real invSqrt(Real v) {
    if constexpr (sizeof(Real) == sizeof(float)) {
      return compatInvSqrt(v);
    } else {
      return Real(1) / std::sqrt(v);
    }
  }
};

constexpr Vec3 operator*(Real s, const Vec3& v) { return v * s; }

/// Component-wise minimum and maximum.
constexpr Vec3 min(const Vec3& a, const Vec3& b) {
  return {a.x < b.x ? a.x : b.x, a.y < b.y ? a.y : b.y, a.z < b.z ? a.z : b.z};
}
constexpr Vec3 max(const Vec3& a, const Vec3& b) {
  return {a.x > b.x ? a.x : b.x, a.y > b.y ? a.y : b.y, a.z > b.z ? a.z : b.z};
}

/// Two unit vectors perpendicular to the unit vector n and to each other
/// (right = first, up = second), chosen as the original's NormalVectors.
void normalVectors(const Vec3& n, Vec3& right, Vec3& up);

}  // namespace cmkit
