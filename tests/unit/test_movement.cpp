// The player move (movement.h): stairs climbed and refused, slopes walked
// and slid down, corners, falls and jumps against their formulas, a moving
// platform ridden, starts in solid, identical bits on a second run. Worlds
// are tests/data/maps/stairs.map (make_stairs.py) or brushes written in code.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <ostream>
#include <span>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "cmkit/compile.h"
#include "cmkit/map.h"
#include "cmkit/movement.h"
#include "cmkit/world.h"
#include "test_support.h"

namespace cmkit {

/// GoogleTest prints a part by its name.
void PrintTo(PlayerMovePart part, std::ostream* os) { *os << toString(part); }

namespace {

constexpr Real kDt = move::kTimeStep;
/// Where a player at rest stands above its floor: translations stop
/// tol::kClipEpsilon in front of a surface.
constexpr Real kRest = tol::kClipEpsilon;

/// Seconds as a number of steps.
int stepsFor(double seconds) { return int(std::lround(seconds / double(kDt))); }

/// A plane of a brush: outward normal n, n . p = dist on it.
struct Face {
  Vec3 n;
  Real dist;
};

/// Map text of one worldspawn of convex brushes.
class MapWriter {
 public:
  MapWriter& brush(const std::vector<Face>& faces) {
    text_ << "{\n brushDef3\n {\n";
    for (const Face& f : faces) {
      // brushDef3 writes n . p + d = 0: d = -dist.
      text_ << "  ( " << f.n.x << " " << f.n.y << " " << f.n.z << " " << -f.dist
            << " ) ( ( 0.0078125 0 0 ) ( 0 0.0078125 0 ) ) \"textures/base_wall/lfwall27d\" 0 0 0\n";
    }
    text_ << " }\n}\n";
    return *this;
  }
  MapWriter& box(const Vec3& lo, const Vec3& hi) {
    return brush({{{1, 0, 0}, hi.x},
                  {{-1, 0, 0}, -lo.x},
                  {{0, 1, 0}, hi.y},
                  {{0, -1, 0}, -lo.y},
                  {{0, 0, 1}, hi.z},
                  {{0, 0, -1}, -lo.z}});
  }
  /// A ramp rising along +x from z = 0 at x = foot, at `degrees`, up to
  /// x = back, for y in [-width/2, width/2].
  MapWriter& ramp(Real foot, Real back, Real width, double degrees) {
    const double a = degrees * std::numbers::pi / 180;
    const Vec3 n{Real(-std::sin(a)), 0, Real(std::cos(a))};
    return brush({{n, n.x * foot},
                  {{0, 0, -1}, 0},
                  {{1, 0, 0}, back},
                  {{0, 1, 0}, width / 2},
                  {{0, -1, 0}, width / 2}});
  }
  /// The world built from the brushes.
  World build() const {
    const std::string text = "Version 2\n{\n\"classname\" \"worldspawn\"\n" + text_.str() + "}\n";
    auto map = parseMapText(text, "movement_test.map");
    EXPECT_TRUE(map) << (map ? "" : map.error().toString());
    auto built = buildCollisionModels(*map, MaterialTable{});
    EXPECT_TRUE(built) << (built ? "" : built.error().toString());
    auto world = World::fromMap(*map, built->models);
    EXPECT_TRUE(world) << (world ? "" : world.error().toString());
    return std::move(world->world);
  }

 private:
  std::ostringstream text_;
};

/// A floor (top at z = 0) 1024 units square around the origin.
MapWriter withFloor() {
  MapWriter m;
  m.box({-512, -512, -16}, {512, 512, 0});
  return m;
}

World loadStairs() {
  auto loaded = World::loadMap((test::testDataDir() / "maps" / "stairs.map").string(), MaterialTable{});
  EXPECT_TRUE(loaded) << (loaded ? "" : loaded.error().toString());
  return std::move(loaded->world);
}

PlayerState at(const Vec3& origin) {
  PlayerState s;
  s.origin = origin;
  return s;
}

PlayerInput walk(Real dx, Real dy) {
  PlayerInput in;
  in.wishDir = {dx, dy, 0};
  return in;
}

TEST(PlayerShapes, TheDefaultsAreTheOriginalsBox) {
  const PlayerShape shape = PlayerShape::standard();
  EXPECT_EQ(shape.standing.bounds().min, (Vec3{-16, -16, 0}));
  EXPECT_EQ(shape.standing.bounds().max, (Vec3{16, 16, 74}));
  EXPECT_EQ(shape.crouched.bounds().max, (Vec3{16, 16, 38}));
  EXPECT_EQ(shape.contentMask, contents::kMaskPlayerSolid);
  EXPECT_TRUE(PlayerShape::cylinder(8));
  EXPECT_FALSE(PlayerShape::box(32, 74, 80));  // crouched taller than standing
  EXPECT_FALSE(PlayerShape::fromTraceModel(TraceModel::point()));
}

// (a) and (b) with an 8-sided cylinder in the same bounds: its flat face
// meets the risers as the box does.
TEST(PlayerMove, ACylinderClimbs12UnitRisersAndIsHeldBy24) {
  const World world = loadStairs();
  const auto shape = PlayerShape::cylinder(8);
  ASSERT_TRUE(shape);
  WorldQueryWork work;
  const PlayerState up = runPlayer(world, *shape, at({-64, 64, 1}), walk(1, 0), stepsFor(4), kDt, work);
  EXPECT_TRUE(up.onGround);
  EXPECT_NEAR(up.origin.z, 60 + kRest, 0.05);
  EXPECT_NEAR(up.origin.x, 256 - 16 - kRest, 0.05);
  const PlayerState held = runPlayer(world, *shape, at({-64, -64, 1}), walk(1, 0), stepsFor(4), kDt, work);
  EXPECT_NEAR(held.origin.z, kRest, 0.05);
  EXPECT_NEAR(held.origin.x, 64 - 16 - kRest, 0.05);
}

// (a) Risers of 12 (treads of 16): the player walks up onto the landing at
// z = 60 and on to the far wall (x = 256 - 16 - 0.25).
TEST(PlayerMove, ClimbsStairsOf12UnitRisersOntoTheLanding) {
  const World world = loadStairs();
  const PlayerShape shape = PlayerShape::standard();
  WorldQueryWork work;
  std::vector<PlayerState> path;
  const PlayerState end =
      runPlayer(world, shape, at({-64, 64, 1}), walk(1, 0), stepsFor(4), kDt, work, {}, &path);
  EXPECT_FALSE(end.stuck);
  EXPECT_TRUE(end.onGround);
  EXPECT_EQ(end.groundEntity, kWorldspawnEntity);
  EXPECT_NEAR(end.origin.z, 60 + kRest, 0.05);
  EXPECT_NEAR(end.origin.x, 256 - 16 - kRest, 0.05);
  EXPECT_NEAR(end.origin.y, 64, 1e-3);
  // Every tread was stood on: the heights seen on the ground include each top.
  for (const int top : {0, 12, 24, 36, 48, 60}) {
    bool seen = false;
    for (const PlayerState& s : path)
      seen = seen || (s.onGround && std::abs(s.origin.z - (top + kRest)) < 0.05);
    EXPECT_TRUE(seen) << "never on the tread at z = " << top;
  }
}

// (b) Risers of 24: more than the step height (16): held before the first.
TEST(PlayerMove, IsHeldByStairsOf24UnitRisers) {
  const World world = loadStairs();
  const PlayerShape shape = PlayerShape::standard();
  WorldQueryWork work;
  const PlayerState end = runPlayer(world, shape, at({-64, -64, 1}), walk(1, 0), stepsFor(4), kDt, work);
  EXPECT_FALSE(end.stuck);
  EXPECT_TRUE(end.onGround);
  EXPECT_NEAR(end.origin.z, kRest, 0.05);
  EXPECT_LE(end.origin.x, 64 - 16 - kRest + 0.01);  // the first riser is at x = 64
  EXPECT_GT(end.origin.x, 64 - 16 - kRest - 0.05);  // and it got there
}

// Risers of exactly the step height are climbed; a little more is not.
TEST(PlayerMove, ClimbsARiserOfTheStepHeightButNotMore) {
  const PlayerShape shape = PlayerShape::standard();
  for (const Real riser : {Real(16), Real(17)}) {
    const World world = withFloor().box({64, -64, 0}, {256, 64, riser}).build();
    WorldQueryWork work;
    const PlayerState end = runPlayer(world, shape, at({0, 0, 1}), walk(1, 0), stepsFor(2), kDt, work);
    if (riser <= move::kStepHeight) {
      EXPECT_NEAR(end.origin.z, riser + kRest, 0.05) << riser;
    } else {
      EXPECT_NEAR(end.origin.z, kRest, 0.05) << riser;
      EXPECT_LE(end.origin.x, 64 - 16 - kRest + 0.01) << riser;
    }
  }
}

// (c) A 45-degree ramp (normal z 0.707 >= 0.7) is walked up; a 60-degree
// one (normal z 0.5) stops the walk at its foot, and a player put on it
// slides down to the floor.
TEST(PlayerMove, WalksUpA45DegreeSlopeButNotA60DegreeOne) {
  const PlayerShape shape = PlayerShape::standard();
  WorldQueryWork work;
  {
    const World world = withFloor().ramp(64, 400, 256, 45).build();
    const PlayerState end = runPlayer(world, shape, at({0, 0, 1}), walk(1, 0), stepsFor(2), kDt, work);
    EXPECT_TRUE(end.onGround);
    EXPECT_NEAR(end.groundNormal.z, std::cos(std::numbers::pi / 4), 1e-3);
    // About 2 s at 140 units/s along the slope, less the first 48 units
    // (to the foot) and the start: well above 100 units up.
    EXPECT_GT(end.origin.z, 100);
    // On the slope the front bottom edge rests on it: z = (x + 16 - 64) + 0.25 / sin 45.
    EXPECT_NEAR(end.origin.z, end.origin.x + 16 - 64 + kRest * std::numbers::sqrt2, 0.1);
  }
  {
    const World world = withFloor().ramp(64, 400, 256, 60).build();
    std::vector<PlayerState> path;
    const PlayerState end =
        runPlayer(world, shape, at({0, 0, 1}), walk(1, 0), stepsFor(3), kDt, work, {}, &path);
    Real highest = 0;
    for (const PlayerState& s : path) highest = std::max(highest, s.origin.z);
    EXPECT_LT(highest, 1.5);  // never climbed (it started 1 above the floor)
    EXPECT_NEAR(end.origin.z, kRest, 0.05);
    EXPECT_LT(end.origin.x, 64 - 16);
    // Put on the slope 100 units up, standing still: it slides down to the floor.
    const Real x = 64 - 16 + Real(100 / std::tan(std::numbers::pi / 3));
    const PlayerState slid = runPlayer(world, shape, at({x, 0, 101}), {}, stepsFor(3), kDt, work);
    EXPECT_FALSE(slid.stuck);
    EXPECT_TRUE(slid.onGround);
    EXPECT_NEAR(slid.origin.z, kRest, 0.05);
    EXPECT_LT(slid.origin.x, 64 - 16);
  }
}

// (d) Walking diagonally into the corner of two walls: the player stops in
// the corner, inside the room, and stays there bit for bit.
TEST(PlayerMove, StopsInACornerWithoutJitter) {
  const World world =
      withFloor().box({128, -512, 0}, {144, 512, 128}).box({-512, 128, 0}, {512, 144, 128}).build();
  const PlayerShape shape = PlayerShape::standard();
  WorldQueryWork work;
  std::vector<PlayerState> path;
  runPlayer(world, shape, at({0, 0, 1}), walk(1, 1), stepsFor(3), kDt, work, {}, &path);
  const PlayerState& end = path.back();
  EXPECT_NEAR(end.origin.x, 128 - 16 - kRest, 0.05);
  EXPECT_NEAR(end.origin.y, 128 - 16 - kRest, 0.05);
  EXPECT_NEAR(end.origin.z, kRest, 0.05);
  EXPECT_LE(end.origin.x, 128 - 16);
  EXPECT_LE(end.origin.y, 128 - 16);
  for (std::size_t i = path.size() - 30; i < path.size(); ++i)
    EXPECT_EQ(path[i].origin, end.origin) << "step " << i;
  // Along one wall: it slides along it to the corner too.
  const PlayerState along =
      runPlayer(world, shape, at({0, 100, 1}), walk(1, Real(0.2)), stepsFor(3), kDt, work);
  EXPECT_NEAR(along.origin.x, 128 - 16 - kRest, 0.05);
  EXPECT_NEAR(along.origin.y, 128 - 16 - kRest, 0.05);
}

// (e) A fall from rest of h lands at t = sqrt(2h/g), within a step; a jump
// rises jumpHeight (48) and lands after 2 sqrt(2 * 48 / g).
TEST(PlayerMove, FallsAndJumpsByTheFormulas) {
  const World world = withFloor().build();
  const PlayerShape shape = PlayerShape::standard();
  WorldQueryWork work;
  const Real h = 200;
  PlayerState s = at({0, 0, h + kRest});
  int steps = 0;
  while (!s.onGround && steps < 1000) {
    s = stepPlayer(world, shape, s, {}, kDt, work);
    ++steps;
  }
  const double expected = std::sqrt(2 * double(h) / double(move::kGravity));  // 0.6126 s
  EXPECT_NEAR(steps * double(kDt), expected, double(kDt));
  EXPECT_NEAR(s.origin.z, kRest, 0.05);
  EXPECT_EQ(s.velocity.z, 0);

  // Jump once from rest (a press, then released).
  s = runPlayer(world, shape, s, {}, 10, kDt, work);
  ASSERT_TRUE(s.onGround);
  const Real floorZ = s.origin.z;
  PlayerInput jump;
  jump.jump = true;
  s = stepPlayer(world, shape, s, jump, kDt, work);
  EXPECT_TRUE(s.jumped);
  EXPECT_FALSE(s.onGround);
  Real apex = s.origin.z;
  int airSteps = 1;
  while (!s.onGround && airSteps < 1000) {
    s = stepPlayer(world, shape, s, jump, kDt, work);  // held
    apex = std::max(apex, s.origin.z);
    ++airSteps;
  }
  // The path is the exact parabola at the steps' times; its top (t = 0.300 s)
  // falls within 0.001 s of step 18: within g dt^2 / 8 = 0.04 of 48.
  EXPECT_NEAR(apex - floorZ, move::kJumpHeight, 0.04);
  const double flight = 2 * std::sqrt(2 * double(move::kJumpHeight) / double(move::kGravity));  // 0.600 s
  EXPECT_NEAR(airSteps * double(kDt), flight, double(kDt));
  EXPECT_EQ(s.velocity.z, 0);
  // Still held, the button does not jump again on landing; pressed again, it does.
  s = runPlayer(world, shape, s, jump, 30, kDt, work);
  EXPECT_TRUE(s.onGround);
  EXPECT_FALSE(s.jumped);
  s = stepPlayer(world, shape, s, {}, kDt, work);
  s = stepPlayer(world, shape, s, jump, kDt, work);
  EXPECT_TRUE(s.jumped);
}

// (f) A platform entity moved by setPlacement between steps carries the
// player standing on it: up, then sideways.
TEST(PlayerMove, RidesAMovingPlatform) {
  World world = withFloor().build();
  auto box = TraceModel::box(Bounds({-64, -64, 0}, {64, 64, 16}));
  ASSERT_TRUE(box);
  Placement place;
  auto platform = world.addTraceModelEntity("platform", *box, place);
  ASSERT_TRUE(platform);
  const PlayerShape shape = PlayerShape::standard();
  WorldQueryWork work;
  PlayerState s = runPlayer(world, shape, at({0, 0, 20}), {}, 30, kDt, work);
  ASSERT_TRUE(s.onGround);
  EXPECT_EQ(s.groundEntity, *platform);
  EXPECT_NEAR(s.origin.z, 16 + kRest, 0.05);
  for (int i = 0; i < 60; ++i) {  // up 1 unit a step: 60 units/s
    place.origin.z += 1;
    ASSERT_TRUE(world.setPlacement(*platform, place));
    s = stepPlayer(world, shape, s, {}, kDt, work);
    ASSERT_TRUE(s.onGround) << i;
    ASSERT_FALSE(s.stuck) << i;
  }
  EXPECT_NEAR(s.origin.z, 76 + kRest, 0.05);
  for (int i = 0; i < 30; ++i) {  // along +x, 1 unit a step
    place.origin.x += 1;
    ASSERT_TRUE(world.setPlacement(*platform, place));
    s = stepPlayer(world, shape, s, {}, kDt, work);
  }
  EXPECT_TRUE(s.onGround);
  EXPECT_NEAR(s.origin.x, 30, 0.05);
  EXPECT_NEAR(s.origin.z, 76 + kRest, 0.05);
  // Down again, faster than it would fall in the first steps: still on it.
  for (int i = 0; i < 20; ++i) {
    place.origin.z -= 2;
    ASSERT_TRUE(world.setPlacement(*platform, place));
    s = stepPlayer(world, shape, s, {}, kDt, work);
    ASSERT_TRUE(s.onGround) << i;
  }
  EXPECT_NEAR(s.origin.z, 36 + kRest, 0.05);
}

// Starts in solid: a few units into the floor is lifted out (nudged); deep
// inside a brush is stuck and does not move.
TEST(PlayerMove, StartInSolidIsNudgedUpOrReportedStuck) {
  const World world = withFloor().box({200, -64, 0}, {400, 64, 300}).build();
  const PlayerShape shape = PlayerShape::standard();
  WorldQueryWork work;
  PlayerState s = stepPlayer(world, shape, at({0, 0, -3}), {}, kDt, work);
  EXPECT_TRUE(s.nudged);
  EXPECT_FALSE(s.stuck);
  EXPECT_GE(s.origin.z, 0);
  s = runPlayer(world, shape, s, {}, 30, kDt, work);
  EXPECT_TRUE(s.onGround);
  EXPECT_NEAR(s.origin.z, kRest, 0.05);

  PlayerState in = at({300, 0, 100});
  in.velocity = {50, 0, 0};
  s = stepPlayer(world, shape, in, walk(1, 0), kDt, work);
  EXPECT_TRUE(s.stuck);
  EXPECT_EQ(s.origin, in.origin);
  EXPECT_EQ(s.velocity, (Vec3{}));
  // Refused input: the state as it was, stuck.
  s = stepPlayer(world, shape, at({0, 0, 1}), walk(1, 0), 0, work);
  EXPECT_TRUE(s.stuck);
  EXPECT_EQ(s.origin, (Vec3{0, 0, 1}));
}

// Crouched under a low ceiling the player cannot stand up until it is out.
TEST(PlayerMove, StandsUpOnlyWhereTheStandingShapeFits) {
  // A ceiling 50 above the floor for x > 64.
  const World world = withFloor().box({64, -256, 50}, {512, 256, 66}).build();
  const PlayerShape shape = PlayerShape::standard();
  WorldQueryWork work;
  PlayerInput crouch = walk(1, 0);
  crouch.crouch = true;
  PlayerState s = runPlayer(world, shape, at({0, 0, 1}), crouch, stepsFor(1.5), kDt, work);
  EXPECT_TRUE(s.crouched);
  EXPECT_GT(s.origin.x, 64 + 16);  // under the ceiling (80 units/s crouched)
  s = stepPlayer(world, shape, s, {}, kDt, work);
  EXPECT_TRUE(s.crouched);  // no room to stand
  // Standing, the player does not get under it.
  const PlayerState upright = runPlayer(world, shape, at({0, 0, 1}), walk(1, 0), stepsFor(1.5), kDt, work);
  EXPECT_FALSE(upright.crouched);
  EXPECT_LE(upright.origin.x, 64 - 16 - kRest + 0.01);
}

bool sameBits(const std::vector<PlayerState>& a, const std::vector<PlayerState>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::memcmp(&a[i].origin, &b[i].origin, sizeof(Vec3)) != 0 ||
        std::memcmp(&a[i].velocity, &b[i].velocity, sizeof(Vec3)) != 0 || a[i].onGround != b[i].onGround ||
        a[i].groundEntity != b[i].groundEntity)
      return false;
  }
  return true;
}

// (g) The same inputs give the same bits: a second run, a fresh scratch,
// another thread.
TEST(PlayerMove, RunsAreDeterministic) {
  const World world = loadStairs();
  const PlayerShape shape = PlayerShape::standard();
  PlayerInput in = walk(1, Real(0.3));
  in.run = true;
  in.jump = true;
  auto run = [&](std::vector<PlayerState>& path) {
    WorldQueryWork work;
    runPlayer(world, shape, at({-100, 40, 30}), in, stepsFor(3), kDt, work, {}, &path);
  };
  std::vector<PlayerState> first, second, third;
  run(first);
  run(second);
  std::thread other([&] { run(third); });
  other.join();
  EXPECT_TRUE(sameBits(first, second));
  EXPECT_TRUE(sameBits(first, third));
  EXPECT_FALSE(first.back().origin == first.front().origin);
}

/// Keeps every translation a step reports.
struct Recorder : PlayerMoveObserver {
  std::vector<PlayerTranslation> seen;
  void translated(const PlayerTranslation& t) override { seen.push_back(t); }
};

/// The parts of the translations seen, in order.
std::vector<PlayerMovePart> partsOf(const Recorder& r) {
  std::vector<PlayerMovePart> parts;
  for (const PlayerTranslation& t : r.seen) parts.push_back(t.part);
  return parts;
}

/// The same bits: a reported answer and World::translate's for its move.
bool sameAnswer(const World& world, const PlayerTranslation& t, WorldQueryWork& work) {
  TranslationQuery q;
  q.trm = t.trm;
  q.start = t.start;
  q.end = t.end;
  q.contentMask = t.contentMask;
  EntityFilter filter;
  if (t.ignored != kNoEntity) filter.ignore = std::span<const EntityId>(&t.ignored, 1);
  const WorldTraceResult r = world.translate(q, work, filter);
  return std::memcmp(&r.trace.fraction, &t.result.trace.fraction, sizeof(Real)) == 0 &&
         std::memcmp(&r.trace.endPos, &t.result.trace.endPos, sizeof(Vec3)) == 0 &&
         std::memcmp(&r.trace.contact.normal, &t.result.trace.contact.normal, sizeof(Vec3)) == 0 &&
         r.entity == t.result.entity;
}

// The observer is told of exactly the translations of a step. A walk on a
// floor in the open: the ground probe, one slide that meets nothing, the
// stay-down probe and the end's probe; every answer is World::translate's
// for its move, the slide starts where the ground put the feet, the step
// ends where the last probe stopped. Into a riser: the flat slide (two
// moves), the lift, the stepped slide, the put-down, then the two probes.
// Without an observer the steps are the same bits.
TEST(PlayerMove, TheObserverSeesEveryTranslationOfAStep) {
  using P = PlayerMovePart;
  const PlayerShape shape = PlayerShape::standard();
  const World world = withFloor().box({64, -64, 0}, {256, 64, 8}).build();
  WorldQueryWork work;
  const PlayerState rest = runPlayer(world, shape, at({0, 0, 1}), walk(1, 0), 5, kDt, work);
  ASSERT_TRUE(rest.onGround);

  Recorder open;
  const PlayerState next = stepPlayer(world, shape, rest, walk(1, 0), kDt, work, {}, &open);
  ASSERT_EQ(partsOf(open), (std::vector<P>{P::Ground, P::Slide, P::Ground, P::Ground}));
  for (const PlayerTranslation& t : open.seen) {
    EXPECT_EQ(t.trm, &shape.standing);
    EXPECT_EQ(t.contentMask, shape.contentMask);
    EXPECT_EQ(t.ignored, kNoEntity);
    EXPECT_TRUE(sameAnswer(world, t, work)) << toString(t.part);
  }
  EXPECT_TRUE(open.seen[1].start == open.seen[0].result.trace.endPos);
  EXPECT_EQ(open.seen[1].result.trace.fraction, 1);
  EXPECT_GT(open.seen[1].end.x, open.seen[1].start.x);
  EXPECT_TRUE(open.seen.back().result.trace.endPos == next.origin);
  const PlayerState unobserved = stepPlayer(world, shape, rest, walk(1, 0), kDt, work);
  EXPECT_TRUE(sameBits({next}, {unobserved}));

  // Walk on until a step climbs the riser.
  PlayerState s = next;
  std::vector<P> climb;
  for (int i = 0; i < stepsFor(2) && climb.empty(); ++i) {
    Recorder r;
    const PlayerState after = stepPlayer(world, shape, s, walk(1, 0), kDt, work, {}, &r);
    EXPECT_TRUE(sameBits({after}, {stepPlayer(world, shape, s, walk(1, 0), kDt, work)}));
    for (const PlayerTranslation& t : r.seen) EXPECT_TRUE(sameAnswer(world, t, work)) << toString(t.part);
    if (after.origin.z > 4) {
      climb = partsOf(r);
      EXPECT_TRUE(r.seen.back().result.trace.endPos == after.origin);
    }
    s = after;
  }
  // The flat slide meets the riser and slides on (the overclip leaves it a
  // hair of speed away from it: a second move); the stepped slide meets
  // nothing.
  EXPECT_EQ(climb, (std::vector<P>{P::Ground, P::Slide, P::Slide, P::StepUp, P::Slide, P::StepDown, P::Ground,
                                   P::Ground}));
}

// One writer, many readers (movement.h, THREAD SAFETY): four threads step
// the same players at once, each with its own scratch and observer, then the
// one writer moves the crate between the rounds, never while they step (the
// player standing on it is carried at its next step). Every thread's paths
// and observed translations equal one thread's made before the round. (Run
// under ThreadSanitizer by ./dev.sh tsan: no race.)
TEST(PlayerMove, PlayersOnManyThreadsBetweenTheWritersMoves) {
  World world = withFloor().build();
  auto crateShape = TraceModel::box({{-32, -32, 0}, {32, 32, 32}});
  ASSERT_TRUE(crateShape);
  Placement crateAt;
  crateAt.origin = {100, 0, 0};
  auto crate = world.addTraceModelEntity("crate", *crateShape, crateAt);
  ASSERT_TRUE(crate) << crate.error().toString();
  const PlayerShape shape = PlayerShape::standard();
  // On the crate, walking into it, walking in the open.
  std::vector<PlayerState> players = {at({100, 0, 33}), at({-100, 0, 1}), at({-100, 200, 1})};
  const std::vector<PlayerInput> inputs = {walk(0, 0), walk(1, 0), walk(0, 1)};
  struct Steps {
    std::vector<std::vector<PlayerState>> paths;
    std::size_t translations = 0;
  };
  auto stepAll = [&](const std::vector<PlayerState>& from) {
    Steps out;
    WorldQueryWork work;
    Recorder seen;
    for (std::size_t p = 0; p < from.size(); ++p) {
      out.paths.emplace_back();
      runPlayer(world, shape, from[p], inputs[p], stepsFor(0.5), kDt, work, {}, &out.paths.back(), &seen);
    }
    out.translations = seen.seen.size();
    return out;
  };
  for (int round = 0; round < 3; ++round) {
    const Steps expected = stepAll(players);
    std::array<Steps, 4> got;
    std::vector<std::thread> readers;
    for (std::size_t t = 0; t < got.size(); ++t) readers.emplace_back([&, t] { got[t] = stepAll(players); });
    for (std::thread& r : readers) r.join();
    for (std::size_t t = 0; t < got.size(); ++t) {
      EXPECT_EQ(got[t].translations, expected.translations) << "round " << round << " reader " << t;
      for (std::size_t p = 0; p < players.size(); ++p)
        EXPECT_TRUE(sameBits(got[t].paths[p], expected.paths[p])) << "round " << round << " player " << p;
    }
    for (std::size_t p = 0; p < players.size(); ++p) players[p] = expected.paths[p].back();
    EXPECT_EQ(players[0].groundEntity, *crate) << "round " << round;
    // The one writer, between the rounds: the crate slides along +x.
    const Vec3 was = players[0].origin;
    crateAt.origin.x += 20;
    ASSERT_TRUE(world.setPlacement(*crate, crateAt).ok());
    WorldQueryWork work;
    const PlayerState carried = stepPlayer(world, shape, players[0], inputs[0], kDt, work);
    EXPECT_NEAR(carried.origin.x, was.x + 20, 0.01) << "round " << round;
  }
}

/// The "end" array of `cmkit walk --json` output.
Vec3 jsonEnd(const std::string& json) {
  const std::size_t at = json.find("\"end\": [");
  Vec3 v{-1e9f, -1e9f, -1e9f};
  if (at == std::string::npos) return v;
  double x = 0, y = 0, z = 0;
  if (std::sscanf(json.c_str() + at, "\"end\": [%lf, %lf, %lf]", &x, &y, &z) == 3)
    v = {Real(x), Real(y), Real(z)};
  return v;
}

// `cmkit walk` on stairs.map: the same ends as the library's walks above.
TEST(CmkitWalk, EndsOnTheLandingAndIsHeldByHighRisers) {
  const std::string cli = CMKIT_CLI_PATH;
  const std::string map = "'" + (test::testDataDir() / "maps" / "stairs.map").string() + "'";
  test::ScratchDir scratch("cmkit_walk");
  const std::string csv = (scratch.path() / "steps.csv").string();
  int rc = -1;
  std::string out = test::runCapture(
      cli + " walk " + map + " --from=-64,64,1 --wish 1,0 --seconds 4 --json --path '" + csv + "'", rc);
  ASSERT_EQ(rc, 0) << out;
  Vec3 end = jsonEnd(out);
  EXPECT_NEAR(end.x, 256 - 16 - kRest, 0.05) << out;
  EXPECT_NEAR(end.z, 60 + kRest, 0.05) << out;
  EXPECT_NE(out.find("\"on_ground\": true"), std::string::npos) << out;
  EXPECT_NE(out.find("\"ground_entity\": \"worldspawn\""), std::string::npos) << out;
  EXPECT_NE(out.find("\"steps\": 240"), std::string::npos) << out;
  const std::string steps = test::readFile(csv);
  EXPECT_EQ(std::count(steps.begin(), steps.end(), '\n'), 241);  // a header and 240 steps
  EXPECT_EQ(steps.rfind("step,time,x,y,z,", 0), 0u);

  out = test::runCapture(cli + " walk " + map + " --from=-64,-64,1 --wish 1,0 --seconds 4 --json", rc);
  ASSERT_EQ(rc, 0) << out;
  end = jsonEnd(out);
  EXPECT_NEAR(end.x, 64 - 16 - kRest, 0.05) << out;
  EXPECT_NEAR(end.z, kRest, 0.05) << out;
  // The text form; refused arguments exit with 2.
  out = test::runCapture(cli + " walk " + map + " --from=-64,64,1 --wish 1,0 --seconds 4", rc);
  EXPECT_EQ(rc, 0);
  EXPECT_NE(out.find("end (239.750 64.000 60.250)"), std::string::npos) << out;
  for (const char* bad : {"--wish 1 --seconds 1", "--wish 1,0 --seconds -1", "--wish 1,0 --seconds nan",
                          "--wish 1,0 --seconds 1 --shape point", "--wish 1,0,0,0 --seconds 1"}) {
    test::runCapture(cli + " walk " + map + " --from=0,64,1 " + bad + " 2>/dev/null", rc);
    EXPECT_EQ(rc, 2) << bad;
  }
}

}  // namespace
}  // namespace cmkit
