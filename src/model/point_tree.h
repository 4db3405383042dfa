// Internal: the BSP tree as position tests and rotations' box walks read it,
// made once with the model (query_data.h): 8 bytes a node, a node's two
// children side by side, the pairs in depth-first order (a walk down a
// subtree stays near its root's line), so that a walk reads a few cache
// lines instead of a node's 36 bytes each. (Point contents read the model's
// point grid instead, point_grid.h.)
#pragma once

#include <cstdint>
#include <vector>

#include "cmkit/model.h"

namespace cmkit::detail {

/// A node: its split (plane distance, axis) and children, or a leaf.
struct PointNode {
  Real dist;  ///< the split plane's coordinate (0 in a leaf)
  /// Bits 0-1: the split axis (kLeafAxis: a leaf); bit 2: the node lists
  /// brushes; bit 3: it lists polygons; bits 4-31: the
  /// front child's number (the back child's is the next).
  std::uint32_t word;

  static constexpr std::uint32_t kLeafAxis = 3;
  static constexpr std::uint32_t kHasBrushes = 4;
  static constexpr std::uint32_t kHasPolygons = 8;
  static constexpr int kFrontShift = 4;
  std::uint32_t axis() const { return word & 3u; }
  bool hasBrushes() const { return (word & kHasBrushes) != 0; }
  /// The node lists brushes or polygons (PointTree::modelNodes names it).
  bool hasItems() const { return (word & (kHasBrushes | kHasPolygons)) != 0; }
  std::uint32_t front() const { return word >> kFrontShift; }
};

struct PointTree {
  /// Node 0 is the root (none for a model without nodes).
  std::vector<PointNode> nodes;
  /// Per node: the model's node it is (read only where PointNode::hasItems:
  /// a position test tests that node's brushes and polygons).
  std::vector<std::uint32_t> modelNodes;
  bool empty() const { return nodes.empty(); }
};

/// Models with at most this many nodes are walked from their own nodes: a
/// small tree is in the cache either way, and fetching the point tree cost
/// more than it saved (measured when point contents still walked it: those
/// of the small reference maps take 10-60 ns).
constexpr std::size_t kPointTreeMinNodes = 256;

/// The point tree of a model's BSP tree (numbers in range, children below
/// 2^28; a tree with more nodes gets none: the walks then read the model's).
PointTree buildPointTree(const ModelArrays& m);

}  // namespace cmkit::detail
