// scenes.cpp: the triangles of a map's world model (lt4 by default), the
// same list for cmkit and every peer.
#include <algorithm>
#include <cstdio>

#include "cmkit/compile.h"
#include "cmkit/map.h"
#include "peers.h"

namespace peers {

void Scene::computeBounds() {
  for (int k = 0; k < 3; ++k) {
    boundsMin[k] = 1e300;
    boundsMax[k] = -1e300;
  }
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const int k = int(i % 3);
    boundsMin[k] = std::min(boundsMin[k], double(positions[i]));
    boundsMax[k] = std::max(boundsMax[k], double(positions[i]));
  }
}

Scene loadMapScene(const std::string& mapPath) {
  Scene scene;
  auto map = cmkit::loadMapFile(mapPath);
  if (!map) {
    std::fprintf(stderr, "cmkit_peers: %s\n", map.error().toString().c_str());
    return scene;
  }
  auto models = cmkit::buildCollisionModels(*map, cmkit::MaterialTable{});
  if (!models || models->models.empty()) {
    std::fprintf(stderr, "cmkit_peers: %s: no models\n", mapPath.c_str());
    return scene;
  }
  const cmkit::CollisionModel& world = *models->models.front();
  // Every polygon the player collides with, as a fan over its vertices (the
  // world model's polygons are one-sided; as a mesh every engine gets them
  // two-sided).
  constexpr std::uint32_t kMask = cmkit::contents::kSolid | cmkit::contents::kPlayerClip;
  for (const cmkit::Vec3& v : world.vertices())
    scene.positions.insert(scene.positions.end(), {v.x, v.y, v.z});
  std::vector<std::uint32_t> v;
  for (const cmkit::CmPolygon& p : world.polygons()) {
    if ((p.contents & kMask) == 0) continue;
    v.clear();
    for (std::int32_t e : world.edgesOf(p)) v.push_back(std::uint32_t(world.edgeStart(e)));
    for (std::size_t k = 1; k + 1 < v.size(); ++k)
      scene.indices.insert(scene.indices.end(), {v[0], v[k], v[k + 1]});
  }
  scene.name = mapPath.substr(mapPath.find_last_of('/') + 1) + " world model (" +
               std::to_string(world.polygons().size()) + " polygons)";
  scene.computeBounds();
  return scene;
}

}  // namespace peers
