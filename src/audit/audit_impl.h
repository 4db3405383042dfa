// Internal to the audit (cmkit/audit.h): what its steps share. audit.cpp
// runs them: the reachability search (audit_reach.cpp), the spots' position
// tests (audit_spots.cpp) and the crack rays (audit_shells.cpp).
#pragma once

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "cmkit/audit.h"
#include "cmkit/movement.h"
#include "cmkit/world.h"

namespace cmkit::audit_detail {

/// A finding before merging: its kind, where, what, and the cell it came
/// from (-1: none, e.g. an embedded spot).
struct RawFinding {
  AuditKind kind = AuditKind::FallOut;
  AuditSeverity severity = AuditSeverity::High;
  Vec3 position;
  std::string what;
  std::int32_t cell = -1;
};

/// A cell of the search: its standing state and how it was reached.
struct SearchCell {
  Vec3 position;             ///< the feet, at rest
  bool crouched = false;     ///< came to rest crouched
  std::int32_t parent = -1;  ///< the cell moved from; -1 for a start
  std::int32_t start = -1;   ///< index into the starts
};

/// What the search shares with the checks.
struct SearchContext {
  const World& world;
  PlayerShape shape;
  Bounds bounds;  ///< the world's bounds
  Real grid = 16;
  int threads = 1;
};

/// The search's output.
struct SearchResult {
  std::vector<SearchCell> cells;
  std::vector<Vec3> starts;
  std::vector<RawFinding> findings;  ///< fall-outs, stuck cells, tunnels
  std::size_t movesTried = 0;
  bool truncated = false;
};

/// The breadth-first search from the starts (audit_reach.cpp).
SearchResult searchReachable(const SearchContext& ctx, const std::vector<Vec3>& starts, std::size_t maxCells,
                             const std::function<void(std::size_t, std::size_t)>& progress);

/// Position tests of the spots (audit_spots.cpp).
std::vector<RawFinding> findEmbedded(const World& world, std::span<const AuditSpot> spots);

/// Crack rays from every cell (audit_shells.cpp); `done` is called with the
/// cells checked so far.
std::vector<RawFinding> findOpenShells(const SearchContext& ctx, const std::vector<SearchCell>& cells,
                                       const std::function<void(std::size_t)>& done);

/// "(x y z)" with one decimal, for the findings' text.
inline std::string pointText(const Vec3& p) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.1f %.1f %.1f)", double(p.x), double(p.y), double(p.z));
  return buf;
}

/// The centre of the grid square a point is in (z kept).
inline Vec3 cellCentre(const Vec3& p, Real grid) {
  return {std::floor(p.x / grid + Real(0.5)) * grid, std::floor(p.y / grid + Real(0.5)) * grid, p.z};
}

/// Runs fn(i, work) for i in [0, n) on `threads` workers, each with its own
/// WorldQueryWork; items are handed out one at a time, so fn must write
/// only its own item's output.
inline void parallelFor(std::size_t n, int threads,
                        const std::function<void(std::size_t, WorldQueryWork&)>& fn) {
  const std::size_t workers =
      std::min<std::size_t>(std::size_t(std::max(threads, 1)), std::max<std::size_t>(n, 1));
  std::atomic<std::size_t> next{0};
  auto run = [&] {
    WorldQueryWork work;
    for (std::size_t i = next++; i < n; i = next++) fn(i, work);
  };
  if (workers <= 1) {
    run();
    return;
  }
  std::vector<std::thread> pool;
  for (std::size_t t = 1; t < workers; ++t) pool.emplace_back(run);
  run();
  for (std::thread& t : pool) t.join();
}

}  // namespace cmkit::audit_detail
