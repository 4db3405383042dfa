// The engine of `cmkit soak` (soak.h): sweeps, the walker, the checks and
// the classification of embedded ends (by the brush-face cover and overlap
// depths of soak_geometry.h).
#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "cmkit/query.h"
#include "cmkit/tools/query_format.h"
#include "soak.h"
#include "soak_geometry.h"

namespace cmkit::cli {

namespace {

using soak_geometry::overlapDepth;
using soak_geometry::placedVertices;
using soak_geometry::WorldFacts;

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

bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

bool finite(const TraceResult& r) {
  return std::isfinite(r.fraction) && finite(r.endPos) && finite(r.contact.point) &&
         finite(r.contact.normal) && std::isfinite(r.contact.dist);
}

std::string vec(const Vec3& v) { return fmt::format("{},{},{}", v.x, v.y, v.z); }

Bounds boundsOf(const std::vector<Vec3>& verts) {
  Bounds b;
  for (const Vec3& v : verts) b.addPoint(v);
  return b;
}

}  // namespace

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

  void runItem(std::uint64_t item, QueryWork& work, ItemTally& tally, std::vector<Case>& cases) {
    std::mt19937_64 rng(o_.seed * 0x9E3779B97F4A7C15ull + item * 0xBF58476D1CE4E5B9ull + 1);
    Ctx c{work, tally, cases, item, rng};
    if (item < o_.sweeps) {
      sweep(c, shapes_[item % shapes_.size()]);
    } else {
      const std::uint64_t w = item - o_.sweeps;
      const std::uint64_t steps =
          std::min<std::uint64_t>(kWalkerStepsPerItem, o_.walkerSteps - w * kWalkerStepsPerItem);
      walk(c, int(steps));
    }
  }

  /// Runs one translation and names what its end is: "free", or the class
  /// of the finding (the --replay of a pasted query line).
  StuckCause diagnoseStuck(const Vec3& pos, const Vec3& wish, QueryWork& work, std::string* detail) const {
    ItemTally tally;
    std::vector<Case> cases;
    std::mt19937_64 rng(0);
    Ctx c{work, tally, cases, 0, rng};
    return diagnoseStuck(c, pos, wish, -1, detail);
  }

  std::string replay(const Shape& s, const Vec3& from, const Vec3& to, QueryWork& work) const {
    ItemTally tally;
    std::vector<Case> cases;
    std::mt19937_64 rng(0);
    Ctx c{work, tally, cases, 0, rng};
    const TraceResult r = move(c, s, from, to);
    if (!checkResult(c, s, from, to, r)) return kFindingNames[std::size_t(cases.front().finding)];
    if (isFree(c, s, r.endPos)) return fmt::format("free (fraction {})", r.fraction);
    std::string detail;
    const Finding f = classify(c, s, from, r.endPos, &detail);
    return fmt::format("{} (fraction {}, end {}{}{})", kFindingNames[std::size_t(f)], r.fraction,
                       vec(r.endPos), detail.empty() ? "" : "; entered ", detail);
  }

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

  TraceResult move(Ctx& c, const Shape& s, const Vec3& from, const Vec3& to) const {
    TranslationQuery q;
    q.trm = s.query();
    q.trmAxis = s.axis;
    q.start = from;
    q.end = to;
    q.contentMask = o_.mask;
    return translate(world_, q, c.work);
  }
  ContentsQuery at(const Shape& s, const Vec3& pos) const {
    ContentsQuery q;
    q.trm = s.query();
    q.trmAxis = s.axis;
    q.position = pos;
    q.contentMask = o_.mask;
    return q;
  }
  /// Nothing of the mask overlaps the trace model at `pos`. (A point's
  /// contents test reports the first brush containing it whatever the mask,
  /// so points use pointContents and the mask here.)
  bool isFree(Ctx& c, const Shape& s, const Vec3& pos) const {
    if (s.trm.isPoint()) return (pointContents(world_, {pos, {}}, c.work).contents & o_.mask) == 0;
    return (contentsTest(world_, at(s, pos), c.work).contents & o_.mask) == 0;
  }
  /// A free position inside the map: point traces along +-x, +-y, +-z all
  /// hit a surface (so not in the void around the map).
  std::optional<Vec3> freeStart(Ctx& c, const Shape& s) const {
    static const Vec3 kAxes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    const Vec3 size = world_.bounds().max - world_.bounds().min;
    const Real reach = size.x + size.y + size.z;
    Shape point{"point", TraceModel::point(), {}};
    for (int tryNo = 0; tryNo < kStartTries; ++tryNo) {
      const Vec3 p = randomIn(c, inner_);
      if (!isFree(c, s, p)) continue;
      bool enclosed = true;
      for (const Vec3& axis : kAxes) {
        if (move(c, point, p, p + axis * reach).fraction >= 1) {
          enclosed = false;
          break;
        }
      }
      if (enclosed) return p;
    }
    return std::nullopt;
  }

  /// " trmaxis=r0,r1,r2" (the rows) for a turned trace model, else nothing.
  static std::string axisField(const Shape& s) {
    if (!s.rotated()) return {};
    const Mat3& a = s.axis;
    return fmt::format(" trmaxis={},{},{}", vec(a[0]), vec(a[1]), vec(a[2]));
  }
  std::string translationLine(const Shape& s, const Vec3& from, const Vec3& to) const {
    return fmt::format("translation trm={}{} start={} end={} mask={}\n", s.spec, axisField(s), vec(from),
                       vec(to), o_.mask);
  }
  std::string contentsLine(const Shape& s, const Vec3& pos) const {
    return fmt::format("contents trm={}{} start={} mask={}\n", s.spec, axisField(s), vec(pos), o_.mask);
  }

  /// A uniformly random rotation (rotationFromUniforms).
  Mat3 randomRotation(Ctx& c) const {
    const double u1 = double(uniform(c, 0, 1)), u2 = double(uniform(c, 0, 1)), u3 = double(uniform(c, 0, 1));
    return rotationFromUniforms(u1, u2, u3);
  }

  void record(Ctx& c, Finding f, std::string lines) const {
    // Each thread keeps its first --examples cases per class; since it runs
    // its items in increasing order, the first ones overall are among them.
    if (++c.tally.counts[std::size_t(f)] <= o_.examples)
      c.cases.push_back({c.item, f, StuckCause::Unexplained, std::move(lines)});
  }

  /// A walker-stuck case: counted, and kept when among the first --examples
  /// of its cause (so that every cause has examples).
  void recordStuck(Ctx& c, StuckCause why, std::string lines) const {
    c.tally.counts[std::size_t(Finding::WalkerStuck)]++;
    if (++c.tally.stuckCauses[std::size_t(why)] <= o_.examples)
      c.cases.push_back({c.item, Finding::WalkerStuck, why, std::move(lines)});
  }

  /// Checks a translation's result; false when a must-hold check failed.
  bool checkResult(Ctx& c, const Shape& s, const Vec3& from, const Vec3& to, const TraceResult& r) const {
    if (!finite(r)) {
      record(c, Finding::NonFinite, translationLine(s, from, to));
      return false;
    }
    if (!(r.fraction >= 0 && r.fraction <= 1)) {
      record(c, Finding::FractionRange, translationLine(s, from, to));
      return false;
    }
    return true;
  }

  /// Why the trace model at `end` overlaps solid after moving from `from`.
  /// The closed-brush test comes first: an end that overlaps a brush the
  /// start did not (by the exact separating-axis depth, deeper than
  /// kPrecisionDepth) whose faces to cross all have polygons is a missed
  /// collision whatever penetration() or the move's angle say, so neither
  /// the precision nor the grazing class can hide one.
  /// `detail` (when given) gets the brushes entered: number, depth, closed or open.
  Finding classify(Ctx& c, const Shape& s, const Vec3& from, const Vec3& end,
                   std::string* detail = nullptr) const {
    const std::vector<Vec3> vEnd = placedVertices(s, end);
    const std::vector<Vec3> vFrom = placedVertices(s, from);
    const Bounds bEnd = boundsOf(vEnd).expanded(1);
    // The brushes the end overlaps (exact separating-axis test) that the start did not.
    bool anyOpen = false, anyClosed = false;
    for (std::size_t b = 0; b < world_.brushes().size(); ++b) {
      const CmBrush& brush = world_.brushes()[b];
      if (!(brush.contents & o_.mask) || !brush.bounds.intersects(bEnd)) continue;
      const double depth = overlapDepth(world_, brush, s, end);
      if (depth <= kPrecisionDepth) continue;
      if (overlapDepth(world_, brush, s, from) > 0) continue;  // started inside it
      const bool closed = closedForMove(brush, vFrom);
      (closed ? anyClosed : anyOpen) = true;
      if (detail)
        *detail += fmt::format("{}brush {} depth {:.4f} {}", detail->empty() ? "" : ", ", b, depth,
                               closed ? "closed" : "open");
    }
    if (anyClosed) return Finding::ClosedBrush;
    const ContentsQuery q = at(s, end);
    const PenetrationResult pen =
        penetration(world_, {q.trm, q.trmAxis, q.position, q.contentMask, q.placement}, c.work);
    if (pen.stuck && pen.depth <= kPrecisionDepth) return Finding::Precision;
    Vec3 dir = end - from;
    const Real length = dir.length();
    if (length > 0) dir = dir * (1 / length);
    if (pen.stuck && length > 0 && std::fabs(dir.dot(pen.direction)) < kGrazingCos) return Finding::Grazing;
    if (anyOpen) return Finding::BrushFace;
    // No brush entered overlaps the end deeper than kPrecisionDepth by the
    // exact test: the end is in polygons only (or in brushes it started in).
    // Only polygons: was one crossed from behind (start wholly behind its
    // plane, end straddling it)?
    for (const CmPolygon& p : world_.polygons()) {
      if (!(p.contents & o_.mask) || !p.bounds.intersects(bEnd)) continue;
      Real fromMax = -std::numeric_limits<Real>::max(), endMin = std::numeric_limits<Real>::max(),
           endMax = -std::numeric_limits<Real>::max();
      for (const Vec3& v : vFrom) fromMax = std::max(fromMax, p.plane.normal.dot(v) - p.plane.dist);
      for (const Vec3& v : vEnd) {
        endMin = std::min(endMin, p.plane.normal.dot(v) - p.plane.dist);
        endMax = std::max(endMax, p.plane.normal.dot(v) - p.plane.dist);
      }
      if (fromMax <= 0 && endMax > 0 && endMin <= 0) return Finding::PatchBehind;
    }
    return Finding::OtherPolygon;
  }

  /// Whether every face the trace model had to cross to get into the brush
  /// has a polygon: the planes the whole trace model was in front of at the
  /// start (all planes if there is none).
  bool closedForMove(const CmBrush& brush, const std::vector<Vec3>& vFrom) const {
    bool anyEntry = false, allHave = true, entryHave = true;
    for (std::uint32_t k = 0; k < brush.numPlanes; ++k) {
      const Plane& plane = world_.brushPlanes()[brush.firstPlane + k];
      Real lowest = std::numeric_limits<Real>::max();
      for (const Vec3& v : vFrom) lowest = std::min(lowest, plane.normal.dot(v) - plane.dist);
      const bool has = facts_.faceCovered(brush, k);
      allHave &= has;
      if (lowest >= 0) {
        anyEntry = true;
        entryHave &= has;
      }
    }
    return anyEntry ? entryHave : allHave;
  }

  void sweep(Ctx& c, const Shape& shape) const {
    // Some sweeps turn the trace model: a copy with a random orientation.
    std::optional<Shape> turned;
    if (!shape.trm.isPoint() && c.rng() % 100 < kRotatedSweepPercent) {
      turned = shape;
      turned->axis = randomRotation(c);
    }
    const Shape& s = turned ? *turned : shape;
    const std::optional<Vec3> start = freeStart(c, s);
    if (!start) {
      c.tally.noStart++;
      return;
    }
    c.tally.sweeps++;
    c.tally.rotatedSweeps += s.rotated();
    c.tally.pointSweeps += s.trm.isPoint();
    Vec3 end;
    if (c.rng() & 1) {
      end = randomIn(c, world_.bounds());
    } else {
      const Real r = uniform(c, 1, 512);
      end = *start + Vec3{uniform(c, -r, r), uniform(c, -r, r), uniform(c, -r, r)};
    }
    const TraceResult r = move(c, s, *start, end);
    if (!checkResult(c, s, *start, end, r)) return;
    if (r.fraction < 1) c.tally.hits++;
    if (isFree(c, s, r.endPos)) return;
    const Finding f = classify(c, s, *start, r.endPos);
    record(c, f, translationLine(s, *start, end) + contentsLine(s, r.endPos));
  }

  /// The contact normals a slide move stopped on, in order.
  struct SlidePlanes {
    Vec3 normals[kMaxSlidePlanes];
    int count = 0;
  };

  /// One slide move of the walker: up to kMaxSlidePlanes contacts per step,
  /// the velocity clipped along each (creases between two planes followed).
  /// False when a must-hold check failed.
  bool slideMove(Ctx& c, Vec3& pos, Vec3& vel, Real time, std::string& lastLine, Vec3& lastFrom,
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
  bool walkerStep(Ctx& c, Vec3& pos, Vec3& vel, const Vec3& wish, bool mayJump, StepInfo& info) const {
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

  /// How far the walker at `pos` moves along the horizontal unit `dir`, up
  /// to kRoomProbe: flat, or after going up kStepHeight (whichever is further).
  Real roomAlong(Ctx& c, const Vec3& pos, const Vec3& dir) const {
    const Real flat = move(c, walker_, pos, pos + dir * kRoomProbe).fraction * kRoomProbe;
    const TraceResult up = move(c, walker_, pos, pos + Vec3{0, 0, kStepHeight});
    const Real stepped = move(c, walker_, up.endPos, up.endPos + dir * kRoomProbe).fraction * kRoomProbe;
    return std::max(flat, stepped);
  }

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

  void walk(Ctx& c, int steps) const {
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

  const CollisionModel& world_;
  std::vector<Shape> shapes_;
  Shape walker_;
  const SoakOptions& o_;
  WorldFacts facts_;
  Bounds inner_;
};

Soak::Soak(const CollisionModel& world, std::vector<Shape> shapes, Shape walker, const SoakOptions& o)
    : impl_(std::make_unique<Impl>(world, std::move(shapes), std::move(walker), o)) {}
Soak::~Soak() = default;
std::size_t Soak::numClosedBrushes() const { return impl_->numClosedBrushes(); }
std::uint64_t Soak::numItems() const { return impl_->numItems(); }
void Soak::runItem(std::uint64_t item, QueryWork& work, ItemTally& tally, std::vector<Case>& cases) const {
  impl_->runItem(item, work, tally, cases);
}
std::string Soak::replay(const Shape& s, const Vec3& from, const Vec3& to, QueryWork& work) const {
  return impl_->replay(s, from, to, work);
}
StuckCause Soak::diagnoseStuck(const Vec3& pos, const Vec3& wish, QueryWork& work,
                               std::string* detail) const {
  return impl_->diagnoseStuck(pos, wish, work, detail);
}

}  // namespace cmkit::cli
