// Rotation queries on lt4: the rotation lines of the shared reference queries
// (/work/shared/reference/lt4.queries.txt) on the world model built from
// /work/shared/maps/lt4/lt4.map. Reports ns per query. Skips cleanly when the
// shared folder is absent.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cmkit/build.h"
#include "cmkit/map.h"
#include "cmkit/query.h"
#include "cmkit/query_file.h"

namespace {

const std::filesystem::path kShared = std::filesystem::path(CMKIT_SOURCE_DIR) / ".." / "shared";

struct Lt4Rotations {
  std::vector<cmkit::ModelPtr> models;
  std::vector<std::string> lines;
  std::string why;  // non-empty: not available
};

const Lt4Rotations& lt4() {
  static const Lt4Rotations data = [] {
    Lt4Rotations d;
    auto map = cmkit::loadMapFile((kShared / "maps/lt4/lt4.map").string());
    if (!map) {
      d.why = "needs ../shared/maps/lt4/lt4.map";
      return d;
    }
    auto models = cmkit::buildCollisionModels(*map, cmkit::MaterialTable{});
    if (!models) {
      d.why = "lt4 did not build";
      return d;
    }
    d.models = std::move(*models);
    std::ifstream in(kShared / "reference/lt4.queries.txt");
    for (std::string line; std::getline(in, line);)
      if (line.rfind("rotation ", 0) == 0) d.lines.push_back(line);
    if (d.lines.empty()) d.why = "needs ../shared/reference/lt4.queries.txt";
    return d;
  }();
  return data;
}

// The whole query line (parsing, query, formatting), as `cmkit query` runs it.
void BM_RotationLt4QueryLines(benchmark::State& state) {
  const Lt4Rotations& d = lt4();
  if (!d.why.empty()) {
    state.SkipWithError(d.why.c_str());
    return;
  }
  cmkit::QueryWork work;
  for (auto _ : state) {
    for (const std::string& line : d.lines)
      benchmark::DoNotOptimize(cmkit::answerQueryLine(d.models, line, work));
  }
  state.SetItemsProcessed(state.iterations() * std::int64_t(d.lines.size()));
  state.counters["ns/query"] = benchmark::Counter(
      double(d.lines.size()), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_RotationLt4QueryLines)->Unit(benchmark::kMillisecond);

}  // namespace
