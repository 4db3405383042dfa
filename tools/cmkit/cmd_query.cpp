// `cmkit query MODELS QUERIES [-o RESULTS]`: runs a query file.
#include <fmt/core.h>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <optional>
#include <string_view>
#include <thread>

#include "cmkit/text_file.h"
#include "cmkit/tools/query_format.h"
#include "commands.h"
#include "model_loading.h"

namespace cmkit::cli {
namespace {

struct QueryOptions {
  std::string models;
  std::string queries;
  std::string output;
  std::string materials;
  bool noProc = false;       ///< --no-proc
  bool robustEdges = false;  ///< --robust-edges
  bool world = false;        ///< --world
  MeshCliOptions mesh;       ///< --up, --scale, --contents (mesh files)
  int threads = 1;
};

int runQueryCommand(const QueryOptions& o) {
  if (o.models == kStdinPath && o.queries == kStdinPath) {
    fmt::print(stderr, "cmkit query: MODELS and QUERIES cannot both be standard input (-)\n");
    return kExitBadInput;
  }
  // --world: a World of the map's placed entities; else the models alone.
  Result<std::vector<ModelPtr>> models = std::vector<ModelPtr>{};
  std::optional<LoadedWorld> world;
  if (o.world) {
    auto loaded = loadWorldForCli(o.models, o.materials, o.noProc, o.robustEdges);
    if (!loaded) {
      fmt::print(stderr, "cmkit query: {}\n", loaded.error().toString());
      return kExitBadInput;
    }
    world = std::move(loaded).value();
  } else {
    models = loadModelsForCli(o.models, o.materials, o.noProc, o.mesh, o.robustEdges);
    if (!models) {
      fmt::print(stderr, "cmkit query: {}\n", models.error().toString());
      return kExitBadInput;
    }
  }
  const Result<std::string> text = readCliText(o.queries);
  if (!text) {
    fmt::print(stderr, "cmkit query: query file: {}\n", text.error().toString());
    return kExitBadInput;
  }
  std::vector<std::string> lines;
  for (std::size_t pos = 0; pos < text->size();) {
    const std::size_t nl = std::min(text->find('\n', pos), text->size());
    const std::string_view line = std::string_view(*text).substr(pos, nl - pos);
    if (isQueryLine(line)) lines.emplace_back(line);
    pos = nl + 1;
  }

  std::vector<std::string> results(lines.size());
  const int threads = std::max(1, std::min<int>(o.threads, int(lines.size()) / 64 + 1));
  const auto t0 = std::chrono::steady_clock::now();
  auto worker = [&](std::size_t first, std::size_t stride) {
    QueryWork work;
    WorldQueryWork worldWork;
    for (std::size_t i = first; i < lines.size(); i += stride)
      results[i] = world ? answerWorldQueryLine(world->world, lines[i], worldWork)
                         : answerQueryLine(models.value(), lines[i], work);
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker, std::size_t(t), std::size_t(threads));
  worker(0, std::size_t(threads));
  for (auto& th : pool) th.join();
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  std::FILE* out = stdout;
  if (!o.output.empty()) {
    out = std::fopen(o.output.c_str(), "wb");
    if (!out) {
      fmt::print(stderr, "cmkit query: {}: cannot write the results file\n", o.output);
      return kExitBadInput;
    }
  }
  std::size_t errors = 0;
  for (const std::string& r : results) {
    errors += r.rfind("error=", 0) == 0;
    std::fputs(r.c_str(), out);
    std::fputc('\n', out);
  }
  if (out != stdout) std::fclose(out);
  if (!o.output.empty() || !isatty(fileno(stdout))) {
    fmt::print(stderr, "{} quer{} on {} thread{} in {:.3f} s ({:.2f} us/query), {} error line{}\n",
               lines.size(), lines.size() == 1 ? "y" : "ies", threads, threads == 1 ? "" : "s", secs,
               lines.empty() ? 0.0 : secs * 1e6 / double(lines.size()), errors, errors == 1 ? "" : "s");
  }
  return errors == 0 ? 0 : kExitQueryErrors;
}

}  // namespace

void registerQuery(CLI::App& app) {
  auto o = std::make_shared<QueryOptions>();
  auto* cmd = app.add_subcommand(
      "query",
      "Run a file of collision queries against the models of a .map, .cm or mesh file and print one\n"
      "result line per query (format: docs/query-format.md).\n\n"
      "Query lines look like:\n"
      "  translation trm=box:-16,-16,0,16,16,72 start=0,0,64 end=0,0,-64 mask=solid,playerclip\n"
      "  contents trm=cylinder:8:-16,-16,0,16,16,72 start=10,20,30\n"
      "  pointcontents pos=10,20,30\n"
      "  contacts trm=point start=0,0,8 dir=0,0,-1 depth=16 max=8\n"
      "  rotation trm=bone:40,12 start=0,0,32 rotorigin=0,0,32 rotaxis=0,0,1 angle=90\n"
      "  contacts trm=bone:40,12 start=0,0,32 rotorigin=0,0,32 rotaxis=0,0,1 angle=90 max=8\n"
      "(contacts along a rotation: no dir/depth; each contact gets angle.i=, the degrees turned).\n"
      "Optional keys: trmaxis=9 numbers, mask=names|number, model=NAME|#N, origin=x,y,z,\n"
      "modelaxis=9 numbers. A line that cannot run gives error=REASON and the rest go on.\n\n"
      "--world (MODELS a .map): each line is answered against the whole world, the world model and\n"
      "every entity model placed by its origin/angle/rotation keys (docs/world.md); a result with a\n"
      "hit ends with entity=NAME (worldspawn: the world model; contacts: entity.i=NAME each).\n"
      "model=, origin= and modelaxis= are errors there.\n\n"
      "MODELS or QUERIES may be - (standard input, not both). A MODELS file that is not named\n"
      "*.map, *.cm or a mesh file is read as a .cm when its first token is CM, else as a .map.\n\n"
      "Exit codes: 0 every line answered; 3 every line written, but some are error=REASON (so that\n"
      "scripts notice); 2 bad input (unreadable models or query file, bad option).\n\n"
      "Examples:\n"
      "  cmkit query maps/box_room.map queries.txt -o results.txt\n"
      "  echo 'pointcontents pos=0,0,8' | cmkit query maps/box_room.map -\n"
      "  cmkit compile maps/box_room.map -o - | cmkit query - queries.txt   (a .cm through a pipe)");
  cmd->add_option("MODELS", o->models,
                  "a .map (built on the fly), .cm or mesh file (.obj, .glb, ...); - for standard input")
      ->required();
  cmd->add_option("QUERIES", o->queries, "the query file; - for standard input")->required();
  cmd->add_option("-o,--output", o->output, "write results here instead of standard output");
  cmd->add_option("--materials", o->materials, "directory of .mtr files (default: the built-in rules)");
  addNoProcFlag(cmd, o->noProc);
  addRobustEdgesFlag(cmd, o->robustEdges);
  addMeshOptions(cmd, o->mesh);
  cmd->add_flag("--world", o->world,
                "answer against the whole world of the .map (placed entities) and name the entity hit");
  cmd->add_option("-j,--threads", o->threads, "worker threads (results are the same for any count)")
      ->capture_default_str()
      ->check(CLI::Range(1, 256));
  cmd->callback([o] {
    if (int rc = runQueryCommand(*o); rc != 0) std::exit(rc);
  });
}

}  // namespace cmkit::cli
