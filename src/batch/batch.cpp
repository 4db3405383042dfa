// batch.cpp: the batch forms of the queries (cmkit/batch.h): a chunked
// parallel loop over independent single queries.
#include "cmkit/batch.h"

#include <algorithm>
#include <string>

#include "batch/batch_queries.h"

namespace cmkit {

using detail::kMaxRayChunk;
using detail::kMinChunk;
using detail::kRayChunksPerBatch;
using detail::runChunks;
using detail::runQueries;

Result<std::size_t> batchSize(std::size_t a, std::size_t b, const char* what) {
  if (a == b || b == 1) return a;
  if (a == 1) return b;
  return Error(std::string("batch inputs of different lengths: ") + what + " (" + std::to_string(a) +
               " and " + std::to_string(b) + "; each must be 1 or the batch size)");
}

Status translateBatch(const CollisionModel& model, const TranslationBatch& batch, std::span<TraceResult> out,
                      const BatchOptions& options) {
  return runQueries<QueryWork>(batch, out, options, [&](const TranslationQuery& q, QueryWork& work) {
    return translate(model, q, work);
  });
}

Status rotateBatch(const CollisionModel& model, const RotationBatch& batch, std::span<TraceResult> out,
                   const BatchOptions& options) {
  return runQueries<QueryWork>(
      batch, out, options, [&](const RotationQuery& q, QueryWork& work) { return rotate(model, q, work); });
}

Status contentsBatch(const CollisionModel& model, const ContentsBatch& batch, std::span<ContentsResult> out,
                     const BatchOptions& options) {
  return runQueries<QueryWork>(batch, out, options, [&](const ContentsQuery& q, QueryWork& work) {
    return contentsTest(model, q, work);
  });
}

Status contactsBatch(const CollisionModel& model, const ContactsBatch& batch, std::span<ContactsResult> out,
                     const BatchOptions& options) {
  return runQueries<QueryWork>(
      batch, out, options, [&](const ContactsQuery& q, QueryWork& work) { return contacts(model, q, work); });
}

Status pointContentsBatch(const CollisionModel& model, const PointContentsBatch& batch,
                          std::span<PointContentsResult> out, const BatchOptions& options) {
  return runQueries<QueryWork>(batch, out, options, [&](const PointContentsQuery& q, QueryWork& work) {
    return pointContents(model, q, work);
  });
}

Status castRayBatch(const RayIndex& index, const RayBatch& batch, std::span<RayHit> out,
                    const BatchOptions& options) {
  const auto n = detail::queryCount(batch, out.size());
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
