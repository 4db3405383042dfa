// auditWorld (audit.h): movers off, the search, the checks, the findings
// merged, sorted and given their paths; movers back as they were.
#include <algorithm>
#include <cmath>

#include "audit/audit_impl.h"

namespace cmkit {

namespace {

using audit_detail::RawFinding;
using audit_detail::SearchCell;

/// Way points of a finding's path between its start and its cell.
constexpr int kPathWayPoints = 4;

/// The start, up to kPathWayPoints cells along the way, and the cell.
std::vector<Vec3> pathTo(const std::vector<SearchCell>& cells, const std::vector<Vec3>& starts,
                         std::int32_t cell) {
  if (cell < 0) return {};
  std::vector<std::int32_t> chain;
  for (std::int32_t c = cell; c >= 0; c = cells[std::size_t(c)].parent) chain.push_back(c);
  std::reverse(chain.begin(), chain.end());
  std::vector<Vec3> out;
  const std::int32_t start = cells[std::size_t(chain.front())].start;
  if (start >= 0 && std::size_t(start) < starts.size()) out.push_back(starts[std::size_t(start)]);
  const std::size_t n = chain.size();
  for (int k = 1; k <= kPathWayPoints; ++k) {
    const std::size_t i = n * std::size_t(k) / std::size_t(kPathWayPoints + 1);
    if (i > 0 && i + 1 < n) out.push_back(cells[std::size_t(chain[i])].position);
  }
  out.push_back(cells[std::size_t(cell)].position);
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

bool positionLess(const Vec3& a, const Vec3& b) {
  if (a.x != b.x) return a.x < b.x;
  if (a.y != b.y) return a.y < b.y;
  return a.z < b.z;
}

/// One kind's findings: sorted by position, merged within
/// kAuditClusterRadius, each with its path.
std::vector<AuditFinding> merge(std::vector<RawFinding> raw, const audit_detail::SearchResult& search) {
  std::stable_sort(raw.begin(), raw.end(), [](const RawFinding& a, const RawFinding& b) {
    return positionLess(a.position, b.position);
  });
  std::vector<AuditFinding> out;
  for (RawFinding& r : raw) {
    auto near = std::find_if(out.begin(), out.end(), [&](const AuditFinding& f) {
      return f.severity == r.severity && (f.position - r.position).length() < kAuditClusterRadius;
    });
    if (near != out.end()) {
      ++near->merged;
      continue;
    }
    AuditFinding f;
    f.kind = r.kind;
    f.severity = r.severity;
    f.position = r.position;
    f.what = std::move(r.what);
    f.path = pathTo(search.cells, search.starts, r.cell);
    out.push_back(std::move(f));
  }
  return out;
}

/// The union of the bounds of every entity that collides.
Bounds worldBounds(const World& world) {
  Bounds b;
  for (EntityId id : world.entityIds()) {
    const WorldEntity* e = world.entity(id);
    if (e->contents != 0) b.addBounds(e->bounds);
  }
  return b;
}

}  // namespace

std::vector<const AuditFinding*> AuditReport::numbered() const {
  std::vector<const AuditFinding*> out;
  for (const auto* list : {&fallOuts, &stuck, &tunnels, &embedded, &openShells})
    for (const AuditFinding& f : *list) out.push_back(&f);
  return out;
}

bool AuditReport::hasHighSeverity() const {
  for (const AuditFinding* f : numbered())
    if (f->severity == AuditSeverity::High) return true;
  return false;
}

Result<AuditReport> auditWorld(World& world, std::span<const AuditSpot> spots, const AuditOptions& options) {
  if (!(options.grid >= 4) || !std::isfinite(options.grid))
    return Error("audit: the grid must be a finite number of at least 4 units");
  if (options.threads < 1) return Error("audit: at least one thread");
  for (const Vec3& s : options.extraStarts)
    if (!s.isFinite()) return Error("audit: a start that is not finite");

  AuditReport report;
  // Movers (by default) and triggers off for the audit (restored below).
  std::vector<std::pair<EntityId, std::uint32_t>> movers;
  for (EntityId id : world.entityIds()) {
    const WorldEntity* e = world.entity(id);
    if (id == kWorldspawnEntity || e->contents == 0) continue;
    if (isTriggerClass(e->className)) {
      ++report.triggersIgnored;
      movers.emplace_back(id, e->contents);
    } else if (options.ignoreMovers && isMoverClass(e->className)) {
      ++report.moversIgnored;
      movers.emplace_back(id, e->contents);
    }
  }
  for (const auto& [id, c] : movers) (void)world.setContents(id, 0);
  report.worldBounds = worldBounds(world);

  const World& w = world;
  audit_detail::SearchContext ctx{w, PlayerShape::standard(), report.worldBounds, options.grid,
                                  options.threads};
  std::vector<Vec3> starts;
  for (const AuditSpot& s : spots)
    if (s.kind == AuditSpotKind::PlayerStart) starts.push_back(s.origin);
  starts.insert(starts.end(), options.extraStarts.begin(), options.extraStarts.end());

  // Progress: the search's cells, then the crack rays' (counted again).
  std::size_t searched = 0;
  audit_detail::SearchResult search;
  if (!report.worldBounds.isCleared())
    search = audit_detail::searchReachable(
        ctx, starts, options.maxCells, [&](std::size_t done, std::size_t known) {
          searched = done;
          if (options.progress) options.progress(done, known + (options.openShells ? known : 0));
        });
  std::vector<RawFinding> shells;
  if (options.openShells && !search.cells.empty())
    shells = audit_detail::findOpenShells(ctx, search.cells, [&](std::size_t done) {
      if (options.progress) options.progress(searched + done, 2 * search.cells.size());
    });
  std::vector<RawFinding> embedded = audit_detail::findEmbedded(w, spots);

  std::vector<RawFinding> byKind[5];
  for (RawFinding& f : search.findings) byKind[int(f.kind)].push_back(std::move(f));
  report.fallOuts = merge(std::move(byKind[int(AuditKind::FallOut)]), search);
  report.stuck = merge(std::move(byKind[int(AuditKind::Stuck)]), search);
  report.tunnels = merge(std::move(byKind[int(AuditKind::Tunnel)]), search);
  report.embedded = merge(std::move(embedded), search);
  report.openShells = merge(std::move(shells), search);
  report.cells.reserve(search.cells.size());
  for (const SearchCell& c : search.cells) report.cells.push_back({c.position, c.crouched});
  report.starts = std::move(search.starts);
  report.truncated = search.truncated;
  report.movesTried = search.movesTried;

  for (const auto& [id, c] : movers) (void)world.setContents(id, c);
  return report;
}

}  // namespace cmkit
