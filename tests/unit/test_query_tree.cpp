// Queries on unusual trees: a .cm whose tree is deeper than any fixed path
// buffer (penetration() on it: test_query_penetration.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "cmkit/cm_file.h"
#include "cmkit/query.h"
#include "cmkit/tolerances.h"
#include "test_support.h"
#include "tree_fixtures.h"

namespace cmkit {
namespace {

/// The depth of the leaf the walk to `x` ends in.
int leafDepth(const CollisionModel& m, Real x) {
  int depth = 0;
  for (std::int32_t n = 0; !m.nodes()[std::size_t(n)].isLeaf(); ++depth) {
    const CmNode& node = m.nodes()[std::size_t(n)];
    n = x > node.planeDist ? node.children[0] : node.children[1];
  }
  return depth;
}

TEST(PointContents, SeesTheBrushInTheLeafOfADeepTree) {
  for (const int depth : {10, 300}) {
    const ModelPtr m = test::deepChain(depth);
    ASSERT_TRUE(m);
    ASSERT_EQ(m->nodes().size(), std::size_t(2 * depth + 1));
    EXPECT_EQ(leafDepth(*m, 1005), depth);
    ASSERT_EQ(m->brushesAt(m->nodes()[std::size_t(depth)]).size(), 1u) << "the brush is in the deepest leaf";
    EXPECT_EQ(test::pointContentsAt(*m, {1005, 5, 5}), contents::kSolid) << "depth " << depth;
    EXPECT_EQ(test::pointContentsAt(*m, {1005, 5, 15}), 0u) << "depth " << depth;
    EXPECT_EQ(test::pointContentsAt(*m, {5, 5, 5}), 0u) << "depth " << depth;
  }
}

TEST(Contents, SeesTheBrushInTheLeafOfADeepTree) {
  // A position test walks both sides of every split it stands on: on the
  // 300-deep chain the walk keeps a far side waiting at every node (more
  // than the walk's stack starts with, so it grows on the way).
  const TraceModel box = *TraceModel::box({{-2, -2, -2}, {2, 2, 2}});
  QueryWork work;
  for (const int depth : {10, 300}) {
    const ModelPtr m = test::deepChain(depth);
    ASSERT_TRUE(m);
    ContentsQuery q;
    q.trm = &box;
    q.position = {1005, 5, 5};
    EXPECT_EQ(contentsTest(*m, q, work).contents, contents::kSolid) << "depth " << depth;
    q.position = {1005, 5, 15};
    EXPECT_EQ(contentsTest(*m, q, work).contents, 0u) << "depth " << depth;
    q.position = {5, 5, 5};
    EXPECT_EQ(contentsTest(*m, q, work).contents, 0u) << "depth " << depth;
  }
}

}  // namespace
}  // namespace cmkit
