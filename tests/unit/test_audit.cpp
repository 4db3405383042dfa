// The map audit (audit.h) on hand-made maps with one planted fault each
// (tests/data/maps/audit_*.map, make_audit_maps.py): a sealed room has no
// findings; a hole over nothing is a fall-out beside it; a V trench a stuck
// spot in it; a crack in the floor or a slit in a wall an open shell; a start in a
// pillar an embedded player start; a gap is jumped. Also: movers, thread counts, lt4, and
// `cmkit audit` (exit codes, JSON, picture).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "cmkit/audit.h"
#include "cmkit/map.h"
#include "cmkit/movement.h"
#include "cmkit/query.h"
#include "cmkit/world.h"
#include "test_support.h"

namespace cmkit {
namespace {

std::string mapPath(const std::string& name) { return (test::testDataDir() / "maps" / name).string(); }

/// A map's World and spots, audited.
struct Audited {
  AuditReport report;
  std::vector<AuditSpot> spots;
};

Audited audit(const std::string& path, AuditOptions options = {}) {
  auto map = loadMapFile(path);
  EXPECT_TRUE(map.ok()) << path;
  auto loaded = World::loadMap(path, MaterialTable{});
  EXPECT_TRUE(loaded.ok()) << path;
  Audited out;
  out.spots = auditSpotsFromMap(*map);
  auto report = auditWorld(loaded->world, out.spots, options);
  EXPECT_TRUE(report.ok()) << (report ? "" : report.error().toString());
  if (report) out.report = std::move(*report);
  return out;
}

std::size_t findingCount(const AuditReport& r) { return r.numbered().size(); }

/// Distance in the xy plane from a point to the rectangle [lo, hi].
Real distanceToRect(const Vec3& p, Real x0, Real y0, Real x1, Real y1) {
  const Real dx = std::max({x0 - p.x, Real(0), p.x - x1});
  const Real dy = std::max({y0 - p.y, Real(0), p.y - y1});
  return std::sqrt(dx * dx + dy * dy);
}

bool sameBits(const Vec3& a, const Vec3& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

/// Two reports are the same, field by field, bit for bit.
void expectSameReport(const AuditReport& a, const AuditReport& b) {
  ASSERT_EQ(a.cells.size(), b.cells.size());
  for (std::size_t i = 0; i < a.cells.size(); ++i) {
    ASSERT_TRUE(sameBits(a.cells[i].position, b.cells[i].position)) << i;
    ASSERT_EQ(a.cells[i].crouched, b.cells[i].crouched) << i;
  }
  EXPECT_EQ(a.movesTried, b.movesTried);
  const auto fa = a.numbered(), fb = b.numbered();
  ASSERT_EQ(fa.size(), fb.size());
  for (std::size_t i = 0; i < fa.size(); ++i) {
    EXPECT_EQ(fa[i]->kind, fb[i]->kind) << i;
    EXPECT_TRUE(sameBits(fa[i]->position, fb[i]->position)) << i;
    EXPECT_EQ(fa[i]->what, fb[i]->what) << i;
    EXPECT_EQ(fa[i]->merged, fb[i]->merged) << i;
    ASSERT_EQ(fa[i]->path.size(), fb[i]->path.size()) << i;
    for (std::size_t k = 0; k < fa[i]->path.size(); ++k)
      EXPECT_TRUE(sameBits(fa[i]->path[k], fb[i]->path[k]));
  }
}

TEST(Audit, SpotsAndMoverClasses) {
  auto map = loadMapFile(mapPath("audit_sealed.map"));
  ASSERT_TRUE(map.ok());
  const auto spots = auditSpotsFromMap(*map);
  ASSERT_EQ(spots.size(), 3u);
  EXPECT_EQ(spots[0].kind, AuditSpotKind::PlayerStart);
  EXPECT_TRUE(sameBits(spots[0].origin, {-160, 0, 1}));
  EXPECT_EQ(spots[1].kind, AuditSpotKind::Monster);
  EXPECT_EQ(spots[2].kind, AuditSpotKind::Item);
  EXPECT_EQ(spots[2].name, "item_1");
  for (const char* mover : {"func_door", "func_door_rotating", "atdm:mover_door_sliding", "lt4:door_wood",
                            "func_plat", "moveable_barrel", "atdm:moveable_chair_wood_1", "func_rotating"})
    EXPECT_TRUE(isMoverClass(mover)) << mover;
  for (const char* fixed :
       {"func_static", "worldspawn", "info_player_start", "atdm:lamp_electric_square_2_lit"})
    EXPECT_FALSE(isMoverClass(fixed)) << fixed;
}

TEST(Audit, RefusesBadOptions) {
  auto loaded = World::loadMap(mapPath("audit_sealed.map"), MaterialTable{});
  ASSERT_TRUE(loaded.ok());
  AuditOptions o;
  o.grid = 2;
  EXPECT_FALSE(auditWorld(loaded->world, {}, o).ok());
  o.grid = std::nan("");
  EXPECT_FALSE(auditWorld(loaded->world, {}, o).ok());
  o.grid = 16;
  o.threads = 0;
  EXPECT_FALSE(auditWorld(loaded->world, {}, o).ok());
}

TEST(Audit, SealedRoomHasNoFindings) {
  const Audited a = audit(mapPath("audit_sealed.map"));
  // The room is 512 x 512 inside: 32 x 32 grid squares, less the squares
  // whose centres the walls keep the player from.
  EXPECT_GT(a.report.cells.size(), 800u);
  EXPECT_LE(a.report.cells.size(), 33u * 33u);
  EXPECT_EQ(findingCount(a.report), 0u);
  EXPECT_FALSE(a.report.hasHighSeverity());
  for (const AuditCell& c : a.report.cells) EXPECT_NEAR(c.position.z, tol::kClipEpsilon, 1e-3);
}

TEST(Audit, HoleOverNothingIsAFallOutBesideIt) {
  const Audited a = audit(mapPath("audit_hole.map"));
  ASSERT_FALSE(a.report.fallOuts.empty());
  // The hole is x 64..160, y -48..48.
  for (const AuditFinding& f : a.report.fallOuts) {
    EXPECT_LE(distanceToRect(f.position, 64, -48, 160, 48), 96) << f.what;
    EXPECT_EQ(f.severity, AuditSeverity::High);
    ASSERT_GE(f.path.size(), 2u);
    EXPECT_TRUE(sameBits(f.path.back(), f.position));
    EXPECT_NEAR(f.path.front().x, -160, 1);  // the start
  }
  EXPECT_TRUE(a.report.stuck.empty());
  EXPECT_TRUE(a.report.tunnels.empty());
  EXPECT_TRUE(a.report.embedded.empty());
  EXPECT_TRUE(a.report.openShells.empty());
  EXPECT_TRUE(a.report.hasHighSeverity());
}

TEST(Audit, WedgeTrapIsAStuckSpotInIt) {
  const Audited a = audit(mapPath("audit_wedge.map"));
  ASSERT_EQ(a.report.stuck.size(), 1u);
  const AuditFinding& f = a.report.stuck[0];
  // In the trench (x -64..64, y -20..20), down in its V.
  EXPECT_LE(std::abs(f.position.x), 8);
  EXPECT_LE(std::abs(f.position.y), 20);
  EXPECT_LT(f.position.z, -60);
  EXPECT_EQ(f.severity, AuditSeverity::High);
  EXPECT_TRUE(a.report.fallOuts.empty());
  EXPECT_TRUE(a.report.tunnels.empty());
  EXPECT_TRUE(a.report.openShells.empty());
}

TEST(Audit, CrackBetweenTwoBrushesIsAnOpenShell) {
  const Audited a = audit(mapPath("audit_crack.map"));
  ASSERT_FALSE(a.report.openShells.empty());
  // The crack is x 37..39 along the whole floor: found along it, not elsewhere.
  Real yMin = 1e9f, yMax = -1e9f;
  for (const AuditFinding& f : a.report.openShells) {
    EXPECT_GE(f.position.x, 37 - kAuditCrackProbe);
    EXPECT_LE(f.position.x, 39 + kAuditCrackProbe);
    EXPECT_NEAR(f.position.z, 0, 1);
    EXPECT_EQ(f.severity, AuditSeverity::Medium);
    yMin = std::min(yMin, f.position.y);
    yMax = std::max(yMax, f.position.y);
  }
  EXPECT_GT(yMax - yMin, 256);
  // The player does not fall through it.
  EXPECT_TRUE(a.report.fallOuts.empty());
  EXPECT_TRUE(a.report.stuck.empty());
  EXPECT_FALSE(a.report.hasHighSeverity());
  // Without the crack rays, nothing.
  AuditOptions o;
  o.openShells = false;
  EXPECT_EQ(findingCount(audit(mapPath("audit_crack.map"), o).report), 0u);
}

TEST(Audit, GapIsCrossedByARunningJump) {
  // The start is at x = -160; the floor beyond the gap (x > 32) is reached
  // only by jumping across it (a run drops into the pit, 128 down).
  const Audited a = audit(mapPath("audit_gap.map"));
  const auto farSide = std::count_if(a.report.cells.begin(), a.report.cells.end(), [](const AuditCell& c) {
    return c.position.x > 48 && std::abs(c.position.z - tol::kClipEpsilon) < 1e-3f;
  });
  EXPECT_GT(farSide, 300);  // squares x 64..240, y -240..240: 12 x 31
  const auto pit = std::count_if(a.report.cells.begin(), a.report.cells.end(),
                                 [](const AuditCell& c) { return c.position.z < -100; });
  EXPECT_GT(pit, 30);
  EXPECT_EQ(findingCount(a.report), 0u);
}

TEST(Audit, SlitInAWallIsAnOpenShell) {
  const Audited a = audit(mapPath("audit_wall_crack.map"));
  ASSERT_FALSE(a.report.openShells.empty());
  // The slit is y 37..39 through the wall x 256..272, up to the ceiling.
  for (const AuditFinding& f : a.report.openShells) {
    EXPECT_GE(f.position.x, 256 - 1);
    EXPECT_LE(f.position.x, 272);
    EXPECT_GE(f.position.y, 37 - kAuditCrackProbe);
    EXPECT_LE(f.position.y, 39 + kAuditCrackProbe);
    EXPECT_NE(f.what.find("wall"), std::string::npos) << f.what;
  }
  EXPECT_EQ(findingCount(a.report), a.report.openShells.size());
}

TEST(Audit, PlayerStartInAPillarIsEmbedded) {
  const Audited a = audit(mapPath("audit_pillar.map"));
  ASSERT_EQ(a.report.embedded.size(), 1u);
  const AuditFinding& f = a.report.embedded[0];
  EXPECT_TRUE(sameBits(f.position, {128, 0, 1}));
  EXPECT_EQ(f.severity, AuditSeverity::High);
  EXPECT_NE(f.what.find("info_player_start_2"), std::string::npos) << f.what;
  EXPECT_EQ(a.report.fallOuts.size() + a.report.stuck.size() + a.report.tunnels.size(), 0u);
  // The search went on from both starts (the second freed beside the pillar).
  EXPECT_EQ(a.report.starts.size(), 2u);
  EXPECT_GT(a.report.cells.size(), 800u);
}

TEST(Audit, MonsterAndItemInSolidAreEmbedded) {
  auto loaded = World::loadMap(mapPath("audit_pillar.map"), MaterialTable{});
  ASSERT_TRUE(loaded.ok());
  std::vector<AuditSpot> spots(2);
  spots[0].kind = AuditSpotKind::Monster;
  spots[0].origin = {128, 0, 1};  // in the pillar
  spots[1].kind = AuditSpotKind::Item;
  spots[1].origin = {0, 0, -8};  // in the floor, deeper than a lift frees
  AuditOptions o;
  o.extraStarts = {{-160, 0, 1}};
  auto r = auditWorld(loaded->world, spots, o);
  ASSERT_TRUE(r.ok());
  ASSERT_EQ(r->embedded.size(), 2u);
  EXPECT_EQ(r->embedded[0].severity, AuditSeverity::Low);  // sorted by position: the item first
  EXPECT_EQ(r->embedded[1].severity, AuditSeverity::Medium);
  EXPECT_FALSE(r->hasHighSeverity());
  // On the floor (a little into it, as maps often put them): not embedded.
  spots[0].origin = {0, 100, 0};
  spots[1].origin = {0, 0, 2};
  r = auditWorld(loaded->world, spots, o);
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(r->embedded.empty());
}

TEST(Audit, TriggersAreIgnored) {
  // A trigger_multiple around the start, of a material the default rules
  // make solid: not an embedded start, and the search goes through it.
  auto loaded = World::loadMap(mapPath("audit_trigger.map"), MaterialTable{});
  ASSERT_TRUE(loaded.ok());
  ASSERT_EQ(loaded->world.size(), 2u);
  const EntityId trigger = 1;
  ASSERT_TRUE(isTriggerClass(loaded->world.entity(trigger)->className));
  const std::uint32_t contents = loaded->world.entity(trigger)->contents;
  ASSERT_NE(contents & contents::kSolid, 0u);
  const Audited a = audit(mapPath("audit_trigger.map"));
  EXPECT_EQ(a.report.triggersIgnored, 1);
  EXPECT_EQ(findingCount(a.report), 0u);
  EXPECT_GT(a.report.cells.size(), 900u);
  EXPECT_FALSE(isTriggerClass("func_static"));
  EXPECT_TRUE(isTriggerClass("atdm:trigger_once"));
}

TEST(Audit, MoversIgnoredOpenTheDoorAndAreRestored) {
  auto map = loadMapFile(mapPath("two_halls.map"));
  ASSERT_TRUE(map.ok());
  auto loaded = World::loadMap(mapPath("two_halls.map"), MaterialTable{});
  ASSERT_TRUE(loaded.ok());
  const auto spots = auditSpotsFromMap(*map);
  const EntityId door = 1;
  ASSERT_TRUE(isMoverClass(loaded->world.entity(door)->className));
  const std::uint32_t doorContents = loaded->world.entity(door)->contents;
  ASSERT_NE(doorContents, 0u);
  auto open = auditWorld(loaded->world, spots);
  ASSERT_TRUE(open.ok());
  EXPECT_EQ(open->moversIgnored, 1);
  EXPECT_EQ(loaded->world.entity(door)->contents, doorContents);
  AuditOptions closed;
  closed.ignoreMovers = false;
  auto shut = auditWorld(loaded->world, spots, closed);
  ASSERT_TRUE(shut.ok());
  EXPECT_EQ(shut->moversIgnored, 0);
  // Closed, the player stays in its hall (x < 0); open, it reaches both.
  for (const AuditCell& c : shut->cells) EXPECT_LT(c.position.x, 0);
  EXPECT_TRUE(std::any_of(open->cells.begin(), open->cells.end(),
                          [](const AuditCell& c) { return c.position.x > 64; }));
  EXPECT_GT(open->cells.size(), shut->cells.size() * 3 / 2);
  EXPECT_EQ(findingCount(*open), 0u);
}

TEST(Audit, SameReportAtAnyThreadCount) {
  for (const char* name : {"audit_hole.map", "audit_wedge.map", "audit_crack.map"}) {
    AuditOptions one, two;
    two.threads = 2;
    SCOPED_TRACE(name);
    expectSameReport(audit(mapPath(name), one).report, audit(mapPath(name), two).report);
  }
}

// lt4 (the bundled map): the search reaches thousands of cells from its start,
// the same at 1 and 2 threads; the start that touches a crate beside its door
// is reported.
TEST(Audit, Lt4SameAtOneAndTwoThreads) {
  const std::string lt4 =
      (std::filesystem::path(CMKIT_SOURCE_DIR) / "data" / "maps" / "lt4" / "lt4.map").string();
  AuditOptions one, two;
  two.threads = 2;
  const Audited a = audit(lt4, one), b = audit(lt4, two);
  EXPECT_GT(a.report.cells.size(), 2000u);
  expectSameReport(a.report, b.report);
  // Every tunnel's end is in solid; the high ones overlap a brush, the low
  // ones polygons only (a patch).
  auto loaded = World::loadMap(lt4, MaterialTable{});
  ASSERT_TRUE(loaded.ok());
  WorldQueryWork work;
  const PlayerShape player = PlayerShape::standard();
  ASSERT_FALSE(a.report.tunnels.empty());
  for (const AuditFinding& f : a.report.tunnels) {
    const TraceModel& trm = f.what.find("crouched") != std::string::npos ? player.crouched : player.standing;
    ContentsQuery q;
    q.trm = &trm;
    q.position = f.position;
    q.contentMask = player.contentMask;
    EXPECT_NE(loaded->world.contentsTest(q, work).result.contents, 0u) << f.what;
    bool brush = false;
    for (EntityId id : loaded->world.entityIds()) {
      const WorldEntity* e = loaded->world.entity(id);
      PenetrationQuery p;
      p.trm = &trm;
      p.position = f.position;
      p.contentMask = player.contentMask;
      p.placement = e->placement;
      const PenetrationResult r = penetration(*e->model, p, work.modelWork());
      brush = brush || (r.stuck && r.depth > Real(0.01));
    }
    EXPECT_EQ(brush, f.severity == AuditSeverity::High) << f.what;
  }
  ASSERT_FALSE(a.report.embedded.empty());
  EXPECT_TRUE(std::any_of(a.report.embedded.begin(), a.report.embedded.end(), [](const AuditFinding& f) {
    return f.what.find("info_player_start_1") != std::string::npos;
  }));
}

TEST(CmkitAudit, ExitCodesJsonAndPicture) {
  const std::string cli = CMKIT_CLI_PATH;
  test::ScratchDir scratch("cmkit_audit");
  const std::string json = (scratch.path() / "a.json").string();
  const std::string png = (scratch.path() / "a.png").string();
  int rc = -1;
  std::string out = test::runCapture(
      cli + " audit '" + mapPath("audit_sealed.map") + "' --json '" + json + "' --picture '" + png + "'", rc);
  EXPECT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("fall-outs 0, stuck 0, tunnels 0, embedded 0, open shells 0"), std::string::npos) << out;
  std::string text = test::readFile(json);
  for (const char* key : {"\"reachable_cells\": ", "\"fallouts\": []", "\"stuck\": []", "\"tunnels\": []",
                          "\"embedded\": []", "\"open_shells\": []"})
    EXPECT_NE(text.find(key), std::string::npos) << key << "\n" << text;
  const std::string picture = test::readFile(png);
  ASSERT_GT(picture.size(), 8u);
  EXPECT_EQ(picture.substr(1, 3), "PNG");

  // A fall-out: exit status 1; the JSON lists it with its position.
  out = test::runCapture(cli + " audit '" + mapPath("audit_hole.map") + "' --json '" + json + "'", rc);
  EXPECT_EQ(rc, 1) << out;
  text = test::readFile(json);
  EXPECT_NE(text.find("\"kind\": \"fallout\", \"severity\": \"high\", \"position\": ["), std::string::npos)
      << text;
  // A crack only (medium): 0.
  out = test::runCapture(cli + " audit '" + mapPath("audit_crack.map") + "'", rc);
  EXPECT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("open_shell"), std::string::npos) << out;
  // Threads: the same JSON (but for the time taken).
  const std::string json2 = (scratch.path() / "b.json").string();
  test::runCapture(cli + " audit '" + mapPath("audit_wedge.map") + "' --json '" + json + "'", rc);
  EXPECT_EQ(rc, 1);
  test::runCapture(cli + " audit '" + mapPath("audit_wedge.map") + "' --threads 2 --json '" + json2 + "'",
                   rc);
  EXPECT_EQ(rc, 1);
  auto withoutTime = [](std::string s) {
    const std::size_t at = s.find("\"seconds\"");
    return at == std::string::npos ? s : s.erase(at, s.find('\n', at) - at);
  };
  EXPECT_EQ(withoutTime(test::readFile(json)), withoutTime(test::readFile(json2)));
  // A search stopped at --max-cells says so.
  out = test::runCapture(
      cli + " audit '" + mapPath("audit_sealed.map") + "' --max-cells 100 --json '" + json + "'", rc);
  EXPECT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("100 reachable cells"), std::string::npos) << out;
  EXPECT_NE(out.find("STOPPED at the cell limit"), std::string::npos) << out;
  EXPECT_NE(test::readFile(json).find("\"truncated\": true"), std::string::npos);
  // --from, repeatable, before or after the map.
  out = test::runCapture(
      cli + " audit --from 0,0,1 --from 100,0,1 '" + mapPath("audit_sealed.map") + "' --no-shells", rc);
  EXPECT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("from 3 starts"), std::string::npos) << out;
  // Bad input: 2.
  for (const std::string& bad :
       {"'" + mapPath("no_such.map") + "'", "'" + mapPath("audit_sealed.map") + "' --grid 1",
        "'" + mapPath("audit_sealed.map") + "' --threads 0",
        "'" + mapPath("audit_sealed.map") + "' --from 1,2",
        "'" + mapPath("audit_sealed.map") + "' --movers open"}) {
    test::runCapture(cli + " audit " + bad + " 2>/dev/null", rc);
    EXPECT_EQ(rc, 2) << bad;
  }
}

}  // namespace
}  // namespace cmkit
