// Fuzz target: query-file lines (spec/query-format.md) parsed against a small
// built model and run, results formatted.
#include <memory>
#include <string>
#include <vector>

#include "cmkit/compile.h"
#include "cmkit/map.h"
#include "cmkit/tools/query_format.h"
#include "fuzz_common.h"

namespace {

/// A brushDef3 box from (x0,y0,z0) to (x1,y1,z1).
std::string box(int x0, int y0, int z0, int x1, int y1, int z1, const char* material) {
  std::string s = "{\nbrushDef3\n{\n";
  auto side = [&](const char* normal, int dist) {
    s += std::string("( ") + normal + " " + std::to_string(dist) + " ) ( ( 1 0 0 ) ( 0 1 0 ) ) \"" +
         material + "\" 0 0 0\n";
  };
  side("0 0 1", -z1);
  side("0 0 -1", z0);
  side("1 0 0", -x1);
  side("-1 0 0", x0);
  side("0 1 0", -y1);
  side("0 -1 0", y0);
  return s + "}\n}\n";
}

/// A floor with a pillar (the world) and a player-clip door entity placed
/// by its origin, built once.
const std::vector<cmkit::ModelPtr>& roomModels() {
  static const std::vector<cmkit::ModelPtr> models = [] {
    const std::string text =
        "Version 2\n{\n\"classname\" \"worldspawn\"\n" + box(-256, -256, -16, 256, 256, 0, "textures/a") +
        box(-32, -32, 0, 32, 32, 64, "textures/a") +
        "}\n{\n\"classname\" \"func_static\"\n\"name\" \"door\"\n\"origin\" \"100 0 0\"\n" +
        box(-4, -48, 0, 4, 48, 96, "textures/common/player_clip") + "}\n";
    auto map = cmkit::parseMapText(text, "room.map");
    if (!map) std::abort();
    auto built = cmkit::buildCollisionModels(*map, cmkit::MaterialTable{});
    if (!built) std::abort();
    return std::move(built->models);
  }();
  return models;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > 4096) return 0;  // one line
  const std::string_view line(reinterpret_cast<const char*>(data), size);
  const auto& models = roomModels();
  if (!cmkit::isQueryLine(line)) return 0;
  auto query = cmkit::parseQueryLine(models, line);
  if (!query) return 0;
  cmkit::QueryWork work;
  (void)cmkit::runParsedQuery(models, *query, work);
  return 0;
}
