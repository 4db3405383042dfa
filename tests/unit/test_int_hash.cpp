// The build's edge table (src/compile/int_hash.h): what it maps, in both of
// its layouts, and that a real mesh's edges keep the near layout (a
// scattered table makes every lookup a cache miss: lt4's world as triangles
// scattered it, and every edge lookup of its build was then a cache miss).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <random>
#include <unordered_map>
#include <vector>

#include "cmkit/contents.h"
#include "cmkit/model.h"
#include "compile/builder.h"  // edgeKey
#include "compile/int_hash.h"
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
  // The edge keys the mesh build makes of lt4's world model as triangles
  // (each polygon a fan over its vertices, two-sided, as cmkit_peers builds
  // it): vertices numbered as they are first met, a triangle's directed
  // edge shared with an earlier one that uses it the other way once (its
  // reversed copy shares all three), else a new key. Before, an insertion
  // probed past the limit and the table was scattered: with the old limit
  // (64) in float builds, and in double builds (a model of slightly fewer
  // triangles: a table half as large, fuller) with homes eight slots a
  // vertex whatever the table's size, which wrapped round it.
  const std::vector<ModelPtr> models = test::buildMapModels(test::dataFile("maps/lt4/lt4.map"));
  ASSERT_FALSE(models.empty());
  const CollisionModel& world = *models.front();
  std::vector<int> number(world.vertices().size(), -1);
  int numbered = 0;
  const auto vertexNumber = [&](std::int32_t v) {
    int& n = number[std::size_t(v)];
    if (n < 0) n = numbered++;
    return n;
  };
  std::map<std::uint64_t, int> users;  // directed edge -> users of its newest edge
  IntHashMap table;
  std::size_t numIndices = 0;
  constexpr std::uint32_t kMask = contents::kSolid | contents::kPlayerClip;  // (cmkit_peers' polygons)
  for (const CmPolygon& p : world.polygons())
    if (p.contents & kMask) numIndices += 3 * std::size_t(std::max(0, int(p.numEdges) - 2));
  table.reserve(numIndices);  // as convertMeshSurfaces does
  const auto useEdge = [&](int a, int b) {
    const auto reverse = users.find(edgeKey(b, a));
    if (reverse != users.end() && reverse->second == 1) {
      reverse->second = 2;
      return;
    }
    users[edgeKey(a, b)] = 1;
    int& value = table.at(edgeKey(a, b));
    if (value == IntHashMap::kEmpty) value = int(users.size());
  };
  std::vector<int> corners;
  for (const CmPolygon& p : world.polygons()) {
    if (!(p.contents & kMask)) continue;
    corners.clear();
    for (const std::int32_t e : world.edgesOf(p)) corners.push_back(vertexNumber(world.edgeStart(e)));
    for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
      const int a = corners[0], b = corners[k], c = corners[k + 1];
      useEdge(a, b), useEdge(b, c), useEdge(c, a);
      useEdge(a, c), useEdge(c, b), useEdge(b, a);  // the reversed copy
    }
  }
  EXPECT_GT(users.size(), 40000u);
  EXPECT_FALSE(table.scattered());
}

}  // namespace
}  // namespace cmkit
