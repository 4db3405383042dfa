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
#include "commands.h"
#include "progress_bar.h"
#include "stats_print.h"

namespace cmkit::cli {

namespace {

/// Maps at least this large (bytes) get a progress bar on a terminal.
constexpr std::uintmax_t kProgressMinFileSize = 1u << 20;

}  // namespace

int runMapBuild(const MapBuildRequest& request) {
  const std::string& cmd = request.command;
  MaterialTable materials;
  if (!request.materialsDir.empty()) {
    if (const Status st = materials.addMtrDirectory(request.materialsDir); !st) {
      fmt::print(stderr, "cmkit {}: {}\n", cmd, st.error().toString());
      return kExitBadInput;
    }
    for (const std::string& w : materials.warnings()) fmt::print(stderr, "warning: {}\n", w);
  }

  const auto start = std::chrono::steady_clock::now();
  auto map = loadMapFile(request.mapPath);
  if (!map) {
    fmt::print(stderr, "cmkit {}: {}\n", cmd, map.error().toString());
    return kExitBadInput;
  }

  std::error_code ec;
  const std::uintmax_t fileSize = std::filesystem::file_size(request.mapPath, ec);
  ProgressBar bar(!request.json && isatty(fileno(stderr)) && !ec && fileSize >= kProgressMinFileSize);
  std::vector<std::string> warnings;
  BuildOptions options;
  options.warnings = &warnings;
  options.progress = [&bar](std::size_t done, std::size_t total) { bar.update(done, total); };
  auto models = buildCollisionModels(*map, materials, options);
  bar.finish();
  if (!models) {
    fmt::print(stderr, "cmkit {}: {}\n", cmd, models.error().toString());
    return kExitBadInput;
  }
  const auto elapsed = std::chrono::steady_clock::now() - start;
  for (const std::string& w : warnings) fmt::print(stderr, "warning: {}: {}\n", request.mapPath, w);

  if (!request.outPath.empty()) {
    if (const Status st = saveCmFile(request.outPath, *models, map->geometryCrc); !st) {
      fmt::print(stderr, "cmkit {}: {}\n", cmd, st.error().toString());
      return kExitBadInput;
    }
  }

  StatsContext context;
  context.source = request.mapPath;
  context.milliseconds = std::chrono::duration_cast<std::chrono::milliseconds>(elapsed).count();
  context.entities = static_cast<long long>(map->entities.size());
  context.perModel = !request.quiet;
  if (request.json) {
    fmt::print("{}", statsJson(*models, context));
  } else {
    printStatsText(stdout, *models, context);
    if (!request.outPath.empty()) fmt::print("wrote {} ({} models)\n", request.outPath, models->size());
  }
  return 0;
}

}  // namespace cmkit::cli
