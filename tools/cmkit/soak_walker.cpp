// The walker of `cmkit soak` (soak_impl.h): the library's player
// (movement.h, stepPlayer) walking, stepping, sliding, falling and jumping
// through the world model; every translation of its steps (reported by a
// PlayerMoveObserver) checked as a sweep's end is, and classified when it
// ends in solid; its stuck spells diagnosed.
#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "soak_impl.h"

namespace cmkit::cli {

namespace {

/// Keeps the translations of one player step.
struct StepTranslations : PlayerMoveObserver {
  std::vector<PlayerTranslation> seen;
  void translated(const PlayerTranslation& t) override { seen.push_back(t); }
};

/// A player standing (or falling) at `pos`, at rest.
PlayerState playerAt(const Vec3& pos) {
  PlayerState s;
  s.origin = pos;
  return s;
}

/// The walker's input: running along the horizontal direction of `wish`
/// (its length does not matter), a jump pressed when `jump`.
PlayerInput walkerInput(const Vec3& wish, bool jump) {
  PlayerInput in;
  const Vec3 flat{wish.x, wish.y, 0};
  const Real len = flat.length();
  in.wishDir = len > 0 ? flat * (1 / len) : Vec3{};
  in.run = true;
  in.jump = jump;
  return in;
}

}  // namespace

StuckCause Soak::Impl::diagnoseStuck(const Vec3& pos, const Vec3& wish, QueryWork& work,
                                     std::string* detail) const {
  ItemTally tally;
  std::vector<Case> cases;
  std::mt19937_64 rng(0);
  Ctx c{work, tally, cases, 0, rng};
  return diagnoseStuck(c, pos, wish, -1, detail);
}

bool Soak::Impl::walkerStep(Ctx& c, WorldQueryWork& playerWork, const PlayerState& state,
                            const PlayerInput& input, StepInfo& info) const {
  StepTranslations step;
  info = StepInfo{};
  info.state = stepPlayer(playerWorld_, *player_, state, input, move::kTimeStep, playerWork, {}, &step);
  for (const PlayerTranslation& t : step.seen) {
    const TraceResult& r = t.result.trace;
    if (!checkResult(c, walker_, t.start, t.end, r)) return false;
    if (t.part == PlayerMovePart::Slide && r.fraction < 1 && info.planes.count < kMaxSlidePlanes)
      info.planes.normals[info.planes.count++] = r.contact.normal;
    if (!info.embedded && !isFree(c, walker_, r.endPos)) info.embedded = t;
  }
  if (!step.seen.empty()) info.last = step.seen.back();
  return true;
}

Real Soak::Impl::roomAlong(Ctx& c, const Vec3& pos, const Vec3& dir) const {
  const Real flat = move(c, walker_, pos, pos + dir * kRoomProbe).fraction * kRoomProbe;
  const TraceResult up = move(c, walker_, pos, pos + Vec3{0, 0, move::kStepHeight});
  const Real stepped = move(c, walker_, up.endPos, up.endPos + dir * kRoomProbe).fraction * kRoomProbe;
  return std::max(flat, stepped);
}

StuckCause Soak::Impl::diagnoseStuck(Ctx& c, const Vec3& pos, const Vec3& wish, int blockedSteps,
                                     std::string* detail) const {
  Real most = -1;
  Vec3 mostDir;
  for (int k = 0; k < kRoomDirections; ++k) {
    const Real a = Real(k) * (kTwoPi / Real(kRoomDirections));
    const Vec3 dir{std::cos(a), std::sin(a), 0};
    const Real room = roomAlong(c, pos, dir);
    if (room > most) {
      most = room;
      mostDir = dir;
    }
  }
  // One step from rest, without a jump.
  WorldQueryWork playerWork;
  StepInfo info;
  const bool ok = walkerStep(c, playerWork, playerAt(pos), walkerInput(wish, false), info);
  const Vec3 stepped = ok ? info.state.origin : pos;
  const Real moved = (stepped - pos).length();
  if (blockedSteps < 0) blockedSteps = ok && blockedStep(pos, stepped, info) ? kStuckSteps : 0;
  // The plane of the step nearest to facing the wish: the angle between the
  // wish and its inward normal, in the horizontal plane.
  const Vec3 wishDir = walkerInput(wish, false).wishDir;
  Real facing = -1;
  for (int i = 0; i < info.planes.count; ++i) {
    const Vec3& n = info.planes.normals[i];
    const Real flat = std::sqrt(n.x * n.x + n.y * n.y);
    if (flat > 0) facing = std::max(facing, -(wishDir.x * n.x + wishDir.y * n.y) / flat);
  }
  StuckCause cause = StuckCause::Unexplained;
  if (most < kStuckDistance)
    cause = StuckCause::NoRoom;
  else if (2 * blockedSteps >= kStuckSteps)
    cause = StuckCause::Cornered;
  else if (facing >= std::cos(kPressingDegrees * (kTwoPi / 360)))
    cause = StuckCause::Pressing;
  if (detail) {
    std::string planes;
    for (int i = 0; i < info.planes.count; ++i) {
      const Vec3& n = info.planes.normals[i];
      planes += fmt::format("{}({:.3f} {:.3f} {:.3f})", i ? " " : "", n.x, n.y, n.z);
    }
    *detail = fmt::format(
        "{} of {} steps blocked; {}, wish ({:.3f} {:.3f}): a step from rest moves it {:.5f} against {} "
        "plane(s) {}{}; room along the wish {:.3f}, most room {:.3f} toward ({:.3f} {:.3f})",
        blockedSteps, kStuckSteps, info.state.onGround ? "on the ground" : "in the air", wishDir.x, wishDir.y,
        moved, info.planes.count, planes,
        facing > -1 ? fmt::format(" (the wish {:.2f} degrees from the nearest one's normal)",
                                  std::acos(std::min(facing, Real(1))) * (360 / kTwoPi))
                    : "",
        roomAlong(c, pos, wishDir), most, mostDir.x, mostDir.y);
  }
  return cause;
}

void Soak::Impl::walk(Ctx& c, int steps) const {
  std::optional<Vec3> start = freeStart(c, walker_);
  if (!start) {
    c.tally.noStart++;
    return;
  }
  WorldQueryWork playerWork;
  PlayerState player = playerAt(*start);
  Vec3 wish;
  Vec3 progressFrom = player.origin;
  int sinceProgress = 0, blockedSteps = 0;
  StepInfo info;
  for (int step = 0; step < steps; ++step) {
    c.tally.walkerSteps++;
    if (step % kWishSteps == 0) {
      const Real a = uniform(c, 0, kTwoPi);
      wish = {std::cos(a), std::sin(a), 0};
    }
    const bool jump = c.rng() % kJumpOneIn == 0;
    const Vec3 before = player.origin;
    if (!walkerStep(c, playerWork, player, walkerInput(wish, jump), info)) return;
    player = info.state;
    const Vec3& pos = player.origin;
    // A translation that ended in solid (or a step that did, or found no
    // way out of solid), fallen out of the map or stuck: count it and start
    // again from a new free position.
    std::optional<Finding> finding;
    bool restart = false;
    if (info.embedded || player.stuck || !isFree(c, walker_, pos)) {
      finding = Finding::WalkerEmbedded;
    } else if (pos.z < world_.bounds().min.z - 64) {
      restart = true;
    } else if ((pos - progressFrom).length() >= kStuckDistance) {
      progressFrom = pos;
      sinceProgress = blockedSteps = 0;
    } else {
      blockedSteps += blockedStep(before, pos, info);
      if (++sinceProgress >= kStuckSteps) finding = Finding::WalkerStuck;
    }
    // The translation that ended in solid (else the step's last) is
    // classified as a sweep's end is (the map's faults: brush-face,
    // patch-behind, other-polygon; cmkit's: closed-brush, precision,
    // grazing), counted per class and named in the case; a stuck walker is
    // diagnosed (diagnoseStuck) likewise.
    if (finding == Finding::WalkerEmbedded) {
      const std::optional<PlayerTranslation>& t = info.embedded ? info.embedded : info.last;
      const Vec3 from = t ? t->start : before, to = t ? t->end : pos;
      const Vec3 end = t ? t->result.trace.endPos : pos;
      const Finding why = classify(c, walker_, from, end);
      c.tally.walkerCauses[std::size_t(why)]++;
      record(c, *finding,
             fmt::format("# walker-embedded: {} (a {} translation)\n", kFindingNames[std::size_t(why)],
                         t ? toString(t->part) : "step's end") +
                 translationLine(walker_, from, to) + contentsLine(walker_, end));
    } else if (finding == Finding::WalkerStuck) {
      std::string detail;
      const StuckCause why = diagnoseStuck(c, pos, wish, blockedSteps, &detail);
      const Vec3 from = info.last ? info.last->start : before, to = info.last ? info.last->end : pos;
      recordStuck(c, why,
                  fmt::format("# walker-stuck: {}: {}\n", kStuckCauseNames[std::size_t(why)], detail) +
                      translationLine(walker_, from, to) + contentsLine(walker_, pos));
    }
    if (finding || restart) {
      if (!(start = freeStart(c, walker_))) return;
      c.tally.respawns++;
      player = playerAt(*start);
      progressFrom = player.origin;
      sinceProgress = blockedSteps = 0;
    }
  }
}

}  // namespace cmkit::cli
