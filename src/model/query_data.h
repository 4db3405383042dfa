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

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "cmkit/model.h"

namespace cmkit::detail {

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
  Real min[3][kLanes];     ///< bounds.min, per axis
  Real max[3][kLanes];     ///< bounds.max, per axis
  Real normal[3][kLanes];  ///< plane.normal, per axis
  std::uint32_t contents[kLanes];
};

struct QueryData {
  /// The arrays it was made from: it serves only the model that owns them.
  const Vec3* vertices = nullptr;
  const CmEdge* edges = nullptr;
  const std::int32_t* polygonEdges = nullptr;
  const CmPolygon* polygons = nullptr;
  const CmNode* nodes = nullptr;
  const std::int32_t* polygonRefs = nullptr;
  std::size_t numVertices = 0, numEdges = 0, numPolygonEdges = 0, numPolygons = 0, numNodes = 0,
              numPolygonRefs = 0;

  /// Per polygonEdges entry: its edge's line.
  std::vector<LineBlock> lines;
  /// Per polygonRefs entry: its polygon's culls.
  std::vector<CullBlock> culls;
};

/// model.queryData when it was made from this model's arrays (not a copy's,
/// nor before they changed size), else null: the queries then compute what
/// they need themselves.
inline const QueryData* queryDataOf(const CollisionModel& m) {
  const QueryData* d = m.queryData.get();
  if (d && d->vertices == m.vertices.data() && d->edges == m.edges.data() &&
      d->polygonEdges == m.polygonEdges.data() && d->polygons == m.polygons.data() &&
      d->nodes == m.nodes.data() && d->polygonRefs == m.polygonRefs.data() &&
      d->numVertices == m.vertices.size() && d->numEdges == m.edges.size() &&
      d->numPolygonEdges == m.polygonEdges.size() && d->numPolygons == m.polygons.size() &&
      d->numNodes == m.nodes.size() && d->numPolygonRefs == m.polygonRefs.size())
    return d;
  return nullptr;
}

}  // namespace cmkit::detail
