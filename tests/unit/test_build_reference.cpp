// The map builder against the original: for every map with a statistics
// file in the shared reference data (or its bundled part), every model's name, bounds, contents
// and counts (vertices, edges, polygons, brushes, nodes, references,
// internal and sharp edges, contained polygons removed, polygons merged)
// equal the original's; the CLI's report equals the original's text.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "cmkit/cm_file.h"
#include "cmkit/compile.h"
#include "cmkit/map.h"
#include "test_support.h"

namespace {

namespace fs = std::filesystem;
using namespace cmkit;

/// One "model N "name": bounds (...)-(...) contents C" block of a stats file.
struct RefModel {
  std::string header;  ///< the model line after "model N "
  std::map<std::string, long long> counts;
};

std::vector<RefModel> parseStats(const fs::path& p) {
  std::vector<RefModel> models;
  std::istringstream in(cmkit::test::readFile(p));
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model ", 0) == 0) {
      // "model N <header>"
      const auto space = line.find(' ', 6);
      if (space != std::string::npos) models.push_back({line.substr(space + 1), {}});
    } else if (!models.empty()) {
      // "   <count> <name words>[ (<n> KB)]"
      std::string rest = line;
      if (const auto kb = rest.find(" ("); kb != std::string::npos && rest.ends_with(" KB)")) rest.resize(kb);
      std::istringstream fields(rest);
      std::string count, word, name;
      if (!(fields >> count) || count.find_first_not_of("0123456789") != std::string::npos) continue;
      bool words = true;
      while (fields >> word) {
        if (word.find_first_not_of("abcdefghijklmnopqrstuvwxyz") != std::string::npos) words = false;
        name += (name.empty() ? "" : " ") + word;
      }
      if (words && !name.empty()) models.back().counts[name] = std::stoll(count);
    }
  }
  return models;
}

std::string g(float v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%g", static_cast<double>(v));
  return buf;
}

std::string header(const CollisionModel& m) {
  return "\"" + m.name() + "\": bounds (" + g(m.bounds().min.x) + " " + g(m.bounds().min.y) + " " +
         g(m.bounds().min.z) + ")-(" + g(m.bounds().max.x) + " " + g(m.bounds().max.y) + " " +
         g(m.bounds().max.z) + ") contents " + std::to_string(m.contents());
}

std::map<std::string, long long> counts(const CollisionModel& m) {
  return {{"vertices", static_cast<long long>(m.vertices().size())},
          {"edges", static_cast<long long>(m.edges().size())},
          {"polygons", static_cast<long long>(m.polygons().size())},
          {"brushes", static_cast<long long>(m.brushes().size())},
          {"nodes", static_cast<long long>(m.nodes().size()) - 1},
          {"polygon refs", static_cast<long long>(m.polygonRefs().size())},
          {"brush refs", static_cast<long long>(m.brushRefs().size())},
          {"internal edges", m.stats().internalEdges},
          {"sharp edges", m.stats().sharpEdges},
          {"contained polygons removed", m.stats().containedPolygonsRemoved},
          {"polygons merged", m.stats().polygonsMerged}};
}

/// A map with a stats file: its reference folder ("reference", or
/// "reference-proc" for maps built with the .proc beside them), name and .map.
struct RefMap {
  std::string dir;
  std::string name;
  fs::path path;
};

/// Maps that have a stats file in either reference folder.
std::vector<RefMap> mapsWithStats() {
  std::vector<RefMap> out;
  std::map<std::string, fs::path> maps;
  for (const fs::path& p : test::dataMaps()) maps[p.stem().string()] = p;
  for (const std::string dir : {"reference", "reference-proc"}) {
    for (const auto& e : fs::directory_iterator(test::dataDir() / dir)) {
      const std::string f = e.path().filename().string();
      const std::string suffix = ".stats.txt";
      if (f.size() <= suffix.size() || f.compare(f.size() - suffix.size(), suffix.size(), suffix) != 0)
        continue;
      const std::string name = f.substr(0, f.size() - suffix.size());
      if (maps.count(name)) out.push_back({dir, name, maps[name]});
    }
  }
  std::sort(out.begin(), out.end(), [](const RefMap& a, const RefMap& b) { return a.name < b.name; });
  return out;
}

TEST(BuildReference, EveryModelOfEveryMapMatchesTheOriginalsStatistics) {
  CMKIT_FLOAT_BUILD_ONLY();
  const auto maps = mapsWithStats();
  if (!test::haveShared()) std::printf("note: %s\n", test::bundledOnlyNote().c_str());
  ASSERT_GE(maps.size(), test::haveShared() ? 17u : 9u);
  for (const auto& [dir, name, path] : maps) {
    SCOPED_TRACE(name);
    auto map = loadMapFile(path.string());
    ASSERT_TRUE(map.ok()) << map.error().toString();
    auto models = test::buildAsLoaded(*map, path);  // with the .proc beside the map
    ASSERT_TRUE(models.ok()) << models.error().toString();
    const auto ref = parseStats(test::dataDir() / dir / (name + ".stats.txt"));
    ASSERT_EQ(models->size(), ref.size());
    int mismatches = 0;
    for (std::size_t i = 0; i < ref.size() && mismatches < 10; ++i) {
      const CollisionModel& m = *(*models)[i];
      if (header(m) != ref[i].header) {
        ++mismatches;
        ADD_FAILURE() << "model " << i << ": " << header(m) << " vs the original's " << ref[i].header;
      }
      for (const auto& [key, value] : counts(m)) {
        const auto it = ref[i].counts.find(key);
        ASSERT_NE(it, ref[i].counts.end()) << key;
        if (it->second != value) {
          ++mismatches;
          ADD_FAILURE() << "model " << i << " \"" << m.name() << "\": " << key << " " << value
                        << ", the original " << it->second;
        }
      }
    }
  }
}

TEST(BuildReference, WrittenCmFilesAreByteIdenticalToTheOriginals) {
  CMKIT_FLOAT_BUILD_ONLY();
  int compared = 0;
  for (const auto& [dir, name, path] : mapsWithStats()) {
    const fs::path refCm = test::dataDir() / dir / (name + ".cm");
    if (!fs::exists(refCm)) continue;
    SCOPED_TRACE(name);
    auto map = loadMapFile(path.string());
    ASSERT_TRUE(map.ok()) << map.error().toString();
    auto models = test::buildAsLoaded(*map, path);
    ASSERT_TRUE(models.ok()) << models.error().toString();
    const std::string mine = writeCmText(*models, map->geometryCrc);
    const std::string ref = cmkit::test::readFile(refCm);
    if (mine != ref) {
      // report the first differing line
      std::istringstream a(mine), b(ref);
      std::string la, lb;
      int line = 0;
      while (true) {
        ++line;
        const bool ga = static_cast<bool>(std::getline(a, la));
        const bool gb = static_cast<bool>(std::getline(b, lb));
        if (!ga || !gb || la != lb) {
          ADD_FAILURE() << name << ".cm line " << line << ": cmkit \"" << (ga ? la : "<eof>")
                        << "\", original \"" << (gb ? lb : "<eof>") << "\"";
          break;
        }
      }
    }
    ++compared;
  }
  // Without the shared folder: the bundled maps but lt4 (its .cm is 5.4 MB).
  EXPECT_GE(compared, test::haveShared() ? 17 : 8);
}

/// The text without the timing line (msec differ).
std::string withoutTiming(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  std::string out;
  while (std::getline(in, line)) {
    if (line.find(" msec to ") != std::string::npos) continue;
    out += line + "\n";
  }
  return out;
}

#define CMKIT_REQUIRE_CLI() \
  if (std::string(CMKIT_CLI_PATH).empty()) GTEST_SKIP() << "the CLI is not built"

TEST(BuildReference, CliReportEqualsTheOriginalsText) {
  CMKIT_FLOAT_BUILD_ONLY();
  CMKIT_REQUIRE_CLI();
  for (const std::string name : {"test", "box_room", "altar", "inline_patch", "water_clip", "portalsky",
                                 "box_room_proc", "inline_patch_proc"}) {
    SCOPED_TRACE(name);
    RefMap ref;
    for (const RefMap& m : mapsWithStats()) {
      if (m.name == name) ref = m;
    }
    if (name == "altar" && !test::haveShared()) {
      std::printf("note: altar left out: %s\n",
                  test::whyNotBundled("maps/darkradiant-altar/altar.map").c_str());
      continue;
    }
    ASSERT_FALSE(ref.path.empty());
    int status = 0;
    const std::string out = test::runCapture(
        std::string(CMKIT_CLI_PATH) + " info '" + ref.path.string() + "' 2>/dev/null", status);
    EXPECT_EQ(status, 0);
    EXPECT_EQ(withoutTiming(out),
              withoutTiming(cmkit::test::readFile(test::dataDir() / ref.dir / (name + ".stats.txt"))));
  }
}

// --memory adds one line after the original's text: the memory the models
// take in cmkit (arrays, and the query data beside them).
TEST(BuildReference, CliInfoMemoryLine) {
  CMKIT_REQUIRE_CLI();
  int status = 0;
  const std::string out = test::runCapture(std::string(CMKIT_CLI_PATH) + " info '" + CMKIT_SOURCE_DIR +
                                               "/data/maps/lt4/lt4.map' --quiet --memory 2>/dev/null",
                                           status);
  EXPECT_EQ(status, 0);
  const auto at = out.find("in cmkit: ");
  ASSERT_NE(at, std::string::npos) << out;
  long arraysKb = 0, queryDataKb = 0;
  double ratio = 0;
  ASSERT_EQ(std::sscanf(out.c_str() + at,
                        "in cmkit: %ld KB of model arrays, %ld KB of query data beside them (%lfx)",
                        &arraysKb, &queryDataKb, &ratio),
            3)
      << out;
  EXPECT_GT(arraysKb, 1000);  // lt4: about 3.5 MB
  EXPECT_GT(queryDataKb, 0);
  EXPECT_LE(ratio, 2.5);  // (QueryData.AtMostTwoAndAHalfTimesTheModelsArrays)
}

TEST(BuildReference, CliRejectsBrokenMapsWithFileAndLine) {
  CMKIT_REQUIRE_CLI();
  const test::ScratchDir scratch("build_cli");
  const fs::path& dir = scratch.path();
  const fs::path bad = dir / "bad.map";
  {
    std::ofstream f(bad);
    f << "Version 2\n{\n\"classname\" \"worldspawn\"\n{\nbrushDef3\n{\n( 0 0 1 oops ) \n}\n}\n}\n";
  }
  int status = 0;
  const std::string out =
      test::runCapture(std::string(CMKIT_CLI_PATH) + " compile '" + bad.string() + "' 2>&1", status);
  EXPECT_EQ(status, 2);
  EXPECT_NE(out.find("bad.map:7"), std::string::npos) << out;
  const std::string missing = test::runCapture(
      std::string(CMKIT_CLI_PATH) + " info '" + (dir / "none.map").string() + "' 2>&1", status);
  EXPECT_EQ(status, 2);
  fs::remove_all(dir);
}

TEST(BuildReference, CliCompileWritesTheCmFile) {
  CMKIT_FLOAT_BUILD_ONLY();
  CMKIT_REQUIRE_CLI();
  const test::ScratchDir scratch("build_cli_box_room");
  const fs::path out = scratch.path() / "box_room.cm";
  int status = 0;
  const fs::path map = test::dataFile("maps/synthetic/box_room.map");
  test::runCapture(
      std::string(CMKIT_CLI_PATH) + " compile -q '" + map.string() + "' -o '" + out.string() + "'", status);
  EXPECT_EQ(status, 0);
  EXPECT_EQ(cmkit::test::readFile(out), cmkit::test::readFile(test::dataFile("reference/box_room.cm")));
  fs::remove(out);
}

TEST(BuildReference, CliJsonHasTotalsAndModels) {
  CMKIT_REQUIRE_CLI();
  int status = 0;
  const fs::path map = test::dataFile("maps/synthetic/water_clip.map");
  const std::string out =
      test::runCapture(std::string(CMKIT_CLI_PATH) + " compile --json '" + map.string() + "'", status);
  EXPECT_EQ(status, 0);
  EXPECT_NE(out.find("\"total\": {\"models\": 3,"), std::string::npos) << out;
  EXPECT_NE(out.find("\"name\": \"worldMap\""), std::string::npos);
  EXPECT_EQ(out.front(), '{');
}
}  // namespace
