// cmkit's own query layout of a model (src/model/polygon_bvh.h,
// point_tree.h, point_grid.h): the polygon hierarchy holds every polygon
// once, with boxes and contents that contain what is below them; the point
// tree is the BSP tree node for node; the point grid lists at each point the
// brushes the walk down the tree meets there. (That the queries answer alike with and without it:
// QueryData.PreparedAndBareModelsAnswerAlike* in test_query_properties.cpp.)
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "cmkit/contents.h"
#include "cmkit/query.h"
#include "model/model_access.h"
#include "model/query_data.h"
#include "model/twins.h"
#include "model_fixtures.h"
#include "test_support.h"
#include "tree_fixtures.h"

namespace cmkit {
namespace {

using detail::BvhLeaf;
using detail::BvhNode;
using detail::kLanes;
using detail::PointNode;
using detail::PointTree;
using detail::PolygonBvh;

/// The bundled lt4's world model (11 489 polygons).
ModelPtr lt4World() {
  const auto models = test::buildMapModels(std::filesystem::path(CMKIT_SOURCE_DIR) / "data/maps/lt4/lt4.map");
  return models.empty() ? nullptr : models.front();
}

/// Whether box [min, max] of lane j of a node or leaf contains bounds b.
template <class Block>
bool laneContains(const Block& block, std::size_t j, const Bounds& b) {
  for (int k = 0; k < 3; ++k)
    if (block.min[k][j] > b.min[k] || block.max[k][j] < b.max[k]) return false;
  return true;
}

/// Checks the subtree of `child` against its box and contents in the parent
/// (lane j of `parent`); adds its polygons to `seen`; returns its inner depth.
std::size_t checkSubtree(const CollisionModel& m, const PolygonBvh& bvh, std::int32_t child,
                         const BvhNode* parent, std::size_t lane, std::vector<int>& seen) {
  std::uint32_t contents = 0;
  if (child < 0) {
    const std::size_t leaf = std::size_t(~child);
    EXPECT_LT(leaf, bvh.leaves.size());
    const BvhLeaf& b = bvh.leaves[leaf];
    for (std::size_t j = 0; j < kLanes; ++j) {
      const std::int32_t polyNum = b.polygon[j] < 0 ? -1 : b.polygonAt(j);
      if (polyNum < 0) {
        EXPECT_EQ(b.contents[j], 0u) << "an unused lane has no contents";
        EXPECT_GT(b.min[0][j], b.max[0][j]) << "an unused lane's box is inverted";
        EXPECT_EQ(b.polygon[j], -1) << "an unused lane has no twin";
        EXPECT_EQ(b.twinLanes() >> j & 1u, 0u) << "an unused lane's -1 has the twin bit, yet no twin";
        continue;
      }
      const CmPolygon& p = m.polygons()[std::size_t(polyNum)];
      ++seen[std::size_t(polyNum)];
      const std::int32_t twin = b.twin[j];
      EXPECT_EQ(b.twinLanes() >> j & 1u, unsigned(twin >= 0)) << "the lane's flag says whether it has a twin";
      // What a translation's test reads of the lane's polygons: the leaf's
      // copies (materials, edge counts, the uses one polygon after another).
      const auto expectCorners = [&](const CmPolygon& q, const detail::PolygonCorner* corners) {
        const detail::QueryData* d = detail::queryDataOf(m);
        for (std::size_t i = 0; i < q.numEdges; ++i) {
          // Corner i: edge i's entry and internal flag, and the position of
          // the vertex where it starts in the polygon's order, which is where
          // the edge before it ends.
          const detail::EdgeUse& want = d->edgeUses[q.firstEdge + i];
          const detail::PolygonCorner& got = corners[i];
          EXPECT_EQ(got.edgeNum(), want.edgeNum);
          EXPECT_EQ(got.internal(), want.internal != 0);
          EXPECT_EQ(got.p, m.vertices()[std::size_t(want.start())]);
          const detail::EdgeUse& before = d->edgeUses[q.firstEdge + (i == 0 ? q.numEdges : i) - 1];
          EXPECT_EQ(got.p, m.vertices()[std::size_t(before.end())]);
        }
      };
      const auto expectUses = [&](const CmPolygon& q, std::size_t at) {
        ASSERT_LE(at + q.numEdges, bvh.uses.size());
        expectCorners(q, bvh.uses.data() + at);
      };
      EXPECT_EQ(b.numEdges[j], p.numEdges);
      EXPECT_EQ(b.material[j], p.material);
      const BvhLeaf::UseStarts uses = b.useStarts();
      expectUses(p, uses.of(j));
      EXPECT_EQ(uses.of(j) % BvhLeaf::kUsesPerLine, 0u) << "each polygon's uses start a line";
      if (twin >= 0) {  // the lane's other side: reversed, its culls the lane's
        const CmPolygon& t = m.polygons()[std::size_t(twin)];
        ++seen[std::size_t(twin)];
        EXPECT_TRUE(detail::isTwin(m.arrays(), p, t)) << "polygon " << polyNum << " twin " << twin;
        EXPECT_EQ(t.bounds.min, p.bounds.min);
        EXPECT_EQ(t.bounds.max, p.bounds.max);
        EXPECT_EQ(b.twinMaterial[j], t.material);
        if (b.twinMade(j)) {  // made from the polygon's: what would be stored
          EXPECT_LE(t.numEdges, BvhLeaf::kMaxMadeTwinEdges);
          if (t.numEdges <= BvhLeaf::kMaxMadeTwinEdges) {
            detail::PolygonCorner made[BvhLeaf::kMaxMadeTwinEdges];
            b.twinCorners(j, bvh.uses.data() + uses.of(j), made);
            expectCorners(t, made);
          }
        } else {
          expectUses(t, uses.twinOf(j));  // (a stored twin's uses follow its polygon's)
          EXPECT_EQ(uses.twinOf(j) % BvhLeaf::kUsesPerLine, 0u) << "each polygon's uses start a line";
        }
      } else {
        EXPECT_NE(b.twinStart[j], BvhLeaf::kStoredTwin) << "a lane without a twin stores none";
      }
      contents |= p.contents;
      EXPECT_EQ(b.contents[j], p.contents);
      EXPECT_EQ(b.dist[j], p.plane.dist);
      for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(b.min[k][j], p.bounds.min[k]);
        EXPECT_EQ(b.max[k][j], p.bounds.max[k]);
        EXPECT_EQ(b.normal[k][j], p.plane.normal[k]);
      }
      if (parent) {
        EXPECT_TRUE(laneContains(*parent, lane, p.bounds)) << "polygon " << polyNum;
      }
    }
    if (parent) {
      EXPECT_EQ(parent->contents[lane], contents);
    }
    return 0;
  }
  EXPECT_LT(std::size_t(child), bvh.nodes.size());
  const BvhNode& n = bvh.nodes[std::size_t(child)];
  std::size_t depth = 0;
  for (std::size_t j = 0; j < kLanes; ++j) {
    if (n.contents[j] == 0 && n.min[0][j] > n.max[0][j]) continue;  // unused
    contents |= n.contents[j];
    if (parent) {
      Bounds box;
      for (int k = 0; k < 3; ++k) {
        box.min[k] = n.min[k][j];
        box.max[k] = n.max[k][j];
      }
      EXPECT_TRUE(laneContains(*parent, lane, box));
    }
    depth = std::max(depth, checkSubtree(m, bvh, n.child[j], &n, j, seen));
  }
  if (parent) {
    EXPECT_EQ(parent->contents[lane], contents);
  }
  return depth + 1;
}

TEST(PolygonBvh, HoldsEveryPolygonOnceInBoxesThatContainIt) {
  if (!detail::kCullBlocks)
    GTEST_SKIP() << "a build without float lanes (double, no SIMD) makes no hierarchy";
  const ModelPtr world = lt4World();
  ASSERT_TRUE(world);
  ASSERT_GT(world->polygons().size(), detail::kBvhMinPolygons);
  const detail::QueryData* d = detail::queryDataOf(*world);
  ASSERT_NE(d, nullptr);
  const PolygonBvh& bvh = d->bvh;
  ASSERT_FALSE(bvh.empty());
  std::vector<int> seen(world->polygons().size(), 0);
  const std::size_t depth = checkSubtree(*world, bvh, 0, nullptr, 0, seen);
  for (std::size_t i = 0; i < seen.size(); ++i) ASSERT_EQ(seen[i], 1) << "polygon " << i;
  // Every polygon's copied once, each from a line's start, but the twins'
  // made from their polygons'.
  std::size_t uses = 0;
  for (const CmPolygon& p : world->polygons()) uses += BvhLeaf::usesStride(p.numEdges);
  for (const BvhLeaf& b : bvh.leaves)
    for (std::size_t j = 0; j < kLanes; ++j)
      if ((b.twinLanes() >> j & 1u) && b.twinMade(j)) uses -= BvhLeaf::usesStride(b.numEdges[j]);
  EXPECT_EQ(bvh.uses.size(), uses);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(bvh.uses.data()) % 64, 0u);
  EXPECT_EQ(depth, bvh.depth) << "the walks' stacks are sized by the depth";
  // A leaf per about three polygons at least (kLanes a leaf at most).
  EXPECT_GE(bvh.leaves.size() * kLanes, world->polygons().size());
  EXPECT_LE(bvh.leaves.size() * 2, world->polygons().size());
}

// A two-sided surface's polygon and its reversed twin take one lane (their
// culls are the same but the facing one): the hierarchy of a two-sided
// terrain holds every polygon once, half of them as twins, in about half the
// leaves.
TEST(PolygonBvh, HoldsATwoSidedSurfaceAsPairsInOneLane) {
  if (!detail::kCullBlocks)
    GTEST_SKIP() << "a build without float lanes (double, no SIMD) makes no hierarchy";
  std::mt19937 rng(41);
  const ModelPtr terrain = test::twoSidedTerrainModel(24, rng);
  ASSERT_TRUE(terrain);
  const PolygonBvh& bvh = detail::queryDataOf(*terrain)->bvh;
  ASSERT_FALSE(bvh.empty());
  std::vector<int> seen(terrain->polygons().size(), 0);
  checkSubtree(*terrain, bvh, 0, nullptr, 0, seen);
  for (std::size_t i = 0; i < seen.size(); ++i) ASSERT_EQ(seen[i], 1) << "polygon " << i;
  std::size_t twins = 0;
  for (const BvhLeaf& b : bvh.leaves) twins += std::size_t(std::popcount(b.twinLanes()));
  // 24 x 24 x 2 terrain triangles, each with its twin; the boxes' 144
  // one-sided triangles (merged into faces) have none.
  EXPECT_EQ(twins, std::size_t(24 * 24 * 2));
  EXPECT_LE(bvh.leaves.size() * 2, terrain->polygons().size() - twins);
  // The builder's reversed copies: every twin's corners are made from its
  // polygon's (checked against the twin's own in checkSubtree), none stored.
  std::size_t uses = 0;
  for (const CmPolygon& p : terrain->polygons()) uses += BvhLeaf::usesStride(p.numEdges);
  for (const BvhLeaf& b : bvh.leaves)
    for (std::size_t j = 0; j < kLanes; ++j)
      if (b.twinLanes() >> j & 1u) {
        EXPECT_TRUE(b.twinMade(j));
        uses -= BvhLeaf::usesStride(b.numEdges[j]);
      }
  EXPECT_EQ(bvh.uses.size(), uses);
}

// A twin's corners are made from its polygon's up to kMaxMadeTwinEdges
// edges (the queries make them on the stack); a two-sided polygon of more
// edges keeps its twin's stored (checkSubtree checks both against the
// twin's own edges).
TEST(PolygonBvh, StoresTheCornersOfTwinsOfManyEdges) {
  if (!detail::kCullBlocks)
    GTEST_SKIP() << "a build without float lanes (double, no SIMD) makes no hierarchy";
  for (const int sides : {int(BvhLeaf::kMaxMadeTwinEdges), int(BvhLeaf::kMaxMadeTwinEdges) + 4}) {
    const ModelPtr m = test::twoSidedPrismWorld(sides);
    ASSERT_TRUE(m);
    const PolygonBvh& bvh = detail::queryDataOf(*m)->bvh;
    ASSERT_FALSE(bvh.empty()) << m->polygons().size() << " polygons";
    std::vector<int> seen(m->polygons().size(), 0);
    checkSubtree(*m, bvh, 0, nullptr, 0, seen);
    for (std::size_t i = 0; i < seen.size(); ++i) ASSERT_EQ(seen[i], 1) << "polygon " << i;
    std::size_t caps = 0, twins = 0, stored = 0;
    for (const BvhLeaf& b : bvh.leaves)
      for (std::size_t j = 0; j < kLanes; ++j) {
        if (!(b.twinLanes() >> j & 1u)) continue;
        ++twins;
        if (b.numEdges[j] == std::size_t(sides)) ++caps;
        if (!b.twinMade(j)) {
          ++stored;
          EXPECT_EQ(b.numEdges[j], std::size_t(sides)) << "only the caps' twins are stored";
        }
      }
    EXPECT_EQ(twins * 2, m->polygons().size()) << "every face with its twin in one lane";
    EXPECT_EQ(caps, 2u) << sides << " sides";
    EXPECT_EQ(stored, std::size_t(sides) > BvhLeaf::kMaxMadeTwinEdges ? 2u : 0u) << sides << " sides";
  }
}

/// A quad (edges 1..4) and polygons whose edge lists are `other`, of the
/// quad's opposite plane, contents and edge count.
bool quadTwinOf(std::vector<std::int32_t> other) {
  ModelArrays m;
  m.polygonEdges = {1, 2, 3, 4};
  m.polygonEdges.insert(m.polygonEdges.end(), other.begin(), other.end());
  CmPolygon a;
  a.plane = Plane(Vec3{0, 0, 1}, 8);
  a.contents = contents::kSolid;
  a.firstEdge = 0;
  a.numEdges = 4;
  CmPolygon b = a;
  b.plane = Plane(Vec3{-0.0f, -0.0f, -1}, -8);
  b.firstEdge = 4;
  b.numEdges = std::uint32_t(other.size());
  return detail::isTwin(m, a, b) && detail::isTwin(m, b, a);
}

TEST(Twins, AreTheReversedEdgesInAnyOrder) {
  // A builder's reversed copy: negated, in reverse order from any edge.
  EXPECT_TRUE(quadTwinOf({-4, -3, -2, -1}));
  EXPECT_TRUE(quadTwinOf({-2, -1, -4, -3}));
  EXPECT_TRUE(quadTwinOf({-1, -4, -3, -2}));
  // The same edges in another order (not a builder's, still the other side).
  EXPECT_TRUE(quadTwinOf({-1, -2, -3, -4}));
  EXPECT_TRUE(quadTwinOf({-3, -1, -4, -2}));
  // Not the other side: an edge walked the same way, another edge, an edge
  // twice, or another number of edges.
  EXPECT_FALSE(quadTwinOf({-4, -3, 2, -1}));
  EXPECT_FALSE(quadTwinOf({-4, -3, -5, -1}));
  EXPECT_FALSE(quadTwinOf({-4, -4, -2, -1}));
  EXPECT_FALSE(quadTwinOf({-4, -3, -2}));
  // Where a builder's reversed copy starts (the hierarchy makes such a
  // twin's corners from its polygon's): -1 for any other order.
  const std::vector<std::int32_t> quad{1, 2, 3, 4};
  const auto from = [&](std::vector<std::int32_t> other) { return detail::reversedFrom(quad, other); };
  EXPECT_EQ(from({-4, -3, -2, -1}), 3);
  EXPECT_EQ(from({-2, -1, -4, -3}), 1);
  EXPECT_EQ(from({-1, -4, -3, -2}), 0);
  EXPECT_EQ(from({-1, -2, -3, -4}), -1);
  EXPECT_EQ(from({-4, -3, -2}), -1);
  EXPECT_EQ(from({}), -1);
}

TEST(PolygonBvh, SmallModelsHaveNone) {
  test::ModelMaker maker;
  maker.addBox({{-10, -10, -10}, {10, 10, 10}});
  const CollisionModel box = maker.build();
  ASSERT_LE(box.polygons().size(), detail::kBvhMinPolygons);
  const detail::QueryData* d = detail::queryDataOf(box);
  ASSERT_NE(d, nullptr);
  EXPECT_TRUE(d->bvh.empty());
  EXPECT_TRUE(detail::buildPolygonBvh(ModelArrays{}, {}).empty());
}

/// Walks the model's node `nodeNum` and the point tree's place `place`
/// together, checking each pair.
void checkPointNode(const CollisionModel& m, const PointTree& t, std::int32_t nodeNum, std::uint32_t place,
                    std::size_t& visited) {
  ASSERT_LT(place, t.nodes.size());
  ++visited;
  const CmNode& n = m.nodes()[std::size_t(nodeNum)];
  const PointNode& p = t.nodes[place];
  EXPECT_EQ(p.hasBrushes(), n.numBrushRefs != 0);
  EXPECT_EQ(p.hasItems(), n.numBrushRefs != 0 || n.numPolygonRefs != 0);
  EXPECT_EQ(t.modelNodes[place], std::uint32_t(nodeNum));
  if (n.isLeaf()) {
    EXPECT_EQ(p.axis(), PointNode::kLeafAxis);
    return;
  }
  EXPECT_EQ(p.axis(), std::uint32_t(n.planeType));
  EXPECT_EQ(p.dist, n.planeDist);
  checkPointNode(m, t, n.children[0], p.front(), visited);
  checkPointNode(m, t, n.children[1], p.front() + 1, visited);
}

TEST(PointTree, IsTheBspTreeNodeForNode) {
  const ModelPtr world = lt4World();
  ASSERT_TRUE(world);
  const detail::QueryData* d = detail::queryDataOf(*world);
  ASSERT_NE(d, nullptr);
  const PointTree& t = d->pointTree;
  ASSERT_FALSE(t.empty());
  std::size_t visited = 0;
  checkPointNode(*world, t, 0, 0, visited);
  EXPECT_EQ(visited, world->nodes().size());
  EXPECT_EQ(t.nodes.size(), world->nodes().size());
}

/// The brushes whose bounds hold p among those of the nodes on p's path
/// down the model's own tree (what point contents test the planes of),
/// sorted, each once.
std::vector<std::uint32_t> brushesOnThePath(const CollisionModel& m, const Vec3& p) {
  std::vector<std::uint32_t> out;
  for (std::int32_t n = 0;;) {
    const CmNode& node = m.nodes()[std::size_t(n)];
    for (const std::int32_t b : m.brushesAt(node))
      if (m.brushes()[std::size_t(b)].bounds.containsPoint(p)) out.push_back(std::uint32_t(b));
    if (node.isLeaf()) break;
    n = p[node.planeType] > node.planeDist ? node.children[0] : node.children[1];
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

/// The brushes whose boxes in p's cell of the grid hold p, sorted, each once.
std::vector<std::uint32_t> brushesInTheCell(const detail::PointGrid& g, const Vec3& p) {
  std::vector<std::uint32_t> out;
  if (!g.bounds.containsPoint(p)) return out;
  const std::size_t cell = g.cellOf(p);
  for (std::uint32_t i = g.firstBox[cell]; i < g.firstBox[cell + 1]; ++i)
    if (g.boxes[i].bounds.containsPoint(p)) out.push_back(g.boxes[i].brush);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

/// Points where the walk's and the grid's edges are: in a random brush's
/// bounds, each coordinate at random, or at the bounds' faces, or at a split
/// of the tree within them (exactly, or the next number up, where the walk
/// turns front), or rounded to an integer (map coordinates are).
std::vector<Vec3> pointsAtTheEdges(const CollisionModel& m, std::size_t count) {
  std::mt19937 rng(11);
  std::vector<Real> splits[3];
  for (const CmNode& n : m.nodes())
    if (!n.isLeaf()) splits[n.planeType].push_back(n.planeDist);
  for (auto& s : splits) std::sort(s.begin(), s.end());
  std::vector<Vec3> out;
  while (out.size() < count) {
    const CmBrush& b =
        m.brushes()[std::uniform_int_distribution<std::size_t>(0, m.brushes().size() - 1)(rng)];
    Vec3 p;
    for (int k = 0; k < 3; ++k) {
      const Real lo = b.bounds.min[k], hi = b.bounds.max[k];
      Real c = std::uniform_real_distribution<Real>(lo, hi)(rng);
      switch (std::uniform_int_distribution<int>(0, 5)(rng)) {
        case 0:
          c = lo;
          break;
        case 1:
          c = hi;
          break;
        case 2:
        case 3: {  // a split within the bounds, or the next number up
          const auto first = std::lower_bound(splits[k].begin(), splits[k].end(), lo);
          const auto last = std::upper_bound(splits[k].begin(), splits[k].end(), hi);
          if (first != last) {
            c = first[std::uniform_int_distribution<std::ptrdiff_t>(0, last - first - 1)(rng)];
            if (std::uniform_int_distribution<int>(0, 1)(rng)) c = std::nextafter(c, Real(1e30));
          }
          break;
        }
        case 4:
          c = std::round(c);
          break;
        default:
          break;
      }
      p[k] = c;
    }
    out.push_back(p);
  }
  return out;
}

TEST(PointGrid, ListsAtEachPointTheBrushesTheWalkMeetsThere) {
  // The grid's cell of a point lists (among others) a box holding it for
  // exactly the brushes whose bounds hold it on the point's path down the
  // tree: a brush straddling a split is met only on the side the walk takes
  // (front: coordinate > split), so its box is cut there. Here the points
  // lie on brushes' faces and on splits, where a cut one number off shows.
  const ModelPtr world = lt4World();
  ASSERT_TRUE(world);
  const detail::QueryData* d = detail::queryDataOf(*world);
  ASSERT_NE(d, nullptr);
  const detail::PointGrid& g = d->pointGrid;
  ASSERT_FALSE(g.empty()) << "lt4's world has a point grid";
  ASSERT_EQ(g.firstBox.size(), std::size_t(g.dims[0]) * g.dims[1] * g.dims[2] + 1);
  ASSERT_EQ(g.firstBox.back(), g.boxes.size());
  for (const detail::PointBrushBox& box : g.boxes) {
    ASSERT_LT(box.brush, world->brushes().size());
    const CmBrush& b = world->brushes()[box.brush];
    EXPECT_EQ(box.contents, b.contents);
    EXPECT_TRUE(b.bounds.containsBounds(box.bounds)) << "a box is a part of its brush's bounds";
  }
  std::size_t met = 0;
  for (const Vec3& p : pointsAtTheEdges(*world, 100000)) {
    const std::vector<std::uint32_t> walk = brushesOnThePath(*world, p);
    ASSERT_EQ(brushesInTheCell(g, p), walk) << p.x << " " << p.y << " " << p.z;
    met += !walk.empty();
  }
  EXPECT_GT(met, 50000u) << "too few points in a brush's bounds: the test would test little";
}

/// How many of `count` random points in the model's bounds and `count`
/// points at its brushes' edges are inside a brush, each point's contents
/// through the grid checked against the walk of the model's nodes.
int pointContentsAsThroughTheNodes(const CollisionModel& m, std::size_t count) {
  const CollisionModel bare = detail::ModelAccess::withoutQueryData(m);
  std::mt19937 rng(7);
  const Bounds b = m.bounds();
  std::uniform_real_distribution<float> x(b.min.x, b.max.x), y(b.min.y, b.max.y), z(b.min.z, b.max.z);
  std::vector<Vec3> points = pointsAtTheEdges(m, count);
  for (std::size_t i = 0; i < count; ++i) points.push_back({x(rng), y(rng), z(rng)});
  QueryWork work;
  int inside = 0;
  for (const Vec3& p : points) {
    const PointContentsQuery q{p, {}};
    const std::uint32_t a = pointContents(m, q, work).contents;
    const std::uint32_t walked = pointContents(bare, q, work).contents;
    EXPECT_EQ(a, walked) << p.x << " " << p.y << " " << p.z;
    if (a != walked) break;  // (one point's report is enough)
    inside += a != 0;
  }
  return inside;
}

TEST(PointGrid, PointContentsThroughItAreThoseThroughTheModelsNodes) {
  const ModelPtr world = lt4World();
  ASSERT_TRUE(world);
  ASSERT_FALSE(detail::queryDataOf(*world)->pointGrid.empty());
  EXPECT_GT(pointContentsAsThroughTheNodes(*world, 20000), 4000)
      << "too few points inside brushes: the test would test little";
  // A small map's (54 nodes).
  const auto room = test::buildMapModels(test::dataFile("maps/synthetic/box_room.map"));
  ASSERT_FALSE(room.empty());
  ASSERT_FALSE(detail::queryDataOf(*room.front())->pointGrid.empty());
  EXPECT_GT(pointContentsAsThroughTheNodes(*room.front(), 5000), 1000)
      << "too few points inside brushes: the test would test little";
}

TEST(PointGrid, NoneForOneLeafModelsWithoutBrushesAndBrushesAsLargeAsTheModel) {
  const auto gridOf = [](const CollisionModel& m) -> const detail::PointGrid& {
    return detail::queryDataOf(m)->pointGrid;
  };
  // 21 and 601 nodes, one brush: a grid of its one box (in each cell it meets).
  for (const int depth : {10, 300}) {
    const ModelPtr chain = test::deepChain(depth);
    ASSERT_TRUE(chain);
    ASSERT_FALSE(gridOf(*chain).empty()) << depth;
    for (const detail::PointBrushBox& box : gridOf(*chain).boxes) EXPECT_EQ(box.brush, 0u);
  }
  // One leaf: its list is the brushes; no grid.
  const ModelPtr leaf = test::deepChain(0);
  ASSERT_TRUE(leaf);
  ASSERT_EQ(leaf->nodes().size(), 1u);
  EXPECT_TRUE(gridOf(*leaf).empty());
  EXPECT_EQ(test::pointContentsAt(*leaf, {1005, 5, 5}), contents::kSolid);
  // 300 brushes each nearly as long as the model: every cell of any grid
  // would list most of them, so none (the walk of the model's nodes).
  const ModelPtr nested = test::brushAtEveryNode(300, [](int) { return contents::kSolid; });
  ASSERT_TRUE(nested);
  EXPECT_TRUE(gridOf(*nested).empty());
  EXPECT_EQ(test::pointContentsAt(*nested, {1004, 5, 5}), contents::kSolid);
}

TEST(PointGrid, NoneOverBoxesOfInfiniteSize) {
  // Arrays only (buildPointGrid takes them before any check): a split at
  // x = 0, a brush in each leaf; one brush reaching to infinity leaves no
  // size to divide into cells, so no grid (the nodes' walk answers).
  ModelArrays m;
  m.nodes.resize(3);
  m.nodes[0].planeType = 0;
  m.nodes[0].children[0] = 1;
  m.nodes[0].children[1] = 2;
  m.brushes.resize(2);
  m.brushes[0].bounds = {{1, 0, 0}, {10, 10, 10}};
  m.brushes[1].bounds = {{-10, 0, 0}, {-1, 10, 10}};
  m.brushRefs = {0, 1};
  m.nodes[1].firstBrushRef = 0;
  m.nodes[1].numBrushRefs = 1;
  m.nodes[2].firstBrushRef = 1;
  m.nodes[2].numBrushRefs = 1;
  EXPECT_FALSE(detail::buildPointGrid(m).empty());
  m.brushes[1].bounds.min.x = -std::numeric_limits<Real>::infinity();
  EXPECT_TRUE(detail::buildPointGrid(m).empty());
  m.brushes[1].bounds.min.x = -std::numeric_limits<Real>::max();
  m.brushes[0].bounds.max.x = std::numeric_limits<Real>::max();  // (the size overflows)
  EXPECT_TRUE(detail::buildPointGrid(m).empty());
  // The same from a .cm file (its reader takes bounds that large): the
  // model loads, has no grid, and its point contents are its brush's.
  std::string cm = test::deepChainCm(3);
  const std::string bounds = "( 1000 0 0 ) ( 1010 10 10 )";
  ASSERT_NE(cm.find(bounds), std::string::npos);
  cm.replace(cm.find(bounds), bounds.size(), "( -3e38 0 0 ) ( 3e38 10 10 )");
  auto f = parseCmText(cm, "huge.cm", MaterialTable{});
  ASSERT_TRUE(f.ok()) << f.error().toString();
  const CollisionModel& huge = *f->models.front();
  EXPECT_TRUE(detail::queryDataOf(huge)->pointGrid.empty());
  EXPECT_EQ(test::pointContentsAt(huge, {1005, 5, 5}), contents::kSolid);
  EXPECT_EQ(test::pointContentsAt(huge, {5, 5, 5}), 0u);
}

}  // namespace
}  // namespace cmkit
