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

/// The entities of the models of MODELS, one per model, or none.
struct ModelEntities {
  /// For a .map, each model at its entity's "origin", turned by its
  /// "rotation" (or "angle") key as the game turns it (models are built in
  /// entity order, one per entity with primitives, each in its entity's
  /// frame); for a .cm file, empty: all at the origin (the file has no
  /// placements).
  std::vector<Placement> placements;
  std::vector<std::string> classNames;  ///< each model's entity's "classname" (.map), else empty
};

/// Reads where the models of MODELS go and what their entities are (see
/// ModelEntities); empty when MODELS is not a .map or its entities with
/// primitives are not `numModels`.
ModelEntities modelEntities(const std::string& modelsPath, std::size_t numModels);

/// What render, export and view draw: the models of MODELS, the traces of
/// --queries / --results and where each model is placed.
struct CliScene {
  std::vector<ModelPtr> models;
  std::vector<TraceRecord> traces;
  std::vector<Placement> placements;    ///< one per model, or none (modelEntities)
  std::vector<std::string> classNames;  ///< one per model, or none (modelEntities)
};

/// Loads a CliScene (loadModelsForCli, loadTraceRecords, modelEntities);
/// the first error, naming its file.
Result<CliScene> loadSceneForCli(const std::string& modelsPath, const std::string& materialsDir, bool noProc,
                                 const MeshCliOptions& mesh, const std::string& queriesPath,
                                 const std::string& resultsPath);

}  // namespace cmkit::cli
