// The CLI's conventions (docs: cmkit --help, cmkit query --help): exit codes,
// unknown commands, standard input as "-", the format of a models file told
// by its first token, singular and plural in counts.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "test_support.h"

namespace cmkit {
namespace {

namespace fs = std::filesystem;

std::string cli() { return CMKIT_CLI_PATH; }
std::string q(const fs::path& p) { return "'" + p.string() + "'"; }

class CliConventions : public ::testing::Test {
 protected:
  void SetUp() override {
    map_ = test::testDataDir() / "maps" / "features.map";
    std::ofstream(dir_ / "good.txt") << "translation trm=box:-8,-8,0,8,8,16 start=0,0,64 end=0,0,-64\n";
    std::ofstream(dir_ / "bad.txt") << "translation trm=box:-8,-8,0,8,8,16 start=0,0,64 end=0,0,-64\n"
                                       "translation trm=box:1,1,1,0,0,0 start=0,0,0 end=1,1,1\n";
  }
  test::ScratchDir scratch_{"cli_conventions"};
  const fs::path& dir_ = scratch_.path();
  fs::path map_;
};

TEST_F(CliConventions, AnUnknownCommandIsNamedAndExitsWith2) {
  int rc = -1;
  const std::string out = test::runCapture(cli() + " bogus 2>&1", rc);
  EXPECT_EQ(rc, 2);
  EXPECT_NE(out.find("unknown command 'bogus'"), std::string::npos) << out;
  EXPECT_NE(out.find("query"), std::string::npos) << out;  // the commands are listed
  test::runCapture(cli() + " query --no-such-option 2>&1", rc);
  EXPECT_EQ(rc, 2);
  test::runCapture(cli() + " 2>&1", rc);
  EXPECT_EQ(rc, 2);
  test::runCapture(cli() + " --help", rc);
  EXPECT_EQ(rc, 0);
}

TEST(CliExitCodes, EveryCommandsHelpSaysThem) {
  for (const char* command : {"trm", "compile", "info", "validate", "query", "render", "export", "view",
                              "bench", "soak", "walk", "audit", "demo"}) {
    int rc = -1;
    const std::string out = test::runCapture(cli() + " " + command + " --help", rc);
    EXPECT_EQ(rc, 0) << command;
    EXPECT_NE(out.find("Exit codes"), std::string::npos) << command << ":\n" << out;
  }
  int rc = -1;
  const std::string top = test::runCapture(cli() + " --help", rc);
  EXPECT_NE(top.find("3 query only"), std::string::npos) << top;
}

TEST_F(CliConventions, QueryExits3WhenALineIsAnErrorAnd0Otherwise) {
  int rc = -1;
  std::string out = test::runCapture(cli() + " query " + q(map_) + " " + q(dir_ / "good.txt") + " 2>&1", rc);
  EXPECT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("1 query on 1 thread"), std::string::npos) << out;  // singular
  out = test::runCapture(cli() + " query " + q(map_) + " " + q(dir_ / "bad.txt") + " 2>&1", rc);
  EXPECT_EQ(rc, 3) << out;
  EXPECT_NE(out.find("fraction="), std::string::npos) << out;  // every line is still written
  EXPECT_NE(out.find("error=degenerate trm"), std::string::npos) << out;
  EXPECT_NE(out.find("2 queries on 1 thread"), std::string::npos) << out;
  EXPECT_NE(out.find("1 error line\n"), std::string::npos) << out;
}

TEST_F(CliConventions, StandardInputAndSniffedFormats) {
  int rc = -1;
  const std::string expected =
      test::runCapture(cli() + " query " + q(map_) + " " + q(dir_ / "good.txt") + " 2>/dev/null", rc);
  ASSERT_EQ(rc, 0);
  ASSERT_NE(expected.find("fraction=0 "), std::string::npos) << expected;
  // Queries from standard input.
  EXPECT_EQ(test::runCapture(
                "cat " + q(dir_ / "good.txt") + " | " + cli() + " query " + q(map_) + " - 2>/dev/null", rc),
            expected);
  EXPECT_EQ(rc, 0);
  // A .map from standard input.
  EXPECT_EQ(test::runCapture(
                "cat " + q(map_) + " | " + cli() + " query - " + q(dir_ / "good.txt") + " 2>/dev/null", rc),
            expected);
  EXPECT_EQ(rc, 0);
  // A .cm through a pipe: compile -o - writes it to standard output.
  EXPECT_EQ(test::runCapture(cli() + " compile " + q(map_) + " -o - 2>/dev/null | " + cli() + " query - " +
                                 q(dir_ / "good.txt") + " 2>/dev/null",
                             rc),
            expected);
  EXPECT_EQ(rc, 0);
  // Files of other names: a .cm named .dat and a .map named .txt.
  test::runCapture(cli() + " compile " + q(map_) + " -o " + q(dir_ / "features.cm") + " 2>/dev/null", rc);
  ASSERT_EQ(rc, 0);
  fs::copy_file(dir_ / "features.cm", dir_ / "features.dat", fs::copy_options::overwrite_existing);
  fs::copy_file(map_, dir_ / "features.txt", fs::copy_options::overwrite_existing);
  for (const char* name : {"features.dat", "features.txt"}) {
    EXPECT_EQ(test::runCapture(
                  cli() + " query " + q(dir_ / name) + " " + q(dir_ / "good.txt") + " 2>/dev/null", rc),
              expected)
        << name;
    EXPECT_EQ(rc, 0) << name;
  }
  // info reads standard input too (a .map built, a .cm loaded).
  const std::string fromFile = test::runCapture(cli() + " info " + q(dir_ / "features.cm") + " --json", rc);
  ASSERT_EQ(rc, 0);
  for (const char* name : {"features.txt", "features.cm"}) {
    const std::string fromPipe =
        test::runCapture("cat " + q(dir_ / name) + " | " + cli() + " info - --json", rc);
    EXPECT_EQ(rc, 0) << name;
    const auto totals = [](const std::string& json) { return json.substr(json.find("\"total\"")); };
    ASSERT_NE(fromPipe.find("\"total\""), std::string::npos) << fromPipe;
    EXPECT_EQ(totals(fromPipe), totals(fromFile)) << name;
  }
  // Not both from standard input.
  const std::string both = test::runCapture("true | " + cli() + " query - - 2>&1", rc);
  EXPECT_EQ(rc, 2);
  EXPECT_NE(both.find("cannot both be standard input"), std::string::npos) << both;
}

// bench --suite --slowest: each kind's N slowest queries, by their line in
// the file (lines that are not queries counted), slowest first.
TEST_F(CliConventions, BenchSuiteSlowestNamesTheQueriesLines) {
  fs::create_directories(dir_ / "suite" / "reference");
  fs::create_directories(dir_ / "suite" / "maps" / "m");
  fs::copy_file(map_, dir_ / "suite" / "maps" / "m" / "features.map");
  std::ofstream(dir_ / "suite" / "reference" / "features.queries.txt")
      << "# a comment: line 1\n"
         "translation trm=box:-8,-8,0,8,8,16 start=0,0,64 end=0,0,-64\n"
         "pointcontents pos=0,0,0\n"
         "translation trm=point start=0,0,64 end=0,0,63\n"
         "translation trm=cylinder:8:-8,-8,0,8,8,16 start=0,0,64 end=64,0,-64\n";
  int rc = -1;
  const std::string out = test::runCapture(
      cli() + " bench --suite " + q(dir_ / "suite" / "reference") + " --slowest 2 --repeat 3 2>&1", rc);
  ASSERT_EQ(rc, 0) << out;
  // (Read with string functions: std::regex trips GCC's maybe-uninitialized
  // warning in the sanitizer build.)
  const std::size_t head = out.find("slowest 2 of 3 translation queries in features.queries.txt (");
  ASSERT_NE(head, std::string::npos) << out;
  EXPECT_NE(out.find(" % of their time", head), std::string::npos) << out;
  EXPECT_NE(out.find("slowest 1 of 1 pointcontents queries"), std::string::npos) << out;
  std::istringstream rest(out.substr(head));
  std::string text;
  std::getline(rest, text);                  // the heading
  std::vector<std::pair<double, int>> rows;  // ns, line
  for (int k = 0; k < 2 && std::getline(rest, text); ++k) {
    std::istringstream words(text);
    double ns = -1;
    std::string unit, lineWord;
    int line = -1;
    words >> ns >> unit >> lineWord >> line;
    ASSERT_TRUE(words && unit == "ns" && lineWord == "line") << text;
    rows.emplace_back(ns, line);
  }
  ASSERT_EQ(rows.size(), 2u) << out;
  EXPECT_GE(rows[0].first, rows[1].first) << out;  // slowest first
  for (const auto& [ns, line] : rows) EXPECT_TRUE(line == 2 || line == 4 || line == 5) << out;
  EXPECT_NE(rows[0].second, rows[1].second) << out;
  // Not with --json, whose output the text lists would break.
  const std::string both = test::runCapture(
      cli() + " bench --suite " + q(dir_ / "suite" / "reference") + " --slowest 2 --json 2>&1", rc);
  EXPECT_EQ(rc, 2) << both;
  EXPECT_NE(both.find("--json"), std::string::npos) << both;
}

TEST_F(CliConventions, CompileReadsAMapFromStandardInput) {
  int rc = -1;
  test::runCapture(cli() + " compile " + q(map_) + " -q -o " + q(dir_ / "file.cm") + " 2>/dev/null", rc);
  ASSERT_EQ(rc, 0);
  const std::string report = test::runCapture(
      "cat " + q(map_) + " | " + cli() + " compile - -q -o " + q(dir_ / "pipe.cm") + " 2>&1", rc);
  ASSERT_EQ(rc, 0) << report;
  EXPECT_EQ(report.find(".proc"), std::string::npos) << report;        // no .proc note for standard input
  EXPECT_EQ(report.find("warning: -:"), std::string::npos) << report;  // warnings name <stdin>
  EXPECT_EQ(test::readFile(dir_ / "pipe.cm"), test::readFile(dir_ / "file.cm"));
  // -o - as well: the .cm on standard output, the report on stderr.
  const std::string piped =
      test::runCapture("cat " + q(map_) + " | " + cli() + " compile - -q -o - 2>/dev/null", rc);
  ASSERT_EQ(rc, 0);
  EXPECT_EQ(piped, test::readFile(dir_ / "file.cm"));
  // A malformed map: exit 2, the error names standard input and the line.
  std::ofstream(dir_ / "bad.map") << "{\n\"classname\" \"worldspawn\"\n{\n( 1 2";
  const std::string bad =
      test::runCapture("cat " + q(dir_ / "bad.map") + " | " + cli() + " compile - 2>&1", rc);
  EXPECT_EQ(rc, 2) << bad;
  EXPECT_NE(bad.find("<stdin>:"), std::string::npos) << bad;
}

TEST(CliLooksLikeCm, FirstTokenDecides) {
  // (The rule of tools/cmkit/model_loading.h, seen through the CLI above;
  // here its edge cases through a pipe.)
  int rc = -1;
  const std::string out =
      test::runCapture("printf 'CMX' | " + std::string(CMKIT_CLI_PATH) + " query - /dev/null 2>&1", rc);
  EXPECT_EQ(rc, 2) << out;  // "CMX" is no .cm header: read as a .map, which it is not either
  EXPECT_NE(out.find("<stdin>"), std::string::npos) << out;
}

}  // namespace
}  // namespace cmkit
