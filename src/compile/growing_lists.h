// The lists of items of a growing axial BSP tree (axial_tree.cpp grows the
// tree on them, splitter.cpp searches them for a node's split plane).
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "compile/builder.h"

namespace cmkit::detail {

/// The items of the nodes while the tree grows. The tree grows depth first,
/// so each kind's lists live on one stack of (bounds, item): the node being
/// split has its items on top; below lie, from the root down, the items that
/// stayed at each ancestor and the items of each back child still to be
/// split. A list is stored in reverse list order (the head last: prepending
/// is push_back). Items prepended to a node before it is split are chained
/// beside the stack until it is; a node whose subtree is finished has its
/// list written to the builder's references, and later items are prepended
/// there, as the original links them.
///
/// Two neighbours in a list with the same bounds (bit for bit) and item
/// numbers p and p + 1 (a two-sided polygon and its reversed copy, made one
/// after the other) meet every test alike and move together: every split
/// and every push down keeps them side by side. They are one entry here, a
/// pair, so each search and split reads it once. A list keeps or reverses
/// its items' order as they move: a pair's entry says which of the two
/// comes first in the array, and turns with it.
struct ModelBuilder::GrowingLists {
  /// `item`: an item number, or for a pair p | kPair, with kTurned when
  /// p + 1 comes first in the array.
  struct Item {
    Bounds bounds;
    int item = kNone;
  };
  static constexpr int kTurned = 1 << 29;
  static constexpr int kPair = 1 << 30;
  /// Pairs are made only of item numbers below this.
  static constexpr int kMaxPaired = kTurned - 1;
  /// How many items an entry stands for.
  static std::uint32_t itemsOf(int item) { return (item & kPair) != 0 ? 2 : 1; }
  /// The entry of an item or pair moved to a list in reverse order.
  static int turned(int item) { return item ^ ((item >> 1) & kTurned); }
  /// The entry's items in array order.
  template <class F>
  static void forEachItem(int item, F&& f) {
    if ((item & kPair) == 0) {
      f(item);
      return;
    }
    const int p = item & kMaxPaired;
    const bool turnedPair = (item & kTurned) != 0;
    f(turnedPair ? p + 1 : p);
    f(turnedPair ? p : p + 1);
  }
  /// A list on the stack.
  struct Span {
    std::uint32_t begin = 0;
    std::uint32_t count = 0;
  };
  struct Chained {
    Item it;
    int next = kNone;
  };
  struct Kind {
    std::vector<Item> stack;
    /// Per node: its list while it waits to be split or is an ancestor of
    /// the node being split (what stayed at it).
    std::vector<Span> at;
    /// Per node waiting to be split: the items prepended to it since its
    /// parent's split, newest first (chained in `chained`).
    std::vector<int> prepended;
    std::vector<Chained> chained;
    /// The entries of `chained` moved onto the stack, free to be used again
    /// (linked by `next`): a large model would otherwise grow `chained` by
    /// every item pushed down, reallocating and touching new pages.
    int freeChained = kNone;
    std::vector<Item> copy;  ///< scratch of splitItems
    const Item* data(const Span& s) const { return stack.data() + s.begin; }
  };
  Kind polygons;
  Kind brushes;
  /// Per node: whether its subtree is finished (its list in the references).
  std::vector<char> done;
  /// pushItemsDown's path: the nodes below its node down to the split
  /// node, top down, and the child off the path at each node from its node
  /// down (above the split).
  std::vector<int> path, offPath;
  /// The nodes above the one splitNode is at, from the root down (the tree
  /// grows depth first: they are splitNode's callers).
  std::vector<int> ancestors;
  /// The places in `ancestors` of those that hold items, in the same order.
  /// An ancestor never gets items (splits give items to their new children,
  /// and pushItemsDown to nodes off the path, which are not above the split
  /// node): one is listed when it becomes an ancestor holding items and
  /// dropped when pushItemsDown has taken its last, so the walks up the tree
  /// (two per split) skip the others. (Listed until the end of their
  /// subtrees, the generated scene of cmkit_peers had ~10 per split, nearly
  /// all empty: their items went down at later splits.)
  std::vector<std::size_t> filledAncestors;
  struct Source {
    const Item* items;
    std::size_t count;
  };
  std::vector<Source> sources;  ///< scratch of findSplitter
  Kind& of(ItemKind kind) { return kind == ItemKind::Polygon ? polygons : brushes; }
  bool holdsItems(int node) const {
    const auto n = static_cast<std::size_t>(node);
    return polygons.at[n].count != 0 || brushes.at[n].count != 0;
  }
  /// Room for (at least) the nodes of the builder's tree: doubled when
  /// short, not grown by the two nodes of every split (five arrays).
  void grow(std::size_t numNodes) {
    if (done.size() >= numNodes) return;
    const std::size_t size = std::max(numNodes, 2 * done.size());
    for (Kind* k : {&polygons, &brushes}) {
      k->at.resize(size);
      k->prepended.resize(size, kNone);
    }
    done.resize(size, 0);
  }
};

}  // namespace cmkit::detail
