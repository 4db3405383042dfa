// hello_trace: load a map, drop a player-sized box onto the floor and print
// where it stopped. Every call that can fail returns a cmkit::Result, and
// every Result is checked before it is used.
//
//   hello_trace [MAP]   (default: the bundled data/maps/lt4/lt4.map)
#include <cmkit/compile.h>
#include <cmkit/map.h>
#include <cmkit/materials.h>
#include <cmkit/query.h>

#include <cstdio>
#include <string>

int main(int argc, char** argv) {
  const std::string path = argc > 1 ? argv[1] : CMKIT_EXAMPLE_MAP;

  auto map = cmkit::loadMapFile(path);  // Result<MapFile>: file:line errors
  if (!map) {
    std::fprintf(stderr, "hello_trace: %s\n", map.error().toString().c_str());
    return 1;
  }
  const cmkit::MaterialTable materials;                       // no .mtr files: the default rules
  auto built = cmkit::buildCollisionModels(*map, materials);  // one immutable model per entity
  if (!built || built->models.empty()) {
    std::fprintf(stderr, "hello_trace: %s\n",
                 built ? "the map has no models" : built.error().toString().c_str());
    return 1;
  }
  const std::vector<cmkit::ModelPtr>& models = built->models;  // built->warnings: what the build skipped
  auto box = cmkit::TraceModel::box({{-16, -16, 0}, {16, 16, 72}});  // a player's bounds
  if (!box) {
    std::fprintf(stderr, "hello_trace: %s\n", box.error().toString().c_str());
    return 1;
  }

  cmkit::QueryWork work;  // scratch memory: one per thread, reusable
  cmkit::TranslationQuery q;
  q.trm = &*box;
  q.start = {1548, -734, -144};
  q.end = {1548, -734, -656};  // 512 units straight down
  const cmkit::TraceResult r = cmkit::translate(*models[0], q, work);
  if (r.status != cmkit::QueryStatus::Ok) {
    std::fprintf(stderr, "hello_trace: query refused: %s\n", cmkit::toString(r.status));
    return 1;
  }

  std::printf("model %s: %zu polygons\n", models[0]->name().c_str(), models[0]->polygons().size());
  std::printf("fraction %.6f\n", double(r.fraction));
  std::printf("end      %.3f %.3f %.3f\n", double(r.endPos.x), double(r.endPos.y), double(r.endPos.z));
  if (r.fraction < 1) {
    const cmkit::Vec3& n = r.contact.normal;
    std::printf("normal   %.3f %.3f %.3f (material %s)\n", double(n.x), double(n.y), double(n.z),
                std::string(models[0]->materialName(r.contact.material)).c_str());
  } else {
    std::printf("no contact\n");
  }
  return 0;
}
