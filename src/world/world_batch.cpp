// The batch forms of the world's queries (world.h): the single world
// queries in a chunked loop (batch/run_chunks.h), one WorldQueryWork per
// worker, so out[i] is the single query's answer at any thread count.
#include "batch/run_chunks.h"
#include "cmkit/world.h"

namespace cmkit {

using detail::checkOut;
using detail::pairedSize;
using detail::pick;
using detail::runChunks;

Status translateBatch(const World& world, const TranslationBatch& batch, std::span<WorldTraceResult> out,
                      const BatchOptions& options, const EntityFilter& filter) {
  const auto n = pairedSize(batch.starts.size(), batch.ends.size(), "starts and ends", out.size());
  if (!n) return n.error();
  return runChunks<WorldQueryWork>(*n, options,
                                   [&](std::size_t begin, std::size_t end, WorldQueryWork& work) {
                                     TranslationQuery q = batch.query;
                                     for (std::size_t i = begin; i < end; ++i) {
                                       q.start = pick(batch.starts, i);
                                       q.end = pick(batch.ends, i);
                                       out[i] = world.translate(q, work, filter);
                                     }
                                   });
}

Status rotateBatch(const World& world, const RotationBatch& batch, std::span<WorldTraceResult> out,
                   const BatchOptions& options, const EntityFilter& filter) {
  const auto n = pairedSize(batch.starts.size(), batch.rotations.size(), "starts and rotations", out.size());
  if (!n) return n.error();
  return runChunks<WorldQueryWork>(*n, options,
                                   [&](std::size_t begin, std::size_t end, WorldQueryWork& work) {
                                     RotationQuery q = batch.query;
                                     for (std::size_t i = begin; i < end; ++i) {
                                       q.start = pick(batch.starts, i);
                                       q.rotation = pick(batch.rotations, i);
                                       out[i] = world.rotate(q, work, filter);
                                     }
                                   });
}

Status contentsBatch(const World& world, const ContentsBatch& batch, std::span<WorldContentsResult> out,
                     const BatchOptions& options, const EntityFilter& filter) {
  if (auto s = checkOut(out.size(), batch.positions.size()); !s) return s;
  return runChunks<WorldQueryWork>(batch.positions.size(), options,
                                   [&](std::size_t begin, std::size_t end, WorldQueryWork& work) {
                                     ContentsQuery q = batch.query;
                                     for (std::size_t i = begin; i < end; ++i) {
                                       q.position = batch.positions[i];
                                       out[i] = world.contentsTest(q, work, filter);
                                     }
                                   });
}

Status pointContentsBatch(const World& world, const PointContentsBatch& batch,
                          std::span<WorldPointContentsResult> out, const BatchOptions& options,
                          const EntityFilter& filter) {
  if (auto s = checkOut(out.size(), batch.points.size()); !s) return s;
  return runChunks<WorldQueryWork>(batch.points.size(), options,
                                   [&](std::size_t begin, std::size_t end, WorldQueryWork& work) {
                                     PointContentsQuery q = batch.query;
                                     for (std::size_t i = begin; i < end; ++i) {
                                       q.point = batch.points[i];
                                       out[i] = world.pointContents(q, work, filter);
                                     }
                                   });
}

Status contactsBatch(const World& world, const ContactsBatch& batch, std::span<WorldContactsResult> out,
                     const BatchOptions& options, const EntityFilter& filter) {
  // As the single-model contactsBatch: starts, dirs (unless rotations stand
  // without them) and rotations (when given), each 1 or N.
  const bool turning = !batch.rotations.empty();
  const bool sharedDir = turning && batch.dirs.empty();
  Result<std::size_t> n = batch.starts.size();
  if (!sharedDir) n = batchSize(*n, batch.dirs.size(), "starts and dirs");
  if (n && turning) n = batchSize(*n, batch.rotations.size(), "starts, dirs and rotations");
  if (!n) return n.error();
  if (auto s = checkOut(out.size(), *n); !s) return s;
  return runChunks<WorldQueryWork>(*n, options,
                                   [&](std::size_t begin, std::size_t end, WorldQueryWork& work) {
                                     ContactsQuery q = batch.query;
                                     for (std::size_t i = begin; i < end; ++i) {
                                       q.start = pick(batch.starts, i);
                                       if (!sharedDir) q.dir = pick(batch.dirs, i);
                                       if (turning) q.rotation = pick(batch.rotations, i);
                                       out[i] = world.contacts(q, work, filter);
                                     }
                                   });
}

Status castRayBatch(const World& world, const RayBatch& batch, std::span<WorldRayHit> out,
                    const BatchOptions& options, const EntityFilter& filter) {
  const auto n = pairedSize(batch.starts.size(), batch.ends.size(), "starts and ends", out.size());
  if (!n) return n.error();
  return runChunks<WorldQueryWork>(*n, options,
                                   [&](std::size_t begin, std::size_t end, WorldQueryWork& work) {
                                     RayCastQuery q = batch.query;
                                     for (std::size_t i = begin; i < end; ++i) {
                                       q.start = pick(batch.starts, i);
                                       q.end = pick(batch.ends, i);
                                       out[i] = world.castRay(q, work, filter);
                                     }
                                   });
}

}  // namespace cmkit
