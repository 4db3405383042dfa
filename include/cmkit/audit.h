// audit.h: a map audit. Where can a player (movement.h) stand, starting at
// the map's player starts, and what is wrong with the places it reaches:
// falls out of the world, spots it cannot leave, moves that end inside
// solid, entities placed in solid and cracks in the level's shell.
//
// CONTRACT
// - Input: a World (world.h) and the SPOTS of its map (auditSpotsFromMap: the
//   player starts, monsters and items, which own no primitives and so are
//   not in the World). Units are map units; +z is up.
// - REACHABILITY: the standing positions of the player (PlayerShape::
//   standard(), MoveParams defaults) on a horizontal grid of
//   AuditOptions::grid units. A CELL is a key (round(x / grid),
//   round(y / grid), round(z / kAuditCellHeight)) and the first standing
//   position found in it. From every start (each player start, then each
//   AuditOptions::extraStarts) the player settles (falls to the ground);
//   from each cell it tries eight MOVES: running (move::kRunSpeed) towards
//   the centres of the eight neighbouring cells, each a few stepPlayer calls
//   of move::kTimeStep, then falling until it rests. Where a run gets less
//   than half a cell away (blocked), a crouched run and a running jump the
//   same way are tried too; where it drops (falls more than a step, or out
//   of the world), a running jump. Where a move comes to rest is a cell. The search
//   is breadth-first, level by level; a level's moves (one task per cell
//   and direction) run in parallel (AuditOptions::threads) and are merged in
//   a fixed order, so the report is the same at any thread count.
// - FINDINGS (AuditFinding; the kinds are AuditKind):
//     FallOut   a move from a reachable cell falls below the world's bounds,
//               leaves them, or falls for longer than a fall through the
//               world's height takes. Severity high.
//     Stuck     a reachable cell from which every move (runs, crouched runs,
//               jumps) ends within kAuditStuckFraction * grid of it. High.
//     Tunnel    a step of a move ended with the player inside solid (the
//               next step's position test found it in solid, or the move's
//               end overlaps solid). High when the player there overlaps a
//               brush deeper than 0.01 units (penetration()); low when it
//               overlaps polygons only (a one-sided patch).
//     Embedded  a spot's trace model overlaps solid where the map puts it
//               (a player start: lifted by up to tol::kPlayerMaxNudge it is
//               still in solid, as the player would be). Player starts high,
//               monsters medium, items low.
//     OpenShell a crack in the shell next to reachable space: from a cell, a
//               point ray (down through the floor, or across to a wall)
//               leaves the world's bounds while rays kAuditCrackProbe to
//               either side of it stop at a surface close by (so the gap is
//               narrower than 2 * kAuditCrackProbe: not a ledge or a
//               window). Rays are kAuditCrackSpacing apart: a crack wider
//               than that is always crossed. Severity medium.
//   Findings of a kind and severity closer than kAuditClusterRadius to one
//   already kept are merged into it (AuditFinding::merged counts them). Each list is
//   sorted by position (x, y, z); the report numbers them in the order
//   fallOuts, stuck, tunnels, embedded, openShells (AuditReport::numbered).
// - MOVERS (doors, lifts, moveable objects: isMoverClass) are ignored by
//   default, TRIGGERS (isTriggerClass) always: their contents are set to 0
//   for the audit and restored at the end, so auditWorld needs the World as its one writer (no other thread
//   may query it meanwhile). AuditOptions::ignoreMovers = false keeps them as placed.
// - COST: proportional to the reachable cells times the moves tried; lt4
//   (data/maps/lt4) takes the time docs/audit.md gives.
// - THREAD SAFETY: auditWorld writes the World (movers) before and after
//   the search; in between its workers only query it, each with its own
//   WorldQueryWork.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cmkit/map.h"
#include "cmkit/math.h"
#include "cmkit/result.h"
#include "cmkit/world.h"

namespace cmkit {

/// Height of a cell's z bucket (units): two standing positions at the same
/// x, y are at least a crouched player's height apart, more than this.
inline constexpr Real kAuditCellHeight = 32;
/// A cell is stuck when every move ends within this fraction of a grid step.
inline constexpr Real kAuditStuckFraction = Real(0.75);
/// Findings of one kind closer than this (units) are merged into one.
inline constexpr Real kAuditClusterRadius = 64;
/// Spacing (units) of the crack rays across a cell.
inline constexpr Real kAuditCrackSpacing = 1;
/// How far (units) to each side of a ray that escapes the rays that must stop
/// close by are cast: a crack is narrower than twice this.
inline constexpr Real kAuditCrackProbe = 8;
/// A side ray stops "close by" within this distance (units) of where the
/// escaping ray enters the surface's layer.
inline constexpr Real kAuditCrackDepth = 24;

/// What a finding is.
enum class AuditKind { FallOut, Stuck, Tunnel, Embedded, OpenShell };

/// How bad a finding is.
enum class AuditSeverity { Low, Medium, High };

/// "fallout", "stuck", "tunnel", "embedded", "open_shell".
std::string_view toString(AuditKind kind);
/// "low", "medium", "high".
std::string_view toString(AuditSeverity severity);

/// What a spot of the map is.
enum class AuditSpotKind {
  PlayerStart,  ///< info_player_start: the player's box
  Monster,      ///< monster_*, ai_*: a 32 x 32 x 64 box on its origin
  Item,         ///< item_*, weapon_*, ammo_*, moveable_*, ...: a 12-unit cube on its origin
};

/// An entity of the map without primitives whose position matters.
struct AuditSpot {
  AuditSpotKind kind = AuditSpotKind::Item;  ///< what it is
  Vec3 origin;                               ///< its `origin` key
  std::string name;                          ///< `name` key ("#N" without one)
  std::string className;                     ///< `classname` key
  std::int32_t mapEntity = -1;               ///< index into the map's entities
};

/// The spots of a map: every info_player_start, monster and item entity.
/// Class names are matched after any "prefix:" (The Dark Mod's "atdm:").
std::vector<AuditSpot> auditSpotsFromMap(const MapFile& map);

/// True for class names of entities that move (doors, lifts, movers,
/// moveable objects): func_door*, func_mover, func_plat, func_rotating,
/// func_elevator, func_pendulum, func_bobbing, func_moveable, moveable_*,
/// mover_*, and any name containing "door" (after any "prefix:").
bool isMoverClass(std::string_view className);

/// True for class names of triggers (trigger_*, after any "prefix:"): the
/// game never lets them block the player, whatever their materials say, so
/// the audit always leaves them out.
bool isTriggerClass(std::string_view className);

/// One finding.
struct AuditFinding {
  AuditKind kind = AuditKind::FallOut;           ///< what it is
  AuditSeverity severity = AuditSeverity::High;  ///< how bad
  Vec3 position;                                 ///< where (see AuditKind's notes in the contract)
  std::string what;                              ///< one line saying what was found
  /// How it was reached: the start, a few way points, the cell (empty for
  /// Embedded, which is not reached).
  std::vector<Vec3> path;
  int merged = 1;  ///< findings merged into this one (kAuditClusterRadius)
};

/// Options of auditWorld.
struct AuditOptions {
  Real grid = 16;                  ///< cell size (units), at least 4
  int threads = 1;                 ///< worker threads (at least 1)
  std::vector<Vec3> extraStarts;   ///< more starts (feet positions) beside the player starts
  bool ignoreMovers = true;        ///< movers ignored (true) or kept as placed
  bool openShells = true;          ///< look for cracks (the costliest check after the search)
  std::size_t maxCells = 4000000;  ///< the search stops at this many cells (AuditReport::truncated)
  /// Called on the calling thread between levels and checks: (work done,
  /// work known so far). May be empty.
  std::function<void(std::size_t, std::size_t)> progress;
};

/// A reachable cell: a standing position.
struct AuditCell {
  Vec3 position;          ///< the player's feet
  bool crouched = false;  ///< reached crouched
};

/// What auditWorld found.
struct AuditReport {
  std::vector<AuditCell> cells;          ///< the reachable cells, in the order found
  std::vector<Vec3> starts;              ///< where the search started (settled)
  std::vector<AuditFinding> fallOuts;    ///< AuditKind::FallOut
  std::vector<AuditFinding> stuck;       ///< AuditKind::Stuck
  std::vector<AuditFinding> tunnels;     ///< AuditKind::Tunnel
  std::vector<AuditFinding> embedded;    ///< AuditKind::Embedded
  std::vector<AuditFinding> openShells;  ///< AuditKind::OpenShell
  Bounds worldBounds;                    ///< the bounds of every colliding entity
  int moversIgnored = 0;                 ///< movers whose contents were set to 0
  int triggersIgnored = 0;               ///< triggers whose contents were set to 0
  bool truncated = false;                ///< the search stopped at AuditOptions::maxCells
  std::size_t movesTried = 0;            ///< moves run in the search

  /// Every finding in report order (fallOuts, stuck, tunnels, embedded,
  /// openShells): finding k is number k + 1 in pictures and text.
  std::vector<const AuditFinding*> numbered() const;
  /// True when a finding of high severity was found.
  bool hasHighSeverity() const;
};

/// Audits a world: reachability from the starts, then the findings (see the
/// contract). Error: a grid under 4 or not finite, threads under 1.
Result<AuditReport> auditWorld(World& world, std::span<const AuditSpot> spots,
                               const AuditOptions& options = {});

}  // namespace cmkit
