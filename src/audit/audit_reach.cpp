// The audit's reachability search (audit.h, "REACHABILITY"): cells of
// standing positions, found breadth-first by running the player
// (movement.h) from each cell towards its eight neighbours.
#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <unordered_map>

#include "audit/audit_impl.h"

namespace cmkit::audit_detail {

namespace {

/// A cell's key: the grid square and the z bucket.
struct CellKey {
  std::int32_t x = 0, y = 0, z = 0;
  bool operator==(const CellKey&) const = default;
};

struct CellKeyHash {
  std::size_t operator()(const CellKey& k) const {
    std::uint64_t h = std::uint64_t(std::uint32_t(k.x)) * 0x9E3779B97F4A7C15ull;
    h ^= std::uint64_t(std::uint32_t(k.y)) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
    h ^= std::uint64_t(std::uint32_t(k.z)) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
    return std::size_t(h);
  }
};

CellKey keyOf(const Vec3& p, Real grid) {
  return {std::int32_t(std::floor(p.x / grid + Real(0.5))), std::int32_t(std::floor(p.y / grid + Real(0.5))),
          std::int32_t(std::floor(p.z / kAuditCellHeight + Real(0.5)))};
}

/// The eight directions, in the order tried.
constexpr std::array<std::array<int, 2>, 8> kDirections{
    {{1, 0}, {1, 1}, {0, 1}, {-1, 1}, {-1, 0}, {-1, -1}, {0, -1}, {1, -1}}};

/// A player at rest moved less than this (units) in a step...
constexpr Real kRestDistance = Real(0.01);
/// ...this many steps running is at rest (wedged where no ground holds it).
constexpr int kRestSteps = 3;
/// Extra time (s) a fall may take beyond a fall through the world's height.
constexpr Real kFallSlack = 1;
/// A run that gets less than this fraction of a grid step away was blocked.
constexpr Real kBlockedFraction = Real(0.5);

/// A tunnel's end overlapping a brush by at most this (units) is a precision
/// case, not a brush entered (the soak's kPrecisionDepth).
constexpr Real kTunnelDepth = Real(0.01);
/// How far (units) around a start in solid a free start is looked for.
constexpr Real kStartSearchRadius = 64;

enum class MoveMode { Run, Crouch, Jump };

/// How one move ended.
struct MoveEnd {
  Vec3 position;                ///< where it came to rest
  bool crouched = false;        ///< crouched at rest
  bool fellOut = false;         ///< left the world (fallOutAt)
  Vec3 fallOutAt;               ///< where it was when it left
  bool tunnel = false;          ///< a step ended in solid (tunnelAt)
  Vec3 tunnelAt;                ///< that step's end
  bool tunnelCrouched = false;  ///< the player was crouched at tunnelAt
  bool tunnelBrush = false;     ///< tunnelAt overlaps a brush (not polygons only)
  bool usable() const { return !fellOut && !tunnel; }
};

/// What the moves from one cell found.
struct CellMoves {
  std::vector<MoveEnd> ends;  ///< every move's end, in the order run
  bool stuck = false;
};

class Mover {
 public:
  explicit Mover(const SearchContext& ctx) : ctx_(ctx) {
    const Real height = ctx.bounds.max.z - ctx.bounds.min.z + 64;
    const Real fallTime = std::sqrt(2 * height / move::kGravity) + kFallSlack;
    maxAirSteps_ = int(std::ceil(fallTime / move::kTimeStep));
    inside_ = ctx.bounds.expanded(1);
  }

  /// The player at `from` settles: falls until it rests (a start).
  MoveEnd settle(const Vec3& from, WorldQueryWork& work) const {
    PlayerState s;
    s.origin = from;
    MoveEnd end;
    fall(s, PlayerInput{}, end, work, true);
    return end;
  }

  /// A move from a cell towards `target` (feet height ignored).
  MoveEnd run(const SearchCell& cell, const Vec3& target, MoveMode mode, WorldQueryWork& work) const {
    PlayerState s;
    s.origin = cell.position;
    s.crouched = cell.crouched;
    Vec3 wish{target.x - cell.position.x, target.y - cell.position.y, 0};
    const Real dist = wish.normalize();
    PlayerInput input;
    input.wishDir = wish;
    input.run = true;
    input.crouch = mode == MoveMode::Crouch;
    input.jump = mode == MoveMode::Jump;
    const Real speed = (input.crouch || cell.crouched) ? move::kCrouchSpeed : move::kRunSpeed;
    s.velocity = wish * speed;
    MoveEnd end;
    if (mode == MoveMode::Jump) {
      fall(s, input, end, work, false);
      return end;
    }
    const int steps = std::max(1, int(std::ceil(dist / (speed * move::kTimeStep))));
    for (int i = 0; i < steps; ++i)
      if (!step(s, input, end, work)) return end;
    PlayerInput still;
    still.crouch = input.crouch;
    if (s.onGround) {
      finish(s, end, work);
      return end;
    }
    fall(s, still, end, work, false);
    return end;
  }

  /// Whether the player (crouched or standing) at `at` overlaps a brush of some entity
  /// deeper than kTunnelDepth (penetration(), brushes only), rather than
  /// polygons only (a patch, one-sided, that the move crossed or touched).
  bool overlapsBrush(const Vec3& at, bool crouched, WorldQueryWork& work) const {
    const TraceModel& trm = crouched ? ctx_.shape.crouched : ctx_.shape.standing;
    const Bounds box = trm.bounds().translated(at).expanded(1);
    for (EntityId id : ctx_.world.entityIds()) {
      const WorldEntity* e = ctx_.world.entity(id);
      if ((e->contents & ctx_.shape.contentMask) == 0 || !e->bounds.intersects(box)) continue;
      PenetrationQuery q;
      q.trm = &trm;
      q.position = at;
      q.contentMask = ctx_.shape.contentMask;
      q.placement = e->placement;
      const PenetrationResult r = penetration(*e->model, q, work.modelWork());
      if (r.stuck && r.depth > kTunnelDepth) return true;
    }
    return false;
  }

 private:
  /// One step; false when the move ended (out of the world, or a tunnel).
  bool step(PlayerState& s, const PlayerInput& input, MoveEnd& end, WorldQueryWork& work) const {
    const Vec3 was = s.origin;
    const bool wasCrouched = s.crouched;
    const std::int64_t before = s.steps;
    s = stepPlayer(ctx_.world, ctx_.shape, s, input, move::kTimeStep, work);
    // The step's position test found the last step's end in solid.
    if ((s.nudged || s.stuck) && before > 0) {
      end.tunnel = true;
      end.tunnelAt = was;
      end.tunnelCrouched = wasCrouched;
      end.position = was;
      return false;
    }
    if (!inside_.containsPoint(s.origin)) {
      end.fellOut = true;
      end.fallOutAt = s.origin;
      end.position = s.origin;
      return false;
    }
    return true;
  }

  /// Runs with `input` (the jump press only on the first step) until the
  /// player is on the ground, rests, or leaves the world.
  void fall(PlayerState& s, PlayerInput input, MoveEnd& end, WorldQueryWork& work, bool start) const {
    int resting = 0;
    for (int i = 0; i < maxAirSteps_; ++i) {
      const Vec3 was = s.origin;
      if (start && i == 0) {
        // A start may be in solid: stepPlayer lifts it or says it is stuck.
        s = stepPlayer(ctx_.world, ctx_.shape, s, input, move::kTimeStep, work);
        if (s.stuck) {
          end.tunnel = true;
          end.tunnelAt = was;
          end.position = was;
          return;
        }
      } else if (!step(s, input, end, work)) {
        return;
      }
      input.jump = false;
      if (s.onGround && !s.jumped) break;
      resting = (s.origin - was).length() < kRestDistance ? resting + 1 : 0;
      if (resting >= kRestSteps) break;
      if (i + 1 == maxAirSteps_) {
        end.fellOut = true;
        end.fallOutAt = s.origin;
        end.position = s.origin;
        return;
      }
    }
    finish(s, end, work);
  }

  /// The move's end: at rest where it is, unless that overlaps solid.
  void finish(const PlayerState& s, MoveEnd& end, WorldQueryWork& work) const {
    ContentsQuery q;
    q.trm = &playerTraceModel(ctx_.shape, s);
    q.position = s.origin;
    q.contentMask = ctx_.shape.contentMask;
    if (ctx_.world.contentsTest(q, work).result.contents != 0) {
      end.tunnel = true;
      end.tunnelAt = s.origin;
      end.tunnelCrouched = s.crouched;
    }
    end.position = s.origin;
    end.crouched = s.crouched;
  }

  const SearchContext& ctx_;
  int maxAirSteps_ = 0;
  Bounds inside_;
};

/// The moves of a cell in one direction (the contract's order: a run, then
/// when blocked a crouched run and a jump, when it dropped a jump).
std::vector<MoveEnd> movesToward(const Mover& mover, const SearchCell& cell, int direction, Real grid,
                                 WorldQueryWork& work) {
  std::vector<MoveEnd> out;
  auto classified = [&](MoveEnd e) {
    if (e.tunnel) e.tunnelBrush = mover.overlapsBrush(e.tunnelAt, e.tunnelCrouched, work);
    return e;
  };
  const Vec3 centre = cellCentre(cell.position, grid);
  const auto& d = kDirections[std::size_t(direction)];
  const Vec3 target{centre.x + Real(d[0]) * grid, centre.y + Real(d[1]) * grid, cell.position.z};
  MoveEnd e = classified(mover.run(cell, target, MoveMode::Run, work));
  const Vec3 moved = e.position - cell.position;
  const bool blocked = e.usable() && Vec3{moved.x, moved.y, 0}.length() < kBlockedFraction * grid;
  // Dropped: it fell (more than a step) or out of the world: a jump may
  // clear the gap.
  const bool dropped = e.fellOut || (e.usable() && moved.z < -move::kStepHeight);
  out.push_back(e);
  if (blocked || cell.crouched) out.push_back(classified(mover.run(cell, target, MoveMode::Crouch, work)));
  if (blocked || cell.crouched || dropped)
    out.push_back(classified(mover.run(cell, target, MoveMode::Jump, work)));
  return out;
}

/// A cell's moves, all directions in order, and whether it is stuck.
CellMoves gather(const SearchCell& cell, std::span<std::vector<MoveEnd>> byDirection, Real grid) {
  CellMoves out;
  for (std::vector<MoveEnd>& ends : byDirection)
    for (MoveEnd& e : ends) out.ends.push_back(std::move(e));
  const Real stuckRadius = kAuditStuckFraction * grid;
  bool leaves = false;
  for (const MoveEnd& e : out.ends)
    if (e.fellOut || (e.usable() && (e.position - cell.position).length() >= stuckRadius)) leaves = true;
  out.stuck = !leaves;
  return out;
}

}  // namespace

SearchResult searchReachable(const SearchContext& ctx, const std::vector<Vec3>& starts, std::size_t maxCells,
                             const std::function<void(std::size_t, std::size_t)>& progress) {
  SearchResult out;
  const Mover mover(ctx);
  std::unordered_map<CellKey, std::int32_t, CellKeyHash> index;
  std::vector<std::int32_t> frontier;
  auto addCell = [&](const MoveEnd& e, std::int32_t parent, std::int32_t start) {
    const CellKey key = keyOf(e.position, ctx.grid);
    if (index.count(key) != 0 || out.cells.size() >= maxCells) {
      out.truncated = out.truncated || (index.count(key) == 0);
      return;
    }
    const auto id = std::int32_t(out.cells.size());
    index.emplace(key, id);
    out.cells.push_back({e.position, e.crouched, parent, start});
    frontier.push_back(id);
  };

  // The starts, settled one by one.
  {
    WorldQueryWork work;
    for (std::size_t i = 0; i < starts.size(); ++i) {
      MoveEnd e = mover.settle(starts[i], work);
      // A start in solid (an Embedded finding of its own) still starts the
      // search: from the nearest free place around it.
      for (Real r = 1; e.tunnel && r <= kStartSearchRadius; r *= 2)
        for (const auto& d : kDirections) {
          e = mover.settle(starts[i] + Vec3{Real(d[0]) * r, Real(d[1]) * r, 0}, work);
          if (!e.tunnel) break;
        }
      out.starts.push_back(e.position);
      if (e.fellOut) {
        out.findings.push_back(
            {AuditKind::FallOut, AuditSeverity::High, starts[i],
             "the player falls out of the world from a start, leaving it at " + pointText(e.fallOutAt), -1});
        continue;
      }
      if (!e.tunnel) addCell(e, -1, std::int32_t(i));
    }
  }

  // Level by level: the frontier's moves in parallel, merged in order.
  std::size_t done = 0;
  while (!frontier.empty()) {
    const std::vector<std::int32_t> level = std::move(frontier);
    frontier.clear();
    // One task per cell and direction: small levels still keep every
    // worker busy.
    const std::vector<SearchCell>& cells = out.cells;
    constexpr std::size_t kDirs = kDirections.size();
    std::vector<std::vector<MoveEnd>> byTask(level.size() * kDirs);
    parallelFor(byTask.size(), ctx.threads, [&](std::size_t t, WorldQueryWork& work) {
      byTask[t] = movesToward(mover, cells[std::size_t(level[t / kDirs])], int(t % kDirs), ctx.grid, work);
    });
    std::vector<CellMoves> moves(level.size());
    for (std::size_t i = 0; i < level.size(); ++i)
      moves[i] = gather(cells[std::size_t(level[i])], std::span(byTask).subspan(i * kDirs, kDirs), ctx.grid);
    for (std::size_t i = 0; i < level.size(); ++i) {
      const std::int32_t id = level[i];
      const SearchCell cell = out.cells[std::size_t(id)];
      const CellMoves& m = moves[i];
      out.movesTried += m.ends.size();
      bool fellOut = false, tunnel = false;
      for (const MoveEnd& e : m.ends) {
        if (e.fellOut && !fellOut) {
          fellOut = true;
          out.findings.push_back(
              {AuditKind::FallOut, AuditSeverity::High, cell.position,
               "the player falls out of the world from here, leaving its bounds at " + pointText(e.fallOutAt),
               id});
        }
        if (e.tunnel && !tunnel) {
          tunnel = true;
          out.findings.push_back(
              {AuditKind::Tunnel, e.tunnelBrush ? AuditSeverity::High : AuditSeverity::Low, e.tunnelAt,
               "a move from " + pointText(cell.position) + " ended a step inside " +
                   (e.tunnelBrush ? std::string("a brush")
                                  : std::string("polygons only (a one-sided patch or polygon, no brush)")) +
                   (e.tunnelCrouched ? ", crouched" : ""),
               id});
        }
        if (e.usable()) addCell(e, id, cell.start);
      }
      if (m.stuck)
        out.findings.push_back({AuditKind::Stuck, AuditSeverity::High, cell.position,
                                "no run, crouched run or jump gets " +
                                    std::to_string(int(kAuditStuckFraction * ctx.grid)) +
                                    " units away from here",
                                id});
    }
    done += level.size();
    if (progress) progress(done, out.cells.size());
  }
  return out;
}

}  // namespace cmkit::audit_detail
