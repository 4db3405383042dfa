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

#include "cmkit/query.h"
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
/// The walker: frame time, gravity, speed, step height, slide planes.
constexpr Real kFrameTime = 1.0f / 60.0f;
constexpr Real kGravity = 800.0f;
constexpr Real kWalkSpeed = 320.0f;
constexpr Real kJumpSpeed = 270.0f;
constexpr Real kStepHeight = 18.0f;
constexpr int kMaxSlidePlanes = 4;
constexpr Real kOverbounce = 1.001f;
constexpr Real kMinWalkNormalZ = 0.7f;
/// The room test of a stuck walker: how far the box moves (up to
/// kRoomProbe units) along each of kRoomDirections horizontal directions.
constexpr Real kRoomProbe = 4.0f;
constexpr int kRoomDirections = 8;
constexpr Real kTwoPi = 6.2831853f;

struct Soak::Impl {
 public:
  Impl(const CollisionModel& world, std::vector<Shape> shapes, Shape walker, const SoakOptions& o)
      : world_(world), shapes_(std::move(shapes)), walker_(std::move(walker)), o_(o), facts_(world, o.mask) {
    const Vec3 size = world.bounds().max - world.bounds().min;
    inner_ = world.bounds().expanded(-std::min({size.x, size.y, size.z}) * 0.01f);
  }

  std::size_t numClosedBrushes() const { return facts_.numClosed(); }

  /// Item i < sweeps is sweep i; after them come the walkers.
  std::uint64_t numItems() const { return o_.sweeps + walkerItems(); }
  std::uint64_t walkerItems() const {
    return (o_.walkerSteps + kWalkerStepsPerItem - 1) / kWalkerStepsPerItem;
  }

  void runItem(std::uint64_t item, QueryWork& work, ItemTally& tally, std::vector<Case>& cases);

  /// Why a walker at `pos` with the wish velocity `wish` is stuck, one step
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
  /// the precision nor the grazing class can hide one.
  /// `detail` (when given) gets the brushes entered: number, depth, closed or open.
  Finding classify(Ctx& c, const Shape& s, const Vec3& from, const Vec3& end,
                   std::string* detail = nullptr) const;

  /// Whether every face the trace model had to cross to get into the brush
  /// has a polygon: the planes the whole trace model was in front of at the
  /// start (all planes if there is none).
  bool closedForMove(const CmBrush& brush, const std::vector<Vec3>& vFrom) const;

  void sweep(Ctx& c, const Shape& shape) const;

  /// The contact normals a slide move stopped on, in order.
  struct SlidePlanes {
    Vec3 normals[kMaxSlidePlanes];
    int count = 0;
  };

  /// One slide move of the walker: up to kMaxSlidePlanes contacts per step,
  /// the velocity clipped along each (creases between two planes followed).
  /// False when a must-hold check failed.
  bool slideMove(Ctx& c, Vec3& pos, Vec3& vel, Real time, std::string& lastLine, Vec3& lastFrom,
                 SlidePlanes& hit) const;

  /// What one walker step did: whether it stood on walkable ground, the
  /// contact normals of the slide move it kept, its last move.
  struct StepInfo {
    bool onGround = false;
    SlidePlanes planes;
    std::string lastLine;
    Vec3 lastFrom;
  };

  /// One walker step from `pos` with velocity `vel` and wish velocity `wish`:
  /// a ground check, the velocity (the wish on the ground, a jump when
  /// `mayJump` and the generator says so; gravity in the air), a slide move
  /// and the step-up (over kStepHeight, move, back down; kept when it got
  /// further). False when a must-hold check failed.
  bool walkerStep(Ctx& c, Vec3& pos, Vec3& vel, const Vec3& wish, bool mayJump, StepInfo& info) const;

  /// How far the walker at `pos` moves along the horizontal unit `dir`, up
  /// to kRoomProbe: flat, or after going up kStepHeight (whichever is further).
  Real roomAlong(Ctx& c, const Vec3& pos, const Vec3& dir) const;

  /// A blocked step: it moved the walker less than kStuckDistance /
  /// kStuckSteps, and its slide move stopped on at least one plane (the
  /// contact planes clipped its velocity to ~0).
  static bool blockedStep(const Vec3& from, const Vec3& to, const StepInfo& info) {
    return (to - from).length() * Real(kStuckSteps) < kStuckDistance && info.planes.count > 0;
  }

  /// Why a walker at `pos` with the wish velocity `wish` made no progress,
  /// `blockedSteps` of its last kStuckSteps steps blocked (blockedStep;
  /// negative: unknown, one step replayed from rest stands for them all):
  ///  no-room     it moves less than kStuckDistance along each of
  ///              kRoomDirections horizontal directions, flat or after a
  ///              step up (the map's: a space too small for the box);
  ///  cornered    else, at least half of the steps were blocked: their
  ///              contact planes clipped the velocity to ~0 while another
  ///              direction has room (the walk's: its wish pointed into a
  ///              corner or crease);
  ///  unexplained else: the steps moved the box, yet it made no progress
  ///              (would hint at a query fault).
  /// Half, not all: the wish direction changes every 40 steps, so a walker
  /// cornered for 59 steps may be freed by the 60th.
  StuckCause diagnoseStuck(Ctx& c, const Vec3& pos, const Vec3& wish, int blockedSteps,
                           std::string* detail) const;

  void walk(Ctx& c, int steps) const;

  const CollisionModel& world_;
  std::vector<Shape> shapes_;
  Shape walker_;
  const SoakOptions& o_;
  soak_geometry::WorldFacts facts_;
  Bounds inner_;
};

}  // namespace cmkit::cli
