// door_walk: a player walks a route through two doors of the bundled lt4 map,
// in a World (every entity placed). With the doors closed it stops at the
// first one, and the world says which entity stopped it; the doors are then
// opened by turning each 90 degrees about its hinge (World::setPlacement,
// the world's one writer, between the walks) and the same walk passes both.
// A top view of the rooms with both paths is written as a picture.
//
//   door_walk [PICTURE.png]   (default: door_walk.png in the current folder)
//
// The route and the doors are lt4's (lt4_door_wood_3 and lt4_door_wood_4,
// two doorways 136 units apart on one corridor); the same walk in Python is
// examples/python/door_walk.py.
#include <cmkit/materials.h>
#include <cmkit/movement.h>
#include <cmkit/tools/picture.h>
#include <cmkit/world.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

namespace {

// Where the player's feet go, in order (z is the corridor's floor, found by
// the first step). The doorways are tight (40 units for a 32-unit player),
// so the route keeps to the middle of each.
const std::vector<cmkit::Vec3> kRoute = {
    {1000, -1483.5f, -530}, {900, -1483.5f, -530}, {850, -1492, -530}, {700, -1492, -530}};
// A waypoint counts as reached this close (map units, horizontally).
constexpr cmkit::Real kReached = 4;
// The walk gives up after this many steps without moving a unit (blocked).
constexpr int kPatienceSteps = 30;
// And after this many steps in all (20 s at 60 steps a second).
constexpr int kMaxSteps = 1200;

struct Door {
  const char* name;
  cmkit::Vec3 hinge;  // a point on the vertical line it turns about
};
// Each door turns about its -y end, away from a player coming from +x.
const Door kDoors[] = {{"lt4_door_wood_3", {935, -1504, 0}}, {"lt4_door_wood_4", {799, -1512, 0}}};

struct Walk {
  std::vector<cmkit::Vec3> path;  // the feet after each step
  bool arrived = false;
};

// Steers a player along kRoute: each step wishes towards the next waypoint.
Walk walkRoute(const cmkit::World& world, const cmkit::PlayerShape& shape) {
  cmkit::WorldQueryWork work;
  cmkit::PlayerState state;
  state.origin = kRoute.front();
  Walk walk;
  std::size_t next = 1;
  int still = 0;
  for (int step = 0; step < kMaxSteps && next < kRoute.size(); ++step) {
    cmkit::Vec3 toward = kRoute[next] - state.origin;
    toward.z = 0;
    if (toward.length() < kReached) {
      ++next;
      continue;
    }
    cmkit::PlayerInput input;
    input.wishDir = toward.normalized();
    const cmkit::PlayerState before = state;
    state = cmkit::stepPlayer(world, shape, state, input, cmkit::move::kTimeStep, work);
    walk.path.push_back(state.origin);
    still = (state.origin - before.origin).length() < cmkit::Real(1) / 60 ? still + 1 : 0;
    if (still >= kPatienceSteps) return walk;
  }
  walk.arrived = next == kRoute.size();
  return walk;
}

// What stops the player box a little further on from the walk's end.
std::string blockerAfter(const cmkit::World& world, const cmkit::PlayerShape& shape, const Walk& walk) {
  cmkit::TranslationQuery q;
  q.trm = &shape.standing;
  q.start = walk.path.back();
  q.end = q.start + cmkit::Vec3{-32, 0, 0};  // the route runs along -x
  q.contentMask = cmkit::contents::kMaskPlayerSolid;
  cmkit::WorldQueryWork work;
  const cmkit::WorldTraceResult r = world.translate(q, work);
  const cmkit::WorldEntity* e = world.entity(r.entity);
  return e ? e->name : "nothing";
}

// Turns an entity about the vertical line through `hinge`.
void turnAbout(cmkit::World& world, cmkit::EntityId id, const cmkit::Vec3& hinge, cmkit::Real degrees) {
  const cmkit::Placement now = world.entity(id)->placement;
  const cmkit::Mat3 turn =
      cmkit::Mat3::fromAxisAngle({0, 0, 1}, degrees * std::numbers::pi_v<cmkit::Real> / 180);
  cmkit::Placement opened;
  opened.origin = hinge + (now.origin - hinge) * turn;  // world = origin + local * axis
  opened.axis = now.axis * turn;
  if (!world.setPlacement(id, opened)) std::fprintf(stderr, "door_walk: could not move entity %d\n", id);
}

// The two paths over a view of the corridor, with where the closed doors stood.
cmkit::Image drawPaths(const cmkit::World& world, const Walk& closed, const Walk& open,
                       const std::vector<cmkit::Bounds>& closedDoors) {
  std::vector<cmkit::ModelPtr> models;
  cmkit::PictureOptions options;
  for (cmkit::EntityId id : world.entityIds()) {
    models.push_back(world.entity(id)->model);
    options.placements.push_back(world.entity(id)->placement);
  }
  options.width = 960;
  options.height = 540;
  // From above the corridor's south side, looking down at it; the ceilings
  // and everything above half the player's height is cut away.
  cmkit::Camera camera;
  camera.eye = {845, -1660, -120};
  const cmkit::Vec3 target{840, -1490, -552};
  camera.forward = (target - camera.eye).normalized();
  camera.right = cmkit::Vec3{1, 0, 0};
  camera.up = camera.right.cross(camera.forward);
  camera.fovYDegrees = 45;
  options.camera = camera;
  options.cutHeight = -500;
  options.overlay = [&](cmkit::DebugDraw& draw) {
    const auto line = [&](const Walk& walk, const cmkit::Rgba& color) {
      for (std::size_t i = 1; i < walk.path.size(); ++i)
        for (cmkit::Real dy : {-1, 0, 1}) {  // three lines: 1 pixel is thin
          const cmkit::Vec3 d{0, dy, 0};
          draw.line(walk.path[i - 1] + d, walk.path[i] + d, color, {cmkit::DrawKind::TracePath});
        }
    };
    line(open, cmkit::colors::kGreen);
    line(closed, cmkit::colors::kRed);
    // Where the doors stood when closed: their bounds' outline on the floor.
    for (const cmkit::Bounds& b : closedDoors) {
      const cmkit::Real z = b.min.z + 1;
      const cmkit::Vec3 c[4] = {
          {b.min.x, b.min.y, z}, {b.max.x, b.min.y, z}, {b.max.x, b.max.y, z}, {b.min.x, b.max.y, z}};
      for (int k = 0; k < 4; ++k)
        draw.line(c[k], c[(k + 1) % 4], cmkit::colors::kOrange, {cmkit::DrawKind::Label});
    }
    draw.text(kRoute.front() + cmkit::Vec3{8, 8, 0}, "start", cmkit::colors::kWhite,
              {cmkit::DrawKind::Label});
    draw.text(closed.path.back() + cmkit::Vec3{0, -48, 0}, "doors closed: stopped", cmkit::colors::kRed,
              {cmkit::DrawKind::Label});
    draw.text(open.path.back() + cmkit::Vec3{0, 24, 0}, "doors opened: through", cmkit::colors::kGreen,
              {cmkit::DrawKind::Label});
  };
  return cmkit::renderPicture(models, {}, options);
}

}  // namespace

int main(int argc, char** argv) {
  const std::string picture = argc > 1 ? argv[1] : "door_walk.png";
  auto loaded = cmkit::World::loadMap(CMKIT_EXAMPLE_MAP, cmkit::MaterialTable{});
  if (!loaded) {
    std::fprintf(stderr, "door_walk: %s\n", loaded.error().toString().c_str());
    return 1;
  }
  cmkit::World& world = loaded->world;
  std::printf("%zu entities placed\n", world.size());
  const cmkit::PlayerShape shape = cmkit::PlayerShape::standard();

  const Walk closed = walkRoute(world, shape);
  const cmkit::Vec3 stop = closed.path.back();
  std::printf("doors closed: %s at (%.2f %.2f %.2f) after %zu steps, stopped by %s\n",
              closed.arrived ? "arrived" : "stopped", double(stop.x), double(stop.y), double(stop.z),
              closed.path.size(), blockerAfter(world, shape, closed).c_str());

  std::vector<cmkit::Bounds> closedDoors;
  for (const Door& door : kDoors) {
    const cmkit::EntityId id = world.find(door.name);
    if (id == cmkit::kNoEntity) {
      std::fprintf(stderr, "door_walk: the map has no entity %s\n", door.name);
      return 1;
    }
    closedDoors.push_back(world.entity(id)->bounds);
    turnAbout(world, id, door.hinge, -90);  // the door swings towards -x, away from the player
    const cmkit::Bounds& b = world.entity(id)->bounds;
    std::printf("opened %s: now (%.0f %.0f)-(%.0f %.0f) seen from above\n", door.name, double(b.min.x),
                double(b.min.y), double(b.max.x), double(b.max.y));
  }

  const Walk open = walkRoute(world, shape);
  const cmkit::Vec3 end = open.path.back();
  std::printf("doors open: %s at (%.2f %.2f %.2f) after %zu steps\n", open.arrived ? "arrived" : "stopped",
              double(end.x), double(end.y), double(end.z), open.path.size());

  if (!cmkit::savePng(picture, drawPaths(world, closed, open, closedDoors))) {
    std::fprintf(stderr, "door_walk: could not write %s\n", picture.c_str());
    return 1;
  }
  std::printf("picture: %s\n", picture.c_str());
  return closed.arrived || !open.arrived ? 1 : 0;
}
