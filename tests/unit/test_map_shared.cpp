// The map parser on every map in the shared data: parses (the three
// TrenchBroom Valve 220 maps too), and the geometry CRC equals line 3 of the
// .cm files the original tools (and, for the Valve 220 maps, the fork's
// tools) wrote.
#include <algorithm>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "cmkit/map.h"
#include "test_support.h"

namespace {

namespace fs = std::filesystem;
using cmkit::test::sharedDir;

std::vector<fs::path> sharedMaps() {
  std::vector<fs::path> maps;
  for (const auto& e : fs::recursive_directory_iterator(sharedDir() / "maps")) {
    if (e.is_regular_file() && e.path().extension() == ".map") maps.push_back(e.path());
  }
  std::sort(maps.begin(), maps.end());
  return maps;
}

bool isValve220(const fs::path& p) {
  static const std::set<std::string> kNames = {"ep1", "test_hdri", "test_func_group_instancing"};
  return kNames.count(p.stem().string()) != 0;
}

/// Line 3 of a .cm file: the CRC of the map it was built from.
std::uint32_t cmCrc(const fs::path& cm) {
  std::istringstream in(cmkit::test::readFile(cm));
  std::string line;
  for (int i = 0; i < 3; ++i) std::getline(in, line);
  return static_cast<std::uint32_t>(std::stoul(line));
}

TEST(MapShared, EveryMapParses) {
  CMKIT_REQUIRE_SHARED();
  const auto maps = sharedMaps();
  ASSERT_GE(maps.size(), 18u);
  for (const auto& p : maps) {
    SCOPED_TRACE(p.string());
    auto map = cmkit::loadMapFile(p.string());
    ASSERT_TRUE(map.ok()) << map.error().toString();
    EXPECT_FALSE(map->entities.empty());
    EXPECT_EQ(map->version, isValve220(p) ? 1 : 2);  // Valve 220 maps have no Version line
  }
}

// The fork's tools wrote a .cm beside each Valve 220 map; its CRC is ours
// (docs/fidelity.md compares the models).
TEST(MapShared, Valve220MapsHaveTheCrcOfTheForksCmFiles) {
  CMKIT_FLOAT_BUILD_ONLY();
  CMKIT_REQUIRE_SHARED();
  int pairs = 0;
  for (const auto& p : sharedMaps()) {
    if (!isValve220(p)) continue;
    SCOPED_TRACE(p.string());
    auto map = cmkit::loadMapFile(p.string());
    ASSERT_TRUE(map.ok()) << map.error().toString();
    fs::path cm = p;
    cm.replace_extension(".cm");
    EXPECT_EQ(map->geometryCrc, cmCrc(cm));
    ++pairs;
  }
  EXPECT_EQ(pairs, 3);
}

TEST(MapShared, GeometryCrcMatchesEveryReferenceCm) {
  CMKIT_REQUIRE_SHARED();
  int pairs = 0;
  for (const auto& p : sharedMaps()) {
    const fs::path cm = sharedDir() / "reference" / (p.stem().string() + ".cm");
    if (!fs::exists(cm)) continue;
    SCOPED_TRACE(p.string());
    auto map = cmkit::loadMapFile(p.string());
    ASSERT_TRUE(map.ok()) << map.error().toString();
    EXPECT_EQ(map->geometryCrc, cmCrc(cm)) << "reference " << cm;
    ++pairs;
  }
  EXPECT_EQ(pairs, 15);  // every .map with a reference .cm
}

TEST(MapShared, GeometryCrcMatchesTheOriginalToolsTestCm) {
  CMKIT_REQUIRE_SHARED();
  const fs::path dir = sharedDir() / "maps" / "opentechbfg-test";
  auto map = cmkit::loadMapFile((dir / "test.map").string());
  ASSERT_TRUE(map.ok()) << map.error().toString();
  EXPECT_EQ(map->geometryCrc, cmCrc(dir / "test.cm"));
  EXPECT_EQ(map->geometryCrc, 18121552u);
}

}  // namespace
