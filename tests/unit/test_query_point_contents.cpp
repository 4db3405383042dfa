// pointContents() (src/query/point_contents.cpp): the brushes containing a
// point, on a turned model too; the planes tested four at a time agree with
// one by one; the usual query's test is the guard's.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "cmkit/query.h"
#include "guard_values.h"
#include "model/model_access.h"
#include "model_fixtures.h"
#include "query/query_guards.h"  // guardPointContents
#include "query/trace_work.h"    // pointContentsMasked

using namespace cmkit;
using cmkit::test::ModelMaker;

TEST(PointContents, SeesBrushesAndHandlesRotation) {
  const CollisionModel m = ModelMaker()
                               .addBox({{0, 0, 0}, {10, 10, 10}})
                               .addBox({{20, 0, 0}, {30, 10, 10}}, contents::kWater)
                               .build();
  QueryWork work;
  EXPECT_EQ(pointContents(m, {{5, 5, 5}, {}}, work).contents, contents::kSolid | contents::kOpaque);
  EXPECT_EQ(pointContents(m, {{25, 5, 5}, {}}, work).contents, contents::kWater);
  EXPECT_EQ(pointContents(m, {{15, 5, 5}, {}}, work).contents, 0u);
  EXPECT_EQ(pointContents(m, {{10, 5, 5}, {}}, work).contents, 0u);  // on a plane is outside
  // Turned 90 degrees about z: model x points along world y.
  const Placement turned{{0, 0, 0}, Mat3{{0, 1, 0}, {-1, 0, 0}, {0, 0, 1}}};
  const PointContentsResult water = pointContents(m, {{-5, 25, 5}, turned}, work);
  EXPECT_EQ(water.status, QueryStatus::Ok);
  EXPECT_EQ(water.contents, contents::kWater);
  EXPECT_EQ(pointContents(m, {{25, 5, 5}, turned}, work).contents, 0u);
}

TEST(PointContents, AOneLeafModelHasTheFlagsOfEveryBrushHoldingThePoint) {
  // Overlapping brushes in a model of one leaf (its brushes tested in turn,
  // without a walk): a point in two has both's flags, whatever their order.
  const CollisionModel m = ModelMaker()
                               .addBox({{0, 0, 0}, {10, 10, 10}}, contents::kWater)
                               .addBox({{5, 0, 0}, {15, 10, 10}}, contents::kPlayerClip)
                               .addBox({{8, 0, 0}, {9, 10, 10}}, contents::kWater)
                               .build();
  ASSERT_EQ(m.nodes().size(), 1u);
  QueryWork work;
  EXPECT_EQ(pointContents(m, {{2, 5, 5}, {}}, work).contents, contents::kWater);
  EXPECT_EQ(pointContents(m, {{7, 5, 5}, {}}, work).contents, contents::kWater | contents::kPlayerClip);
  EXPECT_EQ(pointContents(m, {{8.5, 5, 5}, {}}, work).contents, contents::kWater | contents::kPlayerClip);
  EXPECT_EQ(pointContents(m, {{12, 5, 5}, {}}, work).contents, contents::kPlayerClip);
  EXPECT_EQ(pointContents(m, {{20, 5, 5}, {}}, work).contents, 0u);
  const CollisionModel bare = detail::ModelAccess::withoutQueryData(m);
  EXPECT_EQ(pointContents(bare, {{7, 5, 5}, {}}, work).contents, contents::kWater | contents::kPlayerClip);
}

// A brush's planes are tested four at a time where SSE2 float lanes exist:
// the answers must be those of Plane::distance plane by plane, on the
// planes, at their corners and a rounding step either side, for brushes of
// 6, 9, 12 and 17 planes (whole blocks of four and the rest one by one).
TEST(PointContents, PlanesFourAtATimeAgreeWithOneByOne) {
  const TraceModel shapes[] = {*TraceModel::box({{-10, -12, -7}, {13, 9, 11}}),
                               *TraceModel::cylinder({{-20, -16, -9}, {18, 21, 14}}, 7),
                               *TraceModel::dodecahedron({{-15, -15, -18}, {15, 15, 18}}),
                               *TraceModel::cone({{-27.5f, -12.5f, -18.5f}, {27.5f, 12.5f, 18.5f}}, 15)};
  std::uint32_t seed = 12345;
  const auto unit = [&seed] {  // in [-1, 1)
    seed = seed * 1664525u + 1013904223u;
    return Real(seed >> 8) / Real(1 << 23) - 1;
  };
  for (const TraceModel& shape : shapes) {
    const CollisionModel m = ModelMaker().addConvex(shape).build();
    ASSERT_EQ(m.brushes().size(), 1u);
    const CmBrush& brush = m.brushes()[0];
    ASSERT_GE(brush.numPlanes, 6u);
    const auto expected = [&](const Vec3& p) {
      if (!brush.bounds.containsPoint(p)) return std::uint32_t(0);
      for (const Plane& plane : m.planesOf(brush))
        if (plane.distance(p) >= 0) return std::uint32_t(0);
      return brush.contents;
    };
    int inside = 0, onOrOutside = 0;
    QueryWork work;
    for (int i = 0; i < 3000; ++i) {
      // A vertex (on several planes), a point on an edge or a face, nudged
      // by a rounding step or two, or a point anywhere in the bounds.
      const int a = int((unit() + 1) * Real(shape.numVertices()) / 2) % shape.numVertices();
      const int b = int((unit() + 1) * Real(shape.numVertices()) / 2) % shape.numVertices();
      Vec3 p = shape.vertex(a);
      switch (i % 4) {
        case 0:
          break;
        case 1:
          p = p + (shape.vertex(b) - p) * ((unit() + 1) / 2);
          break;
        case 2:
          for (int k = 0; k < 3; ++k) p[k] = std::nextafter(p[k], unit() > 0 ? Real(1e9) : Real(-1e9));
          break;
        default:
          for (int k = 0; k < 3; ++k) p[k] = (brush.bounds.min[k] + brush.bounds.max[k]) / 2 + unit() * 30;
      }
      const std::uint32_t want = expected(p);
      (want != 0 ? inside : onOrOutside)++;
      ASSERT_EQ(pointContents(m, {p, {}}, work).contents, want)
          << shape.describe() << " point " << p.x << " " << p.y << " " << p.z;
    }
    EXPECT_GT(inside, 50) << shape.describe();  // both answers were met
    EXPECT_GT(onOrOutside, 50) << shape.describe();
  }
}

// pointContents decides the usual query (point and origin in range, the
// model's axis exactly the identity) by its own range and axis tests; any
// other query goes through the guard. Each of the query's 15 floats set to
// values at and past the limits (range: 1e9 and the next float, infinities,
// NaN, -0; axis: -0 and 0 off the diagonal, 1 and its neighbours, -1, a
// subnormal): the status and contents are those of the guard and the
// general path. On a model of brushes, and on one of triangles alone (no
// brush: contents 0 whatever the point, so only the status tells).
TEST(PointContents, TheUsualQueryTestIsTheGuardsOnEveryFloat) {
  std::mt19937 rng(7);
  const auto mesh = test::twoSidedTerrainModel(4, rng);
  ASSERT_TRUE(mesh);
  ASSERT_TRUE(mesh->brushes().empty());
  const CollisionModel brushes = ModelMaker().addBox({{-10, -10, -10}, {10, 10, 10}}).build();
  ASSERT_FALSE(brushes.brushes().empty());
  for (const CollisionModel* model : {&brushes, mesh.get()}) {
    const CollisionModel& m = *model;
    QueryWork work;
    const std::vector<Real> rangeValues = test::rangeEdgeValues(), axisValues = test::axisEdgeValues();
    int checked = 0, refused = 0;
    for (int f = 0; f < 15; ++f)
      for (const Real v : f < 6 ? rangeValues : axisValues) {
        PointContentsQuery q{{1, 2, 3}, {}};
        Real* value = f < 3   ? &q.point[f]
                      : f < 6 ? &q.placement.origin[f - 3]
                              : &q.placement.axis[(f - 6) / 3][(f - 6) % 3];
        *value = v;
        PointContentsQuery guarded = q;
        const QueryStatus status = detail::guardPointContents(guarded);
        const std::uint32_t contents =
            status == QueryStatus::Ok
                ? detail::pointContentsMasked(m, q.point, q.placement, ~std::uint32_t(0))
                : 0;
        const PointContentsResult r = pointContents(m, q, work);
        EXPECT_EQ(r.status, status) << "float " << f << " = " << v;
        EXPECT_EQ(r.contents, contents) << "float " << f << " = " << v;
        ++checked;
        refused += status != QueryStatus::Ok;
      }
    EXPECT_GT(refused, 20);  // both outcomes were met
    EXPECT_GT(checked - refused, 20);
  }
}
