// movement.h: a player that walks, steps, slides, falls, jumps and rides
// through a World, in the manner of Doom 3's player physics.
//
// CONTRACT
// - Units: map units (1 unit = 1 inch in Doom 3), seconds, units/s and
//   units/s². Axes: +z is up (gravity pulls along -z); the player never
//   turns: its shape stays axis-aligned (trmAxis identity).
// - The player is a TraceModel (PlayerShape) whose ORIGIN is the BOTTOM
//   CENTRE of its bounds: PlayerState::origin is where its feet are. The
//   default shape is the original's box, 32 x 32 x 74 (bounds -16,-16,0 to
//   16,16,74), 38 high when crouched; a cylinder works the same way.
// - stepPlayer() advances one time step of `dt` seconds. The intended step
//   is move::kTimeStep (1/60 s, the original's game tick); any dt > 0 works,
//   but the path depends on dt (a jump's apex and a fall's duration only to
//   within a step). One step:
//     1. carry: when the player stood on an entity at the end of the last
//        step (PlayerState::groundEntity) and that entity has moved since
//        (the caller moves entities with World::setPlacement BETWEEN steps),
//        the player is moved by the displacement of the point under its
//        feet (a translation through the world that ignores that entity);
//     2. crouch or stand up (standing up only where the standing shape fits);
//     3. a start in solid: the player is lifted by up to
//        tol::kPlayerMaxNudge to free space; when none is found it stays
//        where it is, its velocity zeroed, and `stuck` says so;
//     4. ground: a short trace down (tol::kPlayerGroundProbe) finds the
//        ground; a surface is walkable when its normal's z is at least
//        MoveParams::minWalkNormalZ (0.7, the original's MIN_WALK_NORMAL);
//     5. velocity: on the ground friction, then acceleration towards the
//        wished velocity, projected onto the ground plane; a jump (a new
//        press of PlayerInput::jump on the ground) sets the upward speed to
//        sqrt(2 g jumpHeight); in the air a weak acceleration and gravity;
//     6. move: World::translate with the shape and PlayerShape::contentMask;
//        the player slides along at most move::kMaxClipPlanes planes met in
//        one step: along the one plane hit, along the crease of two planes
//        when the velocity would enter both, and stops when a crease would
//        run into a third. On the ground, a move that hits something is
//        also tried stepped up by at most stepHeight (16) and then down; the
//        stepped move is kept when it lands on walkable ground further on.
//        On the ground, surfaces too steep to walk stop the player as walls
//        do (it does not climb them); in the air it slides down them;
//     7. stay down: a player that walked on the ground is put back on
//        walkable ground within stepHeight below (down stairs and slopes);
//     8. ground again: the state reports the ground found under the end.
// - cmkit stops every translation tol::kClipEpsilon (0.25) in front of a
//   surface, so a player at rest on a floor has its origin 0.25 above it.
// - DETERMINISM: stepPlayer and runPlayer are pure functions of their
//   arguments and of the World's entities and placements: no hidden or
//   static state, every field of every struct initialised, no threads. The
//   same inputs give the same bits, on any thread, with any WorldQueryWork
//   (the scratch holds no answer across calls). The move's own arithmetic
//   is +, -, *, / and std::sqrt, all correctly rounded, so the bits do not
//   depend on the maths library; they differ between the float and double
//   builds (Real).
// - THREAD SAFETY: as the World's queries: any number of threads may step
//   players in one World at once, each with its own WorldQueryWork, while
//   nothing moves the World's entities.
// - OBSERVING A STEP: a PlayerMoveObserver passed to stepPlayer (or
//   runPlayer) is told of every World::translate the step makes, in order,
//   on the stepping thread, as it returns: what moved (the shape, its mask),
//   from where to where, what for (PlayerMovePart) and the answer. It only
//   watches: the step's result is the same bits with or without one. Each
//   stepping thread needs its own observer (or one that is safe to call at
//   once); stepPlayer keeps no pointer to it after it returns. The
//   position tests of a step (crouch, unstick) are not translations and are
//   not reported. `cmkit soak` checks every reported end with a position
//   test (docs/reliability.md).
#pragma once

#include <cstdint>
#include <vector>

#include "cmkit/contents.h"
#include "cmkit/math.h"
#include "cmkit/query.h"
#include "cmkit/result.h"
#include "cmkit/trace_model.h"
#include "cmkit/world.h"

namespace cmkit {

/// The player's parameters, Doom 3's values (its pm_* settings and
/// Physics_Player constants) unless stated.
namespace move {
/// The time step the defaults are tuned for and the tests use: 1/60 s, the
/// original's game tick.
inline constexpr Real kTimeStep = Real(1) / Real(60);
/// Gravity, units/s² (the original's default g_gravity).
inline constexpr Real kGravity = 1066;
/// The highest step climbed without a jump (pm_stepsize).
inline constexpr Real kStepHeight = 16;
/// The least z of a walkable surface's normal: slopes up to about 45.6
/// degrees (MIN_WALK_NORMAL).
inline constexpr Real kMinWalkNormalZ = Real(0.7);
/// How high a jump lifts the feet (pm_jumpheight): the jump's speed is
/// sqrt(2 * kGravity * kJumpHeight), about 319.9 units/s.
inline constexpr Real kJumpHeight = 48;
/// Walking speed, units/s (pm_walkspeed).
inline constexpr Real kWalkSpeed = 140;
/// Running speed, units/s (pm_runspeed).
inline constexpr Real kRunSpeed = 220;
/// Speed while crouched, units/s (pm_crouchspeed).
inline constexpr Real kCrouchSpeed = 80;
/// Ground acceleration, in wished speeds per second: from rest, 1/10 s to
/// full speed before friction (PM_ACCELERATE).
inline constexpr Real kGroundAccel = 10;
/// Air acceleration, the same unit: some steering in a jump, no flying
/// (PM_AIRACCELERATE).
inline constexpr Real kAirAccel = 1;
/// Ground friction, per second: the speed lost each second is
/// kFriction * max(speed, kStopSpeed) (PM_FRICTION).
inline constexpr Real kFriction = 6;
/// Below this speed friction acts as at this speed, so a player stops in a
/// bounded time instead of creeping to rest (PM_STOPSPEED).
inline constexpr Real kStopSpeed = 100;
/// The default shape: 32 units wide and deep (pm_bboxwidth),
inline constexpr Real kPlayerWidth = 32;
/// 74 units high standing (pm_normalheight),
inline constexpr Real kPlayerHeight = 74;
/// and 38 crouched (pm_crouchheight).
inline constexpr Real kCrouchHeight = 38;
/// At most this many planes are met in one step; the fifth stops the
/// player (MAX_CLIP_PLANES; more only happen in tight, jagged corners).
inline constexpr int kMaxClipPlanes = 4;
}  // namespace move

/// The player's parameters; the defaults are move::k*.
struct MoveParams {
  Real gravity = move::kGravity;                ///< units/s², along -z
  Real stepHeight = move::kStepHeight;          ///< highest step climbed
  Real minWalkNormalZ = move::kMinWalkNormalZ;  ///< walkable when normal.z >= this
  Real jumpHeight = move::kJumpHeight;          ///< height of a jump
  Real walkSpeed = move::kWalkSpeed;            ///< units/s
  Real runSpeed = move::kRunSpeed;              ///< units/s (PlayerInput::run)
  Real crouchSpeed = move::kCrouchSpeed;        ///< units/s while crouched
  Real groundAccel = move::kGroundAccel;        ///< wished speeds per second, on the ground
  Real airAccel = move::kAirAccel;              ///< wished speeds per second, in the air
  Real friction = move::kFriction;              ///< per second, on the ground
  Real stopSpeed = move::kStopSpeed;            ///< friction's least speed
};

/// The player's shape: trace models whose origin is the bottom centre.
struct PlayerShape {
  TraceModel standing;  ///< the standing shape (a point when default-made: use the factories)
  TraceModel crouched;  ///< the crouched shape (same footprint, lower)
  /// What blocks the player: solid, player clip, bodies.
  std::uint32_t contentMask = contents::kMaskPlayerSolid;

  /// The original's box: width x width x height (bounds -w/2,-w/2,0 to
  /// w/2,w/2,height), crouchHeight high crouched.
  static Result<PlayerShape> box(Real width = move::kPlayerWidth, Real height = move::kPlayerHeight,
                                 Real crouchHeight = move::kCrouchHeight);
  /// A vertical prism of `sides` (3..10) faces around the z axis, in the
  /// same bounds as box().
  static Result<PlayerShape> cylinder(int sides = 8, Real width = move::kPlayerWidth,
                                      Real height = move::kPlayerHeight,
                                      Real crouchHeight = move::kCrouchHeight);
  /// Any trace model (e.g. TraceModel::parse's "box:..." or
  /// "cylinder:N:..."), its origin at the feet; crouching keeps the shape.
  /// Error for a point or a shape that is not a closed convex solid.
  static Result<PlayerShape> fromTraceModel(const TraceModel& standing);
  /// box() with the defaults (cannot fail).
  static PlayerShape standard();
};

/// What the player wants this step.
struct PlayerInput {
  /// Wished direction of walking, world space; z is ignored. Its horizontal
  /// length is the fraction of full speed (clamped to 1): (1,0,0) walks
  /// along +x at full speed, (0,0,0) stands still.
  Vec3 wishDir;
  bool jump = false;    ///< jump button held (a jump needs a new press on the ground)
  bool crouch = false;  ///< crouch button held
  bool run = false;     ///< run (MoveParams::runSpeed) instead of walk
};

/// The player's state between steps: plain data, every field defined.
struct PlayerState {
  Vec3 origin;    ///< the feet: bottom centre of the shape (world space)
  Vec3 velocity;  ///< units/s
  /// On walkable ground at the end of the step.
  bool onGround = false;
  /// The ground's normal (onGround), else zero.
  Vec3 groundNormal;
  /// The entity stood on (onGround), else kNoEntity. kWorldspawnEntity for
  /// a map's world model.
  EntityId groundEntity = kNoEntity;
  /// Where groundEntity was placed at the end of the step: the next step
  /// carries the player by that entity's move since.
  Placement groundPlacement;
  bool crouched = false;  ///< the crouched shape is in use
  /// The step started in solid and no lift of up to tol::kPlayerMaxNudge
  /// freed it: the player did not move (velocity zeroed).
  bool stuck = false;
  /// The step started in solid and was lifted to free space.
  bool nudged = false;
  /// A jump started this step.
  bool jumped = false;
  /// The jump button was held at the last step (a jump needs a new press).
  bool jumpHeld = false;
  /// Steps taken (each stepPlayer adds 1).
  std::int64_t steps = 0;
};

/// What a translation of a player step was for (the steps of the contract).
enum class PlayerMovePart : std::uint8_t {
  Carry,     ///< 1. carried by the ground entity's move
  Ground,    ///< 4, 7, 8. a trace down looking for the ground
  Slide,     ///< 6. a move of the slide (the flat one, or the stepped one's)
  StepUp,    ///< 6. the lift of a step up (by at most stepHeight)
  StepDown,  ///< 6. the stepped slide put down again
};

/// The name of a part: "carry", "ground", "slide", "step-up", "step-down".
const char* toString(PlayerMovePart part);

/// One translation of a player step, as World::translate answered it.
struct PlayerTranslation {
  PlayerMovePart part = PlayerMovePart::Slide;  ///< what it was for
  const TraceModel* trm = nullptr;              ///< the shape moved (standing or crouched)
  Vec3 start;                                   ///< the shape's origin (the feet) at the start
  Vec3 end;                                     ///< where it was to go
  std::uint32_t contentMask = 0;                ///< PlayerShape::contentMask
  /// The entity left out (a carry ignores the entity stood on), else kNoEntity.
  EntityId ignored = kNoEntity;
  /// The answer: result.trace.endPos is where the shape stopped.
  WorldTraceResult result;
};

/// Told of each translation a player step makes (see the contract).
class PlayerMoveObserver {
 public:
  virtual ~PlayerMoveObserver() = default;
  /// One translation, in the order the step made them.
  virtual void translated(const PlayerTranslation& t) = 0;
};

/// Advances the player one step of `dt` seconds (see the contract).
/// Refused input (dt not > 0 or not finite, a non-finite origin, velocity
/// or wish) leaves the state as it was, `stuck` set.
/// `observer`, when not null, is told of every translation the step makes.
PlayerState stepPlayer(const World& world, const PlayerShape& shape, const PlayerState& state,
                       const PlayerInput& input, Real dt, WorldQueryWork& work, const MoveParams& params = {},
                       PlayerMoveObserver* observer = nullptr);

/// `steps` calls of stepPlayer with the same input, each from the last's
/// state; `path`, when not null, gets every step's state appended;
/// `observer`, when not null, every step's translations. The world does not
/// change between the steps (move entities between your own stepPlayer
/// calls instead).
PlayerState runPlayer(const World& world, const PlayerShape& shape, const PlayerState& start,
                      const PlayerInput& input, int steps, Real dt, WorldQueryWork& work,
                      const MoveParams& params = {}, std::vector<PlayerState>* path = nullptr,
                      PlayerMoveObserver* observer = nullptr);

/// The shape in use in a state: shape.crouched when state.crouched.
const TraceModel& playerTraceModel(const PlayerShape& shape, const PlayerState& state);

}  // namespace cmkit
