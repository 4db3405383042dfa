// Internal to `cmkit soak` (soak.h): the engine, Soak::Impl, whose sweeps,
// checks and classification of embedded ends are soak.cpp's and whose
// walker is soak_walker.cpp's; the constants of both.
#pragma once

#include <algorithm>
#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "cmkit/movement.h"
#include "cmkit/query.h"
#include "cmkit/world.h"
#include "soak.h"
#include "soak_geometry.h"

namespace cmkit::cli {

/// An embedded end at most this deep (penetration()) is a precision case.
constexpr Real kPrecisionDepth = 0.01f;
/// A move whose direction makes |cos| below this with the plane it must
/// leave by is edge-on (grazing).
constexpr Real kGrazingCos = 0.02f;
/// Random positions tried per item for a free start.
constexpr int kStartTries = 400;
/// Steps of one walker before it starts again elsewhere (each walker is one
/// item with its own random generator, so results do not depend on threads).
constexpr int kWalkerStepsPerItem = 500;
/// A walker that moves less than kStuckDistance in kStuckSteps steps is stuck.
constexpr int kStuckSteps = 60;
constexpr Real kStuckDistance = 1.0f;
/// The walker is the library's player (movement.h, stepPlayer) with the
/// default MoveParams, running: steps of move::kTimeStep, a new random wish
/// direction every kWishSteps steps, a jump pressed at one step in
/// kJumpOneIn.
constexpr int kWishSteps = 40;
constexpr std::uint64_t kJumpOneIn = 97;
/// The slide planes of a step kept for a stuck walker's diagnosis.
constexpr int kMaxSlidePlanes = move::kMaxClipPlanes;
/// The room test of a stuck walker: how far the box moves (up to
/// kRoomProbe units) along each of kRoomDirections horizontal directions,
/// flat or lifted by the player's step height.
constexpr Real kRoomProbe = 4.0f;
/// A stuck walker whose wish is within this many degrees of the (inward)
/// normal of a plane its step from rest stops on is pressing into a wall
/// (movement.h): each step friction first takes the speed the last one left
/// (6 x 100 units/s a second below the stop speed, 10 a step), then the
/// acceleration adds 10 x 220 / 60 = 36.7 units/s along the wish, of which
/// the wall leaves 36.7 sin(angle) along it: within 3 degrees, under 1.92
/// units a second (60 steps; cmkit walk measures 1.92 at 3 degrees, 0.96 at
/// 1.5), so a window of kStuckSteps that also holds part of another wish, or
/// an angle under 1.56 degrees, makes less than kStuckDistance of progress.
constexpr Real kPressingDegrees = 3.0f;
constexpr int kRoomDirections = 8;
constexpr Real kTwoPi = 6.2831853f;

struct Soak::Impl {
 public:
  /// With walker steps (o.walkerSteps > 0), `walker` must be a closed
  /// convex solid (the player's shape): std::invalid_argument otherwise.
  Impl(ModelPtr world, std::vector<Shape> shapes, Shape walker, const SoakOptions& o);

  std::size_t numClosedBrushes() const { return facts_.numClosed(); }

  /// Item i < sweeps is sweep i; after them come the walkers.
  std::uint64_t numItems() const { return o_.sweeps + walkerItems(); }
  std::uint64_t walkerItems() const {
    return (o_.walkerSteps + kWalkerStepsPerItem - 1) / kWalkerStepsPerItem;
  }

  void runItem(std::uint64_t item, QueryWork& work, ItemTally& tally, std::vector<Case>& cases);

  /// Why a walker at `pos` wishing to walk along `wish` is stuck, one step
  /// from rest replayed (Soak::diagnoseStuck).
  StuckCause diagnoseStuck(const Vec3& pos, const Vec3& wish, QueryWork& work, std::string* detail) const;

  /// Runs one translation and names what its end is: "free", or the class
  /// of the finding (the --replay of a pasted query line).
  std::string replay(const Shape& s, const Vec3& from, const Vec3& to, QueryWork& work) const;

 private:
  struct Ctx {
    QueryWork& work;
    ItemTally& tally;
    std::vector<Case>& cases;
    std::uint64_t item;
    std::mt19937_64& rng;
  };

  Real uniform(Ctx& c, Real lo, Real hi) const {
    return lo + (hi - lo) * Real(double(c.rng() >> 11) * (1.0 / 9007199254740992.0));
  }
  Vec3 randomIn(Ctx& c, const Bounds& b) const {
    return {uniform(c, b.min.x, b.max.x), uniform(c, b.min.y, b.max.y), uniform(c, b.min.z, b.max.z)};
  }

  TraceResult move(Ctx& c, const Shape& s, const Vec3& from, const Vec3& to) const;
  ContentsQuery at(const Shape& s, const Vec3& pos) const;
  /// Nothing of the mask overlaps the trace model at `pos`. (A point's
  /// contents test reports the first brush containing it whatever the mask,
  /// so points use pointContents and the mask here.)
  bool isFree(Ctx& c, const Shape& s, const Vec3& pos) const;
  /// A free position inside the map: point traces along +-x, +-y, +-z all
  /// hit a surface (so not in the void around the map).
  std::optional<Vec3> freeStart(Ctx& c, const Shape& s) const;

  /// " trmaxis=r0,r1,r2" (the rows) for a turned trace model, else nothing.
  static std::string axisField(const Shape& s);
  std::string translationLine(const Shape& s, const Vec3& from, const Vec3& to) const;
  std::string contentsLine(const Shape& s, const Vec3& pos) const;

  /// A uniformly random rotation (rotationFromUniforms).
  Mat3 randomRotation(Ctx& c) const;

  void record(Ctx& c, Finding f, std::string lines) const;

  /// A walker-stuck case: counted, and kept when among the first --examples
  /// of its cause (so that every cause has examples).
  void recordStuck(Ctx& c, StuckCause why, std::string lines) const;

  /// Checks a translation's result; false when a must-hold check failed.
  bool checkResult(Ctx& c, const Shape& s, const Vec3& from, const Vec3& to, const TraceResult& r) const;

  /// Why the trace model at `end` overlaps solid after moving from `from`.
  /// The closed-brush test comes first: an end that overlaps a brush the
  /// start did not (by the exact separating-axis depth, deeper than
  /// kPrecisionDepth) whose faces to cross all have polygons is a missed
  /// collision whatever penetration() or the move's angle say, so neither
  /// the precision nor the grazing class can hide one. Next, an end that
  /// overlaps (by any depth) a brush the start did not, entered where a face
  /// to cross has no polygon at all, is brush-face: nothing could stop the
  /// move there (lt4's visportal brushes: the walker slid 0.0001 to 0.1
  /// units through their visportal side, a precision or grazing case
  /// before), so precision and grazing are left to faces with polygons.
  /// `detail` (when given) gets the brushes entered: number, depth, closed or open.
  Finding classify(Ctx& c, const Shape& s, const Vec3& from, const Vec3& end,
                   std::string* detail = nullptr) const;

  /// The faces the trace model had to cross to get into the brush (the
  /// planes the whole trace model was in front of at the start; all planes
  /// if there is none): closed when every one is covered by polygons, bare
  /// when one has no polygon at all (WorldFacts::faceBare).
  struct EntryCover {
    bool closed = false;
    bool bare = false;
  };
  EntryCover entryCover(const CmBrush& brush, const std::vector<Vec3>& vFrom) const;

  void sweep(Ctx& c, const Shape& shape) const;

  /// The contact normals the slide moves of a step stopped on, in order
  /// (the first kMaxSlidePlanes).
  struct SlidePlanes {
    Vec3 normals[kMaxSlidePlanes];
    int count = 0;
  };

  /// What one walker step did, from the translations the player reported
  /// (PlayerMoveObserver): the player's state after it, the slide moves'
  /// contact normals, and the first translation that ended in solid.
  struct StepInfo {
    PlayerState state;
    SlidePlanes planes;
    /// The first translation whose end a position test found in solid.
    std::optional<PlayerTranslation> embedded;
    /// The step's last translation (a step ends where its last probe did).
    std::optional<PlayerTranslation> last;
  };

  /// One player step of the walker from `state` (stepPlayer with `input`),
  /// every translation it makes checked: the must-hold checks (false when
  /// one failed: the walk ends), then a position test at its end.
  bool walkerStep(Ctx& c, WorldQueryWork& playerWork, const PlayerState& state, const PlayerInput& input,
                  StepInfo& info) const;

  /// How far the walker at `pos` moves along the horizontal unit `dir`, up
  /// to kRoomProbe: flat, or after going up the player's step height
  /// (whichever is further).
  Real roomAlong(Ctx& c, const Vec3& pos, const Vec3& dir) const;

  /// A blocked step: it moved the walker less than kStuckDistance /
  /// kStuckSteps, and its slide move stopped on at least one plane (the
  /// contact planes clipped its velocity to ~0).
  static bool blockedStep(const Vec3& from, const Vec3& to, const StepInfo& info) {
    return (to - from).length() * Real(kStuckSteps) < kStuckDistance && info.planes.count > 0;
  }

  /// Why a walker at `pos` wishing to walk along `wish` made no progress,
  /// `blockedSteps` of its last kStuckSteps steps blocked (blockedStep;
  /// negative: unknown, one step replayed from rest stands for them all):
  ///  no-room     it moves less than kStuckDistance along each of
  ///              kRoomDirections horizontal directions, flat or after a
  ///              step up (the map's: a space too small for the box);
  ///  cornered    else, at least half of the steps were blocked: their
  ///              contact planes clipped the velocity to ~0 while another
  ///              direction has room (the walk's: its wish pointed into a
  ///              corner or crease);
  ///  pressing    else, the wish is within kPressingDegrees of the inward
  ///              normal of a plane that stops its step from rest (the
  ///              walk's: the player creeps along the wall, movement.h);
  ///  unexplained else: the steps moved the box, yet it made no progress
  ///              (would hint at a query fault).
  /// Half, not all: the wish direction changes every 40 steps, so a walker
  /// cornered for 59 steps may be freed by the 60th.
  StuckCause diagnoseStuck(Ctx& c, const Vec3& pos, const Vec3& wish, int blockedSteps,
                           std::string* detail) const;

  void walk(Ctx& c, int steps) const;

  ModelPtr worldModel_;
  const CollisionModel& world_;
  /// The world model alone in a World, at the origin: where the walker, a
  /// player, walks (a World's answers are its models' answers bit for bit).
  World playerWorld_;
  std::vector<Shape> shapes_;
  Shape walker_;
  /// The walker's shape as a player (standing and crouched: walker_.trm)
  /// with the soak's mask; made (with playerWorld_'s entity) only for a
  /// soak with walker steps.
  std::optional<PlayerShape> player_;
  const SoakOptions& o_;
  soak_geometry::WorldFacts facts_;
  Bounds inner_;
};

}  // namespace cmkit::cli
