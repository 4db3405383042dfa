// Bad input gives a clear Error (or, in the CLI, a message and exit code 2),
// never an exception, an abort or a number that is not finite (issue #17 §3).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cmkit/cm_file.h"
#include "cmkit/manager.h"
#include "cmkit/map.h"
#include "cmkit/materials.h"
#include "cmkit/text_file.h"
#include "cmkit/tools/query_format.h"
#include "test_support.h"

namespace {

namespace fs = std::filesystem;
using cmkit::test::runCapture;

const std::string kBom = "\xEF\xBB\xBF";

const char* const kBoxMap =
    "Version 2\n"
    "{\n\"classname\" \"worldspawn\"\n"
    "{\nbrushDef3\n{\n"
    "( 0 0 -1 0 ) ( ( 1 0 0 ) ( 0 1 0 ) ) \"textures/a\" 0 0 0\n"
    "( 0 0 1 -64 ) ( ( 1 0 0 ) ( 0 1 0 ) ) \"textures/a\" 0 0 0\n"
    "( 0 -1 0 0 ) ( ( 1 0 0 ) ( 0 1 0 ) ) \"textures/a\" 0 0 0\n"
    "( 0 1 0 -64 ) ( ( 1 0 0 ) ( 0 1 0 ) ) \"textures/a\" 0 0 0\n"
    "( -1 0 0 0 ) ( ( 1 0 0 ) ( 0 1 0 ) ) \"textures/a\" 0 0 0\n"
    "( 1 0 0 -64 ) ( ( 1 0 0 ) ( 0 1 0 ) ) \"textures/a\" 0 0 0\n"
    "}\n}\n}\n";

/// A scratch directory, removed at the end of the test.
class BadInput : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("cmkit_bad_input_" + std::to_string(getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(dir_ / name, std::ios::binary) << text;
    return path(name);
  }
  fs::path dir_;
};

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

TEST_F(BadInput, EveryLoaderRefusesADirectoryAndAMissingFile) {
  const std::string d = path("x.cm");
  fs::create_directories(d);
  const cmkit::MaterialTable materials;
  for (const std::string& p : {d, path("missing.cm")}) {
    const bool isDir = p == d;
    const std::string why = isDir ? "is a directory" : "no such file";
    auto cm = cmkit::loadCmFile(p, materials);
    ASSERT_FALSE(cm.ok());
    EXPECT_EQ(cm.error().file, p);
    EXPECT_TRUE(contains(cm.error().message, why)) << cm.error().toString();
    auto crc = cmkit::readCmFileCrc(p);
    ASSERT_FALSE(crc.ok());
    EXPECT_TRUE(contains(crc.error().message, why)) << crc.error().toString();
    auto map = cmkit::loadMapFile(p);
    ASSERT_FALSE(map.ok());
    EXPECT_TRUE(contains(map.error().message, why)) << map.error().toString();
    cmkit::MaterialTable table;
    auto mtr = table.addMtrFile(p);
    ASSERT_FALSE(mtr.ok());
    EXPECT_TRUE(contains(mtr.error().message, why)) << mtr.error().toString();
    auto text = cmkit::readTextFile(p);
    ASSERT_FALSE(text.ok());
    EXPECT_EQ(text.error().toString(), p + ": " + text.error().message);
    cmkit::ModelManager manager;
    auto loaded = manager.loadCm(p, materials);
    ASSERT_FALSE(loaded.ok());
    EXPECT_TRUE(contains(loaded.error().message, why));
    auto loadedMap = manager.loadMap(p, materials);
    ASSERT_FALSE(loadedMap.ok());
    EXPECT_EQ(manager.size(), 0u);
  }
}

TEST_F(BadInput, UnreadableFileIsAnError) {
  if (geteuid() == 0) GTEST_SKIP() << "running as root: every file is readable";
  const std::string p = write("locked.map", kBoxMap);
  fs::permissions(p, fs::perms::none);
  auto map = cmkit::loadMapFile(p);
  ASSERT_FALSE(map.ok());
  EXPECT_TRUE(contains(map.error().message, "permission denied")) << map.error().toString();
}

TEST_F(BadInput, ReadTextFileStopsAtMaxBytes) {
  const std::string p = write("a.txt", "abcdef");
  auto all = cmkit::readTextFile(p);
  ASSERT_TRUE(all.ok());
  EXPECT_EQ(*all, "abcdef");
  auto head = cmkit::readTextFile(p, 4);
  ASSERT_TRUE(head.ok());
  EXPECT_EQ(*head, "abcd");
}

TEST(BadInputText, MapNumbersMustBeFinite) {
  std::string text = kBoxMap;
  text.replace(text.find("-64 )"), 3, "1e999");  // line 6: ( 0 0 1 1e999 )
  auto map = cmkit::parseMapText(text, "inf.map");
  ASSERT_FALSE(map.ok());
  EXPECT_EQ(map.error().toString(), "inf.map:8:9: the number 1e999 is not a finite float (beyond 3.4e38)");

  for (const char* value : {"inf 0 0", "0 nan 0", "0 0 1e999"}) {
    const std::string withOrigin =
        std::string("Version 2\n{\n\"classname\" \"func_static\"\n\"origin\" \"") + value + "\"\n}\n";
    auto m = cmkit::parseMapText(withOrigin, "origin.map");
    ASSERT_FALSE(m.ok()) << value;
    EXPECT_EQ(m.error().line, 4) << m.error().toString();
    EXPECT_EQ(m.error().column, 10) << m.error().toString();
    EXPECT_TRUE(contains(m.error().message, "not a finite float")) << m.error().toString();
  }
  auto angle = cmkit::parseMapText("{\n\"classname\" \"x\"\n\"angle\" \"nan\"\n}\n", "a.map");
  ASSERT_FALSE(angle.ok());
  EXPECT_EQ(angle.error().line, 3);
  // A large finite number is still a number.
  std::string big = kBoxMap;
  big.replace(big.find("-64 )"), 3, "1e30");
  EXPECT_TRUE(cmkit::parseMapText(big, "big.map").ok());
}

TEST(BadInputText, CmNumbersMustBeFinite) {
  const std::string text = "CM \"1.00\"\n0\ncollisionModel \"x\" {\n vertices { 1\n ( 0 1e999 0 )\n }\n}\n";
  auto cm = cmkit::parseCmText(text, "inf.cm", cmkit::MaterialTable{});
  ASSERT_FALSE(cm.ok());
  EXPECT_EQ(cm.error().file, "inf.cm");
  EXPECT_EQ(cm.error().line, 5);
  EXPECT_TRUE(contains(cm.error().message, "not a finite float")) << cm.error().toString();
}

TEST(BadInputText, QueryNumbersMustBeFinite) {
  const auto models = cmkit::test::buildMapModels(cmkit::test::testDataDir() / "maps" / "features.map");
  ASSERT_FALSE(models.empty());
  cmkit::QueryWork work;
  for (const char* line :
       {"translation trm=point start=0,0,1e999 end=0,0,0", "translation trm=point start=0,0,0 end=inf,0,0",
        "translation trm=box:-1,-1,-1,1,1,nan start=0,0,0 end=1,0,0",
        "contacts trm=point start=0,0,0 dir=1,0,0 depth=nan"}) {
    const std::string r = cmkit::answerQueryLine(models, line, work);
    EXPECT_EQ(r.rfind("error=", 0), 0u) << line << " -> " << r;
  }
}

TEST(BadInputText, ALeadingByteOrderMarkIsSkipped) {
  // .map: parses, and positions count from after the mark.
  auto map = cmkit::parseMapText(kBom + kBoxMap, "bom.map");
  ASSERT_TRUE(map.ok()) << map.error().toString();
  EXPECT_EQ(map->entities.size(), 1u);
  auto bad = cmkit::parseMapText(kBom + "Version 2\n}", "bom.map");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().line, 2);
  EXPECT_EQ(bad.error().column, 1);
  auto badFirst = cmkit::parseMapText(kBom + "}", "bom.map");
  ASSERT_FALSE(badFirst.ok());
  EXPECT_EQ(badFirst.error().column, 1) << badFirst.error().toString();
  EXPECT_FALSE(contains(badFirst.error().message, "\xEF")) << badFirst.error().toString();

  // .cm, and its CRC alone.
  const std::string cm = kBom + "CM \"1.00\"\n\n1234\n";
  auto file = cmkit::parseCmText(cm, "bom.cm", cmkit::MaterialTable{});
  ASSERT_TRUE(file.ok()) << file.error().toString();
  EXPECT_EQ(file->crc, 1234u);

  // .mtr: the declaration is read.
  cmkit::MaterialTable table;
  table.addMtrText(kBom + "textures/bom/water { water }\n", "bom.mtr");
  EXPECT_TRUE(table.warnings().empty()) << table.warnings().front();
  EXPECT_EQ(table.numDeclared(), 1u);
  EXPECT_NE(table.contents("textures/bom/water") & cmkit::contents::kWater, 0u);

  // A query line (the first line of a query file).
  const auto models = cmkit::test::buildMapModels(cmkit::test::testDataDir() / "maps" / "features.map");
  ASSERT_FALSE(models.empty());
  cmkit::QueryWork work;
  const std::string line = "translation trm=point start=0,0,0 end=1,0,0";
  EXPECT_TRUE(cmkit::isQueryLine(kBom + line));
  EXPECT_EQ(cmkit::answerQueryLine(models, kBom + line, work), cmkit::answerQueryLine(models, line, work));
  EXPECT_FALSE(cmkit::isQueryLine(kBom + "# a comment"));
}

TEST_F(BadInput, ByteOrderMarkInFiles) {
  const std::string map = write("bom.map", kBom + kBoxMap);
  EXPECT_TRUE(cmkit::loadMapFile(map).ok());
  const std::string cm = write("bom.cm", kBom + "CM \"1.00\"\n\n77\n");
  auto crc = cmkit::readCmFileCrc(cm);
  ASSERT_TRUE(crc.ok()) << crc.error().toString();
  EXPECT_EQ(*crc, 77u);
  cmkit::MaterialTable table;
  ASSERT_TRUE(table.addMtrFile(write("bom.mtr", kBom + "textures/bom/clip { playerclip }\n")).ok());
  EXPECT_NE(table.contents("textures/bom/clip") & cmkit::contents::kPlayerClip, 0u);
}

// ---- through the CLI ----

#define REQUIRE_CLI() \
  if (std::string(CMKIT_CLI_PATH).empty()) GTEST_SKIP() << "the CLI is not built"

TEST_F(BadInput, CliCommandsRefuseADirectory) {
  REQUIRE_CLI();
  const std::string cli = CMKIT_CLI_PATH;
  const std::string d = path("x.cm");
  fs::create_directories(d);
  const std::string map = write("ok.map", kBoxMap);
  const std::string queries = write("q.txt", "translation trm=point start=1,1,1 end=2,2,2\n");
  const std::string q = "'" + d + "'";
  const std::string viewer = write("index.html", "<html></html>");  // a stand-in for the built viewer
  for (const std::string& args :
       {"info " + q, "validate " + q, "query " + q + " '" + queries + "'",
        "render " + q + " -o '" + path("o.png") + "'", "export " + q + " -o '" + path("o.obj") + "'",
        "bench " + q, "view " + q + " --exit-after 1 --viewer-dir '" + dir_.string() + "'", "soak " + q,
        "compile " + q, "query '" + map + "' " + q}) {
    int rc = 0;
    const std::string out = runCapture(cli + " " + args + " 2>&1", rc);
    EXPECT_EQ(rc, 2) << args << "\n" << out;
    EXPECT_TRUE(contains(out, d + ": is a directory, not a file")) << args << "\n" << out;
  }
  int rc = 0;
  const std::string out = runCapture(cli + " info '" + path("nothing.map") + "' 2>&1", rc);
  EXPECT_EQ(rc, 2) << out;
  EXPECT_TRUE(contains(out, "nothing.map: no such file")) << out;
}

TEST(BadInputCli, NumberOptionsMustBeFiniteAndInRange) {
  REQUIRE_CLI();
  const std::string cli = CMKIT_CLI_PATH;
  const std::string lt4 = std::string(CMKIT_SOURCE_DIR) + "/data/maps/lt4/lt4.map";
  for (const std::string& args :
       {"bench '" + lt4 + "' --length nan", "bench '" + lt4 + "' --length -5",
        "bench '" + lt4 + "' --angle nan", "bench '" + lt4 + "' --angle inf",
        "bench '" + lt4 + "' --origin nan,0,0", "bench '" + lt4 + "' --origin 1,2",
        "bench '" + lt4 + "' --origin 1e999,0,0", "bench '" + lt4 + "' --radius -1",
        "bench '" + lt4 + "' --times 0", std::string("trm box:0,0,0,1,1,1 --density nan"),
        std::string("trm box:0,0,0,1,1,1 --density -1"), "render '" + lt4 + "' --cut nan",
        "view '" + lt4 + "' --exit-after nan", "soak '" + lt4 + "' --fail-on everything",
        std::string("trm --no-such-option")}) {
    int rc = 0;
    const std::string out = runCapture(cli + " " + args + " 2>&1", rc);
    EXPECT_EQ(rc, 2) << args << "\n" << out;
    EXPECT_FALSE(contains(out, "nan ")) << args << "\n" << out;
  }
  int rc = 0;
  const std::string out = runCapture(cli + " bench --help", rc);
  EXPECT_EQ(rc, 0) << out;
}

TEST_F(BadInput, CompileWritesNothingOnError) {
  REQUIRE_CLI();
  const std::string cli = CMKIT_CLI_PATH;
  std::string text = kBoxMap;
  text.replace(text.find("-64 )"), 3, "1e999");
  const std::string bad = write("bad.map", text);
  const std::string out = path("out.cm");
  int rc = 0;
  const std::string msg = runCapture(cli + " compile '" + bad + "' -o '" + out + "' 2>&1", rc);
  EXPECT_EQ(rc, 2) << msg;
  EXPECT_TRUE(contains(msg, bad + ":8:9: the number 1e999 is not a finite float")) << msg;
  EXPECT_FALSE(fs::exists(out));
  // A query file with a bad path leaves no results file either.
  const std::string good = write("good.map", kBoxMap);
  const std::string results = path("results.txt");
  runCapture(cli + " query '" + good + "' '" + path("none.txt") + "' -o '" + results + "' 2>&1", rc);
  EXPECT_EQ(rc, 2);
  EXPECT_FALSE(fs::exists(results));
}

}  // namespace
