// One entity's model to a file (the original's WriteCollisionModelForMapEntity)
// and `cmkit compile MAP --entity NAME -o FILE.cm [--test-trm]`.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "cmkit/cm_file.h"
#include "cmkit/compile.h"
#include "cmkit/map.h"
#include "test_support.h"

namespace {

namespace fs = std::filesystem;
using namespace cmkit;

fs::path scratch() {
  const fs::path dir = test::uniqueTempPath("entity_model");
  fs::create_directories(dir);
  return dir;
}

MapFile inlinePatchMap() {
  auto map = loadMapFile((test::testDataDir() / "proc" / "inline_patch_proc.map").string());
  EXPECT_TRUE(map.ok()) << map.error().toString();
  return *map;
}

TEST(EntityModel, FindsEntitiesByNameOrNumber) {
  const MapFile map = inlinePatchMap();
  EXPECT_EQ(*map.findEntity("door_1"), 2u);
  EXPECT_EQ(*map.findEntity("#0"), 0u);
  EXPECT_EQ(*map.findEntity("#4"), 4u);
  EXPECT_FALSE(map.findEntity("#6").ok());
  EXPECT_FALSE(map.findEntity("#x").ok());
  const auto unknown = map.findEntity("nosuch");
  ASSERT_FALSE(unknown.ok());
  EXPECT_NE(unknown.error().message.find("nosuch"), std::string::npos);
}

// Every entity with primitives: the written file holds one model named
// after the file, CRC 0, with the counts of that entity's model in the
// full compile (without the .proc, which the original never applies here).
TEST(EntityModel, TheWrittenModelEqualsTheEntitysModelInTheFullCompile) {
  CMKIT_FLOAT_BUILD_ONLY();
  const MapFile map = inlinePatchMap();
  auto all = buildCollisionModels(map, MaterialTable{});
  ASSERT_TRUE(all.ok());
  std::size_t model = 0;
  for (std::size_t e = 0; e < map.entities.size(); ++e) {
    if (map.entities[e].primitives.empty()) continue;
    SCOPED_TRACE(e);
    const std::string path = (scratch() / ("entity" + std::to_string(e) + ".cm")).string();
    const Result<EntityModelReport> written = writeCollisionModelForMapEntity(map, e, path, MaterialTable{});
    ASSERT_TRUE(written.ok());
    const EntityModelReport& report = *written;
    auto file = loadCmFile(path, MaterialTable{});
    ASSERT_TRUE(file.ok()) << file.error().toString();
    EXPECT_EQ(file->crc, 0u);
    ASSERT_EQ(file->models.size(), 1u);
    const CollisionModel& read = *file->models[0];
    const CollisionModel& full = *all->models[model++];
    EXPECT_EQ(read.name(), path);
    EXPECT_EQ(report.model->name(), path);
    EXPECT_EQ(read.vertices().size(), full.vertices().size());
    EXPECT_EQ(read.edges().size(), full.edges().size());
    EXPECT_EQ(read.polygons().size(), full.polygons().size());
    EXPECT_EQ(read.brushes().size(), full.brushes().size());
    EXPECT_EQ(read.nodes().size(), full.nodes().size());
    EXPECT_EQ(read.bounds().min, full.bounds().min);
    EXPECT_EQ(read.bounds().max, full.bounds().max);
    // the same text as the full compile's model renamed
    ModelArrays renamed = full.arrays();
    renamed.name = path;
    const ModelPtr one = *CollisionModel::create(std::move(renamed));
    EXPECT_EQ(test::readFile(path), writeCmText(std::span<const ModelPtr>(&one, 1), 0));
    EXPECT_FALSE(report.traceModel.has_value());  // not asked
  }
  EXPECT_EQ(model, all->models.size());
  fs::remove_all(scratch());
}

TEST(EntityModel, TestsTheTraceModel) {
  const MapFile map = inlinePatchMap();
  const std::string path = (scratch() / "door.cm").string();
  EntityModelOptions options;
  options.testTraceModel = true;
  Result<EntityModelReport> report =
      writeCollisionModelForMapEntity(map, *map.findEntity("door_1"), path, MaterialTable{}, options);
  ASSERT_TRUE(report.ok());
  ASSERT_TRUE(report->traceModel.has_value());
  ASSERT_TRUE(report->traceModel->ok()) << report->traceModel->error().toString();
  EXPECT_EQ((*report->traceModel)->numVertices(), 8);
  EXPECT_EQ((*report->traceModel)->numEdges(), 12);
  EXPECT_EQ((*report->traceModel)->numPolygons(), 6);
  // the world (a room seen from inside) is no trace model: a finding, the
  // file is still written
  report = writeCollisionModelForMapEntity(map, 0, path, MaterialTable{}, options);
  ASSERT_TRUE(report.ok());
  ASSERT_TRUE(report->traceModel.has_value());
  EXPECT_FALSE(report->traceModel->ok());
  EXPECT_FALSE(report->traceModel->error().message.empty());
  EXPECT_TRUE(fs::exists(path));
  fs::remove_all(scratch());
}

TEST(EntityModel, ErrorsWriteNothing) {
  const MapFile map = inlinePatchMap();
  const fs::path path = scratch() / "none.cm";
  const Result<EntityModelReport> noPrimitives =
      writeCollisionModelForMapEntity(map, 5, path.string(), MaterialTable{});
  ASSERT_FALSE(noPrimitives.ok());
  EXPECT_NE(noPrimitives.error().message.find("no brushes or patches"), std::string::npos);
  EXPECT_FALSE(writeCollisionModelForMapEntity(map, 99, path.string(), MaterialTable{}).ok());
  EXPECT_FALSE(fs::exists(path));
  const Result<EntityModelReport> noDir =
      writeCollisionModelForMapEntity(map, 2, (scratch() / "missing" / "x.cm").string(), MaterialTable{});
  EXPECT_FALSE(noDir.ok());
  for (const auto& e : fs::directory_iterator(scratch())) ADD_FAILURE() << "left behind: " << e.path();
  fs::remove_all(scratch());
}

#define CMKIT_REQUIRE_CLI() \
  if (std::string(CMKIT_CLI_PATH).empty()) GTEST_SKIP() << "the CLI is not built"

TEST(EntityModel, CliCompileEntity) {
  CMKIT_REQUIRE_CLI();
  const std::string cli = CMKIT_CLI_PATH;
  const std::string map = (test::testDataDir() / "proc" / "inline_patch_proc.map").string();
  const std::string out = (scratch() / "door.cm").string();
  int status = 0;
  std::string text = test::runCapture(
      cli + " compile '" + map + "' --entity door_1 -o '" + out + "' --test-trm 2>&1", status);
  EXPECT_EQ(status, 0) << text;
  EXPECT_NE(text.find("trace model: 8 vertices, 12 edges, 6 polygons"), std::string::npos) << text;
  EXPECT_TRUE(fs::exists(out));
  text =
      test::runCapture(cli + " compile '" + map + "' --entity '#0' -o '" + out + "' --test-trm 2>&1", status);
  EXPECT_EQ(status, 0) << text;
  EXPECT_NE(text.find("not a trace model: "), std::string::npos) << text;
  text = test::runCapture(cli + " compile '" + map + "' --entity nosuch -o '" + out + "' 2>&1", status);
  EXPECT_EQ(status, 2);
  EXPECT_NE(text.find("no entity named \"nosuch\""), std::string::npos) << text;
  text = test::runCapture(cli + " compile '" + map + "' --entity info_player_start_1 -o '" + out + "' 2>&1",
                          status);
  EXPECT_EQ(status, 2);
  EXPECT_NE(text.find("no brushes or patches"), std::string::npos) << text;
  fs::remove_all(scratch());
}

}  // namespace
