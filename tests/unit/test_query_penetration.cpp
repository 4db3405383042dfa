// penetration() (src/query/penetration.cpp), which walks the tree, against a
// scan of every brush written independently of it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <vector>

#include "cmkit/query.h"
#include "cmkit/tolerances.h"
#include "test_support.h"
#include "tree_fixtures.h"

namespace cmkit {
namespace {

/// penetration() as a scan of every brush in index order (the deepest brush
/// wins, the first one on equal depths), written independently of the tree.
PenetrationResult everyBrush(const CollisionModel& m, const TraceModel& trm, const Mat3& trmAxis,
                             const Vec3& position, const Placement& placement) {
  std::vector<Vec3> verts;
  Bounds tb;
  for (int i = 0; i < trm.numVertices(); ++i) {
    Vec3 v = trm.vertex(i) * trmAxis + position - placement.origin;
    if (!placement.axis.isIdentity()) v = placement.axis * v;
    verts.push_back(v);
    tb.addPoint(v);
  }
  PenetrationResult r;
  for (const CmBrush& b : m.brushes()) {
    if (!(b.contents & contents::kMaskSolid) || !b.bounds.intersects(tb) || b.numPlanes == 0) continue;
    Real depth = tol::kBoundsInfinity;
    Vec3 normal;
    bool separated = false;
    for (const Plane& plane : m.planesOf(b)) {
      Real lowest = tol::kBoundsInfinity;
      for (const Vec3& v : verts) lowest = std::min(lowest, plane.distance(v));
      separated |= lowest >= 0;
      if (separated) break;
      if (-lowest < depth) {
        depth = -lowest;
        normal = plane.normal;
      }
    }
    if (separated || (r.stuck && !(depth > r.depth))) continue;
    r = {true, depth, placement.axis.isIdentity() ? normal : normal * placement.axis, b.contents};
  }
  return r;
}

TEST(Penetration, SameAsScanningEveryBrush) {
  std::vector<ModelPtr> models =
      test::buildMapModels(std::filesystem::path(CMKIT_SOURCE_DIR) / "data" / "maps" / "lt4" / "lt4.map");
  ASSERT_FALSE(models.empty());
  models.resize(std::min<std::size_t>(models.size(), 6));
  for (const auto& m : test::buildMapModels(test::testDataDir() / "maps" / "features.map"))
    models.push_back(m);
  models.push_back(test::deepChain(300));
  const TraceModel small = *TraceModel::box({{-4, -4, -4}, {4, 4, 4}});
  const TraceModel player = *TraceModel::box({{-16, -16, 0}, {16, 16, 72}});
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0, 1);
  const Mat3 turned{{0, 1, 0}, {-1, 0, 0}, {0, 0, 1}};
  QueryWork work;
  int tested = 0, stuck = 0;
  for (const ModelPtr& m : models) {
    if (m->brushes().empty()) continue;
    const Bounds b = m->bounds().expanded(8);
    for (int n = 0; n < 3000; ++n) {
      const TraceModel& trm = n % 2 ? small : player;
      Vec3 p{b.min.x + u(rng) * (b.max.x - b.min.x), b.min.y + u(rng) * (b.max.y - b.min.y),
             b.min.z + u(rng) * (b.max.z - b.min.z)};
      // Some on a brush plane or a grid coordinate, where ties and touching happen.
      if (n % 5 == 0) p = {std::round(p.x / 8) * 8, std::round(p.y / 8) * 8, std::round(p.z / 8) * 8};
      PenetrationQuery q;
      q.trm = &trm;
      q.trmAxis = n % 3 == 0 ? turned : Mat3::identity();
      q.position = p;
      if (n % 7 == 0) q.placement = {{0, 0, 0}, turned};
      if (n % 7 == 0) q.position = p * q.placement.axis;  // the same place in the model's frame
      const PenetrationResult fast = penetration(*m, q, work);
      const PenetrationResult slow = everyBrush(*m, trm, q.trmAxis, q.position, q.placement);
      ASSERT_EQ(fast.stuck, slow.stuck) << m->name() << " query " << n;
      EXPECT_EQ(fast.depth, slow.depth) << m->name() << " query " << n;
      EXPECT_EQ(fast.direction, slow.direction) << m->name() << " query " << n;
      EXPECT_EQ(fast.contents, slow.contents) << m->name() << " query " << n;
      ++tested;
      stuck += fast.stuck;
    }
  }
  EXPECT_GT(stuck, tested / 20) << "too few stuck positions for the comparison to mean much";
  std::printf("%d positions, %d stuck\n", tested, stuck);
}

}  // namespace
}  // namespace cmkit
