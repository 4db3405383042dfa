// QueryWork's work counters: counted only by a library built with
// -DCMKIT_QUERY_STATS=ON (the stats preset), compiled out otherwise.
#include <gtest/gtest.h>

#include "cmkit/query.h"
#include "model_fixtures.h"

using namespace cmkit;
using cmkit::test::ModelMaker;

namespace {

// A box dropped on a floor (one tested polygon at least), a rotation beside
// it, a position test on it.
void runThreeQueries(const CollisionModel& m, QueryWork& work) {
  const TraceModel box = *TraceModel::box({{-16, -16, 0}, {16, 16, 72}});
  TranslationQuery t;
  t.trm = &box;
  t.start = {0, 0, 100};
  t.end = {0, 0, -100};
  EXPECT_LT(translate(m, t, work).fraction, 1);
  RotationQuery r;
  r.trm = &box;
  r.start = {0, 0, 1};
  r.rotation = Rotation({40, 0, 1}, {0, 1, 0}, 90);  // swings the box down into the floor
  EXPECT_LT(rotate(m, r, work).fraction, 1);
  ContentsQuery c;
  c.trm = &box;
  c.position = {0, 0, -8};  // sunk into the floor
  EXPECT_NE(contentsTest(m, c, work).contents, 0u);
}

}  // namespace

TEST(QueryStats, CountedOnlyWhenBuiltIn) {
  const CollisionModel m = ModelMaker().addBox({{-256, -256, -16}, {256, 256, 0}}).build();
  QueryWork work;
  runThreeQueries(m, work);
  const QueryStats& s = work.stats();
  if (!queryStatsEnabled()) {
    // Compiled out: nothing is counted.
    EXPECT_EQ(s.queries, 0u);
    EXPECT_EQ(s.nodesVisited, 0u);
    EXPECT_EQ(s.polygonsMet, 0u);
    EXPECT_EQ(s.polygonsTested, 0u);
    EXPECT_EQ(s.polygonsCloser, 0u);
    EXPECT_EQ(s.brushesMet, 0u);
    EXPECT_EQ(s.vertexTests, 0u);
    EXPECT_EQ(s.edgePairs, 0u);
    return;
  }
  EXPECT_EQ(s.queries, 3u);
  EXPECT_GT(s.nodesVisited, 0u);
  EXPECT_GE(s.polygonsMet, s.polygonsTested);
  EXPECT_GE(s.polygonsTested, 3u);  // the floor's top face, by each query
  // The translation and the rotation stop on it (the position test finds the
  // box in the floor's brush first, before any polygon).
  EXPECT_GE(s.polygonsCloser, 2u);
  EXPECT_LE(s.polygonsCloser, s.polygonsTested);
  EXPECT_GE(s.brushesMet, 1u);  // the floor brush, by the position test
  EXPECT_GT(s.vertexTests, 0u);
  work.resetStats();
  EXPECT_EQ(work.stats().queries, 0u);
  EXPECT_EQ(work.stats().polygonsMet, 0u);
}
