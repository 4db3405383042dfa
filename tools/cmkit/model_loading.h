// Loading the models named on a command line: a .cm file, a .map file
// whose entities are built into models (the world pruned with NAME.proc
// beside the map, as the original does, unless --no-proc), or a mesh file
// (.obj, .gltf, .glb, .ase, .lwo, ...) converted into one model.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <CLI/CLI.hpp>

#include "cmkit/materials.h"
#include "cmkit/mesh.h"
#include "cmkit/model.h"
#include "cmkit/proc_file.h"
#include "cmkit/result.h"
#include "cmkit/world.h"

namespace cmkit::cli {

/// How a mesh file on the command line is read (--up, --scale, --contents).
struct MeshCliOptions {
  std::string up = "auto";  ///< auto, y or z (MeshUpAxis)
  double scale = 1;
  std::string contents;  ///< empty: the materials decide
};

/// Adds --up, --scale and --contents (the same text in every command).
void addMeshOptions(CLI::App* cmd, MeshCliOptions& options);

/// Reads a mesh file into one model named after the path (warnings
/// appended when not null); `robustEdges`: MeshBuildOptions::robustEdges.
Result<ModelPtr> loadMeshForCli(const std::string& path, const MaterialTable& materials,
                                const MeshCliOptions& options, std::vector<std::string>* warnings,
                                bool robustEdges = false);

/// The built-in material rules, plus the .mtr files under `materialsDir`
/// when it is not empty (--materials).
Result<MaterialTable> materialsForCli(const std::string& materialsDir);

/// The path that means standard input.
inline constexpr const char* kStdinPath = "-";

/// The whole text of a file, or of standard input for "-".
Result<std::string> readCliText(const std::string& path);

/// Whether text is a .cm file's: its first token (after a UTF-8 byte-order
/// mark, blanks and comments) is CM. Anything else is taken for a .map.
bool looksLikeCm(std::string_view text);

/// Reads FILE.cm, builds every model of FILE.map or converts a mesh file
/// (isMeshFileName) into one model (materials from `materialsDir` when not
/// empty, else the default rules). For a .map, one line on stderr says
/// whether a .proc pruned the world (procNote). `robustEdges`:
/// BuildOptions::robustEdges for a .map, MeshBuildOptions::robustEdges for a
/// mesh file (ignored for a .cm). "-" (standard
/// input) and files of other names are read whole and told apart by their
/// first token (looksLikeCm): a .cm's models, or a .map built without a
/// .proc.
Result<std::vector<ModelPtr>> loadModelsForCli(const std::string& path, const std::string& materialsDir,
                                               bool noProc = false, const MeshCliOptions& mesh = {},
                                               bool robustEdges = false);

/// The World of a .map (World::loadMap: NAME.cm beside it when its CRC
/// matches, else built; NAME.proc prunes the world model unless `noProc`),
/// for `query --world` and `bench --world`. Another file is an error: the
/// world needs the map's entities.
Result<LoadedWorld> loadWorldForCli(const std::string& path, const std::string& materialsDir,
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
