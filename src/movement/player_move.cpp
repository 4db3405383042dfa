// The player move of movement.h. One step: carry by the ground entity,
// crouch, free a start in solid, find the ground, update the velocity, move
// (slide along what is met, step up on the ground), stay down on the ground,
// find the ground again. Every move is a World::translate of the player's
// shape; nothing is kept between steps but the PlayerState.
#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <string>

#include "cmkit/movement.h"
#include "cmkit/tolerances.h"

namespace cmkit {

namespace {

/// What the moves of one step share: the world, the shape in use, its mask,
/// the caller's scratch and observer.
struct Mover {
  const World& world;
  const TraceModel& trm;
  std::uint32_t mask;
  WorldQueryWork& work;
  PlayerMoveObserver* observer;

  /// The shape moved from `from` towards `to`, stopped by what it meets
  /// (reported to the observer as `part`); `ignored`: an entity left out.
  WorldTraceResult trace(PlayerMovePart part, const Vec3& from, const Vec3& to,
                         EntityId ignored = kNoEntity) const {
    TranslationQuery q;
    q.trm = &trm;
    q.start = from;
    q.end = to;
    q.contentMask = mask;
    EntityFilter filter;
    if (ignored != kNoEntity) filter.ignore = std::span<const EntityId>(&ignored, 1);
    const WorldTraceResult r = world.translate(q, work, filter);
    if (observer) observer->translated({part, &trm, from, to, mask, ignored, r});
    return r;
  }

  /// True when `shape` at `at` overlaps nothing the player collides with.
  bool fits(const TraceModel& shape, const Vec3& at) const {
    ContentsQuery q;
    q.trm = &shape;
    q.position = at;
    q.contentMask = mask;
    return world.contentsTest(q, work).result.contents == 0;
  }
  /// fits() for the shape in use.
  bool fits(const Vec3& at) const { return fits(trm, at); }
};

/// The planes met by one slide (unit normals facing the player).
struct ClipPlanes {
  std::array<Vec3, move::kMaxClipPlanes> normal{};
  int count = 0;
};

/// v without its component into the plane of unit normal n (a hair more:
/// tol::kPlayerOverclip), unchanged when it does not enter the plane.
Vec3 clipToPlane(const Vec3& v, const Vec3& n) {
  const Real into = v.dot(n);
  return into < 0 ? v - n * (into * tol::kPlayerOverclip) : v;
}

/// v without its component along unit normal n, whatever its sign: a
/// velocity made to run within the ground's plane.
Vec3 alongPlane(const Vec3& v, const Vec3& n) { return v - n * v.dot(n); }

/// True when v enters none of the planes but planes[skipA], planes[skipB].
bool entersNone(const Vec3& v, const ClipPlanes& planes, int skipA, int skipB) {
  for (int k = 0; k < planes.count; ++k) {
    if (k != skipA && k != skipB && v.dot(planes.normal[std::size_t(k)]) < 0) return false;
  }
  return true;
}

/// The velocity that `v` becomes against the planes met: v itself when it
/// enters none; else v slid along one plane it enters, when that slide
/// enters no other; else v's part along the crease of two planes, when
/// that enters no third; else zero (a corner: the player stops).
Vec3 slideAlongPlanes(const Vec3& v, const ClipPlanes& planes) {
  bool entersAny = false;
  for (int i = 0; i < planes.count; ++i) {
    if (v.dot(planes.normal[std::size_t(i)]) >= 0) continue;
    entersAny = true;
    const Vec3 slid = clipToPlane(v, planes.normal[std::size_t(i)]);
    if (entersNone(slid, planes, i, -1)) return slid;
  }
  if (!entersAny) return v;
  for (int i = 0; i < planes.count; ++i) {
    for (int j = i + 1; j < planes.count; ++j) {
      Vec3 crease = planes.normal[std::size_t(i)].cross(planes.normal[std::size_t(j)]);
      const Real sine = crease.length();
      if (sine < tol::kPlayerCreaseSine) continue;
      crease = crease * (1 / sine);
      const Vec3 along = crease * crease.dot(v);
      if (entersNone(along, planes, i, j)) return along;
    }
  }
  return {};
}

/// Adds n to the planes unless one of them is the same plane (their crease
/// has no direction). False when the planes are full: the player stops.
bool addPlane(ClipPlanes& planes, const Vec3& n) {
  for (int k = 0; k < planes.count; ++k) {
    const Vec3& m = planes.normal[std::size_t(k)];
    if (m.dot(n) > 0 && m.cross(n).length() < tol::kPlayerCreaseSine) return true;
  }
  if (planes.count == move::kMaxClipPlanes) return false;
  planes.normal[std::size_t(planes.count++)] = n;
  return true;
}

/// Where a slide ended.
struct Slide {
  Vec3 pos;              ///< the end
  Vec3 vel;              ///< the velocity slid along what was met
  ClipPlanes planes;     ///< what was met
  bool blocked = false;  ///< something was met
};

/// Moves from `pos` with velocity `vel` for `time` seconds, sliding along
/// what it meets (each move a translation; at most kMaxClipPlanes planes
/// and one move more). `steepAsWalls` (a player on the ground): a plane too
/// steep to walk on counts as the vertical wall under it, so that walking
/// into a steep slope stops instead of climbing it.
Slide slideMove(const Mover& m, const Vec3& pos, const Vec3& vel, Real time, bool steepAsWalls,
                const MoveParams& params) {
  Slide out;
  out.pos = pos;
  out.vel = vel;
  for (int bump = 0; bump <= move::kMaxClipPlanes && time > 0 && !out.vel.isZero(); ++bump) {
    const WorldTraceResult r = m.trace(PlayerMovePart::Slide, out.pos, out.pos + out.vel * time);
    out.pos = r.trace.endPos;
    if (!(r.trace.fraction < 1)) break;
    out.blocked = true;
    time -= time * r.trace.fraction;
    Vec3 n = r.trace.contact.normal;
    if (steepAsWalls && n.z < params.minWalkNormalZ) {
      const Vec3 wall{n.x, n.y, 0};
      const Real len = wall.length();
      if (len >= tol::kPlayerCreaseSine) n = wall * (1 / len);
    }
    if (!addPlane(out.planes, n)) {
      out.vel = {};
      break;
    }
    out.vel = slideAlongPlanes(vel, out.planes);
  }
  return out;
}

/// Horizontal squared distance from a to b.
Real flatDistanceSquared(const Vec3& a, const Vec3& b) {
  const Real dx = b.x - a.x, dy = b.y - a.y;
  return dx * dx + dy * dy;
}

/// A move on the ground: the slide, and when it met something the same
/// slide stepped up by at most stepHeight and put down again, kept when it
/// lands on walkable ground further on.
Slide groundMove(const Mover& m, const Vec3& pos, const Vec3& vel, Real time, const MoveParams& params) {
  Slide flat = slideMove(m, pos, vel, time, true, params);
  if (!flat.blocked || !(params.stepHeight > 0)) return flat;
  const Vec3 top = m.trace(PlayerMovePart::StepUp, pos, pos + Vec3{0, 0, params.stepHeight}).trace.endPos;
  if (!(top.z > pos.z)) return flat;
  Slide high = slideMove(m, top, vel, time, true, params);
  const Vec3 downTo{high.pos.x, high.pos.y, std::min(pos.z, high.pos.z) - tol::kPlayerGroundProbe};
  const WorldTraceResult down = m.trace(PlayerMovePart::StepDown, high.pos, downTo);
  const bool walkable = down.trace.fraction < 1 && down.trace.contact.normal.z >= params.minWalkNormalZ;
  const Real steppedFar = std::sqrt(flatDistanceSquared(pos, down.trace.endPos));
  const Real flatFar = std::sqrt(flatDistanceSquared(pos, flat.pos));
  if (!walkable || !(steppedFar > flatFar + tol::kPlayerStepGain)) return flat;
  high.pos = down.trace.endPos;
  return high;
}

/// The ground under the feet.
struct Ground {
  bool found = false;           ///< walkable ground within the probe, not left
  Vec3 pos;                     ///< the feet put down on it (found), else as given
  Vec3 normal;                  ///< its normal (found), else zero
  EntityId entity = kNoEntity;  ///< whose (found)
};

/// Looks for walkable ground within `depth` below the feet at `pos`; a
/// player moving away from it faster than tol::kPlayerLeaveGroundSpeed
/// (a jump) has none.
Ground findGround(const Mover& m, const Vec3& pos, const Vec3& vel, Real depth, const MoveParams& params) {
  Ground g;
  g.pos = pos;
  const WorldTraceResult r = m.trace(PlayerMovePart::Ground, pos, pos - Vec3{0, 0, depth});
  if (!(r.trace.fraction < 1) || r.trace.status != QueryStatus::Ok) return g;
  const Vec3& n = r.trace.contact.normal;
  if (n.z < params.minWalkNormalZ || vel.dot(n) > tol::kPlayerLeaveGroundSpeed) return g;
  g.found = true;
  g.pos = r.trace.endPos;
  g.normal = n;
  g.entity = r.entity;
  return g;
}

/// Friction on the ground: speed lost at friction * max(speed, stopSpeed)
/// per second, never below zero.
Vec3 applyFriction(const Vec3& vel, Real dt, const MoveParams& params) {
  const Real speed = vel.length();
  if (!(speed > 0)) return {};
  const Real drop = std::max(speed, params.stopSpeed) * params.friction * dt;
  const Real kept = std::max<Real>(speed - drop, 0);
  return vel * (kept / speed);
}

/// Accelerates towards wishSpeed along the unit direction `dir` (accel:
/// wished speeds per second), never past wishSpeed along it.
Vec3 accelerate(const Vec3& vel, const Vec3& dir, Real wishSpeed, Real accel, Real dt) {
  const Real missing = wishSpeed - vel.dot(dir);
  if (!(missing > 0)) return vel;
  return vel + dir * std::min(accel * dt * wishSpeed, missing);
}

/// `d` with its component along the unit normal n removed, made unit again
/// (zero when d runs along n): a wished direction along a slope.
Vec3 directionAlongPlane(const Vec3& d, const Vec3& n) {
  Vec3 along = alongPlane(d, n);
  const Real len = along.length();
  return len > 0 ? along * (1 / len) : Vec3{};
}

bool finiteInput(const PlayerState& s, const PlayerInput& in, Real dt) {
  return std::isfinite(dt) && dt > 0 && s.origin.isFinite() && s.velocity.isFinite() && in.wishDir.isFinite();
}

/// Carries the player by its ground entity's move since the last step.
Vec3 carried(const Mover& m, const PlayerState& s) {
  if (s.groundEntity == kNoEntity) return s.origin;
  const WorldEntity* e = m.world.entity(s.groundEntity);
  if (e == nullptr) return s.origin;
  const Placement& was = s.groundPlacement;
  const Placement& now = e->placement;
  if (was.origin == now.origin && was.axis == now.axis) return s.origin;
  const Vec3 local = was.axis * (s.origin - was.origin);  // the feet in the entity's frame
  const Vec3 moved = now.origin + local * now.axis;
  if (moved == s.origin) return s.origin;
  return m.trace(PlayerMovePart::Carry, s.origin, moved, s.groundEntity).trace.endPos;
}

}  // namespace

const char* toString(PlayerMovePart part) {
  switch (part) {
    case PlayerMovePart::Carry:
      return "carry";
    case PlayerMovePart::Ground:
      return "ground";
    case PlayerMovePart::Slide:
      return "slide";
    case PlayerMovePart::StepUp:
      return "step-up";
    case PlayerMovePart::StepDown:
      return "step-down";
  }
  return "?";
}

const TraceModel& playerTraceModel(const PlayerShape& shape, const PlayerState& state) {
  return state.crouched ? shape.crouched : shape.standing;
}

PlayerState stepPlayer(const World& world, const PlayerShape& shape, const PlayerState& state,
                       const PlayerInput& input, Real dt, WorldQueryWork& work, const MoveParams& params,
                       PlayerMoveObserver* observer) {
  PlayerState s = state;
  ++s.steps;
  s.stuck = false;
  s.nudged = false;
  s.jumped = false;
  if (!finiteInput(state, input, dt)) {
    s.stuck = true;
    return s;
  }
  const bool jumpPressed = input.jump && !state.jumpHeld;
  s.jumpHeld = input.jump;

  // 1. Carried by the ground entity's move since the last step.
  s.origin = carried(Mover{world, playerTraceModel(shape, s), shape.contentMask, work, observer}, s);

  // 2. Crouch, or stand up where the standing shape fits (with the clip
  // epsilon's room above, so that the next moves start free).
  const Mover standing{world, shape.standing, shape.contentMask, work, observer};
  if (input.crouch) {
    s.crouched = true;
  } else if (s.crouched && standing.fits(s.origin + Vec3{0, 0, tol::kClipEpsilon})) {
    s.crouched = false;
  }
  const Mover m{world, playerTraceModel(shape, s), shape.contentMask, work, observer};

  // 3. A start in solid: lifted to free space, or stuck.
  if (!m.fits(s.origin)) {
    bool freed = false;
    for (Real lift = tol::kPlayerNudgeStep; lift <= tol::kPlayerMaxNudge; lift += tol::kPlayerNudgeStep) {
      if (m.fits(s.origin + Vec3{0, 0, lift})) {
        // The clip epsilon's room more where there is room, so that the
        // next moves start free rather than touching.
        const Real clear = lift + tol::kClipEpsilon;
        s.origin.z += m.fits(s.origin + Vec3{0, 0, clear}) ? clear : lift;
        freed = true;
        break;
      }
    }
    if (!freed) {
      s.stuck = true;
      s.velocity = {};
      s.onGround = false;
      s.groundNormal = {};
      s.groundEntity = kNoEntity;
      s.groundPlacement = {};
      return s;
    }
    s.nudged = true;
  }

  // 4. The ground under the feet.
  const Ground ground = findGround(m, s.origin, s.velocity, tol::kPlayerGroundProbe, params);
  bool onGround = ground.found;
  if (onGround) s.origin = ground.pos;

  // 5. Velocity: friction and acceleration on the ground, a jump, or
  // steering and gravity in the air.
  const Real fullSpeed = s.crouched ? params.crouchSpeed : (input.run ? params.runSpeed : params.walkSpeed);
  Vec3 wishDir{input.wishDir.x, input.wishDir.y, 0};
  const Real wishLength = wishDir.length();
  const Real wishSpeed = fullSpeed * std::min<Real>(wishLength, 1);
  wishDir = wishLength > 0 ? wishDir * (1 / wishLength) : Vec3{};
  if (onGround && jumpPressed) {
    s.velocity.z = std::sqrt(2 * params.gravity * params.jumpHeight);
    s.jumped = true;
    onGround = false;
  }
  Vec3 moveVel, endVel;
  if (onGround) {
    Vec3 v = applyFriction(s.velocity, dt, params);
    v = accelerate(v, directionAlongPlane(wishDir, ground.normal), wishSpeed, params.groundAccel, dt);
    endVel = moveVel = alongPlane(v, ground.normal);
  } else {
    // The move takes the mean of the velocities at the step's start and
    // end: the exact path of constant gravity (a jump's apex is jumpHeight).
    endVel = accelerate(s.velocity, wishDir, wishSpeed, params.airAccel, dt);
    moveVel = endVel;
    endVel.z -= params.gravity * dt;
    moveVel.z = (moveVel.z + endVel.z) / 2;
  }

  // 6. The move.
  const Slide slid = onGround ? groundMove(m, s.origin, moveVel, dt, params)
                              : slideMove(m, s.origin, moveVel, dt, false, params);
  s.origin = slid.pos;
  s.velocity = onGround ? slid.vel : slideAlongPlanes(endVel, slid.planes);

  // 7. A walk stays on the ground: down stairs and slopes within stepHeight.
  if (onGround) {
    const Ground below =
        findGround(m, s.origin, s.velocity, params.stepHeight + tol::kPlayerGroundProbe, params);
    if (below.found) s.origin = below.pos;
  }

  // 8. The ground at the end.
  const Ground end = findGround(m, s.origin, s.velocity, tol::kPlayerGroundProbe, params);
  s.onGround = end.found;
  s.groundNormal = end.normal;
  s.groundEntity = end.entity;
  s.groundPlacement = {};
  if (end.found) {
    s.origin = end.pos;
    s.velocity = alongPlane(s.velocity, end.normal);  // landed, or walking along it
    if (const WorldEntity* e = world.entity(end.entity)) s.groundPlacement = e->placement;
  }
  return s;
}

PlayerState runPlayer(const World& world, const PlayerShape& shape, const PlayerState& start,
                      const PlayerInput& input, int steps, Real dt, WorldQueryWork& work,
                      const MoveParams& params, std::vector<PlayerState>* path,
                      PlayerMoveObserver* observer) {
  PlayerState s = start;
  for (int i = 0; i < steps; ++i) {
    s = stepPlayer(world, shape, s, input, dt, work, params, observer);
    if (path) path->push_back(s);
  }
  return s;
}

Result<PlayerShape> PlayerShape::box(Real width, Real height, Real crouchHeight) {
  if (!(width > 0 && height > 0 && crouchHeight > 0 && crouchHeight <= height) || !std::isfinite(width) ||
      !std::isfinite(height))
    return Error{"a player box needs width > 0, height > 0 and 0 < crouch height <= height"};
  const Real half = width / 2;
  auto standing = TraceModel::box(Bounds({-half, -half, 0}, {half, half, height}));
  auto crouched = TraceModel::box(Bounds({-half, -half, 0}, {half, half, crouchHeight}));
  if (!standing) return standing.error();
  if (!crouched) return crouched.error();
  PlayerShape shape;
  shape.standing = std::move(*standing);
  shape.crouched = std::move(*crouched);
  return shape;
}

Result<PlayerShape> PlayerShape::cylinder(int sides, Real width, Real height, Real crouchHeight) {
  if (!(width > 0 && height > 0 && crouchHeight > 0 && crouchHeight <= height) || !std::isfinite(width) ||
      !std::isfinite(height))
    return Error{"a player cylinder needs width > 0, height > 0 and 0 < crouch height <= height"};
  const Real half = width / 2;
  auto standing = TraceModel::cylinder(Bounds({-half, -half, 0}, {half, half, height}), sides);
  if (!standing) return standing.error();
  auto crouched = TraceModel::cylinder(Bounds({-half, -half, 0}, {half, half, crouchHeight}), sides);
  if (!crouched) return crouched.error();
  PlayerShape shape;
  shape.standing = std::move(*standing);
  shape.crouched = std::move(*crouched);
  return shape;
}

Result<PlayerShape> PlayerShape::fromTraceModel(const TraceModel& standing) {
  if (standing.isPoint() || !standing.isConvex())
    return Error{"a player shape must be a closed convex solid (box, cylinder, ...), not " +
                 std::string(toString(standing.shape()))};
  PlayerShape shape;
  shape.standing = standing;
  shape.crouched = standing;
  return shape;
}

PlayerShape PlayerShape::standard() { return *box(); }

}  // namespace cmkit
