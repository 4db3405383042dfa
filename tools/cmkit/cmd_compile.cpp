// `cmkit compile MAP`: build the collision models of a map, print their
// statistics and optionally write them as a .cm file.
#include <cstdlib>

#include "commands.h"
#include "map_build.h"
#include "model_loading.h"

namespace cmkit::cli {

void registerCompile(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "compile",
      "Build the collision models of a Doom 3 .map file (one per entity with brushes or\n"
      "patches, as the original engine does when it loads a map) and print their\n"
      "statistics in the original's layout: vertices, edges, polygons, brushes, BSP nodes,\n"
      "references, internal and sharp edges, polygons removed inside brushes, polygons\n"
      "merged, memory. With -o the models are written as a .cm file (the original's\n"
      "CM \"1.00\" text format, with the map's geometry CRC).\n\n"
      "With NAME.proc beside NAME.map (the renderer's BSP a map compiler writes), world\n"
      "polygons lying entirely in its solid leaves are dropped, as the original does; a\n"
      "line on stderr says so (\"pruned with NAME.proc: N polygons dropped\" or \"no .proc\n"
      "beside NAME.map\"). --no-proc ignores it. MAP - reads the map from standard input\n"
      "(never pruned: there is no .proc beside it).\n\n"
      "--entity NAME writes one entity's model alone (the original's\n"
      "WriteCollisionModelForMapEntity): NAME is the entity's \"name\" value or #N for\n"
      "entity N (#0 = worldspawn); the model is named after the -o file, written with CRC 0\n"
      "and never pruned by a .proc. --test-trm also converts it to a trace model and prints\n"
      "it, or why it cannot be one (not convex, too many vertices/edges/polygons, ...).\n\n"
      "--robust-edges marks fewer edges internal than the original, so that no edge of a\n"
      "brush's shell is hidden where brushes overlap with coplanar faces (the .cm then\n"
      "differs from the original's; see docs/reliability.md), and builds the edges of\n"
      "two-sided surfaces as one sheet (edge normals are not in the .cm: they only change\n"
      "the models built in memory, e.g. by query and soak). Off by default.\n\n"
      "A mesh file instead of a map (.obj, .gltf, .glb, .ase, .lwo, .fbx, .ply, ..., read with\n"
      "assimp) becomes one model named after the file, as the original converts a render\n"
      "model: every triangle of every surface whose material has contents, or only the\n"
      "collision surfaces (material keyword \"collision\", textures/common/collision) when\n"
      "there are any; triangles counter-clockwise seen from the front. -o writes it with\n"
      "CRC 0. --up says which axis is up in the file (glTF is y up), --scale resizes it,\n"
      "--contents replaces the materials' contents (meshes without Doom 3 materials).\n\n"
      "Materials decide which brush sides and patches collide (and how): by default the\n"
      "rules of docs/materials.md (textures/common/clip is player/monster/moveable clip,\n"
      "names containing \"water\" are water, ...); --materials DIR reads the .mtr files\n"
      "below DIR first.\n\n"
      "Examples:\n"
      "  cmkit compile maps/lt4.map                  statistics only\n"
      "  cmkit compile maps/lt4.map -o maps/lt4.cm   write the .cm as well\n"
      "  cmkit compile level.map --materials base/materials --json > stats.json\n"
      "  cmkit compile maps/lt4.map --entity func_static_1 -o door.cm --test-trm\n"
      "  cmkit compile maps/lt4.map --robust-edges -o lt4-robust.cm\n"
      "  generate_map | cmkit compile - -o - > level.cm   a .map from standard input\n"
      "  cmkit compile crate.obj -o crate.cm --contents solid,playerclip\n"
      "  cmkit compile level.glb --scale 39.37 -o level.cm      metres to Doom units\n\n"
      "Exit codes: 0 success, 2 unreadable or malformed input (file:line: message), an\n"
      "unknown --entity or one without brushes or patches.");
  auto req = std::make_shared<MapBuildRequest>();
  req->command = "compile";
  cmd->add_option("MAP", req->mapPath, "the .map file, a mesh file, or - (a .map's text from standard input)")
      ->required();
  cmd->add_option("-o,--output", req->outPath,
                  "write the models to this .cm file (- : standard output; the report then goes to stderr)");
  cmd->add_option("--materials", req->materialsDir,
                  "directory of .mtr material files (searched recursively)");
  cmd->add_flag("--json", req->json, "print the statistics as JSON (for scripts)");
  cmd->add_flag("-q,--quiet", req->quiet, "print only the totals, not every model");
  addNoProcFlag(cmd, req->noProc);
  addRobustEdgesFlag(cmd, req->robustEdges);
  cmd->add_option("--entity", req->entity,
                  "write only this entity's model to -o: its \"name\" value, or #N for entity N");
  cmd->add_flag("--test-trm", req->testTrm, "with --entity: convert the model to a trace model and report");
  addMeshOptions(cmd, req->mesh);
  cmd->callback([req] {
    const int rc = runMapBuild(*req);
    if (rc != 0) std::exit(rc);
  });
}

}  // namespace cmkit::cli
