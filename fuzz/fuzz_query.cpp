// Fuzz target: query-file lines (spec/query-format.md) parsed against a small
// built model and run, results formatted.
#include <memory>

#include "cmkit/build.h"
#include "cmkit/map.h"
#include "cmkit/query_file.h"
#include "fuzz_common.h"

namespace {

/// A closed room with a pillar, water and a clip brush, built once.
const std::vector<cmkit::ModelPtr>& roomModels() {
  static const std::vector<cmkit::ModelPtr> models = [] {
    const char* text =
        "Version 2\n{\n\"classname\" \"worldspawn\"\n"
        "{\nbrushDef3\n{\n( 0 0 1 0 ) ( ( 1 0 0 ) ( 0 1 0 ) ) \"textures/a\" 0 0 0\n"
        "( 0 0 -1 -16 ) ( ( 1 0 0 ) ( 0 1 0 ) ) \"textures/a\" 0 0 0\n"
        "( 1 0 0 -256 ) ( ( 1 0 0 ) ( 0 1 0 ) ) \"textures/a\" 0 0 0\n"
        "( -1 0 0 -256 ) ( ( 1 0 0 ) ( 0 1 0 ) ) \"textures/a\" 0 0 0\n"
        "( 0 1 0 -256 ) ( ( 1 0 0 ) ( 0 1 0 ) ) \"textures/a\" 0 0 0\n"
        "( 0 -1 0 -256 ) ( ( 1 0 0 ) ( 0 1 0 ) ) \"textures/a\" 0 0 0\n}\n}\n"
        "{\nbrushDef3\n{\n( 0 0 1 -64 ) ( ( 1 0 0 ) ( 0 1 0 ) ) \"textures/a\" 0 0 0\n"
        "( 0 0 -1 0 ) ( ( 1 0 0 ) ( 0 1 0 ) ) \"textures/a\" 0 0 0\n"
        "( 1 0 0 -32 ) ( ( 1 0 0 ) ( 0 1 0 ) ) \"textures/a\" 0 0 0\n"
        "( -1 0 0 -32 ) ( ( 1 0 0 ) ( 0 1 0 ) ) \"textures/a\" 0 0 0\n"
        "( 0 1 0 -32 ) ( ( 1 0 0 ) ( 0 1 0 ) ) \"textures/a\" 0 0 0\n"
        "( 0 -1 0 -32 ) ( ( 1 0 0 ) ( 0 1 0 ) ) \"textures/a\" 0 0 0\n}\n}\n}\n"
        "{\n\"classname\" \"func_static\"\n\"name\" \"door\"\n\"origin\" \"100 0 0\"\n"
        "{\nbrushDef3\n{\n( 0 0 1 -96 ) ( ( 1 0 0 ) ( 0 1 0 ) ) \"textures/common/player_clip\" 0 0 0\n"
        "( 0 0 -1 0 ) ( ( 1 0 0 ) ( 0 1 0 ) ) \"textures/common/player_clip\" 0 0 0\n"
        "( 1 0 0 -4 ) ( ( 1 0 0 ) ( 0 1 0 ) ) \"textures/common/player_clip\" 0 0 0\n"
        "( -1 0 0 -4 ) ( ( 1 0 0 ) ( 0 1 0 ) ) \"textures/common/player_clip\" 0 0 0\n"
        "( 0 1 0 -48 ) ( ( 1 0 0 ) ( 0 1 0 ) ) \"textures/common/player_clip\" 0 0 0\n"
        "( 0 -1 0 -48 ) ( ( 1 0 0 ) ( 0 1 0 ) ) \"textures/common/player_clip\" 0 0 0\n}\n}\n}\n";
    auto map = cmkit::parseMapText(text, "room.map");
    if (!map) std::abort();
    auto built = cmkit::buildCollisionModels(*map, cmkit::MaterialTable{});
    if (!built) std::abort();
    return std::move(*built);
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
