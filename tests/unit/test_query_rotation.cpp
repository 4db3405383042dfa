// Hand-computed rotations: fractions from trigonometry (with the 0.25 clip
// epsilon along the surface normal), both directions, parts above 180 and
// 360 degrees, axes through and far from the trace model, placed models,
// points, angle 0. The original's rotation bugs: test_original_bugs.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "cmkit/query.h"
#include "model_fixtures.h"
#include "query/rotate_work.h"  // firstQuadraticRoot

using namespace cmkit;
using cmkit::test::ModelMaker;

namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

void expectVecNear(const Vec3& a, const Vec3& b, float eps) {
  EXPECT_NEAR(a.x, b.x, eps);
  EXPECT_NEAR(a.y, b.y, eps);
  EXPECT_NEAR(a.z, b.z, eps);
}

// A wall filling x in [20, 40] (its face toward the origin at x = 20).
CollisionModel wallModel() { return ModelMaker().addBox({{20, -200, -200}, {40, 200, 200}}).build(); }

// The first angle (degrees, > 0) at which the corner of a 32x32 box turning
// clockwise about its own vertical axis gets to x = 19.75: the corner at
// 45 degrees has radius 16 sqrt 2 and x = r cos(45 - a).
double boxCornerAngle() { return 45.0 - std::acos(19.75 / (16 * std::sqrt(2.0))) * kDeg; }

RotationQuery boxQuery(const TraceModel& box, Real angle) {
  RotationQuery q;
  q.trm = &box;
  q.start = {0, 0, 0};
  q.rotation = Rotation({0, 0, 0}, {0, 0, 1}, angle);
  return q;
}

}  // namespace

TEST(Rotation, BoxTurningIntoAWallStopsWhenItsCornerIsAQuarterUnitAway) {
  const CollisionModel m = wallModel();
  const TraceModel box = *TraceModel::box({{-16, -16, 0}, {16, 16, 72}});
  QueryWork work;
  const TraceResult r = rotate(m, boxQuery(box, 90), work);
  EXPECT_NEAR(r.fraction, boxCornerAngle() / 90, 1e-5);
  EXPECT_EQ(r.contact.type, ContactType::TrmVertex);
  expectVecNear(r.contact.normal, {-1, 0, 0}, 1e-6f);
  EXPECT_EQ(r.contact.dist, -20.0f);
  EXPECT_NEAR(r.contact.point.x, 19.75f, 1e-3f);
  // The corner that was at (16, 16) turned clockwise: y = r sin(45 - a) > 0.
  EXPECT_GT(r.contact.point.y, 0);
  // The end pose: the box's axes turned clockwise by fraction * 90 degrees.
  const double a = r.fraction * 90 / kDeg;
  expectVecNear(r.endAxis[0], {Real(std::cos(a)), Real(-std::sin(a)), 0}, 1e-5f);
  expectVecNear(r.endPos, {0, 0, 0}, 1e-6f);
  EXPECT_LT(r.endAxis.orthonormalityError(), 1e-5f);
}

TEST(Rotation, AnEdgeThatPassesAModelEdgesLineBeyondItsEndIsTestedAgain) {
  // A box turning about a slanted axis: one of its 12-unit edges first
  // crosses the line of the slab's bottom front edge (y = 40, z = -20) beyond
  // the edge's end (46.1 degrees), then crosses the edge itself (~58.7
  // degrees, where the brute force below finds the overlap). Only the first
  // crossing used to be tested: the box went on into the slab and stopped at
  // 67.3 degrees with a vertex contact, 8.6 degrees deep (found by the
  // brute-force test of rotational contacts, seed 34 trial 69).
  const CollisionModel m = ModelMaker().addBox({{-30, 40, -20}, {30, 50, 20}}).build();
  const TraceModel box = *TraceModel::box({{-6, -4, -3}, {6, 4, 3}});
  RotationQuery q;
  q.trm = &box;
  q.start = {16.429739f, 18.0616989f, -10.7344065f};
  q.rotation = Rotation({36.3963089f, 31.1707573f, -18.3682194f}, {0.472971767f, 0.547795475f, 0.690085411f},
                        108.571945f);
  QueryWork work;
  const TraceResult r = rotate(m, q, work);
  // The brute force: the first overlapping pose, in 0.01-degree steps.
  double overlapAt = -1;
  for (int k = 0; k <= 10857 && overlapAt < 0; ++k) {
    const Rotation at(q.rotation.origin, q.rotation.axis, Real(k * 0.01));
    if (contentsTest(
            m, {&box, at.rotateAxis(Mat3::identity()), at.rotatePoint(q.start), contents::kMaskSolid, {}},
            work)
            .contents != 0)
      overlapAt = k * 0.01;
  }
  ASSERT_GT(overlapAt, 58.0);
  ASSERT_LT(overlapAt, 59.0);
  EXPECT_LT(r.fraction * 108.571945, overlapAt);
  EXPECT_EQ(r.contact.type, ContactType::Edge);
  EXPECT_EQ(contentsTest(m, {&box, r.endAxis, r.endPos, contents::kMaskSolid, {}}, work).contents, 0u);
}

TEST(Rotation, BothDirectionsGiveTheSameAngleBySymmetry) {
  const CollisionModel m = wallModel();
  const TraceModel box = *TraceModel::box({{-16, -16, 0}, {16, 16, 72}});
  QueryWork work;
  const TraceResult neg = rotate(m, boxQuery(box, -90), work);
  EXPECT_NEAR(neg.fraction, boxCornerAngle() / 90, 1e-5);
  EXPECT_LT(neg.contact.point.y, 0);  // the corner at (16, -16) turned counter-clockwise
  const double a = -neg.fraction * 90 / kDeg;
  expectVecNear(neg.endAxis[0], {Real(std::cos(a)), Real(-std::sin(a)), 0}, 1e-5f);
}

TEST(Rotation, AnglesOf180AndMoreAreTracedInParts) {
  const CollisionModel m = wallModel();
  const TraceModel box = *TraceModel::box({{-16, -16, 0}, {16, 16, 72}});
  QueryWork work;
  for (Real angle : {200.0f, 300.0f, 400.0f, -250.0f, -720.0f}) {
    const TraceResult r = rotate(m, boxQuery(box, angle), work);
    EXPECT_NEAR(r.fraction * std::fabs(angle), boxCornerAngle(), 1e-3) << angle;
  }
  // Free turns keep fraction 1 and end at the whole angle.
  const CollisionModel far = ModelMaker().addBox({{500, 500, 0}, {600, 600, 10}}).build();
  for (Real angle : {270.0f, 400.0f, -450.0f}) {
    const TraceResult r = rotate(far, boxQuery(box, angle), work);
    EXPECT_EQ(r.fraction, 1.0f);
    const Mat3 expected = Rotation({0, 0, 0}, {0, 0, 1}, angle).rotateAxis(Mat3::identity());
    for (int i = 0; i < 3; ++i) expectVecNear(r.endAxis[i], expected[i], 1e-5f);
  }
}

TEST(Rotation, AxisFarFromTheTraceModel) {
  // A 16-unit cube centred at (100, 0, 0) swings clockwise about the z axis
  // through the origin toward a slab whose top face is y = -50. Its lowest
  // vertex (108, -8) has y = -108 sin a - 8 cos a; it stops at y = -49.75.
  const CollisionModel m = ModelMaker().addBox({{-300, -200, -100}, {300, -50, 100}}).build();
  const TraceModel cube = *TraceModel::box({{-8, -8, -8}, {8, 8, 8}});
  QueryWork work;
  RotationQuery q;
  q.trm = &cube;
  q.start = {100, 0, 0};
  q.rotation = Rotation({0, 0, 0}, {0, 0, 1}, 90);
  const TraceResult r = rotate(m, q, work);
  const double radius = std::hypot(108.0, 8.0);
  const double expected = (std::asin(49.75 / radius) - std::atan2(8.0, 108.0)) * kDeg;
  EXPECT_NEAR(r.fraction * 90, expected, 1e-3);
  EXPECT_EQ(r.contact.type, ContactType::TrmVertex);
  expectVecNear(r.contact.normal, {0, 1, 0}, 1e-6f);
  EXPECT_NEAR(r.contact.point.y, -49.75f, 1e-3f);
  const double a = r.fraction * 90 / kDeg;
  expectVecNear(r.endPos, {Real(100 * std::cos(a)), Real(-100 * std::sin(a)), 0}, 1e-3f);
}

TEST(Rotation, BoneTippingOntoAFloor) {
  // A bone of length 64 lying along y (trmAxis: its z axis -> world y),
  // centred 20 above a floor (top z = 0), turning about the x axis through
  // its centre. Positive angles turn clockwise seen from +x: the tip at
  // +y goes down, z = 20 - 32 sin a, and stops 0.25 above the floor. The
  // bone's middle vertices (radius 8 at most) stay higher.
  const CollisionModel m = ModelMaker().addBox({{-200, -200, -50}, {200, 200, 0}}).build();
  const TraceModel bone = *TraceModel::bone(64, 16);
  QueryWork work;
  RotationQuery q;
  q.trm = &bone;
  q.trmAxis = Mat3{{1, 0, 0}, {0, 0, -1}, {0, 1, 0}};
  q.start = {0, 0, 20};
  q.rotation = Rotation({0, 0, 20}, {1, 0, 0}, 120);
  const TraceResult r = rotate(m, q, work);
  EXPECT_NEAR(r.fraction * 120, std::asin(19.75 / 32) * kDeg, 1e-3);
  EXPECT_EQ(r.contact.type, ContactType::TrmVertex);
  expectVecNear(r.contact.normal, {0, 0, 1}, 1e-6f);
  EXPECT_NEAR(r.contact.point.z, 0.25f, 1e-3f);
  EXPECT_GT(r.contact.point.y, 0);
  // The other way the tip at -y goes down: same angle.
  q.rotation.angle = -120;
  const TraceResult r2 = rotate(m, q, work);
  EXPECT_NEAR(r2.fraction * 120, std::asin(19.75 / 32) * kDeg, 1e-3);
  EXPECT_LT(r2.contact.point.y, 0);
}

TEST(Rotation, PlacedModelGivesTheSameAnswerInTheWorld) {
  // The wall model placed at (1000, 0, 0) and turned 90 degrees (its x axis
  // along world y): its face is now the world plane y = 20 (relative).
  const CollisionModel m = wallModel();
  const TraceModel box = *TraceModel::box({{-16, -16, 0}, {16, 16, 72}});
  QueryWork work;
  RotationQuery q = boxQuery(box, 90);
  q.start = {1000, 0, 0};
  q.rotation.origin = {1000, 0, 0};
  q.placement.origin = {1000, 0, 0};
  q.placement.axis = Mat3{{0, 1, 0}, {-1, 0, 0}, {0, 0, 1}};
  const TraceResult r = rotate(m, q, work);
  EXPECT_NEAR(r.fraction, boxCornerAngle() / 90, 1e-5);
  expectVecNear(r.contact.normal, {0, -1, 0}, 1e-6f);
  EXPECT_NEAR(r.contact.point.y, 19.75f, 1e-3f);
  EXPECT_NEAR(r.contact.dist, r.contact.normal.dot(r.contact.point) - 0.25f, 1e-3f);  // 0.25 in front
}

TEST(Rotation, PointTurningIntoASlab) {
  // (100, 0, 10) turning clockwise about z goes to (0, -100, 10); the slab
  // below y = -50 stops it where 100 sin a = 49.75.
  const CollisionModel m = ModelMaker().addBox({{-300, -200, -100}, {300, -50, 100}}).build();
  QueryWork work;
  RotationQuery q;
  q.start = {100, 0, 10};
  q.rotation = Rotation({0, 0, 0}, {0, 0, 1}, 90);
  const TraceResult r = rotate(m, q, work);
  EXPECT_NEAR(r.fraction * 90, std::asin(0.4975) * kDeg, 1e-3);
  EXPECT_EQ(r.contact.type, ContactType::TrmVertex);
  EXPECT_EQ(r.endAxis, Mat3::identity());
  EXPECT_NEAR(r.endPos.y, -49.75f, 1e-3f);
  // Counter-clockwise it goes to +y: free.
  q.rotation.angle = -90;
  const TraceResult free = rotate(m, q, work);
  EXPECT_EQ(free.fraction, 1.0f);
  expectVecNear(free.endPos, {0, 100, 10}, 1e-3f);
}

TEST(Rotation, AngleZeroIsAPositionTest) {
  const CollisionModel m = wallModel();
  const TraceModel box = *TraceModel::box({{-16, -16, 0}, {16, 16, 72}});
  QueryWork work;
  RotationQuery q = boxQuery(box, 0);
  q.start = {10, 0, 0};  // reaches x = 26: inside the wall
  const TraceResult stuck = rotate(m, q, work);
  EXPECT_EQ(stuck.fraction, 0.0f);
  EXPECT_TRUE(stuck.startSolid);
  q.start = {4, 0, 0};  // reaches x = 20 exactly: touching is free
  const TraceResult touching = rotate(m, q, work);
  EXPECT_EQ(touching.fraction, 1.0f);
  EXPECT_FALSE(touching.startSolid);
  EXPECT_EQ(touching.endPos, q.start);
}

TEST(Rotation, StartSolidIsReportedWhenAsked) {
  const CollisionModel m = wallModel();
  const TraceModel box = *TraceModel::box({{-16, -16, 0}, {16, 16, 72}});
  QueryWork work;
  RotationQuery q = boxQuery(box, 30);
  q.detectStartSolid = true;
  EXPECT_FALSE(rotate(m, q, work).startSolid);
  q.start = {10, 0, 0};
  EXPECT_TRUE(rotate(m, q, work).startSolid);
}

TEST(Rotation, QuadraticSolverNeverReturnsNaN) {
  // The original's solver computed -b + sqrt(b^2 - ac) for b > 0, which is
  // 0 when ac = 0, and then c / 0 = 0 / 0. A root at exactly 0 must come out.
  const CollisionModel m = ModelMaker().addBox({{-300, -200, -100}, {300, -50, 100}}).build();
  QueryWork work;
  RotationQuery q;
  // The point starts exactly on the epsilon plane (y = -49.75) moving down.
  q.start = {0, -49.75f, 0};
  q.rotation = Rotation({-100, -49.75f, 0}, {0, 0, 1}, 45);
  const TraceResult r = rotate(m, q, work);
  EXPECT_TRUE(std::isfinite(r.fraction));
  EXPECT_EQ(r.fraction, 0.0f);
  EXPECT_TRUE(r.endPos.isFinite());
}

TEST(Rotation, QuadraticSolverFindsTheFirstRootInItsInterval) {
  // (u - 1)(u - 2) = u^2 + 2 * (-1.5) u + 2.
  double u = -1;
  EXPECT_TRUE(cmkit::detail::firstQuadraticRoot(1, -1.5, 2, 0, 3, u));
  EXPECT_EQ(u, 1.0);
  EXPECT_TRUE(cmkit::detail::firstQuadraticRoot(1, -1.5, 2, 1, 1.5, u));  // a root at lo counts
  EXPECT_EQ(u, 1.0);
  EXPECT_FALSE(cmkit::detail::firstQuadraticRoot(1, -1.5, 2, 0, 1, u));      // not at hi
  EXPECT_FALSE(cmkit::detail::firstQuadraticRoot(1, -1.5, 2, 0, 0.99, u));   // both beyond
  EXPECT_FALSE(cmkit::detail::firstQuadraticRoot(1, -1.5, 2, 1.2, 1.8, u));  // between the roots
  EXPECT_TRUE(cmkit::detail::firstQuadraticRoot(1, -1.5, 2, 1.2, 2.5, u));
  EXPECT_EQ(u, 2.0);
  EXPECT_FALSE(cmkit::detail::firstQuadraticRoot(1, -1.5, 2, 2.5, 9, u));  // both before
  // The second crossing after a first at 0 (lo the least double, subnormal:
  // solved, not ruled out from the ends' signs): u (u - 0.5) = u^2 + 2 (-0.25) u.
  const double afterZero = std::nextafter(0.0, 1.0);
  EXPECT_TRUE(cmkit::detail::firstQuadraticRoot(1, -0.25, 0, afterZero, 1, u));
  EXPECT_EQ(u, 0.5);
  EXPECT_FALSE(cmkit::detail::firstQuadraticRoot(1, -0.25, 0, afterZero, 0.4, u));
  EXPECT_FALSE(cmkit::detail::firstQuadraticRoot(1, -1.5, 2, afterZero, 0.99, u));  // (u - 1)(u - 2)
  EXPECT_TRUE(cmkit::detail::firstQuadraticRoot(1, -1.5, 2, afterZero, 1.5, u));
  EXPECT_EQ(u, 1.0);
  // A coefficient that is not finite: no root, u untouched, whether the
  // ends' signs are tried first (lo 0 or not, hi finite) or not.
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  for (const double lo : {0.0, 0.5})
    for (const double hi : {3.0, inf})
      for (const auto& [a, b, c] : {std::array{inf, -1.5, 2.0},
                                    {-inf, -1.5, 2.0},
                                    {1.0, inf, 2.0},
                                    {1.0, -inf, 2.0},
                                    {1.0, -1.5, inf},
                                    {1.0, -1.5, -inf},
                                    {nan, -1.5, 2.0},
                                    {1.0, nan, 2.0},
                                    {1.0, -1.5, nan}}) {
        u = -1;
        double later = -1;
        EXPECT_FALSE(cmkit::detail::firstQuadraticRoot(a, b, c, lo, hi, u, &later))
            << a << " " << b << " " << c << " [" << lo << ", " << hi << ")";
        EXPECT_EQ(u, -1.0);
        EXPECT_EQ(later, -1.0);
      }

  // Random quadratics a (u - r1)(u - r2) and intervals: the root found (or
  // none) is the first of r1, r2 in [lo, hi), whichever way the solver
  // decides (solving, or ruling the interval out from the ends' signs).
  // Intervals with an end within 1e-6 of a root are left out (rounding may
  // put the root on either side).
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> any(-4, 4), scale(-50, 50);
  int found = 0, none = 0, seconds = 0;
  for (int i = 0; i < 200000; ++i) {
    const double r1 = any(rng), r2 = any(rng), a = scale(rng);
    if (std::fabs(a) < 1e-3 || std::fabs(r1 - r2) < 1e-3) continue;
    double lo = std::fabs(any(rng)), hi = std::fabs(any(rng));
    if (hi < lo) std::swap(lo, hi);
    const auto nearEnd = [&](double r) { return std::fabs(r - lo) < 1e-6 || std::fabs(r - hi) < 1e-6; };
    if (nearEnd(r1) || nearEnd(r2)) continue;
    double expected = std::numeric_limits<double>::infinity();
    for (const double r : {r1, r2})
      if (r >= lo && r < hi) expected = std::min(expected, r);
    double root = 0, later = 0;
    const double qa = a, qb = -a * (r1 + r2) / 2, qc = a * r1 * r2;
    const bool ok = cmkit::detail::firstQuadraticRoot(qa, qb, qc, lo, hi, root, &later);
    ASSERT_EQ(ok, std::isfinite(expected)) << a << " " << r1 << " " << r2 << " [" << lo << ", " << hi << ")";
    if (ok) {
      EXPECT_NEAR(root, expected, 1e-9 * (1 + std::fabs(expected)));
      ++found;
      // The next root given with it is, bit for bit, what solving again
      // from just after the root finds (the rotations' second crossing).
      double again = 0;
      const bool more = cmkit::detail::firstQuadraticRoot(qa, qb, qc, std::nextafter(root, 9.0), hi, again);
      ASSERT_EQ(more, !std::isnan(later)) << a << " " << r1 << " " << r2 << " [" << lo << ", " << hi << ")";
      if (more) {
        EXPECT_EQ(later, again);
        ++seconds;
      }
    } else {
      ++none;
    }
  }
  EXPECT_GT(found, 10000);  // both outcomes are exercised
  EXPECT_GT(none, 10000);
  EXPECT_GT(seconds, 1000);
}

TEST(Rotation, ArcBoxesOfManyVerticesAreEachVertexsArcBox) {
  using cmkit::detail::arcBounds;
  const cmkit::Real eps = cmkit::tol::kBoxEpsilon;
  // By hand: about z through the origin, (1,0,0) turned by 135 degrees ends
  // at (-s, s, 0), s = sqrt(1/2), passing (0,1,0) on the way: the box holds
  // y = 1. A second vertex on the axis's own circle of radius 2 turns a
  // quarter, (0,-2,3) to (2,0,3), and passes no extreme.
  const cmkit::Real s = std::sqrt(cmkit::Real(0.5));
  cmkit::detail::VertexArcs arcs;
  arcs.set(0, {1, 0, 0}, {-s, s, 0}, {0, 0, 0});
  arcs.set(1, {0, -2, 3}, {2, 0, 3}, {0, 0, 3});
  cmkit::detail::FeatureBoxes boxes;
  const cmkit::Bounds all = cmkit::detail::vertexArcBoxes(arcs, 2, {0, 0, 1}, boxes);
  EXPECT_EQ(boxes.get(0), cmkit::Bounds({-s - eps, -eps, -eps}, {1 + eps, 1 + eps, eps}));
  EXPECT_EQ(boxes.get(1), cmkit::Bounds({-eps, -2 - eps, 3 - eps}, {2 + eps, eps, 3 + eps}));
  EXPECT_EQ(all, cmkit::Bounds({-s - eps, -2 - eps, -eps}, {2 + eps, 1 + eps, 3 + eps}));

  // Random arcs below 180 degrees about random axes, 1 to 32 vertices: each
  // box is the scalar arcBounds' padded box, bit for bit (the four-lane form
  // does the same arithmetic), and the union is theirs.
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> pos(-300, 300), unit(-1, 1), angle(-179, 179);
  for (int round = 0; round < 400; ++round) {
    cmkit::Vec3 axis{unit(rng), unit(rng), unit(rng)};
    if (axis.length() < cmkit::Real(0.1)) continue;
    axis.normalize();
    const cmkit::Vec3 origin{pos(rng), pos(rng), pos(rng)};
    const cmkit::Mat3 turn = cmkit::Rotation(origin, axis, angle(rng)).matrix();
    const int n = 1 + round % 32;
    std::vector<cmkit::Bounds> expected;
    cmkit::Bounds expectedAll;
    for (int i = 0; i < n; ++i) {
      const cmkit::Vec3 p{pos(rng), pos(rng), pos(rng)};
      const cmkit::Vec3 end = origin + (p - origin) * turn;
      const cmkit::Vec3 ro = origin + axis * axis.dot(p - origin);
      arcs.set(std::size_t(i), p, end, ro);
      expected.push_back(arcBounds(ro, axis, p, end).expanded(eps));
      expectedAll.addBounds(expected.back());
    }
    const cmkit::Bounds got = cmkit::detail::vertexArcBoxes(arcs, n, axis, boxes);
    for (int i = 0; i < n; ++i)
      ASSERT_EQ(boxes.get(std::size_t(i)), expected[std::size_t(i)]) << round << " " << i;
    ASSERT_EQ(got, expectedAll) << round;
  }
}
