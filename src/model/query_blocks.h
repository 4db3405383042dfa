// Internal: the SIMD blocks of a model's query data (query_data.h): kLanes
// entries per block, one array per number, lane i % kLanes of block
// i / kLanes holding entry i.
#pragma once

#include <cstddef>
#include <cstdint>
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

/// Writes the lines of `edges` (signed edge numbers: the line of |e|, in its
/// stored direction) to out[0 .. edges.size() - 1].
void writeEdgeLines(const ModelArrays& m, std::span<const std::int32_t> edges, Pluecker* out);

/// What a translation's culls read of kLanes polygonRefs entries' polygons:
/// lane j of each array is entry j's (lanes past the last entry are 0).
struct alignas(16) CullBlock {
  Real min[3][kLanes];             ///< bounds.min, per axis
  Real max[3][kLanes];             ///< bounds.max, per axis
  std::uint32_t contents[kLanes];  ///< (beside the bounds: the first cull reads these 112 bytes)
  Real normal[3][kLanes];          ///< plane.normal, per axis
};

}  // namespace cmkit::detail
