// Loading the models named on a command line: a .cm file, or a .map file
// whose entities are built into models (the world pruned with NAME.proc
// beside the map, as the original does, unless --no-proc).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cmkit/materials.h"
#include "cmkit/model.h"
#include "cmkit/proc_file.h"
#include "cmkit/result.h"

namespace cmkit::cli {

/// Reads FILE.cm or builds every model of FILE.map (materials from
/// `materialsDir` when not empty, else the default rules). For a .map, one
/// line on stderr says whether a .proc pruned the world (procNote).
/// `robustEdges`: BuildOptions::robustEdges for a .map (ignored for a .cm).
Result<std::vector<ModelPtr>> loadModelsForCli(const std::string& path, const std::string& materialsDir,
                                               bool noProc = false, bool robustEdges = false);

/// Adds the --no-proc flag (the same text in every command).
void addNoProcFlag(CLI::App* cmd, bool& noProc);

/// Adds the --robust-edges flag (the same text in every command).
void addRobustEdgesFlag(CLI::App* cmd, bool& robustEdges);

/// NAME.proc for a .map on the command line.
struct ProcForCli {
  std::optional<ProcBsp> bsp;  ///< loaded and usable; nullopt: none used
  std::string path;            ///< NAME.proc
  bool present = false;        ///< the file exists
  bool ignored = false;        ///< present, but --no-proc
};

/// Loads NAME.proc beside the map unless `noProc` (warnings appended).
/// Error for a malformed .proc.
Result<ProcForCli> loadProcForCli(const std::string& mapPath, bool noProc,
                                  std::vector<std::string>* warnings);

/// The one line saying what happened: "pruned with NAME.proc: N polygons
/// dropped", "no .proc beside NAME.map", ...
std::string procNote(const ProcForCli& proc, const std::string& mapPath, const std::vector<ModelPtr>& models);

}  // namespace cmkit::cli
