// Internal: what the queries derive from a built model once instead of per
// query (made with the model by its constructor, makeQueryData):
//  - every polygonEdges entry with its edge's vertices and internal flag
//    (a polygon's are the entries firstEdge .. firstEdge + numEdges - 1,
//    one after another; the edges' lines are made from the vertices when a
//    polygon is tested);
//  - the bounds, normal and contents of every polygonRefs entry's polygon (a
//    node's polygons are the entries firstPolygonRef ..), for a
//    translation's culls, in blocks of kLanes entries with one array per
//    number, for SIMD loads;
//  - the BSP tree in 8 bytes a node for position tests and rotations' box
//    walks (point_tree.h);
//  - a grid of brush boxes for point contents (point_grid.h);
//  - the polygons' own hierarchy (polygon_bvh.h), which the translations
//    walk instead of the BSP tree.
// Block entry i is lane i % kLanes of block i / kLanes. The edge uses hold 16
// bytes per entry, the culls 40, in the order the queries read them.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "cmkit/model.h"

#include "model/point_grid.h"
#include "model/point_tree.h"
#include "model/polygon_bvh.h"
#include "model/query_blocks.h"

namespace cmkit::detail {

struct QueryData {
  /// Per polygonEdges entry: the entry with its edge's vertices and
  /// internal flag. One after another: a polygon's are one run of memory (a
  /// triangle's 48 bytes).
  std::vector<EdgeUse> edgeUses;
  /// Per polygonRefs entry: its polygon's culls (kCullBlocks builds; else empty).
  std::vector<CullBlock> culls;
  /// The polygons' hierarchy (kCullBlocks builds; else empty).
  PolygonBvh bvh;
  /// The BSP tree as position tests and rotations' box walks read it.
  PointTree pointTree;
  /// The brushes in a grid for point contents (models with a tree).
  PointGrid pointGrid;
};

/// The query data of arrays whose numbers are in range (a sealed model's).
std::shared_ptr<const QueryData> makeQueryData(const ModelArrays& m);

/// The model's query data (null only for ModelAccess::withoutQueryData's
/// copies, which tests use to compare the paths with and without it).
const QueryData* queryDataOf(const CollisionModel& m);

}  // namespace cmkit::detail
