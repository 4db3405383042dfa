// buildCollisionModels: one collision model per map entity with primitives.
#include "cmkit/compile.h"

#include "compile/builder.h"

namespace cmkit {

Result<std::vector<ModelPtr>> buildCollisionModels(const MapFile& map, const MaterialTable& materials,
                                                   const BuildOptions& options) {
  std::vector<ModelPtr> models;
  detail::MaterialCache cache(materials);
  const std::size_t total = map.entities.size();
  for (std::size_t i = 0; i < total; ++i) {
    const MapEntity& entity = map.entities[i];
    if (!entity.primitives.empty()) {
      std::string name;
      if (auto v = entity.value("model")) {
        name = std::string(*v);
      } else if (auto n = entity.value("name")) {
        name = std::string(*n);
      } else {
        name = models.empty() ? "worldMap" : "unnamed inline model";
      }
      detail::ModelBuilder builder(entity, std::move(name), cache, options.warnings);
      models.push_back(std::make_shared<const CollisionModel>(builder.build()));
    }
    if (options.progress) options.progress(i + 1, total);
  }
  return models;
}

}  // namespace cmkit
