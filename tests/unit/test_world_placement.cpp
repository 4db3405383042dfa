// World (cmkit/world.h): entities placed from their map keys against
// hand-computed positions (origin, angle, rotation, brushes in the entity's
// local frame), what is left out (noclipmodel, mesh models), and the
// two-halls map: a player box stops at the func_door, passes once the door
// has moved, and passes through the world model alone.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "cmkit/compile.h"
#include "cmkit/map.h"
#include "cmkit/world.h"
#include "test_support.h"

using namespace cmkit;

namespace {

// A brushDef3 box [lo, hi] (in its entity's frame).
std::string boxBrush(const Vec3& lo, const Vec3& hi) {
  auto side = [](int a, int b, int c, Real d) {
    return "  ( " + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(c) + " " +
           std::to_string(d) + " ) ( ( 0.0078125 0 0 ) ( 0 0.0078125 0 ) ) \"textures/common/solid\" 0 0 0\n";
  };
  return "{\n brushDef3\n {\n" + side(0, 0, 1, -hi.z) + side(0, 0, -1, lo.z) + side(1, 0, 0, -hi.x) +
         side(-1, 0, 0, lo.x) + side(0, 1, 0, -hi.y) + side(0, -1, 0, lo.y) + " }\n}\n";
}

// A map: a floor in the worldspawn, then the entities given (key lines and
// primitives).
Result<LoadedWorld> worldFromText(const std::string& entities) {
  const std::string text = "Version 2\n{\n\"classname\" \"worldspawn\"\n" +
                           boxBrush({-1024, -1024, -16}, {1024, 1024, 0}) + "}\n" + entities;
  Result<MapFile> map = parseMapText(text, "placement.map");
  if (!map) return map.error();
  Result<BuildResult> built = buildCollisionModels(*map, MaterialTable{});
  if (!built) return built.error();
  return World::fromMap(*map, built->models);
}

void expectNear(const Vec3& a, const Vec3& b, Real tolerance = 1e-4f) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

std::filesystem::path twoHalls() { return test::testDataDir() / "maps" / "two_halls.map"; }

}  // namespace

TEST(WorldPlacement, OriginAngleAndRotationFromKeys) {
  // Each entity's brush is the local box x 0..32, y 0..16, z 0..8.
  const std::string brush = boxBrush({0, 0, 0}, {32, 16, 8});
  auto loaded = worldFromText(
      "{\n\"classname\" \"func_static\"\n\"name\" \"moved\"\n\"origin\" \"100 200 300\"\n" + brush + "}\n" +
      "{\n\"classname\" \"func_static\"\n\"name\" \"yawed\"\n\"origin\" \"0 0 64\"\n\"angle\" \"90\"\n" +
      brush + "}\n" +
      // rotation wins over angle: the rows (0,0,1), (0,1,0), (-1,0,0): local x
      // goes to world +z, local z to world -x.
      "{\n\"classname\" \"func_mover\"\n\"name\" \"tilted\"\n\"origin\" \"-50 0 0\"\n\"angle\" \"45\"\n"
      "\"rotation\" \"0 0 1 0 1 0 -1 0 0\"\n" +
      brush + "}\n" + "{\n\"classname\" \"info_player_start\"\n\"origin\" \"1 2 3\"\n}\n");
  ASSERT_TRUE(loaded.ok()) << loaded.error().toString();
  const World& world = loaded->world;
  ASSERT_EQ(world.size(), 4u);
  EXPECT_EQ(loaded->report.entitiesPlaced, 4);

  const WorldEntity* ws = world.entity(kWorldspawnEntity);
  ASSERT_NE(ws, nullptr);
  EXPECT_EQ(ws->name, "worldspawn");
  EXPECT_EQ(ws->className, "worldspawn");
  EXPECT_EQ(ws->mapEntity, 0);

  const WorldEntity* moved = world.entity(world.find("moved"));
  ASSERT_NE(moved, nullptr);
  EXPECT_EQ(moved->className, "func_static");
  EXPECT_EQ(moved->mapEntity, 1);
  EXPECT_EQ(moved->placement.origin, (Vec3{100, 200, 300}));
  EXPECT_TRUE(moved->placement.axis.isIdentity());
  expectNear(moved->bounds.min, {100, 200, 300});
  expectNear(moved->bounds.max, {132, 216, 308});
  EXPECT_EQ(moved->value("ORIGIN"), std::optional<std::string_view>("100 200 300"));

  // Yaw 90 about +z: rows (cos, sin, 0) = (0, 1, 0) and (-sin, cos, 0) =
  // (-1, 0, 0): local x -> world +y, local y -> world -x.
  const WorldEntity* yawed = world.entity(world.find("yawed"));
  ASSERT_NE(yawed, nullptr);
  expectNear(yawed->placement.axis[0], {0, 1, 0}, 1e-6f);
  expectNear(yawed->placement.axis[1], {-1, 0, 0}, 1e-6f);
  expectNear(yawed->placement.axis[2], {0, 0, 1}, 1e-6f);
  expectNear(yawed->bounds.min, {-16, 0, 64});
  expectNear(yawed->bounds.max, {0, 32, 72});

  const WorldEntity* tilted = world.entity(world.find("tilted"));
  ASSERT_NE(tilted, nullptr);
  EXPECT_EQ(tilted->placement.axis, Mat3({0, 0, 1}, {0, 1, 0}, {-1, 0, 0}));
  expectNear(tilted->bounds.min, {-58, 0, 0});
  expectNear(tilted->bounds.max, {-50, 16, 32});

  // The queries see the placed boxes: a point inside each, and outside.
  WorldQueryWork work;
  EXPECT_EQ(world.pointContents({{116, 208, 304}, {}}, work).entity, moved->id);
  EXPECT_EQ(world.pointContents({{-8, 16, 68}, {}}, work).entity, yawed->id);
  EXPECT_EQ(world.pointContents({{-54, 8, 16}, {}}, work).entity, tilted->id);
  EXPECT_EQ(world.pointContents({{8, 8, 4}, {}}, work).entity, kNoEntity);
  EXPECT_EQ(world.pointContents({{0, 0, -8}, {}}, work).entity, kWorldspawnEntity);
}

TEST(WorldPlacement, NoclipAndMeshEntitiesAreLeftOut) {
  const std::string brush = boxBrush({0, 0, 0}, {8, 8, 8});
  auto loaded = worldFromText(
      "{\n\"classname\" \"func_static\"\n\"name\" \"ghost\"\n\"noclipmodel\" \"1\"\n" + brush + "}\n" +
      "{\n\"classname\" \"func_static\"\n\"name\" \"statue\"\n"
      "\"model\" \"models/mapobjects/statue.lwo\"\n\"origin\" \"0 0 0\"\n}\n" +
      "{\n\"classname\" \"func_static\"\n\"origin\" \"64 0 0\"\n" + brush + "}\n");
  ASSERT_TRUE(loaded.ok()) << loaded.error().toString();
  EXPECT_EQ(loaded->world.size(), 2u);
  EXPECT_EQ(loaded->report.noclipSkipped, 1);
  EXPECT_EQ(loaded->report.meshModelsSkipped, 1);
  EXPECT_EQ(loaded->world.find("ghost"), kNoEntity);
  // Unnamed: "#N", N its map entity.
  EXPECT_NE(loaded->world.find("#3"), kNoEntity);
}

TEST(WorldPlacement, ModelCountMustMatchTheMap) {
  Result<MapFile> map = loadMapFile(twoHalls().string());
  ASSERT_TRUE(map.ok()) << map.error().toString();
  Result<BuildResult> built = buildCollisionModels(*map, MaterialTable{});
  ASSERT_TRUE(built.ok());
  built->models.pop_back();
  EXPECT_FALSE(World::fromMap(*map, built->models).ok());
}

TEST(WorldPlacement, FuncGroupsWithoutModelsAreInTheWorldModel) {
  // Models for every entity with primitives but the func_group (as tools
  // that merge func_groups into the world write them): the group is left
  // out and counted; with its model it is an entity as any other.
  const std::string text = "Version 2\n{\n\"classname\" \"worldspawn\"\n" +
                           boxBrush({-1024, -1024, -16}, {1024, 1024, 0}) + "}\n" +
                           "{\n\"classname\" \"func_group\"\n" + boxBrush({0, 0, 0}, {8, 8, 8}) + "}\n" +
                           "{\n\"classname\" \"func_static\"\n\"name\" \"crate\"\n\"origin\" \"64 0 0\"\n" +
                           boxBrush({-8, -8, 0}, {8, 8, 16}) + "}\n";
  Result<MapFile> map = parseMapText(text, "groups.map");
  ASSERT_TRUE(map.ok()) << map.error().toString();
  Result<BuildResult> built = buildCollisionModels(*map, MaterialTable{});
  ASSERT_TRUE(built.ok());
  ASSERT_EQ(built->models.size(), 3u);
  auto all = World::fromMap(*map, built->models);
  ASSERT_TRUE(all.ok()) << all.error().toString();
  EXPECT_EQ(all->world.size(), 3u);
  EXPECT_EQ(all->report.funcGroupsInWorld, 0);

  const std::vector<ModelPtr> merged = {built->models[0], built->models[2]};
  auto groups = World::fromMap(*map, merged);
  ASSERT_TRUE(groups.ok()) << groups.error().toString();
  EXPECT_EQ(groups->world.size(), 2u);
  EXPECT_EQ(groups->report.funcGroupsInWorld, 1);
  const EntityId crate = groups->world.find("crate");
  ASSERT_NE(crate, kNoEntity);
  EXPECT_EQ(groups->world.entity(crate)->model, built->models[2]);
  EXPECT_EQ(groups->world.entity(crate)->placement.origin, (Vec3{64, 0, 0}));
  // Any other count is still an error, naming the func_groups.
  const std::vector<ModelPtr> one = {built->models[0]};
  auto wrong = World::fromMap(*map, one);
  ASSERT_FALSE(wrong.ok());
  EXPECT_NE(wrong.error().message.find("func_group"), std::string::npos) << wrong.error().message;
}

TEST(WorldPlacement, RbdoomCmWithFuncGroupsMergedLoads) {
  // test_func_group_instancing.cm (RBDoom-3-BFG's tools, CC0, bundled) has
  // no models for the map's func_groups: its world model holds them.
  const auto path = test::dataFile("maps/rbdoom-unittests/test_func_group_instancing.map");
  auto loaded = World::loadMap(path.string(), MaterialTable{});
  ASSERT_TRUE(loaded.ok()) << loaded.error().toString();
  EXPECT_TRUE(loaded->report.models.fromCmFile);
  EXPECT_EQ(loaded->report.funcGroupsInWorld, 4);
  EXPECT_EQ(loaded->world.size(), 6u);
}

// The scenario: a player box walks from one hall to the other.
TEST(WorldDoor, PlayerStopsAtTheDoorAndPassesWhenItMoves) {
  auto loaded = World::loadMap(twoHalls().string(), MaterialTable{});
  ASSERT_TRUE(loaded.ok()) << loaded.error().toString();
  World& world = loaded->world;
  ASSERT_EQ(world.size(), 2u);  // worldspawn and the door
  const EntityId door = world.find("door1");
  ASSERT_NE(door, kNoEntity);
  // The door's brush (local x -32..32, y -4..4, z -48..48) turned by its
  // "angle" "90" and moved to its origin fills the doorway.
  expectNear(world.entity(door)->bounds.min, {-4, -32, 0});
  expectNear(world.entity(door)->bounds.max, {4, 32, 96});

  auto player = TraceModel::box({{-16, -16, 0}, {16, 16, 74}});
  ASSERT_TRUE(player.ok());
  TranslationQuery walk;
  walk.trm = &*player;
  walk.start = {-200, 0, 1};
  walk.end = {200, 0, 1};
  WorldQueryWork work;

  // Stops 0.25 in front of the door's face at x = -4: the box's front at
  // x = -4.25, its centre at -20.25.
  WorldTraceResult r = world.translate(walk, work);
  EXPECT_EQ(r.entity, door);
  EXPECT_NEAR(r.trace.fraction, (-20.25 + 200) / 400, 1e-5);
  EXPECT_NEAR(r.trace.endPos.x, -20.25, 1e-3);
  EXPECT_NEAR(r.trace.contact.normal.x, -1, 1e-6);

  // The world model alone lets the player through the doorway.
  QueryWork modelWork;
  const TraceResult alone = translate(*world.entity(kWorldspawnEntity)->model, walk, modelWork);
  EXPECT_EQ(alone.fraction, 1);

  // The door slides up into the ceiling (as a func_door opens): the player passes.
  Placement open = world.entity(door)->placement;
  open.origin.z += 96;
  ASSERT_TRUE(world.setPlacement(door, open).ok());
  expectNear(world.entity(door)->bounds.min, {-4, -32, 96});
  r = world.translate(walk, work);
  EXPECT_EQ(r.entity, kNoEntity);
  EXPECT_EQ(r.trace.fraction, 1);

  // Closed again: stopped again.
  open.origin.z -= 96;
  ASSERT_TRUE(world.setPlacement(door, open).ok());
  EXPECT_EQ(world.translate(walk, work).entity, door);

  // Left out by the filter (ignore list, then callback): passes.
  const EntityId ignore[] = {door};
  EXPECT_EQ(world.translate(walk, work, {ignore, {}}).trace.fraction, 1);
  EntityFilter noDoors;
  noDoors.accept = [](const WorldEntity& e) { return e.className != "func_door"; };
  EXPECT_EQ(world.translate(walk, work, noDoors).trace.fraction, 1);

  // Non-solid (setContents 0): passes; the mask decides too.
  ASSERT_TRUE(world.setContents(door, 0).ok());
  EXPECT_EQ(world.translate(walk, work).trace.fraction, 1);
  ASSERT_TRUE(world.setContents(door, world.entity(door)->model->contents()).ok());
  EXPECT_EQ(world.translate(walk, work).entity, door);

  // Removed: passes; its id is not reused.
  ASSERT_TRUE(world.removeEntity(door).ok());
  EXPECT_EQ(world.entity(door), nullptr);
  EXPECT_FALSE(world.setPlacement(door, open).ok());
  EXPECT_EQ(world.translate(walk, work).trace.fraction, 1);
  auto monster = world.addTraceModelEntity("monster", *player, {{100, 0, 1}, {}});
  ASSERT_TRUE(monster.ok());
  EXPECT_GT(*monster, door);
  // The player now stops at the monster: its box face at x = 84.
  r = world.translate(walk, work);
  EXPECT_EQ(r.entity, *monster);
  EXPECT_NEAR(r.trace.endPos.x, 84 - 16 - 0.25, 1e-3);
}

TEST(WorldDoor, RaysAndContactsNameTheDoor) {
  auto loaded = World::loadMap(twoHalls().string(), MaterialTable{});
  ASSERT_TRUE(loaded.ok()) << loaded.error().toString();
  const World& world = loaded->world;
  const EntityId door = world.find("door1");
  WorldQueryWork work;
  const WorldRayHit hit = world.castRay({{-200, 0, 40}, {200, 0, 40}}, work);
  EXPECT_EQ(hit.entity, door);
  EXPECT_NEAR(hit.hit.point.x, -4, 1e-3);
  // Along the dividing wall, the door and the lintel both touch.
  ContactsQuery cq;
  cq.start = {-10, 0, 100};
  cq.dir = {1, 0, 0};
  cq.depth = 20;
  cq.maxContacts = 8;
  const WorldContactsResult contacts = world.contacts(cq, work);
  ASSERT_FALSE(contacts.contacts.empty());
  EXPECT_EQ(contacts.contacts.front().entity, kWorldspawnEntity);
  // A position test inside the door names it.
  auto small = TraceModel::box({{-1, -1, -1}, {1, 1, 1}});
  ASSERT_TRUE(small.ok());
  const WorldContentsResult inside =
      world.contentsTest({&*small, {}, {0, 0, 50}, contents::kMaskSolid, {}}, work);
  EXPECT_EQ(inside.entity, door);
  EXPECT_NE(inside.result.contents, 0u);
}

// `cmkit query MAP QUERIES --world`: the same walk names the door.
TEST(WorldDoor, QueryCommandNamesTheEntityHit) {
  test::ScratchDir dir("world_query");
  const auto queries = dir.path() / "walk.txt";
  std::ofstream(queries) << "translation trm=box:-16,-16,0,16,16,74 start=-200,0,1 end=200,0,1\n"
                            "pointcontents pos=0,0,-8\n"
                            "translation trm=box:-16,-16,0,16,16,74 start=-200,0,1 end=0,0,1 origin=1,2,3\n";
  int rc = 0;
  const std::string out = test::runCapture(std::string(CMKIT_CLI_PATH) + " query '" + twoHalls().string() +
                                               "' '" + queries.string() + "' --world 2>/dev/null",
                                           rc);
  EXPECT_EQ(rc, 3) << out;  // the third line is an error line
  // 0.449375 printed as the float it is (0.449375004) or, in the double
  // build, as the double (0.449375).
  EXPECT_TRUE(out.find("fraction=0.449375004 ") != std::string::npos ||
              out.find("fraction=0.449375 ") != std::string::npos)
      << out;
  EXPECT_NE(out.find(" entity=door1\n"), std::string::npos) << out;
  EXPECT_NE(out.find("contents=3 entity=worldspawn\n"), std::string::npos) << out;
  EXPECT_NE(out.find("error=model=, origin= and modelaxis= do not apply"), std::string::npos) << out;
  // Without --world: the world model alone, no entity field.
  const std::string alone = test::runCapture(std::string(CMKIT_CLI_PATH) + " query '" + twoHalls().string() +
                                                 "' '" + queries.string() + "' 2>/dev/null",
                                             rc);
  EXPECT_EQ(alone.find("entity="), std::string::npos) << alone;
  EXPECT_NE(alone.find("fraction=1 "), std::string::npos) << alone;
}
