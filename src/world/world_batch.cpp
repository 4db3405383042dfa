// The batch forms of the world's queries (world.h): the single world
// queries in a chunked loop (batch/batch_queries.h), one WorldQueryWork per
// worker, so out[i] is the single query's answer at any thread count.
#include "batch/batch_queries.h"
#include "cmkit/world.h"

namespace cmkit {

using detail::runQueries;

Status translateBatch(const World& world, const TranslationBatch& batch, std::span<WorldTraceResult> out,
                      const BatchOptions& options, const EntityFilter& filter) {
  return runQueries<WorldQueryWork>(
      batch, out, options,
      [&](const TranslationQuery& q, WorldQueryWork& work) { return world.translate(q, work, filter); });
}

Status rotateBatch(const World& world, const RotationBatch& batch, std::span<WorldTraceResult> out,
                   const BatchOptions& options, const EntityFilter& filter) {
  return runQueries<WorldQueryWork>(batch, out, options, [&](const RotationQuery& q, WorldQueryWork& work) {
    return world.rotate(q, work, filter);
  });
}

Status contentsBatch(const World& world, const ContentsBatch& batch, std::span<WorldContentsResult> out,
                     const BatchOptions& options, const EntityFilter& filter) {
  return runQueries<WorldQueryWork>(batch, out, options, [&](const ContentsQuery& q, WorldQueryWork& work) {
    return world.contentsTest(q, work, filter);
  });
}

Status pointContentsBatch(const World& world, const PointContentsBatch& batch,
                          std::span<WorldPointContentsResult> out, const BatchOptions& options,
                          const EntityFilter& filter) {
  return runQueries<WorldQueryWork>(batch, out, options,
                                    [&](const PointContentsQuery& q, WorldQueryWork& work) {
                                      return world.pointContents(q, work, filter);
                                    });
}

Status contactsBatch(const World& world, const ContactsBatch& batch, std::span<WorldContactsResult> out,
                     const BatchOptions& options, const EntityFilter& filter) {
  return runQueries<WorldQueryWork>(batch, out, options, [&](const ContactsQuery& q, WorldQueryWork& work) {
    return world.contacts(q, work, filter);
  });
}

Status castRayBatch(const World& world, const RayBatch& batch, std::span<WorldRayHit> out,
                    const BatchOptions& options, const EntityFilter& filter) {
  return runQueries<WorldQueryWork>(batch, out, options, [&](const RayCastQuery& q, WorldQueryWork& work) {
    return world.castRay(q, work, filter);
  });
}

}  // namespace cmkit
