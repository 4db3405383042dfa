#include "model_loading.h"

#include <fmt/core.h>

#include <cstdio>
#include <filesystem>

#include "cmkit/cm_file.h"
#include "cmkit/compile.h"
#include "cmkit/contents.h"
#include "cmkit/map.h"
#include "cmkit/text_file.h"
#include "option_checks.h"

namespace cmkit::cli {

void addNoProcFlag(CLI::App* cmd, bool& noProc) {
  cmd->add_flag("--no-proc", noProc,
                "ignore NAME.proc beside a .map (by default its BSP drops world polygons lying\n"
                "entirely in solid space, as the original does)");
}

void addRobustEdgesFlag(CLI::App* cmd, bool& robustEdges) {
  cmd->add_flag("--robust-edges", robustEdges,
                "for a .map or mesh: internal-edge marking that never hides an edge of a brush's\n"
                "shell (not the original's: where brushes overlap with coplanar faces the original\n"
                "hides the corner edges of both, and trace-model edges pass through the corner),\n"
                "edge normals that make a two-sided surface one sheet (traces stop 0.25 from\n"
                "it, not up to 0.83 and more as in the original), and, for a .map, polygons cut\n"
                "where a coplanar face's corner lies on their edge (T-junctions), so that point\n"
                "traces cannot pass between them");
}

Result<ProcForCli> loadProcForCli(const std::string& mapPath, bool noProc,
                                  std::vector<std::string>* warnings) {
  ProcForCli out;
  out.path = procPathForMap(mapPath);
  std::error_code ec;
  out.present = std::filesystem::is_regular_file(out.path, ec);
  if (!out.present) return out;
  if (noProc) {
    out.ignored = true;
    return out;
  }
  Result<ProcBsp> bsp = loadProcFile(out.path, warnings);
  if (!bsp) return bsp.error();
  if (bsp->usable()) out.bsp = std::move(*bsp);
  return out;
}

std::string procNote(const ProcForCli& proc, const std::string& mapPath,
                     const std::vector<ModelPtr>& models) {
  const std::string procName = std::filesystem::path(proc.path).filename().string();
  if (proc.bsp) {
    const int dropped = models.empty() ? 0 : models.front()->stats().procPolygonsRemoved;
    return fmt::format("pruned with {}: {} polygon{} dropped", procName, dropped, dropped == 1 ? "" : "s");
  }
  if (proc.ignored) return fmt::format("{} ignored (--no-proc)", procName);
  if (proc.present) return fmt::format("{} not used (no BSP nodes in it)", procName);
  return fmt::format("no .proc beside {}", std::filesystem::path(mapPath).filename().string());
}

void addMeshOptions(CLI::App* cmd, MeshCliOptions& options) {
  cmd->add_option("--up", options.up,
                  "mesh files: which axis is up in the file: auto (glTF/GLB y, others z), y or z;\n"
                  "y-up coordinates (x, y, z) become (x, -z, y)")
      ->check(CLI::IsMember({"auto", "y", "z"}));
  cmd->add_option("--scale", options.scale, "mesh files: multiply every coordinate by this (default 1)")
      ->check(finiteAtLeast(0));
  cmd->add_option("--contents", options.contents,
                  "mesh files: give every surface these contents (\"solid,playerclip\", ...) instead\n"
                  "of its material's");
}

Result<ModelPtr> loadMeshForCli(const std::string& path, const MaterialTable& materials,
                                const MeshCliOptions& options, std::vector<std::string>* warnings,
                                bool robustEdges) {
  MeshLoadOptions load;
  load.up = options.up == "y" ? MeshUpAxis::Y : options.up == "z" ? MeshUpAxis::Z : MeshUpAxis::Auto;
  load.scale = static_cast<Real>(options.scale);
  MeshBuildOptions build;
  build.robustEdges = robustEdges;
  if (!options.contents.empty()) {
    Result<std::uint32_t> c = contentsFromString(options.contents);
    if (!c) return Error("--contents: " + c.error().message);
    build.contents = *c;
  }
  Result<MeshBuildResult> built = loadMeshModel(path, materials, load, build);
  if (!built) return built.error();
  if (warnings) warnings->insert(warnings->end(), built->warnings.begin(), built->warnings.end());
  return std::move(built->model);
}

Result<std::string> readCliText(const std::string& path) {
  return path == kStdinPath ? readStandardInput() : readTextFile(path);
}

bool looksLikeCm(std::string_view text) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);  // a UTF-8 byte-order mark
  std::size_t i = 0;
  while (i < text.size()) {
    const char c = text[i];
    if (c == ' ' || c == '\t' || c == '\r' || c == '\n') {
      ++i;
    } else if (text.substr(i, 2) == "//") {
      i = std::min(text.find('\n', i), text.size());
    } else if (text.substr(i, 2) == "/*") {
      const std::size_t end = text.find("*/", i + 2);
      i = end == std::string_view::npos ? text.size() : end + 2;
    } else {
      break;
    }
  }
  const std::string_view rest = text.substr(i);
  return rest.substr(0, 2) == "CM" && (rest.size() == 2 || rest[2] == ' ' || rest[2] == '\t' ||
                                       rest[2] == '\r' || rest[2] == '\n' || rest[2] == '"');
}

namespace {

/// Models from text whose format is told by its first token (looksLikeCm):
/// a .cm file's models, or every entity of a .map built (no .proc: there is
/// no file beside it to look for).
Result<std::vector<ModelPtr>> modelsFromText(const std::string& text, const std::string& name,
                                             const MaterialTable& materials, bool robustEdges) {
  if (looksLikeCm(text)) {
    auto file = parseCmText(text, name, materials);
    if (!file) return file.error();
    return std::move(file->models);
  }
  auto map = parseMapText(text, name);
  if (!map) return map.error();
  BuildOptions options;
  options.robustEdges = robustEdges;
  Result<BuildResult> built = buildCollisionModels(*map, materials, options);
  if (!built) return built.error();
  return std::move(built->models);
}

}  // namespace

Result<MaterialTable> materialsForCli(const std::string& materialsDir) {
  MaterialTable materials;
  if (!materialsDir.empty()) {
    if (Status s = materials.addMtrDirectory(materialsDir); !s) return s.error();
  }
  return materials;
}

Result<LoadedWorld> loadWorldForCli(const std::string& path, const std::string& materialsDir, bool noProc,
                                    bool robustEdges) {
  if (path.size() < 4 || path.compare(path.size() - 4, 4, ".map") != 0)
    return Error("a world needs a .map file (its entities place the models)", path);
  Result<MaterialTable> table = materialsForCli(materialsDir);
  if (!table) return table.error();
  LoadMapOptions options;
  options.useProcFile = !noProc;
  options.build.robustEdges = robustEdges;
  // A .cm beside the map is built without robust edges: rebuild for them.
  options.forceRebuild = robustEdges;
  return World::loadMap(path, *table, options);
}

Result<std::vector<ModelPtr>> loadModelsForCli(const std::string& path, const std::string& materialsDir,
                                               bool noProc, const MeshCliOptions& mesh, bool robustEdges) {
  Result<MaterialTable> table = materialsForCli(materialsDir);
  if (!table) return table.error();
  const MaterialTable& materials = *table;
  auto endsWith = [&](const char* ext) {
    const std::string e(ext);
    return path.size() >= e.size() && path.compare(path.size() - e.size(), e.size(), e) == 0;
  };
  if (endsWith(".cm")) {
    auto file = loadCmFile(path, materials);
    if (!file) return file.error();
    return std::move(file->models);
  }
  if (endsWith(".map")) {
    auto map = loadMapFile(path);
    if (!map) return map.error();
    std::vector<std::string> warnings;
    auto proc = loadProcForCli(path, noProc, &warnings);
    for (const std::string& w : warnings) fmt::print(stderr, "warning: {}\n", w);
    if (!proc) return proc.error();
    BuildOptions options;
    if (proc->bsp) options.procBsp = &*proc->bsp;
    options.robustEdges = robustEdges;
    Result<BuildResult> built = buildCollisionModels(*map, materials, options);
    if (!built) return built.error();
    fmt::print(stderr, "{}\n", procNote(*proc, path, built->models));
    return std::move(built->models);
  }
  if (isMeshFileName(path)) {
    std::vector<std::string> warnings;
    Result<ModelPtr> model = loadMeshForCli(path, materials, mesh, &warnings, robustEdges);
    for (const std::string& w : warnings) fmt::print(stderr, "warning: {}\n", w);
    if (!model) return model.error();
    return std::vector<ModelPtr>{std::move(*model)};
  }
  // Standard input ("-") or a file of another name: the first token tells a
  // .cm file from a .map; mesh files need their extension (assimp reads the
  // file itself).
  std::error_code ec;
  if (path != kStdinPath && std::filesystem::is_directory(path, ec))
    return Error{"is a directory; expected a .map, .cm or mesh file (.obj, .gltf, .glb, .ase, ...)", path};
  Result<std::string> text = readCliText(path);
  if (!text) return text.error();
  return modelsFromText(*text, path == kStdinPath ? "<stdin>" : path, materials, robustEdges);
}

}  // namespace cmkit::cli
