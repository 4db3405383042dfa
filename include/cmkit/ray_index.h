// ray_index.h: fast ray casts against a collision model.
//
// CONTRACT
// - RayIndex is built once from a model (an 8-wide bounding volume hierarchy
//   over its polygons, with their planes and corners copied in; lt4's
//   world: ~15 ms, ~2 MB) and is then immutable: cast() is a const function,
//   safe to call from any number of threads at once, with no scratch memory.
//   It does not refer to the model after construction.
// - cast() answers: where does the segment start -> end first cross the front
//   face of a polygon whose contents match the mask? The fraction is the
//   crossing itself (0 at start, 1 at end; a segment that ends exactly on a
//   surface hits at 1), with the polygon's plane, contents and material. A
//   crossing counts only within the polygon's bounds padded by
//   tol::kRayAcceptPadding, so rounding in the edge tests cannot make a
//   polygon take a ray that passes far from it.
//   Polygons are one-sided, as in translate(): a segment leaving a polygon
//   from behind passes through it.
// - "Inside the polygon" is decided by the same Plücker edge tests the
//   translations use, so a segment through the edge two polygons share hits
//   exactly one of them (no leaks between neighbours). Equal crossings pick the
//   lowest polygon index: results are deterministic.
// - HOW IT DIFFERS FROM translate() WITH A POINT: translate() reproduces the
//   original engine's point trace — it stops tol::kClipEpsilon (0.25 units) in
//   front of the surface along its normal and walks the model's BSP tree in
//   the original's order, which decides ties and rare grazing cases. cast()
//   reports the surface crossing with none of that, which is what a sensor or
//   picking ray wants, at a fraction of the cost (docs/performance.md). Where
//   cast() hits, translate() stops too, no later (tests check this on lt4).
// - Non-finite input or start == end: no hit.
// - The node test runs 8 children at a time with AVX2 where the processor has
//   AVX2 and FMA (chosen when the index is built), else as two halves with
//   SSE2 (or one child at a time off x86). Both give exactly the same answers.
// - castMany() casts many rays at once, the same answers as cast() on each:
//   with AVX2 it walks packets of eight neighbouring rays together.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>

#include "cmkit/contents.h"
#include "cmkit/math.h"
#include "cmkit/model.h"
#include "cmkit/query.h"
#include "cmkit/tolerances.h"

namespace cmkit {

/// The answer of RayIndex::cast(). World space. On a miss every field keeps
/// its default (fraction 1, polygon -1, material -1).
struct RayHit {
  Real fraction = 1;           ///< where the segment crosses the surface
  Vec3 point;                  ///< the crossing
  Vec3 normal;                 ///< the polygon's normal (facing the start)
  Real dist = 0;               ///< normal . p = dist on the polygon's plane
  std::int32_t polygon = -1;   ///< index into the model's polygons
  std::uint32_t contents = 0;  ///< contents of the polygon
  std::int32_t material = -1;  ///< index into the model's materials, -1 = none

  /// True when the ray hit a polygon.
  bool hit() const { return polygon >= 0; }
};

/// A ray cast: the segment start -> end against the model placed in the
/// world by `placement`, hitting polygons whose contents match the mask.
struct RayCastQuery {
  /// Start of the segment (world space).
  Vec3 start;
  /// End of the segment (world space).
  Vec3 end;
  /// Content flags of the polygons the ray can hit.
  std::uint32_t contentMask = contents::kMaskSolid;
  /// Where the model is placed in the world.
  Placement placement = {};
};

/// Ray casts of one model: ray i is `query` with the segment starts[i] (or
/// starts[0]) -> ends[i] (or ends[0]); query.start and query.end are
/// ignored. For RayIndex::castMany and castRayBatch (cmkit/batch.h).
struct RayBatch {
  /// The fields every ray shares (start and end ignored): mask, placement.
  RayCastQuery query;
  std::span<const Vec3> starts;  ///< 1 or N
  std::span<const Vec3> ends;    ///< 1 or N
};

namespace detail {
struct RayIndexData;
}  // namespace detail

/// A ray-cast acceleration structure of one model. Copies share the
/// (immutable) index.
class RayIndex {
 public:
  /// Which node test cast() uses. Auto: AVX2 if the processor (AVX2 and
  /// FMA) and the build have it, else the baseline. Baseline: SSE2 on x86-64, plain C++
  /// elsewhere; for tests and comparisons, the answers are the same.
  enum class NodeTest { Auto, Baseline };

  /// Indexes every polygon of `model` with a finite plane and bounds.
  explicit RayIndex(const CollisionModel& model, NodeTest nodeTest = NodeTest::Auto);

  ~RayIndex();
  /// Shares the copied index.
  RayIndex(const RayIndex&);
  /// Takes the index over.
  RayIndex(RayIndex&&) noexcept;
  /// Shares the copied index.
  RayIndex& operator=(const RayIndex&);
  /// Takes the index over.
  RayIndex& operator=(RayIndex&&) noexcept;

  /// The first front face the segment query.start -> query.end crosses
  /// (model placed in the world by query.placement).
  RayHit cast(const RayCastQuery& query) const;

  /// Many casts at once: out[i] = cast(ray i of `batch`) bit for bit (a
  /// span of one start or end is used for every ray). Faster per ray than a loop of cast() for many rays:
  /// they are sorted by where they start and which way they point, and with the AVX2 node test walked eight
  /// at a time (one packet of neighbouring rays shares the node visits). Spans of other lengths (not 1 and
  /// not out.size()) leave `out` untouched; castRayBatch (cmkit/batch.h) checks them and spreads a batch over
  /// threads. Scratch is on the stack and the heap of the caller's thread: safe from any number of threads at
  /// once.
  void castMany(const RayBatch& batch, std::span<RayHit> out) const;

  /// Whether cast() tests nodes with AVX2.
  bool usesAvx2() const;
  /// Number of 8-wide nodes.
  std::size_t numNodes() const;
  /// Number of polygons indexed.
  std::size_t numPolygons() const;
  /// Heap memory held.
  std::size_t memoryBytes() const;

 private:
  std::shared_ptr<const detail::RayIndexData> data_;  ///< immutable: copies share it
};

}  // namespace cmkit
