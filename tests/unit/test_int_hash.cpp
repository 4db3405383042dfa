// The build's edge table (src/compile/int_hash.h): what it maps, in both of
// its layouts, and that a real mesh's edges keep the near layout (a
// scattered table makes every lookup a cache miss: lt4's world as triangles
// scattered it, and every edge lookup of its build was then a cache miss).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <unordered_map>
#include <vector>

#include "cmkit/contents.h"
#include "cmkit/materials.h"
#include "cmkit/mesh.h"
#include "cmkit/model.h"
#include "compile/builder.h"  // edgeKey, ModelBuilder
#include "compile/int_hash.h"
#include "model/material_cache.h"
#include "test_support.h"

namespace cmkit {
namespace {

using detail::edgeKey;
using detail::IntHashMap;

/// Inserts every key of `keys` (value: its position) and checks that each
/// is found with its value, that keys never inserted are not, and that
/// inserting a key again finds its value instead of adding it.
void expectMapsEveryKey(IntHashMap& map, const std::vector<std::uint64_t>& keys) {
  std::unordered_map<std::uint64_t, int> expected;
  for (const std::uint64_t key : keys) {
    int& value = map.at(key);
    const auto [it, added] = expected.emplace(key, int(expected.size()));
    if (added) {
      ASSERT_EQ(value, IntHashMap::kEmpty) << "new key " << key;
      value = it->second;
    } else {
      ASSERT_EQ(value, it->second) << "key " << key << " inserted again";
    }
  }
  for (const auto& [key, value] : expected) ASSERT_EQ(map.find(key), value) << "key " << key;
  std::mt19937_64 rng(7);
  for (int i = 0; i < 2000; ++i) {
    const std::uint64_t key = rng();
    if (!expected.count(key)) {
      EXPECT_EQ(map.find(key), IntHashMap::kEmpty);
    }
  }
}

TEST(IntHashMap, MapsEveryKeyNearAndScattered) {
  // Mesh-like keys (a few per high half, high halves dense), growing from empty.
  std::mt19937 rng(1);
  std::vector<std::uint64_t> near;
  for (int v = 0; v < 20000; ++v)
    for (int k = 0, n = int(rng() % 7); k < n; ++k) near.push_back(edgeKey(v, int(rng() % 30000)));
  IntHashMap grown;
  expectMapsEveryKey(grown, near);
  EXPECT_FALSE(grown.scattered());

  // One high half with thousands of keys (a vertex at the centre of a huge
  // fan): the insertions probe past the limit, the keys are scattered, and
  // the map still holds every one, those inserted before and after.
  std::vector<std::uint64_t> crowd = near;
  for (int k = 0; k < 5000; ++k) crowd.push_back(edgeKey(123, 100000 + k));
  for (int v = 20000; v < 21000; ++v) crowd.push_back(edgeKey(v, v + 1));
  IntHashMap scattered;
  scattered.reserve(crowd.size() / 4);  // (grows on the way too)
  expectMapsEveryKey(scattered, crowd);
  EXPECT_TRUE(scattered.scattered());

  // Cleared, it starts near again.
  scattered.clear();
  EXPECT_FALSE(scattered.scattered());
  EXPECT_EQ(scattered.find(near.front()), IntHashMap::kEmpty);
  expectMapsEveryKey(scattered, near);
}

TEST(IntHashMap, KeepsTheEdgesOfLt4AsTrianglesNear) {
  // lt4's world model as triangles, as cmkit_peers builds it (every solid or
  // playerclip polygon as a fan over its vertices, two-sided), through the
  // mesh build itself: its edge table must keep the near layout. Before, an
  // insertion probed past the limit and the table was scattered: with the
  // old limit (64) in float builds, and in double builds (a model of slightly
  // fewer triangles: a table half as large, fuller) with homes eight slots a
  // vertex whatever the table's size, which wrapped round it.
  const std::vector<ModelPtr> models = test::buildMapModels(test::dataFile("maps/lt4/lt4.map"));
  ASSERT_FALSE(models.empty());
  const CollisionModel& world = *models.front();
  TriangleMesh mesh;
  mesh.positions.assign(world.vertices().begin(), world.vertices().end());
  MeshSurface surface{"textures/test/twosided", {}};
  constexpr std::uint32_t kMask = contents::kSolid | contents::kPlayerClip;  // (cmkit_peers' polygons)
  std::vector<std::uint32_t> corners;
  for (const CmPolygon& p : world.polygons()) {
    if (!(p.contents & kMask)) continue;
    corners.clear();
    for (const std::int32_t e : world.edgesOf(p)) corners.push_back(std::uint32_t(world.edgeStart(e)));
    for (std::size_t k = 1; k + 1 < corners.size(); ++k)
      surface.indices.insert(surface.indices.end(), {corners[0], corners[k], corners[k + 1]});
  }
  mesh.surfaces.push_back(std::move(surface));
  EXPECT_GT(mesh.surfaces[0].indices.size(), 3u * 20000u);
  MaterialTable materials;
  materials.addMtrText("textures/test/twosided { twosided }\n", "test.mtr");
  detail::MaterialCache cache(materials);
  std::vector<std::string> warnings;
  detail::ModelBuilder builder(mesh, "lt4 as triangles", cache, &warnings);
  const ModelPtr built = builder.build();
  ASSERT_TRUE(built);
  EXPECT_GT(built->edges().size(), 40000u);
  EXPECT_FALSE(builder.edgeTableScattered());
}

}  // namespace
}  // namespace cmkit
