// cmkit_cycle: how a query kind's time in `cmkit bench` depends on how many
// different queries the loop cycles through, and on what happens between
// queries. It parses the queries of one kind from a query file, keeps the
// first N, and times a query at a time over P passes (the best pass counts),
// optionally running B unpredictable branches (registers only, no memory)
// or reading K KB of other memory between queries, both outside the timing.
//
//   cmkit_cycle MAP QUERIES [--kind translation] [--first N] [--passes P]
//               [--branches B] [--evict KB] [--shuffle]
//
// MAP is a .map file (loaded as the engine loads it: ModelManager::loadMap)
// or a .cm file. docs/performance.md ("Where a translation's time goes") uses
// it: cycling through 200 of a large map's translations against all of them,
// and the 200 again with --branches 20000 (the branch predictor's state lost
// between queries) or --evict 1024 (the second-level cache's data lost).
// The times include two clock reads per query (the same in every mode).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "cmkit/manager.h"
#include "cmkit/materials.h"
#include "cmkit/query.h"
#include "cmkit/text_file.h"
#include "cmkit/tools/query_format.h"

namespace {

using Clock = std::chrono::steady_clock;

struct Options {
  std::string models, queries, kind = "translation";
  std::size_t first = 0;  // 0: all
  int passes = 20;
  long branches = 0;
  std::size_t evictKb = 0;
  bool shuffle = false;
};

int usage() {
  std::fprintf(stderr,
               "usage: cmkit_cycle MAP QUERIES [--kind translation] [--first N] [--passes P] "
               "[--branches B] [--evict KB] [--shuffle]\n");
  return 2;
}

// The models as the engine loads them (ModelManager: NAME.cm beside a map
// when it matches, else built with NAME.proc's pruning when there is one; a
// .cm file as it is), in handle order, which query lines' model= name.
cmkit::Result<std::vector<cmkit::ModelPtr>> loadModels(const std::string& path) {
  const cmkit::MaterialTable materials;
  cmkit::ModelManager manager;
  if (path.size() > 3 && path.ends_with(".cm")) {
    if (auto handles = manager.loadCm(path, materials); !handles) return handles.error();
  } else if (auto loaded = manager.loadMap(path, materials); !loaded) {
    return loaded.error();
  }
  std::vector<cmkit::ModelPtr> models;
  for (const cmkit::ModelListEntry& entry : manager.list()) models.push_back(entry.model);
  return models;
}

// B branches whose outcomes come from a pseudo-random sequence (the state
// lives in registers): enough of them leave the predictor nothing of the
// queries before.
long unpredictableBranches(long count, std::uint32_t& state) {
  long x = 0;
  for (long k = 0; k < count; ++k) {
    state = state * 1103515245u + 12345u;
    if (state & 0x10000u)
      x += k;
    else
      x -= 3;
    if (state & 0x20000u) x ^= k;
    if (state & 0x40000u) x += 7;
  }
  return x;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  std::vector<std::string_view> args(argv + 1, argv + argc);
  std::vector<std::string> positional;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const auto value = [&]() -> const char* { return i + 1 < args.size() ? argv[1 + ++i] : nullptr; };
    const char* v = nullptr;
    if (args[i] == "--kind" && (v = value()))
      o.kind = v;
    else if (args[i] == "--first" && (v = value()))
      o.first = std::strtoul(v, nullptr, 10);
    else if (args[i] == "--passes" && (v = value()))
      o.passes = std::max(1, std::atoi(v));
    else if (args[i] == "--branches" && (v = value()))
      o.branches = std::strtol(v, nullptr, 10);
    else if (args[i] == "--evict" && (v = value()))
      o.evictKb = std::strtoul(v, nullptr, 10);
    else if (args[i] == "--shuffle")
      o.shuffle = true;
    else if (args[i].starts_with("-"))
      return usage();
    else
      positional.emplace_back(args[i]);
  }
  if (positional.size() != 2) return usage();
  o.models = positional[0];
  o.queries = positional[1];

  auto models = loadModels(o.models);
  if (!models) {
    std::fprintf(stderr, "cmkit_cycle: %s\n", models.error().toString().c_str());
    return 1;
  }
  const auto text = cmkit::readTextFile(o.queries);
  if (!text) {
    std::fprintf(stderr, "cmkit_cycle: %s\n", text.error().toString().c_str());
    return 1;
  }
  std::vector<cmkit::ParsedQuery> queries;
  for (std::size_t pos = 0; pos < text->size();) {
    const std::size_t nl = std::min(text->find('\n', pos), text->size());
    const std::string_view line = std::string_view(*text).substr(pos, nl - pos);
    pos = nl + 1;
    if (line.substr(0, line.find(' ')) != o.kind) continue;
    if (auto q = cmkit::parseQueryLine(*models, line)) queries.push_back(std::move(*q));
  }
  if (o.first != 0 && queries.size() > o.first) queries.resize(o.first);
  if (queries.empty()) {
    std::fprintf(stderr, "cmkit_cycle: no %s queries in %s\n", o.kind.c_str(), o.queries.c_str());
    return 1;
  }

  cmkit::QueryWork work;
  std::vector<cmkit::ContactInfo> contacts;
  std::vector<std::size_t> order(queries.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::mt19937 rng(1);
  std::vector<unsigned char> junk(o.evictKb * 1024, 1);
  std::uint32_t state = 1;
  long sink = 0;
  double answers = 0, best = 1e300;
  for (int pass = 0; pass < o.passes; ++pass) {
    if (o.shuffle) std::shuffle(order.begin(), order.end(), rng);
    double ns = 0;
    for (const std::size_t i : order) {
      if (o.branches > 0) sink += unpredictableBranches(o.branches, state);
      for (std::size_t k = 0; k < junk.size(); k += 64) sink += junk[k];
      const auto t0 = Clock::now();
      answers += cmkit::runParsedQueryUnformatted(*models, queries[i], work, contacts);
      ns += std::chrono::duration<double, std::nano>(Clock::now() - t0).count();
    }
    best = std::min(best, ns);
  }
  std::printf("%zu %s queries, %d passes%s%s: %.0f ns/query (best pass)\n", queries.size(), o.kind.c_str(),
              o.passes, o.shuffle ? ", shuffled" : "",
              o.branches > 0 || o.evictKb > 0 ? (", between queries " + std::to_string(o.branches) +
                                                 " branches, " + std::to_string(o.evictKb) + " KB read")
                                                    .c_str()
                                              : "",
              best / double(queries.size()));
  return (sink == 42 && answers < 0) ? 3 : 0;  // (keeps the work; never true)
}
