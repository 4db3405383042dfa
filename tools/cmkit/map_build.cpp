// The shared part of `cmkit compile` and `cmkit info`.
#include "map_build.h"

#include <fmt/core.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "cmkit/cm_file.h"
#include "cmkit/compile.h"
#include "cmkit/map.h"
#include "cmkit/materials.h"
#include "cmkit/mesh.h"
#include "commands.h"
#include "model_loading.h"
#include "progress_bar.h"
#include "stats_print.h"

namespace cmkit::cli {

namespace {

/// Maps at least this large (bytes) get a progress bar on a terminal.
constexpr std::uintmax_t kProgressMinFileSize = 1u << 20;

}  // namespace

namespace {

/// `compile MAP --entity NAME -o FILE.cm [--test-trm]`.
int runEntityWrite(const MapBuildRequest& request, const MapFile& map, const MaterialTable& materials) {
  const std::string& cmd = request.command;
  if (request.outPath.empty() || request.outPath == kStdinPath) {
    fmt::print(stderr, "cmkit {}: --entity needs -o FILE.cm (the file the model is written to; not -)\n",
               cmd);
    return kExitBadInput;
  }
  const Result<std::size_t> index = map.findEntity(request.entity);
  if (!index) {
    fmt::print(stderr, "cmkit {}: {}\n", cmd, index.error().toString());
    return kExitBadInput;
  }
  EntityModelOptions options;
  options.testTraceModel = request.testTrm;
  options.robustEdges = request.robustEdges;
  const Result<EntityModelReport> written =
      writeCollisionModelForMapEntity(map, *index, request.outPath, materials, options);
  if (!written) {
    fmt::print(stderr, "cmkit {}: {}\n", cmd, written.error().toString());
    return kExitBadInput;
  }
  const EntityModelReport& report = *written;
  for (const std::string& w : report.warnings) fmt::print(stderr, "warning: {}: {}\n", request.mapPath, w);
  const CollisionModel& m = *report.model;
  fmt::print("entity #{}: model \"{}\": {} vertices, {} edges, {} polygons, {} brushes\n", *index, m.name(),
             m.vertices().size(), m.numEdges(), m.polygons().size(), m.brushes().size());
  fmt::print("wrote {} (1 model, CRC 0)\n", request.outPath);
  if (report.traceModel) {
    if (*report.traceModel) {
      const TraceModel& trm = report.traceModel->value();
      fmt::print("trace model: {} vertices, {} edges, {} polygons\n", trm.numVertices(), trm.numEdges(),
                 trm.numPolygons());
      fmt::print("{}", trm.describe());
    } else {
      fmt::print("not a trace model: {}\n", report.traceModel->error().message);
    }
  }
  return 0;
}

/// `compile MESH [-o FILE.cm]`: one model from a mesh file.
int runMeshBuild(const MapBuildRequest& request, const MaterialTable& materials) {
  const std::string& cmd = request.command;
  if (!request.entity.empty()) {
    fmt::print(stderr, "cmkit {}: --entity needs a .map file; {} is a mesh (one model)\n", cmd,
               request.mapPath);
    return kExitBadInput;
  }
  const auto start = std::chrono::steady_clock::now();
  std::vector<std::string> warnings;
  Result<ModelPtr> model =
      loadMeshForCli(request.mapPath, materials, request.mesh, &warnings, request.robustEdges);
  for (const std::string& w : warnings) fmt::print(stderr, "warning: {}: {}\n", request.mapPath, w);
  if (!model) {
    fmt::print(stderr, "cmkit {}: {}\n", cmd, model.error().toString());
    return kExitBadInput;
  }
  const auto elapsed = std::chrono::steady_clock::now() - start;
  const std::vector<ModelPtr> models{*model};
  if (!request.outPath.empty()) {
    if (const Status st = saveCmFile(request.outPath, models, 0); !st) {
      fmt::print(stderr, "cmkit {}: {}\n", cmd, st.error().toString());
      return kExitBadInput;
    }
  }
  StatsContext context;
  context.source = request.mapPath;
  context.milliseconds = std::chrono::duration_cast<std::chrono::milliseconds>(elapsed).count();
  context.perModel = !request.quiet;
  context.cmkitMemory = request.memory;
  if (request.json) {
    fmt::print("{}", statsJson(models, context));
  } else {
    printStatsText(stdout, models, context);
    if (!request.outPath.empty()) fmt::print("wrote {} (1 model, CRC 0)\n", request.outPath);
  }
  return 0;
}

}  // namespace

int runMapBuild(const MapBuildRequest& request) {
  const std::string& cmd = request.command;
  Result<MaterialTable> table = materialsForCli(request.materialsDir);
  if (!table) {
    fmt::print(stderr, "cmkit {}: {}\n", cmd, table.error().toString());
    return kExitBadInput;
  }
  const MaterialTable& materials = *table;
  for (const std::string& w : materials.warnings()) fmt::print(stderr, "warning: {}\n", w);
  if (isMeshFileName(request.mapPath)) return runMeshBuild(request, materials);

  const auto start = std::chrono::steady_clock::now();
  // "-": the map's text from standard input (no .proc beside it, no
  // progress bar: its size is not known before it is read).
  const bool fromStdin = request.mapPath == kStdinPath;
  const std::string source = fromStdin ? "<stdin>" : request.mapPath;
  Result<MapFile> map = [&]() -> Result<MapFile> {
    if (!fromStdin) return loadMapFile(request.mapPath);
    Result<std::string> text = readCliText(request.mapPath);
    if (!text) return text.error();
    return parseMapText(*text, "<stdin>");
  }();
  if (!map) {
    fmt::print(stderr, "cmkit {}: {}\n", cmd, map.error().toString());
    return kExitBadInput;
  }

  if (!request.entity.empty()) return runEntityWrite(request, *map, materials);

  std::vector<std::string> warnings;
  const Result<ProcForCli> proc = fromStdin ? Result<ProcForCli>(ProcForCli{})
                                            : loadProcForCli(request.mapPath, request.noProc, &warnings);
  if (!proc) {
    fmt::print(stderr, "cmkit {}: {}\n", cmd, proc.error().toString());
    return kExitBadInput;
  }

  std::error_code ec;
  const std::uintmax_t fileSize = fromStdin ? 0 : std::filesystem::file_size(request.mapPath, ec);
  ProgressBar bar(!request.json && isatty(fileno(stderr)) && !ec && fileSize >= kProgressMinFileSize);
  BuildOptions options;
  if (proc->bsp) options.procBsp = &*proc->bsp;
  options.robustEdges = request.robustEdges;
  options.progress = [&bar](std::size_t done, std::size_t total) { bar.update(done, total); };
  Result<BuildResult> built = buildCollisionModels(*map, materials, options);
  bar.finish();
  if (!built) {
    fmt::print(stderr, "cmkit {}: {}\n", cmd, built.error().toString());
    return kExitBadInput;
  }
  const auto elapsed = std::chrono::steady_clock::now() - start;
  const std::vector<ModelPtr>& models = built->models;
  warnings.insert(warnings.end(), built->warnings.begin(), built->warnings.end());
  for (const std::string& w : warnings) fmt::print(stderr, "warning: {}: {}\n", source, w);
  if (!fromStdin) fmt::print(stderr, "{}\n", procNote(*proc, request.mapPath, models));

  // "-o -": the .cm text goes to standard output and the report to stderr.
  const bool cmToStdout = request.outPath == kStdinPath;
  std::FILE* report = cmToStdout ? stderr : stdout;
  if (cmToStdout) {
    const std::string text = writeCmText(models, map->geometryCrc);
    std::fwrite(text.data(), 1, text.size(), stdout);
    std::fflush(stdout);
  } else if (!request.outPath.empty()) {
    if (const Status st = saveCmFile(request.outPath, models, map->geometryCrc); !st) {
      fmt::print(stderr, "cmkit {}: {}\n", cmd, st.error().toString());
      return kExitBadInput;
    }
  }

  StatsContext context;
  context.source = source;
  context.milliseconds = std::chrono::duration_cast<std::chrono::milliseconds>(elapsed).count();
  context.entities = static_cast<long long>(map->entities.size());
  context.perModel = !request.quiet;
  context.cmkitMemory = request.memory;
  if (proc->bsp) context.procFile = proc->path;
  if (request.json) {
    fmt::print(report, "{}", statsJson(models, context));
  } else {
    printStatsText(report, models, context);
    if (!request.outPath.empty())
      fmt::print(report, "wrote {} ({} model{})\n",
                 cmToStdout ? "the .cm to standard output" : request.outPath, models.size(),
                 models.size() == 1 ? "" : "s");
  }
  return 0;
}

}  // namespace cmkit::cli
