// The engine of `cmkit soak` (soak.h, soak_impl.h): sweeps, the checks and
// the classification of embedded ends (by the brush-face cover and overlap
// depths of soak_geometry.h); the walker is soak_walker.cpp's.
#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "cmkit/query.h"
#include "cmkit/tools/query_format.h"
#include "soak_impl.h"

namespace cmkit::cli {

namespace {

using soak_geometry::overlapDepth;
using soak_geometry::placedVertices;

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

void Soak::Impl::runItem(std::uint64_t item, QueryWork& work, ItemTally& tally, std::vector<Case>& cases) {
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

std::string Soak::Impl::replay(const Shape& s, const Vec3& from, const Vec3& to, QueryWork& work) const {
  ItemTally tally;
  std::vector<Case> cases;
  std::mt19937_64 rng(0);
  Ctx c{work, tally, cases, 0, rng};
  const TraceResult r = move(c, s, from, to);
  if (!checkResult(c, s, from, to, r)) return kFindingNames[std::size_t(cases.front().finding)];
  if (isFree(c, s, r.endPos)) return fmt::format("free (fraction {})", r.fraction);
  std::string detail;
  const Finding f = classify(c, s, from, r.endPos, &detail);
  return fmt::format("{} (fraction {}, end {}{}{})", kFindingNames[std::size_t(f)], r.fraction, vec(r.endPos),
                     detail.empty() ? "" : "; entered ", detail);
}

TraceResult Soak::Impl::move(Ctx& c, const Shape& s, const Vec3& from, const Vec3& to) const {
  TranslationQuery q;
  q.trm = s.query();
  q.trmAxis = s.axis;
  q.start = from;
  q.end = to;
  q.contentMask = o_.mask;
  return translate(world_, q, c.work);
}

ContentsQuery Soak::Impl::at(const Shape& s, const Vec3& pos) const {
  ContentsQuery q;
  q.trm = s.query();
  q.trmAxis = s.axis;
  q.position = pos;
  q.contentMask = o_.mask;
  return q;
}

bool Soak::Impl::isFree(Ctx& c, const Shape& s, const Vec3& pos) const {
  if (s.trm.isPoint()) return (pointContents(world_, {pos, {}}, c.work).contents & o_.mask) == 0;
  return (contentsTest(world_, at(s, pos), c.work).contents & o_.mask) == 0;
}

std::optional<Vec3> Soak::Impl::freeStart(Ctx& c, const Shape& s) const {
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

std::string Soak::Impl::axisField(const Shape& s) {
  if (!s.rotated()) return {};
  const Mat3& a = s.axis;
  return fmt::format(" trmaxis={},{},{}", vec(a[0]), vec(a[1]), vec(a[2]));
}

std::string Soak::Impl::translationLine(const Shape& s, const Vec3& from, const Vec3& to) const {
  return fmt::format("translation trm={}{} start={} end={} mask={}\n", s.spec, axisField(s), vec(from),
                     vec(to), o_.mask);
}

std::string Soak::Impl::contentsLine(const Shape& s, const Vec3& pos) const {
  return fmt::format("contents trm={}{} start={} mask={}\n", s.spec, axisField(s), vec(pos), o_.mask);
}

Mat3 Soak::Impl::randomRotation(Ctx& c) const {
  const double u1 = double(uniform(c, 0, 1)), u2 = double(uniform(c, 0, 1)), u3 = double(uniform(c, 0, 1));
  return rotationFromUniforms(u1, u2, u3);
}

void Soak::Impl::record(Ctx& c, Finding f, std::string lines) const {
  // Each thread keeps its first --examples cases per class; since it runs
  // its items in increasing order, the first ones overall are among them.
  if (++c.tally.counts[std::size_t(f)] <= o_.examples)
    c.cases.push_back({c.item, f, StuckCause::Unexplained, std::move(lines)});
}

void Soak::Impl::recordStuck(Ctx& c, StuckCause why, std::string lines) const {
  c.tally.counts[std::size_t(Finding::WalkerStuck)]++;
  if (++c.tally.stuckCauses[std::size_t(why)] <= o_.examples)
    c.cases.push_back({c.item, Finding::WalkerStuck, why, std::move(lines)});
}

bool Soak::Impl::checkResult(Ctx& c, const Shape& s, const Vec3& from, const Vec3& to,
                             const TraceResult& r) const {
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

Finding Soak::Impl::classify(Ctx& c, const Shape& s, const Vec3& from, const Vec3& end,
                             std::string* detail) const {
  const std::vector<Vec3> vEnd = placedVertices(s, end);
  const std::vector<Vec3> vFrom = placedVertices(s, from);
  const Bounds bEnd = boundsOf(vEnd).expanded(1);
  // The brushes the end overlaps (exact separating-axis test) that the start did not.
  bool anyOpen = false, anyClosed = false, anyBare = false;
  for (std::size_t b = 0; b < world_.brushes().size(); ++b) {
    const CmBrush& brush = world_.brushes()[b];
    if (!(brush.contents & o_.mask) || !brush.bounds.intersects(bEnd)) continue;
    const double depth = overlapDepth(world_, brush, s, end);
    if (depth <= 0) continue;
    if (overlapDepth(world_, brush, s, from) > 0) continue;  // started inside it
    const EntryCover entry = entryCover(brush, vFrom);
    // Entered by any depth through a face without a polygon: nothing there
    // could stop the move, however deep or edge-on (before precision and
    // grazing, which would otherwise take such an end).
    anyBare |= entry.bare;
    if (depth <= kPrecisionDepth && !entry.bare) continue;
    (entry.closed ? anyClosed : anyOpen) = true;
    if (detail)
      *detail += fmt::format("{}brush {} depth {:.4f} {}", detail->empty() ? "" : ", ", b, depth,
                             entry.bare     ? "open (a face to cross has no polygon)"
                             : entry.closed ? "closed"
                                            : "open");
  }
  if (anyClosed) return Finding::ClosedBrush;
  if (anyBare) return Finding::BrushFace;
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

Soak::Impl::EntryCover Soak::Impl::entryCover(const CmBrush& brush, const std::vector<Vec3>& vFrom) const {
  bool anyEntry = false, allHave = true, entryHave = true, anyBare = false, entryBare = false;
  for (std::uint32_t k = 0; k < brush.numPlanes; ++k) {
    const Plane& plane = world_.brushPlanes()[brush.firstPlane + k];
    Real lowest = std::numeric_limits<Real>::max();
    for (const Vec3& v : vFrom) lowest = std::min(lowest, plane.normal.dot(v) - plane.dist);
    const bool has = facts_.faceCovered(brush, k), bare = facts_.faceBare(brush, k);
    allHave &= has;
    anyBare |= bare;
    if (lowest >= 0) {
      anyEntry = true;
      entryHave &= has;
      entryBare |= bare;
    }
  }
  return anyEntry ? EntryCover{entryHave, entryBare} : EntryCover{allHave, anyBare};
}

void Soak::Impl::sweep(Ctx& c, const Shape& shape) const {
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

Soak::Impl::Impl(ModelPtr world, std::vector<Shape> shapes, Shape walker, const SoakOptions& o)
    : worldModel_(std::move(world)),
      world_(*worldModel_),
      shapes_(std::move(shapes)),
      walker_(std::move(walker)),
      o_(o),
      facts_(world_, o.mask) {
  const Vec3 size = world_.bounds().max - world_.bounds().min;
  inner_ = world_.bounds().expanded(-std::min({size.x, size.y, size.z}) * 0.01f);
  if (walkerItems() == 0) return;
  Result<PlayerShape> player = PlayerShape::fromTraceModel(walker_.trm);
  if (!player) throw std::invalid_argument("cmkit soak: the walker: " + player.error().message);
  player->contentMask = o_.mask;
  player_ = std::move(*player);
  EntityDesc entity;
  entity.name = "worldspawn";
  entity.model = worldModel_;
  if (Result<EntityId> added = playerWorld_.addEntity(std::move(entity)); !added)
    throw std::invalid_argument("cmkit soak: the walker's world: " + added.error().message);
}

Soak::Soak(ModelPtr world, std::vector<Shape> shapes, Shape walker, const SoakOptions& o)
    : impl_(std::make_unique<Impl>(std::move(world), std::move(shapes), std::move(walker), o)) {}
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
