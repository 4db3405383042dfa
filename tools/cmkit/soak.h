// soak.h: the engine of `cmkit soak` (random sweeps of every trace-model
// kind and a walker, the library's player (movement.h), through the world
// model, every end checked with a position test and every embedded end
// classified; docs/reliability.md).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "cmkit/query.h"

namespace cmkit::cli {

/// Example cases printed per class unless --examples says otherwise.
inline constexpr std::size_t kExamplesDefault = 3;

inline const char* const kDefaultTrms[] = {
    "point",
    "box:-16,-16,0,16,16,72",
    "cylinder:8:-16,-16,0,16,16,72",
    "cone:6:-12,-12,0,12,12,40",
    "octahedron:-16,-16,-16,16,16,16",
    "dodecahedron:-16,-16,-16,16,16,16",
    "bone:48,12",
    "polygon:-16,-16,0;16,-16,0;16,16,0;-16,16,0",
    "polygonvolume:8:-16,-16,8;16,-16,8;16,16,8;-16,16,8",
};
inline constexpr const char* kWalkerTrm = "box:-16,-16,0,16,16,72";

/// What a check found. The first two must never happen (exit 1).
enum class Finding : std::uint8_t {
  NonFinite,       // a result with a nan or inf
  FractionRange,   // fraction outside [0, 1]
  BrushFace,       // (a) end in a brush with a face not (wholly) covered by polygons
  PatchBehind,     // (b) end overlaps only polygons, one crossed from behind
  Grazing,         // (c) the move is edge-on to the plane it must leave by
  Precision,       // (d) penetration <= kPrecisionDepth
  ClosedBrush,     // (e) end in a closed brush the move started outside of
  OtherPolygon,    // end overlaps only polygons, none crossed from behind
  WalkerEmbedded,  // a translation of a walker step ended in solid
  WalkerStuck,     // a walker made no progress for kStuckSteps steps
  Count
};
inline constexpr std::size_t kNumFindings = std::size_t(Finding::Count);
inline const char* const kFindingNames[kNumFindings] = {
    "non-finite", "fraction-range", "brush-face",    "patch-behind",    "grazing",
    "precision",  "closed-brush",   "other-polygon", "walker-embedded", "walker-stuck"};
inline const char* const kFindingMeaning[kNumFindings] = {
    "a result with nan or inf (must not happen)",
    "fraction outside [0,1] (must not happen)",
    "(a) end in a brush; a face the move crossed is not wholly covered by polygons",
    "(b) end overlaps only polygons; the move crossed one from behind (one-sided)",
    "(c) the move is edge-on to the plane it must leave the brush by",
    "(d) penetration <= 0.01 units",
    "(e) end in a brush whose faces the move crossed are all covered by polygons",
    "end overlaps only polygons, none crossed from behind",
    "a translation of a walker step ended in solid",
    "walker made no progress",
};

/// Why a walker made no progress (the class of a walker-stuck case; soak.cpp,
/// diagnoseStuck). Unexplained first: its cases are printed first.
enum class StuckCause : std::uint8_t {
  Unexplained,  // none of the below: would hint at a query fault
  Cornered,     // the walk's: contact planes clipped the velocity to ~0 for most steps
  NoRoom,       // the map's: the box cannot move 1 unit in any of 8 horizontal directions
  Pressing,     // the walk's: the wish within kPressingDegrees of a wall's normal (it creeps)
  Count
};
inline constexpr std::size_t kNumStuckCauses = std::size_t(StuckCause::Count);
inline const char* const kStuckCauseNames[kNumStuckCauses] = {"unexplained", "cornered", "no-room",
                                                              "pressing"};
inline const char* const kStuckCauseMeaning[kNumStuckCauses] = {
    "none below: the steps moved the box, yet it made no progress (a query fault?)",
    ("the walk's: for at least half of the steps the slide planes clipped the velocity to ~0 "
     "(a corner or crease), though another direction has room"),
    "the map's: the box cannot move 1 unit in any of 8 horizontal directions, flat or 16 up",
    ("the walk's: the wish is within 3 degrees of the normal of the wall that stops it; friction "
     "takes what each step adds along the wall, and it creeps (under 2 units a second)"),
};

struct SoakOptions {
  std::string map;
  std::string materials;
  std::vector<std::string> trms;
  std::vector<std::string> failOn;
  std::uint64_t sweeps = 100000;
  std::uint64_t walkerSteps = 10000;
  std::uint64_t seed = 1;
  int threads = 1;
  std::uint32_t mask = contents::kMaskPlayerSolid;
  std::size_t examples = kExamplesDefault;
  std::string replay;
  bool robustEdges = false;  ///< build a .map with BuildOptions::robustEdges
  bool noProc = false;       ///< ignore NAME.proc beside the map
  std::string offset;        ///< "x,y,z": move a .map's world geometry by this first (empty: not moved)
};

/// Percent of the sweeps (of trace models other than a point) that turn
/// the trace model to a random orientation (TranslationQuery::trmAxis).
inline constexpr std::uint64_t kRotatedSweepPercent = 30;

/// A trace model as the soak moves it: its spec, the model, and its
/// orientation (identity unless the sweep turned it; a point ignores it).
struct Shape {
  std::string spec;
  TraceModel trm;
  Mat3 axis;
  const TraceModel* query() const { return trm.isPoint() ? nullptr : &trm; }
  bool rotated() const { return !trm.isPoint() && !axis.isIdentity(); }
};

/// A finding of one item, with the query lines that show it.
struct Case {
  std::uint64_t item = 0;
  Finding finding = Finding::NonFinite;
  StuckCause stuck = StuckCause::Unexplained;  ///< the class of a walker-stuck case
  std::string lines;
};

/// What one item (a sweep or a walker) did.
struct ItemTally {
  std::uint64_t sweeps = 0, rotatedSweeps = 0, pointSweeps = 0, noStart = 0, hits = 0, walkerSteps = 0,
                respawns = 0;
  std::array<std::uint64_t, kNumFindings> counts{};
  /// Walker-embedded steps by the class of their last move's end (as a sweep's).
  std::array<std::uint64_t, kNumFindings> walkerCauses{};
  /// Walker-stuck cases by cause.
  std::array<std::uint64_t, kNumStuckCauses> stuckCauses{};
};

/// Runs the items of a soak (sweeps, then walkers); const after set-up, so
/// any number of threads may run items at once, each with its own QueryWork.
class Soak {
 public:
  /// Soaks `world` with the sweeps of `shapes` and `walker` as the player
  /// of the walks. With walker steps (o.walkerSteps > 0) the walker must be
  /// a closed convex solid: std::invalid_argument otherwise.
  Soak(ModelPtr world, std::vector<Shape> shapes, Shape walker, const SoakOptions& o);
  ~Soak();
  Soak(const Soak&) = delete;
  Soak& operator=(const Soak&) = delete;

  /// Brushes every face of which has a polygon.
  std::size_t numClosedBrushes() const;
  /// Item i < sweeps is sweep i; after them come the walkers.
  std::uint64_t numItems() const;
  /// Runs item `item` with its own seeded random generator.
  void runItem(std::uint64_t item, QueryWork& work, ItemTally& tally, std::vector<Case>& cases) const;
  /// Runs one translation and names what its end is: "free", or the class
  /// of the finding (the --replay of a pasted query line).
  std::string replay(const Shape& s, const Vec3& from, const Vec3& to, QueryWork& work) const;
  /// Why a walker at the free position `pos` wishing to walk along `wish`
  /// (horizontal; its length does not matter) makes no progress; `detail`
  /// (when given) gets what the tests measured. Needs walker steps.
  StuckCause diagnoseStuck(const Vec3& pos, const Vec3& wish, QueryWork& work,
                           std::string* detail = nullptr) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace cmkit::cli
