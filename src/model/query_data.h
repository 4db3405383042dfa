// Internal: what the queries derive from a built model once instead of per
// query (CollisionModel::queryData, made by prepareQueries), in blocks of
// kLanes entries with one array per number, for SIMD loads:
//  - the line of every polygonEdges entry's edge (a polygon's edge lines are
//    the entries firstEdge .. firstEdge + numEdges - 1);
//  - the bounds, normal and contents of every polygonRefs entry's polygon (a
//    node's polygons are the entries firstPolygonRef ..), for a
//    translation's culls.
// Entry i is lane i % kLanes of block i / kLanes: the arrays hold about 24
// and 40 bytes per entry, in the order the queries read them.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "cmkit/model.h"

// The queries read the cull blocks only four polygons at a time, with SSE2
// and float lanes (CMKIT_QUERY_LANES); other builds (another target,
// -DCMKIT_NO_SIMD, a double build) make none.
#if defined(__SSE2__) && !defined(CMKIT_NO_SIMD) && !CMKIT_DOUBLE
#define CMKIT_QUERY_LANES 1
#endif

namespace cmkit::detail {

/// Whether prepareQueries makes cull blocks (CMKIT_QUERY_LANES).
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

/// The lines of kLanes polygonEdges entries' edges, each in its edge's stored
/// direction (Pluecker::fromLine of vertex[0] -> vertex[1]): coordinate k of
/// lane j at c[k][j].
struct alignas(16) LineBlock {
  Real c[6][kLanes];
};

/// The line of entry i of an array of line blocks.
inline Pluecker blockLine(const LineBlock* blocks, std::size_t i) {
  const LineBlock& b = blocks[i / kLanes];
  Pluecker l;
  for (std::size_t k = 0; k < 6; ++k) l.p[k] = b.c[k][i % kLanes];
  return l;
}

/// The line of model edge e (unsigned number) in its stored direction.
inline Pluecker modelEdgeLine(const CollisionModel& m, std::size_t e) {
  const CmEdge& edge = m.edges[e];
  return Pluecker::fromLine(m.vertices[std::size_t(edge.vertex[0])], m.vertices[std::size_t(edge.vertex[1])]);
}

/// Writes the lines of `edges` (signed edge numbers) as entries 0 ..
/// edges.size() - 1 of the blocks at `out` (blocksSpanned(0, edges.size())
/// of them; the lanes past the last are 0).
void writeEdgeLines(const CollisionModel& m, std::span<const std::int32_t> edges, LineBlock* out);

/// What a translation's culls read of kLanes polygonRefs entries' polygons:
/// lane j of each array is entry j's (lanes past the last entry are 0).
struct alignas(16) CullBlock {
  Real min[3][kLanes];             ///< bounds.min, per axis
  Real max[3][kLanes];             ///< bounds.max, per axis
  std::uint32_t contents[kLanes];  ///< (beside the bounds: the first cull reads these 112 bytes)
  Real normal[3][kLanes];          ///< plane.normal, per axis
};

/// Where a model's arrays are and how long they are (vertices, edges,
/// polygon edges, polygons, nodes, polygon references): what a QueryData was
/// made from.
struct ModelArrays {
  std::array<const void*, 6> data{};
  std::array<std::size_t, 6> size{};
};
inline ModelArrays modelArrays(const CollisionModel& m) {
  return {{m.vertices.data(), m.edges.data(), m.polygonEdges.data(), m.polygons.data(), m.nodes.data(),
           m.polygonRefs.data()},
          {m.vertices.size(), m.edges.size(), m.polygonEdges.size(), m.polygons.size(), m.nodes.size(),
           m.polygonRefs.size()}};
}

struct QueryData {
  /// The arrays it was made from: it serves only the model that owns them.
  ModelArrays source;

  /// Per polygonEdges entry: its edge's line.
  std::vector<LineBlock> lines;
  /// Per polygonRefs entry: its polygon's culls (kCullBlocks builds; else empty).
  std::vector<CullBlock> culls;
};

/// model.queryData when it was made from this model's arrays (not a copy's,
/// nor before they changed size), else null: the queries then compute what
/// they need themselves.
inline const QueryData* queryDataOf(const CollisionModel& m) {
  const QueryData* d = m.queryData.get();
  if (!d) return nullptr;
  // (Array by array, stopping at the first difference: what every query pays.)
  const ModelArrays& s = d->source;
  return s.data[0] == m.vertices.data() && s.size[0] == m.vertices.size() && s.data[1] == m.edges.data() &&
                 s.size[1] == m.edges.size() && s.data[2] == m.polygonEdges.data() &&
                 s.size[2] == m.polygonEdges.size() && s.data[3] == m.polygons.data() &&
                 s.size[3] == m.polygons.size() && s.data[4] == m.nodes.data() &&
                 s.size[4] == m.nodes.size() && s.data[5] == m.polygonRefs.data() &&
                 s.size[5] == m.polygonRefs.size()
             ? d
             : nullptr;
}

}  // namespace cmkit::detail
