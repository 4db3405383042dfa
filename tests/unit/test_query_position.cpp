// The position test (contentsTest of a trace model): which trace-model
// vertex it reports inside a brush, and against which plane, computed here
// vertex by vertex and plane by plane; which trace-model face it reports a
// model polygon's edge crossing, found here by geometry.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "cmkit/materials.h"
#include "cmkit/mesh.h"
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

// Where segment a-b crosses trace-model polygon j's face away from its
// border (by `margin`): true, with the point in `at`.
bool crossesFace(const TraceModel& trm, int j, const Vec3& a, const Vec3& b, Real margin) {
  const TrmPolygon& face = trm.polygon(j);
  const Real da = face.normal.dot(a) - face.dist, db = face.normal.dot(b) - face.dist;
  if (!((da < -margin && db > margin) || (da > margin && db < -margin))) return false;
  const Vec3 at = a + (b - a) * (da / (da - db));
  for (const int e : face.edgeList()) {  // counter-clockwise around the normal
    const Vec3 from = trm.vertex(trm.edgeVertex(std::abs(e), e < 0 ? 1 : 0));
    const Vec3 to = trm.vertex(trm.edgeVertex(std::abs(e), e < 0 ? 0 : 1));
    const Vec3 along = to - from;
    if ((along.cross(at - from)).dot(face.normal) < margin * along.length()) return false;
  }
  return true;
}

// Whether segment a-b crosses the triangle t0 t1 t2 near or inside it.
bool crossesTriangleNear(const Vec3& a, const Vec3& b, const Vec3& t0, const Vec3& t1, const Vec3& t2) {
  const Vec3 n = (t1 - t0).cross(t2 - t0).normalized();
  const Real da = n.dot(a - t0), db = n.dot(b - t0);
  if ((da > 0) == (db > 0)) return false;
  const Vec3 at = a + (b - a) * (da / (da - db));
  const Vec3 corners[3] = {t0, t1, t2};
  for (int k = 0; k < 3; ++k) {
    const Vec3 along = corners[(k + 1) % 3] - corners[k];
    if (along.cross(at - corners[k]).dot(n) < -0.1f * along.length()) return false;  // (0.1 outside: near)
  }
  return true;
}

// A thin triangle (one polygon of a mesh) whose two long edges pass through
// a trace model at the origin, its corners far outside: no model vertex is
// inside the trace model and, where no trace-model edge crosses the triangle
// (checked here; the others are left out), the position test reports the
// first trace-model polygon, in order, whose face a long edge crosses: an
// edge contact against that face's plane negated. Both long edges cross the
// same two faces (checked here), so it is the first of those. Directions all
// round, so that the faces take indices past the first four (the test's
// float lanes take four planes at a time).
TEST(PositionTest, ReportsTheFirstTrmFaceAModelEdgeCrosses) {
  const Bounds size{{-12, -12, -10}, {12, 12, 10}};
  const std::vector<TraceModel> shapes = {*TraceModel::box(size), *TraceModel::cylinder(size, 8),
                                          *TraceModel::cylinder(size, 10), *TraceModel::cone(size, 13),
                                          *TraceModel::dodecahedron(size)};
  MeshBuildOptions options;
  options.contents = contents::kSolid;
  QueryWork work;
  int tested = 0, laterFaces = 0, leftOut = 0;
  for (const TraceModel& trm : shapes) {
    for (int k = 0; k < 90; ++k) {
      const Real angle = Real(2 * 3.14159265358979 * (k + 0.37) / 90);
      const Vec3 dir{std::cos(angle), std::sin(angle), 0};
      const Vec3 centre{0.7f, -0.4f, 0.3f};
      const Vec3 a = centre - dir * 60, b = centre + dir * 60, c = b + Vec3{0, 0, 0.5f};
      // The first face each long edge crosses, in the trace model's order.
      int first = -1, firstOther = -1;
      for (int j = trm.numPolygons() - 1; j >= 0; --j) {
        if (crossesFace(trm, j, a, b, Real(0.01))) first = j;
        if (crossesFace(trm, j, c, a, Real(0.01))) firstOther = j;
      }
      bool edgeThrough = false;  // a trace-model edge through the triangle: the earlier test's case
      for (int e = 1; e <= trm.numEdges(); ++e)
        edgeThrough |=
            crossesTriangleNear(trm.vertex(trm.edgeVertex(e, 0)), trm.vertex(trm.edgeVertex(e, 1)), a, b, c);
      if (first < 0 || first != firstOther || edgeThrough) {
        ++leftOut;
        continue;
      }
      TriangleMesh mesh;
      mesh.positions = {a, b, c};
      mesh.surfaces.push_back({"sliver", {0, 1, 2}});
      const auto built = buildCollisionModelFromTriangles(mesh, "sliver", MaterialTable{}, options);
      ASSERT_TRUE(built) << built.error().message;
      ASSERT_EQ(built->model->polygons().size(), 1u) << (built->warnings.empty() ? "" : built->warnings[0]);
      ContentsQuery q;
      q.trm = &trm;
      const ContentsResult r = contentsTest(*built->model, q, work);
      ++tested;
      laterFaces += first >= 4;
      ASSERT_EQ(r.contents, contents::kSolid) << trm.numPolygons() << " polygons, direction " << k;
      ASSERT_EQ(r.trace.contact.type, ContactType::Edge) << trm.numPolygons() << " polygons, direction " << k;
      EXPECT_EQ(r.trace.contact.trmFeature, first) << trm.numPolygons() << " polygons, direction " << k;
      const Vec3 want = -trm.polygon(first).normal;
      EXPECT_NEAR(r.trace.contact.normal.x, want.x, 1e-5)
          << trm.numPolygons() << " polygons, direction " << k;
      EXPECT_NEAR(r.trace.contact.normal.y, want.y, 1e-5)
          << trm.numPolygons() << " polygons, direction " << k;
      EXPECT_NEAR(r.trace.contact.normal.z, want.z, 1e-5)
          << trm.numPolygons() << " polygons, direction " << k;
    }
  }
  // Almost every direction tested (448 of 450), 90 of them against a face
  // past the fourth.
  EXPECT_GT(tested, 400) << leftOut << " left out";
  EXPECT_GT(laterFaces, 60);
}

}  // namespace
}  // namespace cmkit
