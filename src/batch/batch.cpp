// batch.cpp: the batch forms of the queries (cmkit/batch.h): a chunked
// parallel loop over independent single queries.
#include "cmkit/batch.h"

#include <algorithm>
#include <string>

#include "batch/run_chunks.h"

namespace cmkit {

using detail::checkOut;
using detail::kMaxRayChunk;
using detail::kMinChunk;
using detail::kRayChunksPerBatch;
using detail::pick;
using detail::runChunks;

Result<std::size_t> batchSize(std::size_t a, std::size_t b, const char* what) {
  if (a == b || b == 1) return a;
  if (a == 1) return b;
  return Error(std::string("batch inputs of different lengths: ") + what + " (" + std::to_string(a) +
               " and " + std::to_string(b) + "; each must be 1 or the batch size)");
}

using detail::pairedSize;

Status translateBatch(const CollisionModel& model, const TranslationBatch& batch, std::span<TraceResult> out,
                      const BatchOptions& options) {
  const auto n = pairedSize(batch.starts.size(), batch.ends.size(), "starts and ends", out.size());
  if (!n) return n.error();
  return runChunks<QueryWork>(*n, options, [&](std::size_t begin, std::size_t end, QueryWork& work) {
    TranslationQuery q = batch.query;
    for (std::size_t i = begin; i < end; ++i) {
      q.start = pick(batch.starts, i);
      q.end = pick(batch.ends, i);
      out[i] = translate(model, q, work);
    }
  });
}

Status rotateBatch(const CollisionModel& model, const RotationBatch& batch, std::span<TraceResult> out,
                   const BatchOptions& options) {
  const auto n = pairedSize(batch.starts.size(), batch.rotations.size(), "starts and rotations", out.size());
  if (!n) return n.error();
  return runChunks<QueryWork>(*n, options, [&](std::size_t begin, std::size_t end, QueryWork& work) {
    RotationQuery q = batch.query;
    for (std::size_t i = begin; i < end; ++i) {
      q.start = pick(batch.starts, i);
      q.rotation = pick(batch.rotations, i);
      out[i] = rotate(model, q, work);
    }
  });
}

Status contentsBatch(const CollisionModel& model, const ContentsBatch& batch, std::span<ContentsResult> out,
                     const BatchOptions& options) {
  if (auto s = checkOut(out.size(), batch.positions.size()); !s) return s;
  return runChunks<QueryWork>(batch.positions.size(), options,
                              [&](std::size_t begin, std::size_t end, QueryWork& work) {
                                ContentsQuery q = batch.query;
                                for (std::size_t i = begin; i < end; ++i) {
                                  q.position = batch.positions[i];
                                  out[i] = contentsTest(model, q, work);
                                }
                              });
}

Status contactsBatch(const CollisionModel& model, const ContactsBatch& batch, std::span<ContactsResult> out,
                     const BatchOptions& options) {
  // starts, dirs (unless rotations stand without them) and rotations (when
  // given): each 1 or N.
  const bool turning = !batch.rotations.empty();
  const bool sharedDir = turning && batch.dirs.empty();
  Result<std::size_t> n = batch.starts.size();
  if (!sharedDir) n = batchSize(*n, batch.dirs.size(), "starts and dirs");
  if (n && turning) n = batchSize(*n, batch.rotations.size(), "starts, dirs and rotations");
  if (!n) return n.error();
  if (auto s = checkOut(out.size(), *n); !s) return s;
  return runChunks<QueryWork>(*n, options, [&](std::size_t begin, std::size_t end, QueryWork& work) {
    ContactsQuery q = batch.query;
    for (std::size_t i = begin; i < end; ++i) {
      q.start = pick(batch.starts, i);
      if (!sharedDir) q.dir = pick(batch.dirs, i);
      if (turning) q.rotation = pick(batch.rotations, i);
      out[i] = contacts(model, q, work);
    }
  });
}

Status pointContentsBatch(const CollisionModel& model, const PointContentsBatch& batch,
                          std::span<PointContentsResult> out, const BatchOptions& options) {
  if (auto s = checkOut(out.size(), batch.points.size()); !s) return s;
  return runChunks<QueryWork>(batch.points.size(), options,
                              [&](std::size_t begin, std::size_t end, QueryWork& work) {
                                PointContentsQuery q = batch.query;
                                for (std::size_t i = begin; i < end; ++i) {
                                  q.point = batch.points[i];
                                  out[i] = pointContents(model, q, work);
                                }
                              });
}

Status castRayBatch(const RayIndex& index, const RayBatch& batch, std::span<RayHit> out,
                    const BatchOptions& options) {
  const auto n = pairedSize(batch.starts.size(), batch.ends.size(), "starts and ends", out.size());
  if (!n) return n.error();
  // Larger chunks than the other batches': RayIndex::castMany sorts each
  // chunk's rays into packets, and more rays give more coherent packets.
  BatchOptions rayOptions = options;
  if (rayOptions.chunkSize == 0)
    rayOptions.chunkSize = std::clamp<std::size_t>(*n / kRayChunksPerBatch, kMinChunk, kMaxRayChunk);
  return runChunks<QueryWork>(*n, rayOptions, [&](std::size_t begin, std::size_t end, QueryWork&) {
    const auto part = [&](std::span<const Vec3> v) {
      return v.size() == 1 ? v : v.subspan(begin, end - begin);
    };
    index.castMany({batch.query, part(batch.starts), part(batch.ends)}, out.subspan(begin, end - begin));
  });
}

}  // namespace cmkit
