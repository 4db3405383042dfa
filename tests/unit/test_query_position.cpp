// The position test's brush test (contentsTest of a trace model): which
// trace-model vertex it reports inside a brush, and against which plane,
// computed here vertex by vertex and plane by plane.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "cmkit/query.h"
#include "cmkit/trace_model.h"
#include "model_fixtures.h"

namespace cmkit {
namespace {

struct Expected {
  int vertex = -1;  ///< the first vertex inside the brush, -1 for none
  Plane plane;      ///< its nearest plane (the first of the greatest distances)
};

Expected firstVertexInside(const TraceModel& trm, const Vec3& position, std::span<const Plane> planes) {
  for (int j = 0; j < trm.numVertices(); ++j) {
    const Vec3 p = trm.vertex(j) + position;
    Real best = -tol::kBoundsInfinity;
    std::size_t bestPlane = 0;
    bool inside = true;
    for (std::size_t i = 0; i < planes.size() && inside; ++i) {
      const Real d = planes[i].distance(p);
      inside = d < 0;
      if (inside && d > best) {
        best = d;
        bestPlane = i;
      }
    }
    if (inside) return {j, planes[bestPlane]};
  }
  return {};
}

// Trace models of 3 to 20 vertices (the most a shape has within the trace
// models' 32 edges: cones, cylinders, a dodecahedron, flat polygons) at random
// places around a brush of 11 planes: the reported vertex and plane are
// those of the first vertex inside, in vertex order.
TEST(PositionTest, ReportsTheFirstVertexInsideABrushAndItsNearestPlane) {
  const TraceModel brushShape = *TraceModel::cylinder({{-40, -40, -24}, {40, 40, 24}}, 9);
  const CollisionModel m = test::ModelMaker().addConvex(brushShape).build();
  ASSERT_EQ(m.brushes().size(), 1u);
  const std::span<const Plane> planes = m.planesOf(m.brushes()[0]);
  ASSERT_EQ(planes.size(), 11u);
  const Bounds size{{-12, -12, -10}, {12, 12, 10}};
  std::vector<TraceModel> shapes;
  for (int sides = 3; sides <= 15; ++sides) shapes.push_back(*TraceModel::cone(size, sides));
  for (int sides = 3; sides <= 10; ++sides) shapes.push_back(*TraceModel::cylinder(size, sides));
  shapes.push_back(*TraceModel::dodecahedron(size));
  for (int n = 3; n <= 16; ++n) {  // tilted flat polygons
    std::vector<Vec3> v;
    for (int k = 0; k < n; ++k) {
      const Real a = Real(2 * 3.14159265358979 * k / n);
      v.push_back({14 * std::cos(a), 14 * std::sin(a), 8 * std::cos(a)});
    }
    shapes.push_back(*TraceModel::polygon(v));
  }
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> at(-60, 60);
  QueryWork work;
  int inside = 0, laterBlock = 0, outside = 0;
  for (const TraceModel& trm : shapes) {
    const int n = trm.numVertices();
    for (int i = 0; i < 200; ++i) {
      const Vec3 position{at(rng), at(rng), at(rng) * 0.6f};
      const Expected want = firstVertexInside(trm, position, planes);
      ContentsQuery q;
      q.trm = &trm;
      q.position = position;
      const ContentsResult r = contentsTest(m, q, work);
      if (want.vertex < 0) {
        ++outside;
        // (The polygons may still find the trace model crossing the brush's faces.)
        if (r.contents != 0) {
          EXPECT_NE(r.trace.contact.type, ContactType::TrmVertex);
        }
        continue;
      }
      ++inside;
      laterBlock += want.vertex >= 4;
      ASSERT_EQ(r.contents, contents::kSolid | contents::kOpaque);
      ASSERT_EQ(r.trace.contact.type, ContactType::TrmVertex) << n << " vertices, query " << i;
      EXPECT_EQ(r.trace.contact.trmFeature, want.vertex) << n << " vertices, query " << i;
      EXPECT_EQ(r.trace.contact.normal, want.plane.normal) << n << " vertices, query " << i;
      EXPECT_EQ(r.trace.contact.dist, want.plane.dist) << n << " vertices, query " << i;
      EXPECT_EQ(r.trace.contact.point, trm.vertex(want.vertex) + position);
    }
  }
  // Both outcomes, and first vertices inside past the fourth.
  EXPECT_GT(inside, 500);
  EXPECT_GT(outside, 500);
  EXPECT_GT(laterBlock, 100);
}

}  // namespace
}  // namespace cmkit
