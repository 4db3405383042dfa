// `cmkit bench MODELS`: the original's collision speed test, and `--suite DIR`
// to time the reference query files per kind.
#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>

#include "bench_report.h"
#include "bench_world.h"
#include "cmkit/text_file.h"
#include "cmkit/tools/query_format.h"
#include "commands.h"
#include "model_loading.h"
#include "option_checks.h"

namespace cmkit::cli {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

/// The query kinds of the suite, in print order.
constexpr std::array<QueryOp, 5> kSuiteOps = {QueryOp::Translation, QueryOp::Rotation, QueryOp::Contents,
                                              QueryOp::PointContents, QueryOp::Contacts};

struct BenchOptions {
  std::string models;
  std::string materials;
  bool noProc = false;  ///< --no-proc
  MeshCliOptions mesh;  ///< --up, --scale, --contents (mesh files)
  std::string trm = kSpeedTestDefaultTrm;
  std::string origin;
  std::string suite;
  int repeat = 1;
  bool json = false;
  bool stats = false;  ///< --stats
  int slowest = 0;     ///< --slowest: the N slowest queries of each kind and file
  bool noRotation = false;
  bool world = false;  ///< --world
  int rounds = 15;     ///< --rounds (--world)
  SpeedTestOptions test;
};

}  // namespace

void printSpeedTestBatch(const SpeedTestBatch& b) {
  fmt::print(
      "{:<12} {:5} queries  total {:9.3f} ms  min {:8.2f} us  avg {:8.2f} us  max {:9.2f} us  hits {:5}  "
      "hash {:016x}\n",
      b.kind + ":", b.count, b.sumMs, b.minUs, b.avgUs, b.maxUs, b.hits, b.hash);
}

bool runAndPrintSpeedTest(const CollisionModel& model, const TraceModel& trm, const std::string& trmSpec,
                          const SpeedTestOptions& options) {
  fmt::print("speed test on model \"{}\" ({} polygons, {} brushes): trm {}, origin ({} {} {})\n",
             model.name(), model.polygons().size(), model.brushes().size(), trmSpec, options.origin.x,
             options.origin.y, options.origin.z);
  fmt::print("  {} translations (end within +-{} per axis){}, mask {:#x}, seed {}{}{}{}\n", options.times,
             options.length,
             options.rotations ? fmt::format(" + {} rotations of {} deg (origins within +-{})", options.times,
                                             options.angle, options.radius)
                               : std::string(),
             options.contentMask, options.seed, options.randomMany ? ", random-many" : "",
             options.walk ? ", walk" : "", options.rays ? ", the moves again as ray casts" : "");
  SpeedTestOptions single = options;
  single.threads = 1;
  const SpeedTestReport one = runSpeedTest(model, trm, single);
  if (options.rays)
    fmt::print("  ray index: {} nodes, {} polygons, {:.1f} MB, built in {:.1f} ms, {} node test\n",
               one.rayIndex.nodes, one.rayIndex.polygons, double(one.rayIndex.bytes) / (1024.0 * 1024.0),
               one.rayIndex.buildMs, one.rayIndex.avx2 ? "AVX2" : "baseline");
  fmt::print("1 thread:\n");
  printSpeedTestBatch(one.translation);
  if (options.rotations) printSpeedTestBatch(one.rotation);
  if (options.rays) printSpeedTestBatch(one.rays);
  if (options.threads <= 1) return true;

  const SpeedTestReport many = runSpeedTest(model, trm, options);
  fmt::print("{} threads:\n", options.threads);
  printSpeedTestBatch(many.translation);
  if (options.rotations) printSpeedTestBatch(many.rotation);
  if (options.rays) printSpeedTestBatch(many.rays);
  bool same = true;
  for (const auto& [a, b] : {std::pair{&one.translation, &many.translation},
                             {&one.rotation, &many.rotation},
                             {&one.rays, &many.rays}}) {
    if (a->count == 0) continue;
    const bool equal = a->hash == b->hash && a->hits == b->hits;
    same = same && equal;
    fmt::print("{:<12} 1 thread {:10.0f} q/s, {} threads {:10.0f} q/s: speed-up {:.2f}x, hash {}\n",
               a->kind + ":", a->queriesPerSecond, options.threads, b->queriesPerSecond,
               a->queriesPerSecond > 0 ? b->queriesPerSecond / a->queriesPerSecond : 0.0,
               equal ? "identical" : "DIFFERENT");
  }
  return same;
}

namespace {

/// The model source of NAME.queries.txt in DIR, as the reference results
/// were made: DIR/../maps/rbdoom-unittests/NAME.cm when it exists (those
/// queries ran on the .cm files), else DIR/../maps/*/NAME.map; empty when
/// there is none.
std::string suiteModelSource(const fs::path& dir, const std::string& name) {
  const fs::path maps = dir / ".." / "maps";
  const fs::path cm = maps / "rbdoom-unittests" / (name + ".cm");
  std::error_code ec;
  if (fs::is_regular_file(cm, ec)) return cm.lexically_normal().string();
  std::vector<fs::path> candidates;
  for (const auto& entry : fs::directory_iterator(maps, ec))
    if (entry.is_directory() && fs::exists(entry.path() / (name + ".map"), ec))
      candidates.push_back(entry.path());
  std::sort(candidates.begin(), candidates.end());
  if (!candidates.empty()) return (candidates.front() / (name + ".map")).lexically_normal().string();
  return {};
}

struct KindTime {
  double ns = 0;
  std::size_t count = 0;  ///< queries timed (lines x passes)
  std::size_t lines = 0;  ///< query lines of this kind
};

/// One row of the suite: a reference file's times per kind, or why it was skipped.
struct SuiteRow {
  std::string name;
  std::string skipped;
  std::map<QueryOp, KindTime> kinds;
};

std::string jsonString(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\')
      out += {'\\', c};
    else if (static_cast<unsigned char>(c) < 0x20)
      out += fmt::format("\\u{:04x}", int(c));
    else
      out += c;
  }
  return out + "\"";
}

std::string jsonKinds(const std::map<QueryOp, KindTime>& kinds) {
  std::string out = "{";
  for (QueryOp op : kSuiteOps) {
    const auto it = kinds.find(op);
    if (it == kinds.end() || !it->second.count) continue;
    if (out.size() > 1) out += ", ";
    out += fmt::format("\"{}\": {{\"ns\": {:.1f}, \"queries\": {}}}", toString(op),
                       it->second.ns / double(it->second.count), it->second.lines);
  }
  return out + "}";
}

/// --slowest: times each query of one kind of a file on its own (--repeat
/// times in a row, the fastest counting: the caches warm, as in the passes)
/// and prints the N slowest with their lines and their share of the kind's
/// time. Returns the results' sum (kept alive by the caller).
double printSlowest(std::span<const ModelPtr> models, const std::vector<ParsedQuery>& queries,
                    const std::vector<int>& lines, const fs::path& file, QueryOp op, const BenchOptions& o,
                    QueryWork& work, std::vector<ContactInfo>& contacts) {
  double sink = 0;
  std::vector<std::pair<double, std::size_t>> times;  // ns, query
  double total = 0;
  for (std::size_t i = 0; i < queries.size(); ++i) {
    double best = std::numeric_limits<double>::infinity();
    for (int pass = 0; pass < o.repeat; ++pass) {
      const auto t0 = Clock::now();
      sink += runParsedQueryUnformatted(models, queries[i], work, contacts);
      best = std::min(best, std::chrono::duration<double, std::nano>(Clock::now() - t0).count());
    }
    times.emplace_back(best, i);
    total += best;
  }
  std::sort(times.begin(), times.end(), std::greater<>());
  const std::size_t n = std::min(times.size(), std::size_t(o.slowest));
  double shown = 0;
  for (std::size_t k = 0; k < n; ++k) shown += times[k].first;
  fmt::print("slowest {} of {} {} queries in {} ({:.1f} % of their time, each the fastest of {} runs):\n", n,
             queries.size(), toString(op), file.filename().string(), total > 0 ? 100 * shown / total : 0.0,
             o.repeat);
  for (std::size_t k = 0; k < n; ++k)
    fmt::print("  {:10.0f} ns  line {}\n", times[k].first, lines[times[k].second]);
  return sink;
}

void printSuiteText(const std::vector<SuiteRow>& rows, const SuiteRow& all, int repeat) {
  fmt::print("ns/query per kind (parsed once, results not formatted; {} pass{}, 1 thread; (n) = queries)\n",
             repeat, repeat == 1 ? "" : "es");
  fmt::print("{:<36}", "file");
  for (QueryOp op : kSuiteOps) fmt::print(" {:>20}", toString(op));
  fmt::print("\n");
  for (const SuiteRow* row : [&] {
         std::vector<const SuiteRow*> r;
         for (const SuiteRow& x : rows) r.push_back(&x);
         r.push_back(&all);
         return r;
       }()) {
    if (!row->skipped.empty()) {
      fmt::print("{:<36} (skipped: {})\n", row->name, row->skipped);
      continue;
    }
    fmt::print("{:<36}", row->name);
    for (QueryOp op : kSuiteOps) {
      const auto it = row->kinds.find(op);
      const bool has = it != row->kinds.end() && it->second.count;
      fmt::print(
          " {:>20}",
          has ? fmt::format("{:.0f} ({})", it->second.ns / double(it->second.count), it->second.lines) : "-");
    }
    fmt::print("\n");
  }
}

/// The kinds that ran (--stats) with their work counters per query, in
/// QueryStats' order after the count: nodes, polygons met, tested and
/// closer, brushes met, vertex tests, edge pairs (the text table and the
/// JSON).
struct KindWork {
  QueryOp op;
  std::uint64_t queries;
  std::array<double, 7> perQuery;
};
std::vector<KindWork> workPerQuery(const std::map<QueryOp, QueryStats>& stats) {
  std::vector<KindWork> out;
  for (QueryOp op : kSuiteOps) {
    const auto it = stats.find(op);
    if (it == stats.end() || it->second.queries == 0) continue;
    const QueryStats& s = it->second;
    const double n = double(s.queries);
    out.push_back({op,
                   s.queries,
                   {double(s.nodesVisited) / n, double(s.polygonsMet) / n, double(s.polygonsTested) / n,
                    double(s.polygonsCloser) / n, double(s.brushesMet) / n, double(s.vertexTests) / n,
                    double(s.edgePairs) / n}});
  }
  return out;
}

/// The work counters per query of each kind (--stats), as a JSON object.
std::string jsonWork(const std::map<QueryOp, QueryStats>& stats) {
  static constexpr const char* kNames[7] = {"nodes",           "polygons met", "polygons tested",
                                            "polygons closer", "brushes met",  "vertex tests",
                                            "edge pairs"};
  std::string out = "{";
  for (const KindWork& k : workPerQuery(stats)) {
    if (out.size() > 1) out += ", ";
    out += fmt::format("\"{}\": {{\"queries\": {}", toString(k.op), k.queries);
    for (std::size_t c = 0; c < k.perQuery.size(); ++c)
      out += fmt::format(", \"{}\": {:.2f}", kNames[c], k.perQuery[c]);
    out += "}";
  }
  return out + "}";
}

/// The suite's times as JSON; with --stats (`work` set) the work counters too
/// (in the JSON: text after it would break its readers).
void printSuiteJson(const std::vector<SuiteRow>& rows, const SuiteRow& all, int repeat,
                    const std::map<QueryOp, QueryStats>* work) {
  fmt::print("{{\n  \"unit\": \"ns per query\",\n  \"passes\": {},\n  \"threads\": 1,\n  \"files\": [\n",
             repeat);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const SuiteRow& r = rows[i];
    fmt::print("    {{\"name\": {}, ", jsonString(r.name));
    if (!r.skipped.empty())
      fmt::print("\"skipped\": {}}}", jsonString(r.skipped));
    else
      fmt::print("\"kinds\": {}}}", jsonKinds(r.kinds));
    fmt::print("{}\n", i + 1 < rows.size() ? "," : "");
  }
  fmt::print("  ],\n  \"all\": {}", jsonKinds(all.kinds));
  if (work) fmt::print(",\n  \"work per query\": {}", jsonWork(*work));
  fmt::print("\n}}\n");
}

/// The work counters of one query kind over the suite (--stats).
void printSuiteStats(const std::map<QueryOp, QueryStats>& stats) {
  fmt::print(
      "\nwork per query, all files (counted by a CMKIT_QUERY_STATS build; see QueryStats in "
      "cmkit/query.h)\n");
  fmt::print("{:<14} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9}\n", "kind", "queries", "nodes",
             "polys met", "polys tst", "closer", "brushes", "vert tst", "edge prs");
  for (const KindWork& k : workPerQuery(stats)) {
    const auto& w = k.perQuery;
    fmt::print("{:<14} {:>9} {:>9.1f} {:>9.1f} {:>9.1f} {:>9.1f} {:>9.1f} {:>9.1f} {:>9.1f}\n",
               toString(k.op), k.queries, w[0], w[1], w[2], w[3], w[4], w[5], w[6]);
  }
}

int runSuite(const BenchOptions& o) {
  if (o.stats && !queryStatsEnabled()) {
    fmt::print(stderr,
               "cmkit bench: --stats needs a library that counts the queries' work; build one with\n"
               "  cmake --preset stats && cmake --build --preset stats   (then build/stats/bin/cmkit)\n");
    return kExitBadInput;
  }
  const fs::path dir(o.suite);
  std::error_code ec;
  std::vector<fs::path> files;
  const std::string suffix = ".queries.txt";
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string f = entry.path().filename().string();
    if (f.size() > suffix.size() && f.compare(f.size() - suffix.size(), suffix.size(), suffix) == 0)
      files.push_back(entry.path());
  }
  if (ec || files.empty()) {
    fmt::print(stderr, "cmkit bench: --suite {}: no NAME.queries.txt files\n", o.suite);
    return kExitBadInput;
  }
  std::sort(files.begin(), files.end());
  std::vector<SuiteRow> rows;
  SuiteRow all{"all files", {}, {}};
  QueryWork work;
  std::vector<ContactInfo> contacts;    // kept from query to query, as a game loop keeps it
  std::map<QueryOp, QueryStats> stats;  // --stats: per kind, all files
  double sink = 0;
  for (const fs::path& file : files) {
    const std::string fname = file.filename().string();
    SuiteRow& row = rows.emplace_back();
    row.name = fname.substr(0, fname.size() - suffix.size());
    const std::string source = suiteModelSource(dir, row.name);
    if (source.empty()) {
      row.skipped = "no model source";
      continue;
    }
    auto models = loadModelsForCli(source, o.materials, o.noProc, o.mesh);
    if (!models) {
      row.skipped = models.error().toString();
      continue;
    }
    const Result<std::string> text = readTextFile(file.string());
    if (!text) {
      row.skipped = text.error().toString();
      continue;
    }
    std::map<QueryOp, std::vector<ParsedQuery>> byKind;
    std::map<QueryOp, std::vector<int>> lineNumbers;  // (--slowest) each query's line in the file
    int lineNumber = 0;
    for (std::size_t pos = 0; pos < text->size();) {
      const std::size_t nl = std::min(text->find('\n', pos), text->size());
      const std::string_view line = std::string_view(*text).substr(pos, nl - pos);
      pos = nl + 1;
      ++lineNumber;
      if (!isQueryLine(line)) continue;
      auto parsed = parseQueryLine(*models, line);
      if (!parsed) continue;
      lineNumbers[parsed->op].push_back(lineNumber);
      byKind[parsed->op].push_back(std::move(*parsed));
    }
    for (QueryOp op : kSuiteOps) {
      const auto& queries = byKind[op];
      if (queries.empty()) continue;
      work.resetStats();
      const auto t0 = Clock::now();
      for (int pass = 0; pass < o.repeat; ++pass)
        for (const ParsedQuery& q : queries) sink += runParsedQueryUnformatted(*models, q, work, contacts);
      const double ns = std::chrono::duration<double, std::nano>(Clock::now() - t0).count();
      QueryStats& st = stats[op];
      const QueryStats& w = work.stats();
      for (auto field : {&QueryStats::queries, &QueryStats::nodesVisited, &QueryStats::polygonsMet,
                         &QueryStats::polygonsTested, &QueryStats::polygonsCloser, &QueryStats::brushesMet,
                         &QueryStats::vertexTests, &QueryStats::edgePairs})
        st.*field += w.*field;
      const std::size_t n = queries.size() * std::size_t(o.repeat);
      row.kinds[op] = {ns, n, queries.size()};
      KindTime& t = all.kinds[op];
      t.ns += ns;
      t.count += n;
      t.lines += queries.size() * std::size_t(o.repeat);
      if (o.slowest > 0) sink += printSlowest(*models, queries, lineNumbers[op], file, op, o, work, contacts);
    }
  }
  if (o.json) {
    printSuiteJson(rows, all, o.repeat, o.stats ? &stats : nullptr);
  } else {
    printSuiteText(rows, all, o.repeat);
    if (o.stats) printSuiteStats(stats);
  }
  if (sink == -1) fmt::print("\n");  // keeps the results alive
  return 0;
}

int runBench(const BenchOptions& o) {
  if (!o.suite.empty()) return runSuite(o);
  if (o.world) {
    WorldBenchOptions w;
    w.map = o.models;
    w.materials = o.materials;
    w.noProc = o.noProc;
    w.trm = o.trm;
    w.times = o.test.times;
    w.length = double(o.test.length);
    w.seed = o.test.seed;
    w.rounds = o.rounds;
    return runWorldBench(w);
  }
  if (o.models.empty()) {
    fmt::print(stderr, "cmkit bench: give MODELS (a .map, .cm or mesh file) or --suite DIR\n");
    return kExitBadInput;
  }
  auto models = loadModelsForCli(o.models, o.materials, o.noProc, o.mesh);
  if (!models) {
    fmt::print(stderr, "cmkit bench: {}\n", models.error().toString());
    return kExitBadInput;
  }
  if (models->empty()) {
    fmt::print(stderr, "cmkit bench: {}: no collision models\n", o.models);
    return kExitBadInput;
  }
  auto trm = TraceModel::parse(o.trm);
  if (!trm) {
    fmt::print(stderr, "cmkit bench: --trm: {}\n", trm.error().toString());
    return kExitBadInput;
  }
  const CollisionModel& world = *models->front();
  SpeedTestOptions test = o.test;
  test.rotations = !o.noRotation;
  if (o.origin.empty()) {
    test.origin = (world.bounds().min + world.bounds().max) * Real(0.5);
  } else {
    test.origin = *parseFiniteVec3(o.origin);  // checked while parsing the options
  }
  fmt::print("{}: ", o.models);
  return runAndPrintSpeedTest(world, *trm, o.trm, test) ? 0 : 1;
}

}  // namespace

void registerBench(CLI::App& app) {
  auto o = std::make_shared<BenchOptions>();
  auto* cmd = app.add_subcommand(
      "bench",
      "The original's collision speed test (cm_testCollision): --times translations of a trace\n"
      "model from an origin (default: the centre of the world model) to seeded random end points\n"
      "within +-length per axis (mask solid|playerclip), then --times rotations of --angle degrees\n"
      "about random axes through points within +-radius of the origin. Every query is timed;\n"
      "per kind it prints the total, min/avg/max, the hits (fraction < 1) and a hash of all\n"
      "results, which is the same at any --threads. --rays also casts the moves as rays through\n"
      "a RayIndex (cmkit's fast ray casts: the first surface crossed, not the original's point\n"
      "trace).\n\n"
      "--suite DIR times every NAME.queries.txt of DIR (files of queries in the query format) against\n"
      "its models (DIR/../maps/rbdoom-unittests/NAME.cm, else DIR/../maps/*/NAME.map): each file is\n"
      "parsed once and run --repeat times on 1 thread; it prints ns/query per kind and file, or JSON\n"
      "with --json. bench/compare.sh OLD_COMMIT compares these tables of two builds in one run.\n"
      "--stats adds the work per query of each kind (tree nodes, polygons met and tested, the tested\n"
      "ones that brought the nearest contact closer, feature tests), counted by a library built with\n"
      "-DCMKIT_QUERY_STATS=ON (cmake --preset stats); with --json as the object \"work per query\".\n\n"
      "Examples:\n"
      "  cmkit bench data/maps/lt4/lt4.map\n"
      "  cmkit bench data/maps/lt4/lt4.map --threads 2 --walk\n"
      "  cmkit bench data/maps/lt4/lt4.map --rays --no-rotation\n"
      "  cmkit bench --suite ../shared/reference --repeat 20\n"
      "  cmkit bench --suite ../shared/reference --repeat 20 --slowest 10\n"
      "  cmkit bench --suite ../shared/reference --json\n"
      "  build/stats/bin/cmkit bench --suite ../shared/reference --stats");
  cmd->add_option("MODELS", o->models,
                  "a .map (built on the fly), .cm or mesh file (.obj, .glb, ...); the first model is tested");
  cmd->add_option("--trm", o->trm, "trace model (query-format syntax)")->capture_default_str();
  cmd->add_option("--origin", o->origin, "start of the moves x,y,z (default: centre of the model's bounds)")
      ->check(finiteVec3());
  cmd->add_option("--times", o->test.times, "queries per kind (cm_testTimes)")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000000));
  cmd->add_option("--length", o->test.length, "end points within +-length per axis (cm_testLength)")
      ->capture_default_str()
      ->check(finiteAtLeast(0));
  cmd->add_option("--angle", o->test.angle, "degrees per rotation (cm_testAngle)")
      ->capture_default_str()
      ->check(finiteNumber());
  cmd->add_option("--radius", o->test.radius, "rotation origins within +-radius (cm_testRadius)")
      ->capture_default_str()
      ->check(finiteAtLeast(0));
  cmd->add_flag("--random-many", o->test.randomMany, "one shared end point / rotation (cm_testRandomMany)");
  cmd->add_flag("--walk", o->test.walk, "chained moves: each starts where the previous ended (cm_testWalk)");
  cmd->add_flag("--no-rotation", o->noRotation, "translations only");
  cmd->add_flag("--rays", o->test.rays, "also cast the moves as RayIndex rays (not in the original)");
  cmd->add_option("--seed", o->test.seed, "seed of the random generator")->capture_default_str();
  cmd->add_option("-j,--threads", o->test.threads, "also run on this many threads and compare")
      ->capture_default_str()
      ->check(CLI::Range(1, 256));
  cmd->add_flag(
      "--world", o->world,
      "MODELS is a .map: time --times translations (--trm, ends within +-length, --seed) that meet no "
      "entity on the whole World and on its world model alone, in alternating rounds, and print "
      "the ratio (docs/world.md, \"Cost\")");
  cmd->add_option("--rounds", o->rounds, "--world: alternating rounds (the best of each side counts)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));
  cmd->add_option("--suite", o->suite, "time every NAME.queries.txt of this directory");
  cmd->add_option("--repeat", o->repeat, "suite: passes over each file")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  CLI::Option* json =
      cmd->add_flag("--json", o->json, "suite: print the times as JSON (for scripts) instead of the table");
  cmd->add_flag("--stats", o->stats,
                "suite: also print the work per query (nodes, polygons, feature tests) of each kind; needs a "
                "build with -DCMKIT_QUERY_STATS=ON (cmake --preset stats)");
  cmd->add_option("--slowest", o->slowest,
                  "suite: also time each query on its own (--repeat runs, the fastest counting) and print "
                  "the N slowest of each kind and file, with their line numbers and share of the time (not "
                  "with --json: the lists are text)")
      ->check(CLI::Range(1, 1000000))
      ->excludes(json);
  cmd->add_option("--materials", o->materials, "directory of .mtr files (default: the built-in rules)");
  addNoProcFlag(cmd, o->noProc);
  addMeshOptions(cmd, o->mesh);
  cmd->callback([o] {
    if (int rc = runBench(*o); rc != 0) std::exit(rc);
  });
}

}  // namespace cmkit::cli
