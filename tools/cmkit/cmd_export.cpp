// `cmkit export MODELS -o out.gltf|out.glb|out.obj [--queries Q --results R]`.
#include <fmt/core.h>

#include "cmkit/tools/export.h"
#include "commands.h"
#include "model_loading.h"
#include "trace_loading.h"

namespace cmkit::cli {
namespace {

struct ExportCliOptions {
  std::string models;
  std::string output;
  std::string queries;
  std::string results;
  std::string materials;
  bool noProc = false;  ///< --no-proc
  MeshCliOptions mesh;  ///< --up, --scale, --contents (mesh files)
  std::string mask;
  bool noEdges = false;
  bool noInternalEdges = false;
};

int runExport(const ExportCliOptions& o) {
  ExportOptions e;
  e.edges = !o.noEdges;
  e.internalEdges = !o.noInternalEdges;
  if (!o.mask.empty()) {
    auto mask = parseContentsMask(o.mask);
    if (!mask) {
      fmt::print(stderr, "cmkit export: --mask: {}\n", mask.error().toString());
      return kExitBadInput;
    }
    e.contentMask = *mask;
  }
  auto scene = loadSceneForCli(o.models, o.materials, o.noProc, o.mesh, o.queries, o.results);
  if (!scene) {
    fmt::print(stderr, "cmkit export: {}\n", scene.error().toString());
    return kExitBadInput;
  }
  e.placements = scene->placements;
  e.classNames = scene->classNames;
  if (Status s = saveScene(o.output, scene->models, scene->traces, e); !s) {
    fmt::print(stderr, "cmkit export: {}\n", s.error().toString());
    return kExitBadInput;
  }
  const std::size_t models = scene->models.size(), traces = scene->traces.size();
  fmt::print("{}: {} model{} and {} trace{}\n", o.output, models, models == 1 ? "" : "s", traces,
             traces == 1 ? "" : "s");
  return 0;
}

}  // namespace

void registerExport(CLI::App& app) {
  auto o = std::make_shared<ExportCliOptions>();
  auto* cmd = app.add_subcommand(
      "export",
      "Export the collision models of a .map, .cm or mesh file, and optionally the traces of a\n"
      "query/results pair, as glTF 2.0 (.gltf with the buffer embedded, or binary .glb) or\n"
      "Wavefront OBJ (+ .mtl beside it). Map coordinates (z up) are kept in the buffers; the\n"
      "glTF root node turns them y-up. One material per contents value; edges, internal edges\n"
      "and each trace are separate meshes/nodes (docs: include/cmkit/tools/export.h).\n\n"
      "Examples:\n"
      "  cmkit export maps/lt4.map -o lt4.glb\n"
      "  cmkit export maps/box_room.map --queries q.txt --results r.txt -o box_room.gltf\n"
      "  cmkit export level.cm --mask playerclip -o clip.obj");
  cmd->add_option("MODELS", o->models, "a .map (built on the fly), .cm or mesh file (.obj, .glb, ...)")
      ->required();
  cmd->add_option("-o,--output", o->output, "the file to write (.gltf, .glb or .obj)")->required();
  cmd->add_option("--queries", o->queries, "query file whose traces to export (with --results)");
  cmd->add_option("--results", o->results,
                  "results of the queries; without --queries, query lines each followed by its result line");
  cmd->add_option("--mask", o->mask, "only polygons with these contents (names or number; default all)");
  cmd->add_flag("--no-edges", o->noEdges, "leave out polygon edges");
  cmd->add_flag("--no-internal-edges", o->noInternalEdges, "leave out internal edges");
  cmd->add_option("--materials", o->materials, "directory of .mtr files (default: the built-in rules)");
  addNoProcFlag(cmd, o->noProc);
  addMeshOptions(cmd, o->mesh);
  cmd->callback([o] {
    if (int rc = runExport(*o); rc != 0) std::exit(rc);
  });
}

}  // namespace cmkit::cli
