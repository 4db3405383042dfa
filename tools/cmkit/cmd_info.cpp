// `cmkit info FILE`: statistics of the collision models of a map, without
// writing anything.
#include <cstdlib>
#include <string>

#include <fmt/core.h>

#include <chrono>

#include "commands.h"
#include "map_build.h"
#include "model_loading.h"
#include "stats_print.h"

namespace cmkit::cli {

void registerInfo(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "info",
      "Print the statistics of the collision models of FILE without writing anything:\n"
      "for a .map, the models are built as by 'cmkit compile' (per model: bounds,\n"
      "contents, vertices, edges, polygons, brushes, nodes, references, internal and\n"
      "sharp edges, contained polygons removed, polygons merged, memory as the\n"
      "original counts it: the original's text, line for line); a .cm\n"
      "file is loaded instead; a mesh file (.obj, .gltf, .glb, .ase, .lwo, ...) is\n"
      "converted into one model as by 'cmkit compile' (--up, --scale, --contents).\n"
      "NAME.proc beside a .map prunes the world model as in the original\n"
      "(--no-proc: not).\n\n"
      "Examples:\n"
      "  cmkit info maps/lt4.map\n"
      "  cmkit info maps/lt4.map --quiet          totals only\n"
      "  cmkit info maps/lt4.cm --quiet --memory  and the memory the models take in cmkit\n"
      "  cmkit info maps/lt4.cm\n"
      "  cmkit info maps/lt4.map --json | jq '.total.polygons'\n\n"
      "Exit codes: 0 success, 2 unreadable or malformed input (file:line: message).");
  auto req = std::make_shared<MapBuildRequest>();
  req->command = "info";
  cmd->add_option(
         "FILE", req->mapPath,
         "the .map file, a .cm file (loaded, not built), a mesh file, or - (standard input: .map or .cm)")
      ->required();
  cmd->add_option("--materials", req->materialsDir,
                  "directory of .mtr material files (searched recursively)");
  cmd->add_flag("--json", req->json, "print the statistics as JSON (for scripts)");
  cmd->add_flag("-q,--quiet", req->quiet, "print only the totals, not every model");
  cmd->add_flag("--memory", req->memory,
                "also print the memory the models take in cmkit: their arrays and the query data made beside "
                "them (always in --json)");
  addNoProcFlag(cmd, req->noProc);
  addMeshOptions(cmd, req->mesh);
  cmd->callback([req] {
    // A .cm file: loaded, not built; standard input: a .cm's models or a
    // .map built without a .proc, told apart by the first token.
    if (req->mapPath == kStdinPath || (req->mapPath.size() > 3 && req->mapPath.ends_with(".cm"))) {
      const auto start = std::chrono::steady_clock::now();
      Result<std::vector<ModelPtr>> models = loadModelsForCli(req->mapPath, req->materialsDir);
      if (!models) {
        fmt::print(stderr, "cmkit info: {}\n", models.error().toString());
        std::exit(kExitBadInput);
      }
      StatsContext context;
      context.source = req->mapPath;
      context.milliseconds =
          std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - start)
              .count();
      context.perModel = !req->quiet;
      context.cmkitMemory = req->memory;
      if (req->json) {
        fmt::print("{}", statsJson(*models, context));
      } else {
        printStatsText(stdout, *models, context);
      }
      return;
    }
    const int rc = runMapBuild(*req);
    if (rc != 0) std::exit(rc);
  });
}

}  // namespace cmkit::cli
