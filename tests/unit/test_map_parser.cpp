// The .map parser on hand-written input: structure, numbers, CRC, errors.
#include <cstring>
#include <string>

#include "cmkit/map.h"
#include "io/map_crc.h"
#include "test_support.h"
#include "text/text_cursor.h"

namespace {

using cmkit::buildCollisionModels;
using cmkit::CollisionModel;
using cmkit::MapBrush;
using cmkit::MapFile;
using cmkit::MapPatch;
using cmkit::Mat3;
using cmkit::MaterialTable;
using cmkit::parseMapText;
using cmkit::Real;
using cmkit::Vec3;

std::uint32_t bits(float f) {
  std::uint32_t u = 0;
  std::memcpy(&u, &f, sizeof u);
  return u;
}

std::string featuresMap() {
  return cmkit::test::readFile(cmkit::test::testDataDir() / "maps" / "features.map");
}

/// A one-brush map whose sides are `sides` (each a full side line).
std::string oneBrush(const std::string& sides, const std::string& header = "Version 2\n") {
  return header + "{\n\"classname\" \"worldspawn\"\n{\nbrushDef3\n{\n" + sides + "}\n}\n}\n";
}

const char* kSide = "( 0 0 1 -64 ) ( ( 0.0078125 0 0 ) ( 0 0.0078125 0 ) ) \"a\" 0 0 0\n";

/// Expects a parse error on `line` whose message contains `what`.
void expectError(const std::string& text, int line, const std::string& what) {
  auto r = parseMapText(text, "t.map");
  ASSERT_FALSE(r.ok()) << "parsed although it should fail: " << text;
  EXPECT_EQ(r.error().file, "t.map");
  EXPECT_EQ(r.error().line, line) << r.error().toString();
  EXPECT_GT(r.error().column, 0);
  EXPECT_NE(r.error().message.find(what), std::string::npos) << r.error().toString();
}

TEST(MapParser, ParsesEveryPrimitiveOfTheFeaturesMap) {
  auto r = parseMapText(featuresMap(), "features.map");
  ASSERT_TRUE(r.ok()) << r.error().toString();
  const MapFile& map = *r;
  EXPECT_EQ(map.fileName, "features.map");
  EXPECT_EQ(map.version, 2);
  ASSERT_EQ(map.entities.size(), 2u);
  const auto& world = map.entities[0];
  EXPECT_EQ(world.line, 6);
  EXPECT_EQ(world.value("CLASSNAME").value_or(""), "worldspawn");  // keys are case-insensitive
  ASSERT_EQ(world.primitives.size(), 1u);
  const auto& brush = std::get<MapBrush>(world.primitives[0]);
  EXPECT_EQ(brush.line, 10);
  ASSERT_EQ(brush.sides.size(), 6u);
  // "( a b c d )" means a x + b y + c z + d = 0: dist = -d. The world's
  // origin key does not move its brushes.
  EXPECT_EQ(brush.sides[0].plane.normal, (Vec3{0, 0, 1}));
  EXPECT_EQ(brush.sides[0].plane.dist, 64.0f);
  EXPECT_EQ(brush.sides[1].plane.dist, 0.0f);
  EXPECT_EQ(brush.sides[0].material, "textures/base_wall/a");
  EXPECT_EQ(brush.sides[5].material, "textures/common/clip");
  // "-0" is a '-' token applied to 0: negative zero.
  EXPECT_EQ(bits(brush.sides[5].plane.normal.x), 0x80000000u);

  const auto& ent = map.entities[1];
  EXPECT_EQ(ent.origin(), (Vec3{16, 32, 48}));
  ASSERT_EQ(ent.primitives.size(), 3u);
  // brushDef: plane through the points minus the origin, normal
  // (p1 - p2) x (p3 - p2) normalised, dist = normal . p2.
  const auto& old = std::get<MapBrush>(ent.primitives[0]);
  ASSERT_EQ(old.sides.size(), 4u);  // fewer than 4 would be kept too
  EXPECT_EQ(old.sides[0].plane.normal, (Vec3{0, 0, -1}));
  EXPECT_EQ(old.sides[0].plane.dist, 40.0f);  // -(8 - 48)
  EXPECT_EQ(old.sides[1].plane.normal, (Vec3{0, 0, 1}));
  EXPECT_EQ(old.sides[1].plane.dist, -48.0f);
  EXPECT_EQ(old.sides[2].plane.normal, (Vec3{-1, 0, 0}));
  EXPECT_EQ(old.sides[2].plane.dist, 8.0f);  // -(8 - 16)

  const auto& p2 = std::get<MapPatch>(ent.primitives[1]);
  EXPECT_FALSE(p2.explicitSubdivisions);
  EXPECT_EQ(p2.material, "textures/base_wall/curve");
  EXPECT_EQ(p2.width, 3);
  EXPECT_EQ(p2.height, 3);
  ASSERT_EQ(p2.points.size(), 9u);
  // File group j, point i -> points[i * width + j]; minus the origin.
  EXPECT_EQ(p2.points[0 * 3 + 1], (Vec3{64 - 16, 0 - 32, 0 - 48}));
  EXPECT_EQ(p2.points[1 * 3 + 0], (Vec3{0 - 16, 0 - 32, 32 - 48}));
  EXPECT_EQ(p2.points[2 * 3 + 2], (Vec3{64 - 16, 64 - 32, 64 - 48}));

  const auto& p3 = std::get<MapPatch>(ent.primitives[2]);
  EXPECT_TRUE(p3.explicitSubdivisions);
  EXPECT_EQ(p3.horzSubdivisions, 4);
  EXPECT_EQ(p3.vertSubdivisions, 2);
  EXPECT_EQ(map.geometryCrc, cmkit::detail::geometryCrc(map));
}

TEST(MapParser, GeometryCrcOfOneSideByHand) {
  auto r = parseMapText(oneBrush(kSide));
  ASSERT_TRUE(r.ok()) << r.error().toString();
  // bits(0) ^ bits(0) ^ bits(1.0f) ^ bits(-64.0f) ^ ('a' << 0)
  EXPECT_EQ(r->geometryCrc, 0x3F800000u ^ 0xC2800000u ^ 0x61u);
  // Material hash: byte i shifted by (i & 3), signed chars.
  EXPECT_EQ(cmkit::detail::stringCrc("abcde"), 0x61u ^ (0x62u << 1) ^ (0x63u << 2) ^ (0x64u << 3) ^ 0x65u);
  EXPECT_EQ(cmkit::detail::stringCrc("\xff"), 0xFFFFFFFFu);
}

TEST(MapParser, GeometryCrcOfPatchesIncludesSubdivisions) {
  auto r = parseMapText(featuresMap());
  ASSERT_TRUE(r.ok());
  const auto& p3 = std::get<MapPatch>(r->entities[1].primitives[2]);
  std::uint32_t expected = 4u ^ 2u;
  for (const Vec3& p : p3.points) expected ^= bits(p.x) ^ bits(p.y) ^ bits(p.z);
  expected ^= cmkit::detail::stringCrc("textures/base_wall/curve");
  EXPECT_EQ(cmkit::detail::patchCrc(p3), expected);
}

TEST(MapParser, NumbersAreReadLikeTheOriginalLexer) {
  using cmkit::detail::originalNumberValue;
  EXPECT_EQ(bits(*originalNumberValue("0.1")), 0x3DCCCCCDu);
  EXPECT_EQ(bits(*originalNumberValue("1.2e-05")), 0x3749539Cu);
  EXPECT_EQ(*originalNumberValue("1e+05"), 100000.0f);
  EXPECT_EQ(*originalNumberValue("2E3"), 2000.0f);
  EXPECT_EQ(*originalNumberValue(".5"), 0.5f);
  EXPECT_EQ(*originalNumberValue("5."), 5.0f);
  // Double accumulation of digits lands just below the float midpoint
  // 1 + 2^-24 where correct rounding (strtof) gives 0x3F800001.
  EXPECT_EQ(bits(*originalNumberValue("1.0000000596046448")), 0x3F800000u);
  EXPECT_EQ(bits(*originalNumberValue("1.000000298023224")), 0x3F800002u);
  EXPECT_FALSE(originalNumberValue("1.2.3"));
  EXPECT_FALSE(originalNumberValue("1e"));
  EXPECT_FALSE(originalNumberValue("12abc"));
  EXPECT_FALSE(originalNumberValue("."));
}

TEST(MapParser, NegativeZeroAndExponentsInPlanes) {
  auto r = parseMapText(oneBrush("( -0 1.2e-05 -1 -0 ) ( ( 1 0 0 ) ( 0 1 0 ) ) \"a\" 0 0 0\n"));
  ASSERT_TRUE(r.ok()) << r.error().toString();
  const auto& side = std::get<MapBrush>(r->entities[0].primitives[0]).sides[0];
  EXPECT_EQ(bits(side.plane.normal.x), 0x80000000u);
  EXPECT_EQ(bits(side.plane.normal.y), 0x3749539Cu);
  EXPECT_EQ(side.plane.normal.z, -1.0f);
  EXPECT_EQ(bits(side.plane.dist), 0u);  // d = -0, dist = -d = +0
  EXPECT_EQ(r->geometryCrc, 0x80000000u ^ 0x3749539Cu ^ bits(-1.0f) ^ 0x80000000u ^ 0x61u);
}

TEST(MapParser, Version3SidesWithoutTrailingIntegers) {
  const std::string v3 = oneBrush(
      "( 0 0 1 -64 ) ( ( 0.0078125 0 0 ) ( 0 0.0078125 0 ) ) \"a\"\n"
      "( 0 0 -1 0 ) ( ( 0.0078125 0 0 ) ( 0 0.0078125 0 ) ) \"a\"\n",
      "Version 3\n");
  auto r = parseMapText(v3);
  ASSERT_TRUE(r.ok()) << r.error().toString();
  EXPECT_EQ(r->version, 3);
  const auto& brush = std::get<MapBrush>(r->entities[0].primitives[0]);
  ASSERT_EQ(brush.sides.size(), 2u);
  EXPECT_EQ(brush.sides[1].plane.normal, (Vec3{0, 0, -1}));
  EXPECT_EQ(brush.sides[1].material, "a");
}

TEST(MapParser, CommentsBlankLinesAndLineEndings) {
  const std::string lf = featuresMap();
  std::string crlf;
  std::string cr;
  for (char c : lf) {
    if (c == '\n') {
      crlf += "\r\n";
      cr += '\r';
    } else {
      crlf += c;
      cr += c;
    }
  }
  auto a = parseMapText(lf);
  auto b = parseMapText(crlf);
  auto c = parseMapText(cr);
  ASSERT_TRUE(a.ok() && b.ok() && c.ok());
  EXPECT_EQ(a->geometryCrc, b->geometryCrc);
  EXPECT_EQ(a->geometryCrc, c->geometryCrc);
  EXPECT_EQ(b->entities[1].line, a->entities[1].line);
  EXPECT_EQ(c->entities[1].line, a->entities[1].line);
  EXPECT_EQ(std::get<MapPatch>(c->entities[1].primitives[2]).line,
            std::get<MapPatch>(a->entities[1].primitives[2]).line);

  // Errors report the same line whatever the line endings.
  std::string bad = "\n\nVersion 2\n{\n\"classname\" \"worldspawn\"\n{\nbrushDef3\n{\n( 0 0 1 x )\n";
  expectError(bad, 9, "a number in a plane equation");
  std::string badCrLf;
  std::string badCr;
  for (char ch : bad) {
    badCrLf += ch == '\n' ? std::string("\r\n") : std::string(1, ch);
    badCr += ch == '\n' ? '\r' : ch;
  }
  expectError(badCrLf, 9, "a number in a plane equation");
  expectError(badCr, 9, "a number in a plane equation");
  // A stray bare CR inside a side line does not break the side.
  auto stray = parseMapText(oneBrush("( 0 0 1 -64 ) ( ( 1 0 0 ) ( 0 1 0 ) ) \"a\"\r0 0 0\n"));
  ASSERT_TRUE(stray.ok()) << stray.error().toString();

  auto comments = parseMapText("/* header\n comment */ // line\nVersion /* inline */ 2 // x\n{ // e\n}\n");
  ASSERT_TRUE(comments.ok()) << comments.error().toString();
  EXPECT_EQ(comments->entities.size(), 1u);
}

TEST(MapParser, OldMapsAndQuake3Brushes) {
  // No Version line: version 1, "textures/" prefixed, keyword-less brushes.
  const std::string q3 =
      "{\n\"classname\" \"worldspawn\"\n{\n"
      "( 0 0 64 ) ( 64 0 64 ) ( 64 64 64 ) base_wall/stone 0 0 0 0.5 0.5 0 0 0\n"
      "( 0 0 0 ) ( 0 64 0 ) ( 64 64 0 ) \"base_wall/stone\" 0 0 0 0.5 0.5\n"
      "}\n}\n";
  auto r = parseMapText(q3);
  ASSERT_TRUE(r.ok()) << r.error().toString();
  EXPECT_EQ(r->version, 1);
  const auto& brush = std::get<MapBrush>(r->entities[0].primitives[0]);
  ASSERT_EQ(brush.sides.size(), 2u);
  EXPECT_EQ(brush.sides[0].material, "textures/base_wall/stone");
  EXPECT_EQ(brush.sides[0].plane.normal, (Vec3{0, 0, -1}));
  EXPECT_EQ(brush.sides[0].plane.dist, -64.0f);
  EXPECT_EQ(brush.sides[1].plane.normal, (Vec3{0, 0, 1}));
}

// A 64-unit box (0..64 on x and y, 0..16 on z) as TrenchBroom writes it in
// its "Doom 3 (Valve)" format: three points, material, two texture axes,
// rotation and scales, three flags (absent on the last side).
const std::string kValve220Box =
    "// Game: Doom 3 BFG\n// Format: Doom3 (Valve)\n{\n\"mapversion\" \"220\"\n"
    "\"classname\" \"worldspawn\"\n{\n"
    "( 0 0 0 ) ( 0 1 0 ) ( 0 0 1 ) base_wall/a [ 0 -1 0 0 ] [ 0 0 -1 0 ] 0 0.5 0.5 0 0 0\n"
    "( 0 0 0 ) ( 0 0 1 ) ( 1 0 0 ) base_wall/a [ 1 0 0 0 ] [ 0 0 -1 0 ] 0 0.5 0.5 0 0 0\n"
    "( 0 0 0 ) ( 1 0 0 ) ( 0 1 0 ) base_floor/b [ -1 0 0 0 ] [ 0 -1 0 0 ] 0 0.5 0.5 0 0 0\n"
    "( 64 64 16 ) ( 64 65 16 ) ( 65 64 16 ) base_floor/b [ 1 0 0 0 ] [ 0 -1 0 0 ] 0 0.5 0.5 0 0 0\n"
    "( 64 64 16 ) ( 65 64 16 ) ( 64 64 17 ) base_wall/a [ -1 0 0 0 ] [ 0 0 -1 0 ] 0 0.5 0.5 0 0 0\n"
    "( 64 64 16 ) ( 64 64 17 ) ( 64 65 16 ) common/caulk [ 0 1 0 -64.5 ] [ 0 0 -1 0 ] 12.5 -0.25 1\n"
    "}\n}\n";

TEST(MapParser, Valve220BrushesGiveThePlanesOfTheirPoints) {
  auto r = parseMapText(kValve220Box, "box.map");
  ASSERT_TRUE(r.ok()) << r.error().toString();
  EXPECT_EQ(r->version, 1);  // no Version line
  ASSERT_EQ(r->entities.size(), 1u);
  ASSERT_EQ(r->entities[0].primitives.size(), 1u);
  const auto& brush = std::get<MapBrush>(r->entities[0].primitives[0]);
  ASSERT_EQ(brush.sides.size(), 6u);
  EXPECT_EQ(brush.line, 6);
  // normal (p1-p2)x(p3-p2), through p2: outward faces of the box
  const Vec3 normals[6] = {{-1, 0, 0}, {0, -1, 0}, {0, 0, -1}, {0, 0, 1}, {0, 1, 0}, {1, 0, 0}};
  const Real dists[6] = {0, 0, 0, 16, 64, 64};
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(brush.sides[i].plane.normal, normals[i]) << "side " << i;
    EXPECT_EQ(brush.sides[i].plane.dist, dists[i]) << "side " << i;
  }
  // Material names get the textures/ folder, as in every map without a Version line.
  EXPECT_EQ(brush.sides[0].material, "textures/base_wall/a");
  EXPECT_EQ(brush.sides[5].material, "textures/common/caulk");
  auto models = buildCollisionModels(*r, MaterialTable{});
  ASSERT_TRUE(models.ok());
  ASSERT_EQ(models->models.size(), 1u);
  const CollisionModel& m = *models->models[0];
  EXPECT_EQ(m.vertices().size(), 8u);
  EXPECT_EQ(m.polygons().size(), 6u);
  EXPECT_EQ(m.brushes().size(), 1u);
  EXPECT_EQ(m.bounds().min, (Vec3{0, 0, 0}));
  EXPECT_EQ(m.bounds().max, (Vec3{64, 64, 16}));
}

TEST(MapParser, Valve220ErrorsGiveFileAndLine) {
  std::string bad = kValve220Box;
  bad.replace(bad.find("[ 0 0 -1 0 ] 0 0.5 0.5 0 0 0\n( 0 0 0 ) ( 1 0 0 )"), 12, "[ 0 0 -1 ]  ");
  expectError(bad, 8, "a number in the second Valve 220 texture axis");
  std::string noScale = kValve220Box;
  noScale.replace(noScale.find("12.5 -0.25 1"), 12, "12.5 -0.25 }");
  expectError(noScale, 12, "a Valve 220 texture rotation or scale");
  std::string noAxis = kValve220Box;
  noAxis.replace(noAxis.find("[ -1 0 0 0 ] [ 0 -1 0 0 ]"), 26, "[ -1 0 0 0 ] 0 0.5 0.5 0 0");
  expectError(noAxis, 9, "to start the second Valve 220 texture axis");
}

TEST(MapParser, EntityKeys) {
  auto r = parseMapText("{\n\"origin\" \"1 2\"\n\"Name\" \"a\"\n\"name\" \"b\"\n}\n");
  ASSERT_TRUE(r.ok());
  const auto& e = r->entities[0];
  EXPECT_EQ(e.keyValues.size(), 2u);  // a repeated key replaces the value
  EXPECT_EQ(e.value("NAME").value_or(""), "b");
  EXPECT_FALSE(e.value("classname"));
  EXPECT_EQ(e.origin(), (Vec3{1, 2, 0}));  // missing components stay 0
  auto junk = parseMapText("{\n\"origin\" \"junk\"\n}\n");
  ASSERT_TRUE(junk.ok());
  EXPECT_EQ(junk->entities[0].origin(), (Vec3{0, 0, 0}));
  EXPECT_EQ(cmkit::MapEntity{}.origin(), (Vec3{0, 0, 0}));
}

TEST(MapParser, EntityAxisFromRotationOrAngle) {
  auto r = parseMapText(
      "{\n\"rotation\" \"0 1 0 -1 0 0 0 0 1\"\n\"angle\" \"45\"\n}\n"
      "{\n\"angle\" \"90\"\n}\n"
      "{\n\"rotation\" \"0 1 0\"\n}\n"
      "{\n\"angle\" \"0\"\n}\n");
  ASSERT_TRUE(r.ok());
  ASSERT_EQ(r->entities.size(), 4u);
  // "rotation" holds the rows and wins over "angle".
  const Mat3 quarterTurn{{0, 1, 0}, {-1, 0, 0}, {0, 0, 1}};
  EXPECT_EQ(r->entities[0].axis(), quarterTurn);
  // A yaw of 90 degrees: forward becomes +y, left becomes -x (up to rounding).
  const Mat3 yaw = r->entities[1].axis();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(yaw[i][j], quarterTurn[i][j], 1e-6f) << i << "," << j;
  // A short "rotation" replaces the first entries only, like sscanf.
  EXPECT_EQ(r->entities[2].axis(), (Mat3{{0, 1, 0}, {0, 1, 0}, {0, 0, 1}}));
  EXPECT_EQ(r->entities[3].axis(), Mat3::identity());
  EXPECT_EQ(cmkit::MapEntity{}.axis(), Mat3::identity());
  // A local point goes to the world as local * axis + origin.
  EXPECT_EQ(Vec3(1, 0, 0) * quarterTurn, (Vec3{0, 1, 0}));
}

TEST(MapParser, EmptyInputIsAnEmptyMap) {
  auto r = parseMapText("");
  ASSERT_TRUE(r.ok());
  EXPECT_TRUE(r->entities.empty());
  EXPECT_EQ(r->geometryCrc, 0u);
}

TEST(MapParser, ErrorsSayWhatWasExpectedAndWhere) {
  expectError("Version 2\n{\n\"classname\" \"worldspawn\"\n{\nbrushDef4\n{\n}\n}\n}\n", 5,
              "unknown primitive 'brushDef4'");
  expectError(oneBrush("( 0 0 1 1.2.3 ) ( ( 1 0 0 ) ( 0 1 0 ) ) \"a\" 0 0 0\n"), 7, "bad number '1.2.3'");
  expectError("Version 1e30\n", 1, "the map version is out of range");  // found by fuzzing
  expectError("Version 1e39\n", 1, "the number 1e39 is not a finite float");
  expectError(oneBrush("( 0 0 1 -64 ) ( ( 1 0 0 ) ( 0 1 0 ) ) 0 0 0\n"), 7, "expected a material name");
  expectError(oneBrush("( 0 0 1 ) ( ( 1 0 0 ) ( 0 1 0 ) ) \"a\"\n"), 7, "a number in a plane equation");
  expectError("Version 2\n{\n\"classname\" \"worldspawn\"\n", 4, "the file ends inside the entity");
  expectError("Version 2\n{\n}\n}\n", 4, "expected '{' to start an entity");
  expectError("Version 2\n{\n\"classname\"\n}\n", 4, "expected the quoted value of key \"classname\"");
  expectError("Version 2\n{\nclassname \"x\"\n}\n", 3, "expected a quoted key");
  expectError("Version 2\n{\n\"classname\" \"x\n}\n", 3, "unterminated string");
  expectError("Version 2\n/* never closed\n{\n}\n", 2, "unterminated /* comment");
  expectError("Version x\n", 1, "the map version");
  expectError("Version 2\n{\n\"a\" \"b\"\n\x01\n}\n", 4, "unexpected control character");
  // brushDef side with collinear points.
  expectError(
      "{\n{\nbrushDef\n{\n( 0 0 0 ) ( 1 0 0 ) ( 2 0 0 ) ( ( 1 0 0 ) ( 0 1 0 ) ) \"a\" 0 0 0\n}\n}\n}\n", 5,
      "collinear");
}

std::string patchMap(const std::string& header, int groups = 3, int points = 3) {
  std::string s = "Version 2\n{\n\"classname\" \"worldspawn\"\n{\npatchDef2\n{\n\"a\"\n" + header + "\n(\n";
  for (int j = 0; j < groups; ++j) {
    s += "(";
    for (int i = 0; i < points; ++i) s += " ( " + std::to_string(j) + " " + std::to_string(i) + " 0 0 0 )";
    s += " )\n";
  }
  return s + ")\n}\n}\n}\n";
}

TEST(MapParser, PatchDimensionsAreChecked) {
  ASSERT_TRUE(parseMapText(patchMap("( 3 3 0 0 0 )")).ok());
  ASSERT_TRUE(parseMapText(patchMap("( 5 3 0 0 0 )", 5, 3)).ok());
  expectError(patchMap("( 2 2 0 0 0 )", 2, 2), 8, "width and height must be odd and at least 3");
  expectError(patchMap("( 3 4 0 0 0 )", 3, 4), 8, "must be odd");
  expectError(patchMap("( 0 0 0 0 0 )", 0, 0), 8, "must be odd");
  expectError(patchMap("( 1 3 0 0 0 )", 1, 3), 8, "at least 3");
  expectError(patchMap("( 3 3.5 0 0 0 )"), 8, "whole number");
  expectError(patchMap("( -3 3 0 0 0 )"), 8, "whole number");
  expectError(patchMap("( 3 3 0 0 )"), 8, "patchDef2 header");
  // Too few points in a column.
  expectError(patchMap("( 3 5 0 0 0 )", 3, 3), 10, "patch control point");
  // patchDef3 needs 7 numbers and subdivisions >= 1.
  std::string def3 = patchMap("( 3 3 0 2 0 0 0 )");
  def3.replace(def3.find("patchDef2"), 9, "patchDef3");
  expectError(def3, 8, "subdivisions must be at least 1");
}

TEST(MapParser, EveryPrefixOfAMapIsAnErrorOrAMap) {
  const std::string text = featuresMap();
  int ok = 0;
  for (std::size_t n = 0; n <= text.size(); ++n) {
    auto r = parseMapText(std::string_view(text).substr(0, n), "prefix.map");
    if (r.ok()) {
      ++ok;
      EXPECT_EQ(r->geometryCrc, cmkit::detail::geometryCrc(*r));
    } else {
      EXPECT_FALSE(r.error().message.empty());
      EXPECT_GT(r.error().line, 0);
    }
  }
  EXPECT_GT(ok, 1);  // the empty prefix, the full file and a few in between
  EXPECT_LT(ok, 100);
}

TEST(MapParser, MissingFileIsAnError) {
  auto r = cmkit::loadMapFile("/nonexistent/dir/x.map");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().file, "/nonexistent/dir/x.map");
}

}  // namespace

namespace {

TEST(MapParser, RandomCorruptionNeverCrashes) {
  // Deterministic byte mutations of a real map: each gives an error or a map.
  const std::string original = featuresMap();
  const std::string alphabet = "{}()\"-.e0123456789 \n\r/*xbrushDef3patchDef";
  std::uint32_t state = 12345;
  auto random = [&state] {
    state = state * 1664525u + 1013904223u;
    return state >> 8;
  };
  int parsed = 0;
  for (int round = 0; round < 3000; ++round) {
    std::string text = original;
    const int edits = 1 + static_cast<int>(random() % 4);
    for (int e = 0; e < edits; ++e) {
      const std::size_t at = random() % text.size();
      switch (random() % 3) {
        case 0:
          text[at] = alphabet[random() % alphabet.size()];
          break;
        case 1:
          text.erase(at, 1 + random() % 8);
          break;
        default:
          text.insert(at, 1, alphabet[random() % alphabet.size()]);
          break;
      }
      if (text.empty()) text = "{";
    }
    auto r = parseMapText(text, "fuzz.map");
    if (r.ok()) {
      ++parsed;
    } else {
      EXPECT_GT(r.error().line, 0) << r.error().toString();
    }
  }
  EXPECT_GT(parsed, 0);
}

}  // namespace
