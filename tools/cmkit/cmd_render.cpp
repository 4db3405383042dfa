// `cmkit render MODELS [-o out.png] [--size WxH] [--top|--perspective]
// [--queries Q --results R]`: a picture of collision models and traces.
#include <fmt/core.h>

#include <cstdio>

#include "cmkit/tools/picture.h"
#include "commands.h"
#include "model_loading.h"
#include "option_checks.h"
#include "trace_loading.h"

namespace cmkit::cli {
namespace {

/// Largest picture side accepted (pixels).
constexpr int kMaxPictureSide = 8192;

struct RenderOptions {
  std::string models;
  std::string output = "cmkit.png";
  std::string size = "1024x768";
  bool top = false;
  bool perspective = false;
  std::string queries;
  std::string results;
  std::string materials;
  bool noProc = false;  ///< --no-proc
  MeshCliOptions mesh;  ///< --up, --scale, --contents (mesh files)
  std::string mask;
  bool noWireframe = false;
  bool internalEdges = false;
  double cut = 0;
  bool haveCut = false;
};

bool parseSize(const std::string& text, int& w, int& h) {
  char x = 0;
  if (std::sscanf(text.c_str(), "%d%c%d", &w, &x, &h) != 3 || (x != 'x' && x != 'X')) return false;
  return w > 0 && h > 0 && w <= kMaxPictureSide && h <= kMaxPictureSide;
}

int runRender(const RenderOptions& o) {
  PictureOptions p;
  if (!parseSize(o.size, p.width, p.height)) {
    fmt::print(stderr, "cmkit render: --size: expected WIDTHxHEIGHT (1..{} each), got '{}'\n",
               kMaxPictureSide, o.size);
    return kExitBadInput;
  }
  p.view = o.top ? CameraView::TopDown : CameraView::Perspective;
  p.wireframe = !o.noWireframe;
  p.internalEdges = o.internalEdges;
  if (o.haveCut) p.cutHeight = Real(o.cut);
  if (!o.mask.empty()) {
    auto mask = parseContentsMask(o.mask);
    if (!mask) {
      fmt::print(stderr, "cmkit render: --mask: {}\n", mask.error().toString());
      return kExitBadInput;
    }
    p.contentMask = *mask;
  }
  auto scene = loadSceneForCli(o.models, o.materials, o.noProc, o.mesh, o.queries, o.results);
  if (!scene) {
    fmt::print(stderr, "cmkit render: {}\n", scene.error().toString());
    return kExitBadInput;
  }
  p.placements = scene->placements;
  const Image image = renderPicture(scene->models, scene->traces, p);
  if (Status s = savePng(o.output, image); !s) {
    fmt::print(stderr, "cmkit render: {}\n", s.error().toString());
    return kExitBadInput;
  }
  const std::size_t models = scene->models.size(), traces = scene->traces.size();
  fmt::print("{}: {}x{} picture of {} model{} and {} trace{}\n", o.output, image.width, image.height, models,
             models == 1 ? "" : "s", traces, traces == 1 ? "" : "s");
  return 0;
}

}  // namespace

void registerRender(CLI::App& app) {
  auto o = std::make_shared<RenderOptions>();
  auto* cmd = app.add_subcommand(
      "render",
      "Render the collision models of a .map, .cm or mesh file to a PNG picture (software rasteriser:\n"
      "polygons coloured by contents and shaded by their normal, edges drawn over them), with the\n"
      "traces of a query/results pair overlaid (path in yellow, trace model at the start and end,\n"
      "contact point red, contact normal orange).\n\n"
      "Examples:\n"
      "  cmkit render maps/lt4.map -o lt4.png\n"
      "  cmkit render maps/lt4.map --top --size 1600x1200 -o plan.png\n"
      "  cmkit query maps/box_room.map q.txt -o r.txt\n"
      "  cmkit render maps/box_room.map --queries q.txt --results r.txt -o traces.png");
  cmd->add_option("MODELS", o->models, "a .map (built on the fly), .cm or mesh file (.obj, .glb, ...)")
      ->required();
  cmd->add_option("-o,--output", o->output, "the PNG to write")->capture_default_str();
  cmd->add_option("--size", o->size, "picture size WIDTHxHEIGHT")->capture_default_str();
  auto* top =
      cmd->add_flag("--top", o->top, "orthographic view straight down (the top of the scene cut away)");
  cmd->add_flag("--perspective", o->perspective, "perspective view from above a corner (the default)")
      ->excludes(top);
  cmd->add_option("--queries", o->queries, "query file whose traces to draw (with --results)");
  cmd->add_option("--results", o->results,
                  "results of the queries ('cmkit query' output); without --queries, a file of query lines "
                  "each followed by its result line");
  cmd->add_option("--mask", o->mask, "only polygons with these contents (names or number; default all)");
  cmd->add_flag("--no-wireframe", o->noWireframe, "do not draw polygon edges");
  cmd->add_flag("--internal-edges", o->internalEdges, "also draw internal edges (green)");
  cmd->add_option("--cut", o->cut, "leave out polygons wholly above this height (z)")
      ->check(finiteNumber())
      ->each([o](const std::string&) { o->haveCut = true; });
  cmd->add_option("--materials", o->materials, "directory of .mtr files (default: the built-in rules)");
  addNoProcFlag(cmd, o->noProc);
  addMeshOptions(cmd, o->mesh);
  cmd->callback([o] {
    if (int rc = runRender(*o); rc != 0) std::exit(rc);
  });
}

}  // namespace cmkit::cli
