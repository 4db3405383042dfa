// Fuzz target: .map text -> parser -> map compiler -> models (validated) ->
// queries.
#include "cmkit/compile.h"
#include "cmkit/map.h"
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > cmkit::fuzz::kMaxInputBytes) return 0;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  auto map = cmkit::parseMapText(text, "fuzz.map");
  if (!map) return 0;
  for (const cmkit::MapEntity& e : map->entities) {
    (void)e.origin();
    (void)e.axis();
  }
  auto models = cmkit::buildCollisionModels(*map, cmkit::MaterialTable{});
  if (!models) return 0;
  for (const cmkit::ModelPtr& m : *models) cmkit::fuzz::requireValid(*m, "the map compiler");
  cmkit::fuzz::exerciseModels(*models);
  return 0;
}
