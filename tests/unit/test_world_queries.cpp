// World queries (cmkit/world.h) against brute force: on lt4 (its world
// model and every func_static, plus trace-model "monsters" placed at random
// orientations), each world answer equals, bit for bit, the closest of the
// answers of every entity asked one by one, for random translations,
// rotations, position tests, point contents, contacts and rays; again after
// entities moved, were removed and added. Filters leave entities out.
// Batches give the single answers on 1 and 3 threads, and readers on
// several threads at once agree with one thread (run under TSan by
// ./dev.sh tsan).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "cmkit/world.h"
#include "test_support.h"

using namespace cmkit;

namespace {

std::string bits(Real v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%a", double(v));
  return buf;
}
std::string bits(const Vec3& v) { return bits(v.x) + "," + bits(v.y) + "," + bits(v.z); }
std::string bits(const Mat3& m) { return bits(m[0]) + ";" + bits(m[1]) + ";" + bits(m[2]); }
std::string bits(const ContactInfo& c) {
  return std::to_string(int(c.type)) + " " + bits(c.point) + " " + bits(c.normal) + " " + bits(c.dist) + " " +
         std::to_string(c.contents) + " " + std::to_string(c.material) + " " +
         std::to_string(c.modelFeature) + " " + std::to_string(c.trmFeature) + " " + bits(c.angle);
}
std::string bits(const TraceResult& r) {
  return bits(r.fraction) + " " + bits(r.endPos) + " " + bits(r.endAxis) + " " + bits(r.contact) + " " +
         std::to_string(int(r.startSolid)) + std::to_string(int(r.status));
}
std::string bits(const WorldTraceResult& r) { return std::to_string(r.entity) + " " + bits(r.trace); }
std::string bits(const WorldContentsResult& r) {
  return std::to_string(r.entity) + " " + std::to_string(r.result.contents) + " " + bits(r.result.trace) +
         std::to_string(int(r.result.status));
}
std::string bits(const WorldPointContentsResult& r) {
  return std::to_string(r.entity) + " " + std::to_string(r.contents) + std::to_string(int(r.status));
}
std::string bits(const WorldContactsResult& r) {
  std::string s = std::to_string(int(r.status));
  for (const WorldContact& c : r.contacts) s += " [" + std::to_string(c.entity) + " " + bits(c.contact) + "]";
  return s;
}
std::string bits(const WorldRayHit& r) {
  return std::to_string(r.entity) + " " + bits(r.hit.fraction) + " " + bits(r.hit.point) + " " +
         bits(r.hit.normal) + " " + std::to_string(r.hit.polygon);
}

// ---- Brute force: every live entity asked, the world.h rules applied. ----

bool keeps(const WorldEntity& e, std::uint32_t mask, const EntityFilter& f) {
  if ((mask == 0 ? e.contents : (e.contents & mask)) == 0) return false;
  if (std::find(f.ignore.begin(), f.ignore.end(), e.id) != f.ignore.end()) return false;
  return !f.accept || f.accept(e);
}

template <class Query, class Run>
WorldTraceResult closestTrace(const World& world, Query q, const EntityFilter& f, Run run) {
  WorldTraceResult out;
  QueryWork work;
  bool asked = false, startSolid = false;
  for (const EntityId id : world.entityIds()) {
    const WorldEntity& e = *world.entity(id);
    if (!keeps(e, q.contentMask, f)) continue;
    q.placement = e.placement;
    const TraceResult r = run(*e.model, q, work);
    startSolid = startSolid || r.startSolid;
    if (!asked || r.fraction < out.trace.fraction) {
      out = {r, id};
      asked = true;
    }
  }
  if (!(out.trace.fraction < 1)) out.entity = kNoEntity;
  out.trace.startSolid = startSolid;
  return out;
}

WorldContentsResult bruteContents(const World& world, ContentsQuery q) {
  WorldContentsResult out;
  QueryWork work;
  std::uint32_t all = 0;
  bool asked = false;
  for (const EntityId id : world.entityIds()) {
    const WorldEntity& e = *world.entity(id);
    if (!keeps(e, q.contentMask, {})) continue;
    q.placement = e.placement;
    const ContentsResult r = contentsTest(*e.model, q, work);
    all |= r.contents;
    if (!asked || (out.entity == kNoEntity && r.contents != 0)) {
      out.result = r;
      out.entity = r.contents != 0 ? id : kNoEntity;
      asked = true;
    }
  }
  out.result.contents = all;
  return out;
}

WorldPointContentsResult brutePoint(const World& world, PointContentsQuery q) {
  WorldPointContentsResult out;
  QueryWork work;
  for (const EntityId id : world.entityIds()) {
    const WorldEntity& e = *world.entity(id);
    if (e.contents == 0) continue;
    q.placement = e.placement;
    const std::uint32_t c = pointContents(*e.model, q, work).contents;
    if (c != 0 && out.entity == kNoEntity) out.entity = id;
    out.contents |= c;
  }
  return out;
}

WorldContactsResult bruteContacts(const World& world, ContactsQuery q) {
  WorldContactsResult out;
  QueryWork work;
  for (const EntityId id : world.entityIds()) {
    const WorldEntity& e = *world.entity(id);
    if (!keeps(e, q.contentMask, {})) continue;
    q.placement = e.placement;
    for (const ContactInfo& c : contacts(*e.model, q, work).contacts) out.contacts.push_back({c, id});
  }
  if (q.rotation)
    std::stable_sort(out.contacts.begin(), out.contacts.end(),
                     [](const WorldContact& a, const WorldContact& b) {
                       return std::fabs(a.contact.angle) < std::fabs(b.contact.angle);
                     });
  if (out.contacts.size() > std::size_t(q.maxContacts)) out.contacts.resize(std::size_t(q.maxContacts));
  return out;
}

WorldRayHit bruteRay(const World& world, RayCastQuery q) {
  // Each model's index built once (by the test, not the world's); the model
  // is kept alive with it, so that its address is not reused.
  static std::map<const CollisionModel*, std::pair<ModelPtr, RayIndex>> indexes;
  WorldRayHit out;
  for (const EntityId id : world.entityIds()) {
    const WorldEntity& e = *world.entity(id);
    if (!keeps(e, q.contentMask, {})) continue;
    q.placement = e.placement;
    auto it = indexes.find(e.model.get());
    if (it == indexes.end())
      it = indexes.emplace(e.model.get(), std::pair(e.model, RayIndex(*e.model))).first;
    const RayHit hit = it->second.second.cast(q);
    if (hit.hit() && (!out.hit.hit() || hit.fraction < out.hit.fraction)) out = {hit, id};
  }
  return out;
}

// ---- The world: lt4 plus monsters. ----

class WorldQueries : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const auto path = std::filesystem::path(CMKIT_SOURCE_DIR) / "data/maps/lt4/lt4.map";
    auto map = loadMapFile(path.string());
    ASSERT_TRUE(map.ok()) << map.error().toString();
    auto models = test::buildAsLoaded(*map, path);
    ASSERT_TRUE(models.ok()) << models.error().toString();
    auto loaded = World::fromMap(*map, *models);
    ASSERT_TRUE(loaded.ok()) << loaded.error().toString();
    world_ = new World(std::move(loaded->world));
    std::mt19937 rng(35);
    const Bounds b = world_->entity(kWorldspawnEntity)->bounds;
    for (int i = 0; i < 40; ++i) {
      auto trm = i % 2 ? TraceModel::box({{-16, -16, 0}, {16, 16, 72}})
                       : TraceModel::cylinder({{-20, -20, -30}, {20, 20, 30}}, 8);
      ASSERT_TRUE(trm.ok());
      auto id = world_->addTraceModelEntity("monster" + std::to_string(i), *trm, randomPlacement(rng, b));
      ASSERT_TRUE(id.ok()) << id.error().toString();
    }
  }
  static void TearDownTestSuite() {
    delete world_;
    world_ = nullptr;
  }

  static Real uniform(std::mt19937& rng, Real lo, Real hi) {
    return lo + (hi - lo) * Real(std::uniform_real_distribution<double>(0, 1)(rng));
  }
  static Vec3 pointIn(std::mt19937& rng, const Bounds& b) {
    return {uniform(rng, b.min.x, b.max.x), uniform(rng, b.min.y, b.max.y), uniform(rng, b.min.z, b.max.z)};
  }
  static Placement randomPlacement(std::mt19937& rng, const Bounds& b) {
    std::uniform_real_distribution<double> u(0, 1);
    return {pointIn(rng, b), rotationFromUniforms(u(rng), u(rng), u(rng))};
  }
  // A start near some entity (half of the time) or anywhere in the map.
  static Vec3 startNear(std::mt19937& rng) {
    const std::vector<EntityId> ids = world_->entityIds();
    if (rng() % 2) return pointIn(rng, world_->entity(kWorldspawnEntity)->bounds);
    const WorldEntity& e = *world_->entity(ids[rng() % ids.size()]);
    return pointIn(rng, e.bounds.expanded(48));
  }
  static Vec3 offset(std::mt19937& rng, Real reach) {
    return {uniform(rng, -reach, reach), uniform(rng, -reach, reach), uniform(rng, -reach, reach)};
  }

  // Every kind, `n` random queries each, world against brute force.
  static void checkAgainstBruteForce(unsigned seed, int n) {
    std::mt19937 rng(seed);
    auto box = TraceModel::box({{-16, -16, 0}, {16, 16, 72}});
    auto bone = TraceModel::bone(40, 12);
    ASSERT_TRUE(box.ok() && bone.ok());
    WorldQueryWork work;
    int hits = 0, entityHits = 0;
    for (int i = 0; i < n; ++i) {
      const TraceModel* trm = i % 3 == 0 ? nullptr : (i % 3 == 1 ? &*box : &*bone);
      std::uniform_real_distribution<double> u(0, 1);
      const Mat3 trmAxis = i % 2 ? Mat3::identity() : rotationFromUniforms(u(rng), u(rng), u(rng));
      const Vec3 start = startNear(rng);

      TranslationQuery tq;
      tq.trm = trm;
      tq.trmAxis = trmAxis;
      tq.start = start;
      tq.end = start + offset(rng, 256);
      tq.detectStartSolid = i % 4 == 0;
      const WorldTraceResult t = world_->translate(tq, work);
      ASSERT_EQ(bits(t), bits(closestTrace(*world_, tq, {},
                                           [](auto& m, auto& q, auto& w) { return translate(m, q, w); })))
          << "translation " << i;
      hits += t.trace.fraction < 1;
      entityHits += t.entity > kWorldspawnEntity;

      RotationQuery rq;
      rq.trm = trm;
      rq.trmAxis = trmAxis;
      rq.start = start;
      const Vec3 axis = offset(rng, 1);
      rq.rotation =
          Rotation(start + offset(rng, 48), axis.lengthSquared() > 1e-4f ? axis.normalized() : Vec3{0, 0, 1},
                   uniform(rng, -200, 200));
      ASSERT_EQ(
          bits(world_->rotate(rq, work)),
          bits(closestTrace(*world_, rq, {}, [](auto& m, auto& q, auto& w) { return rotate(m, q, w); })))
          << "rotation " << i;

      const ContentsQuery cq{trm, trmAxis, start, contents::kMaskSolid, {}};
      ASSERT_EQ(bits(world_->contentsTest(cq, work)), bits(bruteContents(*world_, cq))) << "contents " << i;
      const PointContentsQuery pq{start, {}};
      ASSERT_EQ(bits(world_->pointContents(pq, work)), bits(brutePoint(*world_, pq))) << "point " << i;

      ContactsQuery kq;
      kq.trm = trm;
      kq.trmAxis = trmAxis;
      kq.start = start;
      kq.dir = offset(rng, 1);
      kq.depth = 64;
      kq.maxContacts = 12;
      if (i % 5 == 0) {
        kq.dir = {};
        kq.rotation = rq.rotation;
      }
      ASSERT_EQ(bits(world_->contacts(kq, work)), bits(bruteContacts(*world_, kq))) << "contacts " << i;

      const RayCastQuery ray{start, start + offset(rng, 1024), contents::kMaskSolid, {}};
      ASSERT_EQ(bits(world_->castRay(ray, work)), bits(bruteRay(*world_, ray))) << "ray " << i;
    }
    // The sample is worth something: hits, some of them on entities.
    EXPECT_GT(hits, n / 10);
    EXPECT_GT(entityHits, 0);
  }

  static World* world_;
};

World* WorldQueries::world_ = nullptr;

}  // namespace

TEST_F(WorldQueries, Lt4HasItsEntities) {
  // lt4: the world model and its func_statics with brushes, plus 40 monsters.
  EXPECT_GT(world_->size(), 100u);
  std::printf("lt4 world: %zu entities (40 of them monsters)\n", world_->size());
}

TEST_F(WorldQueries, EqualTheClosestPerEntityAnswer) { checkAgainstBruteForce(1, 400); }

TEST_F(WorldQueries, EqualTheClosestAfterEntitiesMove) {
  // Move every monster, remove some, add others; the broad phase follows.
  std::mt19937 rng(7);
  const Bounds b = world_->entity(kWorldspawnEntity)->bounds;
  std::vector<EntityId> monsters;
  for (const EntityId id : world_->entityIds())
    if (world_->entity(id)->name.rfind("monster", 0) == 0) monsters.push_back(id);
  for (const EntityId id : monsters) ASSERT_TRUE(world_->setPlacement(id, randomPlacement(rng, b)).ok());
  checkAgainstBruteForce(2, 150);
  for (std::size_t k = 0; k < monsters.size(); k += 3) ASSERT_TRUE(world_->removeEntity(monsters[k]).ok());
  auto trm = TraceModel::octahedron({{-24, -24, -24}, {24, 24, 24}});
  ASSERT_TRUE(trm.ok());
  for (int i = 0; i < 10; ++i)
    ASSERT_TRUE(world_->addTraceModelEntity("extra" + std::to_string(i), *trm, randomPlacement(rng, b)).ok());
  checkAgainstBruteForce(3, 150);
}

TEST_F(WorldQueries, FiltersLeaveEntitiesOut) {
  std::mt19937 rng(11);
  WorldQueryWork work;
  std::vector<EntityId> ignore;
  for (const EntityId id : world_->entityIds())
    if (id % 2) ignore.push_back(id);
  EntityFilter f;
  f.ignore = ignore;
  f.accept = [](const WorldEntity& e) { return e.className != "func_static" || e.id % 3 != 0; };
  auto box = TraceModel::box({{-16, -16, 0}, {16, 16, 72}});
  ASSERT_TRUE(box.ok());
  int filteredHits = 0;
  for (int i = 0; i < 150; ++i) {
    TranslationQuery tq;
    tq.trm = &*box;
    tq.start = startNear(rng);
    tq.end = tq.start + offset(rng, 256);
    const WorldTraceResult r = world_->translate(tq, work, f);
    ASSERT_EQ(bits(r), bits(closestTrace(*world_, tq, f,
                                         [](auto& m, auto& q, auto& w) { return translate(m, q, w); })))
        << i;
    ASSERT_TRUE(r.entity == kNoEntity || keeps(*world_->entity(r.entity), tq.contentMask, f));
    filteredHits += bits(r) != bits(world_->translate(tq, work));
  }
  EXPECT_GT(filteredHits, 0);
}

TEST_F(WorldQueries, BatchesAreTheSingleAnswersOnAnyThreadCount) {
  std::mt19937 rng(5);
  auto box = TraceModel::box({{-16, -16, 0}, {16, 16, 72}});
  ASSERT_TRUE(box.ok());
  const std::size_t n = 600;
  std::vector<Vec3> starts(n), ends(n);
  for (std::size_t i = 0; i < n; ++i) {
    starts[i] = startNear(rng);
    ends[i] = starts[i] + offset(rng, 256);
  }
  TranslationBatch batch;
  batch.query.trm = &*box;
  batch.starts = starts;
  batch.ends = ends;
  std::vector<WorldTraceResult> one(n), three(n);
  ASSERT_TRUE(translateBatch(*world_, batch, one, {1, 0, {}}).ok());
  ASSERT_TRUE(translateBatch(*world_, batch, three, {3, 7, {}}).ok());
  WorldQueryWork work;
  for (std::size_t i = 0; i < n; ++i) {
    TranslationQuery q = batch.query;
    q.start = starts[i];
    q.end = ends[i];
    ASSERT_EQ(bits(one[i]), bits(world_->translate(q, work))) << i;
    ASSERT_EQ(bits(one[i]), bits(three[i])) << i;
  }
  std::vector<WorldRayHit> rays1(n), rays3(n);
  RayBatch rb;
  rb.starts = starts;
  rb.ends = ends;
  ASSERT_TRUE(castRayBatch(*world_, rb, rays1, {1, 0, {}}).ok());
  ASSERT_TRUE(castRayBatch(*world_, rb, rays3, {3, 5, {}}).ok());
  for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(bits(rays1[i]), bits(rays3[i])) << i;
  std::vector<WorldTraceResult> wrong(n - 1);
  EXPECT_FALSE(translateBatch(*world_, batch, wrong).ok());
}

TEST_F(WorldQueries, ConcurrentReadersAgreeWithOneThread) {
  // Readers on four threads at once (TSan: no race), between the writer's
  // moves; each reader's answers equal one thread's.
  std::mt19937 rng(9);
  auto cyl = TraceModel::cylinder({{-16, -16, 0}, {16, 16, 64}}, 8);
  ASSERT_TRUE(cyl.ok());
  const int n = 200;
  std::vector<TranslationQuery> queries(n);
  for (TranslationQuery& q : queries) {
    q.trm = &*cyl;
    q.start = startNear(rng);
    q.end = q.start + offset(rng, 200);
  }
  const Bounds b = world_->entity(kWorldspawnEntity)->bounds;
  for (int round = 0; round < 2; ++round) {
    std::vector<std::string> expected(n);
    WorldQueryWork work;
    for (int i = 0; i < n; ++i)
      expected[std::size_t(i)] = bits(world_->translate(queries[std::size_t(i)], work));
    std::vector<int> mismatches(4, 0);
    std::vector<std::thread> readers;
    for (int t = 0; t < 4; ++t)
      readers.emplace_back([&, t] {
        WorldQueryWork mine;
        for (int i = n - 1; i >= 0; --i)
          mismatches[std::size_t(t)] +=
              bits(world_->translate(queries[std::size_t(i)], mine)) != expected[std::size_t(i)];
      });
    for (std::thread& r : readers) r.join();
    for (int t = 0; t < 4; ++t) EXPECT_EQ(mismatches[std::size_t(t)], 0) << "reader " << t;
    // The one writer, between rounds.
    for (const EntityId id : world_->entityIds()) {
      if (world_->entity(id)->name.rfind("monster", 0) == 0) {
        ASSERT_TRUE(world_->setPlacement(id, randomPlacement(rng, b)).ok());
      }
    }
  }
}
