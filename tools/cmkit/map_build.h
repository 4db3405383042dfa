// Building the models of a .map file for the CLI (`compile`, `info`):
// loading, materials, progress bar, warnings and the statistics report.
#pragma once

#include <string>

#include "model_loading.h"

namespace cmkit::cli {

/// What `compile` / `info` were asked to do.
struct MapBuildRequest {
  std::string mapPath;
  std::string outPath;       ///< .cm to write; empty: none
  std::string materialsDir;  ///< .mtr files; empty: the default rules
  bool json = false;         ///< statistics as JSON instead of text
  bool quiet = false;        ///< no per-model statistics (totals only)
  bool memory = false;       ///< info: also the memory the models take in cmkit
  std::string command;       ///< for messages ("compile", "info")
  bool noProc = false;       ///< ignore NAME.proc beside the map
  std::string entity;        ///< compile only this entity ("name" value or #N); needs outPath
  bool testTrm = false;      ///< with `entity`: also convert the model to a trace model
  bool robustEdges = false;  ///< BuildOptions::robustEdges
  MeshCliOptions mesh;       ///< how a mesh file (mapPath) is read
};

/// A mesh file (isMeshFileName) instead of a map: its one model, written
/// with CRC 0 as the original's .cm files for render models.
/// Builds every model of the map (the world pruned with NAME.proc unless
/// noProc; one line on stderr says which), reports the statistics on stdout
/// and warnings on stderr, writes the .cm when asked. With `entity`: only
/// that entity's model, written to outPath (writeCollisionModelForMapEntity).
/// Returns the exit code (0, or kExitBadInput for unreadable or malformed
/// input, an unknown entity or one without primitives).
int runMapBuild(const MapBuildRequest& request);

}  // namespace cmkit::cli
