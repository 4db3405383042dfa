// Math identities and hand-computed cases for Vec3, Mat3, Plane, Bounds,
// Pluecker and Rotation.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "cmkit/math.h"
#include "math/axis_lanes.h"
#include "util/simd.h"

using namespace cmkit;

namespace {

void expectNear(const Vec3& a, const Vec3& b, Real eps) {
  EXPECT_NEAR(a.x, b.x, eps);
  EXPECT_NEAR(a.y, b.y, eps);
  EXPECT_NEAR(a.z, b.z, eps);
}

Vec3 randomUnit(std::mt19937& rng) {
  std::normal_distribution<float> n(0, 1);
  Vec3 v{n(rng), n(rng), n(rng)};
  v.normalize();
  return v;
}

}  // namespace

TEST(Vec3, NormalizeReturnsLengthAndMakesUnit) {
  Vec3 v{3, 4, 12};
  EXPECT_NEAR(v.normalize(), 13.0f, 1e-5f);
  EXPECT_NEAR(v.lengthSquared(), 1.0f, 1e-6f);
  expectNear(v, {3.0f / 13, 4.0f / 13, 12.0f / 13}, 1e-6f);
}

TEST(Vec3, NormalizeOfDegenerateVectorsIsZeroNeverNaN) {
  const float inf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (Vec3 v : {Vec3{0, 0, 0}, Vec3{1e-30f, 0, 0}, Vec3{inf, 0, 0}, Vec3{nan, 1, 1}, Vec3{-0.0f, 0, 0}}) {
    EXPECT_EQ(v.normalize(), 0.0f);
    EXPECT_TRUE(v.isZero());
  }
  EXPECT_EQ(Vec3{}.length(), 0.0f);
}

TEST(Vec3, CompatInvSqrtIsAccurate) {
  // The original's table + two Newton steps is accurate to float precision.
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> exp(-30, 30);
  for (int i = 0; i < 10000; ++i) {
    const float x = std::pow(2.0f, exp(rng)) * (1 + float(i % 97) / 97.0f);
    const double want = 1.0 / std::sqrt(double(x));
    EXPECT_NEAR(compatInvSqrt(x) / want, 1.0, 2e-7) << x;
  }
  EXPECT_EQ(compatInvSqrt(4.0f), 0.5f);
  EXPECT_TRUE(std::isfinite(compatInvSqrt(0.0f)));
}

TEST(Vec3, CrossAndDot) {
  const Vec3 x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
  EXPECT_EQ(x.cross(y), z);
  EXPECT_EQ(y.cross(z), x);
  EXPECT_EQ(z.cross(x), y);
  EXPECT_EQ(Vec3(1, 2, 3).dot({4, -5, 6}), 12.0f);
}

TEST(Vec3, SafeDivideNeverProducesInf) {
  EXPECT_EQ(safeDivide(1, 0), 0.0f);
  EXPECT_EQ(safeDivide(1, 1e-38f, 5), 5.0f);
  EXPECT_EQ(safeDivide(6, 3), 2.0f);
}

TEST(Vec3, SignBitDistinguishesNegativeZero) {
  EXPECT_TRUE(signBitSet(-0.0f));
  EXPECT_FALSE(signBitSet(0.0f));
  EXPECT_TRUE(signBitSet(-1.0f));
}

TEST(Vec3, NormalVectorsArePerpendicular) {
  std::mt19937 rng(3);
  for (int i = 0; i < 100; ++i) {
    const Vec3 n = i == 0 ? Vec3{0, 0, 1} : randomUnit(rng);
    Vec3 right, up;
    normalVectors(n, right, up);
    EXPECT_NEAR(right.dot(n), 0, 1e-6f);
    EXPECT_NEAR(up.dot(n), 0, 1e-6f);
    EXPECT_NEAR(right.dot(up), 0, 1e-6f);
    EXPECT_NEAR(right.lengthSquared(), 1, 1e-5f);
    EXPECT_NEAR(up.lengthSquared(), 1, 1e-5f);
  }
}

TEST(Mat3, AxisAngleIsOrthonormalAndInverts) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> angle(-7, 7);
  for (int i = 0; i < 200; ++i) {
    const Vec3 axis = randomUnit(rng);
    const float a = angle(rng);
    const Mat3 m = Mat3::fromAxisAngle(axis, a);
    EXPECT_LT(m.orthonormalityError(), 1e-5f);
    EXPECT_NEAR(m.determinant(), 1, 1e-5f);
    const Mat3 back = Mat3::fromAxisAngle(axis, -a) * m;
    for (int r = 0; r < 3; ++r) expectNear(back[r], Mat3::identity()[r], 1e-5f);
    expectNear(m * axis, axis, 1e-5f);  // the axis stays put
  }
}

TEST(Mat3, AxisAngleIsRightHanded) {
  // +90 degrees about +z takes x to y when applied as m * v.
  const Mat3 m = Mat3::fromAxisAngle({0, 0, 1}, std::numbers::pi_v<float> / 2);
  expectNear(m * Vec3{1, 0, 0}, {0, 1, 0}, 1e-6f);
  // and the row-vector product turns the other way.
  expectNear(Vec3{1, 0, 0} * m, {0, -1, 0}, 1e-6f);
}

TEST(Mat3, AnglesToMatrix) {
  const Mat3 yaw90 = Mat3::fromAngles(0, 90, 0);
  expectNear(yaw90[0], {0, 1, 0}, 1e-6f);   // forward turns to +y
  expectNear(yaw90[1], {-1, 0, 0}, 1e-6f);  // left turns to -x
  expectNear(yaw90[2], {0, 0, 1}, 1e-6f);
  const Mat3 pitch90 = Mat3::fromAngles(90, 0, 0);
  expectNear(pitch90[0], {0, 0, -1}, 1e-6f);  // positive pitch looks down
  EXPECT_LT(Mat3::fromAngles(12, -170, 33).orthonormalityError(), 1e-5f);
}

TEST(Mat3, TransposeAndProducts) {
  const Mat3 m{{1, 2, 3}, {4, 5, 6}, {7, 8, 10}};
  EXPECT_EQ(m.transposed().transposed(), m);
  const Vec3 v{1, -1, 2};
  EXPECT_EQ(v * m, m.transposed() * v);
  EXPECT_EQ(m * v, Vec3(5, 11, 19));
  EXPECT_EQ(m.determinant(), -3.0f);
}

TEST(Mat3, ValidateAxisKeepsGoodAxesBitForBit) {
  const Mat3 m = Mat3::fromAngles(10, 20, 30);
  auto r = validateAxis(m);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(*r, m);
}

TEST(Mat3, ValidateAxisOrthonormalisesDrift) {
  Mat3 m = Mat3::fromAngles(10, 20, 30);
  m[0] = m[0] * 1.001f;
  m[1] = m[1] + m[0] * 0.002f;
  auto r = validateAxis(m);
  ASSERT_TRUE(r.ok());
  EXPECT_LT(r->orthonormalityError(), 1e-6f);
  EXPECT_NEAR(r->determinant(), 1, 1e-6f);
}

TEST(Mat3, ValidateAxisRejectsNonRotations) {
  Mat3 scaled = Mat3::identity();
  scaled[0] = {2, 0, 0};
  EXPECT_FALSE(validateAxis(scaled).ok());
  const Mat3 reflection{{1, 0, 0}, {0, 1, 0}, {0, 0, -1}};
  auto r = validateAxis(reflection);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("reflection"), std::string::npos);
  Mat3 nan = Mat3::identity();
  nan[1].y = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(validateAxis(nan).ok());
  const Mat3 singular{{1, 0, 0}, {1, 0, 0}, {0, 0, 1}};
  EXPECT_FALSE(validateAxis(singular).ok());
}

TEST(Rotation, PositiveAngleTurnsClockwiseFromTheAxisTip) {
  // The query format's example: 90 degrees about +z takes (100,0,10) to (0,-100,10).
  const Rotation rot({0, 0, 0}, {0, 0, 1}, 90);
  expectNear(rot.rotatePoint({100, 0, 10}), {0, -100, 10}, 1e-4f);
}

TEST(Rotation, AboutAnOffsetOrigin) {
  const Rotation rot({10, 10, 0}, {0, 0, 1}, 180);
  expectNear(rot.rotatePoint({20, 10, 5}), {0, 10, 5}, 1e-4f);
  expectNear(rot.rotateVector({1, 0, 0}), {-1, 0, 0}, 1e-6f);
}

TEST(Rotation, ForwardThenInverseIsIdentity) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-500, 500);
  for (int i = 0; i < 200; ++i) {
    const Rotation rot({u(rng), u(rng), u(rng)}, randomUnit(rng), u(rng));
    EXPECT_LT(rot.matrix().orthonormalityError(), 1e-5f);
    const Vec3 p{u(rng), u(rng), u(rng)};
    expectNear(rot.inverse().rotatePoint(rot.rotatePoint(p)), p, 2e-3f);
  }
}

TEST(Plane, FromPointsUsesTheOriginalWinding) {
  // normal = (p1 - p2) x (p3 - p2)
  auto p = Plane::fromPoints({0, 0, 5}, {1, 0, 5}, {0, 1, 5});
  ASSERT_TRUE(p);
  EXPECT_EQ(p->normal, Vec3(0, 0, -1));
  EXPECT_EQ(p->dist, -5.0f);
  EXPECT_EQ(p->distance({3, 3, 0}), 5.0f);
  EXPECT_FALSE(Plane::fromPoints({0, 0, 0}, {1, 1, 1}, {2, 2, 2}));
}

TEST(Plane, SideWithEpsilon) {
  const Plane p{{0, 0, 1}, 10};
  EXPECT_EQ(p.side({0, 0, 10.05f}), Side::On);
  EXPECT_EQ(p.side({0, 0, 10.5f}), Side::Front);
  EXPECT_EQ(p.side({0, 0, 9.5f}), Side::Back);
  EXPECT_EQ(p.side({0, 0, 10.05f}, 0.01f), Side::Front);
  EXPECT_EQ(p.flipped().side({0, 0, 11}), Side::Back);
}

TEST(Plane, FixDegeneracies) {
  Plane axial{{0, 0, 0.9999f}, 63.99995f};
  EXPECT_TRUE(axial.fixDegeneracies(tol::kDegenerateDistEpsilon));
  EXPECT_EQ(axial.normal, Vec3(0, 0, 1));
  EXPECT_EQ(axial.dist, 64.0f);
  Plane unitX{{1, 0.001f, 0}, 10.5f};
  EXPECT_TRUE(unitX.fixDegeneracies(tol::kDegenerateDistEpsilon));
  EXPECT_EQ(unitX.normal, Vec3(1, 0, 0));
  EXPECT_EQ(unitX.dist, 10.5f);  // not within epsilon of an integer: kept
  Plane oblique{{0.6f, 0.8f, 0}, 3.00001f};
  EXPECT_FALSE(oblique.fixDegeneracies(tol::kDegenerateDistEpsilon));
  EXPECT_EQ(oblique.dist, 3.00001f);  // only fixed normals get their dist rounded
  Plane exact{{0, -1, 0}, 2.00001f};
  EXPECT_FALSE(exact.fixDegeneracies(tol::kDegenerateDistEpsilon));
}

TEST(Bounds, AddIntersectContain) {
  Bounds b;
  EXPECT_TRUE(b.isCleared());
  b.addPoint({1, 2, 3});
  b.addPoint({-1, 5, 0});
  EXPECT_EQ(b.min, Vec3(-1, 2, 0));
  EXPECT_EQ(b.max, Vec3(1, 5, 3));
  const Bounds touching{{1, 2, 0}, {4, 4, 4}};
  EXPECT_TRUE(b.intersects(touching));  // touching counts
  EXPECT_FALSE(b.intersects(Bounds{{1.01f, 2, 0}, {4, 4, 4}}));
  EXPECT_EQ(b.intersection(touching), Bounds({1, 2, 0}, {1, 4, 3}));
  EXPECT_TRUE(b.intersection(Bounds{{9, 9, 9}, {10, 10, 10}}).isCleared());
  EXPECT_TRUE(b.containsPoint({1, 5, 3}));
  EXPECT_FALSE(b.containsPoint({1, 5, 3.01f}));
  EXPECT_EQ(b.expanded(1), Bounds({-2, 1, -1}, {2, 6, 4}));
}

TEST(Bounds, PlaneSide) {
  const Bounds b{{-1, -1, -1}, {1, 1, 1}};
  EXPECT_EQ(b.planeSide({{0, 0, 1}, -2}), Side::Front);
  EXPECT_EQ(b.planeSide({{0, 0, 1}, 2}), Side::Back);
  EXPECT_EQ(b.planeSide({{0, 0, 1}, 0.5f}), Side::Cross);
  // within epsilon of touching counts as crossing
  EXPECT_EQ(b.planeSide({{0, 0, 1}, -1.05f}, 0.1f), Side::Cross);
  // diagonal plane: the box reaches sqrt(3) along (1,1,1)/sqrt(3)
  const Vec3 n = Vec3{1, 1, 1}.normalized();
  EXPECT_EQ(b.planeSide({n, 1.9f}), Side::Back);
  EXPECT_EQ(b.planeSide({n, 1.6f}), Side::Cross);
}

TEST(Bounds, RayAndSegment) {
  const Bounds b{{0, 0, 0}, {10, 10, 10}};
  EXPECT_FLOAT_EQ(b.rayEntry({-10, 5, 5}, {1, 0, 0}), 10.0f);
  EXPECT_LT(b.rayEntry({-10, 5, 5}, {-1, 0, 0}), 0.0f);
  EXPECT_EQ(b.rayEntry({5, 5, 5}, {0, 0, 1}), 0.0f);
  EXPECT_LT(b.rayEntry({-10, 20, 5}, {1, 0, 0}), 0.0f);
  EXPECT_TRUE(b.intersectsSegment({-5, 5, 5}, {5, 5, 5}));
  EXPECT_FALSE(b.intersectsSegment({-5, 5, 5}, {-1, 5, 5}));
  EXPECT_TRUE(b.intersectsSegment({-5, -5, 5}, {15, 15, 5}));
  EXPECT_FALSE(b.intersectsSegment({-5, 6, 5}, {6, 17, 5}));
}

TEST(Pluecker, SignOfHandComputedCases) {
  // A: the x axis, from the origin towards +x.
  const Pluecker a = Pluecker::fromLine({0, 0, 0}, {1, 0, 0});
  // B passes above A (z = 1) going +y: ((1,0,0) x (0,2,0)) . (0,-1,1) = 2.
  EXPECT_EQ(a.permutedInnerProduct(Pluecker::fromLine({0, -1, 1}, {0, 1, 1})), 2.0f);
  // ... below A: -2.
  EXPECT_EQ(a.permutedInnerProduct(Pluecker::fromLine({0, -1, -1}, {0, 1, -1})), -2.0f);
  // reversing B flips the sign
  EXPECT_EQ(a.permutedInnerProduct(Pluecker::fromLine({0, 1, 1}, {0, -1, 1})), -2.0f);
  // intersecting and parallel lines: 0
  EXPECT_EQ(a.permutedInnerProduct(Pluecker::fromLine({3, -1, 0}, {3, 1, 0})), 0.0f);
  EXPECT_EQ(a.permutedInnerProduct(Pluecker::fromLine({0, 5, 0}, {1, 5, 0})), 0.0f);
}

TEST(Pluecker, MatchesTheTripleProductAndRays) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(-100, 100);
  for (int i = 0; i < 1000; ++i) {
    const Vec3 s1{u(rng), u(rng), u(rng)}, e1{u(rng), u(rng), u(rng)};
    const Vec3 s2{u(rng), u(rng), u(rng)}, e2{u(rng), u(rng), u(rng)};
    const double want = double((e1 - s1).cross(e2 - s2).dot(s2 - s1));
    const Pluecker l1 = Pluecker::fromLine(s1, e1);
    const double got = l1.permutedInnerProduct(Pluecker::fromLine(s2, e2));
    EXPECT_NEAR(got, want, 1e-3 * (1 + std::fabs(want)));
    // the ray form describes the same line
    const Pluecker r2 = Pluecker::fromRay(s2, e2 - s2);
    EXPECT_NEAR(l1.permutedInnerProduct(r2), want, 1e-3 * (1 + std::fabs(want)));
    EXPECT_EQ(l1.direction(), e1 - s1);
  }
}

TEST(Mat3, RotationFromUniformsIsARotationAndHandChecked) {
  // u = (0, 0, 0): the quaternion (x, y, z, w) = (0, 1, 0, 0), a half turn about y.
  const Mat3 half = rotationFromUniforms(0, 0, 0);
  EXPECT_EQ(half.rows[0], (Vec3{-1, 0, 0}));
  EXPECT_EQ(half.rows[1], (Vec3{0, 1, 0}));
  EXPECT_EQ(half.rows[2], (Vec3{0, 0, -1}));
  // u1 = 1, u3 = 0: (0, 0, 0, 1), the identity (u2 does not matter).
  const Mat3 identity = rotationFromUniforms(1, 0.3, 0);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(identity.rows[r][c], r == c ? 1.0 : 0.0, 1e-6) << r << c;
  // Any three uniforms: orthonormal and right-handed; the mean of the first
  // row over many draws is near zero (no preferred direction).
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  Vec3 mean{};
  constexpr int kDraws = 20000;
  for (int i = 0; i < kDraws; ++i) {
    const Mat3 m = rotationFromUniforms(u(rng), u(rng), u(rng));
    ASSERT_LT(m.orthonormalityError(), 1e-5f);
    ASSERT_GT(m.determinant(), 0);
    mean = mean + m.rows[0] * (Real(1) / kDraws);
  }
  EXPECT_LT(mean.length(), 0.03f);
}

TEST(Mat3, IsRotatedIsNotIsIdentityElementByElement) {
  // detail::isRotated, of an axis and of a placement (two four-lane
  // compares where there are float lanes)
  // answers !isIdentity() for every element set to each of these: the
  // identity's own value, -0 and +0, 1 and -1, a tiny and a huge value,
  // infinity and NaN. (An off-diagonal -0 counts as 0; a diagonal must be
  // exactly 1.)
  const Real values[] = {0,
                         -Real(0),
                         1,
                         -1,
                         std::numeric_limits<Real>::denorm_min(),
                         Real(1e30),
                         std::numeric_limits<Real>::infinity(),
                         std::numeric_limits<Real>::quiet_NaN(),
                         Real(1) + std::numeric_limits<Real>::epsilon()};
  EXPECT_FALSE(detail::isRotated(Mat3::identity()));
  EXPECT_FALSE(detail::isRotated(Placement{}));
  int turned = 0;
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 3; ++col)
      for (const Real v : values) {
        Mat3 m = Mat3::identity();
        (&m.rows[row].x)[col] = v;
        EXPECT_EQ(detail::isRotated(m), !m.isIdentity()) << "element " << row << "," << col << " = " << v;
        // (The placement's overload reads other bytes: the same answer.)
        const Placement placement{{Real(3), Real(4), Real(5)}, m};
        EXPECT_EQ(detail::isRotated(placement), !m.isIdentity())
            << "element " << row << "," << col << " = " << v;
        turned += detail::isRotated(m);
      }
  EXPECT_EQ(turned, 9 * 9 - 6 * 2 - 3 * 1) << "every value but the identity's own (and -0 off the diagonal)";
}

#ifdef CMKIT_FLOAT_LANES
TEST(SimdLanes, LoadXyzDivisionAndOrderedAsScalars) {
  using detail::simd::F4;
  namespace simd = detail::simd;
  alignas(16) float out[4];
  // loadXyz reads the last vector of an array (exactly 24 bytes: a read
  // past its 12 bytes is caught by the AddressSanitizer build) into lanes
  // 0-2, with 0 in lane 3.
  const std::vector<Vec3> vs = {{1, 2, 3}, {4, -5, 6.5f}};
  F4::loadXyz(&vs.back().x).store(out);
  EXPECT_EQ(out[0], 4.0f);
  EXPECT_EQ(out[1], -5.0f);
  EXPECT_EQ(out[2], 6.5f);
  EXPECT_EQ(std::bit_cast<std::uint32_t>(out[3]), 0u);
  // Division lane by lane, bit for bit the scalar quotient (a double
  // build's casts compute their reciprocals in scalar floats).
  const float num[4] = {1, -3, 1e-30f, 7}, den[4] = {3, 0.1f, 3e-8f, -0.0f};
  (F4::lanes(num[0], num[1], num[2], num[3]) / F4::lanes(den[0], den[1], den[2], den[3])).store(out);
  for (int k = 0; k < 4; ++k)
    EXPECT_EQ(std::bit_cast<std::uint32_t>(out[k]), std::bit_cast<std::uint32_t>(num[k] / den[k])) << k;
  // ordered: the lanes where neither side is NaN.
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  EXPECT_EQ(simd::bits(simd::ordered(F4::lanes(nan, 1, inf, 0), F4::lanes(0, 2, -inf, nan))), 0x6u);
}
#endif
