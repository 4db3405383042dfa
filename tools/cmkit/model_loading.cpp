#include "model_loading.h"

#include <fmt/core.h>

#include <filesystem>

#include "cmkit/cm_file.h"
#include "cmkit/compile.h"
#include "cmkit/contents.h"
#include "cmkit/map.h"
#include "option_checks.h"

namespace cmkit::cli {

void addNoProcFlag(CLI::App* cmd, bool& noProc) {
  cmd->add_flag("--no-proc", noProc,
                "ignore NAME.proc beside a .map (by default its BSP drops world polygons lying\n"
                "entirely in solid space, as the original does)");
}

void addRobustEdgesFlag(CLI::App* cmd, bool& robustEdges) {
  cmd->add_flag("--robust-edges", robustEdges,
                "for a .map: internal-edge marking that never hides an edge of a brush's shell\n"
                "(not the original's: where brushes overlap with coplanar faces the original\n"
                "hides the corner edges of both, and trace-model edges pass through the corner)");
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
    const int dropped = models.empty() ? 0 : models.front()->stats.procPolygonsRemoved;
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
                                const MeshCliOptions& options, std::vector<std::string>* warnings) {
  MeshLoadOptions load;
  load.up = options.up == "y" ? MeshUpAxis::Y : options.up == "z" ? MeshUpAxis::Z : MeshUpAxis::Auto;
  load.scale = static_cast<Real>(options.scale);
  MeshBuildOptions build;
  build.warnings = warnings;
  if (!options.contents.empty()) {
    Result<std::uint32_t> c = contentsFromString(options.contents);
    if (!c) return Error("--contents: " + c.error().message);
    build.contents = *c;
  }
  return loadMeshModel(path, materials, load, build);
}

Result<std::vector<ModelPtr>> loadModelsForCli(const std::string& path, const std::string& materialsDir,
                                               bool noProc, const MeshCliOptions& mesh, bool robustEdges) {
  MaterialTable materials;
  if (!materialsDir.empty()) {
    if (Status s = materials.addMtrDirectory(materialsDir); !s) return s.error();
  }
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
    auto models = buildCollisionModels(*map, materials, options);
    if (models) fmt::print(stderr, "{}\n", procNote(*proc, path, *models));
    return models;
  }
  if (isMeshFileName(path)) {
    std::vector<std::string> warnings;
    Result<ModelPtr> model = loadMeshForCli(path, materials, mesh, &warnings);
    for (const std::string& w : warnings) fmt::print(stderr, "warning: {}\n", w);
    if (!model) return model.error();
    return std::vector<ModelPtr>{std::move(*model)};
  }
  return Error{"expected a .map, .cm or mesh file (.obj, .gltf, .glb, .ase, .lwo, .fbx, .ply, ...)", path};
}

}  // namespace cmkit::cli
