// `cmkit info FILE`: statistics of the collision models of a map, without
// writing anything.
#include <cstdlib>
#include <string>

#include "commands.h"
#include "map_build.h"

namespace cmkit::cli {

void registerInfo(CLI::App& app) {
  auto* cmd =
      app.add_subcommand("info",
                         "Print the statistics of the collision models of FILE without writing anything:\n"
                         "for a .map, the models are built as by 'cmkit compile' (per model: bounds,\n"
                         "contents, vertices, edges, polygons, brushes, nodes, references, internal and\n"
                         "sharp edges, contained polygons removed, polygons merged, memory).\n\n"
                         "Examples:\n"
                         "  cmkit info maps/lt4.map\n"
                         "  cmkit info maps/lt4.map --quiet          totals only\n"
                         "  cmkit info maps/lt4.map --json | jq '.total.polygons'\n\n"
                         "Exit codes: 0 success, 2 unreadable or malformed input (file:line: message).");
  auto req = std::make_shared<MapBuildRequest>();
  req->command = "info";
  cmd->add_option("FILE", req->mapPath, "the .map file")->required();
  cmd->add_option("--materials", req->materialsDir,
                  "directory of .mtr material files (searched recursively)");
  cmd->add_flag("--json", req->json, "print the statistics as JSON (for scripts)");
  cmd->add_flag("-q,--quiet", req->quiet, "print only the totals, not every model");
  cmd->callback([req] {
    const int rc = runMapBuild(*req);
    if (rc != 0) std::exit(rc);
  });
}

}  // namespace cmkit::cli
