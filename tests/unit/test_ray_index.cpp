// RayIndex: hand-computed casts, one-sidedness, content masks, placement,
// no leaks through shared edges, exact agreement with testing every polygon
// (bundled lt4 and the test maps), and the relation to point translations.
#include "cmkit/ray_index.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <thread>

#include "cmkit/cm_file.h"
#include "cmkit/compile.h"
#include "cmkit/map.h"
#include "cmkit/materials.h"
#include "cmkit/mesh.h"
#include "cmkit/query.h"
#include "model_fixtures.h"
#include "test_support.h"

using namespace cmkit;

namespace {

constexpr std::uint32_t kAll = 0xffffffffu;

// A solid box -64..64 x -64..64 x -16..0: its top face is the floor z = 0.
CollisionModel floorBox(std::uint32_t contents = contents::kSolid | contents::kOpaque) {
  return test::ModelMaker().addBox({{-64, -64, -16}, {64, 64, 0}}, contents).build();
}

std::int32_t polygonWithNormal(const CollisionModel& m, const Vec3& n) {
  for (std::size_t i = 0; i < m.polygons().size(); ++i)
    if (m.polygons()[i].plane.normal == n) return std::int32_t(i);
  return -1;
}

/// What RayIndex::cast promises, by testing every polygon: the first front
/// face crossed, the crossing inside its edges and near its bounds, ties to
/// the lower index. Written independently of the index.
struct BruteHit {
  Real fraction = 1;
  std::int32_t polygon = -1;
};
BruteHit castEveryPolygon(const CollisionModel& m, const Vec3& s, const Vec3& e, std::uint32_t mask) {
  BruteHit best;
  const Vec3 dir = e - s;
  const Pluecker ray = Pluecker::fromRay(s, dir);
  for (std::size_t i = 0; i < m.polygons().size(); ++i) {
    const CmPolygon& p = m.polygons()[i];
    if (!(p.contents & mask) || p.numEdges < 3) continue;
    if (!(p.plane.normal.dot(dir) < 0)) continue;
    const Real d1 = p.plane.distance(s), d2 = p.plane.distance(e);
    if (d1 < 0 || d2 > 0 || !(d1 - d2 > 0)) continue;
    const Real t = d1 / (d1 - d2);
    if (best.polygon >= 0 && !(t < best.fraction)) continue;  // lower index wins ties: i only grows
    bool inside = true;
    for (std::int32_t edgeNum : m.edgesOf(p)) {
      const CmEdge& edge = m.edges()[std::size_t(std::abs(edgeNum))];
      const Real product = Pluecker::fromLine(m.vertices()[std::size_t(edge.vertex[0])],
                                              m.vertices()[std::size_t(edge.vertex[1])])
                               .permutedInnerProduct(ray);
      if ((edgeNum < 0) != signBitSet(product)) inside = false;
    }
    if (!inside) continue;
    Real size = 0;
    for (int k = 0; k < 3; ++k)
      size = std::max({size, std::fabs(p.bounds.min[k]), std::fabs(p.bounds.max[k])});
    const Real pad = tol::kRayAcceptPadding * (size + 1);
    if (!p.bounds.expanded(pad).containsPoint(s + dir * t)) continue;
    best = {t, std::int32_t(i)};
  }
  return best;
}

Vec3 randomIn(std::mt19937& rng, const Bounds& b) {
  std::uniform_real_distribution<float> u(0, 1);
  return {b.min.x + u(rng) * (b.max.x - b.min.x), b.min.y + u(rng) * (b.max.y - b.min.y),
          b.min.z + u(rng) * (b.max.z - b.min.z)};
}

/// Random segments over a model: long, short and axis-aligned ones.
std::vector<std::pair<Vec3, Vec3>> randomSegments(const Bounds& bounds, unsigned seed, int count) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1, 1);
  const Bounds around = bounds.expanded(32);
  std::vector<std::pair<Vec3, Vec3>> out;
  for (int i = 0; i < count; ++i) {
    const Vec3 s = randomIn(rng, around);
    Vec3 e = randomIn(rng, around);
    if (i % 3 == 1) e = s + Vec3{u(rng), u(rng), u(rng)} * 48;
    if (i % 7 == 0) {
      e = s;
      e[i % 3] += u(rng) * 200;
    }
    out.emplace_back(s, e);
  }
  return out;
}

/// Returns the number of hits.
int expectSameAsEveryPolygon(const CollisionModel& m, unsigned seed, int count, const std::string& what,
                             RayIndex::NodeTest nodeTest) {
  const RayIndex index(m, nodeTest);
  int hits = 0, i = 0;
  for (const auto& [s, e] : randomSegments(m.bounds(), seed, count)) {
    const std::uint32_t masks[] = {kAll, contents::kMaskSolid, contents::kWater | contents::kPlayerClip};
    const std::uint32_t mask = masks[i++ % 3];
    const RayHit fast = index.cast({s, e, mask});
    const BruteHit slow = castEveryPolygon(m, s, e, mask);
    EXPECT_EQ(fast.polygon, slow.polygon) << what << ": (" << s.x << " " << s.y << " " << s.z << ") -> ("
                                          << e.x << " " << e.y << " " << e.z << ")";
    EXPECT_EQ(std::memcmp(&fast.fraction, &slow.fraction, sizeof(Real)), 0) << what;
    if (fast.polygon != slow.polygon) return hits;  // one report per model is enough
    if (fast.hit()) {  // the polygon's plane, contents and material (a twin's from its lane: its own)
      const CmPolygon& p = m.polygons()[std::size_t(fast.polygon)];
      EXPECT_EQ(fast.normal, p.plane.normal) << what << ": polygon " << fast.polygon;
      EXPECT_EQ(fast.dist, p.plane.dist) << what << ": polygon " << fast.polygon;
      EXPECT_EQ(fast.contents, p.contents) << what;
      EXPECT_EQ(fast.material, p.material) << what;
      if (::testing::Test::HasFailure()) return hits;
    }
    hits += fast.hit();
  }
  return hits;
}

std::filesystem::path bundledLt4() {
  return std::filesystem::path(CMKIT_SOURCE_DIR) / "data" / "maps" / "lt4" / "lt4.map";
}

}  // namespace

TEST(RayIndex, HitsTheFloorWhereItCrosses) {
  const CollisionModel m = floorBox();
  const RayIndex index(m);
  EXPECT_EQ(index.numPolygons(), 6u);
  const RayHit h = index.cast({{8, -4, 64}, {8, -4, -64}});
  ASSERT_TRUE(h.hit());
  EXPECT_EQ(h.fraction, 0.5f);  // 64 of 128 units down
  EXPECT_EQ(h.point, Vec3(8, -4, 0));
  EXPECT_EQ(h.normal, Vec3(0, 0, 1));
  EXPECT_EQ(h.dist, 0.0f);
  EXPECT_EQ(h.polygon, polygonWithNormal(m, {0, 0, 1}));
  EXPECT_EQ(h.contents, contents::kSolid | contents::kOpaque);
  EXPECT_EQ(h.material, 0);
  // A slanted ray: from (-40, 0, 30) to (20, 0, -30) crosses z = 0 at x = -10, halfway.
  const RayHit s = index.cast({{-40, 0, 30}, {20, 0, -30}});
  ASSERT_TRUE(s.hit());
  EXPECT_EQ(s.fraction, 0.5f);
  EXPECT_EQ(s.point, Vec3(-10, 0, 0));
}

TEST(RayIndex, TouchingCountsAtBothEnds) {
  const RayIndex index(floorBox());
  const RayHit ends = index.cast({{0, 0, 64}, {0, 0, 0}});  // ends exactly on the floor
  ASSERT_TRUE(ends.hit());
  EXPECT_EQ(ends.fraction, 1.0f);
  const RayHit starts = index.cast({{0, 0, 0}, {0, 0, -8}});  // starts on it, moves in
  ASSERT_TRUE(starts.hit());
  EXPECT_EQ(starts.fraction, 0.0f);
  EXPECT_FALSE(index.cast({{0, 0, 0}, {0, 0, 8}}).hit());     // leaves it
  EXPECT_FALSE(index.cast({{0, 0, 8}, {0, 0, 0.5f}}).hit());  // stops short
}

TEST(RayIndex, PolygonsAreOneSided) {
  const CollisionModel m = floorBox();
  const RayIndex index(m);
  EXPECT_FALSE(index.cast({{0, 0, -8}, {0, 0, 64}}).hit()) << "from inside the box, out through the top";
  // Through the whole box from below: only the bottom face faces the ray.
  const RayHit h = index.cast({{0, 0, -32}, {0, 0, 32}});
  ASSERT_TRUE(h.hit());
  EXPECT_EQ(h.polygon, polygonWithNormal(m, {0, 0, -1}));
  EXPECT_EQ(h.fraction, 0.25f);  // z = -16 is 16 of 64 units up
  // Along the floor's plane: parallel, no hit.
  EXPECT_FALSE(index.cast({{-100, 0, 0}, {100, 0, 0}}).hit());
  // Beside the box.
  EXPECT_FALSE(index.cast({{70, 0, 64}, {70, 0, -64}}).hit());
}

TEST(RayIndex, ContentMaskSelectsSurfaces) {
  const RayIndex water(floorBox(contents::kWater));
  EXPECT_FALSE(water.cast({{0, 0, 64}, {0, 0, -64}, contents::kMaskSolid}).hit());
  const RayHit h = water.cast({{0, 0, 64}, {0, 0, -64}, contents::kWater});
  ASSERT_TRUE(h.hit());
  EXPECT_EQ(h.contents, contents::kWater);
}

TEST(RayIndex, NearestOfManyAndTiesToTheLowerIndex) {
  // Three stacked slabs; the top one is met first from above, the bottom
  // one first from below.
  const CollisionModel m = test::ModelMaker()
                               .addBox({{-32, -32, 0}, {32, 32, 8}})
                               .addBox({{-32, -32, 40}, {32, 32, 48}})
                               .addBox({{-32, -32, 80}, {32, 32, 88}})
                               .build();
  const RayIndex index(m);
  const RayHit down = index.cast({{0, 0, 200}, {0, 0, -100}});
  ASSERT_TRUE(down.hit());
  EXPECT_EQ(down.point.z, 88.0f);
  const RayHit up = index.cast({{0, 0, -100}, {0, 0, 200}});
  ASSERT_TRUE(up.hit());
  EXPECT_EQ(up.point.z, 0.0f);
  // Two identical boxes: every face exists twice; the lower index wins.
  const CollisionModel twice =
      test::ModelMaker().addBox({{-8, -8, -8}, {8, 8, 8}}).addBox({{-8, -8, -8}, {8, 8, 8}}).build();
  const RayHit h = RayIndex(twice).cast({{0, 0, 50}, {0, 0, -50}});
  ASSERT_TRUE(h.hit());
  EXPECT_EQ(h.polygon, polygonWithNormal(twice, {0, 0, 1}));
  EXPECT_LT(std::size_t(h.polygon), twice.polygons().size() / 2);
}

TEST(RayIndex, NoLeaksThroughSharedEdges) {
  // Rays from outside aimed exactly at points on the edges of a closed,
  // slanted convex piece: two faces share each edge, and exactly one of
  // them must take every such ray.
  const Vec3 pts[] = {{-40, -30, -20}, {50, -35, -10}, {45, 40, -25}, {-35, 45, -15},
                      {-20, -15, 30},  {25, -20, 35},  {20, 25, 40},  {-25, 20, 28}};
  const CollisionModel m = test::ModelMaker().addConvex(*TraceModel::convexHull(pts)).build();
  const RayIndex index(m);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> along(0.1f, 0.9f), dir(-1, 1);
  int rays = 0;
  for (std::size_t e = 1; e < m.edges().size(); ++e) {
    const Vec3 a = m.vertices()[std::size_t(m.edges()[e].vertex[0])],
               b = m.vertices()[std::size_t(m.edges()[e].vertex[1])];
    const Vec3 outward = m.edges()[e].normal;  // between the two faces' normals
    for (int i = 0; i < 200; ++i) {
      const Vec3 target = a + (b - a) * along(rng);
      const Vec3 from = target + (outward * 60) + Vec3{dir(rng), dir(rng), dir(rng)} * 20;
      const Vec3 to = from + (target - from) * 2;  // through the edge point and beyond
      ++rays;
      const RayHit h = index.cast({from, to, kAll});
      ASSERT_TRUE(h.hit()) << "ray " << rays << " slipped through edge " << e;
      EXPECT_NEAR(h.fraction, 0.5f, 1e-3f);
    }
  }
  EXPECT_GT(rays, 1000);
}

TEST(RayIndex, PlacedModelsTransformRaysAndResults) {
  const CollisionModel m = floorBox();
  const RayIndex index(m);
  Placement placed;
  placed.origin = {1000, 500, 100};
  placed.axis = Mat3::fromAngles(30, 90, 0);  // pitched and turned: the floor is slanted in the world
  // A ray through the world position of the floor point (8, -4, 0).
  const Vec3 worldPoint = Vec3{8, -4, 0} * placed.axis + placed.origin;
  const Vec3 worldNormal = Vec3{0, 0, 1} * placed.axis;
  const Vec3 from = worldPoint + worldNormal * 40, to = worldPoint - worldNormal * 40;
  const RayHit h = index.cast({from, to, contents::kMaskSolid, placed});
  ASSERT_TRUE(h.hit());
  EXPECT_NEAR(h.fraction, 0.5f, 1e-5f);
  EXPECT_NEAR((h.point - worldPoint).length(), 0.0f, 1e-3f);
  EXPECT_NEAR((h.normal - worldNormal).length(), 0.0f, 1e-5f);
  EXPECT_NEAR(h.dist, worldNormal.dot(worldPoint), 1e-2f);
  // The point trace of the same move hits the same polygon with the same plane.
  QueryWork work;
  const TraceResult t = translate(m, {nullptr, {}, from, to, contents::kMaskSolid, placed, false}, work);
  ASSERT_LT(t.fraction, 1.0f);
  EXPECT_EQ(t.contact.modelFeature, h.polygon);
  EXPECT_EQ(t.contact.normal, h.normal);
  EXPECT_EQ(t.contact.dist, h.dist);
}

TEST(RayIndex, EveryElementOfThePlacementsAxisCounts) {
  // An axis that differs from the identity in one element rotates the rays:
  // each cast answers as a cast of its ray put in the model's space by hand
  // (axis * (p - origin), the same float operations), the normal turned
  // back into the world. Three rays, through the box's faces x = 64, y = 64
  // and z = -16, so that every element moves some crossing (checked:
  // a cast that ignored the element would answer otherwise). A -0 where the
  // identity has 0 is the identity.
  const CollisionModel m = floorBox();
  const RayIndex index(m);
  const Vec3 origin{3, -5, 2};
  const Vec3 rays[3][2] = {
      {{100, 5, -8}, {0, -3, -6}}, {{4, 100, -7}, {-2, 0, -9}}, {{6, 3, -60}, {-5, 2, -8}}};
  for (int element = 0; element < 9; ++element) {
    for (const Real value : {Real(0.0625), Real(-0.0)}) {
      Placement placed;
      placed.origin = origin;
      const bool diagonal = element / 3 == element % 3;
      placed.axis.rows[element / 3][element % 3] = diagonal ? Real(1) - value : value;
      SCOPED_TRACE(testing::Message() << "element " << element << " value " << value);
      bool moved = false;
      for (const auto& [from, to] : rays) {
        const RayHit h = index.cast({from, to, contents::kMaskSolid, placed});
        const RayHit local = index.cast({placed.axis * (from - origin), placed.axis * (to - origin)});
        const RayHit unturned = index.cast({from - origin, to - origin});
        ASSERT_TRUE(local.hit());
        EXPECT_EQ(h.fraction, local.fraction);
        EXPECT_EQ(h.polygon, local.polygon);
        EXPECT_EQ(h.normal, local.normal * placed.axis);
        moved |= h.fraction != unturned.fraction;
      }
      EXPECT_EQ(moved, value != 0) << "no ray's crossing moved with the element";
    }
  }
}

TEST(RayIndex, BadInputMisses) {
  const RayIndex index(floorBox());
  const Real nan = std::numeric_limits<Real>::quiet_NaN(), inf = std::numeric_limits<Real>::infinity();
  EXPECT_FALSE(index.cast({{0, 0, 8}, {0, 0, 8}}).hit());  // no movement
  EXPECT_FALSE(index.cast({{nan, 0, 8}, {0, 0, -8}}).hit());
  EXPECT_FALSE(index.cast({{0, 0, 8}, {0, inf, -8}}).hit());
  ModelArrays nothing;
  nothing.nodes.emplace_back();  // one empty leaf
  const ModelPtr empty = *CollisionModel::create(std::move(nothing));
  EXPECT_FALSE(RayIndex(*empty).cast({{0, 0, 8}, {0, 0, -8}}).hit());
  EXPECT_EQ(RayIndex(*empty).numNodes(), 0u);
}

TEST(RayIndex, NegativeZeroDirectionsHit) {
  // end - start is -0 on an axis when the start is +0 and the end -0 there:
  // the ray does not move along that axis, whichever zero it is, and must
  // cross the floor as the +0 ray does (with both node tests).
  const CollisionModel m = floorBox();
  for (const RayIndex::NodeTest test : {RayIndex::NodeTest::Auto, RayIndex::NodeTest::Baseline}) {
    const RayIndex index(m, test);
    for (int axis = 0; axis < 2; ++axis) {
      Vec3 start{0, 0, 64}, end{0, 0, -64};
      end[axis] = -0.0f;
      ASSERT_TRUE(std::signbit((end - start)[axis]));
      const RayHit h = index.cast({start, end});
      ASSERT_TRUE(h.hit()) << "axis " << axis;
      EXPECT_EQ(h.fraction, 0.5f);
      EXPECT_EQ(h.polygon, polygonWithNormal(m, {0, 0, 1}));
      // castMany walks packets (AVX2) or single casts: the same answer.
      RayHit many[2];
      const Vec3 starts[2] = {start, start}, ends[2] = {end, end};
      index.castMany({{}, starts, ends}, many);
      EXPECT_EQ(many[0].polygon, h.polygon);
      EXPECT_EQ(many[1].fraction, h.fraction);
    }
  }
}

TEST(RayIndex, SameAsTestingEveryPolygonOnBundledMaps) {
  // lt4's world (11 489 polygons) and its inline models, the feature test
  // map, and the .cm files of the test data.
  std::vector<ModelPtr> models = test::buildMapModels(bundledLt4());
  ASSERT_FALSE(models.empty());
  models.resize(std::min<std::size_t>(models.size(), 12));
  for (const auto& m : test::buildMapModels(test::testDataDir() / "maps" / "features.map"))
    models.push_back(m);
  for (const char* cm : {"opentechbfg_test.cm", "blender_misc_model1.cm"}) {
    auto loaded = loadCmFile((test::testDataDir() / "cm" / cm).string(), MaterialTable{});
    ASSERT_TRUE(loaded.ok()) << (loaded.ok() ? "" : loaded.error().toString());
    for (const auto& m : loaded->models) models.push_back(m);
  }
  unsigned seed = 1;
  int rays = 0, hits = 0;
  for (const ModelPtr& m : models) {
    if (m->polygons().empty()) continue;
    const int count = m->polygons().size() > 1000 ? 6000 : 600;
    rays += count;
    // Both node tests (the same one twice where the processor has no AVX2).
    hits += expectSameAsEveryPolygon(*m, seed, count, m->name(), RayIndex::NodeTest::Auto);
    expectSameAsEveryPolygon(*m, seed++, count, m->name() + " (baseline node test)",
                             RayIndex::NodeTest::Baseline);
  }
  EXPECT_GT(hits, rays / 10) << "too few hits for the comparison to mean much";
}

TEST(RayIndex, BothNodeTestsGiveTheSameAnswers) {
  // The AVX2 and the SSE2 (or portable) node tests walk the same hierarchy
  // with the same arithmetic: every field of every answer is the same.
  const auto models = test::buildMapModels(bundledLt4());
  ASSERT_FALSE(models.empty());
  const CollisionModel& world = *models.front();
  const RayIndex best(world), baseline(world, RayIndex::NodeTest::Baseline);
  EXPECT_FALSE(baseline.usesAvx2());
  if (!best.usesAvx2()) GTEST_SKIP() << "this processor (or build) has no AVX2: there is one node test only";
  int hits = 0;
  for (const auto& [s, e] : randomSegments(world.bounds(), 17, 20000)) {
    const RayHit a = best.cast({s, e}), b = baseline.cast({s, e});
    ASSERT_EQ(a.polygon, b.polygon);
    ASSERT_EQ(std::memcmp(&a.fraction, &b.fraction, sizeof(Real)), 0);
    ASSERT_EQ(a.point, b.point);
    ASSERT_EQ(a.normal, b.normal);
    ASSERT_EQ(a.material, b.material);
    hits += a.hit();
  }
  EXPECT_GT(hits, 2000);
}

// Every field of two hits, bit for bit.
void expectSameHit(const RayHit& a, const RayHit& b, std::size_t i) {
  ASSERT_EQ(a.polygon, b.polygon) << "ray " << i;
  ASSERT_EQ(std::memcmp(&a.fraction, &b.fraction, sizeof(Real)), 0) << "ray " << i;
  ASSERT_EQ(std::memcmp(&a.dist, &b.dist, sizeof(Real)), 0) << "ray " << i;
  ASSERT_EQ(a.point, b.point) << "ray " << i;
  ASSERT_EQ(a.normal, b.normal) << "ray " << i;
  ASSERT_EQ(a.material, b.material) << "ray " << i;
  ASSERT_EQ(a.contents, b.contents) << "ray " << i;
}

TEST(RayIndex, CastManyGivesWhatEachCastGives) {
  // castMany sorts the rays and (with AVX2) walks them in packets of eight
  // with its own slab test: the answers must still be cast()'s, bit for bit.
  // Sensor-like rays from one point (coherent packets) and rays from
  // everywhere, the model placed and turned, both node tests.
  const auto models = test::buildMapModels(bundledLt4());
  ASSERT_FALSE(models.empty());
  const CollisionModel& world = *models.front();
  const Vec3 centre = (world.bounds().min + world.bounds().max) * Real(0.5);
  std::mt19937 rng(23);
  std::uniform_real_distribution<float> unit(-1, 1);
  const std::size_t n = 20000;
  std::vector<Vec3> oneStart{centre}, starts, ends;
  for (std::size_t i = 0; i < n; ++i)
    ends.push_back(centre + Vec3{unit(rng), unit(rng), unit(rng)} * Real(1024));
  for (const auto& [s, e] : randomSegments(world.bounds(), 29, int(n))) starts.push_back(s);
  ends.push_back(centre);  // the last ray has no length (a miss) in both sets
  starts.push_back(centre);
  const std::size_t total = ends.size();
  Placement placed;
  placed.origin = {100, -50, 25};
  placed.axis = Mat3::fromAxisAngle({0, 0, 1}, Real(0.5));
  for (const RayIndex::NodeTest test : {RayIndex::NodeTest::Auto, RayIndex::NodeTest::Baseline}) {
    const RayIndex index(world, test);
    for (const Placement& placement : {Placement{}, placed}) {
      for (const std::vector<Vec3>* from : {&oneStart, &starts}) {
        std::vector<RayHit> many(total);
        index.castMany({{{}, {}, contents::kMaskSolid, placement}, *from, ends}, many);
        int hits = 0;
        for (std::size_t i = 0; i < total; ++i) {
          const Vec3& s = from->size() == 1 ? (*from)[0] : (*from)[i];
          expectSameHit(many[i], index.cast({s, ends[i], contents::kMaskSolid, placement}), i);
          if (::testing::Test::HasFatalFailure()) return;
          hits += many[i].hit();
        }
        EXPECT_GT(hits, int(n) / 4);
        EXPECT_FALSE(many.back().hit());
      }
    }
  }
}

TEST(RayIndex, TwoSidedSurfacesSameAsTestingEveryPolygon) {
  // A two-sided surface is pairs of a polygon and its reversed twin, which
  // the index tests in one lane (RayLayout::LeafHead::twins): a rough
  // two-sided terrain with one-sided boxes on it, single casts against
  // testing every polygon with both node tests, and castMany against cast.
  constexpr int kCells = 24;
  std::mt19937 rng(41);
  const ModelPtr model = test::twoSidedTerrainModel(kCells, rng);
  ASSERT_TRUE(model);
  const CollisionModel& m = *model;
  ASSERT_GT(m.polygons().size(), std::size_t(4 * kCells * kCells));
  const int hits = expectSameAsEveryPolygon(m, 43, 20000, "two-sided terrain", RayIndex::NodeTest::Auto);
  expectSameAsEveryPolygon(m, 43, 20000, "two-sided terrain (baseline node test)",
                           RayIndex::NodeTest::Baseline);
  EXPECT_GT(hits, 2000);
  // Hits from below the terrain (its twins) as well as from above.
  std::vector<Vec3> starts, ends;
  std::uniform_real_distribution<float> unit(0, 1);
  for (int i = 0; i < 4000; ++i) {
    const Real x = unit(rng) * kCells * 32, y = unit(rng) * kCells * 32;
    const Real from = i % 2 ? Real(-100) : Real(100);
    starts.push_back({x, y, from});
    ends.push_back({x + unit(rng) * 64 - 32, y + unit(rng) * 64 - 32, -from});
  }
  for (const RayIndex::NodeTest test : {RayIndex::NodeTest::Auto, RayIndex::NodeTest::Baseline}) {
    const RayIndex index(m, test);
    std::vector<RayHit> many(starts.size());
    index.castMany({{{}, {}, contents::kMaskSolid, {}}, starts, ends}, many);
    int up = 0, down = 0;
    for (std::size_t i = 0; i < starts.size(); ++i) {
      expectSameHit(many[i], index.cast({starts[i], ends[i], contents::kMaskSolid}), i);
      if (::testing::Test::HasFatalFailure()) return;
      const BruteHit slow = castEveryPolygon(m, starts[i], ends[i], contents::kMaskSolid);
      ASSERT_EQ(many[i].polygon, slow.polygon) << "ray " << i;
      up += many[i].hit() && many[i].normal.z > 0;
      down += many[i].hit() && many[i].normal.z < 0;
    }
    EXPECT_GT(up, 1000);
    EXPECT_GT(down, 1000);
  }
}

TEST(RayIndex, RaysAlongEdgeLinesSameAsTestingEveryPolygon) {
  // Rays whose lines meet the boxes' edge lines exactly: the product of the
  // two lines is zero, and its sign bit (the original's answer) depends on
  // the exact terms. The index makes each edge's line from the polygon's
  // corners, and where a product is zero from the edge's stored direction:
  // single casts, castMany's packets (both node tests) and testing every
  // polygon must agree on every ray. Boxes on a grid of 16 units, rays
  // between grid points (vertical ones along the boxes' vertical edges and
  // through their top edges, slanted and level ones), castMany sorting
  // them into packets.
  test::ModelMaker maker;
  for (int x = 0; x < 4; ++x)
    for (int y = 0; y < 4; ++y)
      if ((x + y) % 2 == 0)
        maker.addBox(
            {{Real(32 * x), Real(32 * y), 0}, {Real(32 * x + 16), Real(32 * y + 16), Real(16 + 8 * x)}});
  const CollisionModel m = maker.build();
  std::vector<Vec3> starts, ends;
  for (int x = -1; x <= 16; ++x)
    for (int y = -1; y <= 16; ++y) {
      const Vec3 top{Real(8 * x), Real(8 * y), 64};
      starts.push_back(top);
      ends.push_back({top.x, top.y, -16});  // straight down
      starts.push_back(top);
      ends.push_back({top.x + 16, top.y, -16});  // slanted, between grid points
      starts.push_back({top.x, top.y, 8});
      ends.push_back({top.x + 64, top.y, 8});  // level, along the boxes' sides
    }
  int zeroProducts = 0;  // rays meeting some edge's line of the model exactly
  for (std::size_t i = 0; i < starts.size(); ++i) {
    const Pluecker ray = Pluecker::fromRay(starts[i], ends[i] - starts[i]);
    bool meets = false;
    for (const CmPolygon& p : m.polygons())
      for (std::int32_t e : m.edgesOf(p)) {
        const CmEdge& edge = m.edges()[std::size_t(std::abs(e))];
        meets |= Pluecker::fromLine(m.vertices()[std::size_t(edge.vertex[0])],
                                    m.vertices()[std::size_t(edge.vertex[1])])
                     .permutedInnerProduct(ray) == 0;
      }
    zeroProducts += meets;
  }
  EXPECT_GT(zeroProducts, int(starts.size()) / 2);
  int hits = 0;
  for (const RayIndex::NodeTest test : {RayIndex::NodeTest::Auto, RayIndex::NodeTest::Baseline}) {
    const RayIndex index(m, test);
    std::vector<RayHit> many(starts.size());
    index.castMany({{{}, {}, contents::kMaskSolid, {}}, starts, ends}, many);
    for (std::size_t i = 0; i < starts.size(); ++i) {
      const RayHit one = index.cast({starts[i], ends[i], contents::kMaskSolid});
      expectSameHit(many[i], one, i);
      if (::testing::Test::HasFatalFailure()) return;
      const BruteHit slow = castEveryPolygon(m, starts[i], ends[i], contents::kMaskSolid);
      ASSERT_EQ(one.polygon, slow.polygon) << "ray " << i;
      EXPECT_EQ(std::memcmp(&one.fraction, &slow.fraction, sizeof(Real)), 0) << "ray " << i;
      hits += one.hit();
    }
  }
  EXPECT_GT(hits, int(starts.size()) / 4);
}

TEST(RayIndex, CastManyLeavesMismatchedSpansAlone) {
  const RayIndex index(floorBox());
  const std::vector<Vec3> two{{0, 0, 8}, {1, 0, 8}}, three{{0, 0, -8}, {1, 0, -8}, {2, 0, -8}};
  std::vector<RayHit> out(3);
  out[0].polygon = 77;
  const RayCastQuery all{{}, {}, kAll, {}};
  index.castMany({all, two, three}, out);  // 2 starts for 3 rays
  EXPECT_EQ(out[0].polygon, 77);
  const std::vector<Vec3> one{{0, 0, 8}};
  index.castMany({all, one, three}, out);  // one start for all
  for (const RayHit& h : out) EXPECT_TRUE(h.hit());
  EXPECT_EQ(out[2].point, (Vec3{1, 0, 0}));  // (0,0,8) -> (2,0,-8) crosses z = 0 halfway
  index.castMany({all, {}, {}}, {});         // nothing to do
}

TEST(RayIndex, PointTranslationStopsNoLater) {
  // Wherever the ray crosses a surface, the point trace of the same move
  // (which stops 0.25 in front of surfaces, and also at ones it only comes
  // near) stops at a fraction no larger; where the point trace passes, so
  // does the ray. Most hits are on the same polygon.
  const auto models = test::buildMapModels(bundledLt4());
  ASSERT_FALSE(models.empty());
  const CollisionModel& world = *models.front();
  const RayIndex index(world);
  QueryWork work;
  int bothHit = 0, samePolygon = 0;
  for (const auto& [s, e] : randomSegments(world.bounds(), 11, 6000)) {
    const RayHit ray = index.cast({s, e});
    const TraceResult point = translate(world, {nullptr, {}, s, e, contents::kMaskSolid, {}, false}, work);
    if (!ray.hit()) continue;
    ASSERT_LT(point.fraction, 1.0f) << "the ray hit, the point trace passed";
    EXPECT_LE(point.fraction, ray.fraction * 1.0001f + 1e-6f);
    ++bothHit;
    samePolygon += point.contact.modelFeature == ray.polygon;
  }
  ASSERT_GT(bothHit, 500);
  // Grazing approaches stop the point trace at another polygon's epsilon
  // band first; that is rare (0.3 % on lt4).
  EXPECT_GT(samePolygon, bothHit * 98 / 100);
}

TEST(RayIndex, SameResultsFromManyThreads) {
  const auto models = test::buildMapModels(bundledLt4());
  ASSERT_FALSE(models.empty());
  const RayIndex index(*models.front());
  const auto segments = randomSegments(models.front()->bounds(), 5, 4000);
  std::vector<RayHit> single;
  for (const auto& [s, e] : segments) single.push_back(index.cast({s, e}));
  std::vector<std::vector<RayHit>> perThread(3);
  std::vector<std::thread> threads;
  for (auto& out : perThread)
    threads.emplace_back([&] {
      for (const auto& [s, e] : segments) out.push_back(index.cast({s, e}));
    });
  for (auto& t : threads) t.join();
  for (const auto& out : perThread) {
    ASSERT_EQ(out.size(), single.size());
    for (std::size_t i = 0; i < out.size(); ++i) {
      EXPECT_EQ(out[i].polygon, single[i].polygon);
      EXPECT_EQ(std::memcmp(&out[i].fraction, &single[i].fraction, sizeof(Real)), 0);
    }
  }
}
