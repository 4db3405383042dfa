// The soak's diagnosis of a stuck walker (tools/cmkit/soak_walker.cpp,
// diagnoseStuck; issue #34, item 5; the walker is the library's player,
// stepPlayer): a walker pressed into a room's corner
// with its wish direction into it is `cornered` (the walk's), one in a pit
// a little wider than the box is `no-room` (the map's), and walkers whose
// step moves them (in the open, or sliding along a wall) are `unexplained`
// (the class a query fault would show as; these walkers are not stuck),
// but one wishing within 3 degrees of a wall's normal creeps along it:
// `pressing` (the walk's).
// And the class of a walker's slide that ends in a brush through a side
// without polygons (lt4's visportal brushes): brush-face, the map's.
#if CMKIT_TEST_SOAK
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "cmkit/compile.h"
#include "cmkit/map.h"
#include "cmkit/materials.h"
#include "cmkit/query.h"
#include "soak.h"

namespace cmkit::cli {
/// GoogleTest prints a cause by its name.
void PrintTo(StuckCause cause, std::ostream* os) { *os << kStuckCauseNames[std::size_t(cause)]; }
}  // namespace cmkit::cli

using namespace cmkit;
using cmkit::cli::StuckCause;

namespace {

/// A box brush of `material`, its +x side of `plusX` (default: the same).
std::string box(const Vec3& lo, const Vec3& hi, const char* material = "textures/base_wall/lfwall27d",
                const char* plusX = nullptr) {
  auto face = [&](const char* n, Real d, const char* m) {
    return "  ( " + std::string(n) + " " + std::to_string(d) +
           " ) ( ( 0.0078125 0 0 ) ( 0 0.0078125 0 ) ) \"" + m + "\" 0 0 0\n";
  };
  return "{\n brushDef3\n {\n" + face("0 0 1", -hi.z, material) + face("0 0 -1", lo.z, material) +
         face("1 0 0", -hi.x, plusX ? plusX : material) + face("-1 0 0", lo.x, material) +
         face("0 1 0", -hi.y, material) + face("0 -1 0", lo.y, material) + " }\n}\n";
}

/// A closed room, inside x, y in [-256, 256], z in [0, 256], and in it a
/// pit 33 x 33 units wide (x, y in [111.5, 144.5]) with walls 128 high:
/// the 32 x 32 box has half a unit of room in it. Against the -x wall a
/// visportal brush as lt4 has them (x in [-200, -184], y in [-64, 64], z in
/// [0, 200]): nodraw sides (solid by the built-in material rules) and a
/// visportal side at x = -184, which makes no polygon.
ModelPtr roomWithPit() {
  std::string text = "Version 2\n{\n\"classname\" \"worldspawn\"\n";
  text += box({-272, -272, -16}, {272, 272, 0});    // floor
  text += box({-272, -272, 256}, {272, 272, 272});  // ceiling
  text += box({-272, -272, 0}, {-256, 272, 256});   // walls
  text += box({256, -272, 0}, {272, 272, 256});
  text += box({-256, -272, 0}, {256, -256, 256});
  text += box({-256, 256, 0}, {256, 272, 256});
  text += box({95.5f, 95.5f, 0}, {111.5f, 160.5f, 128});  // the pit's walls
  text += box({144.5f, 95.5f, 0}, {160.5f, 160.5f, 128});
  text += box({111.5f, 95.5f, 0}, {144.5f, 111.5f, 128});
  text += box({111.5f, 144.5f, 0}, {144.5f, 160.5f, 128});
  text += box({-200, -64, 0}, {-184, 64, 200}, "textures/common/nodraw", "textures/editor/visportal");
  text += "}\n";
  auto map = parseMapText(text);
  EXPECT_TRUE(map.ok()) << (map.ok() ? "" : map.error().toString());
  if (!map) return nullptr;
  auto built = buildCollisionModels(*map, MaterialTable{}, BuildOptions{});
  EXPECT_TRUE(built.ok());
  if (!built || built->models.empty()) return nullptr;
  return built->models[0];
}

/// The walker's wished direction toward (x, y).
Vec3 wishToward(Real x, Real y) {
  const Real len = std::sqrt(x * x + y * y);
  return {x / len, y / len, 0};
}

struct SoakWalker : ::testing::Test {
  void SetUp() override {
    world = roomWithPit();
    ASSERT_TRUE(world);
    walker = {cli::kWalkerTrm, *TraceModel::parse(cli::kWalkerTrm), {}};
    soak = std::make_unique<cli::Soak>(world, std::vector<cli::Shape>{}, walker, options);
  }
  /// The diagnosis at `pos` (which must be free: the walker only gets stuck
  /// at free positions).
  StuckCause diagnose(const Vec3& pos, const Vec3& wish, std::string& detail) {
    ContentsQuery q;
    q.trm = &walker.trm;
    q.position = pos;
    q.contentMask = options.mask;
    EXPECT_EQ(contentsTest(*world, q, work).contents & options.mask, 0u) << "not free";
    return soak->diagnoseStuck(pos, wish, work, &detail);
  }
  ModelPtr world;
  cli::Shape walker;
  cli::SoakOptions options;
  std::unique_ptr<cli::Soak> soak;
  QueryWork work;
};

}  // namespace

// The box 0.25 units (the clip epsilon) from two walls of the room's corner,
// wishing into the corner: each slide plane clips the velocity and the
// crease of the two walls is vertical, so a step moves it ~0. The box has
// room along +x and +y.
TEST_F(SoakWalker, WishIntoACornerIsCornered) {
  std::string detail;
  EXPECT_EQ(diagnose({-239.75f, -239.75f, 0.25f}, wishToward(-1, -0.7f), detail), StuckCause::Cornered)
      << detail;
  EXPECT_EQ(diagnose({239.75f, 239.75f, 0.25f}, wishToward(0.3f, 1), detail), StuckCause::Cornered) << detail;
}

// The same corner with the wish along one wall: the walker slides away.
TEST_F(SoakWalker, WishAlongAWallIsNotCornered) {
  std::string detail;
  EXPECT_EQ(diagnose({-239.75f, -239.75f, 0.25f}, wishToward(-1, 0.5f), detail), StuckCause::Unexplained)
      << detail;
  EXPECT_EQ(diagnose({0, 0, 0.25f}, wishToward(1, 0), detail), StuckCause::Unexplained) << detail;
}

// Against the room's -y wall (0.25 units, the clip epsilon, from it) with
// the wish 2.1 and 2.45 degrees from the wall's normal (the two stuck
// walkers of lt4 at 200 000 steps, robust edges): the wall leaves 1.4 and
// 1.6 units/s of each step's 36.7 along it, which the next step's friction
// takes: the walker creeps, pressing. At 10 degrees it slides away (6.4
// units/s a step, 0.1 units a step): not stuck, unexplained if it were.
TEST_F(SoakWalker, WishNearlyIntoAWallIsPressing) {
  std::string detail;
  EXPECT_EQ(diagnose({0, -239.75f, 0.25f}, wishToward(-0.037f, -0.999f), detail), StuckCause::Pressing)
      << detail;
  EXPECT_EQ(diagnose({0, -239.75f, 0.25f}, wishToward(0.043f, -0.999f), detail), StuckCause::Pressing)
      << detail;
  EXPECT_EQ(diagnose({0, -239.75f, 0.25f}, wishToward(-0.174f, -0.985f), detail), StuckCause::Unexplained)
      << detail;
}

// In the pit the box can move 0.25 units along an axis (0.35 diagonally),
// and its walls are higher than a step up: no-room, whatever the wish.
TEST_F(SoakWalker, NarrowPitIsNoRoom) {
  std::string detail;
  for (const Vec3& wish : {wishToward(1, 0), wishToward(-1, -1), wishToward(0.2f, 1)})
    EXPECT_EQ(diagnose({128, 128, 0.25f}, wish, detail), StuckCause::NoRoom) << detail;
}

// The three walker slides of lt4 (robust edges, 200 000 steps) that were
// classed precision (0.0001 and 0.002 units deep) and grazing (0.1 deep,
// edge-on to the face) ended in a visportal brush (brush 2671, x in [408,
// 424]) entered through its visportal side, which has no polygon: nothing
// could stop them, so they are the map's (brush-face), not cmkit's. The
// same moves, shifted from x = 424 to the room's visportal side at x = -184.
TEST_F(SoakWalker, SlideThroughAVisportalSideIsBrushFace) {
  const Real shift = -184 - 424;
  const struct {
    Vec3 from, to;
  } slides[] = {
      {{440.34787f, 0, 50}, {439.99988f, 0, 49.85364f}},          // was precision
      {{440.0998f, 0, 100}, {439.99814f, 3.2698f, 93.9297f}},     // was precision
      {{440.05136f, 0, 100}, {439.90216f, -3.9495f, 85.37937f}},  // was grazing
  };
  for (const auto& m : slides) {
    const Vec3 from{m.from.x + shift, m.from.y, m.from.z}, to{m.to.x + shift, m.to.y, m.to.z};
    const std::string found = soak->replay(walker, from, to, work);
    EXPECT_EQ(found.rfind("brush-face (fraction 1,", 0), 0u) << found;
  }
}
#endif
