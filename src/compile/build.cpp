// buildCollisionModels: one collision model per map entity with primitives,
// and the steps that build one (ModelBuilder::build).
#include "cmkit/compile.h"

#include "cmkit/cm_file.h"
#include "compile/builder.h"
#include "model/model_access.h"

namespace cmkit {

namespace detail {

ModelPtr ModelBuilder::build() {
  allocNode();  // the root
  if (mesh_) {
    // A render model: triangles -> polygons (welded, shared edges) in the
    // root, then the axial BSP tree over them (triangles.cpp).
    convertMeshSurfaces();
  } else {
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
  }
  mergePolygons();
  // Robust edges, maps only: T-junctions between coplanar polygons split, so
  // that their seams are shared edges (t_junctions.cpp; not the original's).
  if (robustEdges_ && !mesh_) splitPolygonsAtTJunctions();
  markInternalEdges();
  // The immutable layout: compacted arrays, the tree flattened in pre-order.
  ModelArrays model;
  model.name = name_;
  const Remap remap = compactVerticesAndEdges(model);
  flattenTree(model, remap);
  finishModel(model);
  return ModelAccess::seal(std::move(model));
}

/// Error for the first brush of `entity` with more than kMaxBrushSides sides.
Status checkBrushSizes(const MapEntity& entity, const std::string& fileName) {
  for (std::size_t i = 0; i < entity.primitives.size(); ++i) {
    const auto* brush = std::get_if<MapBrush>(&entity.primitives[i]);
    if (!brush || brush->sides.size() <= kMaxBrushSides) continue;
    return Error("brush (primitive " + std::to_string(i) + ") has " + std::to_string(brush->sides.size()) +
                     " sides; at most " + std::to_string(kMaxBrushSides) +
                     " are supported (building a brush clips every side by every other)",
                 fileName, brush->line);
  }
  return Ok{};
}

}  // namespace detail

Result<BuildResult> buildCollisionModels(const MapFile& map, const MaterialTable& materials,
                                         const BuildOptions& options) {
  BuildResult result;
  std::vector<ModelPtr>& models = result.models;
  detail::MaterialCache cache(materials);
  const std::size_t total = map.entities.size();
  for (std::size_t i = 0; i < total; ++i) {
    const MapEntity& entity = map.entities[i];
    if (Status st = detail::checkBrushSizes(entity, map.fileName); !st) return st.error();
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
      detail::ModelBuilder builder(entity, std::move(name), cache, &result.warnings, proc);
      builder.setRobustEdges(options.robustEdges);
      models.push_back(builder.build());
    }
    if (options.progress) options.progress(i + 1, total);
  }
  return result;
}

Result<EntityModelReport> writeCollisionModelForMapEntity(const MapFile& map, std::size_t entityIndex,
                                                          const std::string& path,
                                                          const MaterialTable& materials,
                                                          const EntityModelOptions& options) {
  if (entityIndex >= map.entities.size())
    return Error("no entity #" + std::to_string(entityIndex) + ": the map has " +
                     std::to_string(map.entities.size()) + " entities",
                 map.fileName);
  const MapEntity& entity = map.entities[entityIndex];
  if (entity.primitives.empty()) {
    const auto name = entity.value("name");
    return Error("entity #" + std::to_string(entityIndex) + (name ? " \"" + std::string(*name) + "\"" : "") +
                     " has no brushes or patches: it has no collision model",
                 map.fileName, entity.line);
  }
  if (Status st = detail::checkBrushSizes(entity, map.fileName); !st) return st.error();
  EntityModelReport report;
  detail::MaterialCache cache(materials);
  detail::ModelBuilder builder(entity, path, cache, &report.warnings);
  builder.setRobustEdges(options.robustEdges);
  report.model = builder.build();
  if (options.testTraceModel) report.traceModel = traceModelFromCollisionModel(*report.model);
  if (Status saved = saveCmFile(path, std::span<const ModelPtr>(&report.model, 1), 0); !saved)
    return saved.error();
  return report;
}

}  // namespace cmkit
