// Filtering loaded items into the stored tree: see cm_tree.h.
#include "model/tree_filter.h"

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

namespace cmkit::detail {

namespace {

// For every node, per axis, the smallest and largest split distance of the
// interior nodes of its subtree with a plane on that axis. "Inside all
// children" of a node (every interior node of its subtree has the bounds
// strictly straddling its plane) is then: per axis that has planes,
// min < lowest and max > highest.
struct SubtreeSplits {
  std::array<Real, 3> lowest;
  std::array<Real, 3> highest;
};

std::vector<SubtreeSplits> subtreeSplits(const CollisionModel& model) {
  constexpr Real kNone = std::numeric_limits<Real>::infinity();
  std::vector<SubtreeSplits> splits(model.nodes.size(),
                                    SubtreeSplits{{kNone, kNone, kNone}, {-kNone, -kNone, -kNone}});
  // Pre-order storage: children come after their parent, so a reverse pass
  // sees every child before its parent.
  for (std::size_t i = model.nodes.size(); i-- > 0;) {
    const CmNode& node = model.nodes[i];
    if (node.isLeaf()) continue;
    SubtreeSplits& s = splits[i];
    const auto axis = std::size_t(node.planeType);
    s.lowest[axis] = node.planeDist;
    s.highest[axis] = node.planeDist;
    for (const std::int32_t child : node.children) {
      const SubtreeSplits& c = splits[std::size_t(child)];
      for (std::size_t k = 0; k < 3; ++k) {
        if (c.lowest[k] < s.lowest[k]) s.lowest[k] = c.lowest[k];
        if (c.highest[k] > s.highest[k]) s.highest[k] = c.highest[k];
      }
    }
  }
  return splits;
}

bool insideAllChildren(const SubtreeSplits& s, const Bounds& b) {
  for (int k = 0; k < 3; ++k) {
    if (s.lowest[std::size_t(k)] > s.highest[std::size_t(k)]) continue;  // no plane on this axis
    if (!(b.min[k] < s.lowest[std::size_t(k)])) return false;
    if (!(b.max[k] > s.highest[std::size_t(k)])) return false;
  }
  return true;
}

// Appends (node, item) for every node the item's bounds reach.
void filterBounds(const CollisionModel& model, const std::vector<SubtreeSplits>& splits, const Bounds& b,
                  std::int32_t item, std::vector<std::int32_t>& stack,
                  std::vector<std::pair<std::int32_t, std::int32_t>>& out) {
  stack.clear();
  stack.push_back(0);
  while (!stack.empty()) {
    std::int32_t n = stack.back();
    stack.pop_back();
    for (;;) {
      const CmNode& node = model.nodes[std::size_t(n)];
      if (node.isLeaf() || insideAllChildren(splits[std::size_t(n)], b)) {
        out.emplace_back(n, item);
        break;
      }
      if (b.min[node.planeType] >= node.planeDist) {
        n = node.children[0];
      } else if (b.max[node.planeType] <= node.planeDist) {
        n = node.children[1];
      } else {
        stack.push_back(node.children[1]);
        n = node.children[0];
      }
    }
  }
}

// Builds the node ranges from (node, item) pairs given in item order; each
// node's list is in reverse item order (items were prepended).
void buildRanges(CollisionModel& model, const std::vector<std::pair<std::int32_t, std::int32_t>>& pairs,
                 std::vector<std::int32_t>& refs, bool polygons) {
  const std::size_t numNodes = model.nodes.size();
  std::vector<std::uint32_t> count(numNodes, 0);
  for (const auto& [node, item] : pairs) ++count[std::size_t(node)];
  std::vector<std::uint32_t> next(numNodes, 0);
  std::uint32_t first = 0;
  for (std::size_t i = 0; i < numNodes; ++i) {
    CmNode& node = model.nodes[i];
    if (polygons) {
      node.firstPolygonRef = first;
      node.numPolygonRefs = count[i];
    } else {
      node.firstBrushRef = first;
      node.numBrushRefs = count[i];
    }
    next[i] = first;
    first += count[i];
  }
  refs.assign(pairs.size(), -1);
  for (std::size_t i = pairs.size(); i-- > 0;) refs[next[std::size_t(pairs[i].first)]++] = pairs[i].second;
}

}  // namespace

void filterItemsIntoTree(CollisionModel& model) {
  if (model.nodes.empty()) {
    model.nodes.emplace_back();  // a single leaf
  }
  const std::vector<SubtreeSplits> splits = subtreeSplits(model);
  std::vector<std::int32_t> stack;
  std::vector<std::pair<std::int32_t, std::int32_t>> pairs;
  pairs.reserve(model.polygons.size() + model.polygons.size() / 2);
  for (std::size_t i = 0; i < model.polygons.size(); ++i)
    filterBounds(model, splits, model.polygons[i].bounds, std::int32_t(i), stack, pairs);
  buildRanges(model, pairs, model.polygonRefs, true);
  pairs.clear();
  for (std::size_t i = 0; i < model.brushes.size(); ++i)
    filterBounds(model, splits, model.brushes[i].bounds, std::int32_t(i), stack, pairs);
  buildRanges(model, pairs, model.brushRefs, false);
}

}  // namespace cmkit::detail
