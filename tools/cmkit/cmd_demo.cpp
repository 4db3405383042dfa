// `cmkit demo [MAP]`: the main job. Compiles the bundled map (lt4, CC0) with a
// progress bar, runs the original's speed test on it, renders a picture with
// a few traces, and says what it all means.
#include <fmt/core.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <span>
#include <thread>

#include "bench_report.h"
#include "cmkit/compile.h"
#include "cmkit/map.h"
#include "cmkit/tools/picture.h"
#include "commands.h"
#include "data_paths.h"
#include "progress_bar.h"

namespace cmkit::cli {

namespace {

namespace fs = std::filesystem;

/// The bundled map, relative to the source tree (or the current directory).
constexpr const char* kBundledMap = "data/maps/lt4/lt4.map";
/// Map units shown around the drawn moves in the picture.
constexpr Real kDemoFrameMargin = 192;
/// Traces drawn in the picture.
constexpr int kDemoTraces = 12;
/// Threads of the demo's second speed test run (when the machine has them).
constexpr unsigned kDemoThreads = 2;
/// Rotation origins of the demo's speed test lie within this many units of the start.
constexpr Real kDemoRotationRadius = 256;

struct DemoOptions {
  std::string map;
  std::string output = "cmkit-demo.png";
};

/// The bundled map: in the installed tree (PREFIX/share/cmkit/maps/lt4),
/// in the source tree around a build-tree binary, or in the current
/// directory. Empty when not found.
std::string findBundledMap() {
  std::error_code ec;
  if (const fs::path share = installedDataDir(); !share.empty()) {
    const fs::path p = share / "maps" / "lt4" / "lt4.map";
    if (fs::exists(p, ec)) return p.string();
  }
  if (const fs::path p = findAboveExecutable(kBundledMap); !p.empty()) return p.string();
  if (const fs::path p = fs::current_path(ec) / kBundledMap; !ec && fs::exists(p, ec))
    return p.lexically_normal().string();
  return {};
}

int runDemo(const DemoOptions& o) {
  const std::string path = o.map.empty() ? findBundledMap() : o.map;
  if (path.empty()) {
    fmt::print(stderr, "cmkit demo: the bundled map ({}) was not found; give a .map file\n", kBundledMap);
    return kExitBadInput;
  }
  fmt::print("== 1. compiling {}\n", path);
  const auto t0 = std::chrono::steady_clock::now();
  auto map = loadMapFile(path);
  if (!map) {
    fmt::print(stderr, "cmkit demo: {}\n", map.error().toString());
    return kExitBadInput;
  }
  ProgressBar bar(isatty(fileno(stderr)) != 0);
  BuildOptions build;
  build.progress = [&bar](std::size_t done, std::size_t total) { bar.update(done, total); };
  Result<BuildResult> built = buildCollisionModels(*map, MaterialTable{}, build);
  bar.finish();
  if (!built || built->models.empty()) {
    fmt::print(stderr, "cmkit demo: {}\n",
               built ? "the map has no collision models" : built.error().toString());
    return kExitBadInput;
  }
  const std::vector<ModelPtr>& models = built->models;
  const double buildMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  std::size_t polygons = 0, brushes = 0;
  for (const ModelPtr& m : models) {
    polygons += m->polygons().size();
    brushes += m->brushes().size();
  }
  fmt::print("{} entities -> {} collision models, {} polygons, {} brushes in {:.0f} ms\n\n",
             map->entities.size(), models.size(), polygons, brushes, buildMs);

  const CollisionModel& world = *models.front();
  auto trm = TraceModel::parse(kSpeedTestDefaultTrm);
  if (!trm) {
    fmt::print(stderr, "cmkit demo: {}\n", trm.error().toString());
    return kExitBadInput;
  }
  SpeedTestOptions test;
  test.origin = (world.bounds().min + world.bounds().max) * Real(0.5);
  test.threads = int(std::clamp(std::thread::hardware_concurrency(), 1u, kDemoThreads));
  // With the original's default radius (64) every rotation turns the box in
  // the open space around lt4's centre and hits nothing; about points up to
  // kDemoRotationRadius away the box swings into walls (about 1 in 6 is stopped).
  test.radius = kDemoRotationRadius;
  fmt::print(
      "== 2. the original's speed test (cm_testCollision defaults; rotations about points\n"
      "   within +-{:.0f} units instead of 64, so that they hit things)\n",
      double(kDemoRotationRadius));
  const bool same = runAndPrintSpeedTest(world, *trm, kSpeedTestDefaultTrm, test);

  fmt::print("\n== 3. picture\n");
  std::vector<TraceRecord> traces;
  {
    SpeedTestOptions few = test;
    few.times = kDemoTraces;
    QueryWork work;
    SpeedTestRandom random(few.seed);
    for (int i = 0; i < kDemoTraces; ++i) {
      TraceRecord r;
      r.op = "translation";
      r.trm = *trm;
      r.start = test.origin;
      for (int k = 0; k < 3; ++k) r.end[k] = test.origin[k] + random.signedUniform() * test.length;
      TranslationQuery q;
      q.trm = &*trm;
      q.start = r.start;
      q.end = r.end;
      q.contentMask = test.contentMask;
      r.result = translate(world, q, work);
      traces.push_back(std::move(r));
    }
  }
  PictureOptions picture;
  picture.view = CameraView::TopDown;  // the roof cut away: the rooms and the traces in them
  // Framed on the moves (their starts and stops, kDemoFrameMargin around them) rather than
  // the whole map, where they filled a corner; heights are the whole map's, so the camera
  // is above everything.
  Bounds focus;
  for (const TraceRecord& r : traces) {
    focus.addPoint(r.start);
    focus.addPoint(r.result.endPos);
  }
  focus.min = focus.min - Vec3{kDemoFrameMargin, kDemoFrameMargin, 0};
  focus.max = focus.max + Vec3{kDemoFrameMargin, kDemoFrameMargin, 0};
  focus.min.z = world.bounds().min.z;
  focus.max.z = world.bounds().max.z;
  picture.camera = frameCamera(focus, CameraView::TopDown, Real(picture.width) / Real(picture.height));
  // The world model only: inline models are in their entities' local frames.
  const Image image = renderPicture(std::span(models.data(), 1), traces, picture);
  if (Status s = savePng(o.output, image); !s) {
    fmt::print(stderr, "cmkit demo: {}\n", s.error().toString());
    return kExitBadInput;
  }
  fmt::print(
      "wrote {} ({}x{}): the world's collision polygons seen from above (the upper part\n"
      "of the map cut away), framed on {} box moves from the centre of the map:\n",
      fs::absolute(o.output).lexically_normal().string(), image.width, image.height, kDemoTraces);
  fmt::print(
      "  yellow line        the path the box moved, from the start to where it stopped\n"
      "  dim olive line     the rest of the requested move, past the stop (not travelled)\n"
      "  grey box outline   the box at its start; white box outline: where it stopped\n"
      "  red cross          the contact point; orange line: the contact normal\n"
      "  polygon colours    contents (solid grey-blue, clip, water, ...; docs/materials.md)\n\n");
  fmt::print(
      "What the numbers mean: each line is {} queries of one kind. 'total' is the time spent in\n"
      "the queries, min/avg/max the time of one query. Speed against the original or another\n"
      "build is only meaningful when both ran on this machine in one run: docs/performance.md\n"
      "says how (bench/compare.sh), with figures and the commands that produced them.\n"
      "'hits' counts the moves stopped by a surface (fraction < 1; the box stops 0.25 units\n"
      "short of it). 'hash' is a fingerprint of every result bit: the same on any thread count,\n"
      "so the threaded run computed exactly the same answers (its speed-up needs idle cores;\n"
      "on a busy machine single queries show scheduler pauses as large 'max' values).\n",
      test.times);
  return same ? 0 : 1;
}

}  // namespace

void registerDemo(CLI::App& app) {
  auto o = std::make_shared<DemoOptions>();
  auto* cmd = app.add_subcommand(
      "demo",
      "The main job: compile the bundled map (data/maps/lt4/lt4.map, CC0) or MAP into collision\n"
      "models with a progress bar, run the original's speed test on it (1000 box translations +\n"
      "1000 rotations about points within 256 units, so that some hit walls; also on 2 threads),\n"
      "and render a PNG of the map with a few traces.");
  cmd->add_option("MAP", o->map, "a .map file (default: the bundled lt4)");
  cmd->add_option("-o,--output", o->output, "the PNG to write")->capture_default_str();
  cmd->callback([o] {
    if (int rc = runDemo(*o); rc != 0) std::exit(rc);
  });
}

}  // namespace cmkit::cli
