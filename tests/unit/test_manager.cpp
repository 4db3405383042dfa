// The model manager: handles, names, loading maps (with and without an
// up-to-date .cm), trace models as collision models and back, threads.
#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <thread>

#include "cm_test_util.h"
#include "cmkit/cm_file.h"
#include "cmkit/manager.h"
#include "cmkit/validate.h"
#include "model_fixtures.h"
#include "test_support.h"

namespace cmkit {
namespace {

std::string cmData(const char* name) { return (test::testDataDir() / "cm" / name).string(); }

TEST(Manager, LoadFindFreeClearList) {
  ModelManager mm;
  const MaterialTable materials;
  Result<std::vector<ModelHandle>> ep1 = mm.loadCm(cmData("ep1.cm"), materials);
  ASSERT_TRUE(ep1.ok()) << ep1.error().toString();
  ASSERT_EQ(ep1->size(), 4u);
  EXPECT_EQ((*ep1)[0], kWorldModelHandle);
  Result<std::vector<ModelHandle>> test = mm.loadCm(cmData("opentechbfg_test.cm"), materials);
  ASSERT_TRUE(test.ok());
  ASSERT_EQ(test->size(), 1u);
  EXPECT_EQ((*test)[0].index, 4);
  EXPECT_EQ(mm.size(), 5u);

  // Names: the first model of a repeated name; "#N"; unknown names fail.
  Result<ModelHandle> h = mm.find("func_static_2");
  ASSERT_TRUE(h.ok());
  EXPECT_EQ(*h, kWorldModelHandle);
  h = mm.find("worldMap");
  ASSERT_TRUE(h.ok());
  EXPECT_EQ(h->index, 4);
  EXPECT_FALSE(mm.find("no such model").ok());
  EXPECT_FALSE(mm.find("").ok());
  h = mm.find("#2");
  ASSERT_TRUE(h.ok());
  EXPECT_EQ(h->index, 2);
  EXPECT_FALSE(mm.find("#99").ok());

  // The manager hands out models (get, require); what a model is and does
  // are the model's own data and functions.
  Result<ModelPtr> required = mm.require(ModelHandle{4});
  ASSERT_TRUE(required.ok());
  const ModelPtr world = *required;
  EXPECT_EQ(world, mm.get(ModelHandle{4}));
  EXPECT_EQ(world->name(), "worldMap");
  const std::vector<Vec3> winding = polygonWinding(*world, 0);
  EXPECT_EQ(winding.size(), world->polygons()[0].numEdges);
  for (const Vec3& v : winding) EXPECT_LE(std::fabs(world->polygons()[0].plane.distance(v)), 0.25f);
  const std::string stats = modelStatistics(*world);
  EXPECT_EQ(stats.rfind("worldMap\n", 0), 0u);
  EXPECT_NE(stats.find(" vertices ("), std::string::npos);
  EXPECT_NE(stats.find(" sharp edges\n"), std::string::npos);
  EXPECT_NE(stats.find(" KB total memory used\n"), std::string::npos);

  // Freeing one model leaves every other handle valid.
  ASSERT_TRUE(mm.free(ModelHandle{1}).ok());
  EXPECT_FALSE(mm.get(ModelHandle{1}));
  EXPECT_FALSE(mm.free(ModelHandle{1}).ok());
  EXPECT_FALSE(mm.require(ModelHandle{1}).ok());
  EXPECT_EQ(mm.get(ModelHandle{4})->name(), "worldMap");
  EXPECT_TRUE(mm.get(ModelHandle{2}));
  EXPECT_EQ(mm.size(), 4u);
  const auto listed = mm.list();
  ASSERT_EQ(listed.size(), 4u);
  EXPECT_EQ(listed[1].handle.index, 2);
  // A new model gets a new handle; the freed one is not reused.
  const ModelHandle added = mm.add(world);
  EXPECT_EQ(added.index, 5);
  // The freed model's name no longer finds it; a model the caller still
  // holds stays alive.
  ASSERT_TRUE(mm.free(ModelHandle{4}).ok());
  EXPECT_EQ(mm.find("worldMap")->index, 5);
  EXPECT_FALSE(world->polygons().empty());

  mm.clear();
  EXPECT_EQ(mm.size(), 0u);
  EXPECT_TRUE(mm.list().empty());
  EXPECT_FALSE(mm.find("worldMap").ok());
  EXPECT_FALSE(mm.get(kWorldModelHandle));
  EXPECT_EQ(mm.add(world), kWorldModelHandle);
  EXPECT_FALSE(mm.loadCm(cmData("missing.cm"), materials).ok());
  EXPECT_EQ(mm.size(), 1u);
}

TEST(Manager, LoadMapBuildsOrUsesAnUpToDateCm) {
  const test::ScratchDir dir("manager_map");
  const auto mapPath = (dir.path() / "features.map").string();
  std::filesystem::copy_file(test::testDataDir() / "maps" / "features.map", mapPath);
  const MaterialTable materials;
  ModelManager mm;
  mm.add(collisionModelFromTraceModel(*TraceModel::box(Bounds({-1, -1, -1}, {1, 1, 1}))));

  // No .cm: built, and (on request) written like the original does.
  LoadMapOptions write;
  write.writeCmFile = true;
  Result<LoadMapResult> built = mm.loadMap(mapPath, materials, write);
  ASSERT_TRUE(built.ok()) << built.error().toString();
  EXPECT_FALSE(built->fromCmFile);
  ASSERT_FALSE(built->handles.empty());
  EXPECT_EQ(built->handles[0], kWorldModelHandle);
  EXPECT_EQ(mm.size(), built->handles.size());  // the map replaced everything
  const auto cmPath = dir.path() / "features.cm";
  ASSERT_TRUE(std::filesystem::exists(cmPath));
  EXPECT_EQ(*readCmFileCrc(cmPath.string()), built->geometryCrc);
  const ModelPtr builtWorld = mm.get(kWorldModelHandle);

  // The .cm matches the map's CRC: loaded instead of building.
  Result<LoadMapResult> loaded = mm.loadMap(mapPath, materials);
  ASSERT_TRUE(loaded.ok());
  EXPECT_TRUE(loaded->fromCmFile);
  EXPECT_EQ(loaded->handles.size(), built->handles.size());
  EXPECT_EQ(mm.get(kWorldModelHandle)->polygons().size(), builtWorld->polygons().size());
  EXPECT_EQ(mm.get(kWorldModelHandle)->name(), builtWorld->name());

  // Forced: built again.
  LoadMapOptions force;
  force.forceRebuild = true;
  Result<LoadMapResult> rebuilt = mm.loadMap(mapPath, materials, force);
  ASSERT_TRUE(rebuilt.ok());
  EXPECT_FALSE(rebuilt->fromCmFile);

  // An out-of-date .cm (another CRC) is ignored.
  {
    Result<CmFile> f = loadCmFile(cmPath.string(), materials);
    ASSERT_TRUE(f.ok());
    ASSERT_TRUE(saveCmFile(cmPath.string(), f->models, built->geometryCrc ^ 1u).ok());
  }
  Result<LoadMapResult> stale = mm.loadMap(mapPath, materials);
  ASSERT_TRUE(stale.ok());
  EXPECT_FALSE(stale->fromCmFile);

  // A missing map is an error and leaves the manager as it was.
  const std::size_t before = mm.size();
  EXPECT_FALSE(mm.loadMap((dir.path() / "missing.map").string(), materials).ok());
  EXPECT_EQ(mm.size(), before);
}

TEST(Manager, SeveralTraceModelModelsAtOnce) {
  ModelManager mm;
  const TraceModel box = *TraceModel::box(Bounds({-16, -16, 0}, {16, 16, 72}));
  const TraceModel cylinder = *TraceModel::cylinder(Bounds({-8, -8, -8}, {8, 8, 8}), 8);
  const TraceModel polygon = *TraceModel::polygon(std::vector<Vec3>{{0, 0, 0}, {10, 0, 0}, {0, 10, 0}});
  const ModelHandle a = mm.addTraceModel(box);
  const ModelHandle b = mm.addTraceModel(cylinder, contents::kWater, "textures/water");
  const ModelHandle c = mm.addTraceModel(polygon);
  EXPECT_NE(a, b);
  EXPECT_NE(b, c);
  for (const ModelHandle h : {a, b, c}) {
    const ModelPtr m = mm.get(h);
    ASSERT_TRUE(m);
    EXPECT_TRUE(m->isConvex());
    for (const Violation& v : validateModel(*m)) ADD_FAILURE() << v.toString();
  }
  const ModelPtr mb = mm.get(b);
  EXPECT_EQ(mb->contents(), contents::kWater);
  EXPECT_EQ(mb->polygons().size(), std::size_t(cylinder.numPolygons()));
  EXPECT_EQ(mb->numEdges(), std::size_t(cylinder.numEdges()));
  EXPECT_EQ(mb->materialName(mb->polygons()[0].material), "textures/water");
  EXPECT_EQ(mb->bounds(), cylinder.bounds());
  // The box's edges keep the trace model's numbering and normals.
  const ModelPtr ma = mm.get(a);
  for (int e = 1; e <= box.numEdges(); ++e) {
    EXPECT_EQ(ma->edges()[std::size_t(e)].vertex[0], box.edge(e).v[0]);
    EXPECT_EQ(ma->edges()[std::size_t(e)].normal, box.edge(e).normal);
    EXPECT_EQ(ma->edges()[std::size_t(e)].numUsers, 2);
  }
}

TEST(Manager, TrmFromModelRoundTripsAConvexModel) {
  ModelManager mm;
  const TraceModel box = *TraceModel::box(Bounds({-16, -16, 0}, {16, 16, 72}));
  const ModelHandle h = mm.addTraceModel(box);
  Result<TraceModel> back = traceModelFromCollisionModel(*mm.get(h));
  ASSERT_TRUE(back.ok()) << back.error().toString();
  EXPECT_TRUE(back->isConvex());
  EXPECT_EQ(back->numVertices(), 8);
  EXPECT_EQ(back->numEdges(), 12);
  EXPECT_EQ(back->numPolygons(), 6);
  EXPECT_EQ(back->bounds(), box.bounds());
  EXPECT_EQ(back->checkInvariants(), "");

  // A convex model loaded from .cm text (not flagged convex) also converts.
  const TraceModel octa = *TraceModel::octahedron(Bounds({-8, -8, -8}, {8, 8, 8}));
  const ModelPtr octaModel = collisionModelFromTraceModel(octa);
  Result<CmFile> f =
      parseCmText(writeCmText(std::vector<ModelPtr>{octaModel}, 0), "octa.cm", MaterialTable{});
  ASSERT_TRUE(f.ok()) << f.error().toString();
  Result<TraceModel> fromFile = traceModelFromCollisionModel(*f->models[0]);
  ASSERT_TRUE(fromFile.ok()) << fromFile.error().toString();
  EXPECT_EQ(fromFile->numVertices(), 6);
  EXPECT_EQ(fromFile->numPolygons(), 8);
}

TEST(Manager, TrmFromModelRejectsConcaveOpenAndTooBigModels) {
  // Two boxes side by side: each closed, together not convex.
  test::ModelMaker two;
  two.addBox(Bounds({0, 0, 0}, {10, 10, 10})).addBox(Bounds({10, 0, 0}, {20, 10, 20}));
  Result<TraceModel> r = traceModelFromCollisionModel(two.build());
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("not convex"), std::string::npos) << r.error().message;

  // A single polygon is not closed.
  const ModelPtr flat = collisionModelFromTraceModel(
      *TraceModel::polygon(std::vector<Vec3>{{0, 0, 0}, {10, 0, 0}, {10, 10, 0}, {0, 10, 0}}));
  ModelArrays open = flat->arrays();
  open.polygons.resize(1);
  open.nodes[0].numPolygonRefs = 1;
  open.polygonRefs.resize(1);
  r = traceModelFromCollisionModel(**CollisionModel::create(std::move(open)));
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("not closed"), std::string::npos) << r.error().message;

  // A whole map is over the trace model limits.
  Result<CmFile> f = loadCmFile(cmData("opentechbfg_test.cm"), MaterialTable{});
  ASSERT_TRUE(f.ok());
  ModelManager mm;
  const ModelHandle world = mm.add(f->models[0]);
  r = traceModelFromCollisionModel(*mm.get(world));
  ASSERT_FALSE(r.ok());
  EXPECT_FALSE(r.error().message.empty());
}

// Loading and freeing on one thread while others read already loaded models.
TEST(Manager, LoadingIsSafeWhileOtherThreadsQuery) {
  ModelManager mm;
  const MaterialTable materials;
  ASSERT_TRUE(mm.loadCm(cmData("ep1.cm"), materials).ok());
  const ModelHandle world = kWorldModelHandle;
  const std::size_t polygons = mm.get(world)->polygons().size();
  std::atomic<bool> stop{false};
  std::atomic<long> reads{0};
  std::vector<std::thread> readers;
  for (int t = 0; t < 3; ++t) {
    readers.emplace_back([&] {
      while (!stop) {
        const ModelPtr m = mm.get(world);
        if (!m || m->polygons().size() != polygons) ADD_FAILURE() << "world changed";
        if (!mm.find("func_static_2").ok()) ADD_FAILURE() << "name lost";
        (void)mm.list();
        ++reads;
        std::this_thread::yield();
      }
    });
  }
  for (int i = 0; i < 8 || (reads < 100 && i < 100000); ++i) {
    Result<std::vector<ModelHandle>> hs = mm.loadCm(cmData("blender_misc_model1.cm"), materials);
    ASSERT_TRUE(hs.ok());
    for (const ModelHandle h : *hs) ASSERT_TRUE(mm.free(h).ok());
  }
  stop = true;
  for (std::thread& t : readers) t.join();
  EXPECT_GT(reads.load(), 0);
  EXPECT_EQ(mm.size(), 4u);
}

TEST(Manager, RayIndexIsBuiltOnceAndDroppedWithItsModel) {
  ModelManager mm;
  const MaterialTable materials;
  ASSERT_TRUE(mm.loadCm(cmData("opentechbfg_test.cm"), materials).ok());
  const ModelHandle world = kWorldModelHandle;
  Result<std::shared_ptr<const RayIndex>> a = mm.rayIndex(world);
  ASSERT_TRUE(a.ok()) << a.error().toString();
  ASSERT_TRUE(*a);
  EXPECT_EQ((*a)->numPolygons(), mm.get(world)->polygons().size());
  Result<std::shared_ptr<const RayIndex>> b = mm.rayIndex(world);
  ASSERT_TRUE(b.ok());
  EXPECT_EQ(a->get(), b->get()) << "built again";
  // A ray down through the middle of the world hits what the index says.
  const Bounds box = mm.get(world)->bounds();
  const Vec3 mid = (box.min + box.max) * Real(0.5);
  const Vec3 from{mid.x, mid.y, box.max.z + 64}, to{mid.x, mid.y, box.min.z - 64};
  const RayHit hit = (*a)->cast({from, to, ~0u});
  ASSERT_TRUE(hit.hit());

  EXPECT_FALSE(mm.rayIndex(ModelHandle{7}).ok());
  ASSERT_TRUE(mm.free(world).ok());
  EXPECT_FALSE(mm.rayIndex(world).ok()) << "a freed model has no index";
  const RayHit again = (*a)->cast({from, to, ~0u});  // an index handed out stays usable
  EXPECT_EQ(again.polygon, hit.polygon);
  EXPECT_EQ(again.fraction, hit.fraction);
  mm.clear();
  ASSERT_TRUE(mm.loadCm(cmData("blender_misc_model1.cm"), materials).ok());
  Result<std::shared_ptr<const RayIndex>> c = mm.rayIndex(world);
  ASSERT_TRUE(c.ok());
  EXPECT_EQ((*c)->numPolygons(), mm.get(world)->polygons().size()) << "an index of the new model";
}

TEST(Manager, RayIndexFromManyThreadsAtOnce) {
  ModelManager mm;
  ASSERT_TRUE(mm.loadCm(cmData("ep1.cm"), MaterialTable{}).ok());
  std::vector<std::shared_ptr<const RayIndex>> got(4);
  std::vector<std::thread> threads;
  for (std::size_t t = 0; t < got.size(); ++t)
    threads.emplace_back([&, t] {
      auto r = mm.rayIndex(kWorldModelHandle);
      if (r.ok()) got[t] = *r;
    });
  for (std::thread& t : threads) t.join();
  for (const auto& index : got) {
    ASSERT_TRUE(index);
    EXPECT_EQ(index->numPolygons(), got[0]->numPolygons());
  }
  // Afterwards every caller gets the one that was kept.
  EXPECT_EQ(mm.rayIndex(kWorldModelHandle)->get(), mm.rayIndex(kWorldModelHandle)->get());
}

}  // namespace
}  // namespace cmkit
