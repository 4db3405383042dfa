// batch.h: many queries of one kind in one call, on several threads.
//
// CONTRACT
// - Each batch function answers a list of queries over contiguous arrays
//   (spans in, a span out) exactly as a loop of the single query functions
//   (query.h, ray_index.h) would: out[i] is, bit for bit, what the single
//   query i returns. The threads only decide who computes which answer, so
//   results are BIT-IDENTICAL AT ANY THREAD COUNT.
// - Per-query inputs come as spans of length N (the batch size). Where a
//   field says "1 or N", a span of length 1 is used for every query (one
//   start, many ends). Spans of other lengths, or an `out` span whose length
//   is not N, are an Error and nothing is computed. N = 0 is an empty batch:
//   success, nothing written.
// - A trace model pointer may be null (a point), as in the single queries.
// - Threads: BatchOptions::threads workers (0: one per hardware thread, at
//   most one per chunk); each owns a QueryWork. The calling thread is one of
//   them. The queries are cut into chunks of a size that depends only on N
//   (or BatchOptions::chunkSize); workers take the next chunk from a shared
//   counter. Ray batches take larger chunks and cast each with
//   RayIndex::castMany, which reorders a chunk's rays into packets of
//   neighbouring rays: the answers are still those of single casts.
// - Progress and cancelling: BatchOptions::progress, when set, is called on
//   the CALLING thread only, with the number of queries answered so far and
//   N: after each chunk the calling thread answers, while it waits for the
//   other workers each time they have answered more, and once at the end
//   with (N, N). Returning false (at any call) cancels: workers start no new
//   chunk, the function returns an Error ("batch cancelled after K of N
//   queries") and the contents of `out` are unspecified.
// - The functions never throw: a failure to start a thread runs the batch on
//   fewer threads; running out of memory (contacts) is an Error, and so is an
//   exception thrown by the progress hook ("the batch progress hook failed:
//   WHAT"; the batch stops).
//
// WHY std::thread AND NOT TBB: a batch is one flat loop over independent
// queries, so a shared chunk counter balances it as well as work stealing
// would; threads are started per call (tens of microseconds, small against a
// batch worth splitting) and nothing outlives the call, so the library keeps
// no global pool, adds no dependency, and its consumers need not link TBB.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>

#include "cmkit/contents.h"
#include "cmkit/math.h"
#include "cmkit/model.h"
#include "cmkit/query.h"
#include "cmkit/ray_index.h"
#include "cmkit/result.h"
#include "cmkit/rotation.h"
#include "cmkit/trace_model.h"

namespace cmkit {

/// How a batch runs.
struct BatchOptions {
  /// Worker threads, the calling thread included; 0: one per hardware thread.
  int threads = 0;
  /// Queries per chunk; 0: chosen from the batch size alone.
  std::size_t chunkSize = 0;
  /// Called on the calling thread with (queries answered, batch size) now
  /// and then and once at the end; return false to cancel (see the contract).
  std::function<bool(std::size_t done, std::size_t total)> progress;
};

/// Translations of one trace model: query i moves it from starts[i] (or
/// starts[0]) to ends[i] (or ends[0]). See TranslationQuery.
struct TranslationBatch {
  /// The trace model moved (nullptr or a point shape: a point).
  const TraceModel* trm = nullptr;
  /// Orientation of the trace model.
  Mat3 trmAxis;
  std::span<const Vec3> starts;  ///< 1 or N
  std::span<const Vec3> ends;    ///< 1 or N
  /// Content flags the queries collide with.
  std::uint32_t contentMask = contents::kMaskSolid;
  /// Where the model is placed in the world.
  Placement placement;
  /// Also run a position test at each start and set TraceResult::startSolid.
  bool detectStartSolid = false;
};

/// Rotations of one trace model: query i turns it from starts[i] by
/// rotations[i] (either may be 1 long). See RotationQuery.
struct RotationBatch {
  /// The trace model moved (nullptr or a point shape: a point).
  const TraceModel* trm = nullptr;
  /// Orientation of the trace model.
  Mat3 trmAxis;
  std::span<const Vec3> starts;         ///< 1 or N
  std::span<const Rotation> rotations;  ///< 1 or N
  /// Content flags the queries collide with.
  std::uint32_t contentMask = contents::kMaskSolid;
  /// Where the model is placed in the world.
  Placement placement;
  /// Also run a position test at each start and set TraceResult::startSolid.
  bool detectStartSolid = false;
};

/// Position tests of one trace model at many positions. See ContentsQuery.
struct ContentsBatch {
  /// The trace model tested (nullptr or a point shape: point contents).
  const TraceModel* trm = nullptr;
  /// Orientation of the trace model.
  Mat3 trmAxis;
  std::span<const Vec3> positions;  ///< N
  /// Content flags the queries collide with.
  std::uint32_t contentMask = contents::kMaskSolid;
  /// Where the model is placed in the world.
  Placement placement;
};

/// Contacts of one trace model moved from starts[i] along dirs[i] by
/// `depth`. See ContactsQuery.
struct ContactsBatch {
  /// The trace model moved (nullptr or a point shape: a point).
  const TraceModel* trm = nullptr;
  /// Orientation of the trace model.
  Mat3 trmAxis;
  std::span<const Vec3> starts;  ///< 1 or N
  std::span<const Vec3> dirs;    ///< 1 or N
  /// How far each start moves along its direction.
  Real depth = 0;
  /// Content flags the queries collide with.
  std::uint32_t contentMask = contents::kMaskSolid;
  /// Where the model is placed in the world.
  Placement placement;
  /// At most this many contacts per query.
  int maxContacts = 16;
};

/// Ray casts through a RayIndex: segment starts[i] -> ends[i]. See RayCastQuery.
struct RayBatch {
  std::span<const Vec3> starts;  ///< 1 or N
  std::span<const Vec3> ends;    ///< 1 or N
  /// Content flags of the polygons the rays hit.
  std::uint32_t contentMask = contents::kMaskSolid;
  /// Where the model is placed in the world.
  Placement placement;
};

/// The batch size of two "1 or N" spans: the longer length, or an Error
/// naming `what` when both are longer than 1 and differ.
Result<std::size_t> batchSize(std::size_t a, std::size_t b, const char* what);

/// out[i] = translate(model, query i, work).
Status translateBatch(const CollisionModel& model, const TranslationBatch& batch, std::span<TraceResult> out,
                      const BatchOptions& options = {});
/// out[i] = rotate(model, query i, work).
Status rotateBatch(const CollisionModel& model, const RotationBatch& batch, std::span<TraceResult> out,
                   const BatchOptions& options = {});
/// out[i] = contentsTest(model, query i, work).
Status contentsBatch(const CollisionModel& model, const ContentsBatch& batch, std::span<ContentsResult> out,
                     const BatchOptions& options = {});
/// out[i] = contacts(model, query i, work).
Status contactsBatch(const CollisionModel& model, const ContactsBatch& batch, std::span<ContactsResult> out,
                     const BatchOptions& options = {});
/// out[i] = pointContents(model, points[i], placement).
Status pointContentsBatch(const CollisionModel& model, std::span<const Vec3> points,
                          std::span<std::uint32_t> out, const Placement& placement = {},
                          const BatchOptions& options = {});
/// out[i] = index.cast(query i).
Status castRayBatch(const RayIndex& index, const RayBatch& batch, std::span<RayHit> out,
                    const BatchOptions& options = {});

}  // namespace cmkit
