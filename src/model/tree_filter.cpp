// Filtering loaded items into the stored tree: see tree_filter.h.
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

std::vector<SubtreeSplits> subtreeSplits(const ModelArrays& model) {
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

bool straddlesAllSplits(const SubtreeSplits& s, const Bounds& b) {
  for (int k = 0; k < 3; ++k) {
    if (s.lowest[std::size_t(k)] > s.highest[std::size_t(k)]) continue;  // no plane on this axis
    if (!(b.min[k] < s.lowest[std::size_t(k)])) return false;
    if (!(b.max[k] > s.highest[std::size_t(k)])) return false;
  }
  return true;
}

// A stored tree for filterIntoTree, with "inside all children" from the
// precomputed subtree splits (the same test as the walk of
// detail::insideAllChildren, without walking the subtree).
struct StoredTree {
  const ModelArrays& model;
  const std::vector<SubtreeSplits>& splits;
  bool isLeaf(std::int32_t n) const { return model.nodes[std::size_t(n)].isLeaf(); }
  int axis(std::int32_t n) const { return model.nodes[std::size_t(n)].planeType; }
  Real dist(std::int32_t n) const { return model.nodes[std::size_t(n)].planeDist; }
  std::int32_t child(std::int32_t n, int side) const { return model.nodes[std::size_t(n)].children[side]; }
  bool insideAllChildren(std::int32_t n, const Bounds& b) const {
    return straddlesAllSplits(splits[std::size_t(n)], b);
  }
};

// Builds the node ranges from (node, item) pairs given in item order; each
// node's list is in reverse item order (items were prepended).
void buildRanges(ModelArrays& model, const std::vector<std::pair<std::int32_t, std::int32_t>>& pairs,
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

void filterItemsIntoTree(ModelArrays& model) {
  if (model.nodes.empty()) {
    model.nodes.emplace_back();  // a single leaf
  }
  const std::vector<SubtreeSplits> splits = subtreeSplits(model);
  const StoredTree tree{model, splits};
  std::vector<std::int32_t> stack;
  std::vector<std::pair<std::int32_t, std::int32_t>> pairs;
  pairs.reserve(model.polygons.size() + model.polygons.size() / 2);
  for (std::size_t i = 0; i < model.polygons.size(); ++i) {
    const auto item = std::int32_t(i);
    filterIntoTree(tree, 0, model.polygons[i].bounds, stack,
                   [&](std::int32_t n) { pairs.emplace_back(n, item); });
  }
  buildRanges(model, pairs, model.polygonRefs, true);
  pairs.clear();
  for (std::size_t i = 0; i < model.brushes.size(); ++i) {
    const auto item = std::int32_t(i);
    filterIntoTree(tree, 0, model.brushes[i].bounds, stack,
                   [&](std::int32_t n) { pairs.emplace_back(n, item); });
  }
  buildRanges(model, pairs, model.brushRefs, false);
}

}  // namespace cmkit::detail
