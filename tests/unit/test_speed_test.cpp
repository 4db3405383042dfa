// The speed test (include/cmkit/tools/speed_test.h): same results at any
// thread count, hits on a real map, hits and fractions computed by hand on a
// floor; `cmkit bench` prints its statistics lines.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

#include "cmkit/compile.h"
#include "cmkit/map.h"
#include "cmkit/tools/speed_test.h"
#include "debug/speed_test.h"  // planSpeedTest: the queries of a run
#include "model_fixtures.h"
#include "test_support.h"

namespace cmkit {
namespace {

/// Queries per kind in the tests (small: the tests must stay fast).
constexpr int kTestTimes = 300;

/// The world model of the feature test map and the speed test's box, and
/// options with kTestTimes queries from the map's centre.
class SpeedTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto map = loadMapFile((test::testDataDir() / "maps" / "features.map").string());
    ASSERT_TRUE(map.ok());
    auto models = buildCollisionModels(*map, MaterialTable{});
    ASSERT_TRUE(models.ok() && !models->models.empty());
    world = models->models.front();
    auto box = TraceModel::parse("box:-16,-16,0,16,16,64");
    ASSERT_TRUE(box.ok());
    trm = *box;
    options.times = kTestTimes;
    options.origin = (world->bounds().min + world->bounds().max) * Real(0.5);
  }
  SpeedTestReport run(const SpeedTestOptions& o) const { return runSpeedTest(*world, trm, o); }
  /// The same options on 1 and on 2 threads.
  std::pair<SpeedTestReport, SpeedTestReport> runOnOneAndTwoThreads(SpeedTestOptions o) const {
    o.threads = 1;
    SpeedTestReport one = run(o);
    o.threads = 2;
    return {std::move(one), run(o)};
  }

  ModelPtr world;
  TraceModel trm;
  SpeedTestOptions options;
};

TEST_F(SpeedTest, SameResultsOnOneAndTwoThreads) {
  for (bool walk : {false, true}) {
    SpeedTestOptions o = options;
    o.walk = walk;
    const auto [one, two] = runOnOneAndTwoThreads(o);
    SCOPED_TRACE(walk ? "walk" : "plain");
    EXPECT_EQ(one.translation.count, kTestTimes);
    EXPECT_EQ(one.rotation.count, kTestTimes);
    EXPECT_GT(one.translation.hits, 0);
    EXPECT_GT(one.rotation.hits, 0);
    EXPECT_EQ(one.translation.hash, two.translation.hash);
    EXPECT_EQ(one.rotation.hash, two.rotation.hash);
    EXPECT_EQ(one.translation.hits, two.translation.hits);
    EXPECT_EQ(one.rotation.hits, two.rotation.hits);
    EXPECT_LE(one.translation.minUs, one.translation.avgUs);
    EXPECT_LE(one.translation.avgUs, one.translation.maxUs);
  }
}

TEST_F(SpeedTest, RayCastsSameOnOneAndTwoThreads) {
  for (bool walk : {false, true}) {
    SpeedTestOptions o = options;
    o.walk = walk;
    o.rays = true;
    o.rotations = false;
    // Above the map (its centre is inside a brush, from where every ray
    // leaves through back faces): the rays going down hit its top.
    o.origin = {0, 0, world->bounds().max.z + 40};
    o.length = 256;
    const auto [one, two] = runOnOneAndTwoThreads(o);
    SCOPED_TRACE(walk ? "walk" : "plain");
    EXPECT_EQ(one.rays.count, kTestTimes);
    EXPECT_GT(one.rayIndex.nodes, 0u);
    EXPECT_GT(one.rayIndex.polygons, 0u);
    EXPECT_LE(one.rayIndex.polygons, world->polygons().size());
    EXPECT_GT(one.rays.hits, walk ? 0 : kTestTimes / 10);  // a walk wanders off into the open
    EXPECT_LT(one.rays.hits, kTestTimes);
    EXPECT_EQ(one.rays.hash, two.rays.hash);
    EXPECT_EQ(one.rays.hits, two.rays.hits);
  }
}

TEST_F(SpeedTest, SeedChangesTheQueries) {
  SpeedTestOptions o = options;
  o.rotations = false;
  const auto a = run(o);
  o.seed = 1;
  const auto b = run(o);
  EXPECT_NE(a.translation.hash, b.translation.hash);
  EXPECT_EQ(a.rotation.count, 0);
  EXPECT_EQ(a.rays.count, 0);  // not asked for
}

TEST_F(SpeedTest, RandomManySharesOneEndPoint) {
  // Every query is the same one, so all hit or none does: as that one
  // query, run here on its own.
  SpeedTestOptions o = options;
  o.randomMany = true;
  const detail::SpeedTestPlan plan = detail::planSpeedTest(o);
  ASSERT_EQ(plan.moves.size(), std::size_t(kTestTimes));
  for (std::size_t i = 1; i < plan.moves.size(); ++i) {
    ASSERT_EQ(plan.moves[i], plan.moves[0]);
    ASSERT_EQ(plan.turns[i].axis, plan.turns[0].axis);
    ASSERT_EQ(plan.turns[i].originOffset, plan.turns[0].originOffset);
  }
  QueryWork work;
  TranslationQuery t;
  t.trm = &trm;
  t.start = o.origin;
  t.end = o.origin + plan.moves[0];
  t.contentMask = o.contentMask;
  const TraceResult move = translate(*world, t, work);
  RotationQuery q;
  q.trm = &trm;
  q.start = o.origin;
  q.rotation = Rotation(o.origin + plan.turns[0].originOffset, plan.turns[0].axis, o.angle);
  q.contentMask = o.contentMask;
  const TraceResult turn = rotate(*world, q, work);
  ASSERT_LT(move.fraction, 1) << "features.map: the shared move from its centre meets a wall";
  const auto r = run(o);
  EXPECT_EQ(r.translation.count, kTestTimes);
  EXPECT_EQ(r.translation.hits, kTestTimes);
  EXPECT_EQ(r.rotation.count, kTestTimes);
  EXPECT_EQ(r.rotation.hits, turn.fraction < 1 ? kTestTimes : 0);
}

/// A floor slab (top at z = 0) under a box standing 8 units above it: which
/// of the speed test's moves hit is a matter of their z alone.
TEST(SpeedTestOnAFloor, HitsAndFractionsAreTheHandComputedOnes) {
  const CollisionModel floor = test::ModelMaker().addBox({{-4096, -4096, -64}, {4096, 4096, 0}}).build();
  const TraceModel box = *TraceModel::box({{-16, -16, 0}, {16, 16, 64}});
  SpeedTestOptions o;
  o.times = kTestTimes;
  o.length = 256;
  o.radius = 64;
  o.origin = {0, 0, 8};
  const detail::SpeedTestPlan plan = detail::planSpeedTest(o);
  ASSERT_EQ(plan.moves.size(), std::size_t(kTestTimes));

  // Translations: a move hits when it takes the box's bottom (z = 8) below
  // the floor's top; it then stops 0.25 above it, at fraction 7.75 / -z.
  int expectedHits = 0;
  QueryWork work;
  std::uint64_t hash = kFnvOffsetBasis;
  auto mix = [&hash](Real v) { hash = fnv1a(hash, &v, sizeof v); };
  for (const Vec3& move : plan.moves) {
    ASSERT_FALSE(std::fabs(move.z + 8) < 0.5f) << "a move ending on the floor: its hit is not clear-cut";
    const bool hit = move.z < -8;
    expectedHits += hit;
    TranslationQuery q;
    q.trm = &box;
    q.start = o.origin;
    q.end = o.origin + move;
    q.contentMask = o.contentMask;
    const TraceResult r = translate(floor, q, work);
    if (hit) {
      EXPECT_NEAR(r.fraction, 7.75 / -move.z, 1e-5) << move.z;
      EXPECT_NEAR(r.endPos.z, 0.25f, 1e-3f);
    } else {
      EXPECT_EQ(r.fraction, 1) << move.z;
    }
    // The report's hash: fraction, end position, end axis, contact normal.
    mix(r.fraction);
    for (int k = 0; k < 3; ++k) mix(r.endPos[k]);
    for (int row = 0; row < 3; ++row)
      for (int k = 0; k < 3; ++k) mix(r.endAxis[row][k]);
    for (int k = 0; k < 3; ++k) mix(r.contact.normal[k]);
  }
  ASSERT_GT(expectedHits, kTestTimes / 4);
  ASSERT_LT(expectedHits, kTestTimes * 3 / 4);

  // Rotations: a rotation hits when a corner of the box goes below the
  // floor's top on its arc (sampled every 0.03 degrees; the arcs are at most
  // ~200 units long, so a sample lies within 0.1 units of the lowest point).
  // Rotations whose lowest corner comes within half a unit of the floor
  // could go either way and are not counted as sure.
  int sureHits = 0, sureMisses = 0;
  for (const detail::SpeedTestTurn& turn : plan.turns) {
    Real lowest = 1e9f;
    constexpr int kSteps = 2000;
    for (int step = 0; step <= kSteps; ++step) {
      const Rotation partial(o.origin + turn.originOffset, turn.axis, o.angle * Real(step) / kSteps);
      for (int v = 0; v < box.numVertices(); ++v)
        lowest = std::min(lowest, partial.rotatePoint(o.origin + box.vertex(v)).z);
    }
    sureHits += lowest < -0.5f;
    sureMisses += lowest > 0.5f;
  }
  ASSERT_GT(sureHits, 10);
  ASSERT_GT(sureMisses, 10);

  for (int threads : {1, 2}) {
    SCOPED_TRACE(threads);
    o.threads = threads;
    const SpeedTestReport report = runSpeedTest(floor, box, o);
    EXPECT_EQ(report.translation.count, kTestTimes);
    EXPECT_EQ(report.translation.hits, expectedHits);
    EXPECT_EQ(report.translation.hash, hash);
    EXPECT_EQ(report.rotation.count, kTestTimes);
    EXPECT_GE(report.rotation.hits, sureHits);
    EXPECT_LE(report.rotation.hits, kTestTimes - sureMisses);
  }
}

TEST_F(SpeedTest, CliBenchPrintsStatistics) {
  if (std::string(CMKIT_CLI_PATH).empty()) GTEST_SKIP() << "the CLI is not built";
  const auto map = std::filesystem::path(CMKIT_SOURCE_DIR) / "data" / "maps" / "lt4" / "lt4.map";
  if (!std::filesystem::exists(map)) GTEST_SKIP() << "no " << map;
  int status = 0;
  const std::string out = test::runCapture(
      std::string(CMKIT_CLI_PATH) + " bench '" + map.string() + "' --times 200 --threads 2", status);
  EXPECT_EQ(status, 0) << out;
  for (const char* expected : {"translation:", "rotation:", " min ", " avg ", " max ", "hits", "hash",
                               "2 threads:", "speed-up", "hash identical"})
    EXPECT_NE(out.find(expected), std::string::npos) << expected << " missing in:\n" << out;
  EXPECT_EQ(out.find("DIFFERENT"), std::string::npos) << out;
}

}  // namespace
}  // namespace cmkit
