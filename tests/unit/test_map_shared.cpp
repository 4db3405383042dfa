// The map parser on every map in the shared data: parses (the three
// TrenchBroom Valve 220 maps too), and the geometry CRC equals line 3 of the
// .cm files the original tools (and, for the Valve 220 maps, the fork's
// tools) wrote.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "cmkit/map.h"
#include "test_support.h"

namespace {

namespace fs = std::filesystem;

/// The maps of the shared data, or of its bundled part (test::dataMaps).
std::vector<fs::path> sharedMaps() { return cmkit::test::dataMaps(); }

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
  const auto maps = sharedMaps();
  if (!cmkit::test::haveShared()) std::printf("note: %s\n", cmkit::test::bundledOnlyNote().c_str());
  ASSERT_GE(maps.size(), cmkit::test::haveShared() ? 18u : 12u);
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
  int pairs = 0;
  for (const auto& p : sharedMaps()) {
    const fs::path cm = cmkit::test::dataDir() / "reference" / (p.stem().string() + ".cm");
    if (!fs::exists(cm)) continue;
    SCOPED_TRACE(p.string());
    auto map = cmkit::loadMapFile(p.string());
    ASSERT_TRUE(map.ok()) << map.error().toString();
    EXPECT_EQ(map->geometryCrc, cmCrc(cm)) << "reference " << cm;
    ++pairs;
  }
  // Every .map with a reference .cm (bundled: those of the maps whose
  // licence allows it, but lt4's, 5.4 MB).
  EXPECT_EQ(pairs, cmkit::test::haveShared() ? 15 : 6);
}

TEST(MapShared, GeometryCrcMatchesTheOriginalToolsTestCm) {
  const fs::path dir = cmkit::test::dataFile("maps/opentechbfg-test");
  auto map = cmkit::loadMapFile((dir / "test.map").string());
  ASSERT_TRUE(map.ok()) << map.error().toString();
  EXPECT_EQ(map->geometryCrc, cmCrc(dir / "test.cm"));
  EXPECT_EQ(map->geometryCrc, 18121552u);
}

}  // namespace
