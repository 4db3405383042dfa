// The speed test (include/cmkit/speed_test.h): same results at any thread
// count, hits on a real map; `cmkit bench` prints its statistics lines.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <utility>

#include "cmkit/compile.h"
#include "cmkit/map.h"
#include "cmkit/tools/speed_test.h"
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
  SpeedTestOptions o = options;
  o.randomMany = true;
  const auto r = run(o);
  // Every query is the same: all hit or none does.
  EXPECT_TRUE(r.translation.hits == 0 || r.translation.hits == kTestTimes);
  EXPECT_TRUE(r.rotation.hits == 0 || r.rotation.hits == kTestTimes);
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
