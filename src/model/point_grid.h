// Internal: a uniform grid over the brushes of a model with a tree, for
// point contents (made once with the model, query_data.h). Each cell lists, as boxes, the
// brushes whose part seen by the BSP walk meets it: a brush stored at a node
// is seen by the points of that node's region (front: coordinate > split,
// back: <= split) within the brush's bounds, so each (node, brush) pair is
// one box, its bounds cut to the node's region. A point then tests its one
// cell's boxes instead of walking about 20 levels of the tree, each level's
// way a guess the processor often gets wrong; the boxes it meets are exactly
// those the walk meets (the same brushes, the same answers).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "cmkit/model.h"

namespace cmkit::detail {

/// A brush as a cell lists it: the bounds of the part of it the BSP walk
/// sees from one node (below), which decide whether its planes are read, its
/// contents and its number in the model. 32 bytes in float builds.
struct PointBrushBox {
  Bounds bounds;
  std::uint32_t contents = 0;
  std::uint32_t brush = 0;
};

struct PointGrid {
  /// The grid's extent: the union of its boxes (a point outside meets none).
  Bounds bounds;
  /// Cells per unit along each axis.
  Vec3 scale;
  /// Cells along each axis.
  std::uint32_t dims[3] = {0, 0, 0};
  /// Per cell (x fastest, then y, then z), its first box; one more entry at
  /// the end (the last cell's end).
  std::vector<std::uint32_t> firstBox;
  /// The cells' boxes, cell by cell.
  std::vector<PointBrushBox> boxes;
  bool empty() const { return firstBox.empty(); }

  /// The cell column of a coordinate within the grid's bounds on `axis`
  /// (monotonic in the coordinate: a box's min and max cells enclose the
  /// cell of every point in it).
  std::uint32_t cellOf(Real c, int axis) const {
    const auto i = std::uint32_t((c - bounds.min[axis]) * scale[axis]);
    return i < dims[axis] ? i : dims[axis] - 1;
  }
  /// The cell of (x, y, z) cell columns.
  std::size_t cell(std::uint32_t x, std::uint32_t y, std::uint32_t z) const {
    return (std::size_t(z) * dims[1] + y) * dims[0] + x;
  }
  /// The cell of a point within the grid's bounds.
  std::size_t cellOf(const Vec3& p) const { return cell(cellOf(p.x, 0), cellOf(p.y, 1), cellOf(p.z, 2)); }
};

/// The point grid of a model with brushes and a tree (a model of one leaf
/// has its brushes' list: point contents read that); empty for the others,
/// for a tree that is not one, and where the boxes are so much larger than
/// the cells that even a coarser grid lists them too often (point contents
/// walk the model's nodes then).
PointGrid buildPointGrid(const ModelArrays& m);

}  // namespace cmkit::detail
