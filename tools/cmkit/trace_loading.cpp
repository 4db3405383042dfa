#include "trace_loading.h"

#include "cmkit/map.h"
#include "cmkit/text_file.h"

namespace cmkit::cli {
Result<std::vector<TraceRecord>> loadTraceRecords(const std::string& queriesPath,
                                                  const std::string& resultsPath) {
  if (resultsPath.empty()) {
    if (!queriesPath.empty()) return Error{"--queries needs --results (run 'cmkit query' to make one)"};
    return std::vector<TraceRecord>{};
  }
  std::string queries;
  if (!queriesPath.empty()) {
    auto text = readTextFile(queriesPath);
    if (!text) return text.error();
    queries = std::move(*text);
  }
  auto results = readTextFile(resultsPath);
  if (!results) return results.error();
  return parseTraceRecords(queries, *results);
}

ModelEntities modelEntities(const std::string& modelsPath, std::size_t numModels) {
  ModelEntities out;
  const std::string ext = ".map";
  if (modelsPath.size() < ext.size() ||
      modelsPath.compare(modelsPath.size() - ext.size(), ext.size(), ext) != 0)
    return out;
  auto map = loadMapFile(modelsPath);
  if (!map) return out;
  for (const MapEntity& e : map->entities) {
    if (e.primitives.empty()) continue;
    Placement p;
    p.origin = e.origin();
    p.axis = e.axis();
    out.placements.push_back(p);
    out.classNames.emplace_back(e.value("classname").value_or(""));
  }
  if (out.placements.size() != numModels) out = {};  // not the build's order: do not guess
  return out;
}

Result<CliScene> loadSceneForCli(const std::string& modelsPath, const std::string& materialsDir, bool noProc,
                                 const MeshCliOptions& mesh, const std::string& queriesPath,
                                 const std::string& resultsPath) {
  auto models = loadModelsForCli(modelsPath, materialsDir, noProc, mesh);
  if (!models) return models.error();
  auto traces = loadTraceRecords(queriesPath, resultsPath);
  if (!traces) return traces.error();
  CliScene scene{std::move(*models), std::move(*traces), {}, {}};
  ModelEntities entities = modelEntities(modelsPath, scene.models.size());
  scene.placements = std::move(entities.placements);
  scene.classNames = std::move(entities.classNames);
  return scene;
}

}  // namespace cmkit::cli
