// cmkit_peers --speed-test: the speed test's translations run through cmkit and through
// Bullet (btCollisionWorld::convexSweepTest with a box against a
// btBvhTriangleMeshShape of the world model's polygons; rayTest for points)
// and, when built with Embree (Debian libembree-dev), the points through
// rtcIntersect1 against the same triangles, in the same run: ns/query, the
// ratio cmkit/peer, and the hit agreement. The points run twice in cmkit:
// as point translations (the original's point trace) and as RayIndex casts
// (the first surface crossing, what the peers compute). Each timing is the fastest of
// --passes runs over all the queries (robust against a busy machine).
//
//   cmkit_peers --speed-test [MAP] [--times N] [--passes N]
//
// Semantic differences (docs/performance.md): cmkit stops 0.25 units in front
// of a surface and collides only with the front faces of polygons; Bullet's
// triangles are two-sided and its convex sweeps allow no margin here (0).
#include <btBulletCollisionCommon.h>
#ifdef CMKIT_HAVE_EMBREE
#include <embree3/rtcore.h>
#endif

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "cmkit/batch.h"
#include "cmkit/compile.h"
#include "cmkit/map.h"
#include "cmkit/query.h"
#include "cmkit/ray_index.h"
#include "cmkit/tools/speed_test.h"
#include "peers.h"

namespace {

using Clock = std::chrono::steady_clock;

/// The speed test's box (cm_testBox) and move length (cm_testLength).
constexpr cmkit::Real kBoxHalfX = 16, kBoxHalfY = 16, kBoxHalfZ = 32, kBoxCentreZ = 32;
constexpr cmkit::Real kLength = 1024;
constexpr std::uint32_t kMask = cmkit::contents::kSolid | cmkit::contents::kPlayerClip;

btVector3 bt(const cmkit::Vec3& v) { return {v.x, v.y, v.z}; }

/// One kind's comparison.
struct Comparison {
  const char* kind = "";
  const char* peer = "";
  double cmkitNs = 0;
  double peerNs = 0;
  int bothHit = 0;
  int bothMiss = 0;
  int differ = 0;
};

void print(const Comparison& c, int n) {
  std::printf(
      "%-19s cmkit %7.0f ns/query   %-6s %7.0f ns/query   cmkit/%-6s %5.2f   both hit %4d  both miss %4d"
      "  differ %4d (of %d)\n",
      c.kind, c.cmkitNs, c.peer, c.peerNs, c.peer, c.peerNs > 0 ? c.cmkitNs / c.peerNs : 0.0, c.bothHit,
      c.bothMiss, c.differ, n);
}

/// Runs query(i) for every i, `passes` times; returns the fastest pass in ns/query.
double fastestPass(std::size_t n, int passes, const std::function<void(std::size_t)>& query) {
  double best = 0;
  for (int pass = 0; pass < passes; ++pass) {
    const auto t0 = Clock::now();
    for (std::size_t i = 0; i < n; ++i) query(i);
    const double ns = std::chrono::duration<double, std::nano>(Clock::now() - t0).count() / double(n);
    best = pass == 0 ? ns : std::min(best, ns);
  }
  return best;
}

/// Counts agreement of two hit lists into c.
void agreement(Comparison& c, const std::vector<char>& a, const std::vector<char>& b) {
  for (std::size_t i = 0; i < a.size(); ++i)
    (a[i] && b[i]) ? ++c.bothHit : (!a[i] && !b[i]) ? ++c.bothMiss : ++c.differ;
}

#ifdef CMKIT_HAVE_EMBREE
/// One rtcIntersect1 from `from` to `to` (t in [0, 1] spans the move): whether it hits.
bool embreeHits(RTCScene scene, RTCIntersectContext& context, const cmkit::Vec3& from,
                const cmkit::Vec3& to) {
  RTCRayHit rh{};
  rh.ray.org_x = from.x;
  rh.ray.org_y = from.y;
  rh.ray.org_z = from.z;
  rh.ray.dir_x = to.x - from.x;
  rh.ray.dir_y = to.y - from.y;
  rh.ray.dir_z = to.z - from.z;
  rh.ray.tnear = 0;
  rh.ray.tfar = 1;
  rh.ray.mask = ~0u;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene, &context, &rh);
  return rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
}
#endif

/// The speed test's translations: `count` end points within +-kLength per
/// axis of `origin`, seed 0.
std::vector<cmkit::Vec3> speedTestMoves(const cmkit::Vec3& origin, std::size_t count) {
  cmkit::SpeedTestRandom random(0);
  std::vector<cmkit::Vec3> ends(count);
  for (cmkit::Vec3& e : ends)
    for (int k = 0; k < 3; ++k) e[k] = origin[k] + random.signedUniform() * kLength;
  return ends;
}

/// The fastest of `passes` runs of run(), in ns per query of a batch of n.
double fastestBatch(std::size_t n, int passes, const std::function<void()>& run) {
  double best = 0;
  for (int pass = 0; pass < passes; ++pass) {
    const auto t0 = Clock::now();
    run();
    const double ns = std::chrono::duration<double, std::nano>(Clock::now() - t0).count() / double(n);
    best = pass == 0 ? ns : std::min(best, ns);
  }
  return best;
}

/// Batches (cmkit/batch.h) of kBatchSize box translations and kRayBatchSize
/// ray casts (each batch some tens of milliseconds, so that starting the
/// second thread is noise), on 1 and 2 threads, and the same rays through
/// `peerRays` (one peer ray per call, one thread) when given. Prints ns per
/// query and the speed-ups. The moves are the speed test's, continued with
/// the same generator to the batch size: all different (a ray batch sorts
/// its rays, and repeated rays would fall next to each other).
constexpr std::size_t kBatchSize = 20000;
constexpr std::size_t kRayBatchSize = 200000;
void batchThroughput(const cmkit::CollisionModel& world, const cmkit::RayIndex& rays,
                     const cmkit::TraceModel& box, const cmkit::Vec3& origin, int passes,
                     const std::function<void(const cmkit::Vec3&, const cmkit::Vec3&)>& peerRays,
                     const char* peerName) {
  const std::vector<cmkit::Vec3> ends = speedTestMoves(origin, kRayBatchSize);
  const std::span<const cmkit::Vec3> boxEnds(ends.data(), kBatchSize);
  const cmkit::Vec3 starts[] = {origin};
  std::vector<cmkit::TraceResult> traces(kBatchSize);
  std::vector<cmkit::RayHit> hits(kRayBatchSize);
  double boxNs[3] = {}, rayNs[3] = {};
  for (int threads = 1; threads <= 2; ++threads) {
    cmkit::BatchOptions options;
    options.threads = threads;
    cmkit::TranslationQuery shared;
    shared.trm = &box;
    shared.contentMask = kMask;
    const cmkit::TranslationBatch tb{shared, starts, boxEnds};
    boxNs[threads] =
        fastestBatch(kBatchSize, passes, [&] { (void)cmkit::translateBatch(world, tb, traces, options); });
    const cmkit::RayBatch rb{{{}, {}, kMask, {}}, starts, ends};
    rayNs[threads] =
        fastestBatch(kRayBatchSize, passes, [&] { (void)cmkit::castRayBatch(rays, rb, hits, options); });
  }
  std::printf(
      "\nbatches of %zu box translations and %zu rays (the speed test's moves continued, all different; "
      "cmkit/batch.h):\n",
      kBatchSize, kRayBatchSize);
  std::printf(
      "translation (box)   batch 1 thread %7.0f ns/query   2 threads %7.0f ns/query   speed-up %.2fx\n",
      boxNs[1], boxNs[2], boxNs[1] / boxNs[2]);
  std::printf(
      "ray cast (point)    batch 1 thread %7.0f ns/query   2 threads %7.0f ns/query   speed-up %.2fx\n",
      rayNs[1], rayNs[2], rayNs[1] / rayNs[2]);
  if (peerRays) {
    const double peerNs = fastestBatch(kRayBatchSize, passes, [&] {
      for (const cmkit::Vec3& e : ends) peerRays(origin, e);
    });
    std::printf(
        "ray cast (point)    %s loop, 1 thread %7.0f ns/query:  %s / cmkit batch  %.2fx (1 thread)  %.2fx (2 "
        "threads)\n",
        peerName, peerNs, peerName, peerNs / rayNs[1], peerNs / rayNs[2]);
  }
}

}  // namespace

int peers::runSpeedTestSection(const std::string& mapPath, int times, int passes) {
  auto map = cmkit::loadMapFile(mapPath);
  if (!map) {
    std::fprintf(stderr, "cmkit_peers: %s\n", map.error().toString().c_str());
    return 2;
  }
  auto models = cmkit::buildCollisionModels(*map, cmkit::MaterialTable{});
  if (!models || models->models.empty()) {
    std::fprintf(stderr, "cmkit_peers: %s: no models\n", mapPath.c_str());
    return 2;
  }
  const cmkit::CollisionModel& world = *models->models.front();

  // The same geometry for the peers: every polygon matching the mask, as a
  // fan of triangles over the model's vertices.
  std::vector<std::uint32_t> indices;
  for (const cmkit::CmPolygon& p : world.polygons()) {
    if ((p.contents & kMask) == 0) continue;
    std::vector<std::uint32_t> v;
    for (std::int32_t e : world.edgesOf(p)) v.push_back(std::uint32_t(world.edgeStart(e)));
    for (std::size_t k = 1; k + 1 < v.size(); ++k) indices.insert(indices.end(), {v[0], v[k], v[k + 1]});
  }
  const int triangles = int(indices.size() / 3);
  auto mesh = std::make_unique<btTriangleMesh>();
  for (std::size_t t = 0; t < indices.size(); t += 3)
    mesh->addTriangle(bt(world.vertices()[indices[t]]), bt(world.vertices()[indices[t + 1]]),
                      bt(world.vertices()[indices[t + 2]]));
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

#ifdef CMKIT_HAVE_EMBREE
  RTCDevice device = rtcNewDevice(nullptr);
  RTCScene scene = rtcNewScene(device);
  {
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), world.vertices().size()));
    for (std::size_t i = 0; i < world.vertices().size(); ++i)
      for (int k = 0; k < 3; ++k) vertices[3 * i + std::size_t(k)] = world.vertices()[i][k];
    auto* tris = static_cast<std::uint32_t*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                3 * sizeof(std::uint32_t), std::size_t(triangles)));
    std::copy(indices.begin(), indices.end(), tris);
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(scene);
  }
#endif

  // The speed test's translations: from the centre of the world, seed 0.
  const cmkit::Vec3 origin = (world.bounds().min + world.bounds().max) * cmkit::Real(0.5);
  const std::vector<cmkit::Vec3> ends = speedTestMoves(origin, std::size_t(times));
  auto boxTrm = cmkit::TraceModel::parse("box:-16,-16,0,16,16,64");
  if (!boxTrm) return 2;
  const cmkit::RayIndex rayIndex(world);  // for the ray casts
  std::printf(
      "%s: world model %zu polygons -> %d triangles; %d translations from (%g %g %g), mask "
      "solid|playerclip; ray casts with the %s node test\n",
      mapPath.c_str(), world.polygons().size(), triangles, times, origin.x, origin.y, origin.z,
      rayIndex.usesAvx2() ? "AVX2" : "baseline (SSE2)");

  cmkit::QueryWork work;
  const std::size_t n = ends.size();
  std::vector<char> cmkitBox(n), cmkitPoint(n), peerBox(n), peerPoint(n);
  Comparison boxCmp{"translation (box)", "bullet"};
  boxCmp.cmkitNs = fastestPass(n, passes, [&](std::size_t i) {
    cmkit::TranslationQuery q;
    q.trm = &*boxTrm;
    q.start = origin;
    q.end = ends[i];
    q.contentMask = kMask;
    cmkitBox[i] = cmkit::translate(world, q, work).fraction < 1;
  });
  const btVector3 centre(0, 0, kBoxCentreZ);
  boxCmp.peerNs = fastestPass(n, passes, [&](std::size_t i) {
    const btTransform from(btMatrix3x3::getIdentity(), bt(origin) + centre);
    const btTransform to(btMatrix3x3::getIdentity(), bt(ends[i]) + centre);
    btCollisionWorld::ClosestConvexResultCallback cb(from.getOrigin(), to.getOrigin());
    bulletWorld.convexSweepTest(&box, from, to, cb, 0);
    peerBox[i] = cb.hasHit();
  });
  agreement(boxCmp, cmkitBox, peerBox);
  print(boxCmp, times);

  Comparison pointCmp{"translation (point)", "bullet"};
  pointCmp.cmkitNs = fastestPass(n, passes, [&](std::size_t i) {
    cmkit::TranslationQuery q;
    q.start = origin;
    q.end = ends[i];
    q.contentMask = kMask;
    cmkitPoint[i] = cmkit::translate(world, q, work).fraction < 1;
  });
  pointCmp.peerNs = fastestPass(n, passes, [&](std::size_t i) {
    btCollisionWorld::ClosestRayResultCallback cb(bt(origin), bt(ends[i]));
    bulletWorld.rayTest(bt(origin), bt(ends[i]), cb);
    peerPoint[i] = cb.hasHit();
  });
  agreement(pointCmp, cmkitPoint, peerPoint);
  print(pointCmp, times);

  // The same rays through the RayIndex of the world model.
  std::vector<char> cmkitRay(n);
  Comparison rayCmp{"ray cast (point)", "bullet"};
  rayCmp.cmkitNs = fastestPass(n, passes, [&](std::size_t i) {
    cmkitRay[i] = rayIndex.cast({origin, ends[i], kMask}).hit();
  });
  rayCmp.peerNs = pointCmp.peerNs;
  agreement(rayCmp, cmkitRay, peerPoint);
  print(rayCmp, times);

#ifdef CMKIT_HAVE_EMBREE
  Comparison embreeCmp{"translation (point)", "embree"};
  embreeCmp.cmkitNs = pointCmp.cmkitNs;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  embreeCmp.peerNs = fastestPass(
      n, passes, [&](std::size_t i) { peerPoint[i] = embreeHits(scene, context, origin, ends[i]); });
  agreement(embreeCmp, cmkitPoint, peerPoint);
  print(embreeCmp, times);
  Comparison embreeRayCmp{"ray cast (point)", "embree"};
  embreeRayCmp.cmkitNs = rayCmp.cmkitNs;
  embreeRayCmp.peerNs = embreeCmp.peerNs;
  agreement(embreeRayCmp, cmkitRay, peerPoint);
  print(embreeRayCmp, times);
  batchThroughput(
      world, rayIndex, *boxTrm, origin, passes,
      [&](const cmkit::Vec3& from, const cmkit::Vec3& to) { (void)embreeHits(scene, context, from, to); },
      "embree");
  rtcReleaseScene(scene);
  rtcReleaseDevice(device);
#else
  std::printf("Embree: not compared (cmkit_peers was built without libembree-dev)\n");
  batchThroughput(world, rayIndex, *boxTrm, origin, passes, {}, "");
#endif
  bulletWorld.removeCollisionObject(&object);
  return 0;
}
