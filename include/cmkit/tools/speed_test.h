// speed_test.h: the original's collision speed test (cm_testCollision),
// reproduced as a library function: a batch of seeded random translations
// of a trace model from an origin, then a batch of random rotations about
// axes through points near the origin, every query timed.
//
// CONTRACT
// - The queries are a pure function of the options (seeded generator, no
//   global state), so two runs with the same options run the same queries.
// - The queries are cut into fixed chunks of kSpeedTestChunk; threads take
//   whole chunks. Results (and so the hash, hit counts) are the same at any
//   thread count; only the timings change.
// - --walk chains the moves of a chunk: each move starts where the previous
//   one ended (position and orientation); every chunk starts at the origin.
// - `rays` (not in the original) also casts the translations' moves as rays
//   through a RayIndex of the model (built once, untimed): the first surface
//   each segment crosses. In walk mode a ray's next start is its hit point.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "cmkit/contents.h"
#include "cmkit/math.h"
#include "cmkit/model.h"
#include "cmkit/query.h"
#include "cmkit/trace_model.h"

namespace cmkit {

/// Queries per unit of work (and per walk chain).
inline constexpr int kSpeedTestChunk = 50;

/// The original's cm_test* cvars.
struct SpeedTestOptions {
  int times = 1000;         ///< cm_testTimes: queries per kind
  Real length = 1024;       ///< cm_testLength: end points within +-length per axis of the start
  Real angle = 60;          ///< cm_testAngle: degrees per rotation
  Real radius = 64;         ///< cm_testRadius: rotation origins within +-radius per axis of the start
  bool randomMany = false;  ///< cm_testRandomMany: one shared end point (and rotation) for all
  bool walk = false;        ///< cm_testWalk: chained moves (see the contract)
  bool rotations = true;    ///< cm_testRotation: also run the rotation batch
  bool rays = false;        ///< cmkit: also cast the moves as RayIndex rays
  std::uint32_t seed = 0;   ///< seed of the generator (the original: always 0)
  int threads = 1;          ///< worker threads, each with its own QueryWork
  /// Content flags the queries collide with (the original: solid | playerclip).
  std::uint32_t contentMask = contents::kSolid | contents::kPlayerClip;
  Vec3 origin;          ///< start of every move (the original: cm_testOrigin)
  Mat3 trmAxis;         ///< orientation of the trace model at the start
  Placement placement;  ///< where the collision model is placed
};

/// Statistics of one batch (all translations or all rotations).
struct SpeedTestBatch {
  std::string kind;             ///< "translation" or "rotation"
  int count = 0;                ///< queries run
  int hits = 0;                 ///< queries with fraction < 1
  double wallMs = 0;            ///< elapsed time of the whole batch (all threads)
  double sumMs = 0;             ///< sum of the per-query times
  double minUs = 0;             ///< fastest query
  double avgUs = 0;             ///< sumMs / count
  double maxUs = 0;             ///< slowest query
  double queriesPerSecond = 0;  ///< count / wall time
  /// FNV-1a over the bit patterns of fraction, end position, end axis and
  /// contact normal of every result, in query order.
  std::uint64_t hash = 0;
};

/// The two batches of a speed test run.
struct SpeedTestReport {
  /// The translation batch.
  SpeedTestBatch translation;
  SpeedTestBatch rotation;  ///< count 0 when options.rotations is false
  SpeedTestBatch rays;      ///< ray casts; count 0 unless options.rays
  /// The RayIndex of the ray casts (zero unless options.rays).
  struct RayIndexStats {
    /// Number of nodes, polygons indexed and heap bytes.
    ///@{
    std::size_t nodes = 0, polygons = 0, bytes = 0;
    ///@}
    /// Time to build the index, in milliseconds.
    double buildMs = 0;
    bool avx2 = false;  ///< its node test is the AVX2 one (RayIndex::usesAvx2)
  } rayIndex;           ///< the ray index's figures
  /// Threads the batches ran on.
  int threads = 1;
};

/// The generator of the speed test: a 32-bit linear congruential generator
/// (the original's idRandom constants), returning its top 24 bits.
class SpeedTestRandom {
 public:
  /// A generator started from `seed`.
  explicit SpeedTestRandom(std::uint32_t seed) : state_(seed) {}
  /// Uniform in [0, 1).
  Real uniform();
  /// Uniform in [-1, 1).
  Real signedUniform() { return 2 * uniform() - 1; }

 private:
  std::uint32_t state_;
};

/// FNV-1a, 64 bits, continued from `hash` over `size` bytes.
std::uint64_t fnv1a(std::uint64_t hash, const void* data, std::size_t size);

/// The FNV-1a offset basis (the hash of nothing).
inline constexpr std::uint64_t kFnvOffsetBasis = 14695981039346656037ull;

/// Runs the speed test of `trm` against `model` (see the contract).
SpeedTestReport runSpeedTest(const CollisionModel& model, const TraceModel& trm,
                             const SpeedTestOptions& options);

}  // namespace cmkit
