// Rotation queries on lt4 (ns/query = 1e9 / items_per_second, CPU time): the rotation lines of the shared
// reference queries
// (/work/shared/reference/lt4.queries.txt) on the world model built from
// /work/shared/maps/lt4/lt4.map. Reports ns per query. Skips cleanly when the
// shared folder is absent.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "cmkit/compile.h"
#include "cmkit/map.h"
#include "cmkit/query.h"
#include "cmkit/tools/query_format.h"

namespace {

const std::filesystem::path kShared = std::filesystem::path(CMKIT_SOURCE_DIR) / ".." / "shared";

struct ParsedRotation {
  cmkit::RotationQuery query;
  const cmkit::CollisionModel* model = nullptr;
};

struct Lt4Rotations {
  std::vector<cmkit::ModelPtr> models;
  std::vector<std::string> lines;
  std::vector<cmkit::ParsedQuery> queries;  // the lines parsed (they own the trace models)
  std::vector<ParsedRotation> parsed;       // the rotations of `queries`
  std::string why;                          // non-empty: not available
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
    d.models = std::move(models->models);
    std::ifstream in(kShared / "reference/lt4.queries.txt");
    for (std::string line; std::getline(in, line);)
      if (line.rfind("rotation ", 0) == 0) d.lines.push_back(line);
    if (d.lines.empty()) d.why = "needs ../shared/reference/lt4.queries.txt";
    for (const std::string& line : d.lines)
      if (auto q = cmkit::parseQueryLine(d.models, line)) d.queries.push_back(std::move(*q));
    for (const cmkit::ParsedQuery& q : d.queries) {
      ParsedRotation& p = d.parsed.emplace_back();
      p.query = {
          q.trm ? &*q.trm : nullptr, q.trmAxis, q.position, q.rotation, q.contentMask, q.placement, false};
      p.model = d.models[q.model].get();
    }
    return d;
  }();
  return data;
}

// The rotation queries alone (lines parsed beforehand): ns/query to compare
// with the original's Rotation.
void BM_RotationLt4(benchmark::State& state) {
  const Lt4Rotations& d = lt4();
  if (!d.why.empty()) {
    state.SkipWithError(d.why.c_str());
    return;
  }
  cmkit::QueryWork work;
  for (auto _ : state) {
    for (const ParsedRotation& p : d.parsed) benchmark::DoNotOptimize(cmkit::rotate(*p.model, p.query, work));
  }
  state.SetItemsProcessed(state.iterations() * std::int64_t(d.parsed.size()));
}
BENCHMARK(BM_RotationLt4)->Unit(benchmark::kMillisecond);

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
}
BENCHMARK(BM_RotationLt4QueryLines)->Unit(benchmark::kMillisecond);

}  // namespace
