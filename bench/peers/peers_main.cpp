// cmkit_peers: the speed test's translations run through cmkit and through
// Bullet (btCollisionWorld::convexSweepTest with a box against a
// btBvhTriangleMeshShape of the world model's polygons; rayTest for points)
// in the same run: ns/query, the ratio cmkit/peer, and the hit agreement.
//
//   cmkit_peers [MAP] [--times N]
//
// Semantic differences (docs/performance.md): cmkit stops 0.25 units in front
// of a surface and collides only with the front faces of polygons; Bullet's
// triangles are two-sided and its convex sweeps allow no margin here (0).
#include <btBulletCollisionCommon.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "cmkit/build.h"
#include "cmkit/map.h"
#include "cmkit/query.h"
#include "cmkit/speed_test.h"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

/// Queries per kind by default (as the speed test).
constexpr int kDefaultTimes = 1000;
/// The speed test's box (cm_testBox) and move length (cm_testLength).
constexpr cmkit::Real kBoxHalfX = 16, kBoxHalfY = 16, kBoxHalfZ = 32, kBoxCentreZ = 32;
constexpr cmkit::Real kLength = 1024;
constexpr std::uint32_t kMask = cmkit::contents::kSolid | cmkit::contents::kPlayerClip;

btVector3 bt(const cmkit::Vec3& v) { return {v.x, v.y, v.z}; }

/// One kind's comparison.
struct Comparison {
  const char* kind = "";
  double cmkitNs = 0;
  double peerNs = 0;
  int bothHit = 0;
  int bothMiss = 0;
  int differ = 0;
};

void print(const Comparison& c, int n) {
  std::printf(
      "%-18s cmkit %9.0f ns/query   bullet %9.0f ns/query   cmkit/bullet %5.2f   both hit %4d  both miss %4d "
      " "
      "differ %4d (of %d)\n",
      c.kind, c.cmkitNs, c.peerNs, c.peerNs > 0 ? c.cmkitNs / c.peerNs : 0.0, c.bothHit, c.bothMiss, c.differ,
      n);
}

std::string defaultMap() {
  const fs::path source(CMKIT_SOURCE_DIR);
  for (const fs::path& p :
       {source / ".." / "shared" / "maps" / "lt4" / "lt4.map", source / "data" / "maps" / "lt4" / "lt4.map"})
    if (fs::exists(p)) return p.lexically_normal().string();
  return {};
}

}  // namespace

int main(int argc, char** argv) {
  std::string mapPath;
  int times = kDefaultTimes;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--times" && i + 1 < argc) {
      times = std::max(1, std::atoi(argv[++i]));
    } else if (arg == "-h" || arg == "--help") {
      std::printf("usage: cmkit_peers [MAP] [--times N]\n");
      return 0;
    } else {
      mapPath = arg;
    }
  }
  if (mapPath.empty()) mapPath = defaultMap();
  if (mapPath.empty()) {
    std::fprintf(stderr, "cmkit_peers: no map given and lt4.map not found\n");
    return 2;
  }
  auto map = cmkit::loadMapFile(mapPath);
  if (!map) {
    std::fprintf(stderr, "cmkit_peers: %s\n", map.error().toString().c_str());
    return 2;
  }
  auto models = cmkit::buildCollisionModels(*map, cmkit::MaterialTable{});
  if (!models || models->empty()) {
    std::fprintf(stderr, "cmkit_peers: %s: no models\n", mapPath.c_str());
    return 2;
  }
  const cmkit::CollisionModel& world = *models->front();

  // The same geometry for Bullet: every polygon matching the mask, as a fan.
  auto mesh = std::make_unique<btTriangleMesh>();
  int triangles = 0;
  for (const cmkit::CmPolygon& p : world.polygons) {
    if ((p.contents & kMask) == 0) continue;
    const auto edges = world.edgesOf(p);
    std::vector<cmkit::Vec3> v;
    for (std::int32_t e : edges) v.push_back(world.vertices[std::size_t(world.edgeStart(e))]);
    for (std::size_t k = 1; k + 1 < v.size(); ++k, ++triangles)
      mesh->addTriangle(bt(v[0]), bt(v[k]), bt(v[k + 1]));
  }
  auto shape = std::make_unique<btBvhTriangleMeshShape>(mesh.get(), true);
  shape->setMargin(0);
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher(&config);
  btDbvtBroadphase broadphase;
  btCollisionWorld bulletWorld(&dispatcher, &broadphase, &config);
  btCollisionObject object;
  object.setCollisionShape(shape.get());
  bulletWorld.addCollisionObject(&object);
  bulletWorld.updateAabbs();
  btBoxShape box(btVector3(kBoxHalfX, kBoxHalfY, kBoxHalfZ));
  box.setMargin(0);

  // The speed test's translations: from the centre of the world, seed 0.
  const cmkit::Vec3 origin = (world.bounds.min + world.bounds.max) * cmkit::Real(0.5);
  cmkit::SpeedTestRandom random(0);
  std::vector<cmkit::Vec3> ends;
  for (int i = 0; i < times; ++i) {
    cmkit::Vec3 e;
    for (int k = 0; k < 3; ++k) e[k] = origin[k] + random.signedUniform() * kLength;
    ends.push_back(e);
  }
  auto boxTrm = cmkit::TraceModel::parse("box:-16,-16,0,16,16,64");
  if (!boxTrm) return 2;
  std::printf(
      "%s: world model %zu polygons -> %d triangles; %d translations from (%g %g %g), mask "
      "solid|playerclip\n",
      mapPath.c_str(), world.polygons.size(), triangles, times, origin.x, origin.y, origin.z);

  cmkit::QueryWork work;
  for (int pass = 0; pass < 2; ++pass) {  // pass 0 warms up caches; pass 1 is printed
    Comparison boxCmp{"translation (box)"};
    Comparison pointCmp{"translation (point)"};
    std::vector<bool> cmkitBox(ends.size()), cmkitPoint(ends.size());
    auto t0 = Clock::now();
    for (std::size_t i = 0; i < ends.size(); ++i) {
      cmkit::TranslationQuery q;
      q.trm = &*boxTrm;
      q.start = origin;
      q.end = ends[i];
      q.contentMask = kMask;
      cmkitBox[i] = cmkit::translate(world, q, work).fraction < 1;
    }
    auto t1 = Clock::now();
    boxCmp.cmkitNs = std::chrono::duration<double, std::nano>(t1 - t0).count() / double(ends.size());
    std::vector<bool> peerBox(ends.size());
    const btVector3 centre(0, 0, kBoxCentreZ);
    t0 = Clock::now();
    for (std::size_t i = 0; i < ends.size(); ++i) {
      const btTransform from(btMatrix3x3::getIdentity(), bt(origin) + centre);
      const btTransform to(btMatrix3x3::getIdentity(), bt(ends[i]) + centre);
      btCollisionWorld::ClosestConvexResultCallback cb(from.getOrigin(), to.getOrigin());
      bulletWorld.convexSweepTest(&box, from, to, cb, 0);
      peerBox[i] = cb.hasHit();
    }
    t1 = Clock::now();
    boxCmp.peerNs = std::chrono::duration<double, std::nano>(t1 - t0).count() / double(ends.size());

    t0 = Clock::now();
    for (std::size_t i = 0; i < ends.size(); ++i) {
      cmkit::TranslationQuery q;
      q.start = origin;
      q.end = ends[i];
      q.contentMask = kMask;
      cmkitPoint[i] = cmkit::translate(world, q, work).fraction < 1;
    }
    t1 = Clock::now();
    pointCmp.cmkitNs = std::chrono::duration<double, std::nano>(t1 - t0).count() / double(ends.size());
    std::vector<bool> peerPoint(ends.size());
    t0 = Clock::now();
    for (std::size_t i = 0; i < ends.size(); ++i) {
      btCollisionWorld::ClosestRayResultCallback cb(bt(origin), bt(ends[i]));
      bulletWorld.rayTest(bt(origin), bt(ends[i]), cb);
      peerPoint[i] = cb.hasHit();
    }
    t1 = Clock::now();
    pointCmp.peerNs = std::chrono::duration<double, std::nano>(t1 - t0).count() / double(ends.size());
    if (pass == 0) continue;
    for (std::size_t i = 0; i < ends.size(); ++i) {
      (cmkitBox[i] && peerBox[i])     ? ++boxCmp.bothHit
      : (!cmkitBox[i] && !peerBox[i]) ? ++boxCmp.bothMiss
                                      : ++boxCmp.differ;
      (cmkitPoint[i] && peerPoint[i])     ? ++pointCmp.bothHit
      : (!cmkitPoint[i] && !peerPoint[i]) ? ++pointCmp.bothMiss
                                          : ++pointCmp.differ;
    }
    print(boxCmp, times);
    print(pointCmp, times);
  }
  std::printf("Embree: not compared (see docs/performance.md)\n");
  bulletWorld.removeCollisionObject(&object);
  return 0;
}
