// `cmkit bench MAP --world`: what the World costs a query that has no entity
// near, against the same query on the world model alone (docs/world.md,
// "Cost"). Both are timed in one run, in alternating rounds, on the same
// seeded translations.
#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <random>
#include <vector>

#include "bench_world.h"
#include "commands.h"
#include "model_loading.h"

namespace cmkit::cli {

int runWorldBench(const WorldBenchOptions& o) {
  auto loaded = loadWorldForCli(o.map, o.materials, o.noProc);
  if (!loaded) {
    fmt::print(stderr, "cmkit bench: {}\n", loaded.error().toString());
    return kExitBadInput;
  }
  const World& world = loaded->world;
  const WorldEntity* ws = world.entity(kWorldspawnEntity);
  if (!ws) {
    fmt::print(stderr, "cmkit bench: {}: the map has no world model\n", o.map);
    return kExitBadInput;
  }
  auto trm = TraceModel::parse(o.trm);
  if (!trm) {
    fmt::print(stderr, "cmkit bench: --trm: {}\n", trm.error().toString());
    return kExitBadInput;
  }

  // Seeded moves where a game makes them, in the map's rooms: from within
  // 64 units of the origin of a map entity without a model (lights, spawn
  // points, speakers: they sit in the playable space), free at the start
  // (a position test on the world model), ends within +-length per axis;
  // kept only when the swept box (padded as the broad phase pads it, twice
  // over) meets no entity but the world model: "no entity near".
  Result<MapFile> map = loadMapFile(o.map);
  if (!map) {
    fmt::print(stderr, "cmkit bench: {}\n", map.error().toString());
    return kExitBadInput;
  }
  std::vector<Vec3> anchors;
  for (std::size_t i = 1; i < map->entities.size(); ++i)
    if (map->entities[i].primitives.empty() && !map->entities[i].value("model"))
      anchors.push_back(map->entities[i].origin());
  if (anchors.empty()) {
    fmt::print(stderr, "cmkit bench: {}: no entity without a model to start from\n", o.map);
    return kExitBadInput;
  }
  std::mt19937 rng(o.seed);
  std::uniform_real_distribution<double> u(0, 1);
  const std::vector<EntityId> ids = world.entityIds();
  std::vector<Vec3> starts, ends;
  QueryWork work;
  for (int tries = 0; int(starts.size()) < o.times && tries < o.times * 100; ++tries) {
    const Vec3 s =
        anchors[rng() % anchors.size()] +
        Vec3{Real(64 * (2 * u(rng) - 1)), Real(64 * (2 * u(rng) - 1)), Real(64 * (2 * u(rng) - 1))};
    if (contentsTest(*ws->model, {&*trm, {}, s, contents::kMaskSolid, {}}, work).contents != 0) continue;
    const Vec3 e = s + Vec3{Real(o.length * (2 * u(rng) - 1)), Real(o.length * (2 * u(rng) - 1)),
                            Real(o.length * (2 * u(rng) - 1))};
    Bounds sweep = trm->bounds().translated(s);
    sweep.addBounds(trm->bounds().translated(e));
    sweep = sweep.expanded(2 * tol::kWorldBroadPhasePadding);
    bool near = false;
    for (const EntityId id : ids)
      near = near || (id != kWorldspawnEntity && world.entity(id)->bounds.intersects(sweep));
    if (near) continue;
    starts.push_back(s);
    ends.push_back(e);
  }
  const std::size_t n = starts.size();
  if (n == 0) {
    fmt::print(stderr, "cmkit bench: no free move near the map's entities misses every entity\n");
    return kExitBadInput;
  }

  // Alternating rounds; each side's best round is its figure. Both use the
  // same per-model scratch (the WorldQueryWork's QueryWork), warm in both.
  TranslationQuery q;
  q.trm = &*trm;
  WorldQueryWork worldWork;
  double bestModel = 1e30, bestWorld = 1e30, sink = 0;
  std::size_t differ = 0;
  using Clock = std::chrono::steady_clock;
  for (int round = 0; round < o.rounds; ++round) {
    auto t0 = Clock::now();
    for (std::size_t i = 0; i < n; ++i) {
      q.start = starts[i];
      q.end = ends[i];
      sink += translate(*ws->model, q, worldWork.modelWork()).fraction;
    }
    auto t1 = Clock::now();
    for (std::size_t i = 0; i < n; ++i) {
      q.start = starts[i];
      q.end = ends[i];
      sink += world.translate(q, worldWork).trace.fraction;
    }
    auto t2 = Clock::now();
    bestModel = std::min(bestModel, std::chrono::duration<double>(t1 - t0).count());
    bestWorld = std::min(bestWorld, std::chrono::duration<double>(t2 - t1).count());
  }
  for (std::size_t i = 0; i < n; ++i) {
    q.start = starts[i];
    q.end = ends[i];
    differ += translate(*ws->model, q, work).fraction != world.translate(q, worldWork).trace.fraction;
  }
  fmt::print(
      "world bench on {}: {} entities, {} translations of {} from free points near the map's model-less "
      "entities, with no entity near (seed {}, length {}), best of {} alternating rounds\n",
      o.map, world.size(), n, o.trm, o.seed, o.length, o.rounds);
  fmt::print("  world model alone: {:8.3f} us/query\n", bestModel * 1e6 / double(n));
  fmt::print("  whole world:       {:8.3f} us/query\n", bestWorld * 1e6 / double(n));
  fmt::print("  ratio world / world model: {:.3f} (answers that differ: {})\n", bestWorld / bestModel,
             differ);
  if (sink == -1) fmt::print("\n");  // keeps the results alive
  return differ == 0 ? 0 : 1;
}

}  // namespace cmkit::cli
