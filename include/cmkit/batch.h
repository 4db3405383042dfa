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
// - A batch holds the single query's struct (`query`) for the fields every
//   query shares, and spans for the fields that vary; the fields the spans
//   give are ignored in `query` (each batch struct says which).
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
#include <functional>
#include <span>

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

/// Translations of one trace model: query i is `query` moving it from
/// starts[i] (or starts[0]) to ends[i] (or ends[0]). query.start and
/// query.end are ignored (the spans give them); every other field of
/// `query` is shared by all queries. See TranslationQuery.
struct TranslationBatch {
  /// The fields every translation shares (start and end ignored).
  TranslationQuery query;
  std::span<const Vec3> starts;  ///< 1 or N
  std::span<const Vec3> ends;    ///< 1 or N
};

/// Rotations of one trace model: query i is `query` turning it from
/// starts[i] by rotations[i] (either may be 1 long). query.start and
/// query.rotation are ignored. See RotationQuery.
struct RotationBatch {
  /// The fields every rotation shares (start and rotation ignored).
  RotationQuery query;
  std::span<const Vec3> starts;         ///< 1 or N
  std::span<const Rotation> rotations;  ///< 1 or N
};

/// Position tests of one trace model: query i is `query` at positions[i]
/// (query.position is ignored). See ContentsQuery.
struct ContentsBatch {
  /// The fields every position test shares (position ignored).
  ContentsQuery query;
  std::span<const Vec3> positions;  ///< N
};

/// Contacts of one trace model: query i is `query` moved from starts[i]
/// along dirs[i] by query.depth (query.start and query.dir are ignored), or,
/// with `rotations`, turned from starts[i] by rotations[i] (query.rotation
/// ignored; with dirs empty, query.dir for every query). See ContactsQuery.
struct ContactsBatch {
  /// The fields every contacts query shares (start and dir ignored; rotation
  /// too when `rotations` is given).
  ContactsQuery query;
  std::span<const Vec3> starts;  ///< 1 or N
  std::span<const Vec3> dirs;    ///< 1 or N; may be empty when `rotations` is given
  /// Empty: query.rotation for every query (translations when unset); else
  /// 1 or N: contacts along rotations[i] (as ContactsQuery::rotation, so
  /// dirs[i] * query.depth must be zero: QueryStatus::MixedMotion).
  std::span<const Rotation> rotations;
};

/// Point contents of many points: query i is `query` at points[i]
/// (query.point is ignored). See PointContentsQuery.
struct PointContentsBatch {
  /// The fields every query shares (point ignored): the placement.
  PointContentsQuery query;
  std::span<const Vec3> points;  ///< N
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
/// out[i] = pointContents(model, query i, work).
Status pointContentsBatch(const CollisionModel& model, const PointContentsBatch& batch,
                          std::span<PointContentsResult> out, const BatchOptions& options = {});
/// out[i] = index.cast(query i) (RayBatch: ray_index.h).
Status castRayBatch(const RayIndex& index, const RayBatch& batch, std::span<RayHit> out,
                    const BatchOptions& options = {});

}  // namespace cmkit
