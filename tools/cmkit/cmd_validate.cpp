// `cmkit validate FILE.cm|FILE.map|MESH`: check the invariants of every model.
#include <fmt/core.h>

#include <cstdlib>
#include <string>

#include "cmkit/validate.h"
#include "commands.h"
#include "model_loading.h"

namespace cmkit::cli {

void registerValidate(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "validate",
      "Check the invariants of every collision model of FILE (a .cm file, or a .map or mesh\n"
      "file whose models are built first): edges used by at most two polygons (in opposite\n"
      "directions), closed and planar polygon edge loops, bounds that contain their\n"
      "vertices, brushes that enclose a bounded volume inside their bounds, a consistent\n"
      "tree whose nodes reach their items, and no index out of range.\n"
      "Each violation is printed as: model \"NAME\" polygon 12: what is wrong. Violations of\n"
      "structure (an index, range, link or loop that is wrong) mean a corrupt model; those\n"
      "marked [geometry] are odd shapes queries handle (an empty brush, a non-planar or\n"
      "degenerate polygon), which real maps have and the compiler keeps, as the original does.\n\n"
      "Examples:\n"
      "  cmkit validate maps/lt4.cm\n"
      "  cmkit validate maps/lt4.map --max 20\n\n"
      "Exit codes: 0 all invariants hold, 1 violations found, 2 unreadable or malformed input.");
  auto path = std::make_shared<std::string>();
  auto materialsDir = std::make_shared<std::string>();
  auto maxPerModel = std::make_shared<std::size_t>(100);
  auto noProc = std::make_shared<bool>(false);
  auto mesh = std::make_shared<MeshCliOptions>();
  cmd->add_option("FILE", *path, "the .cm, .map or mesh file")->required();
  cmd->add_option("--materials", *materialsDir, "directory of .mtr material files (searched recursively)");
  cmd->add_option("--max", *maxPerModel, "report at most this many violations per model")
      ->capture_default_str();
  addNoProcFlag(cmd, *noProc);
  addMeshOptions(cmd, *mesh);
  cmd->callback([path, materialsDir, maxPerModel, noProc, mesh] {
    Result<std::vector<ModelPtr>> models = loadModelsForCli(*path, *materialsDir, *noProc, *mesh);
    if (!models) {
      fmt::print(stderr, "cmkit validate: {}\n", models.error().toString());
      std::exit(kExitBadInput);
    }
    std::size_t violations = 0, geometry = 0;
    for (std::size_t i = 0; i < models->size(); ++i) {
      const CollisionModel& m = *(*models)[i];
      const std::vector<Violation> found = validateModel(m, *maxPerModel);
      for (const Violation& v : found) {
        const bool odd = v.kind == Violation::Kind::Geometry;
        fmt::print("{}: #{} {}{}\n", *path, i, v.toString(), odd ? " [geometry]" : "");
        geometry += odd;
      }
      violations += found.size();
    }
    if (violations > 0) {
      fmt::print("{}: {} violation(s) in {} model(s): {} of structure (a corrupt model), {} of geometry\n",
                 *path, violations, models->size(), violations - geometry, geometry);
      std::exit(1);
    }
    fmt::print("{}: {} model(s), all invariants hold\n", *path, models->size());
  });
}

}  // namespace cmkit::cli
