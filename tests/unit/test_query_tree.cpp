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

TEST(PointContents, SeesEveryBrushOnAPathLongerThanTheWalksBuffer) {
  // The walks collect the nodes with brushes on the way down 64 at a time
  // (point_contents.cpp's kPath), test their brushes, then go on; here every
  // node of the path holds a brush containing the point. Brushes are
  // solid, but for a few with a flag of their own around the 64th and
  // 128th node, so that one lost at a refill, or a wrong turn after it,
  // shows in the contents. 100 splits: the model's nodes are walked; 300:
  // its point tree (more than kPointTreeMinNodes nodes).
  const std::uint32_t own[] = {contents::kWater,        contents::kPlayerClip, contents::kMonsterClip,
                               contents::kMoveableClip, contents::kIkClip,     contents::kBlood};
  const int ownAt[] = {62, 63, 64, 65, 127, 128};
  const auto contentsOf = [&](int i) {
    for (int k = 0; k < 6; ++k)
      if (ownAt[k] == i) return own[k];
    return contents::kSolid;
  };
  for (const int depth : {100, 300}) {
    const ModelPtr m = test::brushAtEveryNode(depth, contentsOf);
    ASSERT_TRUE(m);
    for (const int i : {0, 50, 63, 64, 99})
      ASSERT_EQ(m->brushesAt(m->nodes()[std::size_t(i)]).size(), 1u) << "node " << i << " holds its brush";
    // Stopping after node `last` (x between last - 1 and last): inside brushes 0 .. last - 1.
    for (const int last : {10, 63, 64, 65, 66, 70, 99, 129, 200, depth}) {
      if (last > depth) continue;
      const Real x = last == depth ? Real(1004) : Real(last) - Real(0.75);
      std::uint32_t expected = 0;
      for (int i = 0; i < depth && Real(i) - Real(0.5) <= x; ++i) expected |= contentsOf(i);
      EXPECT_EQ(test::pointContentsAt(*m, {x, 5, 5}), expected) << "depth " << depth << ", x " << x;
      EXPECT_EQ(test::pointContentsAt(*m, {x, 5, 15}), 0u) << "depth " << depth << ", x " << x;
    }
  }
}

TEST(PointContents, AMaskedPointHasTheFlagsOfEveryBrushMatchingTheMask) {
  // A point's position test honours the mask (docs/fidelity.md): its
  // contents are the OR of the brushes holding the point that match the
  // mask, every flag of each, whatever order the walk meets them in. Here
  // the deepest brush, met first, is solid only; two above it are solid
  // with water and solid with player clip: solid asked finds all three.
  // Both walks: the model's nodes (3 splits) and the point tree (300).
  for (const int depth : {3, 300}) {
    const auto contentsOf = [depth](int i) {
      if (i == depth - 2) return contents::kSolid | contents::kWater;
      if (i == depth - 3) return contents::kSolid | contents::kPlayerClip;
      return contents::kSolid;
    };
    const ModelPtr m = test::brushAtEveryNode(depth, contentsOf);
    ASSERT_TRUE(m);
    QueryWork work;
    ContentsQuery q;
    q.position = {1004, 5, 5};  // in every brush, at the deepest leaf
    q.contentMask = contents::kSolid;
    EXPECT_EQ(contentsTest(*m, q, work).contents, contents::kSolid | contents::kWater | contents::kPlayerClip)
        << "depth " << depth;
    q.contentMask = contents::kWater;
    EXPECT_EQ(contentsTest(*m, q, work).contents, contents::kSolid | contents::kWater) << "depth " << depth;
    q.contentMask = contents::kMonsterClip;
    EXPECT_EQ(contentsTest(*m, q, work).contents, 0u) << "depth " << depth;
    EXPECT_EQ(test::pointContentsAt(*m, q.position),
              contents::kSolid | contents::kWater | contents::kPlayerClip)
        << "depth " << depth;
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
