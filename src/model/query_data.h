// Internal: what the queries derive from a built model once instead of per
// query (CollisionModel::queryData, made by prepareQueries): the lines of
// every polygon's edges, four edges to a block in the order the translation
// tests read them (one array per Plücker coordinate within a block, for SIMD
// loads), and every node's polygons with what a translation's culls read,
// four polygons to a block (one array per number).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "cmkit/model.h"

namespace cmkit::detail {

/// Edges per line block.
inline constexpr std::size_t kLineBlock = 4;
/// Numbers per line block: coordinate k of the block's edge j is at k * kLineBlock + j.
inline constexpr std::size_t kLineBlockSize = 6 * kLineBlock;
/// Line blocks a polygon of numEdges edges takes.
inline constexpr std::size_t lineBlocks(std::size_t numEdges) {
  return (numEdges + kLineBlock - 1) / kLineBlock;
}

/// Writes the lines of a polygon's edges (each in its edge's stored
/// direction, Pluecker::fromLine of vertex[0] -> vertex[1]) into
/// lineBlocks(edges.size()) blocks at `out`; the lanes past the last edge are 0.
void writeEdgeLineBlocks(const CollisionModel& m, std::span<const std::int32_t> edges, Real* out);

/// Line j of a polygon whose blocks start at `blocks`.
inline Pluecker blockLine(const Real* blocks, std::size_t j) {
  const Real* b = blocks + (j / kLineBlock) * kLineBlockSize + j % kLineBlock;
  Pluecker l;
  for (std::size_t k = 0; k < 6; ++k) l.p[k] = b[k * kLineBlock];
  return l;
}

/// Polygons per cull block.
inline constexpr std::size_t kCullBlock = 4;

/// kCullBlock polygons of a node's list, in list order, with what a
/// translation's culls read of them: lane j of each array is polygon j.
/// Lanes past the end of the list have contents 0 (no content mask keeps them)
/// and polygon number -1.
struct alignas(16) PolygonCullBlock {
  Real min[3][kCullBlock];     ///< bounds.min, per axis
  Real max[3][kCullBlock];     ///< bounds.max, per axis
  Real normal[3][kCullBlock];  ///< plane.normal, per axis
  std::uint32_t contents[kCullBlock];
  std::int32_t polygon[kCullBlock];  ///< polygon numbers
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
  /// Per polygon: the index in `lines` of its first block.
  std::vector<std::size_t> firstLine;
  /// The line blocks of every polygon, in polygon order.
  std::vector<Real> lines;

  /// Per node and one past the last: the index in `cullBlocks` of its first block.
  std::vector<std::size_t> firstCullBlock;
  /// The cull blocks of every node, in node order.
  std::vector<PolygonCullBlock> cullBlocks;

  /// The blocks of polygon p.
  const Real* polygonLines(std::size_t p) const { return lines.data() + firstLine[p]; }
  /// The cull blocks of node n.
  std::span<const PolygonCullBlock> nodeCullBlocks(std::size_t n) const {
    return {cullBlocks.data() + firstCullBlock[n], firstCullBlock[n + 1] - firstCullBlock[n]};
  }
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
