// Building the models of a .map file for the CLI (`compile`, `info`):
// loading, materials, progress bar, warnings and the statistics report.
#pragma once

#include <string>

namespace cmkit::cli {

/// What `compile` / `info` were asked to do.
struct MapBuildRequest {
  std::string mapPath;
  std::string outPath;       ///< .cm to write; empty: none
  std::string materialsDir;  ///< .mtr files; empty: the default rules
  bool json = false;         ///< statistics as JSON instead of text
  bool quiet = false;        ///< no per-model statistics (totals only)
  std::string command;       ///< for messages ("compile", "info")
};

/// Builds every model of the map, reports the statistics on stdout and
/// warnings on stderr, writes the .cm when asked. Returns the exit code
/// (0, or kExitBadInput for unreadable or malformed input).
int runMapBuild(const MapBuildRequest& request);

}  // namespace cmkit::cli
