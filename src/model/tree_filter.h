// Internal: the tree-filter rule (which nodes of an axial tree a polygon or
// brush is linked into), shared by the map compiler, which filters into its
// growing tree, and the .cm reader, which filters a loaded model's items into
// its stored tree (docs/cm-format.md, "How cmkit reads a model"). The two must agree: the order of
// polygons and brushes in .cm files comes from it.
#pragma once

#include <cstdint>
#include <vector>

#include "cmkit/model.h"

namespace cmkit::detail {

/// "Inside all children": every interior node of the subtree of `node` has
/// the bounds strictly on both sides of its plane (a leaf: true). The
/// straightforward walk, for a tree that is still growing.
/// Tree: isLeaf(n), axis(n), dist(n), child(n, side).
template <class Tree>
bool insideAllChildren(const Tree& tree, std::int32_t node, const Bounds& b) {
  if (tree.isLeaf(node)) return true;
  if (b.min[tree.axis(node)] >= tree.dist(node)) return false;
  if (b.max[tree.axis(node)] <= tree.dist(node)) return false;
  return insideAllChildren(tree, tree.child(node, 0), b) && insideAllChildren(tree, tree.child(node, 1), b);
}

/// The tree-filter rule: from `node`, an item with bounds b stays at a node
/// that is a leaf or that it is inside all children of; otherwise it goes to
/// the front child if b.min >= dist on the node's axis, to the back child if
/// b.max <= dist, else to both. Calls reached(n) for every node it stays at
/// (front side first). Each node is reached at most once, so where callers
/// prepend the item to the lists of these nodes, every list runs in reverse
/// filtering order whatever the order of the calls.
/// Tree: isLeaf(n), axis(n), dist(n), child(n, side), insideAllChildren(n, b);
/// `stack` is scratch (no recursion: loaded trees can be deep).
template <class Tree, class Reached>
void filterIntoTree(const Tree& tree, std::int32_t node, const Bounds& b, std::vector<std::int32_t>& stack,
                    Reached&& reached) {
  stack.clear();
  stack.push_back(node);
  while (!stack.empty()) {
    std::int32_t n = stack.back();
    stack.pop_back();
    for (;;) {
      if (tree.isLeaf(n) || tree.insideAllChildren(n, b)) {
        reached(n);
        break;
      }
      const int axis = tree.axis(n);
      if (b.min[axis] >= tree.dist(n)) {
        n = tree.child(n, 0);
      } else if (b.max[axis] <= tree.dist(n)) {
        n = tree.child(n, 1);
      } else {
        stack.push_back(tree.child(n, 1));
        n = tree.child(n, 0);
      }
    }
  }
}

/// Fills model.polygonRefs / model.brushRefs and every node's ranges: each
/// polygon, then each brush, in index order, is filtered into the tree by the
/// rule above and prepended to the list of every node it reaches, as the
/// original's loader does. So each node's list runs in reverse index order.
/// Requires a well-formed tree: nodes[0] the root, children after their
/// parent (pre-order), child indices in range.
void filterItemsIntoTree(ModelArrays& model);

}  // namespace cmkit::detail
