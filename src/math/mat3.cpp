// Mat3 constructors and checks, and Rotation.
#include "cmkit/mat3.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include "cmkit/rotation.h"
#include "math/dvec3.h"

namespace cmkit {
namespace {
constexpr Real kDegToRad = std::numbers::pi_v<Real> / Real(180);
}

Real Mat3::orthonormalityError() const {
  Real err = 0;
  for (int i = 0; i < 3; ++i) {
    err = std::max(err, std::fabs(rows[i].lengthSquared() - Real(1)));
    for (int j = i + 1; j < 3; ++j) err = std::max(err, std::fabs(rows[i].dot(rows[j])));
  }
  return err;
}

Mat3 Mat3::fromAxisAngle(const Vec3& axis, Real radians) {
  const Real c = std::cos(radians);
  const Real s = std::sin(radians);
  const Real t = Real(1) - c;
  const Real x = axis.x, y = axis.y, z = axis.z;
  return {{t * x * x + c, t * x * y - s * z, t * x * z + s * y},
          {t * x * y + s * z, t * y * y + c, t * y * z - s * x},
          {t * x * z - s * y, t * y * z + s * x, t * z * z + c}};
}

Mat3 Mat3::fromAngles(Real pitchDeg, Real yawDeg, Real rollDeg) {
  const Real sy = std::sin(yawDeg * kDegToRad), cy = std::cos(yawDeg * kDegToRad);
  const Real sp = std::sin(pitchDeg * kDegToRad), cp = std::cos(pitchDeg * kDegToRad);
  const Real sr = std::sin(rollDeg * kDegToRad), cr = std::cos(rollDeg * kDegToRad);
  return {{cp * cy, cp * sy, -sp},
          {sr * sp * cy + cr * -sy, sr * sp * sy + cr * cy, sr * cp},
          {cr * sp * cy + -sr * -sy, cr * sp * sy + -sr * cy, cr * cp}};
}

std::optional<Mat3> Mat3::orthonormalized() const {
  // Gram-Schmidt in double: the result is then accurate to float precision.
  using detail::DVec3;
  auto norm = [](DVec3& a) {
    const double len = std::sqrt(a.dot(a));
    if (!(len > 1e-12) || !std::isfinite(len)) return false;
    a /= len;
    return true;
  };
  DVec3 r0(rows[0]);
  DVec3 r1(rows[1]);
  if (!norm(r0)) return std::nullopt;
  r1 -= r0 * r0.dot(r1);
  if (!norm(r1)) return std::nullopt;
  const DVec3 r2 = r0.cross(r1);
  return Mat3{r0.toVec3(), r1.toVec3(), r2.toVec3()};
}

Result<Mat3> validateAxis(const Mat3& axis) {
  if (!axis.isFinite()) return Error{"orientation has a non-finite entry"};
  const Real err = axis.orthonormalityError();
  if (!(err <= tol::kAxisRejectTolerance)) {
    return Error{"orientation is not a rotation: its rows deviate from orthonormal by " +
                 std::to_string(err) + " (at most " + std::to_string(tol::kAxisRejectTolerance) +
                 " is accepted)"};
  }
  if (axis.determinant() < 0) return Error{"orientation is a reflection (left-handed axes)"};
  if (err <= tol::kAxisDriftEpsilon) return axis;
  auto fixed = axis.orthonormalized();
  if (!fixed) return Error{"orientation is degenerate"};
  return *fixed;
}

Mat3 rotationFromUniforms(double u1, double u2, double u3) {
  constexpr double kTwoPi = 6.283185307179586;
  const double a = std::sqrt(1 - u1), b = std::sqrt(u1);
  const double x = a * std::sin(kTwoPi * u2), y = a * std::cos(kTwoPi * u2);
  const double z = b * std::sin(kTwoPi * u3), w = b * std::cos(kTwoPi * u3);
  auto row = [](double p, double q, double r) { return Vec3{Real(p), Real(q), Real(r)}; };
  return Mat3{row(1 - 2 * (y * y + z * z), 2 * (x * y + z * w), 2 * (x * z - y * w)),
              row(2 * (x * y - z * w), 1 - 2 * (x * x + z * z), 2 * (y * z + x * w)),
              row(2 * (x * z + y * w), 2 * (y * z - x * w), 1 - 2 * (x * x + y * y))};
}

Mat3 Rotation::matrix() const {
  // Quaternion form of the right-handed rotation by +angle, applied by the
  // original as a row vector (v * M), which turns clockwise.
  const Real half = angle * kDegToRad * Real(0.5);
  const Real s = std::sin(half);
  const Real c = std::cos(half);
  const Real x = axis.x * s, y = axis.y * s, z = axis.z * s;
  const Real x2 = x + x, y2 = y + y, z2 = z + z;
  const Real xx = x * x2, xy = x * y2, xz = x * z2;
  const Real yy = y * y2, yz = y * z2, zz = z * z2;
  const Real wx = c * x2, wy = c * y2, wz = c * z2;
  return {{Real(1) - (yy + zz), xy - wz, xz + wy},
          {xy + wz, Real(1) - (xx + zz), yz - wx},
          {xz - wy, yz + wx, Real(1) - (xx + yy)}};
}

}  // namespace cmkit
