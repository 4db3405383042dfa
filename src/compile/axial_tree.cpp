// The growth of a model's axial BSP tree (the original's
// R_CreateAxialBSPTree and CM_R_InsideAllChildren), on arrays: the lists of
// growing_lists.h, each node's split plane from splitter.cpp.
//
// The original keeps each node's items in its linked list and, after every
// split, tests every item of the split node and of all its ancestors with the
// full "inside all children" recursion over their subtrees, following list
// links all over memory. Here each node's items are a run of (bounds, item)
// on one stack per kind (GrowingLists: no array per node, nothing allocated
// per split), cheap to scan, and the recursion is replaced by what it
// amounts to:
// every item of an interior node is inside all its children (the tree-filter
// rule puts it there only then, and every split re-checks the ancestors), so
// after a split an item of the split node or of an ancestor is still inside
// all children exactly when it straddles the new plane, and one that does not
// goes down the path to the split node, reaching every child off the path
// (it straddles all the planes there) and then the side of the new plane it
// lies on. The lists end as the original's do: same items, same order.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "compile/builder.h"
#include "compile/growing_lists.h"
#include "util/assert.h"

namespace cmkit::detail {

namespace {

/// Room reserved per polygon for the tree's polygon references, and per
/// item for its nodes (readLists).
constexpr std::size_t kRefsPerPolygonRoom = 3;
constexpr std::size_t kNodesPerItemRoom = 1;

/// The tree-filter rule's "not entirely on one side" of an axial plane (an
/// item that straddles stays above it); false for bounds beyond or touching.
bool straddles(const Bounds& b, int axis, Real dist) {
  return !(b.min[axis] >= dist) && !(b.max[axis] <= dist);
}

}  // namespace

void ModelBuilder::createAxialBSPTree(const Bounds& bounds) {
  CMKIT_ASSERT(nodes_.size() == 1);
  GrowingLists lists;
  readLists(lists);
  splitNode(lists, 0, bounds);
}

void ModelBuilder::readLists(GrowingLists& lists) {
  lists.grow(nodes_.size());
  auto read = [&](GrowingLists::Kind& kind, RefList items, auto&& boundsOf) {
    for (const int i : items) {
      CMKIT_ASSERT(i >= 0 && i < GrowingLists::kTurned);  // (the flags' bits are free)
      kind.stack.push_back({boundsOf(i), i});
    }
    std::reverse(kind.stack.begin(), kind.stack.end());
    // Pairs (see GrowingLists) of neighbours.
    std::vector<GrowingLists::Item>& stack = kind.stack;
    std::size_t out = 0;
    for (std::size_t i = 0; i < stack.size(); ++out) {
      const GrowingLists::Item& a = stack[i];
      if (i + 1 < stack.size()) {
        const GrowingLists::Item& b = stack[i + 1];
        const int p = std::min(a.item, b.item);
        if (std::abs(a.item - b.item) == 1 && p < GrowingLists::kMaxPaired &&
            std::memcmp(&a.bounds, &b.bounds, sizeof(Bounds)) == 0) {
          stack[out] = {a.bounds, p | GrowingLists::kPair | (a.item > b.item ? GrowingLists::kTurned : 0)};
          i += 2;
          continue;
        }
      }
      stack[out] = a;
      ++i;
    }
    stack.resize(out);
    kind.at[0] = {0, static_cast<std::uint32_t>(stack.size())};
  };
  read(lists.polygons, polygonsAt(0), [&](int p) { return polygon(p).bounds; });
  read(lists.brushes, brushesAt(0), [&](int b) { return brush(b).bounds; });
  // The references are made anew as the nodes are finished: only the lists'
  // order matters.
  polygonRefs_.clear();
  brushRefs_.clear();
  freePolygonRef_ = kNone;
  // Room from the start for what a tree of this many items usually makes:
  // the generated scene of cmkit_peers lists its polygons ~2.9 times each
  // (lt4's world 2.7) with about a node per polygon; grown by doubling,
  // these arrays were copied twice and their pages touched again. (Only
  // room: more than this still grows them.)
  const std::size_t numItems = polygons_.size() + brushes_.size();
  polygonRefs_.reserve(kRefsPerPolygonRoom * polygons_.size());
  nodes_.reserve(kNodesPerItemRoom * numItems);
  node(0).polygons = kNone;
  node(0).brushes = kNone;
}

void ModelBuilder::prependToList(GrowingLists& lists, ItemKind kind, int nodeNum, const Bounds& bounds,
                                 int item) {
  // (`item` as it lies in its list: its items are prepended from the end of
  // the array, in reverse order)
  const auto n = static_cast<std::size_t>(nodeNum);
  if (lists.done[n]) {
    GrowingLists::forEachItem(GrowingLists::turned(item), [&](int i) { linkToNode(kind, nodeNum, i); });
    return;
  }
  item = GrowingLists::turned(item);
  GrowingLists::Kind& k = lists.of(kind);
  int c = k.freeChained;
  if (c != kNone) {
    k.freeChained = k.chained[static_cast<std::size_t>(c)].next;
    k.chained[static_cast<std::size_t>(c)] = {{bounds, item}, k.prepended[n]};
  } else {
    c = static_cast<int>(k.chained.size());
    k.chained.push_back({{bounds, item}, k.prepended[n]});
  }
  k.prepended[n] = c;
}

void ModelBuilder::finishList(GrowingLists& lists, int nodeNum) {
  const auto n = static_cast<std::size_t>(nodeNum);
  // Each item linked as linkToNode links it, a list at a time: its
  // reference the next new one (none is free while the tree grows: readLists
  // cleared them), prepended to the node's list.
  CMKIT_ASSERT(freePolygonRef_ == kNone);
  for (const ItemKind kind : {ItemKind::Polygon, ItemKind::Brush}) {
    GrowingLists::Kind& k = lists.of(kind);
    const GrowingLists::Item* items = k.data(k.at[n]);
    std::vector<BRef>& refs = kind == ItemKind::Polygon ? polygonRefs_ : brushRefs_;
    int& head = kind == ItemKind::Polygon ? node(nodeNum).polygons : node(nodeNum).brushes;
    for (std::uint32_t i = 0; i < k.at[n].count; ++i) {
      GrowingLists::forEachItem(items[i].item, [&](int item) {
        refs.push_back({item, head});
        head = static_cast<int>(refs.size()) - 1;
      });
    }
    k.at[n].count = 0;
  }
  lists.done[n] = 1;
}

void ModelBuilder::splitNode(GrowingLists& lists, int nodeNum, const Bounds& bounds) {
  const auto n = static_cast<std::size_t>(nodeNum);
  // This node's lists on top of the stacks: what its parent's split gave it
  // (already there), then the items prepended since (the newest last).
  std::uint32_t slotStart[2];
  for (const ItemKind kind : {ItemKind::Polygon, ItemKind::Brush}) {
    GrowingLists::Kind& k = lists.of(kind);
    GrowingLists::Span& span = k.at[n];
    CMKIT_ASSERT(span.count == 0 || span.begin + span.count == k.stack.size());
    span.begin = static_cast<std::uint32_t>(k.stack.size()) - span.count;
    slotStart[kind == ItemKind::Polygon ? 0 : 1] = span.begin;
    std::size_t numPrepended = 0;
    for (int c = k.prepended[n]; c != kNone; c = k.chained[static_cast<std::size_t>(c)].next) ++numPrepended;
    if (numPrepended != 0) {
      std::size_t end = k.stack.size() + numPrepended;
      k.stack.resize(end);
      int last = kNone;
      for (int c = k.prepended[n]; c != kNone; c = k.chained[static_cast<std::size_t>(c)].next) {
        k.stack[--end] = k.chained[static_cast<std::size_t>(c)].it;
        last = c;
      }
      span.count += static_cast<std::uint32_t>(numPrepended);
      // the chain's entries are free again
      k.chained[static_cast<std::size_t>(last)].next = k.freeChained;
      k.freeChained = k.prepended[n];
      k.prepended[n] = kNone;
    }
  }
  auto popSlot = [&] {
    lists.polygons.stack.resize(slotStart[0]);
    lists.brushes.stack.resize(slotStart[1]);
  };
  int planeType = kNone;
  Real planeDist = 0;
  if (!findSplitter(lists, nodeNum, bounds, planeType, planeDist)) {
    node(nodeNum).planeType = kNone;
    finishList(lists, nodeNum);
    popSlot();
    return;
  }
  const int frontNode = allocNode();
  node(frontNode).parent = nodeNum;
  const int backNode = allocNode();
  node(backNode).parent = nodeNum;
  lists.grow(nodes_.size());
  counters_.numNodes += 2;
  Bounds frontBounds = bounds;
  frontBounds.min[planeType] = planeDist;
  Bounds backBounds = bounds;
  backBounds.max[planeType] = planeDist;
  BNode& split = node(nodeNum);
  split.planeType = planeType;
  split.planeDist = planeDist;
  split.children[0] = frontNode;
  split.children[1] = backNode;
  // The new split can leave items of this node and of every ancestor no
  // longer inside all children.
  splitItems(lists, nodeNum);
  // The nearest ancestor first.
  bool emptied = false;
  for (auto a = lists.filledAncestors.rbegin(); a != lists.filledAncestors.rend(); ++a) {
    const int ancestor = lists.ancestors[*a];
    CMKIT_ASSERT(lists.holdsItems(ancestor));
    lists.path.assign(lists.ancestors.begin() + static_cast<std::ptrdiff_t>(*a + 1), lists.ancestors.end());
    lists.path.push_back(nodeNum);
    pushItemsDown(lists, ancestor, nodeNum);
    emptied = emptied || !lists.holdsItems(ancestor);
  }
  if (emptied) {
    // (a loop, not std::erase_if with a lambda: Clang 14 leaves the source's
    // absolute path in one debug-info name of the lambda's std::ref, past the
    // prefix maps, and installed_tree rejects that)
    std::size_t kept = 0;
    for (const std::size_t a : lists.filledAncestors) {
      if (lists.holdsItems(lists.ancestors[a])) lists.filledAncestors[kept++] = a;
    }
    lists.filledAncestors.resize(kept);
  }
  // (dropped again below unless a split further down emptied it first)
  const std::size_t place = lists.ancestors.size();
  if (lists.holdsItems(nodeNum)) lists.filledAncestors.push_back(place);
  lists.ancestors.push_back(nodeNum);
  // (the front child's items are on top of the stacks, the back child's below)
  splitNode(lists, frontNode, frontBounds);
  splitNode(lists, backNode, backBounds);
  lists.ancestors.pop_back();
  if (!lists.filledAncestors.empty() && lists.filledAncestors.back() == place)
    lists.filledAncestors.pop_back();
  finishList(lists, nodeNum);
  popSlot();
}

void ModelBuilder::splitItems(GrowingLists& lists, int splitNum) {
  const BNode& split = node(splitNum);
  const int axis = split.planeType;
  const Real dist = split.planeDist;
  const auto front = static_cast<std::size_t>(split.children[0]);
  const auto back = static_cast<std::size_t>(split.children[1]);
  for (const ItemKind kind : {ItemKind::Polygon, ItemKind::Brush}) {
    GrowingLists::Kind& k = lists.of(kind);
    GrowingLists::Span& span = k.at[static_cast<std::size_t>(splitNum)];
    const std::size_t n = span.count;
    GrowingLists::Item* items = k.stack.data() + span.begin;
    // One pass, each item copied once, to its place found without branches
    // (which side an item is on is unpredictable): those that stay
    // compacted in place, in their order; the back child's and the front
    // child's to two halves of the scratch, each from its end down. Each
    // child prepends its items as the list is walked from its head (the end
    // of the array): they are in reverse array order. Then the children's
    // runs after those that stay: the back child's, and on top the front
    // child's (split first).
    if (k.copy.size() < 2 * n) k.copy.resize(2 * n);
    GrowingLists::Item* backs = k.copy.data();
    GrowingLists::Item* fronts = backs + n;
    std::size_t numStay = 0, backBegin = n, frontBegin = n;
    for (std::size_t i = 0; i < n; ++i) {
      const GrowingLists::Item it = items[i];
      const bool inside = straddles(it.bounds, axis, dist);
      CMKIT_ASSERT(inside == detail::insideAllChildren(GrowingTree{nodes_}, splitNum, it.bounds));
      const bool inFront = !inside & (it.bounds.min[axis] >= dist);
      backBegin -= (!inside & !inFront) ? 1 : 0;
      frontBegin -= inFront ? 1 : 0;
      GrowingLists::Item* to = inside ? items + numStay : inFront ? fronts + frontBegin : backs + backBegin;
      *to = it;
      to->item = inside ? it.item : GrowingLists::turned(it.item);
      numStay += inside ? 1 : 0;
    }
    const std::size_t numBack = n - backBegin, numFront = n - frontBegin;
    static_assert(std::is_trivially_copyable_v<GrowingLists::Item>);
    if (numBack != 0) std::memcpy(items + numStay, backs + backBegin, numBack * sizeof(GrowingLists::Item));
    if (numFront != 0)
      std::memcpy(items + numStay + numBack, fronts + frontBegin, numFront * sizeof(GrowingLists::Item));
    const auto stayEnd = static_cast<std::uint32_t>(span.begin + numStay);
    k.at[back] = {stayEnd, static_cast<std::uint32_t>(numBack)};
    k.at[front] = {static_cast<std::uint32_t>(stayEnd + numBack), static_cast<std::uint32_t>(numFront)};
    span.count = static_cast<std::uint32_t>(numStay);
  }
}

void ModelBuilder::pushItemsDown(GrowingLists& lists, int nodeNum, int splitNum) {
  const BNode& split = node(splitNum);
  const int axis = split.planeType;
  const Real dist = split.planeDist;
  // lists.path: the nodes below nodeNum down to the split node, top down.
  lists.offPath.clear();
  for (std::size_t k = 0, above = static_cast<std::size_t>(nodeNum); k < lists.path.size(); ++k) {
    const BNode& at = node(static_cast<int>(above));
    const int below = lists.path[k];
    lists.offPath.push_back(at.children[0] == below ? at.children[1] : at.children[0]);
    above = static_cast<std::size_t>(below);
  }
  for (const ItemKind kind : {ItemKind::Polygon, ItemKind::Brush}) {
    GrowingLists::Kind& k = lists.of(kind);
    GrowingLists::Span& span = k.at[static_cast<std::size_t>(nodeNum)];
    if (span.count == 0) continue;
    // In list order, from the end of the span (the original filters each
    // item as it meets it); the items that stay keep their order, at the
    // end of the span.
    GrowingLists::Item* here = k.stack.data() + span.begin;
    std::uint32_t kept = span.count;
    for (std::uint32_t i = span.count; i-- > 0;) {
      const GrowingLists::Item it = here[i];
      const bool inside = straddles(it.bounds, axis, dist);
      CMKIT_ASSERT(inside == detail::insideAllChildren(GrowingTree{nodes_}, nodeNum, it.bounds));
      if (inside) {
        here[--kept] = it;
        continue;
      }
      // Through each node above the split, the child off the path, then the
      // side of the split it lies on.
      for (const int offPath : lists.offPath) prependToList(lists, kind, offPath, it.bounds, it.item);
      const int side = it.bounds.min[axis] >= dist ? split.children[0] : split.children[1];
      prependToList(lists, kind, side, it.bounds, it.item);
      // the reference moves to one node; the others are new
      (kind == ItemKind::Polygon ? counters_.numPolygonRefs : counters_.numBrushRefs) +=
          static_cast<int>(lists.path.size() * GrowingLists::itemsOf(it.item));
    }
    span.begin += kept;
    span.count -= kept;
  }
}
}  // namespace cmkit::detail
