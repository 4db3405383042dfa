// mat3.h: 3x3 matrices, used as orientations.
//
// Convention (the original engine's, and the query format's): an orientation
// matrix holds the body's axes as its ROWS (row 0 = forward/x, row 1 =
// left/y, row 2 = up/z). A point in body coordinates goes to world
// coordinates with `local * axis` (row vector times matrix, the sum of the
// rows weighted by the coordinates); a world point goes into the body frame
// with `axis * world` (the matrix times a column vector: dot products with
// the rows).
#pragma once

#include <bit>
#include <cstdint>
#include <optional>
#include <string>
#include <type_traits>

#include "cmkit/result.h"
#include "cmkit/vec3.h"

namespace cmkit {

/// A 3x3 matrix stored as three row vectors.
struct Mat3 {
  /// The three rows (identity by default).
  Vec3 rows[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};

  constexpr Mat3() = default;
  /// A matrix from its rows.
  constexpr Mat3(const Vec3& r0, const Vec3& r1, const Vec3& r2) : rows{r0, r1, r2} {}

  /// The identity matrix.
  static constexpr Mat3 identity() { return Mat3{}; }

  /// Row i.
  constexpr const Vec3& operator[](int i) const { return rows[i]; }
  /// Row i.
  constexpr Vec3& operator[](int i) { return rows[i]; }
  /// Exactly equal, row by row.
  constexpr bool operator==(const Mat3& o) const {
    return rows[0] == o.rows[0] && rows[1] == o.rows[1] && rows[2] == o.rows[2];
  }
  /// Not exactly equal.
  constexpr bool operator!=(const Mat3& o) const { return !(*this == o); }

  /// The transpose (for a rotation: its inverse).
  constexpr Mat3 transposed() const {
    return {{rows[0].x, rows[1].x, rows[2].x},
            {rows[0].y, rows[1].y, rows[2].y},
            {rows[0].z, rows[1].z, rows[2].z}};
  }
  /// Matrix product (this * o).
  constexpr Mat3 operator*(const Mat3& o) const {
    Mat3 r;
    for (int i = 0; i < 3; ++i) {
      r.rows[i] = Vec3{rows[i].x * o.rows[0].x + rows[i].y * o.rows[1].x + rows[i].z * o.rows[2].x,
                       rows[i].x * o.rows[0].y + rows[i].y * o.rows[1].y + rows[i].z * o.rows[2].y,
                       rows[i].x * o.rows[0].z + rows[i].y * o.rows[1].z + rows[i].z * o.rows[2].z};
    }
    return r;
  }
  /// The determinant (1 for a rotation).
  constexpr Real determinant() const { return rows[0].dot(rows[1].cross(rows[2])); }
  /// Exactly the identity.
  constexpr bool isIdentity() const {
    // On the bit patterns, without a branch: queries ask this of every
    // placement. A diagonal element must be exactly 1; an off-diagonal one
    // +0 or -0 (the shift drops the sign bit), as `==` would have it.
    using Bits = std::conditional_t<sizeof(Real) == 8, std::uint64_t, std::uint32_t>;
    constexpr Bits kOne = std::bit_cast<Bits>(Real(1));
    auto off = [](Real v) { return Bits(std::bit_cast<Bits>(v) << 1); };
    auto one = [](Real v) { return Bits(std::bit_cast<Bits>(v) ^ kOne); };
    const Vec3 &a = rows[0], &b = rows[1], &c = rows[2];
    return (one(a.x) | off(a.y) | off(a.z) | off(b.x) | one(b.y) | off(b.z) | off(c.x) | off(c.y) |
            one(c.z)) == 0;
  }
  /// Every element is finite.
  bool isFinite() const { return rows[0].isFinite() && rows[1].isFinite() && rows[2].isFinite(); }

  /// Largest deviation from orthonormality: max over |row length^2 - 1| and
  /// |row_i . row_j|.
  Real orthonormalityError() const;

  /// Rotation matrix for a right-handed (counter-clockwise seen from the
  /// axis tip) rotation by `radians` about the unit vector `axis`, to be
  /// applied as `m * v`. Equivalently, `v * m` rotates clockwise.
  static Mat3 fromAxisAngle(const Vec3& axis, Real radians);
  /// The original's Euler angles in degrees (pitch about y, yaw about z,
  /// roll about x) to an orientation matrix (rows = forward, left, up).
  static Mat3 fromAngles(Real pitchDeg, Real yawDeg, Real rollDeg);
  /// Rows re-orthonormalised by Gram-Schmidt (row 0 keeps its direction,
  /// row 1 its plane, row 2 = row 0 x row 1). Degenerate input gives nullopt.
  std::optional<Mat3> orthonormalized() const;
};

/// Matrix times column vector: (r0.v, r1.v, r2.v). World -> body frame.
constexpr Vec3 operator*(const Mat3& m, const Vec3& v) {
  return {m.rows[0].dot(v), m.rows[1].dot(v), m.rows[2].dot(v)};
}
/// Row vector times matrix: v.x*r0 + v.y*r1 + v.z*r2. Body -> world frame.
/// Evaluated component by component in the original's order.
constexpr Vec3 operator*(const Vec3& v, const Mat3& m) {
  return {m.rows[0].x * v.x + m.rows[1].x * v.y + m.rows[2].x * v.z,
          m.rows[0].y * v.x + m.rows[1].y * v.y + m.rows[2].y * v.z,
          m.rows[0].z * v.x + m.rows[1].z * v.y + m.rows[2].z * v.z};
}

/// Checks a user-supplied orientation: it must be finite, right-handed and
/// orthonormal within tol::kAxisRejectTolerance; if it has drifted by more
/// than tol::kAxisDriftEpsilon it is returned re-orthonormalised, otherwise
/// unchanged (bit for bit). The error message says what is wrong.
Result<Mat3> validateAxis(const Mat3& axis);

/// A rotation drawn uniformly from all rotations, made from three numbers
/// u1, u2, u3 drawn uniformly from [0, 1) (Shoemake's unit quaternion from
/// three uniforms), as the rows of a matrix: a trace model's orientation for
/// random tests, soaks and training data.
Mat3 rotationFromUniforms(double u1, double u2, double u3);

}  // namespace cmkit
