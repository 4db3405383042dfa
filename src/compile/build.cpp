// buildCollisionModels: one collision model per map entity with primitives,
// and the steps that build one (ModelBuilder::build).
#include "cmkit/compile.h"

#include "compile/builder.h"

namespace cmkit {

namespace detail {

CollisionModel ModelBuilder::build() {
  allocNode();  // the root
  // Brushes with collision contents (bounds, contents, material), linked into the root.
  std::vector<BrushPrimitive> brushPrims = convertBrushes();
  // The axial BSP tree over the brushes (more than 4 of them), before any polygon.
  createBSPTreeForBrushes();
  prepareVertexHash();
  // Brush sides and patches -> polygons: (world model with a .proc only)
  // windings in solid leaves of the .proc BSP dropped (choppedAwayByProcBsp,
  // proc_prune.cpp), chopped by the brushes, vertices welded, edges shared,
  // each filtered into the tree.
  convertPrimitivesToPolygons(brushPrims);
  mergePolygons();
  markInternalEdges();
  // The immutable layout: compacted arrays, the tree flattened in pre-order.
  CollisionModel model;
  model.name = name_;
  const Remap remap = compactVerticesAndEdges(model);
  flattenTree(model, remap);
  finishModel(model);
  return model;
}

}  // namespace detail

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
      // The .proc BSP prunes the world model only: the original frees it
      // once the first model is built.
      const ProcBsp* proc = models.empty() ? options.procBsp : nullptr;
      detail::ModelBuilder builder(entity, std::move(name), cache, options.warnings, proc);
      models.push_back(std::make_shared<const CollisionModel>(builder.build()));
    }
    if (options.progress) options.progress(i + 1, total);
  }
  return models;
}

}  // namespace cmkit
