// `cmkit validate` and `cmkit info FILE.cm` through the built CLI.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "test_support.h"

namespace {

namespace fs = std::filesystem;

#define REQUIRE_CLI() \
  if (std::string(CMKIT_CLI_PATH).empty()) GTEST_SKIP() << "the CLI is not built"

TEST(CmCli, ValidateAcceptsGoodFilesAndReportsViolations) {
  REQUIRE_CLI();
  const std::string cli = CMKIT_CLI_PATH;
  int rc = 0;
  std::string out = cmkit::test::runCapture(
      cli + " validate '" + (cmkit::test::testDataDir() / "cm" / "ep1.cm").string() + "'", rc);
  EXPECT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("4 model(s), all invariants hold"), std::string::npos) << out;

  const cmkit::test::ScratchDir scratch("cm_cli");
  const fs::path& dir = scratch.path();
  const fs::path bad = dir / "bad.cm";
  std::ofstream(bad) << "CM \"1.00\" 0 collisionModel \"x\" { vertices { 3 ( 0 0 0 ) ( 1 0 0 ) ( 0 1 5 ) }\n"
                        "edges { 4 ( 0 0 ) 0 0 ( 0 1 ) 0 1 ( 1 2 ) 0 1 ( 2 0 ) 0 1 }\n"
                        "polygons { 3 ( 1 2 3 ) ( 0 0 1 ) 0 ( 0 0 0 ) ( 1 1 0 ) \"a\" } }\n";
  out = cmkit::test::runCapture(cli + " validate '" + bad.string() + "'", rc);
  EXPECT_EQ(rc, 1) << out;
  EXPECT_NE(out.find("model \"x\" polygon 0: not planar"), std::string::npos) << out;
  EXPECT_NE(out.find("model \"x\" polygon 0: a vertex lies outside"), std::string::npos) << out;
  // Both are odd shapes, not corrupt data.
  EXPECT_NE(out.find("off its plane [geometry]"), std::string::npos) << out;
  EXPECT_NE(out.find("0 of structure (a corrupt model), 2 of geometry"), std::string::npos) << out;

  std::ofstream(dir / "broken.cm") << "CM \"1.00\" 0 collisionModel \"x\" { vertices { 3 ( 0 0 0 ) }";
  out = cmkit::test::runCapture(cli + " validate '" + (dir / "broken.cm").string() + "' 2>&1", rc);
  EXPECT_EQ(rc, 2) << out;
  EXPECT_NE(out.find("broken.cm:1:"), std::string::npos) << out;
  fs::remove_all(dir);
}

TEST(CmCli, InfoPrintsStatisticsOfACmFile) {
  REQUIRE_CLI();
  int rc = 0;
  const std::string out = cmkit::test::runCapture(
      std::string(CMKIT_CLI_PATH) + " info '" + cmkit::test::dataFile("reference/box_room.cm").string() + "'",
      rc);
  EXPECT_EQ(rc, 0) << out;
  // The counts stored in the file equal those the original printed when it built it.
  for (const char* line : {"   120 vertices (2 KB)", "   209 edges (7 KB)", "    77 polygons (5 KB)",
                           "    18 brushes (2 KB)", "    97 internal edges"})
    EXPECT_NE(out.find(line), std::string::npos) << line << "\n" << out;
}

}  // namespace
