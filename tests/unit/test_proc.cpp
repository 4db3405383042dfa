// .proc pruning of the world model (docs/algorithms.md, "Building a model") and
// writing one entity's model (the original's WriteCollisionModelForMapEntity).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cmkit/cm_file.h"
#include "cmkit/compile.h"
#include "cmkit/manager.h"
#include "cmkit/map.h"
#include "cmkit/proc_file.h"
#include "test_support.h"

namespace {

namespace fs = std::filesystem;
using namespace cmkit;

fs::path procData() { return test::testDataDir() / "proc"; }

/// A box brush from min to max with one material on every side
/// (test::axialBrush).
std::string boxBrush(const Vec3& mn, const Vec3& mx, const char* material = "textures/base/floor") {
  return test::axialBrush(Bounds(mn, mx), material);
}

std::string worldWith(const std::string& brushes) {
  return "Version 2\n{\n\"classname\" \"worldspawn\"\n" + brushes + "}\n";
}

std::vector<ModelPtr> build(const std::string& mapText, const std::string& procText, int* dropped = nullptr) {
  auto map = parseMapText(mapText, "t.map");
  EXPECT_TRUE(map.ok()) << map.error().toString();
  auto proc = parseProcText(procText, "t.proc");
  EXPECT_TRUE(proc.ok()) << proc.error().toString();
  BuildOptions options;
  options.procBsp = &*proc;
  auto models = buildCollisionModels(*map, MaterialTable{}, options);
  EXPECT_TRUE(models.ok());
  if (dropped) *dropped = models->models[0]->stats().procPolygonsRemoved;
  return models->models;
}

TEST(ProcFile, ReadsTheNodesAndSkipsOtherSections) {
  const auto bsp = parseProcText(
      "mapProcFile003\n"
      "model { /* name = */ \"_area0\" /* numSurfaces = */ 1\n"
      "{ \"textures/a\" 3 3 ( 0 0 0 0 0 0 0 1 ) ( 1 0 0 0 0 0 0 1 ) ( 0 1 0 0 0 0 0 1 ) 0 1 2 } }\n"
      "interAreaPortals { 2 1 4 0 1 ( 0 0 0 ) ( 1 0 0 ) ( 1 1 0 ) ( 0 1 0 ) }\n"
      "nodes { 2\n( 1 0 0 -16 ) 1 0\n( 0 0 -1 0.5 ) -1 -2\n}\n"
      "shadowModel { this is never read ( }\n",
      "a.proc");
  ASSERT_TRUE(bsp.ok()) << bsp.error().toString();
  ASSERT_EQ(bsp->nodes.size(), 2u);
  EXPECT_EQ(bsp->nodes[0].plane.normal, Vec3(1, 0, 0));
  EXPECT_EQ(bsp->nodes[0].plane.dist, 16.0f);  // ( a b c d ): a*x + b*y + c*z + d = 0
  EXPECT_EQ(bsp->nodes[0].children[0], 1);
  EXPECT_EQ(bsp->nodes[0].children[1], 0);
  EXPECT_EQ(bsp->nodes[1].plane.dist, -0.5f);
  EXPECT_EQ(bsp->nodes[1].children[0], -1);
  EXPECT_EQ(bsp->nodes[1].children[1], -2);
  EXPECT_TRUE(bsp->usable());
}

TEST(ProcFile, MalformedFilesAreErrorsWithLineAndColumn) {
  struct Case {
    const char* text;
    int line;
    const char* says;
  };
  const Case cases[] = {
      {"mapProcFile003\nnodes { 1\n( 1 0 0 ) 0 0\n}\n", 3, "expected a number"},
      {"mapProcFile003\nnodes { 2\n( 1 0 0 0 ) 1 0\n( 1 0 0 0 ) 1 0\n}\n", 4, "a node after 1"},
      {"mapProcFile003\nnodes { 1\n( 1 0 0 0 ) 5 0\n}\n", 3, "node 5"},
      {"mapProcFile003\n\nbogus { }\n", 3, "unexpected 'bogus'"},
      {"mapProcFile003\nmodel { \"a\" {\n", 2, "no closing '}'"},
      {"mapProcFile003\nnodes { -3\n", 2, "out of range"},
      {"mapProcFile003\nnodes { 1\n( 1 0 0 0 ) 0 0.5\n}\n", 3, "an integer"},
      {"mapProcFile003\nnodes { 1\n( 1 0 0 0 ) 0 0\n", 4, "to end the nodes section"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    const auto bsp = parseProcText(c.text, "bad.proc");
    ASSERT_FALSE(bsp.ok());
    EXPECT_EQ(bsp.error().file, "bad.proc");
    EXPECT_EQ(bsp.error().line, c.line) << bsp.error().toString();
    EXPECT_GT(bsp.error().column, 0);
    EXPECT_NE(bsp.error().message.find(c.says), std::string::npos) << bsp.error().toString();
  }
}

TEST(ProcFile, AWrongHeaderWarnsAndPrunesNothing) {
  std::vector<std::string> warnings;
  const auto bsp = parseProcText("PROC \"4\"\nnodes { 1 ( 1 0 0 0 ) 0 0 }\n", "old.proc", &warnings);
  ASSERT_TRUE(bsp.ok());
  EXPECT_FALSE(bsp->usable());
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("bad id 'PROC'"), std::string::npos) << warnings[0];
  // without a nodes section: nothing to prune with, no error
  const auto none = parseProcText("mapProcFile003\nmodel { 1 2 3 }\n", "n.proc");
  ASSERT_TRUE(none.ok());
  EXPECT_FALSE(none->usable());
}

// A slab whose top face lies exactly on the proc plane z = 0 (area above,
// solid below): the top face faces the area and stays, the faces below or
// touching the plane from below are dropped.
TEST(ProcPruning, AWindingOnAPlaneFollowsItsNormal) {
  const std::string map = worldWith(boxBrush({-64, -64, -16}, {64, 64, 0}));
  int dropped = 0;
  const auto models = build(map, "mapProcFile003 nodes { 1 ( 0 0 1 0 ) -1 0 }", &dropped);
  const CollisionModel& world = *models[0];
  ASSERT_EQ(world.polygons().size(), 1u);
  EXPECT_EQ(world.polygons()[0].plane.normal, Vec3(0, 0, 1));
  EXPECT_EQ(dropped, 5);
  EXPECT_EQ(world.stats().containedPolygonsRemoved, 5);
  // the same slab above the plane: its bottom face (on the plane, facing
  // the solid side) goes, the others are in the area
  const auto above =
      build(worldWith(boxBrush({-64, -64, 0}, {64, 64, 16})), "mapProcFile003 nodes { 1 ( 0 0 1 0 ) -1 0 }");
  EXPECT_EQ(above[0]->polygons().size(), 5u);
  for (const CmPolygon& p : above[0]->polygons()) EXPECT_NE(p.plane.normal, Vec3(0, 0, -1));
}

// A floor crossing the plane x = 0 with an area on its front side is kept
// whole (not cut at the plane); the face at x = -64 is in the solid half and
// goes, and a box entirely in the solid half goes completely.
TEST(ProcPruning, AWindingReachingAnAreaIsKeptWhole) {
  const char* proc = "mapProcFile003 nodes { 2 ( 1 0 0 0 ) -1 1 ( 0 0 1 1000 ) 0 0 }";
  int dropped = 0;
  const auto models = build(worldWith(boxBrush({-64, -64, -16}, {64, 64, 0})), proc, &dropped);
  const CollisionModel& world = *models[0];
  ASSERT_EQ(world.polygons().size(), 5u);
  EXPECT_EQ(dropped, 1);
  int crossing = 0;
  for (const CmPolygon& p : world.polygons()) {
    EXPECT_NE(p.plane.normal, Vec3(-1, 0, 0));
    if (p.plane.normal.x == 0) {  // top, bottom and the two y faces cross x = 0
      ++crossing;
      EXPECT_EQ(p.bounds.min.x, -64.0f);
      EXPECT_EQ(p.bounds.max.x, 64.0f);
    }
  }
  EXPECT_EQ(crossing, 4);
  const auto solid = build(worldWith(boxBrush({-128, -64, -16}, {-64, 64, 0})), proc, &dropped);
  EXPECT_EQ(solid[0]->polygons().size(), 0u);
  EXPECT_EQ(dropped, 6);
}

// Only the world model is pruned, only solid windings, and not without a BSP.
TEST(ProcPruning, OnlyTheWorldsSolidWindings) {
  const std::string map = worldWith(boxBrush({-64, -64, -16}, {64, 64, 0})) +
                          "{\n\"classname\" \"func_static\"\n\"name\" \"f\"\n" +
                          boxBrush({-8, -8, -8}, {8, 8, 8}) + "}\n" +
                          "{\n\"classname\" \"func_static\"\n\"name\" \"w\"\n" +
                          boxBrush({-8, -8, -8}, {8, 8, 8}, "textures/liquids/water") + "}\n";
  const auto models = build(map, "mapProcFile003 nodes { 1 ( 0 0 1 1000 ) 0 0 }");  // all solid
  ASSERT_EQ(models.size(), 3u);
  EXPECT_EQ(models[0]->polygons().size(), 0u);
  EXPECT_EQ(models[1]->polygons().size(), 6u);
  EXPECT_EQ(models[2]->polygons().size(), 6u);
  const auto waterWorld = build(worldWith(boxBrush({-8, -8, -8}, {8, 8, 8}, "textures/liquids/water")),
                                "mapProcFile003 nodes { 1 ( 0 0 1 1000 ) 0 0 }");
  EXPECT_EQ(waterWorld[0]->polygons().size(), 6u);  // not solid: never pruned
}

/// Builds a map of tests/data/proc as the original loads it (NAME.proc beside).
std::pair<std::string, std::vector<ModelPtr>> buildWithProcBeside(const fs::path& map) {
  auto parsed = loadMapFile(map.string());
  EXPECT_TRUE(parsed.ok()) << parsed.error().toString();
  auto proc = loadProcFileForMap(map.string());
  EXPECT_TRUE(proc.ok() && proc->has_value()) << map;
  BuildOptions options;
  options.procBsp = &**proc;
  auto models = buildCollisionModels(*parsed, MaterialTable{}, options);
  EXPECT_TRUE(models.ok());
  return {writeCmText(models->models, parsed->geometryCrc), models->models};
}

TEST(ProcPruning, TheTwoProcMapsGiveTheOriginalsCmFiles) {
  CMKIT_FLOAT_BUILD_ONLY();
  for (const char* name : {"box_room_proc", "inline_patch_proc"}) {
    SCOPED_TRACE(name);
    const auto [text, models] = buildWithProcBeside(procData() / (std::string(name) + ".map"));
    EXPECT_EQ(text, test::readFile(procData() / (std::string(name) + ".cm")));
    EXPECT_GT(models[0]->stats().procPolygonsRemoved, 0);
    EXPECT_EQ(text, test::readFile(test::dataFile("reference-proc/" + std::string(name) + ".cm")));
  }
}

TEST(ProcPruning, TheManagerUsesTheProcBesideTheMapUnlessTurnedOff) {
  const std::string map = (procData() / "box_room_proc.map").string();
  ModelManager manager;
  LoadMapOptions options;
  options.forceRebuild = true;  // never a .cm beside
  auto pruned = manager.loadMap(map, MaterialTable{}, options);
  ASSERT_TRUE(pruned.ok()) << pruned.error().toString();
  EXPECT_EQ(pruned->procPath, procPathForMap(map));
  EXPECT_GT(pruned->procPolygonsRemoved, 0);
  const std::size_t prunedPolygons = manager.get(kWorldModelHandle)->polygons().size();
  options.useProcFile = false;
  auto whole = manager.loadMap(map, MaterialTable{}, options);
  ASSERT_TRUE(whole.ok());
  EXPECT_TRUE(whole->procPath.empty());
  EXPECT_EQ(whole->procPolygonsRemoved, 0);
  EXPECT_GT(manager.get(kWorldModelHandle)->polygons().size(), prunedPolygons);
}

TEST(ProcPruning, AMalformedProcBesideTheMapIsAnErrorOfTheLoad) {
  const test::ScratchDir scratch("proc");
  const fs::path& dir = scratch.path();
  fs::copy_file(procData() / "box_room_proc.map", dir / "room.map", fs::copy_options::overwrite_existing);
  {
    std::ofstream f(dir / "room.proc");
    f << "mapProcFile003\nnodes { 1\n( 1 0 0 ) 0 0 }\n";
  }
  ModelManager manager;
  LoadMapOptions options;
  options.forceRebuild = true;
  auto r = manager.loadMap((dir / "room.map").string(), MaterialTable{}, options);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().toString().find("room.proc:3:"), std::string::npos) << r.error().toString();
  EXPECT_EQ(manager.size(), 0u);
  fs::remove_all(dir);
}

TEST(ProcPruning, CliSaysWhetherTheProcWasUsed) {
  if (std::string(CMKIT_CLI_PATH).empty()) GTEST_SKIP() << "the CLI is not built";
  const std::string cli = CMKIT_CLI_PATH;
  const std::string map = (procData() / "box_room_proc.map").string();
  int status = 0;
  std::string out = test::runCapture(cli + " info -q '" + map + "' 2>&1", status);
  EXPECT_EQ(status, 0);
  EXPECT_NE(out.find("proc BSP used for pruning: yes"), std::string::npos) << out;
  EXPECT_NE(out.find("pruned with box_room_proc.proc: 43 polygons dropped"), std::string::npos) << out;
  out = test::runCapture(cli + " info -q --no-proc '" + map + "' 2>&1", status);
  EXPECT_EQ(status, 0);
  EXPECT_NE(out.find("proc BSP used for pruning: no"), std::string::npos) << out;
  EXPECT_NE(out.find("box_room_proc.proc ignored (--no-proc)"), std::string::npos) << out;
  // query: the note on stderr only, stdout holds the result lines
  const test::ScratchDir scratch("proc_cli");
  const fs::path queries = scratch.path() / "queries.txt";
  {
    std::ofstream f(queries);
    f << "pointcontents pos=0,0,-8\n";
  }
  out = test::runCapture(cli + " query '" + map + "' '" + queries.string() + "' 2>/dev/null", status);
  EXPECT_EQ(status, 0);
  EXPECT_EQ(out.find("pruned"), std::string::npos) << out;
  EXPECT_EQ(out.rfind("contents=", 0), 0u) << out;
  out = test::runCapture(cli + " query '" + map + "' '" + queries.string() + "' 2>&1 >/dev/null", status);
  EXPECT_NE(out.find("pruned with box_room_proc.proc"), std::string::npos) << out;
  fs::remove(queries);
}

}  // namespace
