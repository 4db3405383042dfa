// `cmkit audit MAP`: where a player can stand from the map's starts, and
// what is wrong there (audit.h): fall-outs, stuck spots, tunnels, embedded
// entities, open shells. A summary, optionally JSON and a top-view picture;
// exit status 1 when a finding is of high severity.
#include <fmt/core.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "cmkit/audit.h"
#include "cmkit/movement.h"
#include "cmkit/tools/debug_draw.h"
#include "cmkit/tools/picture.h"
#include "cmkit/world.h"
#include "commands.h"
#include "model_loading.h"
#include "option_checks.h"
#include "progress_bar.h"
#include "stats_print.h"

namespace cmkit::cli {

namespace {

/// What `cmkit audit` was asked.
struct AuditRequest {
  std::string map;
  std::string json;
  std::string picture;
  std::string size = "1600x1200";
  double grid = 16;
  int threads = 1;
  std::vector<std::string> from;
  std::string movers = "ignore";
  bool noShells = false;
  int worst = 5;
  int focus = 0;
  std::size_t maxCells = AuditOptions{}.maxCells;
  std::string materials;
  bool noProc = false;
};

/// Exit status when a finding is of high severity.
constexpr int kExitHighSeverity = 1;
/// Largest picture side (pixels).
constexpr int kMaxPictureSide = 8192;
/// Half the width (units) of the square a --focus picture shows.
constexpr Real kFocusHalfWidth = 384;
/// The top of the scene left out of the picture (as `cmkit render --top`).
constexpr Real kPictureCut = Real(0.2);

std::string vec(const Vec3& p) { return fmt::format("[{:.2f}, {:.2f}, {:.2f}]", p.x, p.y, p.z); }

/// The findings as JSON (audit.h's lists; each object numbered as in the
/// picture and the text).
std::string reportJson(const AuditRequest& r, const AuditReport& report, double seconds) {
  std::string out = "{\n";
  out += fmt::format("  \"map\": {},\n  \"grid\": {},\n  \"reachable_cells\": {},\n  \"moves_tried\": {},\n",
                     jsonString(r.map), r.grid, report.cells.size(), report.movesTried);
  out += fmt::format("  \"truncated\": {},\n  \"movers_ignored\": {},\n  \"triggers_ignored\": {},\n",
                     report.truncated, report.moversIgnored, report.triggersIgnored);
  out += fmt::format("  \"seconds\": {:.2f},\n", seconds);
  out += "  \"starts\": [";
  for (std::size_t i = 0; i < report.starts.size(); ++i) out += (i ? ", " : "") + vec(report.starts[i]);
  out += "],\n";
  out += fmt::format("  \"high_severity\": {},\n", report.hasHighSeverity());
  int number = 1;
  const std::pair<const char*, const std::vector<AuditFinding>*> lists[] = {
      {"fallouts", &report.fallOuts},
      {"stuck", &report.stuck},
      {"tunnels", &report.tunnels},
      {"embedded", &report.embedded},
      {"open_shells", &report.openShells}};
  for (std::size_t l = 0; l < std::size(lists); ++l) {
    out += fmt::format("  \"{}\": [", lists[l].first);
    const auto& list = *lists[l].second;
    for (std::size_t i = 0; i < list.size(); ++i) {
      const AuditFinding& f = list[i];
      std::string path;
      for (std::size_t k = 0; k < f.path.size(); ++k) path += (k ? ", " : "") + vec(f.path[k]);
      out += fmt::format(
          "{}\n    {{\"number\": {}, \"kind\": \"{}\", \"severity\": \"{}\", \"position\": {}, \"what\": {}, "
          "\"merged\": {}, \"path\": [{}]}}",
          i ? "," : "", number++, toString(f.kind), toString(f.severity), vec(f.position), jsonString(f.what),
          f.merged, path);
    }
    out += list.empty() ? "]" : "\n  ]";
    out += l + 1 < std::size(lists) ? ",\n" : "\n";
  }
  return out + "}\n";
}

/// Leaves out what lies wholly above a height (to see into rooms from above).
class CutDraw final : public DebugDraw {
 public:
  CutDraw(DebugDraw& to, Real cut) : to_(to), cut_(cut) {}
  void line(const Vec3& a, const Vec3& b, const Rgba& color, const DrawTag& tag) override {
    if (std::min(a.z, b.z) <= cut_) to_.line(a, b, color, tag);
  }
  void polygon(std::span<const Vec3> points, const Vec3& normal, const Rgba& color,
               const DrawTag& tag) override {
    for (const Vec3& p : points)
      if (p.z <= cut_) {
        to_.polygon(points, normal, color, tag);
        return;
      }
  }
  void text(const Vec3& at, std::string_view text, const Rgba& color, const DrawTag& tag) override {
    to_.text(at, text, color, tag);
  }

 private:
  DebugDraw& to_;
  Real cut_;
};

/// Blue (low) to red (high).
Rgba heightColor(Real t) {
  t = std::clamp(t, Real(0), Real(1));
  return {std::uint8_t(40 + 215 * t), std::uint8_t(200 - 120 * std::abs(t - Real(0.5)) * 2),
          std::uint8_t(255 - 215 * t), 255};
}

Rgba severityColor(AuditSeverity s) {
  switch (s) {
    case AuditSeverity::High:
      return {255, 40, 40, 255};
    case AuditSeverity::Medium:
      return {255, 160, 0, 255};
    case AuditSeverity::Low:
      return {255, 255, 80, 255};
  }
  return {255, 255, 255, 255};
}

/// The top view: the world (its top cut away), the reachable cells shaded
/// by height, each finding a numbered marker.
/// `focus` > 0: only the square around that finding.
Image auditPicture(const World& world, const AuditReport& report, Real grid, int focus, int width,
                   int height) {
  const Bounds b = report.worldBounds;
  Bounds frame = b;
  const std::vector<const AuditFinding*> numbered = report.numbered();
  if (focus > 0 && std::size_t(focus) <= numbered.size()) {
    const Vec3 p = numbered[std::size_t(focus - 1)]->position;
    frame.min = {p.x - kFocusHalfWidth, p.y - kFocusHalfWidth, b.min.z};
    frame.max = {p.x + kFocusHalfWidth, p.y + kFocusHalfWidth, b.max.z};
  }
  const Camera camera = frameCamera(frame, CameraView::TopDown, Real(width) / Real(height));
  PictureCanvas canvas(width, height, camera, {28, 30, 36, 255});
  // Cut away the top of the scene, and everything higher than a player
  // standing in the highest cell: the roofs over the reachable area.
  Real top = b.max.z - kPictureCut * (b.max.z - b.min.z);
  if (!report.cells.empty()) {
    Real highest = report.cells.front().position.z;
    for (const AuditCell& c : report.cells) highest = std::max(highest, c.position.z);
    top = std::min(top, highest + move::kPlayerHeight);
  }
  CutDraw cut(canvas, top);
  DrawOptions draw;
  draw.filled = true;
  for (EntityId id : world.entityIds()) {
    const WorldEntity* e = world.entity(id);
    if (e->contents != 0) drawModel(cut, *e->model, e->placement, draw);
  }
  // Cells over everything, lowest first, so the highest floor shows.
  canvas.setDepthTest(false);
  std::vector<const AuditCell*> cells;
  for (const AuditCell& c : report.cells) cells.push_back(&c);
  std::stable_sort(cells.begin(), cells.end(),
                   [](const AuditCell* a, const AuditCell* c) { return a->position.z < c->position.z; });
  Real zLo = b.max.z, zHi = b.min.z;
  for (const AuditCell* c : cells) {
    zLo = std::min(zLo, c->position.z);
    zHi = std::max(zHi, c->position.z);
  }
  const Real span = std::max(zHi - zLo, Real(1));
  const Real h = grid / 2;
  const DrawTag tag;
  for (const AuditCell* c : cells) {
    // The square of the cell's key (audit.h), at the height stood on.
    const Vec3 p{std::floor(c->position.x / grid + Real(0.5)) * grid,
                 std::floor(c->position.y / grid + Real(0.5)) * grid, c->position.z};
    const Vec3 square[4] = {
        {p.x - h, p.y - h, p.z}, {p.x + h, p.y - h, p.z}, {p.x + h, p.y + h, p.z}, {p.x - h, p.y + h, p.z}};
    canvas.polygon(square, {0, 0, 1}, heightColor((p.z - zLo) / span), tag);
  }
  // Findings: a ring and the number, coloured by severity.
  const Real r = std::max(grid, (frame.max.x - frame.min.x + frame.max.y - frame.min.y) / Real(300));
  int number = 1;
  for (const AuditFinding* f : numbered) {
    const Rgba color = severityColor(f->severity);
    const Vec3 p = f->position;
    constexpr int kRingSegments = 16;
    for (int k = 0; k < kRingSegments; ++k) {
      const Real a0 = Real(6.2831853) * Real(k) / kRingSegments,
                 a1 = Real(6.2831853) * Real(k + 1) / kRingSegments;
      canvas.line(p + Vec3{r * std::cos(a0), r * std::sin(a0), 0},
                  p + Vec3{r * std::cos(a1), r * std::sin(a1), 0}, color, tag);
    }
    canvas.line(p - Vec3{r, 0, 0}, p + Vec3{r, 0, 0}, color, tag);
    canvas.line(p - Vec3{0, r, 0}, p + Vec3{0, r, 0}, color, tag);
    canvas.text(p + Vec3{r, r, 0}, std::to_string(number++), color, tag);
  }
  return canvas.image();
}

bool parseSize(const std::string& text, int& w, int& h) {
  char x = 0;
  if (std::sscanf(text.c_str(), "%d%c%d", &w, &x, &h) != 3 || (x != 'x' && x != 'X')) return false;
  return w > 0 && h > 0 && w <= kMaxPictureSide && h <= kMaxPictureSide;
}

int runAudit(const AuditRequest& r) {
  int width = 0, height = 0;
  if (!parseSize(r.size, width, height)) {
    fmt::print(stderr, "cmkit audit: --size: expected WIDTHxHEIGHT (1..{} each), got '{}'\n", kMaxPictureSide,
               r.size);
    return kExitBadInput;
  }
  AuditOptions options;
  options.grid = Real(r.grid);
  options.threads = r.threads;
  options.ignoreMovers = r.movers == "ignore";
  options.openShells = !r.noShells;
  options.maxCells = r.maxCells;
  for (const std::string& f : r.from) options.extraStarts.push_back(parseFiniteVec3(f).value_or(Vec3{}));
  Result<MaterialTable> materials = materialsForCli(r.materials);
  if (!materials) {
    fmt::print(stderr, "cmkit audit: {}\n", materials.error().toString());
    return kExitBadInput;
  }
  Result<MapFile> map = loadMapFile(r.map);
  if (!map) {
    fmt::print(stderr, "cmkit audit: {}\n", map.error().toString());
    return kExitBadInput;
  }
  LoadMapOptions loadOptions;
  loadOptions.useProcFile = !r.noProc;
  Result<LoadedWorld> loaded = World::loadMap(r.map, *materials, loadOptions);
  if (!loaded) {
    fmt::print(stderr, "cmkit audit: {}\n", loaded.error().toString());
    return kExitBadInput;
  }
  const std::vector<AuditSpot> spots = auditSpotsFromMap(*map);
  const bool anyStart = !options.extraStarts.empty() ||
                        std::any_of(spots.begin(), spots.end(),
                                    [](const AuditSpot& s) { return s.kind == AuditSpotKind::PlayerStart; });
  if (!anyStart) {
    fmt::print(stderr, "cmkit audit: {}: no info_player_start and no --from: nowhere to start\n", r.map);
    return kExitBadInput;
  }

  const auto t0 = std::chrono::steady_clock::now();
  Result<AuditReport> audited = [&] {
    ProgressBar bar(isatty(fileno(stderr)) != 0, "audit", "cells");
    options.progress = [&bar](std::size_t done, std::size_t total) { bar.update(done, total); };
    return auditWorld(loaded->world, spots, options);
  }();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!audited) {
    fmt::print(stderr, "cmkit audit: {}\n", audited.error().toString());
    return kExitBadInput;
  }
  const AuditReport& report = *audited;

  if (!r.json.empty()) {
    std::FILE* f = std::fopen(r.json.c_str(), "w");
    const std::string text = reportJson(r, report, seconds);
    if (!f || std::fwrite(text.data(), 1, text.size(), f) != text.size() || std::fclose(f) != 0) {
      fmt::print(stderr, "cmkit audit: --json {}: cannot write the file\n", r.json);
      return kExitBadInput;
    }
  }
  if (!r.picture.empty()) {
    // The picture shows the world as audited: triggers, and movers when
    // ignored, left out.
    std::vector<std::pair<EntityId, std::uint32_t>> movers;
    World& world = loaded->world;
    for (EntityId id : world.entityIds())
      if (id != kWorldspawnEntity && (isTriggerClass(world.entity(id)->className) ||
                                      (options.ignoreMovers && isMoverClass(world.entity(id)->className)))) {
        movers.emplace_back(id, world.entity(id)->contents);
        (void)world.setContents(id, 0);
      }
    const Image image = auditPicture(world, report, options.grid, r.focus, width, height);
    for (const auto& [id, c] : movers) (void)world.setContents(id, c);
    if (Status s = savePng(r.picture, image); !s) {
      fmt::print(stderr, "cmkit audit: {}\n", s.error().toString());
      return kExitBadInput;
    }
  }

  // The summary.
  fmt::print(
      "audit of {}: {} reachable cells of {} units from {} start{} ({} moves, {:.1f} s, {} thread{}){}\n",
      r.map, report.cells.size(), r.grid, report.starts.size(), report.starts.size() == 1 ? "" : "s",
      report.movesTried, seconds, r.threads, r.threads == 1 ? "" : "s",
      report.truncated ? "; STOPPED at the cell limit" : "");
  fmt::print("{} mover{} {}, {} trigger{} ignored\n", report.moversIgnored,
             report.moversIgnored == 1 ? "" : "s",
             options.ignoreMovers ? "ignored (doors open)" : "kept as placed", report.triggersIgnored,
             report.triggersIgnored == 1 ? "" : "s");
  fmt::print("fall-outs {}, stuck {}, tunnels {}, embedded {}, open shells {}\n", report.fallOuts.size(),
             report.stuck.size(), report.tunnels.size(), report.embedded.size(), report.openShells.size());
  const std::vector<const AuditFinding*> numbered = report.numbered();
  std::vector<std::size_t> order(numbered.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return numbered[a]->severity > numbered[b]->severity;
  });
  for (std::size_t k = 0; k < order.size() && int(k) < r.worst; ++k) {
    const AuditFinding& f = *numbered[order[k]];
    fmt::print("  #{} {} {} at ({:.1f} {:.1f} {:.1f}): {}{}\n", order[k] + 1, toString(f.severity),
               toString(f.kind), f.position.x, f.position.y, f.position.z, f.what,
               f.merged > 1 ? fmt::format(" (and {} more within {} units)", f.merged - 1, kAuditClusterRadius)
                            : std::string());
  }
  if (int(order.size()) > r.worst)
    fmt::print("  ... {} more (--worst, --json)\n", order.size() - std::size_t(r.worst));
  return report.hasHighSeverity() ? kExitHighSeverity : 0;
}

}  // namespace

void registerAudit(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "audit",
      "Audit a .map for a player (the `walk` player: 32 x 32 x 74, runs, steps 16, jumps 48,\n"
      "crouches): from every info_player_start (and --from), search where it can stand on a grid\n"
      "of --grid units, running, crouching and jumping towards the eight neighbouring cells\n"
      "(doors and other movers ignored unless --movers closed), and report (docs/audit.md):\n"
      "  fall-outs    a reachable place from which the player falls out of the world (high)\n"
      "  stuck        a reachable place no move gets out of (high)\n"
      "  tunnels      a move that ended a step inside a brush (high) or a patch's polygons (low)\n"
      "  embedded     a player start (high), monster (medium) or item (low) placed in solid\n"
      "  open shells  a crack next to reachable space that a point passes out of the world (medium)\n"
      "Prints a summary; --json writes every finding, --picture a top view with the reachable area\n"
      "shaded by height and each finding numbered as in the JSON.\n\n"
      "Examples:\n"
      "  cmkit audit data/maps/lt4/lt4.map --threads 2 --json lt4_audit.json --picture lt4_audit.png\n"
      "  cmkit audit MAP --from 0,0,1 --grid 32\n\n"
      "Exit codes: 0 no finding of high severity, 1 a finding of high severity (to gate a map in\n"
      "CI), 2 bad input or arguments (file:line: message).");
  auto r = std::make_shared<AuditRequest>();
  cmd->add_option("MAP", r->map, "the .map file (NAME.cm beside it is used when its CRC matches)")
      ->required();
  cmd->add_option(
      "--json", r->json,
      "write the findings as JSON: reachable_cells (a count), fallouts, stuck, tunnels, embedded, "
      "open_shells (lists of objects with number, kind, severity, position [x, y, z], what, merged, "
      "path)");
  cmd->add_option("--picture", r->picture,
                  "write a top view (PNG) with the reachable cells and the findings");
  cmd->add_option("--size", r->size, "the picture's size WIDTHxHEIGHT")->capture_default_str();
  cmd->add_option("--focus", r->focus, "the picture shows only the 768 x 768 units around finding N")
      ->check(CLI::Range(1, 1000000));
  cmd->add_option("--grid", r->grid, "the grid of standing positions (units, at least 4)")
      ->capture_default_str()
      ->check(finiteAtLeast(4));
  cmd->add_option("--threads", r->threads, "worker threads")
      ->capture_default_str()
      ->check(CLI::Range(1, 256));
  cmd->add_option("--from", r->from, "another start X,Y,Z (the feet; repeatable)")
      ->allow_extra_args(false)
      ->check(finiteVec3());
  cmd->add_option("--movers", r->movers,
                  "doors, lifts and moveables: ignore (doors open) or closed (as placed)")
      ->capture_default_str()
      ->check(CLI::IsMember({"ignore", "closed"}));
  cmd->add_flag("--no-shells", r->noShells, "skip the crack rays (open shells)");
  cmd->add_option("--max-cells", r->maxCells,
                  "stop the search at this many cells (the summary and JSON say so)")
      ->capture_default_str()
      ->check(CLI::Range(std::size_t(1), std::size_t(1) << 40));
  cmd->add_option("--worst", r->worst, "findings listed in the summary")
      ->capture_default_str()
      ->check(CLI::Range(0, 100000));
  cmd->add_option("--materials", r->materials, "directory of .mtr files (default: the built-in rules)");
  addNoProcFlag(cmd, r->noProc);
  cmd->callback([r] {
    const int rc = runAudit(*r);
    if (rc != 0) std::exit(rc);
  });
}

}  // namespace cmkit::cli
