// batch_queries.h: what every batch of one query kind does the same way,
// for a single model (batch.cpp) and for a World (world/world_batch.cpp):
// how many queries a batch holds (its inputs each 1 or N, the output N),
// query i made from the batch's shared query, and the loop of runChunks
// that asks each one.
#pragma once

#include <cstddef>
#include <span>

#include "batch/run_chunks.h"
#include "cmkit/batch.h"
#include "cmkit/ray_index.h"

namespace cmkit::detail {

/// How many queries a batch holds (the output must hold as many), or why
/// its inputs do not pair up.
inline Result<std::size_t> queryCount(const TranslationBatch& b, std::size_t outSize) {
  return pairedSize(b.starts.size(), b.ends.size(), "starts and ends", outSize);
}
inline Result<std::size_t> queryCount(const RotationBatch& b, std::size_t outSize) {
  return pairedSize(b.starts.size(), b.rotations.size(), "starts and rotations", outSize);
}
inline Result<std::size_t> queryCount(const RayBatch& b, std::size_t outSize) {
  return pairedSize(b.starts.size(), b.ends.size(), "starts and ends", outSize);
}
inline Result<std::size_t> queryCount(const ContentsBatch& b, std::size_t outSize) {
  if (auto s = checkOut(outSize, b.positions.size()); !s) return s.error();
  return b.positions.size();
}
inline Result<std::size_t> queryCount(const PointContentsBatch& b, std::size_t outSize) {
  if (auto s = checkOut(outSize, b.points.size()); !s) return s.error();
  return b.points.size();
}
/// Contacts: starts, dirs (unless rotations stand without them) and
/// rotations (when given), each 1 or N.
inline Result<std::size_t> queryCount(const ContactsBatch& b, std::size_t outSize) {
  const bool turning = !b.rotations.empty();
  Result<std::size_t> n = b.starts.size();
  if (!(turning && b.dirs.empty())) n = batchSize(*n, b.dirs.size(), "starts and dirs");
  if (n && turning) n = batchSize(*n, b.rotations.size(), "starts, dirs and rotations");
  if (!n) return n;
  if (auto s = checkOut(outSize, *n); !s) return s.error();
  return n;
}

/// Puts query i's own fields into `q` (the batch's shared query).
inline void setQuery(const TranslationBatch& b, TranslationQuery& q, std::size_t i) {
  q.start = pick(b.starts, i);
  q.end = pick(b.ends, i);
}
inline void setQuery(const RotationBatch& b, RotationQuery& q, std::size_t i) {
  q.start = pick(b.starts, i);
  q.rotation = pick(b.rotations, i);
}
inline void setQuery(const RayBatch& b, RayCastQuery& q, std::size_t i) {
  q.start = pick(b.starts, i);
  q.end = pick(b.ends, i);
}
inline void setQuery(const ContentsBatch& b, ContentsQuery& q, std::size_t i) { q.position = b.positions[i]; }
inline void setQuery(const PointContentsBatch& b, PointContentsQuery& q, std::size_t i) {
  q.point = b.points[i];
}
inline void setQuery(const ContactsBatch& b, ContactsQuery& q, std::size_t i) {
  const bool turning = !b.rotations.empty();
  q.start = pick(b.starts, i);
  if (!(turning && b.dirs.empty())) q.dir = pick(b.dirs, i);
  if (turning) q.rotation = pick(b.rotations, i);
}

/// out[i] = ask(query i, work) for every query of the batch, on runChunks'
/// workers (each with its own `Work`).
template <class Work, class Batch, class Out, class Ask>
Status runQueries(const Batch& batch, std::span<Out> out, const BatchOptions& options, const Ask& ask) {
  const Result<std::size_t> n = queryCount(batch, out.size());
  if (!n) return n.error();
  return runChunks<Work>(*n, options, [&](std::size_t begin, std::size_t end, Work& work) {
    auto q = batch.query;
    for (std::size_t i = begin; i < end; ++i) {
      setQuery(batch, q, i);
      out[i] = ask(q, work);
    }
  });
}

}  // namespace cmkit::detail
