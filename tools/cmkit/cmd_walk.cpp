// `cmkit walk MAP`: a player (movement.h) walked through a map's World from a
// position in a wished direction for some seconds; prints where it ended.
#include <fmt/core.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>

#include "cmkit/movement.h"
#include "cmkit/world.h"
#include "commands.h"
#include "model_loading.h"
#include "option_checks.h"
#include "stats_print.h"

namespace cmkit::cli {

namespace {

/// What `cmkit walk` was asked.
struct WalkRequest {
  std::string map;
  std::string from;
  std::string wish;
  double seconds = 0;
  bool json = false;
  std::string shape;
  bool run = false;
  bool crouch = false;
  std::optional<double> jumpAt;
  std::string pathCsv;
  std::string materials;
  bool noProc = false;
};

/// The longest walk: an hour of steps (216 000).
constexpr double kMaxSeconds = 3600;

std::string entityName(const World& world, EntityId id) {
  const WorldEntity* e = world.entity(id);
  return e ? e->name : std::string();
}

int runWalk(const WalkRequest& r) {
  if (r.seconds > kMaxSeconds) {
    fmt::print(stderr, "cmkit walk: --seconds {}: at most {} (an hour of steps)\n", r.seconds, kMaxSeconds);
    return kExitBadInput;
  }
  // (--from and --wish were checked while the command line was parsed.)
  const Vec3 from = parseFiniteVec3(r.from).value_or(Vec3{});
  const Vec3 wish = parseFiniteVec2or3(r.wish).value_or(Vec3{});
  PlayerShape shape = PlayerShape::standard();
  if (!r.shape.empty()) {
    auto trm = TraceModel::parse(r.shape);
    auto made = trm ? PlayerShape::fromTraceModel(*trm) : Result<PlayerShape>(trm.error());
    if (!made) {
      fmt::print(stderr, "cmkit walk: --shape {}: {}\n", r.shape, made.error().toString());
      return kExitBadInput;
    }
    shape = std::move(*made);
  }
  Result<MaterialTable> materials = materialsForCli(r.materials);
  if (!materials) {
    fmt::print(stderr, "cmkit walk: {}\n", materials.error().toString());
    return kExitBadInput;
  }
  LoadMapOptions options;
  options.useProcFile = !r.noProc;
  Result<LoadedWorld> loaded = World::loadMap(r.map, *materials, options);
  if (!loaded) {
    fmt::print(stderr, "cmkit walk: {}\n", loaded.error().toString());
    return kExitBadInput;
  }
  const World& world = loaded->world;

  std::FILE* csv = nullptr;
  if (!r.pathCsv.empty()) {
    csv = std::fopen(r.pathCsv.c_str(), "w");
    if (!csv) {
      fmt::print(stderr, "cmkit walk: --path {}: cannot write the file\n", r.pathCsv);
      return kExitBadInput;
    }
    fmt::print(csv, "step,time,x,y,z,vx,vy,vz,on_ground,ground_entity,crouched,stuck\n");
  }
  const Real dt = move::kTimeStep;
  const auto steps = static_cast<std::int64_t>(std::llround(r.seconds / double(dt)));
  const std::int64_t jumpStep =
      r.jumpAt ? static_cast<std::int64_t>(std::llround(*r.jumpAt / double(dt))) : std::int64_t(-1);
  PlayerState s;
  s.origin = from;
  PlayerInput input;
  input.wishDir = wish;
  input.run = r.run;
  input.crouch = r.crouch;
  WorldQueryWork work;
  double pathLength = 0;
  std::int64_t stuckSteps = 0;
  for (std::int64_t i = 0; i < steps; ++i) {
    input.jump = i == jumpStep;
    const Vec3 was = s.origin;
    s = stepPlayer(world, shape, s, input, dt, work);
    pathLength += double((s.origin - was).length());
    stuckSteps += s.stuck ? 1 : 0;
    if (csv)
      fmt::print(csv, "{},{},{},{},{},{},{},{},{},{},{},{}\n", i + 1, double(i + 1) * double(dt), s.origin.x,
                 s.origin.y, s.origin.z, s.velocity.x, s.velocity.y, s.velocity.z, s.onGround ? 1 : 0,
                 s.groundEntity, s.crouched ? 1 : 0, s.stuck ? 1 : 0);
  }
  if (csv && std::fclose(csv) != 0) {
    fmt::print(stderr, "cmkit walk: --path {}: cannot write the file\n", r.pathCsv);
    return kExitBadInput;
  }
  const double distance = double((s.origin - from).length());
  const std::string ground = s.onGround ? entityName(world, s.groundEntity) : std::string();
  if (r.json) {
    fmt::print(
        "{{\"map\": {}, \"from\": [{}, {}, {}], \"wish\": [{}, {}, {}], \"seconds\": {}, \"time_step\": {}, "
        "\"steps\": {}, \"end\": [{}, {}, {}], \"velocity\": [{}, {}, {}], \"on_ground\": {}, "
        "\"ground_entity\": {}, \"crouched\": {}, \"stuck\": {}, \"stuck_steps\": {}, \"distance\": {}, "
        "\"path_length\": {}}}\n",
        jsonString(r.map), from.x, from.y, from.z, wish.x, wish.y, wish.z, r.seconds, dt, steps, s.origin.x,
        s.origin.y, s.origin.z, s.velocity.x, s.velocity.y, s.velocity.z, s.onGround,
        s.onGround ? jsonString(ground) : std::string("null"), s.crouched, s.stuck, stuckSteps, distance,
        pathLength);
    return 0;
  }
  fmt::print("walk in {} from ({} {} {}) wishing ({} {}){}{} for {} s: {} steps of 1/60 s\n", r.map, from.x,
             from.y, from.z, wish.x, wish.y, r.run ? ", running" : "", r.crouch ? ", crouched" : "",
             r.seconds, steps);
  fmt::print("end ({:.3f} {:.3f} {:.3f}), velocity ({:.3f} {:.3f} {:.3f})\n", s.origin.x, s.origin.y,
             s.origin.z, s.velocity.x, s.velocity.y, s.velocity.z);
  fmt::print("{}; {} from the start, {:.3f} walked{}\n",
             s.onGround ? fmt::format("on the ground of entity {} \"{}\"", s.groundEntity, ground)
                        : std::string("in the air"),
             fmt::format("{:.3f}", distance), pathLength,
             stuckSteps > 0 ? fmt::format("; stuck in solid for {} step(s){}", stuckSteps,
                                          s.stuck ? ", at the end too" : "")
                            : std::string());
  return 0;
}

}  // namespace

void registerWalk(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "walk",
      "Walk a player through the World of a .map (its world model and every entity with\n"
      "brushes, placed by its keys) from a position in a wished direction, in steps of\n"
      "1/60 s, and print where it ended: a box 32 x 32 x 74 (the original's player; --shape\n"
      "for another) whose origin is the bottom centre, that walks at 140 units/s (--run: 220),\n"
      "steps up to 16 units, slides along walls, walks slopes up to 45 degrees, falls with\n"
      "gravity 1066 units/s² and jumps 48 units (docs/world.md, \"Movement\").\n\n"
      "Examples:\n"
      "  cmkit walk tests/data/maps/stairs.map --from=-64,64,1 --wish 1,0 --seconds 4\n"
      "      up the stairs of 12-unit risers: ends on the landing at z = 60.25\n"
      "  cmkit walk tests/data/maps/stairs.map --from=-64,-64,1 --wish 1,0 --seconds 4 --json\n"
      "      held by 24-unit risers; as JSON: \"end\" is [x, y, z]\n"
      "  cmkit walk MAP --from 0,0,1 --wish 0,1 --seconds 2 --jump-at 0.5 --path steps.csv\n\n"
      "Exit codes: 0 success (a stuck player too: the output says so), 2 bad input or\n"
      "arguments (file:line: message).");
  auto r = std::make_shared<WalkRequest>();
  cmd->add_option("MAP", r->map, "the .map file (NAME.cm beside it is used when its CRC matches)")
      ->required();
  cmd->add_option("--from", r->from, "where the player's feet start: X,Y,Z (bottom centre of its box)")
      ->required()
      ->check(finiteVec3());
  cmd->add_option("--wish", r->wish,
                  "the wished direction DX,DY[,DZ] (DZ ignored); its length is the fraction of full speed, "
                  "at most 1")
      ->required()
      ->check(finiteVec2or3());
  cmd->add_option("--seconds", r->seconds, "how long to walk, at most 3600")
      ->required()
      ->check(finiteAtLeast(0));
  cmd->add_flag("--json", r->json,
                "print one JSON object: end [x, y, z], velocity, on_ground, ground_entity (a name or null), "
                "crouched, stuck, steps, distance, path_length");
  cmd->add_option("--shape", r->shape,
                  "the player's trace model, its origin at the feet (default box:-16,-16,0,16,16,74; e.g. "
                  "cylinder:8:-16,-16,0,16,16,74); crouching keeps it");
  cmd->add_flag("--run", r->run, "run (220 units/s) instead of walking (140)");
  cmd->add_flag("--crouch", r->crouch, "crouch the whole walk (38 units high, 80 units/s)");
  cmd->add_option("--jump-at", r->jumpAt, "press jump at this time (seconds; once)")->check(finiteAtLeast(0));
  cmd->add_option("--path", r->pathCsv,
                  "write every step to this CSV file: step,time,x,y,z,vx,vy,vz,on_ground,ground_entity,"
                  "crouched,stuck");
  cmd->add_option("--materials", r->materials, "directory of .mtr files (default: the built-in rules)");
  addNoProcFlag(cmd, r->noProc);
  cmd->callback([r] {
    const int rc = runWalk(*r);
    if (rc != 0) std::exit(rc);
  });
}

}  // namespace cmkit::cli
