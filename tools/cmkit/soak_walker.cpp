// The walker of `cmkit soak` (soak_impl.h): a player-like box that walks,
// slides along what it meets, steps up, falls and jumps; its embedded steps
// classified as a sweep's ends are, its stuck spells diagnosed.
#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "soak_impl.h"

namespace cmkit::cli {

StuckCause Soak::Impl::diagnoseStuck(const Vec3& pos, const Vec3& wish, QueryWork& work,
                                     std::string* detail) const {
  ItemTally tally;
  std::vector<Case> cases;
  std::mt19937_64 rng(0);
  Ctx c{work, tally, cases, 0, rng};
  return diagnoseStuck(c, pos, wish, -1, detail);
}

bool Soak::Impl::slideMove(Ctx& c, Vec3& pos, Vec3& vel, Real time, std::string& lastLine, Vec3& lastFrom,
                           SlidePlanes& hit) const {
  Vec3* const planes = hit.normals;
  int& numPlanes = hit.count;
  numPlanes = 0;
  for (int bump = 0; bump < kMaxSlidePlanes && time > 0; ++bump) {
    const Vec3 end = pos + vel * time;
    const TraceResult r = move(c, walker_, pos, end);
    lastLine = translationLine(walker_, pos, end);
    lastFrom = pos;
    if (!checkResult(c, walker_, pos, end, r)) return false;
    pos = r.endPos;
    if (r.fraction >= 1) break;
    time *= 1 - r.fraction;
    if (numPlanes == kMaxSlidePlanes) {
      vel = {};
      break;
    }
    planes[numPlanes++] = r.contact.normal;
    auto clip = [](const Vec3& v, const Vec3& n) {
      const Real into = v.dot(n);
      return into < 0 ? v - n * (into * kOverbounce) : v;
    };
    Vec3 next = clip(vel, r.contact.normal);
    for (int i = 0; i + 1 < numPlanes; ++i) {
      if (next.dot(planes[i]) < 0) {  // pushed into an earlier plane: follow the crease
        Vec3 crease = planes[i].cross(r.contact.normal);
        const Real len = crease.length();
        if (len < 1e-4f) {
          next = {};
          break;
        }
        crease = crease * (1 / len);
        next = crease * crease.dot(vel);
      }
    }
    vel = next;
    if (vel.dot(vel) < 1e-6f) break;
  }
  return true;
}

bool Soak::Impl::walkerStep(Ctx& c, Vec3& pos, Vec3& vel, const Vec3& wish, bool mayJump,
                            StepInfo& info) const {
  // Ground check: a short point-of-feet trace down.
  const TraceResult down = move(c, walker_, pos, pos - Vec3{0, 0, 1});
  if (!checkResult(c, walker_, pos, pos - Vec3{0, 0, 1}, down)) return false;
  info.onGround = down.fraction < 1 && down.contact.normal.z >= kMinWalkNormalZ;
  if (info.onGround) {
    vel.x = wish.x;
    vel.y = wish.y;
    vel.z = (mayJump && c.rng() % 97 == 0) ? kJumpSpeed : std::max<Real>(vel.z, 0);
  } else {
    vel.z -= kGravity * kFrameTime;
  }
  Vec3 slidPos = pos, slidVel = vel;
  if (!slideMove(c, slidPos, slidVel, kFrameTime, info.lastLine, info.lastFrom, info.planes)) return false;
  if (info.onGround) {
    Vec3 up = pos + Vec3{0, 0, kStepHeight};
    const TraceResult ru = move(c, walker_, pos, up);
    if (!checkResult(c, walker_, pos, up, ru)) return false;
    Vec3 stepPos = ru.endPos, stepVel = vel;
    stepVel.z = 0;
    std::string stepLine;
    Vec3 stepFrom;
    SlidePlanes stepPlanes;
    if (!slideMove(c, stepPos, stepVel, kFrameTime, stepLine, stepFrom, stepPlanes)) return false;
    const Vec3 downTo = stepPos - Vec3{0, 0, kStepHeight + 1};
    const TraceResult rd = move(c, walker_, stepPos, downTo);
    if (!checkResult(c, walker_, stepPos, downTo, rd)) return false;
    const auto flat = [&](const Vec3& p) { return Vec3{p.x - pos.x, p.y - pos.y, 0}.lengthSquared(); };
    if (rd.fraction < 1 && rd.contact.normal.z >= kMinWalkNormalZ &&
        flat(rd.endPos) > flat(slidPos) + 0.01f) {
      slidPos = rd.endPos;
      slidVel = stepVel;
      info.planes = stepPlanes;
      info.lastLine = translationLine(walker_, stepPos, downTo);
      info.lastFrom = stepPos;
    }
  }
  pos = slidPos;
  vel = slidVel;
  return true;
}

Real Soak::Impl::roomAlong(Ctx& c, const Vec3& pos, const Vec3& dir) const {
  const Real flat = move(c, walker_, pos, pos + dir * kRoomProbe).fraction * kRoomProbe;
  const TraceResult up = move(c, walker_, pos, pos + Vec3{0, 0, kStepHeight});
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
  Vec3 stepped = pos, vel;
  StepInfo info;
  const bool ok = walkerStep(c, stepped, vel, wish, false, info);
  const Real moved = (stepped - pos).length();
  if (blockedSteps < 0) blockedSteps = ok && blockedStep(pos, stepped, info) ? kStuckSteps : 0;
  StuckCause cause = StuckCause::Unexplained;
  if (most < kStuckDistance)
    cause = StuckCause::NoRoom;
  else if (2 * blockedSteps >= kStuckSteps)
    cause = StuckCause::Cornered;
  if (detail) {
    const Real speed = Vec3{wish.x, wish.y, 0}.length();
    const Vec3 wishDir = speed > 0 ? Vec3{wish.x, wish.y, 0} * (1 / speed) : Vec3{};
    std::string planes;
    for (int i = 0; i < info.planes.count; ++i) {
      const Vec3& n = info.planes.normals[i];
      planes += fmt::format("{}({:.3f} {:.3f} {:.3f})", i ? " " : "", n.x, n.y, n.z);
    }
    *detail = fmt::format(
        "{} of {} steps blocked; {}, wish ({:.3f} {:.3f}): a step from rest moves it {:.5f} against {} "
        "plane(s) {}; room along the wish {:.3f}, most room {:.3f} toward ({:.3f} {:.3f})",
        blockedSteps, kStuckSteps, info.onGround ? "on the ground" : "in the air", wishDir.x, wishDir.y,
        moved, info.planes.count, planes, roomAlong(c, pos, wishDir), most, mostDir.x, mostDir.y);
  }
  return cause;
}

void Soak::Impl::walk(Ctx& c, int steps) const {
  std::optional<Vec3> start = freeStart(c, walker_);
  if (!start) {
    c.tally.noStart++;
    return;
  }
  Vec3 pos = *start, vel;
  Vec3 wish;
  Vec3 progressFrom = pos;
  int sinceProgress = 0, blockedSteps = 0;
  StepInfo info;
  for (int step = 0; step < steps; ++step) {
    c.tally.walkerSteps++;
    if (step % 40 == 0) {
      const Real a = uniform(c, 0, kTwoPi);
      wish = {std::cos(a) * kWalkSpeed, std::sin(a) * kWalkSpeed, 0};
    }
    const Vec3 before = pos;
    if (!walkerStep(c, pos, vel, wish, true, info)) return;
    // Embedded, fallen out of the map or stuck: count it and start again
    // from a new free position.
    std::optional<Finding> finding;
    bool restart = false;
    if (!isFree(c, walker_, pos)) {
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
    // An embedded step's last move is classified as a sweep's end is (the
    // map's faults: brush-face, patch-behind, other-polygon; cmkit's:
    // closed-brush, precision, grazing), counted per class and named in
    // the case; a stuck walker is diagnosed (diagnoseStuck) likewise.
    if (finding == Finding::WalkerEmbedded) {
      const Finding why = classify(c, walker_, info.lastFrom, pos);
      c.tally.walkerCauses[std::size_t(why)]++;
      record(c, *finding,
             fmt::format("# walker-embedded: {}\n", kFindingNames[std::size_t(why)]) + info.lastLine +
                 contentsLine(walker_, pos));
    } else if (finding == Finding::WalkerStuck) {
      std::string detail;
      const StuckCause why = diagnoseStuck(c, pos, wish, blockedSteps, &detail);
      recordStuck(c, why,
                  fmt::format("# walker-stuck: {}: {}\n", kStuckCauseNames[std::size_t(why)], detail) +
                      info.lastLine + contentsLine(walker_, pos));
    }
    if (finding || restart) {
      if (!(start = freeStart(c, walker_))) return;
      c.tally.respawns++;
      pos = progressFrom = *start;
      vel = {};
      sinceProgress = blockedSteps = 0;
    }
  }
}

}  // namespace cmkit::cli
