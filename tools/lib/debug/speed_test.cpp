// The speed test: see include/cmkit/speed_test.h.
#include "debug/speed_test.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <thread>

#include "cmkit/ray_index.h"

namespace cmkit {

namespace {

/// The original idRandom's multiplier and increment (Numerical Recipes LCG).
constexpr std::uint32_t kLcgMultiplier = 69069u;
constexpr std::uint32_t kLcgIncrement = 1u;
/// The generator's output keeps the top 24 bits (the low bits of an LCG
/// have short periods); 2^24 scales them to [0, 1).
constexpr int kRandomShift = 8;
constexpr double kRandomScale = 1.0 / 16777216.0;
/// Rotation axes shorter than this (before normalising) are replaced by +z.
constexpr Real kMinAxisLength = 1e-3f;
/// FNV-1a 64-bit prime.
constexpr std::uint64_t kFnvPrime = 1099511628211ull;

using Clock = std::chrono::steady_clock;

/// What one query needs from its chain: the pose it starts from.
struct Pose {
  Vec3 position;
  Mat3 axis;
};

/// Runs `count` queries in chunks over `threads` threads; `query(i, pose,
/// work)` runs query i from `pose`. Walk mode chains the poses of a chunk.
template <class Query>
SpeedTestBatch runBatch(const char* kind, int count, const SpeedTestOptions& options, Query query) {
  SpeedTestBatch batch;
  batch.kind = kind;
  batch.count = count;
  batch.hash = kFnvOffsetBasis;
  if (count <= 0) return batch;
  std::vector<TraceResult> results(static_cast<std::size_t>(count));
  std::vector<double> micros(static_cast<std::size_t>(count));
  const int chunks = (count + kSpeedTestChunk - 1) / kSpeedTestChunk;
  std::atomic<int> nextChunk{0};
  auto worker = [&] {
    QueryWork work;
    // One untimed query first: the scratch memory grows to the model's size.
    Pose warm{options.origin, options.trmAxis};
    query(0, warm, work);
    for (int c = nextChunk.fetch_add(1); c < chunks; c = nextChunk.fetch_add(1)) {
      Pose pose{options.origin, options.trmAxis};
      const int last = std::min(count, (c + 1) * kSpeedTestChunk);
      for (int i = c * kSpeedTestChunk; i < last; ++i) {
        const auto t0 = Clock::now();
        TraceResult r = query(i, pose, work);
        const auto t1 = Clock::now();
        micros[std::size_t(i)] = std::chrono::duration<double, std::micro>(t1 - t0).count();
        if (options.walk) pose = {r.endPos, r.endAxis};
        results[std::size_t(i)] = r;
      }
    }
  };
  const int threads = std::clamp(options.threads, 1, chunks);
  const auto start = Clock::now();
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (auto& th : pool) th.join();
  batch.wallMs = std::chrono::duration<double, std::milli>(Clock::now() - start).count();

  batch.minUs = micros[0];
  batch.maxUs = micros[0];
  double sum = 0;
  for (std::size_t i = 0; i < results.size(); ++i) {
    sum += micros[i];
    batch.minUs = std::min(batch.minUs, micros[i]);
    batch.maxUs = std::max(batch.maxUs, micros[i]);
    const TraceResult& r = results[i];
    batch.hits += r.fraction < 1;
    auto mix = [&batch](Real v) { batch.hash = fnv1a(batch.hash, &v, sizeof v); };
    mix(r.fraction);
    for (int k = 0; k < 3; ++k) mix(r.endPos[k]);
    for (int row = 0; row < 3; ++row)
      for (int k = 0; k < 3; ++k) mix(r.endAxis[row][k]);
    for (int k = 0; k < 3; ++k) mix(r.contact.normal[k]);
  }
  batch.sumMs = sum / 1000.0;
  batch.avgUs = sum / double(count);
  batch.queriesPerSecond = batch.wallMs > 0 ? double(count) * 1000.0 / batch.wallMs : 0;
  return batch;
}

}  // namespace

Real SpeedTestRandom::uniform() {
  state_ = kLcgMultiplier * state_ + kLcgIncrement;
  return Real(double(state_ >> kRandomShift) * kRandomScale);
}

std::uint64_t fnv1a(std::uint64_t hash, const void* data, std::size_t size) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) {
    hash ^= bytes[i];
    hash *= kFnvPrime;
  }
  return hash;
}

namespace detail {

SpeedTestPlan planSpeedTest(const SpeedTestOptions& options) {
  SpeedTestPlan plan;
  SpeedTestRandom random(options.seed);
  const std::size_t n = std::size_t(std::max(0, options.times));
  auto randomMove = [&] {
    Vec3 v;
    for (int k = 0; k < 3; ++k) v[k] = random.signedUniform() * options.length;
    return v;
  };
  auto randomTurn = [&] {
    // As the original: axis (CRandom, CRandom, Random), normalised.
    Vec3 axis{random.signedUniform(), random.signedUniform(), random.uniform()};
    if (axis.length() < kMinAxisLength) axis = {0, 0, 1};
    axis.normalize();
    SpeedTestTurn turn;
    turn.axis = axis;
    for (int k = 0; k < 3; ++k) turn.originOffset[k] = random.signedUniform() * options.radius;
    return turn;
  };
  if (options.randomMany) {
    plan.moves.assign(n, randomMove());
    plan.turns.assign(n, randomTurn());
  } else {
    plan.moves.reserve(n);
    for (std::size_t i = 0; i < n; ++i) plan.moves.push_back(randomMove());
    plan.turns.reserve(n);
    for (std::size_t i = 0; i < n; ++i) plan.turns.push_back(randomTurn());
  }
  return plan;
}

}  // namespace detail

SpeedTestReport runSpeedTest(const CollisionModel& model, const TraceModel& trm,
                             const SpeedTestOptions& options) {
  const detail::SpeedTestPlan plan = detail::planSpeedTest(options);
  SpeedTestReport report;
  report.threads = std::max(1, options.threads);
  const int n = int(plan.moves.size());
  report.translation = runBatch("translation", n, options, [&](int i, const Pose& pose, QueryWork& work) {
    TranslationQuery q;
    q.trm = &trm;
    q.trmAxis = pose.axis;
    q.start = pose.position;
    q.end = pose.position + plan.moves[std::size_t(i)];
    q.contentMask = options.contentMask;
    q.placement = options.placement;
    return translate(model, q, work);
  });
  if (options.rotations) {
    report.rotation = runBatch("rotation", n, options, [&](int i, const Pose& pose, QueryWork& work) {
      const detail::SpeedTestTurn& turn = plan.turns[std::size_t(i)];
      RotationQuery q;
      q.trm = &trm;
      q.trmAxis = pose.axis;
      q.start = pose.position;
      q.rotation = Rotation(pose.position + turn.originOffset, turn.axis, options.angle);
      q.contentMask = options.contentMask;
      q.placement = options.placement;
      return rotate(model, q, work);
    });
  } else {
    report.rotation.kind = "rotation";
    report.rotation.hash = kFnvOffsetBasis;
  }
  report.rays.kind = "ray cast";
  report.rays.hash = kFnvOffsetBasis;
  if (options.rays) {
    const auto t0 = Clock::now();
    const RayIndex index(model);
    report.rayIndex = {index.numNodes(), index.numPolygons(), index.memoryBytes(),
                       std::chrono::duration<double, std::milli>(Clock::now() - t0).count(),
                       index.usesAvx2()};
    report.rays = runBatch("ray cast", n, options, [&](int i, const Pose& pose, QueryWork&) {
      const Vec3 end = pose.position + plan.moves[std::size_t(i)];
      const RayHit hit = index.cast({pose.position, end, options.contentMask, options.placement});
      TraceResult r;
      r.fraction = hit.fraction;
      r.endPos = hit.hit() ? hit.point : end;
      r.endAxis = pose.axis;
      r.contact.normal = hit.normal;
      return r;
    });
  }
  return report;
}

}  // namespace cmkit
