// `cmkit soak MAP`: random sweeps of every trace-model kind and a walker (the
// library's player) through the world model, each end checked with a
// position test and every embedded end classified (docs/reliability.md).
#include <fmt/core.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "cmkit/compile.h"
#include "cmkit/map.h"
#include "cmkit/query.h"
#include "cmkit/text_file.h"
#include "cmkit/tools/query_format.h"
#include "commands.h"
#include "model_loading.h"
#include "option_checks.h"
#include "progress_bar.h"
#include "soak.h"

namespace cmkit::cli {

namespace {

/// --replay FILE: every translation line of FILE run and its end classified.
int runReplay(const SoakOptions& o, const std::vector<ModelPtr>& models) {
  const Result<std::string> text = readTextFile(o.replay);
  if (!text) {
    fmt::print(stderr, "cmkit soak: --replay: {}\n", text.error().toString());
    return kExitBadInput;
  }
  QueryWork work;
  int bad = 0;
  for (std::size_t pos = 0; pos < text->size();) {
    const std::size_t nl = std::min(text->find('\n', pos), text->size());
    const std::string_view line = std::string_view(*text).substr(pos, nl - pos);
    pos = nl + 1;
    if (!isQueryLine(line)) continue;
    auto q = parseQueryLine(models, line);
    if (!q || q->op != QueryOp::Translation || q->model != 0) {
      if (q && q->op != QueryOp::Translation) continue;  // contents lines of the soak's output
      fmt::print("{}\n  error: {}\n", line, q ? "only translations of the first model" : q.error().message);
      ++bad;
      continue;
    }
    Shape shape{q->trmSpec, q->trm ? *q->trm : TraceModel::point(), q->trmAxis};
    SoakOptions one = o;
    one.mask = q->contentMask;
    one.walkerSteps = 0;
    const Soak soak(models.front(), {}, shape, one);
    fmt::print("{}\n  {}\n", line, soak.replay(shape, q->position, q->end, work));
  }
  return bad == 0 ? 0 : kExitBadInput;
}

/// --offset: the .map's world geometry (the worldspawn's brush planes and
/// patch points) moved by `offset` before it is built, to soak a world far
/// from the origin. No .proc: its planes would have to move too.
Result<std::vector<ModelPtr>> loadMovedMap(const SoakOptions& o, const Vec3& offset) {
  if (o.map.size() < 4 || o.map.compare(o.map.size() - 4, 4, ".map") != 0)
    return Error{"--offset needs a .map file (its geometry is moved before it is built)", o.map};
  Result<MaterialTable> materials = materialsForCli(o.materials);
  if (!materials) return materials.error();
  auto map = loadMapFile(o.map);
  if (!map) return map.error();
  moveWorldGeometry(*map, offset);
  BuildOptions options;
  options.robustEdges = o.robustEdges;
  Result<BuildResult> built = buildCollisionModels(*map, *materials, options);
  if (!built) return built.error();
  return std::move(built->models);
}

int runSoak(const SoakOptions& o) {
  // (--offset was checked by finiteVec3 while the command line was parsed.)
  const bool moved = !o.offset.empty();
  const Vec3 offset = moved ? parseFiniteVec3(o.offset).value_or(Vec3{}) : Vec3{};
  auto models =
      moved ? loadMovedMap(o, offset) : loadModelsForCli(o.map, o.materials, o.noProc, {}, o.robustEdges);
  if (!models) {
    fmt::print(stderr, "cmkit soak: {}\n", models.error().toString());
    return kExitBadInput;
  }
  if (models->empty()) {
    fmt::print(stderr, "cmkit soak: {}: no collision models\n", o.map);
    return kExitBadInput;
  }
  if (!o.replay.empty()) return runReplay(o, *models);
  bool failOnClosed = false;
  for (const std::string& f : o.failOn) failOnClosed |= f == "closed-brush";
  std::vector<Shape> shapes;
  std::vector<std::string> specs = o.trms;
  if (specs.empty()) specs.assign(std::begin(kDefaultTrms), std::end(kDefaultTrms));
  for (const std::string& spec : specs) {
    auto trm = TraceModel::parse(spec);
    if (!trm) {
      fmt::print(stderr, "cmkit soak: --trm {}: {}\n", spec, trm.error().toString());
      return kExitBadInput;
    }
    shapes.push_back({spec, std::move(*trm), {}});
  }
  Shape walker{kWalkerTrm, *TraceModel::parse(kWalkerTrm), {}};
  const CollisionModel& world = *models->front();
  Soak soak(models->front(), std::move(shapes), std::move(walker), o);

  const std::uint64_t items = soak.numItems();
  std::atomic<std::uint64_t> next{0}, done{0};
  std::mutex merge;
  ItemTally total;
  std::vector<Case> cases;
  const auto t0 = std::chrono::steady_clock::now();
  auto worker = [&] {
    QueryWork work;
    ItemTally tally;
    std::vector<Case> mine;
    constexpr std::uint64_t kChunk = 64;
    for (;;) {
      const std::uint64_t first = next.fetch_add(kChunk);
      if (first >= items) break;
      const std::uint64_t last = std::min(items, first + kChunk);
      for (std::uint64_t i = first; i < last; ++i) soak.runItem(i, work, tally, mine);
      done += last - first;
    }
    std::lock_guard lock(merge);
    total.sweeps += tally.sweeps;
    total.rotatedSweeps += tally.rotatedSweeps;
    total.pointSweeps += tally.pointSweeps;
    total.noStart += tally.noStart;
    total.hits += tally.hits;
    total.walkerSteps += tally.walkerSteps;
    total.respawns += tally.respawns;
    for (std::size_t k = 0; k < kNumFindings; ++k) total.counts[k] += tally.counts[k];
    for (std::size_t k = 0; k < kNumFindings; ++k) total.walkerCauses[k] += tally.walkerCauses[k];
    for (std::size_t k = 0; k < kNumStuckCauses; ++k) total.stuckCauses[k] += tally.stuckCauses[k];
    cases.insert(cases.end(), mine.begin(), mine.end());
  };
  std::vector<std::thread> pool;
  for (int t = 0; t < o.threads; ++t) pool.emplace_back(worker);
  {
    ProgressBar bar(isatty(fileno(stderr)) != 0, "soak", "items");
    while (done.load() < items) {
      bar.update(std::size_t(done.load()), std::size_t(items));
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
  }
  for (auto& th : pool) th.join();
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::sort(cases.begin(), cases.end(), [](const Case& a, const Case& b) { return a.item < b.item; });

  fmt::print(
      "soak of \"{}\" in {}: {} polygons, {} brushes ({} with every face covered by polygons), mask {}, seed "
      "{}\n",
      world.name(), o.map, world.polygons().size(), world.brushes().size(), soak.numClosedBrushes(), o.mask,
      o.seed);
  if (moved)
    fmt::print("moved by ({} {} {}): world bounds ({} {} {}) to ({} {} {}); {} precision\n", offset.x,
               offset.y, offset.z, world.bounds().min.x, world.bounds().min.y, world.bounds().min.z,
               world.bounds().max.x, world.bounds().max.y, world.bounds().max.z,
               kDoublePrecision ? "double" : "float");
  fmt::print("trace models:");
  for (const std::string& s : specs) fmt::print(" {}", s);
  fmt::print("\n");
  fmt::print(
      "sweeps: {} run ({} point traces, {} turned trace models), {} without a free start, {} hit "
      "something\n",
      total.sweeps, total.pointSweeps, total.rotatedSweeps, total.noStart, total.hits);
  fmt::print("walker: {} steps ({}), {} restarts\n", total.walkerSteps, kWalkerTrm, total.respawns);
  fmt::print("time: {:.1f} s on {} thread(s)\n", secs, o.threads);
  fmt::print("\nfindings:\n");
  for (std::size_t k = 0; k < kNumFindings; ++k)
    fmt::print("  {:<16} {:>9}  {}\n", kFindingNames[k], total.counts[k], kFindingMeaning[k]);
  if (total.counts[std::size_t(Finding::WalkerEmbedded)] > 0) {
    fmt::print(
        "walker-embedded by the class of the translation that ended in solid (closed-brush, precision, "
        "grazing: "
        "cmkit's; the others: the map's):");
    for (std::size_t k = 0; k < kNumFindings; ++k)
      if (total.walkerCauses[k] > 0) fmt::print(" {} {}", kFindingNames[k], total.walkerCauses[k]);
    fmt::print("\n");
  }
  if (total.counts[std::size_t(Finding::WalkerStuck)] > 0) {
    fmt::print(
        "walker-stuck by cause (cornered, pressing: the walk's; no-room: the map's; unexplained: none of "
        "them):");
    for (std::size_t k = 0; k < kNumStuckCauses; ++k)
      if (total.stuckCauses[k] > 0) fmt::print(" {} {}", kStuckCauseNames[k], total.stuckCauses[k]);
    fmt::print("\n");
  }
  // The first --examples cases of each class; walker-stuck ones per cause,
  // unexplained first.
  for (std::size_t k = 0; k < kNumFindings; ++k) {
    const bool stuck = k == std::size_t(Finding::WalkerStuck);
    std::size_t shown = 0;
    for (std::size_t why = 0; why < (stuck ? kNumStuckCauses : 1); ++why) {
      std::size_t shownOfCause = 0;
      for (const Case& c : cases) {
        if (std::size_t(c.finding) != k || (stuck && std::size_t(c.stuck) != why)) continue;
        if (shownOfCause++ >= o.examples) break;
        if (shown++ == 0) fmt::print("\n# {} ({}):\n", kFindingNames[k], kFindingMeaning[k]);
        fmt::print("{}", c.lines);
      }
    }
  }
  const bool mustHoldFailed = total.counts[std::size_t(Finding::NonFinite)] > 0 ||
                              total.counts[std::size_t(Finding::FractionRange)] > 0;
  const bool closedFailed = failOnClosed && total.counts[std::size_t(Finding::ClosedBrush)] > 0;
  if (mustHoldFailed || closedFailed) {
    fmt::print("\nFAILED: {}\n", mustHoldFailed ? "a result that must hold did not" : "closed-brush misses");
    return 1;
  }
  fmt::print("\nOK: every result finite with its fraction in [0,1]\n");
  return 0;
}

}  // namespace

void registerSoak(CLI::App& app) {
  auto o = std::make_shared<SoakOptions>();
  auto* cmd = app.add_subcommand(
      "soak",
      "Random sweeps and a walker, the library's player, through the world model, every end checked.\n\n"
      "Sweeps: --sweeps translations, the trace models taken in turn (--trm, default every kind),\n"
      "each from a random free start (a contents test of the trace model there finds nothing, and\n"
      "point traces along +-x, +-y, +-z all hit a surface: inside the map) to a random end.\n"
      "30% of the sweeps of a trace model other than the point turn it to a random orientation\n"
      "(trmAxis; the query lines print it as trmaxis=).\n"
      "Walker: --walker-steps steps of the library's player (stepPlayer, docs/movement.md: 60 steps\n"
      "a second, gravity 1066, running at 220, slides along up to 4 planes a step, 16-unit step-up)\n"
      "as a 32x32x72 box, a random wish direction every 40 steps and a jump pressed at one step in\n"
      "97, restarted elsewhere every 500 steps. Every translation of its steps is checked.\n\n"
      "Checks: every result finite and its fraction in [0,1] (these must hold: exit 1), and every\n"
      "end free (a contents test). An end in solid is classified, first match (closed-brush\n"
      "first, so that no other class can hide a miss):\n"
      "  closed-brush   the end overlaps (exact separating-axis depth > 0.01) a brush the start\n"
      "                 did not, and every face the trace model had to cross to get in (each\n"
      "                 brush plane it was wholly in front of at the start; all planes if none)\n"
      "                 is covered by polygons of the mask (every sample point of the face, a grid of\n"
      "                 at most 32 x 32 points 1 unit or more apart, lies in a polygon in its plane:\n"
      "                 same normal, |dist difference| < 0.01): the move should have\n"
      "                 hit that polygon\n"
      "  precision      penetration() depth <= 0.01 units\n"
      "  grazing        |cos| of the move and the plane to leave the brush by < 0.02 (edge-on)\n"
      "  brush-face     as closed-brush, but one of those faces is not (wholly) covered\n"
      "  patch-behind   the end overlaps polygons only; one was crossed from behind\n"
      "  other-polygon  the end overlaps polygons only, none crossed from behind\n"
      "Walker steps with a translation that ends in solid (walker-embedded) or that make less than\n"
      "1 unit of progress in 60 steps (walker-stuck) are counted and the walker restarts. The\n"
      "translation that ended in solid is classified as above (closed-brush, precision, grazing:\n"
      "cmkit's; the others: the map's).\n"
      "A stuck walker is diagnosed, first match:\n"
      "  no-room        the box moves less than 1 unit along each of 8 horizontal directions\n"
      "                 (probes of 4 units, flat or 16 units up): the map's (too small a space)\n"
      "  cornered       at least 30 of the 60 steps were blocked (each moved it less than 1/60\n"
      "                 unit, its slide stopped on a plane: the contact planes clipped the velocity\n"
      "                 to ~0 in a corner or crease; another direction has room): the walk's\n"
      "  pressing       the wish is within 3 degrees of the normal of the wall its step from rest\n"
      "                 stops on: friction takes what each step adds along the wall, and it\n"
      "                 creeps (under 2 units a second): the walk's\n"
      "  unexplained    the steps moved it, yet it made no progress (a query fault?; printed\n"
      "                 first)\n"
      "Prints the count per class and the first --examples cases of each as query lines (the\n"
      "translation, then a contents test at its end) to paste into 'cmkit query'.\n"
      "Results are the same for any --threads (each item has its own seeded generator).\n\n"
      "Exit codes: 0 the must-hold checks passed, 1 one failed (or --fail-on closed-brush and a\n"
      "closed-brush miss), 2 bad input.\n\n"
      "Examples:\n"
      "  cmkit soak data/maps/lt4/lt4.map --sweeps 20000 --walker-steps 2000\n"
      "  cmkit soak data/maps/lt4/lt4.map --trm cone:6:-12,-12,0,12,12,40 --threads 2\n"
      "  cmkit soak data/maps/lt4/lt4.map --robust-edges --fail-on closed-brush\n"
      "  cmkit soak data/maps/lt4/lt4.map --offset 40000,40000,0   (lt4 far from the origin)\n"
      "  cmkit soak data/maps/lt4/lt4.map --replay cases.txt   (classify pasted translation lines)");
  cmd->add_option("MAP", o->map,
                  "a .map (built on the fly), .cm or mesh file (.obj, .glb, ...); the first model is soaked")
      ->required();
  cmd->add_option("--sweeps", o->sweeps, "random translations")
      ->capture_default_str()
      ->check(CLI::Range(std::uint64_t(0), std::uint64_t(1) << 40));
  cmd->add_option("--walker-steps", o->walkerSteps, "steps of the walker")
      ->capture_default_str()
      ->check(CLI::Range(std::uint64_t(0), std::uint64_t(1) << 40));
  cmd->add_option("--seed", o->seed, "seed of the random generators")->capture_default_str();
  cmd->add_option("-j,--threads", o->threads, "worker threads (results are the same for any count)")
      ->capture_default_str()
      ->check(CLI::Range(1, 256));
  cmd->add_option("--trm", o->trms,
                  "a trace model to sweep (query-format syntax; repeatable; default every kind)");
  cmd->add_option("--mask", o->mask, "content mask of every query (default 265: solid|playerclip|body)")
      ->capture_default_str();
  cmd->add_option("--fail-on", o->failOn, "also exit 1 on these findings: closed-brush")
      ->check(CLI::IsMember({"closed-brush"}));
  cmd->add_option("--examples", o->examples, "failing cases printed per class")
      ->capture_default_str()
      ->check(CLI::Range(std::size_t(0), std::size_t(1000)));
  cmd->add_option("--materials", o->materials, "directory of .mtr files (default: the built-in rules)");
  addNoProcFlag(cmd, o->noProc);
  addRobustEdgesFlag(cmd, o->robustEdges);
  cmd->add_option("--offset", o->offset,
                  "X,Y,Z: move the .map's world geometry by this before building it (no .proc), to soak "
                  "a world far from the origin; compare a float and a -DCMKIT_DOUBLE=ON build")
      ->check(finiteVec3());
  cmd->add_option("--replay", o->replay,
                  "instead: run the translation lines of this query file (e.g. the soak's output) and "
                  "print the class of each end");
  cmd->callback([o] { std::exit(runSoak(*o)); });
}

}  // namespace cmkit::cli
