// Material names -> contents: canonical names, default rules, .mtr files,
// and the contents and materials they give a map's brushes and polygons
// (water_clip.map, checked by hand).
#include <filesystem>
#include <fstream>

#include "cmkit/compile.h"
#include "cmkit/contents.h"
#include "cmkit/map.h"
#include "cmkit/materials.h"
#include "cmkit/query.h"
#include "test_support.h"

namespace {

using cmkit::MaterialTable;
namespace c = cmkit::contents;

TEST(Material, CanonicalNames) {
  EXPECT_EQ(MaterialTable::canonicalName("Textures\\Base_Wall\\LfWall27d.TGA"),
            "textures/base_wall/lfwall27d");
  EXPECT_EQ(MaterialTable::canonicalName("textures/common/clip"), "textures/common/clip");
  EXPECT_EQ(MaterialTable::canonicalName("a.b.c"), "a.b");  // the last dot only
  EXPECT_EQ(MaterialTable::canonicalName(""), "");
}

TEST(Material, EveryDefaultRuleRow) {
  struct Row {
    const char* name;
    std::uint32_t contents;
  };
  const Row rows[] = {
      {"textures/common/clip", c::kPlayerClip | c::kMonsterClip | c::kMoveableClip},
      {"textures/common/player_clip", c::kPlayerClip},
      {"textures/common/monster_clip", c::kMonsterClip},
      {"textures/common/nodraw", c::kSolid | c::kOpaque},
      {"textures/common/caulk", c::kSolid | c::kOpaque},
      {"textures/common/nodrawsolid", c::kSolid},
      {"textures/common/trigger", c::kTrigger},
      {"textures/common/trigmulti", c::kSolid | c::kOpaque},  // not "trigger..."
      {"textures/common/triggerwater", c::kTrigger},          // trigger row comes before water
      {"textures/common/trigger_hurt", c::kTrigger},
      {"textures/common/noclip", 0},
      {"textures/common/noclipwater", 0},  // noclip row comes before water
      {"textures/editor/entityGui", 0},
      {"textures/editor/water", 0},
      {"textures/liquids/water1", c::kWater},
      {"textures/base/dirtywaterfall", c::kWater},
      {"water", c::kWater},
      {"textures/common/clipx", c::kSolid | c::kOpaque},  // "exactly" rows are exact
      {"textures/common/clip/more", c::kSolid | c::kOpaque},
      {"textures/base_wall/lfwall27d", c::kSolid | c::kOpaque},
      {"", c::kSolid | c::kOpaque},
  };
  MaterialTable table;
  for (const Row& r : rows) {
    SCOPED_TRACE(r.name);
    EXPECT_EQ(MaterialTable::defaultInfo(MaterialTable::canonicalName(r.name)).contents, r.contents);
    EXPECT_FALSE(MaterialTable::defaultInfo(MaterialTable::canonicalName(r.name)).twoSided);
    EXPECT_EQ(table.contents(r.name), r.contents);
  }
  // Lookups canonicalise first.
  EXPECT_EQ(table.contents("TEXTURES\\COMMON\\CLIP.tga"),
            c::kPlayerClip | c::kMonsterClip | c::kMoveableClip);
  EXPECT_EQ(table.contents("textures/Editor/x"), 0u);
}

constexpr const char* kMtr = R"mtr(
// A comment, then a table (skipped) and a material.
table sinTable { snap { 0, 1, 0, -1 } }
table   flat { { 1 } }

textures/test/glass
{
  qer_editorimage textures/test/glass.tga
  translucent
  twosided
  {
    blend blend
    map textures/test/glass_d.tga
    // 'nonsolid' inside a stage does not count:
    nonsolid
  }
}

material textures/test/Clip_Player {
  NonSolid
  playerclip
}

sound test_sound { wave.wav }
particle test_fx { { count 3 } }
skin test_skin { model x.lwo }

textures/test/pool {
  water
  translucent
  { map x }
}

textures/test/broken {
  solid
  { map x
}
)mtr";

TEST(Material, MtrKeywordsStagesTablesAndOtherDecls) {
  MaterialTable table;
  table.addMtrText(kMtr, "test.mtr");
  // glass, clip_player, pool; "broken" is unterminated and swallowed the
  // rest of the file, so it is skipped with a warning.
  EXPECT_EQ(table.numDeclared(), 3u);
  const auto glass = table.info("textures/test/glass");
  EXPECT_EQ(glass.contents, c::kSolid);  // translucent removes opaque
  EXPECT_TRUE(glass.twoSided);
  EXPECT_EQ(table.contents("textures/test/clip_player.tga"), c::kOpaque | c::kPlayerClip);
  EXPECT_EQ(table.contents("textures/test/pool"), c::kWater);       // water clears solid
  EXPECT_EQ(table.contents("test_sound"), c::kSolid | c::kOpaque);  // not a material: default
  EXPECT_EQ(table.contents("sinTable"), c::kSolid | c::kOpaque);
  EXPECT_EQ(table.contents("textures/test/broken"), c::kSolid | c::kOpaque);
  ASSERT_FALSE(table.warnings().empty());
  EXPECT_NE(table.warnings()[0].find("test.mtr:34:1:"), std::string::npos) << table.warnings()[0];
  EXPECT_NE(table.warnings()[0].find("missing '}'"), std::string::npos) << table.warnings()[0];
  // Declared materials win over the default rules.
  MaterialTable clip;
  clip.addMtrText("textures/common/clip { nonsolid monsterclip }", "c.mtr");
  EXPECT_EQ(clip.contents("textures/common/clip"), c::kOpaque | c::kMonsterClip);
}

TEST(Material, EveryContentKeyword) {
  struct K {
    const char* keyword;
    std::uint32_t contents;
  };
  const std::uint32_t so = c::kSolid | c::kOpaque;
  const K keywords[] = {
      {"solid", so},
      {"nonsolid", c::kOpaque},
      {"water", c::kOpaque | c::kWater},
      {"playerclip", so | c::kPlayerClip},
      {"monsterclip", so | c::kMonsterClip},
      {"moveableclip", so | c::kMoveableClip},
      {"ikclip", so | c::kIkClip},
      {"blood", so | c::kBlood},
      {"trigger", so | c::kTrigger},
      {"aassolid", so | c::kAasSolid},
      {"aasobstacle", so | c::kAasObstacle},
      {"flashlight_trigger", so | c::kFlashlightTrigger},
      {"areaportal", c::kOpaque | c::kAreaPortal},
      {"nocsg", c::kOpaque | c::kNoCsg},
      {"qer_nocarve", c::kOpaque | c::kNoCsg},
      {"translucent", c::kSolid},
      {"twosided", so},
      {"diffusemap", so},
  };
  for (const K& k : keywords) {
    SCOPED_TRACE(k.keyword);
    MaterialTable table;
    table.addMtrText(std::string("m { ") + k.keyword + " }", "k.mtr");
    EXPECT_TRUE(table.warnings().empty());
    EXPECT_EQ(table.contents("m"), k.contents);
  }
}

TEST(Material, SyntaxErrorsAreWarningsAndTheRestIsRead) {
  MaterialTable table;
  table.addMtrText(
      "textures/a { playerclip }\n"
      "} // stray brace\n"
      "textures/b nonsolid\n"       // no '{' after the name
      "textures/c { nonsolid }\n"   // still read
      "\"textures/d\" { 12abc }\n"  // a bad token: this declaration is skipped
      "textures/e { water }\n"
      "textures/a { nonsolid }\n"     // a second declaration: the first wins
      "table { }\n"                   // a table without a name
      "textures/f { trigger } 42\n",  // a number where a name should be
      "bad.mtr");
  EXPECT_EQ(table.contents("textures/a"), c::kSolid | c::kOpaque | c::kPlayerClip);
  EXPECT_EQ(table.contents("textures/c"), c::kOpaque);
  EXPECT_EQ(table.contents("textures/d"), c::kSolid | c::kOpaque);  // default rules
  EXPECT_EQ(table.contents("textures/e"), c::kOpaque | c::kWater);
  EXPECT_EQ(table.contents("textures/f"), c::kSolid | c::kOpaque | c::kTrigger);
  std::string all;
  for (const auto& w : table.warnings()) all += w + "\n";
  EXPECT_NE(all.find("bad.mtr:2:1: expected a declaration name, found '}'"), std::string::npos) << all;
  EXPECT_NE(all.find("bad.mtr:3:1: expected '{' after the declaration name 'textures/b'"), std::string::npos)
      << all;
  EXPECT_NE(all.find("bad.mtr:5:16: bad number '12abc'"), std::string::npos) << all;
  EXPECT_NE(all.find("bad.mtr:5:1: declaration \"textures/d\" skipped"), std::string::npos) << all;
  EXPECT_NE(all.find("bad.mtr:7:1: material 'textures/a' is declared again"), std::string::npos) << all;
  EXPECT_NE(all.find("bad.mtr:8:1: expected a name after 'table'"), std::string::npos) << all;
  EXPECT_NE(all.find("bad.mtr:9:24: expected a declaration name, found '42'"), std::string::npos) << all;
}

TEST(Material, FilesAndDirectories) {
  namespace fs = std::filesystem;
  const fs::path dir =
      fs::temp_directory_path() /
      ("cmkit_mtr_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
  fs::remove_all(dir);
  fs::create_directories(dir / "sub");
  std::ofstream(dir / "b.mtr") << "textures/x { water }\n";
  std::ofstream(dir / "sub" / "a.MTR") << "textures/y { nonsolid }\n";
  std::ofstream(dir / "ignored.txt") << "textures/z { nonsolid }\n";
  MaterialTable table;
  ASSERT_TRUE(table.addMtrDirectory(dir.string()).ok());
  EXPECT_EQ(table.numDeclared(), 2u);
  EXPECT_EQ(table.contents("textures/x"), c::kOpaque | c::kWater);
  EXPECT_EQ(table.contents("textures/y"), c::kOpaque);
  EXPECT_EQ(table.contents("textures/z"), c::kSolid | c::kOpaque);
  MaterialTable one;
  ASSERT_TRUE(one.addMtrFile((dir / "b.mtr").string()).ok());
  EXPECT_EQ(one.numDeclared(), 1u);
  EXPECT_FALSE(one.addMtrFile((dir / "missing.mtr").string()).ok());
  EXPECT_FALSE(one.addMtrDirectory((dir / "missing").string()).ok());
  fs::remove_all(dir);
}

}  // namespace

namespace {

TEST(Material, RandomCorruptionNeverCrashes) {
  const std::string original = kMtr;
  const std::string alphabet = "{}\"/*\n 1e.x";
  std::uint32_t state = 777;
  auto random = [&state] {
    state = state * 1664525u + 1013904223u;
    return state >> 8;
  };
  for (int round = 0; round < 2000; ++round) {
    std::string text = original;
    for (int e = 0; e < 3; ++e) {
      const std::size_t at = random() % text.size();
      if (random() % 2) {
        text[at] = alphabet[random() % alphabet.size()];
      } else {
        text.erase(at, 1 + random() % 5);
      }
    }
    MaterialTable table;
    table.addMtrText(text, "fuzz.mtr");
    EXPECT_LE(table.numDeclared(), 12u);  // mutations may turn other decls into materials
  }
}

}  // namespace

// ---- a map's brushes and polygons -------------------------------------------

namespace {

/// The models of water_clip.map (the project's own map, bundled in
/// tests/data/shared/maps/synthetic; one brush per material rule,
/// docs/materials.md) built with `materials`.
std::vector<cmkit::ModelPtr> waterClipModels(const MaterialTable& materials) {
  auto map = cmkit::loadMapFile(cmkit::test::dataFile("maps/synthetic/water_clip.map").string());
  EXPECT_TRUE(map.ok()) << (map.ok() ? "" : map.error().toString());
  if (!map) return {};
  auto models = cmkit::buildCollisionModels(*map, materials);
  EXPECT_TRUE(models.ok()) << (models.ok() ? "" : models.error().toString());
  return models ? models->models : std::vector<cmkit::ModelPtr>{};
}

/// The name of the material of the brush containing `p` (the only one).
std::string brushMaterialAt(const cmkit::CollisionModel& m, const cmkit::Vec3& p) {
  std::string name;
  int found = 0;
  for (const cmkit::CmBrush& b : m.brushes()) {
    bool inside = b.bounds.containsPoint(p);
    for (const cmkit::Plane& plane : m.planesOf(b)) inside = inside && plane.distance(p) < 0;
    if (!inside) continue;
    ++found;
    name = b.material >= 0 ? m.materials()[std::size_t(b.material)] : "-";
  }
  return found == 1 ? name : "(" + std::to_string(found) + " brushes)";
}

}  // namespace

TEST(MaterialsOnAMap, BrushContentsAndMaterialsFollowTheDefaultRules) {
  // Hand-read from the map: each brush's box, its material and the
  // contents the default rules (docs/materials.md) give it.
  const auto models = waterClipModels(MaterialTable{});
  ASSERT_EQ(models.size(), 3u);  // worldspawn, trigger_once_1, func_liquid_1
  const cmkit::CollisionModel& world = *models[0];
  struct Probe {
    cmkit::Vec3 point;
    std::uint32_t contents;
    const char* material;  // of the brush there ("(0 brushes)": none kept)
  };
  const Probe probes[] = {
      {{-250, -250, 32}, c::kWater, "textures/liquids/water_calm"},     // primitive 6
      {{8, -256, 64}, c::kPlayerClip, "textures/common/player_clip"},   // 7
      {{8, 128, 64}, c::kMonsterClip, "textures/common/monster_clip"},  // 8
      {{232, 232, 32}, c::kPlayerClip | c::kMonsterClip | c::kMoveableClip, "textures/common/clip"},  // 9
      {{232, -232, 32}, c::kSolid | c::kOpaque, "textures/common/nodraw"},                            // 10
      {{332, -232, 32}, c::kSolid, "textures/common/nodrawsolid"},                                    // 11
      {{332, 232, 32}, 0, "(0 brushes)"},  // 12: noclip has no contents
      {{432, 232, 32}, 0, "(0 brushes)"},  // 13: textures/editor/ has none
      // 14: a wall top over caulk sides; the brush takes the material of
      // the second-to-last side (caulk).
      {{-268, 332, 48}, c::kSolid | c::kOpaque, "textures/common/caulk"},
      // 15: noclip sides but the last: the contents leave out the last
      // side, so no brush is kept.
      {{-125, 325, 25}, 0, "(0 brushes)"},
      {{140, 370, 40}, c::kWater, "textures/liquids/water_murky"},               // 16 alone
      {{200, 450, 20}, c::kSolid | c::kOpaque, "textures/base_wall/lfwall27d"},  // 17 alone
      {{-500, 0, 512}, 0, "(0 brushes)"},                                        // the room's air
  };
  for (const Probe& p : probes) {
    SCOPED_TRACE(::testing::Message() << p.point.x << "," << p.point.y << "," << p.point.z);
    EXPECT_EQ(cmkit::test::pointContentsAt(world, p.point), p.contents);
    EXPECT_EQ(brushMaterialAt(world, p.point), p.material);
  }
  // Where 16 (water) and 17 (wall) overlap: both.
  EXPECT_EQ(cmkit::test::pointContentsAt(world, {160, 410, 20}), c::kWater | c::kSolid | c::kOpaque);
  // The inline models: the trigger in its own frame (brushes relative to
  // the entity's origin), the liquid likewise.
  EXPECT_EQ(models[1]->name(), "trigger_once_1");
  EXPECT_EQ(cmkit::test::pointContentsAt(*models[1], {0, 0, 64}), c::kTrigger);
  EXPECT_EQ(cmkit::test::pointContentsAt(*models[1], {0, 0, 140}), 0u);
  EXPECT_EQ(models[2]->name(), "func_liquid_1");
  EXPECT_EQ(cmkit::test::pointContentsAt(*models[2], {0, 0, 16}), c::kWater);
}

TEST(MaterialsOnAMap, PolygonsTakeTheirSidesContentsAndMaterials) {
  // Brush 15's last side (y = 300, wall) still makes a polygon although its
  // brush was dropped; brush 14's top is wall, its other sides caulk.
  const auto models = waterClipModels(MaterialTable{});
  ASSERT_FALSE(models.empty());
  const cmkit::CollisionModel& world = *models[0];
  cmkit::QueryWork work;
  const auto pointTrace = [&](const cmkit::Vec3& from, const cmkit::Vec3& to) {
    cmkit::TranslationQuery q;
    q.start = from;
    q.end = to;
    q.contentMask = cmkit::contents::kMaskAll;
    return cmkit::translate(world, q, work);
  };
  const auto materialOf = [&](const cmkit::TraceResult& r) {
    return r.contact.material >= 0 ? world.materials()[std::size_t(r.contact.material)] : std::string("-");
  };
  // Into brush 15's wall side from -y.
  cmkit::TraceResult r = pointTrace({-125, 250, 25}, {-125, 350, 25});
  ASSERT_LT(r.fraction, 1);
  EXPECT_EQ(r.contact.normal, cmkit::Vec3(0, -1, 0));
  EXPECT_EQ(r.contact.contents, c::kSolid | c::kOpaque);
  EXPECT_EQ(materialOf(r), "textures/base_wall/lfwall27d");
  // Onto brush 14's top (wall) and into its side (caulk).
  r = pointTrace({-268, 332, 200}, {-268, 332, 50});
  ASSERT_LT(r.fraction, 1);
  EXPECT_EQ(r.contact.normal, cmkit::Vec3(0, 0, 1));
  EXPECT_EQ(materialOf(r), "textures/base_wall/lfwall27d");
  r = pointTrace({-200, 332, 48}, {-268, 332, 48});
  ASSERT_LT(r.fraction, 1);
  EXPECT_EQ(r.contact.normal, cmkit::Vec3(1, 0, 0));
  EXPECT_EQ(r.contact.contents, c::kSolid | c::kOpaque);
  EXPECT_EQ(materialOf(r), "textures/common/caulk");
  // Into the water (brush 6) from above: water contents and material.
  r = pointTrace({-250, -250, 100}, {-250, -250, 10});
  ASSERT_LT(r.fraction, 1);
  EXPECT_EQ(r.contact.contents, c::kWater);
  EXPECT_EQ(materialOf(r), "textures/liquids/water_calm");
}

TEST(MaterialsOnAMap, MtrDeclarationsOverrideTheDefaultRules) {
  // caulk declared nonsolid + playerclip (opaque | playerclip), noclip
  // declared solid: brush 14 is wall | caulk = solid, opaque, playerclip;
  // brush 12 (all noclip) now exists; brush 15 too (its contents leave out
  // only the last side).
  MaterialTable table;
  table.addMtrText(
      "textures/common/caulk { nonsolid playerclip }\n"
      "textures/common/noclip { solid }\n",
      "override.mtr");
  ASSERT_TRUE(table.warnings().empty());
  const auto models = waterClipModels(table);
  ASSERT_FALSE(models.empty());
  const cmkit::CollisionModel& world = *models[0];
  EXPECT_EQ(cmkit::test::pointContentsAt(world, {-268, 332, 48}), c::kSolid | c::kOpaque | c::kPlayerClip);
  EXPECT_EQ(cmkit::test::pointContentsAt(world, {332, 232, 32}), c::kSolid | c::kOpaque);
  EXPECT_EQ(brushMaterialAt(world, {332, 232, 32}), "textures/common/noclip");
  EXPECT_EQ(cmkit::test::pointContentsAt(world, {-125, 325, 25}), c::kSolid | c::kOpaque);
  // Undeclared materials keep the default rules.
  EXPECT_EQ(cmkit::test::pointContentsAt(world, {232, 232, 32}),
            c::kPlayerClip | c::kMonsterClip | c::kMoveableClip);
}
