// Rotation queries on lt4 (ns/query = 1e9 / items_per_second, CPU time): the rotation lines of the shared
// reference queries
// (/work/shared/reference/lt4.queries.txt) on the world model built from
// /work/shared/maps/lt4/lt4.map. Reports ns per query. Skips cleanly when the
// shared folder is absent.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "cmkit/compile.h"
#include "cmkit/map.h"
#include "cmkit/query.h"
#include "cmkit/tools/query_format.h"

namespace {

const std::filesystem::path kShared = std::filesystem::path(CMKIT_SOURCE_DIR) / ".." / "shared";

struct ParsedRotation {
  std::unique_ptr<cmkit::TraceModel> trm;  // null: a point
  cmkit::RotationQuery query;
  const cmkit::CollisionModel* model = nullptr;
};

struct Lt4Rotations {
  std::vector<cmkit::ModelPtr> models;
  std::vector<std::string> lines;
  std::vector<ParsedRotation> parsed;
  std::string why;  // non-empty: not available
};

std::vector<float> numbers(const std::string& s) {
  std::vector<float> v;
  std::stringstream in(s);
  for (std::string t; std::getline(in, t, ',');) v.push_back(std::strtof(t.c_str(), nullptr));
  return v;
}
cmkit::Vec3 vec(const std::string& s) {
  const auto v = numbers(s);
  return {v[0], v[1], v[2]};
}
cmkit::Mat3 mat(const std::string& s) {
  const auto v = numbers(s);
  return {{v[0], v[1], v[2]}, {v[3], v[4], v[5]}, {v[6], v[7], v[8]}};
}

// The query of a rotation line (the lines of lt4 are all well-formed).
ParsedRotation parse(const std::string& line, const std::vector<cmkit::ModelPtr>& models) {
  std::map<std::string, std::string> f;
  std::istringstream in(line);
  for (std::string tok; in >> tok;)
    if (const auto eq = tok.find('='); eq != std::string::npos) f[tok.substr(0, eq)] = tok.substr(eq + 1);
  ParsedRotation p;
  auto trm = cmkit::TraceModel::parse(f["trm"]);
  if (trm && !trm->isPoint()) p.trm = std::make_unique<cmkit::TraceModel>(*trm);
  p.query.trm = p.trm.get();
  p.query.start = vec(f["start"]);
  p.query.rotation =
      cmkit::Rotation(vec(f["rotorigin"]), vec(f["rotaxis"]), std::strtof(f["angle"].c_str(), nullptr));
  if (f.count("trmaxis")) p.query.trmAxis = mat(f["trmaxis"]);
  if (f.count("mask"))
    if (auto mask = cmkit::parseContentsMask(f["mask"])) p.query.contentMask = *mask;
  if (f.count("origin")) p.query.placement.origin = vec(f["origin"]);
  if (f.count("modelaxis")) p.query.placement.axis = mat(f["modelaxis"]);
  p.model = models[0].get();
  for (const auto& m : models)
    if (f.count("model") && m->name == f["model"]) p.model = m.get();
  return p;
}

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
    for (const std::string& line : d.lines) d.parsed.push_back(parse(line, d.models));
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
