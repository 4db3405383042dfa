// One regression test per documented bug of the original collision code
// (docs/fidelity.md names each test beside its bug; the reference data's
// README lists them under "Where the original is wrong"). Each test's name
// says what cmkit does instead; its comment says what the original did.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "cmkit/cm_file.h"
#include "cmkit/compile.h"
#include "cmkit/map.h"
#include "cmkit/query.h"
#include "model_fixtures.h"
#include "test_support.h"

namespace cmkit {
namespace {

using test::ModelMaker;

constexpr double kDeg = 180.0 / std::numbers::pi;

void expectVecNear(const Vec3& a, const Vec3& b, float eps) {
  EXPECT_NEAR(a.x, b.x, eps);
  EXPECT_NEAR(a.y, b.y, eps);
  EXPECT_NEAR(a.z, b.z, eps);
}

/// A point translation that does not move: the point position test.
TranslationQuery pointAt(const Vec3& p, std::uint32_t mask) {
  TranslationQuery q;
  q.start = p;
  q.end = p;
  q.contentMask = mask;
  return q;
}

// ---- point contents ---------------------------------------------------------

TEST(OriginalBug, PointContentsFindsBrushesAtInteriorNodes) {
  // The original looked only at the brushes of the leaf the point falls in.
  // A .cm model whose root splits at x = 5: the brush x 0..10 straddles the
  // split, so the reader keeps it at the root, and both leaves are empty.
  const std::string cm =
      "CM \"1.00\" 0\ncollisionModel \"split\" {\n  nodes { ( 0 5 ) ( -1 0 ) ( -1 0 ) }\n"
      "  brushes { 6 { ( 1 0 0 ) 10 ( -1 0 0 ) 0 ( 0 1 0 ) 10 ( 0 -1 0 ) 0 ( 0 0 1 ) 10 "
      "( 0 0 -1 ) 0 } ( 0 0 0 ) ( 10 10 10 ) 1 }\n}\n";
  auto file = parseCmText(cm, "split.cm", MaterialTable{});
  ASSERT_TRUE(file.ok()) << file.error().toString();
  const CollisionModel& m = *file->models.front();
  ASSERT_EQ(m.nodes().size(), 3u);
  ASSERT_EQ(m.brushesAt(m.nodes()[0]).size(), 1u) << "the brush is at the root";
  ASSERT_TRUE(m.brushesAt(m.nodes()[1]).empty());
  ASSERT_TRUE(m.brushesAt(m.nodes()[2]).empty());
  // Both sides of the split, and a point trace standing there.
  EXPECT_EQ(test::pointContentsAt(m, {3, 5, 5}), contents::kSolid);
  EXPECT_EQ(test::pointContentsAt(m, {7, 5, 5}), contents::kSolid);
  EXPECT_EQ(test::pointContentsAt(m, {7, 5, 15}), 0u);
  QueryWork work;
  EXPECT_EQ(translate(m, pointAt({7, 5, 5}, contents::kSolid), work).fraction, 0);
  EXPECT_EQ(translate(m, pointAt({7, 5, 15}, contents::kSolid), work).fraction, 1);
}

TEST(OriginalBug, PointContentsIsTheOrOfEveryBrushNotTheFirstFound) {
  // The original returned the contents of the first brush containing the
  // point: inside a clip brush overlapping a solid one, "not solid".
  const CollisionModel m = ModelMaker()
                               .addBox({{0, 0, 32}, {64, 64, 96}}, contents::kMonsterClip)
                               .addBox({{0, 0, 0}, {64, 64, 64}}, contents::kSolid | contents::kOpaque)
                               .build();
  EXPECT_EQ(test::pointContentsAt(m, {32, 32, 80}), contents::kMonsterClip);
  EXPECT_EQ(test::pointContentsAt(m, {32, 32, 16}), contents::kSolid | contents::kOpaque);
  EXPECT_EQ(test::pointContentsAt(m, {32, 32, 48}),
            contents::kMonsterClip | contents::kSolid | contents::kOpaque);
}

TEST(OriginalBug, PointPositionTestHonoursTheMask) {
  // The original's position test of a point ignored the content mask: a
  // point inside a clip-only brush was "stuck" for a solid-only mask.
  const CollisionModel m = ModelMaker().addBox({{0, 0, 0}, {64, 64, 64}}, contents::kPlayerClip).build();
  QueryWork work;
  EXPECT_EQ(translate(m, pointAt({32, 32, 32}, contents::kSolid), work).fraction, 1);
  EXPECT_EQ(translate(m, pointAt({32, 32, 32}, contents::kPlayerClip), work).fraction, 0);
  EXPECT_EQ(translate(m, pointAt({32, 32, 80}, contents::kPlayerClip), work).fraction, 1);
}

TEST(OriginalBug, TransformedPointContentsAppliesTheModelAxisTheRightWayRound) {
  // The original multiplied the world point by the model's axis instead of
  // its transpose (rotated models only). A water box at model x 20..30, y
  // 0..10; the model turned 90 degrees about z (model x along world y) and
  // moved by (100, 0, 0). Model point (25, 5, 5) is world
  // (100, 0, 0) + 25 (0, 1, 0) + 5 (-1, 0, 0) + 5 (0, 0, 1) = (95, 25, 5).
  // The wrong way round, world (105, -25, 5) would map to it instead.
  const CollisionModel m = ModelMaker().addBox({{20, 0, 0}, {30, 10, 10}}, contents::kWater).build();
  const Placement turned{{100, 0, 0}, Mat3{{0, 1, 0}, {-1, 0, 0}, {0, 0, 1}}};
  EXPECT_EQ(test::pointContentsAt(m, {95, 25, 5}, turned), contents::kWater);
  EXPECT_EQ(test::pointContentsAt(m, {105, -25, 5}, turned), 0u);
  EXPECT_EQ(test::pointContentsAt(m, {125, 5, 5}, turned), 0u);  // the unplaced box moved by the origin only
}

// ---- contacts ---------------------------------------------------------------

TEST(OriginalBug, PointContactsAreMovedToWorldSpace) {
  // The original returned a point's contacts in the model's frame. A floor
  // (top at model z = 0) turned upside down (model z along world -z) and
  // moved up by 100: its top face faces world -z at z = 100.
  const CollisionModel m = ModelMaker().addBox({{-50, -50, -16}, {50, 50, 0}}).build();
  ContactsQuery q;
  q.start = {10, 20, 90};
  q.dir = {0, 0, 1};
  q.depth = 20;
  q.placement = {{0, 0, 100}, Mat3{{1, 0, 0}, {0, -1, 0}, {0, 0, -1}}};
  QueryWork work;
  const ContactsResult r = contacts(m, q, work);
  ASSERT_EQ(r.status, QueryStatus::Ok);
  ASSERT_EQ(r.contacts.size(), 1u);
  const ContactInfo& c = r.contacts[0];
  EXPECT_EQ(c.type, ContactType::TrmVertex);
  expectVecNear(c.normal, {0, 0, -1}, 1e-6f);
  EXPECT_NEAR(c.dist, -100, 1e-4);
  // The point stops the clip epsilon (0.25) short of the face, at world z
  // 99.75 (in the model's frame it would be (10, -20, 0.25)).
  expectVecNear(c.point, {10, 20, 99.75f}, 1e-3f);
}

// ---- rotations --------------------------------------------------------------

TEST(OriginalBug, RotationHitDoesNotDependOnPolygonOrder) {
  // The original marked a model edge tested with the first polygon that
  // contained it even when that polygon's culls had skipped trace-model
  // edges, so which edge pairs were tested depended on polygon order, and a
  // rotation could pass through a face. A cluster of boxes, its polygon list
  // in several orders: every rotation gives the same bits.
  ModelMaker mk;
  mk.addBox({{0, 0, 0}, {40, 40, 40}})
      .addBox({{40, 10, 0}, {60, 30, 60}})
      .addBox({{-30, -30, 0}, {0, 80, 8}});
  mk.addConvex(*TraceModel::octahedron({{10, 50, 0}, {50, 90, 40}}));
  const CollisionModel base = mk.build();
  std::vector<TraceModel> trms = {*TraceModel::box({{-8, -8, -8}, {8, 8, 8}}), *TraceModel::bone(50, 10),
                                  *TraceModel::cylinder({{-6, -6, -12}, {6, 6, 12}}, 6)};
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> pos(-40, 100), ang(-200, 200), unit(-1, 1);
  QueryWork work;
  int hits = 0;
  for (int n = 0; n < 300; ++n) {
    RotationQuery q;
    q.trm = &trms[std::size_t(n) % trms.size()];
    q.start = {pos(rng), pos(rng), pos(rng) * 0.5f};
    Vec3 axis{unit(rng), unit(rng), unit(rng)};
    if (axis.normalize() == 0) continue;
    q.rotation = Rotation(q.start + Vec3{unit(rng), unit(rng), unit(rng)} * 20, axis, ang(rng));
    ModelArrays arrays = base.arrays();
    const TraceResult ref = rotate(base, q, work);
    hits += ref.fraction < 1;
    for (int order = 0; order < 3; ++order) {
      std::vector<std::int32_t>& refs = arrays.polygonRefs;
      if (order == 0) std::reverse(refs.begin(), refs.end());
      if (order == 1) std::rotate(refs.begin(), refs.begin() + 7, refs.end());
      if (order == 2) std::shuffle(refs.begin(), refs.end(), rng);
      const TraceResult r = rotate(**CollisionModel::create(arrays), q, work);
      ASSERT_EQ(r.fraction, ref.fraction) << "query " << n << " order " << order;
      ASSERT_EQ(r.endPos, ref.endPos);
    }
  }
  EXPECT_GT(hits, 30);
}

TEST(OriginalBug, LongRotationArcReachesLeavesItsChordMisses) {
  // The original walked a rotation's tree with one straight chord (its step
  // count rounds to 0), so a long arc skipped leaves. A tree split at
  // y = -50: the back leaf (y < -50) holds a pillar at (0, -100). A point at
  // (100, 0) turns 170 degrees clockwise about the z axis: its chord
  // (100, 0) -> (-98.5, -17.4) stays above y = -18, so the original's walk
  // (one chord, extents = 1 + the 64-unit-chord sagitta, a few units) never
  // enters the back leaf; the arc passes y = -100.
  ModelArrays arrays = ModelMaker().addBox({{-10, -110, -50}, {10, -90, 50}}).buildArrays();
  CmNode root;
  root.planeType = 1;
  root.planeDist = -50;
  root.children[0] = 1;
  root.children[1] = 2;
  CmNode front, back;
  front.parent = back.parent = 0;
  back.numPolygonRefs = std::uint32_t(arrays.polygons.size());
  back.numBrushRefs = std::uint32_t(arrays.brushes.size());
  arrays.nodes = {root, front, back};
  const CollisionModel m = **CollisionModel::create(std::move(arrays));
  QueryWork work;
  RotationQuery q;
  q.start = {100, 0, 0};
  q.rotation = Rotation({0, 0, 0}, {0, 0, 1}, 170);
  const TraceResult r = rotate(m, q, work);
  ASSERT_LT(r.fraction, 1.0f);
  // It meets the pillar's face x = 10 (r = 100: 100 cos a = 10.25).
  EXPECT_NEAR(r.fraction * 170, std::acos(10.25 / 100) * kDeg, 1e-3);
  expectVecNear(r.contact.normal, {1, 0, 0}, 1e-6f);
}

TEST(OriginalBug, RotationEdgeContactNormalOpposesTheMotion) {
  // The original took the sign of a rotation's edge-edge contact normal
  // from a test at the start of the rotation, which is unstable: on the
  // shared reference files its normal follows the motion of the contact
  // point in 80 of 1131 edge contacts past the start. cmkit orients it
  // against the contact point's motion along the arc (and so does every
  // other contact; tests/unit/test_query_rotation_normals.cpp).
  //
  // By hand: a block x -100..0, z -100..0 (its edge along y at x = 0,
  // z = 0, edge normal (1, 0, 1)/sqrt 2) and a wedge whose lowest edge runs
  // from (-10, 0, 10) to (10, 0, -10) relative to it, started at (0, 0, 20).
  // Turning clockwise about the x axis through (0, -300, 20), the edge's
  // point at x = 0 (radius 300) comes down to z = 0 first, at
  // asin(20 / 300) = 3.82 degrees, on the block's edge: an edge contact
  // whose plane holds both edges, normal (1, 0, 1)/sqrt 2 turned a little.
  const CollisionModel block = ModelMaker().addBox({{-100, -100, -100}, {0, 100, 0}}).build();
  const Vec3 wedgePoints[4] = {{-10, 0, 10}, {10, 0, -10}, {-3, -4, 10}, {-3, 4, 10}};
  const TraceModel wedge = *TraceModel::convexHull(wedgePoints);
  QueryWork work;
  RotationQuery q;
  q.trm = &wedge;
  q.start = {0, 0, 20};
  q.rotation = Rotation({0, -300, 20}, {1, 0, 0}, 10);
  const TraceResult r = rotate(block, q, work);
  ASSERT_LT(r.fraction, 1);
  EXPECT_EQ(r.contact.type, ContactType::Edge);
  EXPECT_NEAR(r.fraction * 10, std::asin(20.0 / 300) * kDeg, 0.1);
  EXPECT_GT(r.contact.normal.dot(Vec3{1, 0, 1}) / std::sqrt(Real(2)), 0.99f)
      << r.contact.normal.x << " " << r.contact.normal.y << " " << r.contact.normal.z;
  // Many rotations of a tilted box about the block's corners: every edge
  // contact's normal opposes the motion of its point along the arc.
  const TraceModel box = *TraceModel::box({{-6, -6, -6}, {6, 6, 6}});
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> unit(-1, 1);
  int edgeContacts = 0;
  for (int n = 0; n < 2000; ++n) {
    RotationQuery t;
    t.trm = &box;
    Vec3 tilt{unit(rng), unit(rng), unit(rng)};
    if (tilt.normalize() == 0) continue;
    t.trmAxis = Rotation({}, tilt, unit(rng) * 90).matrix();
    t.start = {unit(rng) * 20 + 12, unit(rng) * 90, unit(rng) * 20 + 12};
    Vec3 axis{unit(rng), unit(rng), unit(rng)};
    if (axis.normalize() == 0) continue;
    t.rotation = Rotation(t.start + Vec3{unit(rng), unit(rng), unit(rng)} * 30, axis, unit(rng) * 180);
    const TraceResult h = rotate(block, t, work);
    if (h.fraction == 1 || h.fraction == 0 || h.contact.type != ContactType::Edge) continue;
    ++edgeContacts;
    const Vec3 motion = (h.contact.point - t.rotation.origin).cross(t.rotation.axis) *
                        (t.rotation.angle < 0 ? Real(-1) : Real(1));
    ASSERT_LE(h.contact.normal.dot(motion), tol::kRotationContactTangentCosine * motion.length())
        << "rotation " << n;
  }
  EXPECT_GT(edgeContacts, 20);
}

// ---- translations -----------------------------------------------------------

TEST(OriginalBug, TranslationsLongerThan4096UnitsMove) {
  // The original refused trace-model moves over 4096 units ("huge
  // translation": fraction 0, no move).
  const CollisionModel m = ModelMaker().addBox({{-256, -256, -16}, {256, 256, 0}}).build();
  const TraceModel box = *TraceModel::box({{-16, -16, 0}, {16, 16, 72}});
  QueryWork work;
  TranslationQuery q;
  q.trm = &box;
  q.start = {0, 0, 10000};
  q.end = {0, 0, -10000};
  const TraceResult r = translate(m, q, work);
  // The box's bottom stops 0.25 above the floor: 9999.75 of 20000 units.
  EXPECT_NEAR(r.endPos.z, 0.25f, 2e-3f);
  EXPECT_NEAR(r.fraction, 9999.75 / 20000, 1e-6);
}

TEST(OriginalBug, NonFiniteInputIsRefusedNotComputed) {
  // The original computed on with NaN input: a NaN origin made a box fall
  // through the floor. cmkit refuses: fraction 0, the end at the start.
  const CollisionModel m = ModelMaker().addBox({{-256, -256, -16}, {256, 256, 0}}).build();
  const TraceModel box = *TraceModel::box({{-16, -16, 0}, {16, 16, 72}});
  QueryWork work;
  TranslationQuery q;
  q.trm = &box;
  q.start = {0, 0, 10};
  q.end = {0, 0, -100};
  q.placement.origin = {std::nanf(""), 0, 0};
  const TraceResult r = translate(m, q, work);
  EXPECT_EQ(r.status, QueryStatus::NonFinite);
  EXPECT_EQ(r.fraction, 0);
  EXPECT_EQ(r.endPos, q.start);
}

// ---- .cm files --------------------------------------------------------------

TEST(OriginalBug, CmBrushesHaveNoMaterialBecauseTheFormatStoresNone) {
  // The reference data lists the original's .cm loader as wrong for giving
  // brushes no material; but a .cm brush has planes, bounds and contents and
  // no material, so there is nothing to read it from: cmkit keeps -1 (and
  // says so in docs/fidelity.md), while its polygons keep theirs.
  const std::string map =
      "Version 2\n{\n\"classname\" \"worldspawn\"\n{\n brushDef3\n {\n"
      "  ( 1 0 0 -64 ) ( ( 0.0078125 0 0 ) ( 0 0.0078125 0 ) ) \"textures/base/a\" 0 0 0\n"
      "  ( -1 0 0 0 ) ( ( 0.0078125 0 0 ) ( 0 0.0078125 0 ) ) \"textures/base/a\" 0 0 0\n"
      "  ( 0 1 0 -64 ) ( ( 0.0078125 0 0 ) ( 0 0.0078125 0 ) ) \"textures/base/a\" 0 0 0\n"
      "  ( 0 -1 0 0 ) ( ( 0.0078125 0 0 ) ( 0 0.0078125 0 ) ) \"textures/base/a\" 0 0 0\n"
      "  ( 0 0 1 -64 ) ( ( 0.0078125 0 0 ) ( 0 0.0078125 0 ) ) \"textures/base/a\" 0 0 0\n"
      "  ( 0 0 -1 0 ) ( ( 0.0078125 0 0 ) ( 0 0.0078125 0 ) ) \"textures/base/a\" 0 0 0\n"
      " }\n}\n}\n";
  auto parsed = parseMapText(map, "one.map");
  ASSERT_TRUE(parsed.ok()) << parsed.error().toString();
  auto built = buildCollisionModels(*parsed, MaterialTable{});
  ASSERT_TRUE(built.ok() && built->models.size() == 1u);
  const CollisionModel& compiled = *built->models.front();
  ASSERT_EQ(compiled.brushes().size(), 1u);
  ASSERT_GE(compiled.brushes()[0].material, 0) << "a compiled brush has its material";
  EXPECT_EQ(compiled.materials()[std::size_t(compiled.brushes()[0].material)], "textures/base/a");
  auto read = parseCmText(writeCmText(built->models, 0), "one.cm", MaterialTable{});
  ASSERT_TRUE(read.ok()) << read.error().toString();
  const CollisionModel& loaded = *read->models.front();
  ASSERT_EQ(loaded.brushes().size(), 1u);
  EXPECT_EQ(loaded.brushes()[0].material, -1);
  ASSERT_FALSE(loaded.polygons().empty());
  for (const CmPolygon& p : loaded.polygons())
    EXPECT_EQ(loaded.materials()[std::size_t(p.material)], "textures/base/a");
}

}  // namespace
}  // namespace cmkit
