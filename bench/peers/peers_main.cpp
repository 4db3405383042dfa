// cmkit_peers: cmkit against Jolt, Bullet and Embree on the same triangles
// and the same queries, in one run and one process, with the agreement of
// each engine with an exact reference (reference.cpp). `--help` explains.
// The old program (the speed test's moves on lt4 and the batches) is the
// `--speed-test` section (speed_test_section.cpp).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "cmkit_side.h"
#include "peers.h"
#include "reference.h"

namespace {

using namespace peers;
using Clock = std::chrono::steady_clock;

constexpr int kDefaultQueries = 10000;
constexpr int kDefaultPasses = 5;
constexpr int kDefaultSpeedTestTimes = 1000;
constexpr std::uint64_t kQuerySeed = 7;
constexpr double kMinLength = 1, kMaxLength = 2000;

/// Distance tolerance of the peers against the exact contact. Their answers
/// are float fractions of moves of up to 2000 units (float's step there is
/// ~1e-4 of a unit) found by iterative methods with their own tolerances
/// (Jolt's and Bullet's GJK-based casts converge to ~1e-3 units); 0.05
/// units is far above both and far below any shape's size.
constexpr double kPeerTolerance = 0.05;
/// Distance tolerance of cmkit against its clip-epsilon bracket
/// (reference.h): the bracket is exact in double; cmkit works in float on
/// coordinates up to ~8000 (a float step of 5e-4 there) and fractions of moves
/// up to 2000 units (a step of ~1e-4): 0.02 units is 40 times those.
constexpr double kCmkitTolerance = 0.02;
/// --list: print every query whose answer disagrees.
bool gList = false;

/// The fastest of `passes` runs of run(), in ns per query of n.
template <class F>
double fastest(int passes, std::size_t n, F&& run) {
  double best = 0;
  for (int p = 0; p < passes; ++p) {
    const auto t0 = Clock::now();
    run();
    const double ns = std::chrono::duration<double, std::nano>(Clock::now() - t0).count() / double(n);
    best = p == 0 ? ns : std::min(best, ns);
  }
  return best;
}

/// The queries: starts uniform in the scene's bounds, directions uniform on
/// the sphere, lengths log-uniform in [kMinLength, kMaxLength].
std::vector<Query> makeQueries(const Scene& scene, std::size_t n) {
  Rng rng(kQuerySeed);
  std::vector<Query> qs(n);
  for (Query& q : qs) {
    double d[3], len2;
    do {
      for (double& c : d) c = rng.uniform(-1, 1);
      len2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    } while (len2 > 1 || len2 < 1e-6);
    const double length = std::exp(rng.uniform(std::log(kMinLength), std::log(kMaxLength))) / std::sqrt(len2);
    for (int k = 0; k < 3; ++k) {
      const double s = rng.uniform(scene.boundsMin[k], scene.boundsMax[k]);
      q.start[k] = float(s);
      q.end[k] = float(s + d[k] * length);
    }
  }
  return qs;
}

/// A fixed orientation that turns every axis (rows = the shape's axes): 37
/// degrees about (1, 2, 3).
void fixedAxis(float (&axis)[9]) {
  const double a = 37 * 3.14159265358979323846 / 180, l = std::sqrt(14.0);
  const double x = 1 / l, y = 2 / l, z = 3 / l, c = std::cos(a), s = std::sin(a), t = 1 - c;
  const double m[9] = {t * x * x + c,     t * x * y - s * z, t * x * z + s * y,
                       t * x * y + s * z, t * y * y + c,     t * y * z - s * x,
                       t * x * z - s * y, t * y * z + s * x, t * z * z + c};
  for (int i = 0; i < 9; ++i) axis[i] = float(m[i]);
}

struct Kind {
  const char* name;
  const char* trm;
  bool turned;
};
constexpr Kind kKinds[] = {{"point ray", "point", false},
                           {"box", "box:-16,-16,0,16,16,64", false},
                           {"box+axis", "box:-16,-16,0,16,16,64", true},
                           {"cylinder:8", "cylinder:8:-16,-16,0,16,16,64", false},
                           {"cylinder:8+axis", "cylinder:8:-16,-16,0,16,16,64", true}};
constexpr int kNumKinds = 5;
enum Engine { kCmkit, kJolt, kBullet, kEmbree, kEngines };
constexpr const char* kEngineNames[kEngines] = {"cmkit", "Jolt", "Bullet", "Embree"};

/// Each engine's fastest of `passes` runs of run(e), in ns per query of n,
/// for the engines e with has[e] (the others get -1). The engines' passes
/// are interleaved, pass 1 of each, then pass 2 of each, ..., the first
/// engine of a pass turning from pass to pass: a burst of load on the
/// machine (on this project's shared 2-core VM, seconds long) then falls on
/// every engine's passes alike, where all passes of one engine and then all
/// of the next put it on one engine's and moved their ratio by up to 1.5x
/// from run to run.
template <class F>
void fastestInterleaved(int passes, std::size_t n, const bool (&has)[kEngines], double (&ns)[kEngines],
                        F&& run) {
  int engines[kEngines];
  int count = 0;
  for (int e = 0; e < kEngines; ++e) {
    ns[e] = -1;
    if (has[e]) engines[count++] = e;
  }
  for (int p = 0; p < passes; ++p)
    for (int k = 0; k < count; ++k) {
      const int e = engines[(p + k) % count];
      const auto t0 = Clock::now();
      run(e);
      const double t = std::chrono::duration<double, std::nano>(Clock::now() - t0).count() / double(n);
      ns[e] = ns[e] < 0 ? t : std::min(ns[e], t);
    }
}

/// One engine's agreement with the reference on one kind.
struct Agreement {
  int hitAgree = 0;
  int bothHit = 0;
  int distAgree = 0;
  double worst = 0;  // largest distance error where both hit
};

struct Row {
  double ns[kEngines] = {-1, -1, -1, -1};
  Agreement agree[kEngines];
  int excluded = 0, considered = 0, refHits = 0;
};

Agreement agreement(const std::vector<RefAnswer>& ref, std::span<const Query> qs, const std::vector<float>& f,
                    bool cmkitModel, double tolerance) {
  Agreement a;
  for (std::size_t i = 0; i < ref.size(); ++i) {
    const RefAnswer& r = ref[i];
    if (r.startOverlap) continue;
    double len = 0;
    for (int k = 0; k < 3; ++k)
      len += double(qs[i].end[k] - qs[i].start[k]) * double(qs[i].end[k] - qs[i].start[k]);
    len = std::sqrt(len);
    const bool hit = f[i] <= 1;
    // The exact contact, or cmkit's bracket (reference.h).
    const bool mustHit = cmkitModel ? r.cmkitMustHit : r.hit, mayHit = cmkitModel ? r.cmkitMayHit : r.hit;
    const double earliest = cmkitModel ? r.cmkitEarliest : r.dist,
                 latest = cmkitModel ? r.cmkitLatest : r.dist;
    if (hit ? mayHit : !mustHit)
      ++a.hitAgree;
    else if (gList)
      std::printf("  disagrees: query %zu length %.3f answered %s, expected %s\n", i, len,
                  hit ? "hit" : "miss", mustHit ? "hit" : "miss");
    if (!hit || !mayHit) continue;
    ++a.bothHit;
    const double d = double(f[i]) * len;
    const double err = d < earliest ? earliest - d : d > latest ? d - latest : 0;
    a.worst = std::max(a.worst, err);
    if (err <= tolerance)
      ++a.distAgree;
    else if (gList)
      std::printf("  disagrees: query %zu length %.3f exact %.4f expected %.4f..%.4f answered %.4f\n", i, len,
                  r.dist, earliest, latest, d);
  }
  return a;
}

std::string cell(double v, const char* fmt) {
  if (v < 0) return "-";
  char b[32];
  std::snprintf(b, sizeof b, fmt, v);
  return b;
}

std::string pct(int n, int of) { return of > 0 ? cell(100.0 * n / of, "%.2f") : "-"; }

struct SceneReport {
  std::string title;
  Row rows[kNumKinds];
  double buildMs[kEngines] = {-1, -1, -1, -1};
  double rayIndexMs = -1;
  bool present[kEngines] = {true, false, false, false};
};

void printReport(const SceneReport& r, bool markdown) {
  const char* sep = markdown ? " | " : "  ";
  auto line = [&](const std::vector<std::string>& cells, const std::vector<int>& widths) {
    std::string s = markdown ? "| " : "";
    for (std::size_t i = 0; i < cells.size(); ++i) {
      char b[64];
      std::snprintf(b, sizeof b, i == 0 ? "%-*s" : "%*s", widths[i], cells[i].c_str());
      s += b;
      if (i + 1 < cells.size()) s += sep;
    }
    std::printf("%s%s\n", s.c_str(), markdown ? " |" : "");
  };
  auto rule = [&](const std::vector<int>& widths) {
    if (!markdown) return;
    std::string s = "|";
    for (std::size_t i = 0; i < widths.size(); ++i)
      s += (i == 0 ? ":" : "") + std::string(std::size_t(widths[i] + 1), '-') + (i == 0 ? "|" : ":|");
    std::printf("%s\n", s.c_str());
  };
  std::printf("\n%s%s\n\n", markdown ? "#### " : "", r.title.c_str());
  const std::vector<int> w = {22, 9, 9, 9, 9, 10, 12, 12};
  line({"ns/query (fastest pass)", "cmkit", "Jolt", "Bullet", "Embree", "cmkit/Jolt", "cmkit/Bullet",
        "cmkit/Embree"},
       w);
  rule(w);
  auto ratio = [](double a, double b) { return a > 0 && b > 0 ? cell(a / b, "%.2f") : std::string("-"); };
  for (int k = 0; k < kNumKinds; ++k) {
    const Row& row = r.rows[k];
    line({kKinds[k].name, cell(row.ns[kCmkit], "%.0f"), cell(row.ns[kJolt], "%.0f"),
          cell(row.ns[kBullet], "%.0f"), cell(row.ns[kEmbree], "%.0f"), ratio(row.ns[kCmkit], row.ns[kJolt]),
          ratio(row.ns[kCmkit], row.ns[kBullet]), ratio(row.ns[kCmkit], row.ns[kEmbree])},
         w);
  }
  const double* b = r.buildMs;
  line({"build, model (ms)", cell(b[kCmkit], "%.1f"), cell(b[kJolt], "%.1f"), cell(b[kBullet], "%.1f"), "-",
        ratio(b[kCmkit], b[kJolt]), ratio(b[kCmkit], b[kBullet]), "-"},
       w);
  line({"build, ray index (ms)", cell(r.rayIndexMs, "%.1f"), "-", "-", cell(b[kEmbree], "%.1f"), "-", "-",
        ratio(r.rayIndexMs, b[kEmbree])},
       w);
  std::printf("\n");
  std::vector<std::string> head = {"agreement: hit% / dist%", "excluded", "ref hits"};
  std::vector<int> w2 = {23, 8, 8};
  for (int e = 0; e < kEngines; ++e)
    if (r.present[e]) {
      head.push_back(kEngineNames[e]);
      w2.push_back(15);
    }
  line(head, w2);
  rule(w2);
  for (int k = 0; k < kNumKinds; ++k) {
    const Row& row = r.rows[k];
    std::vector<std::string> c = {kKinds[k].name, std::to_string(row.excluded), std::to_string(row.refHits)};
    for (int e = 0; e < kEngines; ++e) {
      if (!r.present[e]) continue;
      c.push_back(row.ns[e] < 0 ? "-"
                                : pct(row.agree[e].hitAgree, row.considered) + " / " +
                                      pct(row.agree[e].distAgree, row.agree[e].bothHit));
    }
    line(c, w2);
  }
}

/// Timed passes of a build at most (--build-passes).
int gBuildPasses = 5;
/// --no-reference: times only (profiling), no exact reference.
bool gNoReference = false;
/// --peers: the peers to run (empty: all), by name.
std::vector<std::string> gPeers;
/// --kinds: the kinds to run (empty: all), by name.
std::vector<std::string> gKinds;
/// The items of a comma-separated list.
std::vector<std::string> splitList(const std::string& list) {
  std::vector<std::string> items;
  for (std::size_t at = 0; at <= list.size();) {
    const std::size_t comma = std::min(list.find(',', at), list.size());
    items.push_back(list.substr(at, comma - at));
    at = comma + 1;
  }
  return items;
}
bool wanted(const Kind& kind) {
  return gKinds.empty() || std::find(gKinds.begin(), gKinds.end(), kind.name) != gKinds.end();
}

SceneReport runScene(const Scene& scene, std::size_t n, int passes, int threads, bool verbose) {
  SceneReport r;
  std::printf(
      "%s: %zu triangles, %zu vertices; %zu queries (starts uniform in the bounds, directions uniform, "
      "lengths log-uniform in [%g, %g]); fastest of %d passes\n",
      scene.name.c_str(), scene.numTriangles(), scene.numVertices(), n, kMinLength, kMaxLength, passes);
  std::fflush(stdout);
  std::unique_ptr<Peer> peers[kEngines] = {nullptr, makeJoltPeer(), makeBulletPeer(), makeEmbreePeer()};
  for (int e = kJolt; e < kEngines; ++e)
    if (!gPeers.empty() && std::find(gPeers.begin(), gPeers.end(), kEngineNames[e]) == gPeers.end())
      peers[e].reset();
  CmkitEngine cmkit;
  bool ok = true;
  // (Builds: the fastest of at most kBuildPasses, whatever --passes says:
  // they take long. Interleaved as the queries below.)
  const int buildPasses = std::min(passes, gBuildPasses);
  for (int e = kJolt; e < kEngines; ++e) r.present[e] = peers[e] != nullptr;
  fastestInterleaved(buildPasses, 1, r.present, r.buildMs, [&](int e) {
    if (e == kCmkit)
      ok = ok && cmkit.buildModel(scene);
    else
      peers[e]->build(scene);
  });
  if (!ok) return r;
  for (double& ms : r.buildMs)
    if (ms >= 0) ms *= 1e-6;
  r.rayIndexMs = fastest(buildPasses, 1, [&] { cmkit.buildRayIndex(); }) * 1e-6;
  if (verbose) {
    std::printf("  cmkit's model: %s\n", cmkit.modelSize().c_str());
    std::printf("  cmkit's ray index: %s\n", cmkit.rayIndexSize().c_str());
  }
  const std::vector<Query> qs = makeQueries(scene, n);
  const RefScene refScene(scene);
  float axis[9];
  fixedAxis(axis);
  const float identity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  for (int k = 0; k < kNumKinds; ++k) {
    const Kind& kind = kKinds[k];
    if (!wanted(kind)) continue;
    ShapeSpec spec;
    spec.name = kind.name;
    if (!cmkit.prepare(kind.trm, kind.turned ? axis : identity, spec)) continue;
    const auto t0 = Clock::now();
    // (--no-reference: every query counted as a reference miss; the agreement columns then mean nothing.)
    const std::vector<RefAnswer> ref =
        gNoReference ? std::vector<RefAnswer>(n) : exactReference(refScene, spec, qs, threads);
    const double refSeconds = std::chrono::duration<double>(Clock::now() - t0).count();
    Row& row = r.rows[k];
    for (const RefAnswer& a : ref) {
      row.excluded += a.startOverlap;
      row.refHits += !a.startOverlap && a.hit;
    }
    row.considered = int(n) - row.excluded;
    // Each engine's answers in its own array (the passes are interleaved).
    bool has[kEngines] = {true, false, false, false};
    std::vector<float> answers[kEngines];
    for (int e = 0; e < kEngines; ++e) {
      if (e != kCmkit && (!peers[e] || (!spec.point && !peers[e]->hasSweeps()))) continue;
      if (e != kCmkit) peers[e]->prepare(spec);
      has[e] = true;
      answers[e].resize(n);
    }
    fastestInterleaved(passes, n, has, row.ns, [&](int e) {
      float* out = answers[e].data();
      if (e == kCmkit)
        spec.point ? cmkit.rays(qs, out) : cmkit.sweep(qs, out);
      else
        spec.point ? peers[e]->rays(qs, out) : peers[e]->sweep(qs, out);
    });
    for (int e = 0; e < kEngines; ++e)
      if (has[e])
        row.agree[e] = e == kCmkit ? agreement(ref, qs, answers[e], !spec.point,
                                               spec.point ? kPeerTolerance : kCmkitTolerance)
                                   : agreement(ref, qs, answers[e], false, kPeerTolerance);
    if (verbose) {
      std::printf("  %-16s reference %.1f s; largest distance error where both hit:", kind.name, refSeconds);
      for (int e = 0; e < kEngines; ++e)
        if (row.ns[e] >= 0) std::printf(" %s %.4g", kEngineNames[e], row.agree[e].worst);
      std::printf("\n");
      std::fflush(stdout);
    }
  }
  r.title = scene.name + ", " + std::to_string(scene.numTriangles()) + " triangles, " + std::to_string(n) +
            " queries";
  return r;
}

std::string defaultMap() {
  namespace fs = std::filesystem;
  const fs::path source(CMKIT_SOURCE_DIR);
  for (const fs::path& p :
       {source / ".." / "shared" / "maps" / "lt4" / "lt4.map", source / "data" / "maps" / "lt4" / "lt4.map"})
    if (fs::exists(p)) return p.lexically_normal().string();
  return {};
}

void help() {
  std::printf(
      "usage: cmkit_peers [--queries N] [--passes N] [--scene lt4|generated|both] [--map MAP] [--markdown]\n"
      "                   [--threads N] [--verbose] [--list] [--kinds K,...] [--peers P,...] "
      "[--no-reference]\n"
      "       cmkit_peers --speed-test [MAP] [--times N] [--passes N]\n"
      "\n"
      "Times cmkit against Jolt, Bullet and Embree on the same triangles and the same queries, in\n"
      "one process, and checks every engine against an exact reference.\n"
      "\n"
      "Scenes: lt4's world model (every solid|playerclip polygon as a triangle fan) and a generated\n"
      "scene (~50k triangles: terrain, crates, stairs, ramps). Every engine gets the same triangles,\n"
      "two-sided: cmkit a mesh with one two-sided solid material (buildCollisionModelFromTriangles),\n"
      "Jolt a MeshShape (back faces collide), Bullet a btBvhTriangleMeshShape, Embree a scene.\n"
      "\n"
      "Queries (fixed seed): starts uniform in the scene's bounds, directions uniform on the sphere,\n"
      "lengths log-uniform in [1, 2000]; the same for every kind and engine. Kinds: point ray\n"
      "(cmkit RayIndex::cast, Jolt MeshShape::CastRay, Bullet rayTest, Embree rtcIntersect1); box\n"
      "-16,-16,0..16,16,64 and an 8-sided cylinder of the same bounds, each also turned by a fixed\n"
      "orientation (+axis): cmkit translate(), Jolt BoxShape/ConvexHullShape (convex radius 0) cast\n"
      "with CollisionDispatch::sCastShapeVsShapeLocalSpace, Bullet convexSweepTest (margins 0).\n"
      "Times: ns per query, the fastest of --passes passes over all queries; builds in ms (the\n"
      "fastest of --passes, at most 5). The engines' passes are interleaved (pass 1 of each, then\n"
      "pass 2 of each, ...), so that a burst of load on the machine falls on all of them.\n"
      "Ratios: cmkit time / peer time (below 1: cmkit faster).\n"
      "\n"
      "Agreement: hit%% = queries whose hit/miss matches the reference; dist%% = of the queries both\n"
      "hit, those whose stop distance matches (peers and cmkit's rays: the exact contact within\n"
      "%.2g units; cmkit's sweeps: within %.2g units of the bracket of its clip epsilon: cmkit stops\n"
      "0.25 units in front of a surface along its normal, so it meets the shapes with their\n"
      "separating planes pushed out by 0.25, by up to 0.25 x |edge normal| on edge pairs, see\n"
      "reference.h). Queries starting in contact with a triangle (by the reference)\n"
      "are excluded and counted. The reference is brute force in double precision (reference.cpp).\n"
      "\n"
      "  --queries N   queries per kind (default %d)\n"
      "  --passes N    timed passes, the fastest counts (default %d)\n"
      "  --scene S     lt4, generated or both (default both)\n"
      "  --map MAP     the map of the lt4 scene (default: lt4.map of the shared data or data/)\n"
      "  --markdown    print the tables as Markdown\n"
      "  --threads N   threads of the reference (not timed; default 2)\n"
      "  --verbose     the reference's time and each engine's largest distance error per kind;\n"
      "                the size of cmkit's model and ray index\n"
      "  --list        also every query on which an engine disagrees (before its kind's line)\n"
      "  --kinds K,..  only these kinds (point ray, box, box+axis, cylinder:8, cylinder:8+axis;\n"
      "                default all), e.g. --kinds 'point ray,box+axis'\n"
      "  --build-passes N  timed passes of each build at most (default 5)\n"
      "  --peers P,..  only these peers (Jolt, Bullet, Embree; default all)\n"
      "  --no-reference  times only, for profiling: no exact reference (the agreement columns\n"
      "                are then meaningless)\n"
      "  --speed-test  the older comparison instead: the speed test's moves from lt4's centre\n"
      "                through cmkit, Bullet and Embree, and batches on 1 and 2 threads\n"
      "                (--times N moves, default %d)\n"
      "\n"
      "Jolt is compared when cmkit_peers was built with it (bench/peers/build_jolt.sh), Embree\n"
      "when libembree-dev was found.\n",
      kPeerTolerance, kCmkitTolerance, kDefaultQueries, kDefaultPasses, kDefaultSpeedTestTimes);
}

}  // namespace

int main(int argc, char** argv) {
  int queries = kDefaultQueries, passes = kDefaultPasses, times = kDefaultSpeedTestTimes, threads = 2;
  std::string sceneArg = "both", mapPath;
  bool markdown = false, speedTest = false, verbose = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool hasValue = i + 1 < argc;
    if (arg == "--queries" && hasValue)
      queries = std::max(1, std::atoi(argv[++i]));
    else if (arg == "--passes" && hasValue)
      passes = std::max(1, std::atoi(argv[++i]));
    else if (arg == "--times" && hasValue)
      times = std::max(1, std::atoi(argv[++i]));
    else if (arg == "--threads" && hasValue)
      threads = std::max(1, std::atoi(argv[++i]));
    else if (arg == "--scene" && hasValue)
      sceneArg = argv[++i];
    else if (arg == "--map" && hasValue)
      mapPath = argv[++i];
    else if (arg == "--markdown")
      markdown = true;
    else if (arg == "--no-reference")
      gNoReference = true;
    else if (arg == "--build-passes" && hasValue)
      gBuildPasses = std::max(1, std::atoi(argv[++i]));
    else if (arg == "--peers" && hasValue) {
      gPeers = splitList(argv[++i]);
      for (const std::string& name : gPeers)
        if (std::find(kEngineNames + kJolt, kEngineNames + kEngines, name) == kEngineNames + kEngines) {
          std::fprintf(stderr, "cmkit_peers: unknown peer '%s' (--help)\n", name.c_str());
          return 2;
        }
    } else if (arg == "--kinds" && hasValue) {
      gKinds = splitList(argv[++i]);
      for (const std::string& name : gKinds)
        if (std::none_of(std::begin(kKinds), std::end(kKinds),
                         [&](const Kind& k) { return name == k.name; })) {
          std::fprintf(stderr, "cmkit_peers: unknown kind '%s' (--help)\n", name.c_str());
          return 2;
        }
    } else if (arg == "--verbose")
      verbose = true;
    else if (arg == "--list")
      gList = verbose = true;
    else if (arg == "--speed-test")
      speedTest = true;
    else if (arg == "-h" || arg == "--help") {
      help();
      return 0;
    } else if (speedTest && arg[0] != '-')
      mapPath = arg;
    else {
      std::fprintf(stderr, "cmkit_peers: unknown argument '%s' (--help)\n", arg.c_str());
      return 2;
    }
  }
  if (sceneArg != "lt4" && sceneArg != "generated" && sceneArg != "both") {
    std::fprintf(stderr, "cmkit_peers: --scene lt4, generated or both\n");
    return 2;
  }
  if (mapPath.empty()) mapPath = defaultMap();
  if (speedTest) {
    if (mapPath.empty()) {
      std::fprintf(stderr, "cmkit_peers: no map given and lt4.map not found\n");
      return 2;
    }
    return runSpeedTestSection(mapPath, times, passes);
  }
  if (!joltCompiledIn()) std::printf("Jolt: not compared (run bench/peers/build_jolt.sh)\n");
  if (!embreeCompiledIn())
    std::printf("Embree: not compared (cmkit_peers was built without libembree-dev)\n");
  std::vector<SceneReport> reports;
  if (sceneArg != "generated") {
    if (mapPath.empty()) {
      std::fprintf(stderr, "cmkit_peers: no map given and lt4.map not found\n");
      return 2;
    }
    const Scene lt4 = loadMapScene(mapPath);
    if (lt4.indices.empty()) return 2;
    reports.push_back(runScene(lt4, std::size_t(queries), passes, threads, verbose));
  }
  if (sceneArg != "lt4")
    reports.push_back(runScene(generatedScene(), std::size_t(queries), passes, threads, verbose));
  for (const SceneReport& r : reports) printReport(r, markdown);
  return 0;
}
