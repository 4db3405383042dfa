// Query benchmarks on lt4 (shared/maps/lt4/lt4.map, or the bundled copy in
// data/maps/lt4): the lines of shared/reference/lt4.queries.txt of each kind,
// parsed once, run through the library (results not formatted). lt4/raycast
// runs the point-translation lines as RayIndex casts. lt4/speedtest_* run the
// speed test's 1000 point moves from lt4's centre (as cmkit_peers): as point
// translations, as the same with each move repeated 100 times in a row (every
// branch predicted, everything cached), and as ray casts (with the node test
// the processor gets by default, and with the baseline one: SSE2 on x86-64).
#include <benchmark/benchmark.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "cmkit/compile.h"
#include "cmkit/map.h"
#include "cmkit/ray_index.h"
#include "cmkit/tools/query_format.h"
#include "cmkit/tools/speed_test.h"

namespace {

namespace fs = std::filesystem;

/// lt4 built and its queries parsed, loaded on first use by any benchmark.
struct Lt4Scene {
  std::once_flag once;
  std::string error;         ///< why the models are missing (benchmarks skip with it)
  std::string queriesError;  ///< why the queries are missing
  std::vector<cmkit::ModelPtr> models;
  std::vector<cmkit::ParsedQuery> queries;

  void load() {
    const fs::path source(CMKIT_SOURCE_DIR);
    const fs::path shared = source / ".." / "shared";
    fs::path map = shared / "maps" / "lt4" / "lt4.map";
    if (!fs::exists(map)) map = source / "data" / "maps" / "lt4" / "lt4.map";
    const fs::path queryFile = shared / "reference" / "lt4.queries.txt";
    if (!fs::exists(map)) {
      error = "lt4.map is absent";
      return;
    }
    auto parsed = cmkit::loadMapFile(map.string());
    if (!parsed) {
      error = parsed.error().toString();
      return;
    }
    auto built = cmkit::buildCollisionModels(*parsed, cmkit::MaterialTable{});
    if (!built) {
      error = built.error().toString();
      return;
    }
    models = std::move(built->models);
    if (!fs::exists(queryFile)) {
      queriesError = "shared/reference/lt4.queries.txt is absent";
      return;
    }
    std::ifstream in(queryFile);
    for (std::string line; std::getline(in, line);) {
      if (!cmkit::isQueryLine(line)) continue;
      if (auto q = cmkit::parseQueryLine(models, line)) queries.push_back(std::move(*q));
    }
  }
};

/// Which queries a benchmark runs.
enum class Kind {
  Translation,
  BoxTranslation,
  PointTranslation,
  Rotation,
  Contents,
  PointContents,
  Contacts
};

bool matches(Kind kind, const cmkit::ParsedQuery& q) {
  const bool point = !q.trm || q.trm->isPoint();
  switch (kind) {
    case Kind::Translation:
      return q.op == cmkit::QueryOp::Translation;
    case Kind::BoxTranslation:
      return q.op == cmkit::QueryOp::Translation && !point;
    case Kind::PointTranslation:
      return q.op == cmkit::QueryOp::Translation && point;
    case Kind::Rotation:
      return q.op == cmkit::QueryOp::Rotation;
    case Kind::Contents:
      return q.op == cmkit::QueryOp::Contents;
    case Kind::PointContents:
      return q.op == cmkit::QueryOp::PointContents;
    case Kind::Contacts:
      return q.op == cmkit::QueryOp::Contacts;
  }
  return false;
}

void runKind(benchmark::State& state, Lt4Scene& scene, Kind kind) {
  std::call_once(scene.once, [&scene] { scene.load(); });
  if (const std::string& why = scene.error.empty() ? scene.queriesError : scene.error; !why.empty()) {
    state.SkipWithError(why.c_str());
    return;
  }
  std::vector<const cmkit::ParsedQuery*> queries;
  for (const auto& q : scene.queries)
    if (matches(kind, q)) queries.push_back(&q);
  if (queries.empty()) {
    state.SkipWithError("no queries of this kind in lt4.queries.txt");
    return;
  }
  cmkit::QueryWork work;
  std::vector<cmkit::ContactInfo> contacts;  // kept from query to query
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(cmkit::runParsedQueryUnformatted(scene.models, *queries[i], work, contacts));
    if (++i == queries.size()) i = 0;
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["queries"] = double(queries.size());
}

/// The point-translation lines as ray casts (an index per model they use,
/// built before timing).
void runRayCasts(benchmark::State& state, Lt4Scene& scene) {
  std::call_once(scene.once, [&scene] { scene.load(); });
  if (const std::string& why = scene.error.empty() ? scene.queriesError : scene.error; !why.empty()) {
    state.SkipWithError(why.c_str());
    return;
  }
  std::vector<const cmkit::ParsedQuery*> queries;
  std::map<std::size_t, std::unique_ptr<cmkit::RayIndex>> indexes;
  for (const auto& q : scene.queries) {
    if (!matches(Kind::PointTranslation, q)) continue;
    queries.push_back(&q);
    auto& index = indexes[q.model];
    if (!index) index = std::make_unique<cmkit::RayIndex>(*scene.models[q.model]);
  }
  if (queries.empty()) {
    state.SkipWithError("no point translations in lt4.queries.txt");
    return;
  }
  std::vector<const cmkit::RayIndex*> indexOf;
  for (const auto* q : queries) indexOf.push_back(indexes[q->model].get());
  std::size_t i = 0;
  for (auto _ : state) {
    const cmkit::ParsedQuery& q = *queries[i];
    benchmark::DoNotOptimize(indexOf[i]->cast({q.position, q.end, q.contentMask, q.placement}));
    if (++i == queries.size()) i = 0;
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["queries"] = double(queries.size());
}

/// How lt4/speedtest_* run the speed test's point moves.
enum class SpeedTestRays { Translate, TranslateRepeated, Cast, CastBaseline };

void runSpeedTestRays(benchmark::State& state, Lt4Scene& scene, SpeedTestRays how) {
  std::call_once(scene.once, [&scene] { scene.load(); });
  if (!scene.error.empty()) {
    state.SkipWithError(scene.error.c_str());
    return;
  }
  constexpr int kMoves = 1000;           // cm_testTimes
  constexpr cmkit::Real kLength = 1024;  // cm_testLength
  constexpr int kRepeats = 100;          // TranslateRepeated: each move this many times in a row
  constexpr std::uint32_t kMask = cmkit::contents::kSolid | cmkit::contents::kPlayerClip;
  const cmkit::CollisionModel& world = *scene.models.front();
  const cmkit::Vec3 origin = world.bounds().center();
  cmkit::SpeedTestRandom random(0);
  std::vector<cmkit::Vec3> ends(kMoves);
  for (cmkit::Vec3& e : ends)
    for (int k = 0; k < 3; ++k) e[k] = origin[k] + random.signedUniform() * kLength;
  const cmkit::RayIndex index(world, how == SpeedTestRays::CastBaseline ? cmkit::RayIndex::NodeTest::Baseline
                                                                        : cmkit::RayIndex::NodeTest::Auto);
  cmkit::QueryWork work;
  std::size_t i = 0;
  for (auto _ : state) {
    const cmkit::Vec3& end = ends[how == SpeedTestRays::TranslateRepeated ? i / kRepeats : i];
    if (how == SpeedTestRays::Cast || how == SpeedTestRays::CastBaseline) {
      benchmark::DoNotOptimize(index.cast({origin, end, kMask}));
    } else {
      cmkit::TranslationQuery q;
      q.start = origin;
      q.end = end;
      q.contentMask = kMask;
      benchmark::DoNotOptimize(cmkit::translate(world, q, work));
    }
    if (++i == (how == SpeedTestRays::TranslateRepeated ? ends.size() * kRepeats : ends.size())) i = 0;
  }
  state.SetItemsProcessed(state.iterations());
}

/// Registers the lt4 benchmarks (they share one lazily loaded scene).
bool registerLt4Benchmarks() {
  auto scene = std::make_shared<Lt4Scene>();
  const std::pair<const char*, Kind> kinds[] = {{"lt4/translation", Kind::Translation},
                                                {"lt4/translation_box", Kind::BoxTranslation},
                                                {"lt4/translation_point", Kind::PointTranslation},
                                                {"lt4/rotation", Kind::Rotation},
                                                {"lt4/contents", Kind::Contents},
                                                {"lt4/pointcontents", Kind::PointContents},
                                                {"lt4/contacts", Kind::Contacts}};
  for (const auto& [name, kind] : kinds)
    benchmark::RegisterBenchmark(name,
                                 [scene, kind = kind](benchmark::State& s) { runKind(s, *scene, kind); });
  benchmark::RegisterBenchmark("lt4/raycast", [scene](benchmark::State& s) { runRayCasts(s, *scene); });
  const std::pair<const char*, SpeedTestRays> rays[] = {
      {"lt4/speedtest_point", SpeedTestRays::Translate},
      {"lt4/speedtest_point_repeated", SpeedTestRays::TranslateRepeated},
      {"lt4/speedtest_raycast", SpeedTestRays::Cast},
      {"lt4/speedtest_raycast_baseline", SpeedTestRays::CastBaseline}};
  for (const auto& [name, how] : rays)
    benchmark::RegisterBenchmark(
        name, [scene, how = how](benchmark::State& s) { runSpeedTestRays(s, *scene, how); });
  return true;
}

const bool kLt4Registered = registerLt4Benchmarks();

}  // namespace
