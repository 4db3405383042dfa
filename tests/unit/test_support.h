// Helpers shared by the unit tests.
#pragma once

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <span>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "cmkit/compile.h"
#include "cmkit/map.h"
#include "cmkit/proc_file.h"
#include "cmkit/query.h"
#include "io/fields.h"

/// Skips a test that checks the original's float results bit for bit (.cm
/// bytes, statistics, CRCs, the shared reference answers): a double build
/// (CMKIT_DOUBLE) computes in double, so its last digits differ by design
/// (docs/reliability.md, "Large worlds"). The float build runs them all.
#define CMKIT_FLOAT_BUILD_ONLY()                                                                 \
  if constexpr (cmkit::kDoublePrecision) {                                                       \
    GTEST_SKIP() << "checks the original's float results bit for bit; this is the double build " \
                    "(CMKIT_DOUBLE)";                                                            \
  }                                                                                              \
  static_assert(true)

namespace cmkit::test {

/// A path in the temporary directory of its own for the running test:
/// "cmkit_<stem>_<process id>_<suite>_<test>". ctest runs the tests side by
/// side, each in a process of its own, so two tests must never share a file
/// (two tests of one fixture did: one read the other's half-written query
/// file). Not created.
inline std::filesystem::path uniqueTempPath(const std::string& stem) {
  std::string name = "cmkit_" + stem + "_" + std::to_string(::getpid());
  if (const auto* info = ::testing::UnitTest::GetInstance()->current_test_info())
    name += std::string("_") + info->test_suite_name() + "_" + info->name();
  for (char& c : name)
    if (c == '/') c = '_';  // (parameterised tests' names)
  return std::filesystem::temp_directory_path() / name;
}

/// uniqueTempPath(stem) as a directory, made empty, removed with this object.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& stem) : path_(uniqueTempPath(stem)) {
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

/// A model's array (a span) as a vector, to compare with EXPECT_EQ.
template <class T>
std::vector<std::remove_const_t<T>> toVector(std::span<T> items) {
  return {items.begin(), items.end()};
}

/// The shared data folder beside the clone (../shared, or the configure
/// option CMKIT_SHARED_DIR): maps, reference results, specs. Absent in a
/// user's clone.
inline std::filesystem::path sharedDir() { return CMKIT_SHARED_DIR; }
inline bool haveShared() { return std::filesystem::exists(sharedDir() / "reference"); }

/// The project's own test data (tests/data), always present.
inline std::filesystem::path testDataDir() { return CMKIT_TEST_DATA_DIR; }

/// The part of the shared data whose licence allows bundling it, in the
/// shared folder's layout (tests/data/shared/README.md).
inline std::filesystem::path bundledSharedDir() { return testDataDir() / "shared"; }

/// Where the tests read shared data from: the shared folder when present,
/// else its bundled part.
inline std::filesystem::path dataDir() { return haveShared() ? sharedDir() : bundledSharedDir(); }

/// A file of the shared data by its path in the shared folder ("maps/..."):
/// there when the folder is present, else in its bundled part; lt4's map is
/// bundled in data/maps/lt4 (the demo's map).
inline std::filesystem::path dataFile(const std::string& relative) {
  if (haveShared()) return sharedDir() / relative;
  if (relative.rfind("maps/lt4/", 0) == 0) return std::filesystem::path(CMKIT_SOURCE_DIR) / "data" / relative;
  return bundledSharedDir() / relative;
}

/// Why a file of the shared data (its path in the shared folder) is not in
/// tests/data/shared.
inline std::string whyNotBundled(const std::string& relative) {
  if (relative.find("darkradiant") != std::string::npos || relative.find("altar") != std::string::npos ||
      relative.find("modelexport_patch") != std::string::npos ||
      relative.find("weld_patches") != std::string::npos)
    return "a GPL-2.0+ map (or made from one), which its licence does not allow bundling "
           "(../shared/maps/README.md)";
  if (relative.find(".queries.txt") != std::string::npos ||
      relative.find(".results.txt") != std::string::npos)
    return "the original's reference queries and answers (about 700 KB per map) are not bundled, to keep "
           "the repository small";
  return "too large to bundle (tests/data/shared/README.md)";
}

/// Every .map of the shared data (dataDir()/maps, and lt4 from data/maps
/// when the shared folder is absent), sorted.
inline std::vector<std::filesystem::path> dataMaps() {
  std::vector<std::filesystem::path> maps;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dataDir() / "maps"))
    if (e.is_regular_file() && e.path().extension() == ".map") maps.push_back(e.path());
  if (!haveShared()) maps.push_back(dataFile("maps/lt4/lt4.map"));
  std::sort(maps.begin(), maps.end());
  return maps;
}

/// A note for a test run on the bundled part of the shared data only.
inline std::string bundledOnlyNote() {
  return "the shared folder " + sharedDir().string() +
         " is absent: ran on its bundled part (tests/data/shared); the GPL-2.0+ darkradiant maps, "
         "whose licence does not allow bundling them, and the files too large to bundle were left out";
}

/// The numbers of a query- or result-line value ("1,2,3"), read as cmkit
/// reads them (src/io/fields.h); the ones before a malformed number.
inline std::vector<Real> numbers(std::string_view text) {
  std::vector<Real> v;
  detail::parseRealList(text, v, nullptr, detail::Finite::NotRequired);
  return v;
}

inline std::string readFile(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// Runs a shell command; returns its standard output and sets its exit code
/// (-1 when it could not run or was killed by a signal).
inline std::string runCapture(const std::string& command, int& exitCode) {
  std::string out;
  FILE* p = popen(command.c_str(), "r");
  if (!p) {
    exitCode = -1;
    return out;
  }
  char buf[4096];
  std::size_t n = 0;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  const int status = pclose(p);
  exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return out;
}

/// Builds the models of a parsed map as the original's LoadMap does (no
/// materials: the built-in rules): the world pruned with NAME.proc when it
/// lies beside `path`.
inline Result<std::vector<ModelPtr>> buildAsLoaded(const MapFile& map, const std::filesystem::path& path) {
  auto proc = loadProcFileForMap(path.string());
  if (!proc) return proc.error();
  BuildOptions options;
  if (proc->has_value()) options.procBsp = &**proc;
  Result<BuildResult> built = buildCollisionModels(map, MaterialTable{}, options);
  if (!built) return built.error();
  return std::move(built->models);
}

/// Loads a .map and builds its models (buildAsLoaded). A failure is a test
/// failure and gives no models.
inline std::vector<ModelPtr> buildMapModels(const std::filesystem::path& path) {
  auto map = loadMapFile(path.string());
  EXPECT_TRUE(map.ok()) << (map.ok() ? "" : map.error().toString());
  if (!map.ok()) return {};
  auto models = buildAsLoaded(*map, path);
  EXPECT_TRUE(models.ok()) << (models.ok() ? "" : models.error().toString());
  return models.ok() ? *models : std::vector<ModelPtr>{};
}

/// pointContents(m, {p, placement}, a QueryWork of its own).contents: the
/// contents alone, for tests of what a point is inside.
inline std::uint32_t pointContentsAt(const CollisionModel& m, const Vec3& p,
                                     const Placement& placement = {}) {
  QueryWork work;
  return pointContents(m, {p, placement}, work).contents;
}

/// A brushDef3 side line: the plane a x + b y + c z + d = 0 (normal out of
/// the brush) with `material`.
inline std::string brushSide(double a, double b, double c, double d, const char* material) {
  return "  ( " + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(c) + " " +
         std::to_string(d) + " ) ( ( 0.0078125 0 0 ) ( 0 0.0078125 0 ) ) \"" + material + "\" 0 0 0\n";
}

/// One axial brush side per bound, all with `material`.
inline std::string axialBrush(const Bounds& b, const char* material) {
  std::string s = "{\n brushDef3\n {\n";
  const double planes[6][4] = {{1, 0, 0, -b.max.x}, {-1, 0, 0, b.min.x}, {0, 1, 0, -b.max.y},
                               {0, -1, 0, b.min.y}, {0, 0, 1, -b.max.z}, {0, 0, -1, b.min.z}};
  for (const auto& p : planes) s += brushSide(p[0], p[1], p[2], p[3], material);
  return s + " }\n}\n";
}

/// The models of a parsed or loaded map (a failed parse, load or build
/// fails the test).
inline std::vector<ModelPtr> buildModelsFromMap(const Result<MapFile>& map, bool robustEdges = false) {
  EXPECT_TRUE(map.ok()) << (map.ok() ? "" : map.error().toString());
  if (!map) return {};
  BuildOptions options;
  options.robustEdges = robustEdges;
  auto models = buildCollisionModels(*map, MaterialTable{}, options);
  EXPECT_TRUE(models.ok());
  return models ? models->models : std::vector<ModelPtr>{};
}

/// The models of a map given as text (buildModelsFromMap).
inline std::vector<ModelPtr> buildModelsFromText(const std::string& text, bool robustEdges = false) {
  return buildModelsFromMap(parseMapText(text), robustEdges);
}

}  // namespace cmkit::test

/// Skips the current test with a message when ../shared is absent: for
/// tests over all of its data. `what` names the files needed and why they
/// are not bundled.
#define CMKIT_REQUIRE_SHARED(what)                                                                    \
  do {                                                                                                \
    if (!::cmkit::test::haveShared())                                                                 \
      GTEST_SKIP() << "needs the shared data folder " << ::cmkit::test::sharedDir() << " (" << (what) \
                   << "); absent, so skipped";                                                        \
  } while (0)
