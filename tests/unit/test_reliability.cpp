// Reliability (docs/reliability.md): the robust-edges compile option, the
// out-of-plane edge that lets a corner through (the original's behaviour,
// docs/fidelity.md), points that honour the mask and pointContents as the OR of the brushes
// containing the point.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>

#include "cmkit/compile.h"
#include "cmkit/map.h"
#include "cmkit/query.h"
#include "cmkit/tools/query_format.h"
#include "test_support.h"

using namespace cmkit;

namespace {

/// The lt4 case in small: a 16x16 pillar inside a wall block, sharing the
/// block's corner at x = 0, y = 0 (both brushes' -x and -y faces coplanar).
std::string pillarInWallMap() {
  return "Version 2\n{\n\"classname\" \"worldspawn\"\n" +
         test::axialBrush({{0, 0, 0}, {240, 56, 64}}, "textures/base_wall/lfwall27d") +
         test::axialBrush({{0, 0, 8}, {16, 16, 64}}, "textures/base_wall/lfwall27d") + "}\n";
}

/// Edges of the model lying on the vertical line x = 0, y = 0.
std::vector<const CmEdge*> cornerEdges(const CollisionModel& m) {
  std::vector<const CmEdge*> out;
  for (std::size_t e = 1; e < m.edges().size(); ++e) {
    const Vec3& a = m.vertices()[std::size_t(m.edges()[e].vertex[0])];
    const Vec3& b = m.vertices()[std::size_t(m.edges()[e].vertex[1])];
    if (a.x == 0 && a.y == 0 && b.x == 0 && b.y == 0) out.push_back(&m.edges()[e]);
  }
  return out;
}

std::string lt4Path() { return std::string(CMKIT_SOURCE_DIR) + "/data/maps/lt4/lt4.map"; }

std::vector<ModelPtr> buildLt4(bool robustEdges) {
  return test::buildModelsFromMap(loadMapFile(lt4Path()), robustEdges);
}

TraceModel trm(const char* spec) { return TraceModel::parse(spec).value(); }

std::uint32_t contentsAt(const CollisionModel& m, const TraceModel& t, const Vec3& p, std::uint32_t mask) {
  QueryWork work;
  return contentsTest(m, {&t, Mat3::identity(), p, mask, {}}, work).contents;
}

/// A translation through lt4's world model built with or without robust
/// edges: the result and what the trace model overlaps at its end.
struct Lt4Sweep {
  std::vector<ModelPtr> models;
  TraceResult result;
  std::uint32_t atEnd = 0;
};
Lt4Sweep sweepLt4(bool robustEdges, const TraceModel& t, const Vec3& start, const Vec3& end,
                  std::uint32_t mask) {
  Lt4Sweep s;
  s.models = buildLt4(robustEdges);
  if (s.models.empty()) return s;
  QueryWork work;
  s.result = translate(*s.models[0], {&t, Mat3::identity(), start, end, mask, {}}, work);
  s.atEnd = contentsAt(*s.models[0], t, s.result.endPos, mask);
  return s;
}

}  // namespace

// ---- robust edges ----------------------------------------------------------

TEST(RobustEdges, OverlappingCoplanarFacesNoLongerHideTheCorner) {
  const auto original = test::buildModelsFromText(pillarInWallMap(), false);
  const auto robust = test::buildModelsFromText(pillarInWallMap(), true);
  ASSERT_EQ(original.size(), 1u);
  ASSERT_EQ(robust.size(), 1u);
  // The original's rule: every copy of the corner edge that a front face
  // (-x or -y) uses is internal, hidden by the coplanar face of the other brush.
  const auto before = cornerEdges(*original[0]);
  const auto after = cornerEdges(*robust[0]);
  ASSERT_FALSE(before.empty());
  ASSERT_FALSE(after.empty());
  int visibleBefore = 0, visibleAfter = 0;
  for (const CmEdge* e : before) visibleBefore += !e->internal;
  for (const CmEdge* e : after) visibleAfter += !e->internal;
  EXPECT_GT(visibleAfter, visibleBefore);
  // Same brushes either way. Robust edges also cut the polygons at
  // T-junctions (the pillar's face ends on the block's coplanar face:
  // RobustEdgesMisses.PointTraceAcrossTJunction*), so there are more
  // polygons, and internal edges (the cuts lie in their polygons' planes).
  EXPECT_GT(robust[0]->polygons().size(), original[0]->polygons().size());
  EXPECT_EQ(robust[0]->brushes().size(), original[0]->brushes().size());
}

TEST(RobustEdges, Lt4ConeStopsAtTheCornerItPassedThrough) {
  // The case: a cone whose base edge passes through the vertical
  // corner (2432, -1720) of a pillar standing in a wall block.
  const TraceModel cone = trm("cone:6:-12,-12,0,12,12,40");
  const Vec3 start{2415.85986f, -1718.55566f, -531.321777f};
  const Vec3 end{2842.74463f, -1979.53711f, -202.30777f};
  for (const bool robust : {false, true}) {
    SCOPED_TRACE(robust ? "robust edges" : "the original's edges");
    const Lt4Sweep sweep = sweepLt4(robust, cone, start, end, 1);
    ASSERT_FALSE(sweep.models.empty());
    const TraceResult& r = sweep.result;
    const std::uint32_t atEnd = sweep.atEnd;
    ASSERT_EQ(r.status, QueryStatus::Ok);
    if (robust) {
      EXPECT_EQ(atEnd, 0u) << "fraction " << r.fraction;
      EXPECT_EQ(r.contact.type, ContactType::Edge);
      EXPECT_LT(r.fraction, 0.02f);
    } else {
      EXPECT_EQ(atEnd, 3u) << "the original's rule hides the corner: the cone ends in the brush";
      EXPECT_NEAR(r.fraction, 0.023168165f, 1e-6f);
    }
  }
}

TEST(RobustEdges, Lt4SolidFaceSharingEdgesWithClipKeepsThem) {
  CMKIT_FLOAT_BUILD_ONLY();
  // lt4 polygon 2859: a solid post face 8 units wide (y = -830) whose four
  // edges it shares with the faces of a monster-clip brush. The clip faces
  // mark them internal among themselves, which hides them from the solid
  // face too; a dodecahedron's edge then goes 3.5 units through the post.
  const TraceModel dodeca = trm("dodecahedron:-16,-16,-16,16,16,16");
  const Vec3 start{1543.2588f, -793.9263f, -350.1645f};
  const Vec3 end{1513.0927f, -921.3557f, -421.1849f};
  for (const bool robust : {false, true}) {
    SCOPED_TRACE(robust ? "robust edges" : "the original's edges");
    const Lt4Sweep sweep = sweepLt4(robust, dodeca, start, end, 265);
    ASSERT_FALSE(sweep.models.empty());
    const CollisionModel& m = *sweep.models[0];
    // Polygon 2859 of the original's build; found by its place (robust
    // edges cut polygons at T-junctions, which renumbers them).
    const CmPolygon* post = nullptr;
    for (const CmPolygon& p : m.polygons()) {
      if (p.plane.normal == Vec3{0, 1, 0} && p.plane.dist == -830 && p.bounds.min == Vec3{1536, -830, -424} &&
          p.bounds.max == Vec3{1544, -830, -200})
        post = &p;
    }
    ASSERT_NE(post, nullptr);
    if (!robust) {
      EXPECT_EQ(post, &m.polygons()[2859]);
    }
    int internal = 0;
    for (const std::int32_t e : m.edgesOf(*post)) internal += m.edges()[std::size_t(std::abs(e))].internal;
    const TraceResult& r = sweep.result;
    const std::uint32_t atEnd = sweep.atEnd;
    if (robust) {
      // The three edges shared with clip faces are kept; the bottom edge
      // (this polygon's alone) lies on a solid plank face and stays internal.
      EXPECT_EQ(internal, 1);
      EXPECT_EQ(atEnd, 0u) << "fraction " << r.fraction;
    } else {
      EXPECT_EQ(internal, 4);
      EXPECT_NE(atEnd, 0u) << "the original's edges: the end is inside the post";
    }
  }
}

// ---- the clip-epsilon case (the original's behaviour) ------------------------

TEST(OutOfPlaneEdge, LetsABoxCornerThroughAsTheOriginalDoes) {
  CMKIT_FLOAT_BUILD_ONLY();
  // docs/fidelity.md: polygon 10222 of lt4 (the diagonal face x + y = -575)
  // has a 16-unit edge whose upper vertex (577.03125, -1152, -328) lies
  // 0.022 units behind the polygon's plane. The edge's line, extended, runs
  // 0.67 units in front of the face at the box's height, and a trace-model
  // vertex whose path passes it on the outside is "outside the polygon"
  // for the Plucker test, so the corner goes through. Pinned here as the
  // original's behaviour (lt4's .cm is byte-identical to the original's).
  const auto models = buildLt4(false);
  ASSERT_FALSE(models.empty());
  const CollisionModel& m = *models[0];
  ASSERT_GT(m.polygons().size(), 10222u);
  const CmPolygon& poly = m.polygons()[10222];
  EXPECT_NEAR(poly.plane.normal.x, -0.70710677f, 1e-6f);
  Real worst = 0;
  for (const std::int32_t e : m.edgesOf(poly))
    worst = std::min(worst, poly.plane.distance(m.vertices()[std::size_t(m.edgeStart(e))]));
  EXPECT_NEAR(worst, -0.0221f, 0.001f);

  const TraceModel box = trm("box:-16,-16,0,16,16,72");
  const Vec3 start{560.897461f, -1168.25f, -903.75f};
  QueryWork work;
  EXPECT_EQ(contentsAt(m, box, start, 265), 0u);
  const TraceResult oblique =
      translate(m, {&box, Mat3::identity(), start, {565.717773f, -1170.53235f, -903.75f}, 265, {}}, work);
  EXPECT_EQ(oblique.fraction, 1);
  EXPECT_NE(contentsAt(m, box, oblique.endPos, 265), 0u) << "the end is 1.5 units inside the brush";
  const TraceResult straight =
      translate(m, {&box, Mat3::identity(), start, {565.717773f, -1168.25f, -903.75f}, 265, {}}, work);
  EXPECT_EQ(straight.fraction, 0);
  EXPECT_EQ(straight.contact.modelFeature, 10222);
}

// The same sweep in the double build: the face's edges are computed in
// double, the corner does not get through, and the box stops outside.
TEST(OutOfPlaneEdge, TheDoubleBuildStopsTheCorner) {
  if constexpr (!kDoublePrecision) {
    GTEST_SKIP() << "double build (CMKIT_DOUBLE) only";
  }
  const auto models = buildLt4(false);
  ASSERT_FALSE(models.empty());
  const CollisionModel& m = *models[0];
  const TraceModel box = trm("box:-16,-16,0,16,16,72");
  const Vec3 start{560.897461f, -1168.25f, -903.75f};
  QueryWork work;
  ASSERT_EQ(contentsAt(m, box, start, 265), 0u);
  const TraceResult oblique =
      translate(m, {&box, Mat3::identity(), start, {565.717773f, -1170.53235f, -903.75f}, 265, {}}, work);
  EXPECT_LT(oblique.fraction, 1);
  EXPECT_EQ(contentsAt(m, box, oblique.endPos, 265), 0u) << "the end must not be inside the brush";
}

// ---- large worlds ------------------------------------------------------------

// lt4 built at the origin and moved by (40000, 40000, 0): the same random
// box translations (moved alike) in both. The double build answers alike to
// 1e-6 of the move; the float build drifts (docs/reliability.md, "Large
// worlds": float's spacing is 1/256 of a unit out there), so there the test
// only checks that the moved world answers at all.
TEST(LargeWorlds, SweepsFarFromTheOriginAnswerAsAtTheOrigin) {
  auto map = loadMapFile(lt4Path());
  ASSERT_TRUE(map.ok());
  const Vec3 offset{40000, 40000, 0};
  MapFile moved = *map;
  moveWorldGeometry(moved, offset);
  auto here = buildCollisionModels(*map, MaterialTable{}, {});
  auto far = buildCollisionModels(moved, MaterialTable{}, {});
  ASSERT_TRUE(here.ok() && far.ok());
  const CollisionModel& a = *here->models.front();
  const CollisionModel& b = *far->models.front();
  EXPECT_EQ(b.bounds().min.x, a.bounds().min.x + offset.x);
  if constexpr (kDoublePrecision) {  // (in float, merging rounds differently: a few polygons fewer)
    ASSERT_EQ(a.polygons().size(), b.polygons().size());
  }
  const TraceModel box = trm("box:-16,-16,0,16,16,72");
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0, 1);
  const auto inside = [&](const Bounds& w) {
    return Vec3{w.min.x + (w.max.x - w.min.x) * u(rng), w.min.y + (w.max.y - w.min.y) * u(rng),
                w.min.z + (w.max.z - w.min.z) * u(rng)};
  };
  QueryWork work;
  int hits = 0, farther = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 start = inside(a.bounds()), end = inside(a.bounds());
    const TraceResult r0 = translate(a, {&box, Mat3::identity(), start, end, 265, {}}, work);
    const TraceResult r1 =
        translate(b, {&box, Mat3::identity(), start + offset, end + offset, 265, {}}, work);
    ASSERT_TRUE(std::isfinite(r1.fraction));
    hits += r0.fraction < 1;
    const Real travelled = (r1.endPos - offset - r0.endPos).length();
    farther += travelled > Real(0.01);
    if constexpr (kDoublePrecision) {
      EXPECT_NEAR(r1.fraction, r0.fraction, 1e-6) << "sweep " << i;
      EXPECT_LT(travelled, 1e-3) << "sweep " << i;
    }
  }
  EXPECT_GT(hits, 100);  // the sweeps hit walls, so the comparison means something
  std::printf("far from the origin: %d of 2000 box sweeps end more than 0.01 units apart (%s build)\n",
              farther, kDoublePrecision ? "double" : "float");
}

TEST(LargeWorlds, VersionNamesThePrecision) {
  int rc = -1;
  const std::string out = test::runCapture(std::string(CMKIT_CLI_PATH) + " --version", rc);
  EXPECT_EQ(rc, 0) << out;
  EXPECT_NE(out.find(kDoublePrecision ? "(double precision, CMKIT_DOUBLE)" : "(float precision)"),
            std::string::npos)
      << out;
}

// ---- points honour the mask; pointContents is the OR ------------------------

TEST(PointContents, IsTheOrOfEveryBrushAndPointsHonourTheMask) {
  // A solid block with a clip brush overlapping its upper half.
  const auto models =
      test::buildModelsFromText("Version 2\n{\n\"classname\" \"worldspawn\"\n" +
                                test::axialBrush({{0, 0, 0}, {64, 64, 64}}, "textures/base_wall/lfwall27d") +
                                test::axialBrush({{0, 0, 32}, {64, 64, 96}}, "textures/common/clip") + "}\n");
  ASSERT_EQ(models.size(), 1u);
  const CollisionModel& m = *models[0];
  const std::uint32_t clip = test::pointContentsAt(m, {32, 32, 80});
  ASSERT_NE(clip, 0u);
  EXPECT_EQ(clip & contents::kSolid, 0u);
  // In both brushes: both brushes' contents.
  const std::uint32_t solid = test::pointContentsAt(m, {32, 32, 16});
  EXPECT_EQ(solid, contents::kSolid | contents::kOpaque);
  EXPECT_EQ(test::pointContentsAt(m, {32, 32, 48}), clip | solid);
  // A point position test reports only what matches the mask, like a box.
  const TraceModel tiny = trm("box:-1,-1,-1,1,1,1");
  QueryWork work;
  for (const std::uint32_t mask : {contents::kSolid, contents::kPlayerClip, contents::kMaskAll}) {
    SCOPED_TRACE(mask);
    const ContentsResult p = contentsTest(m, {nullptr, Mat3::identity(), {32, 32, 80}, mask, {}}, work);
    const ContentsResult b = contentsTest(m, {&tiny, Mat3::identity(), {32, 32, 80}, mask, {}}, work);
    EXPECT_EQ(p.contents != 0, b.contents != 0);
    EXPECT_EQ(p.contents, (clip & mask) ? clip : 0u);
    const TraceResult t =
        translate(m, {nullptr, Mat3::identity(), {32, 32, 80}, {32, 32, 80}, mask, {}}, work);
    EXPECT_EQ(t.fraction, (clip & mask) ? 0 : 1);
  }
}

TEST(PointContents, Lt4PointInsideSolidReportsSolid) {
  // The point: the original returns 16 (monsterclip, the first brush
  // found) although the point is 21.8 units inside a solid brush.
  const auto models = buildLt4(false);
  ASSERT_FALSE(models.empty());
  const std::uint32_t c = test::pointContentsAt(*models[0], {2373.79028f, -987.413635f, -463.604645f});
  EXPECT_NE(c & contents::kSolid, 0u);
  EXPECT_NE(c & contents::kMonsterClip, 0u);
}

// ---- brush size cap ----------------------------------------------------------

TEST(BrushSides, MoreThanTheCapIsAClearError) {
  // Building a brush clips every side by every other (sides^2): 20 000 sides
  // took 53 s with no progress. Above kMaxBrushSides the build refuses at once.
  std::string sides;
  const std::size_t n = kMaxBrushSides + 1;
  for (std::size_t i = 0; i < n; ++i) {
    const double z = 1 - 2 * (double(i) + 0.5) / double(n), r = std::sqrt(1 - z * z);
    const double t = 2.399963229728653 * double(i);  // golden angle: normals spread over the sphere
    sides += "  ( " + std::to_string(r * std::cos(t)) + " " + std::to_string(r * std::sin(t)) + " " +
             std::to_string(z) +
             " -256 ) ( ( 0.0078125 0 0 ) ( 0 0.0078125 0 ) ) \"textures/base_wall/lfwall27d\" 0 0 0\n";
  }
  const std::string text =
      "Version 2\n{\n\"classname\" \"worldspawn\"\n{\n brushDef3\n {\n" + sides + " }\n}\n}\n";
  auto map = parseMapText(text, "big.map");
  ASSERT_TRUE(map.ok());
  const auto start = std::chrono::steady_clock::now();
  auto models = buildCollisionModels(*map, MaterialTable{});
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_FALSE(models.ok());
  EXPECT_EQ(models.error().file, "big.map");
  EXPECT_EQ(models.error().line, 4);
  EXPECT_NE(models.error().message.find("has 4097 sides; at most 4096 are supported"), std::string::npos)
      << models.error().message;
  EXPECT_LT(seconds, 1.0);
  const Result<EntityModelReport> entity =
      writeCollisionModelForMapEntity(*map, 0, "/nonexistent-dir/x.cm", MaterialTable{});
  ASSERT_FALSE(entity.ok());
  EXPECT_NE(entity.error().message.find("4097 sides"), std::string::npos) << entity.error().message;
}
