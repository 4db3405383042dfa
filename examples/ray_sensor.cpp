// ray_sensor: a fan of sensor rays cast through a RayIndex (an 8-wide
// bounding volume hierarchy over a model's polygons), printing the distance
// each ray travels before it meets a surface.
//
//   ray_sensor [MAP]   (default: the bundled data/maps/lt4/lt4.map)
#include <cmkit/compile.h>
#include <cmkit/map.h>
#include <cmkit/materials.h>
#include <cmkit/ray_index.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

int main(int argc, char** argv) {
  const std::string path = argc > 1 ? argv[1] : CMKIT_EXAMPLE_MAP;
  auto map = cmkit::loadMapFile(path);
  if (!map) {
    std::fprintf(stderr, "ray_sensor: %s\n", map.error().toString().c_str());
    return 1;
  }
  auto built = cmkit::buildCollisionModels(*map, cmkit::MaterialTable{});
  if (!built || built->models.empty()) {
    std::fprintf(stderr, "ray_sensor: %s\n",
                 built ? "the map has no models" : built.error().toString().c_str());
    return 1;
  }
  const std::vector<cmkit::ModelPtr>& models = built->models;  // built->warnings: what the build skipped

  const cmkit::RayIndex index(*models[0]);  // built once, immutable: cast() from any thread
  std::printf("indexed %zu polygons in %zu nodes (%s)\n", index.numPolygons(), index.numNodes(),
              index.usesAvx2() ? "AVX2" : "baseline");

  // Eleven rays, 18 degrees apart, in a half circle at eye height; range 2048.
  const cmkit::Vec3 eye{1548, -734, -144 + 64};
  const double range = 2048;
  int hits = 0;
  for (int i = 0; i <= 10; ++i) {
    const double angle = std::numbers::pi * i / 10;
    const cmkit::Vec3 end{eye.x + cmkit::Real(range * std::cos(angle)),
                          eye.y + cmkit::Real(range * std::sin(angle)), eye.z};
    const cmkit::RayHit h = index.cast({.start = eye, .end = end});
    if (h.hit()) {
      ++hits;
      std::printf("ray %2d at %5.1f deg: distance %7.2f, polygon %d, normal %.2f %.2f %.2f\n", i,
                  angle * 180 / std::numbers::pi, double(h.fraction) * range, h.polygon, double(h.normal.x),
                  double(h.normal.y), double(h.normal.z));
    } else {
      std::printf("ray %2d at %5.1f deg: nothing within %.0f\n", i, angle * 180 / std::numbers::pi, range);
    }
  }
  std::printf("%d of 11 rays hit\n", hits);
  return 0;
}
