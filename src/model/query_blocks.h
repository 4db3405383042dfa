// Internal: the SIMD blocks of a model's query data (query_data.h): kLanes
// entries per block, one array per number, lane i % kLanes of block
// i / kLanes holding entry i.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>

#include "cmkit/model.h"

#include "util/simd.h"

// The queries read the cull blocks only four polygons at a time, in
// util/simd.h's float lanes (CMKIT_QUERY_LANES); other builds (another
// target, -DCMKIT_NO_SIMD, a double build) make none.
#ifdef CMKIT_FLOAT_LANES
#define CMKIT_QUERY_LANES 1
#endif

namespace cmkit::detail {

/// Whether makeQueryData makes cull blocks (CMKIT_QUERY_LANES).
#ifdef CMKIT_QUERY_LANES
inline constexpr bool kCullBlocks = true;
#else
inline constexpr bool kCullBlocks = false;
#endif

/// Entries per block (SIMD lanes).
inline constexpr std::size_t kLanes = 4;
/// Blocks that entries first .. first + count - 1 touch.
inline constexpr std::size_t blocksSpanned(std::size_t first, std::size_t count) {
  return count == 0 ? 0 : (first + count - 1) / kLanes - first / kLanes + 1;
}

/// kLanes lines (Pluecker coordinates): coordinate k of lane j at c[k][j]
/// (a translation's trace-model vertex paths, TrmFeatures::vertexLines).
struct alignas(16) LineBlock {
  Real c[6][kLanes];
};

/// The line of model edge e (unsigned number) in its stored direction.
inline Pluecker modelEdgeLine(const ModelArrays& m, std::size_t e) {
  const CmEdge& edge = m.edges[e];
  return Pluecker::fromLine(m.vertices[std::size_t(edge.vertex[0])], m.vertices[std::size_t(edge.vertex[1])]);
}

/// The line of model edge e (unsigned number) of a sealed model.
inline Pluecker modelEdgeLine(const CollisionModel& m, std::size_t e) { return modelEdgeLine(m.arrays(), e); }

/// What a translation's test of a polygon reads of one of its polygonEdges
/// entries, side by side: a polygon's entries one after another, in place
/// of the entry and its edge's record in two arrays (for a large mesh, the
/// record read at random). 16 bytes: the edge's line is not stored but made
/// from the two vertices when a polygon is tested (trace_work.h,
/// polygonEdges), the model's vertex array being a fraction of the size of
/// the lines (a large mesh's lines in the uses made them 2.5 times as large
/// and its sweeps wait on memory: docs/performance.md).
struct EdgeUse {
  std::int32_t edgeNum = 0;         ///< the entry: the edge's number, negative when used reversed
  std::int32_t vertex[2] = {0, 0};  ///< the edge's vertices (CmEdge::vertex)
  std::uint32_t internal = 0;       ///< CmEdge::internal
  /// The vertex where the edge starts in the polygon's order.
  std::int32_t start() const { return vertex[edgeNum < 0 ? 1 : 0]; }
  /// The vertex where it ends.
  std::int32_t end() const { return vertex[edgeNum < 0 ? 0 : 1]; }
};
static_assert(sizeof(EdgeUse) == 16);

/// A polygon's edge entry as the polygons' hierarchy keeps it
/// (PolygonBvh::uses): the entry (the edge's number, negative when used
/// reversed) and the edge's internal flag, as 2 * entry + flag (so the
/// entry is one shift away and its sign is the value's), and the position
/// of the polygon's vertex where the edge starts in the polygon's order, so
/// edge i runs from corner i to corner i + 1 (the last to the first). 16
/// bytes, as an EdgeUse, but what a translation's test reads of the
/// vertices is in it, not read at random from the model's vertices.
struct PolygonCorner {
  std::int32_t entry = 0;  ///< 2 * polygonEdges entry + internal flag
  Vec3 p;
  std::int32_t edgeNum() const { return entry >> 1; }  // (arithmetic: -5 >> 1 == -3)
  bool internal() const { return (entry & 1) != 0; }
  static std::int32_t encode(std::int32_t edgeNum, bool internal) {
    return std::int32_t(std::uint32_t(edgeNum) * 2u) | std::int32_t(internal);
  }
};
static_assert(sizeof(PolygonCorner) == 16 || sizeof(Real) != sizeof(float));

/// The EdgeUse of polygonEdges entry `edgeNum`.
inline EdgeUse edgeUse(const ModelArrays& m, std::int32_t edgeNum) {
  const CmEdge& edge = m.edges[std::size_t(std::abs(edgeNum))];
  return {edgeNum, {edge.vertex[0], edge.vertex[1]}, edge.internal ? 1u : 0u};
}

/// Writes the uses of `edges` (signed edge numbers) to out[0 .. edges.size() - 1].
void writeEdgeUses(const ModelArrays& m, std::span<const std::int32_t> edges, EdgeUse* out);

/// What a translation's culls read of kLanes polygonRefs entries' polygons:
/// lane j of each array is entry j's (lanes past the last entry are 0).
struct alignas(16) CullBlock {
  Real min[3][kLanes];             ///< bounds.min, per axis
  Real max[3][kLanes];             ///< bounds.max, per axis
  std::uint32_t contents[kLanes];  ///< (beside the bounds: the first cull reads these 112 bytes)
  Real normal[3][kLanes];          ///< plane.normal, per axis
};

}  // namespace cmkit::detail
