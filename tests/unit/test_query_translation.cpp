// Hand-computed translations: fractions, end positions, normals and feature
// types, derived by hand from the geometry and the 0.25 clip epsilon.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "cmkit/query.h"
#include "model/model_access.h"
#include "model/query_data.h"
#include "model_fixtures.h"

using namespace cmkit;
using cmkit::test::ModelMaker;

namespace {

const Bounds kPlayer{{-16, -16, 0}, {16, 16, 72}};

void expectVecNear(const Vec3& a, const Vec3& b, float eps) {
  EXPECT_NEAR(a.x, b.x, eps);
  EXPECT_NEAR(a.y, b.y, eps);
  EXPECT_NEAR(a.z, b.z, eps);
}

CollisionModel floorModel() { return ModelMaker().addBox({{-256, -256, -16}, {256, 256, 0}}).build(); }

/// A low square pyramid: its apex (model vertex 4) above the middle of a
/// 100-unit base at z = 0 (its sides slope 10 in 50 for an apex at z = 10).
CollisionModel spikeUnder(const Vec3& apex) {
  const Vec3 points[5] = {{apex.x - 50, apex.y - 50, 0},
                          {apex.x + 50, apex.y - 50, 0},
                          {apex.x + 50, apex.y + 50, 0},
                          {apex.x - 50, apex.y + 50, 0},
                          apex};
  return ModelMaker().addConvex(*TraceModel::convexHull(points)).build();
}

/// A flat 64 x 64 x 16 box (its bottom at its origin) moved from (0, 0, 100)
/// to `end` over spikeUnder(apex).
TraceResult boxOverSpike(const Vec3& apex, const Vec3& end) {
  const CollisionModel m = spikeUnder(apex);
  const TraceModel box = *TraceModel::box({{-32, -32, 0}, {32, 32, 16}});
  QueryWork work;
  TranslationQuery q;
  q.trm = &box;
  q.start = {0, 0, 100};
  q.end = end;
  return translate(m, q, work);
}

/// boxOverSpike's result when the apex (z = 10) meets the box's bottom face:
/// within the clip epsilon after 89.75 of the 200 units down.
void expectApexMeetsTheBottomFace(const TraceResult& r) {
  EXPECT_NEAR(r.fraction, 89.75f / 200, 1e-6f);
  EXPECT_EQ(r.contact.type, ContactType::ModelVertex);
  EXPECT_EQ(r.contact.normal, Vec3(0, 0, 1));  // the box's bottom face, negated
  EXPECT_EQ(r.contact.modelFeature, 4);        // the apex
}

}  // namespace

TEST(Translation, BoxDroppedOnAFloorStopsAQuarterUnitAbove) {
  const CollisionModel m = floorModel();
  const TraceModel box = *TraceModel::box(kPlayer);
  QueryWork work;
  TranslationQuery q;
  q.trm = &box;
  q.start = {0, 0, 100};
  q.end = {0, 0, -100};
  const TraceResult r = translate(m, q, work);
  // The box's bottom (z = start.z) reaches 0.25 after 99.75 of 200 units.
  EXPECT_NEAR(r.fraction, 99.75f / 200, 1e-6f);
  expectVecNear(r.endPos, {0, 0, 0.25f}, 1e-4f);
  EXPECT_EQ(r.contact.type, ContactType::TrmVertex);
  EXPECT_EQ(r.contact.normal, Vec3(0, 0, 1));
  EXPECT_EQ(r.contact.dist, 0.0f);
  EXPECT_EQ(r.contact.contents, contents::kSolid | contents::kOpaque);
  EXPECT_NEAR(r.contact.point.z, 0.25f, 1e-4f);
  EXPECT_EQ(r.contact.modelFeature, 1);  // the box's top polygon (index 1)
  EXPECT_LT(r.contact.trmFeature, 4);    // a bottom vertex (0..3)
  EXPECT_EQ(r.endAxis, Mat3::identity());
  EXPECT_FALSE(r.startSolid);
}

TEST(Translation, MissIsFractionOneWithEveryFieldDefined) {
  const CollisionModel m = floorModel();
  const TraceModel box = *TraceModel::box(kPlayer);
  QueryWork work;
  TranslationQuery q;
  q.trm = &box;
  q.start = {0, 0, 100};
  q.end = {0, 0, 50};
  const TraceResult r = translate(m, q, work);
  EXPECT_EQ(r.fraction, 1.0f);
  EXPECT_EQ(r.endPos, Vec3(0, 0, 50));
  EXPECT_EQ(r.contact.type, ContactType::None);
  EXPECT_EQ(r.contact.point, Vec3());
  EXPECT_EQ(r.contact.normal, Vec3());
  EXPECT_EQ(r.contact.material, -1);
  EXPECT_EQ(r.contact.contents, 0u);
}

TEST(Translation, BackFacesDoNotCollide) {
  const CollisionModel m = floorModel();
  const TraceModel box = *TraceModel::box(kPlayer);
  QueryWork work;
  TranslationQuery q;
  q.trm = &box;
  q.start = {0, 0, -200};  // below the slab, moving up through its bottom face
  q.end = {0, 0, -50};
  const TraceResult r = translate(m, q, work);
  // The bottom face (normal -z) faces the box: it stops 0.25 below it.
  EXPECT_NEAR(r.endPos.z + 72, -16.25f, 1e-3f);
  q.start = {0, 0, -8};  // starting inside: the top face is seen from behind
  q.end = {0, 0, 50};
  EXPECT_EQ(translate(m, q, work).fraction, 1.0f);
}

TEST(Translation, PointThroughAThinWall) {
  const CollisionModel m = ModelMaker().addBox({{-1, -100, -100}, {1, 100, 100}}).build();
  QueryWork work;
  TranslationQuery q;  // no trm: a point
  q.start = {-50, 0, 0};
  q.end = {50, 0, 0};
  const TraceResult r = translate(m, q, work);
  EXPECT_NEAR(r.fraction, 48.75f / 100, 1e-6f);
  expectVecNear(r.endPos, {-1.25f, 0, 0}, 1e-4f);
  EXPECT_EQ(r.contact.normal, Vec3(-1, 0, 0));
  EXPECT_EQ(r.contact.type, ContactType::TrmVertex);
  EXPECT_EQ(r.contact.dist, 1.0f);
}

TEST(Translation, EdgeAgainstEdge) {
  // A block whose top edge runs along y at x = 0, z = 0; a wedge whose lowest
  // edge slopes from (15,0,0) up to (-5,0,4) falls onto it. The edges cross
  // above the block edge; the wedge's vertices stay clear of the faces.
  const CollisionModel m = ModelMaker().addBox({{-100, -100, -100}, {0, 100, 0}}).build();
  const Vec3 pts[4] = {{15, 0, 0}, {-5, 0, 4}, {5, -5, 20}, {5, 5, 20}};
  const TraceModel wedge = *TraceModel::convexHull(pts);
  QueryWork work;
  TranslationQuery q;
  q.trm = &wedge;
  q.start = {0, 0, 50};
  q.end = {0, 0, -50};
  const TraceResult r = translate(m, q, work);
  // The block edge's epsilon edge lies at x = z = 0.25 (edge normal (1,0,1));
  // the wedge edge meets it at s = 14.75/20 along, height h + 2.95 = 0.25.
  EXPECT_NEAR(r.fraction, (50 + 2.7f) / 100, 1e-5f);
  EXPECT_NEAR(r.endPos.z, -2.7f, 1e-3f);
  EXPECT_EQ(r.contact.type, ContactType::Edge);
  expectVecNear(r.contact.normal, Vec3{4, 0, 20}.normalized(), 1e-5f);
  expectVecNear(r.contact.point, {0, 0, 0}, 1e-4f);
}

TEST(Translation, CylinderIntoAStairRiser) {
  // A step: riser face at x = 0, tread at z = 16. An 8-sided cylinder moving
  // +x with its bottom below the tread: vertex 0 (angle 0, x = +16) hits.
  const CollisionModel m = ModelMaker().addBox({{0, -100, -100}, {100, 100, 16}}).build();
  const TraceModel cyl = *TraceModel::cylinder(kPlayer, 8);
  QueryWork work;
  TranslationQuery q;
  q.trm = &cyl;
  q.start = {-100, 0, 0};
  q.end = {100, 0, 0};
  const TraceResult r = translate(m, q, work);
  EXPECT_NEAR(r.fraction, (100 - 16.25f) / 200, 1e-5f);
  EXPECT_NEAR(r.endPos.x, -16.25f, 1e-3f);
  EXPECT_EQ(r.contact.normal, Vec3(-1, 0, 0));
  // Its vertical edge at angle 0 touches the face and, at the same moment,
  // the riser's top edge: both are the same contact plane.
  if (r.contact.type == ContactType::TrmVertex) {
    EXPECT_TRUE(r.contact.trmFeature == 0 || r.contact.trmFeature == 8);
  } else {
    EXPECT_EQ(r.contact.type, ContactType::Edge);
    EXPECT_EQ(r.contact.trmFeature, 17);  // vertical edge 2n+1 from vertex 0
  }
  // Lifted above the tread it passes over the step.
  q.start.z = q.end.z = 16.5f;
  EXPECT_EQ(translate(m, q, work).fraction, 1.0f);
}

TEST(Translation, ModelVertexHitsATraceModelFace) {
  // A spike with its apex at (0,0,10) under a wide flat box falling onto it.
  const TraceResult r = boxOverSpike({0, 0, 10}, {0, 0, -100});
  expectApexMeetsTheBottomFace(r);
  EXPECT_NEAR(r.endPos.z, 10.25f, 1e-4f);
  EXPECT_EQ(r.contact.trmFeature, 0);  // the box's bottom polygon
  // The original reports the vertex relative to the trace model's start.
  expectVecNear(r.contact.point, {0, 0, 10 + 200 * r.fraction}, 1e-3f);
}

TEST(Translation, ModelVertexNearTheSweptEdgeIsNotCulled) {
  // The box moves down and sideways, dir (40, 30, -200): its first heart
  // plane (through the move, normal (-0.6, 0.8, 0)) has the moving corner
  // (32, -32) 44.8 units away, the model-vertex cull's limit 45.8. A low
  // spike's apex meets the bottom face 0.2 inside that corner, 1.4 * 31.8 =
  // 44.52 units from the plane: it must be tested (a limit short of the
  // farthest moving vertex by 0.3, or the wrong plane, would drop it). The
  // bottom face gets within the clip epsilon of the apex (z = 10) after 89.75
  // of 200 units down, the box then at (17.95, 13.4625, 10.25); the corner is
  // then still 0.2 * 0.196 + 0.25 * 0.981 = 0.284 from the spike's two
  // nearest faces (slope 10 in 50), beyond their clip epsilon.
  const Vec3 apex{17.95f + 31.8f, 13.4625f - 31.8f, 10};
  const Vec3 end{40, 30, -100};
  expectApexMeetsTheBottomFace(boxOverSpike(apex, end));
  // A unit further out the apex misses the bottom face: the box comes down
  // on the spike's sides later.
  const TraceResult outside = boxOverSpike({apex.x + 1, apex.y - 1, 10}, end);
  EXPECT_GT(outside.fraction, 89.75f / 200 + 1e-4f);
  EXPECT_NE(outside.contact.type, ContactType::ModelVertex);
}

TEST(Translation, RotatedTraceModel) {
  const CollisionModel m = floorModel();
  const TraceModel box = *TraceModel::box({{-16, -16, -16}, {16, 16, 16}});
  QueryWork work;
  TranslationQuery q;
  q.trm = &box;
  q.trmAxis = Mat3::fromAngles(0, 0, 45);  // roll 45: lowest feature an edge at -16*sqrt2
  q.start = {0, 0, 100};
  q.end = {0, 0, -100};
  const TraceResult r = translate(m, q, work);
  const float lowest = 16 * std::sqrt(2.0f);
  EXPECT_NEAR(r.endPos.z, lowest + 0.25f, 1e-3f);
  EXPECT_EQ(r.endAxis, q.trmAxis);
  EXPECT_NEAR(r.contact.normal.z, 1, 1e-6f);
}

TEST(Translation, RotatedAndOffsetModel) {
  // The wall of PointThroughAThinWall, turned 90 degrees about z (its x axis
  // now points along world y) and placed at (0, 10, 5).
  const CollisionModel m = ModelMaker().addBox({{-1, -100, -100}, {1, 100, 100}}).build();
  QueryWork work;
  TranslationQuery q;
  q.placement.origin = {0, 10, 5};
  q.placement.axis = Mat3{{0, 1, 0}, {-1, 0, 0}, {0, 0, 1}};
  q.start = {0, -40, 0};
  q.end = {0, 60, 0};
  const TraceResult r = translate(m, q, work);
  // The wall spans world y in [9, 11]: stop at 8.75.
  EXPECT_NEAR(r.endPos.y, 8.75f, 1e-4f);
  expectVecNear(r.contact.normal, {0, -1, 0}, 1e-6f);
  EXPECT_NEAR(r.contact.dist, -9.0f, 1e-4f);  // n . p = dist on the world plane y = 9
  // the same with a box trace model
  const TraceModel box = *TraceModel::box({{-4, -4, -4}, {4, 4, 4}});
  q.trm = &box;
  const TraceResult rb = translate(m, q, work);
  EXPECT_NEAR(rb.endPos.y, 8.75f - 4, 1e-3f);
  expectVecNear(rb.contact.normal, {0, -1, 0}, 1e-6f);
}

TEST(Translation, StartInsideSolidIsFlagged) {
  const CollisionModel m = floorModel();
  const TraceModel box = *TraceModel::box(kPlayer);
  QueryWork work;
  TranslationQuery q;
  q.trm = &box;
  q.start = {0, 0, -8};
  q.end = {0, 0, 40};
  q.detectStartSolid = true;
  const TraceResult r = translate(m, q, work);
  EXPECT_TRUE(r.startSolid);
  EXPECT_EQ(r.fraction, 1.0f);  // the original's rule: the top face is seen from behind
  const PenetrationResult pen = penetration(m, {&box, {}, q.start, contents::kMaskSolid, {}}, work);
  ASSERT_TRUE(pen.stuck);
  EXPECT_NEAR(pen.depth, 8, 1e-5f);
  EXPECT_EQ(pen.direction, Vec3(0, 0, 1));
  q.start = {0, 0, 8};
  EXPECT_FALSE(translate(m, q, work).startSolid);
  EXPECT_FALSE(penetration(m, {&box, {}, q.start, contents::kMaskSolid, {}}, work).stuck);
}

TEST(PositionTest, ExactlyTouchingIsFreeOneUnitInIsStuck) {
  const CollisionModel m = floorModel();
  const TraceModel box = *TraceModel::box(kPlayer);
  QueryWork work;
  TranslationQuery q;
  q.trm = &box;
  q.start = q.end = {0, 0, 0};  // resting exactly on the floor
  TraceResult r = translate(m, q, work);
  EXPECT_EQ(r.fraction, 1.0f);
  EXPECT_FALSE(r.startSolid);
  q.start = q.end = {0, 0, -1};
  r = translate(m, q, work);
  EXPECT_EQ(r.fraction, 0.0f);
  EXPECT_TRUE(r.startSolid);
  EXPECT_EQ(r.contact.type, ContactType::TrmVertex);
  EXPECT_EQ(r.contact.normal, Vec3(0, 0, 1));  // the nearest brush plane
  const ContentsResult c = contentsTest(m, {&box, {}, {0, 0, -1}, contents::kMaskSolid, {}}, work);
  EXPECT_EQ(c.contents, contents::kSolid | contents::kOpaque);
  // Masked out: water only.
  EXPECT_EQ(contentsTest(m, {&box, {}, {0, 0, -1}, contents::kWater, {}}, work).contents, 0u);
}

TEST(PositionTest, PolygonPiercingWithoutVerticesInside) {
  // A thin plate pierced by a tall thin box: no box vertex is inside the
  // plate's brush... but the plate's vertices are not inside the box either;
  // the box's vertical edges go through the plate's top polygon.
  const CollisionModel m = ModelMaker().addBox({{-100, -100, -1}, {100, 100, 1}}).build();
  const TraceModel pole = *TraceModel::box({{-2, -2, -50}, {2, 2, 50}});
  QueryWork work;
  const ContentsResult c = contentsTest(m, {&pole, {}, {0, 0, 0}, contents::kMaskSolid, {}}, work);
  EXPECT_NE(c.contents, 0u);
  EXPECT_EQ(c.trace.fraction, 0.0f);
  EXPECT_EQ(c.trace.contact.type, ContactType::Edge);
}

TEST(Translation, InternalEdgesAreNeverReported) {
  // Two floor slabs side by side; the top edges along the seam (x = 0) are
  // internal. A wedge whose lowest edge crosses the seam falls on it.
  ModelMaker maker;
  maker.addBox({{-100, -100, -16}, {0, 100, 0}}).addBox({{0, -100, -16}, {100, 100, 0}});
  ModelArrays& raw = maker.model();
  std::vector<std::int32_t> seam;
  for (std::size_t e = 1; e < raw.edges.size(); ++e) {
    const Vec3& a = raw.vertices[std::size_t(raw.edges[e].vertex[0])];
    const Vec3& b = raw.vertices[std::size_t(raw.edges[e].vertex[1])];
    if (a.x == 0 && b.x == 0 && a.z == 0 && b.z == 0) seam.push_back(std::int32_t(e));
  }
  ASSERT_EQ(seam.size(), 2u);
  for (std::int32_t e : seam) maker.markInternal(e);
  const CollisionModel m = maker.build();
  const Vec3 pts[4] = {{15, 0, 0}, {-5, 0, 4}, {5, -5, 20}, {5, 5, 20}};
  const TraceModel wedge = *TraceModel::convexHull(pts);
  QueryWork work;
  TranslationQuery q;
  q.trm = &wedge;
  q.start = {0, 0, 50};
  q.end = {0, 0, -50};
  const TraceResult r = translate(m, q, work);
  // The wedge's low vertex (15,0,0) lands on the floor.
  EXPECT_NEAR(r.endPos.z, 0.25f, 1e-3f);
  EXPECT_EQ(r.contact.type, ContactType::TrmVertex);
  for (std::int32_t e : seam) EXPECT_NE(std::abs(r.contact.modelFeature), e);
}

namespace {

// A floor that is one polygon with 100 edges: the diamond |x| + |y| <= 256
// at z = 0, facing up, with 25 vertices on each side, counter-clockwise seen
// from above from (0, -256); the lower-left side x + y = -256 comes last, as
// edges 76 to 100. More than 64 edges: the edge tests work on groups of 64.
// With `farTriangles` small triangles far below it (each its own edges), so
// that a model of more than detail::kBvhMinPolygons polygons gets the
// polygons' hierarchy, whose corners the tests read instead of edge uses.
CollisionModel hundredEdgeFloor(int farTriangles = 0) {
  ModelArrays m;
  m.name = "hundred";
  const Vec3 corners[4] = {{0, -256, 0}, {256, 0, 0}, {0, 256, 0}, {-256, 0, 0}};
  for (int side = 0; side < 4; ++side)
    for (int k = 0; k < 25; ++k)
      m.vertices.push_back(corners[side] + (corners[(side + 1) % 4] - corners[side]) * (Real(k) / 25));
  m.edges.emplace_back();  // the dummy edge 0
  CmPolygon floor;
  floor.plane = Plane{{0, 0, 1}, 0};
  floor.contents = contents::kSolid;
  floor.bounds = {{-256, -256, 0}, {256, 256, 0}};
  floor.numEdges = 100;
  for (std::int32_t i = 0; i < 100; ++i) {
    CmEdge e;
    e.vertex[0] = i;
    e.vertex[1] = (i + 1) % 100;
    e.numUsers = 1;
    m.edges.push_back(e);
    m.polygonEdges.push_back(i + 1);
  }
  m.polygons.push_back(floor);
  m.bounds = floor.bounds;
  for (int t = 0; t < farTriangles; ++t) {
    const auto first = std::int32_t(m.vertices.size());
    const Vec3 at{Real(-256 + 16 * (t % 32)), Real(-256 + 16 * (t / 32)), -1000};
    for (const Vec3& d : {Vec3{0, 0, 0}, Vec3{8, 0, 0}, Vec3{0, 8, 0}}) m.vertices.push_back(at + d);
    CmPolygon tri;
    tri.plane = Plane{{0, 0, 1}, -1000};
    tri.contents = contents::kSolid;
    tri.bounds = {at, at + Vec3{8, 8, 0}};
    tri.firstEdge = std::uint32_t(m.polygonEdges.size());
    tri.numEdges = 3;
    for (std::int32_t k = 0; k < 3; ++k) {
      CmEdge e;
      e.vertex[0] = first + k;
      e.vertex[1] = first + (k + 1) % 3;
      e.numUsers = 1;
      m.polygonEdges.push_back(std::int32_t(m.edges.size()));
      m.edges.push_back(e);
    }
    m.polygons.push_back(tri);
    m.bounds.addBounds(tri.bounds);
  }
  m.nodes.assign(1, CmNode{});
  for (std::size_t i = 0; i < m.polygons.size(); ++i) m.polygonRefs.push_back(std::int32_t(i));
  m.nodes[0].numPolygonRefs = std::uint32_t(m.polygons.size());
  m.contents = floor.contents;
  detail::computeEdgeNormals(m);
  return **CollisionModel::create(std::move(m));
}

TraceResult dropBox(const CollisionModel& m, Real x, Real y) {
  const TraceModel box = *TraceModel::box({{-16, -16, 0}, {16, 16, 32}});
  QueryWork work;
  TranslationQuery q;
  q.trm = &box;
  q.start = {x, y, 100};
  q.end = {x, y, -100};
  return translate(m, q, work);
}

void expectHundredEdgeFloorStops(const CollisionModel& m) {
  ASSERT_GT(m.polygons()[0].numEdges, 64u);
  // Over the middle and half over the lower-left side: the vertices inside
  // stop 0.25 above the floor.
  for (const Real c : {Real(0), Real(-128)}) {
    const TraceResult r = dropBox(m, c, c);
    EXPECT_NEAR(r.fraction, 99.75f / 200, 1e-6f) << "at " << c;
    EXPECT_EQ(r.contact.type, ContactType::TrmVertex) << "at " << c;
    EXPECT_EQ(r.contact.normal, Vec3(0, 0, 1)) << "at " << c;
  }
  // Inside the floor's bounds but beyond the lower-left side (the nearest
  // vertex at x + y = -304): every vertex is outside one of the last edges
  // only, so nothing is hit.
  EXPECT_EQ(dropBox(m, -168, -168).fraction, 1.0f);

  // Sliding flat into the left corner (-256, 0): the box's front face
  // (x = -384) meets it after 128 of 300 units, 0.25 short.
  const TraceModel slab = *TraceModel::box({{-16, -16, -8}, {16, 16, 8}});
  QueryWork work;
  TranslationQuery q;
  q.trm = &slab;
  q.start = {-400, 0, 0};
  q.end = {-100, 0, 0};
  const TraceResult r = translate(m, q, work);
  EXPECT_NEAR(r.fraction, 127.75f / 300, 1e-5f);
  expectVecNear(r.contact.normal, {-1, 0, 0}, 1e-5f);
  // The corner, vertex 75 (the polygon's 76th corner, past 64), reaches the
  // front face (the box's polygon facing +x; the contact's normal is its
  // reverse).
  EXPECT_EQ(r.contact.type, ContactType::ModelVertex);
  EXPECT_EQ(r.contact.modelFeature, 75);
  EXPECT_EQ(slab.polygons()[std::size_t(r.contact.trmFeature)].normal, Vec3(1, 0, 0));
}

}  // namespace

TEST(Translation, PolygonWithMoreThan64Edges) {
  // Without the model's derived lines (computed per polygon) and with them.
  for (const bool prepared : {false, true}) {
    SCOPED_TRACE(prepared ? "prepared" : "bare");
    const CollisionModel m =
        prepared ? hundredEdgeFloor() : detail::ModelAccess::withoutQueryData(hundredEdgeFloor());
    ASSERT_EQ(detail::queryDataOf(m) != nullptr, prepared);
    expectHundredEdgeFloorStops(m);
  }
}

TEST(Translation, PolygonWithMoreThan64EdgesInTheHierarchy) {
  // The same floor among 300 far triangles: the polygons' hierarchy, whose
  // corners (not edge uses) the tests read; the model vertices' corner loop
  // takes polygons of more than 63 edges edge by edge (its mask has a bit
  // a corner and one more).
  if constexpr (!detail::kCullBlocks) GTEST_SKIP() << "no polygons' hierarchy in this build (double)";
  const CollisionModel m = hundredEdgeFloor(300);
  const detail::QueryData* data = detail::queryDataOf(m);
  ASSERT_NE(data, nullptr);
  ASSERT_FALSE(data->bvh.empty()) << "301 polygons: more than kBvhMinPolygons, so a hierarchy";
  expectHundredEdgeFloorStops(m);
}
