// The audit's crack rays (audit.h, OpenShell): from every reachable cell,
// point rays down through the floor and across to the walls near it. A ray
// that leaves the world's bounds where rays kAuditCrackProbe to both sides
// of it stop close by has found a crack narrower than the player.
#include <array>
#include <initializer_list>
#include <optional>

#include "audit/audit_impl.h"

namespace cmkit::audit_detail {

namespace {

/// Cells checked between progress reports.
constexpr std::size_t kShellChunk = 2048;
/// A wall is looked at when a ray from the cell meets it within this many
/// grid steps.
constexpr Real kWallReach = 2;
/// Where the down rays start, above the feet (units).
constexpr Real kDownRayLift = 4;
/// Heights of the across rays above the feet, as fractions of the shape's
/// height.
constexpr std::array<Real, 3> kAcrossHeights{Real(0.1), Real(0.5), Real(0.9)};

class CrackRays {
 public:
  CrackRays(const SearchContext& ctx, WorldQueryWork& work) : ctx_(ctx), work_(work) {
    const Vec3 size = ctx.bounds.max - ctx.bounds.min;
    far_ = size.length() + 16;
  }

  /// The first surface from `from` along `dir` within `length`, or none.
  WorldRayHit cast(const Vec3& from, const Vec3& dir, Real length) {
    RayCastQuery q;
    q.start = from;
    q.end = from + dir * length;
    q.contentMask = contents::kMaskSolid;
    return ctx_.world.castRay(q, work_);
  }

  /// Where an escaping ray from `q` is flanked: for the first of `sides`
  /// whose rays from q + side and q - side both stop close by (`close`), the
  /// middle of their two hit points; none when no side does.
  template <class Close>
  static std::optional<Vec3> between(const Vec3& q, std::initializer_list<Vec3> sides, const Close& close) {
    for (const Vec3& side : sides) {
      Vec3 a, b;
      if (close(q + side, a) && close(q - side, b)) return (a + b) * Real(0.5);
    }
    return std::nullopt;
  }

  /// A crack under the cell's square: a down ray that escapes between two
  /// that meet the floor.
  std::optional<RawFinding> down(const SearchCell& cell, std::int32_t id) {
    const Vec3 centre = cellCentre(cell.position, ctx_.grid);
    const Real half = ctx_.grid / 2;
    const int n = std::max(1, int(ctx_.grid / kAuditCrackSpacing));
    const Real top = cell.position.z + kDownRayLift;
    const Real length = top - ctx_.bounds.min.z + 16;
    const Vec3 downDir{0, 0, -1};
    auto close = [&](const Vec3& from, Vec3& hitPoint) {
      const WorldRayHit r = cast(from, downDir, length);
      if (!r.hit.hit() || r.hit.point.z < cell.position.z - kAuditCrackDepth) return false;
      hitPoint = r.hit.point;
      return true;
    };
    for (int iy = 0; iy < n; ++iy)
      for (int ix = 0; ix < n; ++ix) {
        const Vec3 q{centre.x - half + (Real(ix) + Real(0.5)) * kAuditCrackSpacing,
                     centre.y - half + (Real(iy) + Real(0.5)) * kAuditCrackSpacing, top};
        if (cast(q, downDir, length).hit.hit()) continue;
        if (const auto at = between(q, {Vec3{kAuditCrackProbe, 0, 0}, Vec3{0, kAuditCrackProbe, 0}}, close))
          return RawFinding{AuditKind::OpenShell, AuditSeverity::Medium, *at,
                            "a point falls through a crack in the floor out of the world (under " +
                                pointText(cell.position) + ")",
                            id};
      }
    return std::nullopt;
  }

  /// A crack in a wall near the cell: an across ray that escapes between
  /// two that meet the wall.
  std::optional<RawFinding> across(const SearchCell& cell, std::int32_t id) {
    const Vec3 centre = cellCentre(cell.position, ctx_.grid);
    const Real half = ctx_.grid / 2;
    const int n = std::max(1, int(ctx_.grid / kAuditCrackSpacing));
    const Real height = (cell.crouched ? ctx_.shape.crouched : ctx_.shape.standing).bounds().max.z;
    for (const Vec3& dir : {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{-1, 0, 0}, Vec3{0, -1, 0}}) {
      const Vec3 perp{-dir.y, dir.x, 0};
      const Vec3 mid = cell.position + Vec3{0, 0, height / 2};
      const WorldRayHit wall = cast(mid, dir, kWallReach * ctx_.grid);
      if (!wall.hit.hit()) continue;
      const Real reach = (wall.hit.point - mid).length() + ctx_.grid + kAuditCrackDepth;
      auto close = [&](const Vec3& from, Vec3& hitPoint) {
        const WorldRayHit r = cast(from, dir, reach);
        if (!r.hit.hit()) return false;
        hitPoint = r.hit.point;
        return true;
      };
      for (Real f : kAcrossHeights)
        for (int k = 0; k < n; ++k) {
          const Real offset = -half + (Real(k) + Real(0.5)) * kAuditCrackSpacing;
          const Vec3 q = Vec3{centre.x, centre.y, cell.position.z + f * height} + perp * offset;
          if (cast(q, dir, far_).hit.hit()) continue;
          if (const auto at = between(q, {perp * kAuditCrackProbe, Vec3{0, 0, kAuditCrackProbe}}, close))
            return RawFinding{AuditKind::OpenShell, AuditSeverity::Medium, *at,
                              "a point passes through a crack in a wall out of the world (from " +
                                  pointText(cell.position) + ")",
                              id};
        }
    }
    return std::nullopt;
  }

 private:
  const SearchContext& ctx_;
  WorldQueryWork& work_;
  Real far_ = 0;
};

}  // namespace

std::vector<RawFinding> findOpenShells(const SearchContext& ctx, const std::vector<SearchCell>& cells,
                                       const std::function<void(std::size_t)>& done) {
  std::vector<std::array<std::optional<RawFinding>, 2>> found(cells.size());
  for (std::size_t first = 0; first < cells.size(); first += kShellChunk) {
    const std::size_t count = std::min(kShellChunk, cells.size() - first);
    parallelFor(count, ctx.threads, [&](std::size_t i, WorldQueryWork& work) {
      const std::size_t c = first + i;
      CrackRays rays(ctx, work);
      found[c][0] = rays.down(cells[c], std::int32_t(c));
      found[c][1] = rays.across(cells[c], std::int32_t(c));
    });
    if (done) done(first + count);
  }
  std::vector<RawFinding> out;
  for (auto& pair : found)
    for (auto& f : pair)
      if (f) out.push_back(std::move(*f));
  return out;
}

}  // namespace cmkit::audit_detail
