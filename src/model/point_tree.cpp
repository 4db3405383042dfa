// The BSP tree as position tests and rotations' box walks read it (point_tree.h):
// buildPointTree.
#include "model/point_tree.h"

#include <utility>

#include "util/assert.h"

namespace cmkit::detail {

PointTree buildPointTree(const ModelArrays& m) {
  PointTree t;
  // Children numbers take 28 bits (the walk's node word).
  constexpr std::size_t kMaxNodes = std::size_t(1) << (32 - PointNode::kFrontShift);
  if (m.nodes.empty() || m.nodes.size() >= kMaxNodes) return t;
  // (A tree of n nodes takes n places, every inner node placing two
  // children; room for two more guards a malformed one.)
  t.nodes.resize(m.nodes.size() + 2);
  t.modelNodes.resize(m.nodes.size() + 2);
  // Depth first: a node's children get the next two free places when the
  // node is placed, and their subtrees follow (front first).
  std::vector<std::pair<std::int32_t, std::uint32_t>> pending;  // model node, its place
  pending.emplace_back(0, 0);
  std::uint32_t next = 1;
  while (!pending.empty()) {
    const auto [nodeNum, place] = pending.back();
    pending.pop_back();
    CMKIT_ASSERT(nodeNum >= 0 && std::size_t(nodeNum) < m.nodes.size() && place < t.nodes.size());
    const CmNode& n = m.nodes[std::size_t(nodeNum)];
    PointNode& out = t.nodes[place];
    t.modelNodes[place] = std::uint32_t(nodeNum);
    const std::uint32_t itemBits = (n.numBrushRefs != 0 ? PointNode::kHasBrushes : 0) |
                                   (n.numPolygonRefs != 0 ? PointNode::kHasPolygons : 0);
    if (n.isLeaf()) {
      out = {0, PointNode::kLeafAxis | itemBits};
      continue;
    }
    const std::uint32_t front = next;
    next += 2;
    if (next > t.nodes.size()) {  // more places than nodes: not a tree
      t = PointTree{};
      return t;
    }
    out = {n.planeDist, std::uint32_t(n.planeType) | itemBits | (front << PointNode::kFrontShift)};
    pending.emplace_back(n.children[1], front + 1);  // (popped after the front subtree)
    pending.emplace_back(n.children[0], front);
  }
  t.nodes.resize(next);
  t.modelNodes.resize(next);
  return t;
}

}  // namespace cmkit::detail
