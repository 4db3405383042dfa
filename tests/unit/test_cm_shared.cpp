// .cm files of the shared data: every one loads and validates, the reference
// files are written back byte for byte, and models built from the reference
// maps are written exactly as the original wrote them.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include "cm_test_util.h"
#include "cmkit/cm_file.h"
#include "cmkit/compile.h"
#include "cmkit/validate.h"
#include "test_support.h"

namespace cmkit {
namespace {

std::vector<std::filesystem::path> sharedCmFiles() {
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::recursive_directory_iterator(test::dataDir()))
    if (e.path().extension() == ".cm") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

TEST(CmShared, EveryCmLoadsValidatesAndRoundTrips) {
  const auto files = sharedCmFiles();
  if (!test::haveShared()) std::printf("note: %s\n", test::bundledOnlyNote().c_str());
  EXPECT_GE(files.size(), test::haveShared() ? 20u : 13u);
  for (const auto& path : files) {
    SCOPED_TRACE(path.string());
    const std::string text = test::readFile(path);
    Result<CmFile> f = parseCmText(text, path.string(), MaterialTable{});
    ASSERT_TRUE(f.ok()) << f.error().toString();
    ASSERT_FALSE(f->models.empty());
    for (const ModelPtr& m : f->models) {
      const auto violations = validateModel(*m, 5);
      for (const Violation& v : violations) ADD_FAILURE() << v.toString();
    }
    // Identical modulo the memory hints is the requirement; cmkit also
    // reproduces the hints, so the whole text must match.
    const std::string written = writeCmText(f->models, f->crc);
    EXPECT_EQ(test::withoutMemoryHints(written), test::withoutMemoryHints(text));
    EXPECT_TRUE(written == text) << "memory hints differ";
    Result<CmFile> again = parseCmText(written, "written", MaterialTable{});
    ASSERT_TRUE(again.ok());
    ASSERT_EQ(again->models.size(), f->models.size());
    for (std::size_t i = 0; i < f->models.size(); ++i)
      EXPECT_EQ(test::modelDifference(*f->models[i], *again->models[i]), "") << "model " << i;
  }
}

// The map builder's models, written by the .cm writer, against the .cm the
// original wrote for the same map.
TEST(CmShared, BuiltReferenceMapsAreWrittenAsTheOriginalWroteThem) {
  CMKIT_FLOAT_BUILD_ONLY();
  int compared = 0;
  for (const auto& e : std::filesystem::recursive_directory_iterator(test::dataDir() / "maps")) {
    if (e.path().extension() != ".map") continue;
    const auto reference = test::dataDir() / "reference" / (e.path().stem().string() + ".cm");
    if (!std::filesystem::exists(reference)) continue;
    SCOPED_TRACE(e.path().string());
    Result<MapFile> map = loadMapFile(e.path().string());
    ASSERT_TRUE(map.ok()) << map.error().toString();
    Result<BuildResult> built = buildCollisionModels(*map, MaterialTable{});
    ASSERT_TRUE(built.ok()) << built.error().toString();
    const std::string written = writeCmText(built->models, map->geometryCrc);
    const std::string expected = test::readFile(reference);
    EXPECT_EQ(test::withoutMemoryHints(written), test::withoutMemoryHints(expected));
    EXPECT_TRUE(written == expected) << "memory hints differ";
    ++compared;
  }
  EXPECT_GE(compared, test::haveShared() ? 15 : 6);
}

}  // namespace
}  // namespace cmkit
