// placed_models: a ModelManager holding a map's models, one entity model
// placed somewhere else in the world (moved and turned), and a box traced
// against it. Entity models are built in their entity's own frame; a query's
// Placement puts them in the world.
//
//   placed_models [MAP]   (default: the bundled data/maps/lt4/lt4.map)
#include <cmkit/manager.h>
#include <cmkit/materials.h>
#include <cmkit/query.h>

#include <cstdio>
#include <string>

namespace {

// Drops `box` from above the placed model's centre straight down through it.
cmkit::TraceResult dropOnto(const cmkit::CollisionModel& model, const cmkit::Placement& placement,
                            const cmkit::TraceModel& box, cmkit::QueryWork& work) {
  const cmkit::Vec3 centre = placement.origin + model.bounds().center() * placement.axis;  // body -> world
  const cmkit::Real reach = 512;
  cmkit::TranslationQuery q;
  q.trm = &box;
  q.start = centre + cmkit::Vec3{0, 0, reach};
  q.end = centre - cmkit::Vec3{0, 0, reach};
  q.placement = placement;
  return cmkit::translate(model, q, work);
}

}  // namespace

int main(int argc, char** argv) {
  const std::string path = argc > 1 ? argv[1] : CMKIT_EXAMPLE_MAP;
  cmkit::ModelManager manager;
  auto loaded = manager.loadMap(path, cmkit::MaterialTable{});
  if (!loaded) {
    std::fprintf(stderr, "placed_models: %s\n", loaded.error().toString().c_str());
    return 1;
  }
  std::printf("%zu models loaded\n", manager.size());
  if (loaded->handles.size() < 2) {
    std::fprintf(stderr, "placed_models: the map has no entity models\n");
    return 1;
  }
  auto model = manager.require(loaded->handles[1]);  // the first entity model
  if (!model) {
    std::fprintf(stderr, "placed_models: %s\n", model.error().toString().c_str());
    return 1;
  }
  const cmkit::CollisionModel& m = **model;
  std::printf("entity model \"%s\": %zu polygons, bounds (%g %g %g)-(%g %g %g)\n", m.name().c_str(),
              m.polygons().size(), double(m.bounds().min.x), double(m.bounds().min.y),
              double(m.bounds().min.z), double(m.bounds().max.x), double(m.bounds().max.y),
              double(m.bounds().max.z));

  auto box = cmkit::TraceModel::box({{-8, -8, -8}, {8, 8, 8}});
  if (!box) {
    std::fprintf(stderr, "placed_models: %s\n", box.error().toString().c_str());
    return 1;
  }
  cmkit::QueryWork work;
  const cmkit::Placement places[] = {
      {{0, 0, 0}, cmkit::Mat3::identity()},                     // where the map built it
      {{4096, 4096, 1024}, cmkit::Mat3::fromAngles(0, 90, 0)},  // moved and turned 90 degrees about z
      {{-2048, 512, 0}, cmkit::Mat3::fromAngles(0, 45, 180)},   // upside down and turned 45 degrees
  };
  for (const cmkit::Placement& place : places) {
    const cmkit::TraceResult r = dropOnto(m, place, *box, work);
    if (r.status != cmkit::QueryStatus::Ok) {
      std::fprintf(stderr, "placed_models: query refused: %s\n", cmkit::toString(r.status));
      return 1;
    }
    std::printf("placed at (%g %g %g): fraction %.4f, stopped at (%.2f %.2f %.2f), normal (%.2f %.2f %.2f)\n",
                double(place.origin.x), double(place.origin.y), double(place.origin.z), double(r.fraction),
                double(r.endPos.x), double(r.endPos.y), double(r.endPos.z), double(r.contact.normal.x),
                double(r.contact.normal.y), double(r.contact.normal.z));
  }
  return 0;
}
