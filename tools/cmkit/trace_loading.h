// Reading the --queries / --results files of the render, export and view
// commands into trace records.
#pragma once

#include <string>
#include <vector>

#include "cmkit/query.h"
#include "cmkit/result.h"
#include "cmkit/tools/debug_draw.h"
#include "model_loading.h"

namespace cmkit::cli {

/// Reads a query file and its results file (or, with `queriesPath` empty, a
/// results file holding each query line followed by its result line).
/// Empty `resultsPath`: no traces. Error when a file cannot be read.
Result<std::vector<TraceRecord>> loadTraceRecords(const std::string& queriesPath,
                                                  const std::string& resultsPath);

/// Where the models of MODELS go in the world: for a .map, each model at
/// its entity's "origin", turned by its "rotation" (or "angle") key as the
/// game turns it (models are built in entity order, one per entity with
/// primitives, each in its entity's frame); for a .cm file, all at the
/// origin (the file has no placements).
std::vector<Placement> modelPlacements(const std::string& modelsPath, std::size_t numModels);

/// What render, export and view draw: the models of MODELS, the traces of
/// --queries / --results and where each model is placed.
struct CliScene {
  std::vector<ModelPtr> models;
  std::vector<TraceRecord> traces;
  std::vector<Placement> placements;  ///< one per model (modelPlacements)
};

/// Loads a CliScene (loadModelsForCli, loadTraceRecords, modelPlacements);
/// the first error, naming its file.
Result<CliScene> loadSceneForCli(const std::string& modelsPath, const std::string& materialsDir, bool noProc,
                                 const MeshCliOptions& mesh, const std::string& queriesPath,
                                 const std::string& resultsPath);

}  // namespace cmkit::cli
