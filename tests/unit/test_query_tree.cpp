// Queries on unusual trees: a .cm whose tree is deeper than any fixed path
// buffer, and penetration() (which walks the tree) against a scan of every
// brush.
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "cmkit/cm_file.h"
#include "cmkit/query.h"
#include "test_support.h"

namespace cmkit {
namespace {

/// A .cm model whose tree is a chain of `depth` splits on x (node i splits at
/// x = i, its front child is node i + 1, its back child an empty leaf), with
/// one solid box brush x 1000..1010, y and z 0..10, which is filtered into the
/// deepest leaf.
std::string deepChainCm(int depth) {
  std::string nodes;
  for (int i = 0; i < depth; ++i) nodes += "( 0 " + std::to_string(i) + " ) ";
  for (int i = 0; i <= depth; ++i) nodes += "( -1 0 ) ";  // the deepest front leaf, then the back leaves
  return "CM \"1.00\" 0\ncollisionModel \"deep\" {\n  nodes { " + nodes +
         "}\n"
         "  brushes { 6 { ( 1 0 0 ) 1010 ( -1 0 0 ) -1000 ( 0 1 0 ) 10 ( 0 -1 0 ) 0 ( 0 0 1 ) 10 "
         "( 0 0 -1 ) 0 } ( 1000 0 0 ) ( 1010 10 10 ) 1 }\n}\n";
}

ModelPtr deepChain(int depth) {
  auto f = parseCmText(deepChainCm(depth), "deep.cm", MaterialTable{});
  EXPECT_TRUE(f.ok()) << (f.ok() ? "" : f.error().toString());
  return f.ok() ? f->models.front() : nullptr;
}

/// The depth of the leaf the walk to `x` ends in.
int leafDepth(const CollisionModel& m, Real x) {
  int depth = 0;
  for (std::int32_t n = 0; !m.nodes[std::size_t(n)].isLeaf(); ++depth) {
    const CmNode& node = m.nodes[std::size_t(n)];
    n = x > node.planeDist ? node.children[0] : node.children[1];
  }
  return depth;
}

TEST(PointContents, SeesTheBrushInTheLeafOfADeepTree) {
  for (const int depth : {10, 300}) {
    const ModelPtr m = deepChain(depth);
    ASSERT_TRUE(m);
    ASSERT_EQ(m->nodes.size(), std::size_t(2 * depth + 1));
    EXPECT_EQ(leafDepth(*m, 1005), depth);
    ASSERT_EQ(m->brushesAt(m->nodes[std::size_t(depth)]).size(), 1u) << "the brush is in the deepest leaf";
    EXPECT_EQ(pointContents(*m, {1005, 5, 5}), contents::kSolid) << "depth " << depth;
    EXPECT_EQ(pointContents(*m, {1005, 5, 15}), 0u) << "depth " << depth;
    EXPECT_EQ(pointContents(*m, {5, 5, 5}), 0u) << "depth " << depth;
  }
}

}  // namespace
}  // namespace cmkit
