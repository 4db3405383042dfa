// The growth of a model's axial BSP tree (the original's CM_FindSplitter,
// R_CreateAxialBSPTree and CM_R_InsideAllChildren), on arrays.
//
// The original keeps each node's items in its linked list and, after every
// split, tests every item of the split node and of all its ancestors with the
// full "inside all children" recursion over their subtrees, following list
// links all over memory. Here each node's items are an array of (bounds,
// item), cheap to scan, and the recursion is replaced by what it amounts to:
// every item of an interior node is inside all its children (the tree-filter
// rule puts it there only then, and every split re-checks the ancestors), so
// after a split an item of the split node or of an ancestor is still inside
// all children exactly when it straddles the new plane, and one that does not
// goes down the path to the split node, reaching every child off the path
// (it straddles all the planes there) and then the side of the new plane it
// lies on. The lists end as the original's do: same items, same order.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <ranges>

#include "compile/builder.h"
#include "util/assert.h"
#include "util/simd.h"

namespace cmkit::detail {

/// Per node, its polygons and brushes with their bounds in reverse list
/// order (the head last: prepending to a list is push_back).
struct ModelBuilder::GrowingLists {
  struct Item {
    Bounds bounds;
    int item = kNone;
  };
  using Lists = std::vector<std::vector<Item>>;
  Lists polygons;
  Lists brushes;
  /// pushItemsDown's path: the nodes below its node down to the split
  /// node, top down, and the child off the path at each node from its node
  /// down (above the split).
  std::vector<int> path, offPath;
  /// The nodes above the one splitNode is at, from the root down (the tree
  /// grows depth first: they are splitNode's callers).
  std::vector<int> ancestors;
  /// The places in `ancestors` of those that held items when they became
  /// ancestors, in the same order. Only these may hold items: an ancestor
  /// never gets any (splits give items to their new children, and
  /// pushItemsDown to nodes off the path, which are not above the split
  /// node), so the walks up the tree skip the others.
  std::vector<std::size_t> filledAncestors;
  std::vector<const std::vector<Item>*> sources;  ///< scratch of findSplitter
  std::vector<Item> stay, back;                   ///< scratch of splitItems
  /// Per node, compact for the walks up the tree: whether it may hold
  /// items (set when it gets one, updated when it loses some).
  std::vector<char> filled;
  Lists& of(ItemKind kind) { return kind == ItemKind::Polygon ? polygons : brushes; }
  void add(Lists& all, int node, const Item& it) {
    all[static_cast<std::size_t>(node)].push_back(it);
    filled[static_cast<std::size_t>(node)] = 1;
  }
  /// Room for the nodes of the builder's tree.
  void grow(const std::vector<BNode>& nodes) {
    polygons.resize(nodes.size());
    brushes.resize(nodes.size());
    filled.resize(nodes.size(), 0);
  }
};

namespace {

/// The tree-filter rule's "not entirely on one side" of an axial plane (an
/// item that straddles stays above it); false for bounds beyond or touching.
bool straddles(const Bounds& b, int axis, Real dist) {
  return !(b.min[axis] >= dist) && !(b.max[axis] <= dist);
}

/// t of a splitter candidate at `dist` in a node spanning lo..hi: how far
/// it is from the middle (twice that), as the original computes it.
inline Real splitterT(Real lo, Real hi, Real dist) { return std::fabs((hi - dist) - (dist - lo)); }

/// The original's search, one candidate at a time in list order (each list
/// from its head, the end of its array; an item's min before its max): the
/// first candidate strictly inside lo..hi with the least t below `size`.
template <class Item>
bool firstMostCentred(const std::vector<const std::vector<Item>*>& sources, int type, Real lo, Real hi,
                      Real size, Real& bestDist) {
  Real bestt = size;
  bestDist = 0;
  for (const std::vector<Item>* items : sources) {
    for (auto it = items->rbegin(); it != items->rend(); ++it) {
      for (const Real dist : {it->bounds.min[type], it->bounds.max[type]}) {
        const Real t = splitterT(lo, hi, dist);
        const bool better = (dist < hi) & (dist > lo) & (t < bestt);
        bestt = better ? t : bestt;
        bestDist = better ? dist : bestDist;
      }
    }
  }
  return bestt < size;
}

/// The splitter firstMostCentred finds. With float lanes, four items at a
/// time in any order: per lane the least t, the plane that gave it first and
/// whether another plane gave the same t; only the position in list order
/// tells apart two planes with the least t, so then (rarely) the search in
/// list order decides.
template <class Item>
bool mostCentredSplitter(const std::vector<const std::vector<Item>*>& sources, int type, Real lo, Real hi,
                         Real size, Real& bestDist) {
#ifdef CMKIT_FLOAT_LANES
  using simd::F4;
  const F4 loV = F4::all(lo), hiV = F4::all(hi), sizeV = F4::all(size);
  F4 best = sizeV, bestD = F4::zero(), tied = F4::zero();
  auto candidates = [&](F4 d) {
    const F4 t = simd::abs((hiV - d) - (d - loV));
    const F4 inside = (d < hiV) & (d > loV);
    const F4 less = inside & (t < best);
    const F4 same = inside & (t == best) & simd::differentBits(d, bestD) & (best < sizeV);
    tied = simd::andNot(less, tied | same);
    best = simd::select(less, t, best);
    bestD = simd::select(less, d, bestD);
  };
  // An item's bounds from coordinate `type` of min on: lane 0 is min[type],
  // lane 3 max[type] (the bounds are six floats; these 16 bytes lie within).
  static_assert(sizeof(Bounds) == 6 * sizeof(float));
  const std::size_t offset = static_cast<std::size_t>(type) * sizeof(float);
  auto row = [offset](const Item& item) {
    alignas(16) float f[4];
    std::memcpy(f, reinterpret_cast<const char*>(&item.bounds) + offset, sizeof f);
    return F4::load(f);
  };
  for (const std::vector<Item>* items : sources) {
    const Item* it = items->data();
    const std::size_t n = items->size();
    std::size_t k = 0;
    for (; k + 4 <= n; k += 4) {
      F4 mins = row(it[k]), r1 = row(it[k + 1]), r2 = row(it[k + 2]), maxs = row(it[k + 3]);
      simd::transpose(mins, r1, r2, maxs);
      candidates(mins);
      candidates(maxs);
    }
    for (; k < n; ++k) {  // the rest in lane 0 (lo in the others is never inside)
      candidates(F4::lanes(it[k].bounds.min[type], lo, lo, lo));
      candidates(F4::lanes(it[k].bounds.max[type], lo, lo, lo));
    }
  }
  const float least = simd::lowest(best);
  if (!(least < size)) {
    bestDist = 0;
    return false;
  }
  alignas(16) float bests[4], dists[4], ties[4];  // (ties: masks, 0 where clear)
  best.store(bests);
  bestD.store(dists);
  tied.store(ties);
  bool first = true;
  bool unique = true;
  for (int j = 0; j < 4; ++j) {
    if (bests[j] != least) continue;
    unique = unique && ties[j] == 0 &&
             (first || std::bit_cast<std::uint32_t>(dists[j]) == std::bit_cast<std::uint32_t>(bestDist));
    if (first) bestDist = dists[j];
    first = false;
  }
  if (unique) return true;
#endif
  return firstMostCentred(sources, type, lo, hi, size, bestDist);
}

}  // namespace

void ModelBuilder::createAxialBSPTree(const Bounds& bounds) {
  CMKIT_ASSERT(nodes_.size() == 1);
  GrowingLists lists;
  readLists(lists);
  splitNode(lists, 0, bounds);
  writeLists(lists);
}

void ModelBuilder::readLists(GrowingLists& lists) const {
  lists.grow(nodes_);
  for (int n = 0; n < static_cast<int>(nodes_.size()); ++n) {
    auto& polygons = lists.polygons[static_cast<std::size_t>(n)];
    for (const int p : polygonsAt(n)) polygons.push_back({polygon(p).bounds, p});
    std::reverse(polygons.begin(), polygons.end());
    auto& brushes = lists.brushes[static_cast<std::size_t>(n)];
    for (const int b : brushesAt(n)) brushes.push_back({brush(b).bounds, b});
    std::reverse(brushes.begin(), brushes.end());
    lists.filled[static_cast<std::size_t>(n)] = !polygons.empty() || !brushes.empty();
  }
}

void ModelBuilder::writeLists(const GrowingLists& lists) {
  // The references are made anew: only the lists' order matters.
  polygonRefs_.clear();
  brushRefs_.clear();
  freePolygonRef_ = kNone;
  for (int n = 0; n < static_cast<int>(nodes_.size()); ++n) {
    BNode& here = node(n);
    here.polygons = kNone;
    for (const auto& it : lists.polygons[static_cast<std::size_t>(n)]) {
      polygonRefs_.push_back({it.item, here.polygons});
      here.polygons = static_cast<int>(polygonRefs_.size()) - 1;
    }
    here.brushes = kNone;
    for (const auto& it : lists.brushes[static_cast<std::size_t>(n)]) {
      brushRefs_.push_back({it.item, here.brushes});
      here.brushes = static_cast<int>(brushRefs_.size()) - 1;
    }
  }
}

bool ModelBuilder::findSplitter(GrowingLists& lists, int nodeNum, const Bounds& bounds, int& planeType,
                                Real& planeDist) const {
  Real size[3];
  int axis[3];
  for (int i = 0; i < 3; ++i) {
    size[i] = bounds.max[i] - bounds.min[i];
    axis[i] = i;
  }
  // Largest axis first (the original's restarting bubble sort).
  for (int i = 0; i < 2; ++i) {
    if (size[i] < size[i + 1]) {
      std::swap(size[i], size[i + 1]);
      std::swap(axis[i], axis[i + 1]);
      i = -1;
    }
  }
  bool forceSplit = false;
  if (size[0] < tol::kMinNodeSize) {
    const std::size_t polyCount = lists.polygons[static_cast<std::size_t>(nodeNum)].size();
    if (polyCount > static_cast<std::size_t>(tol::kMaxNodePolygons)) forceSplit = true;
  }
  for (int i = 0; i < 3; ++i) {
    const int type = axis[i];
    if (!forceSplit && size[i] < tol::kMinNodeSize) break;
    if (i == 0) {
      // candidates from the brushes, then the polygons, of this node and its ancestors
      lists.sources.clear();
      for (const GrowingLists::Lists* all : {&lists.brushes, &lists.polygons}) {
        if (all == &lists.brushes && brushes_.empty()) continue;  // (a mesh: no brush lists to read)
        auto addSource = [&](int n) {
          if (!lists.filled[static_cast<std::size_t>(n)]) return;
          const auto& items = (*all)[static_cast<std::size_t>(n)];
          if (!items.empty()) lists.sources.push_back(&items);
        };
        addSource(nodeNum);
        for (auto a = lists.filledAncestors.rbegin(); a != lists.filledAncestors.rend(); ++a)
          addSource(lists.ancestors[*a]);
      }
    }
    // The most centred splitter (dhewm3: not truncated to an integer): the
    // first bounds plane strictly inside the node with the least t, each
    // list from its head (the end of its array).
    Real bestDist = 0;
    const bool found =
        mostCentredSplitter(lists.sources, type, bounds.min[type], bounds.max[type], size[i], bestDist);
    if (found) {
      planeType = type;
      planeDist = bestDist;
      if (forceSplit) return true;
      // not too close to the node bounds
      if (bounds.max[type] - planeDist > tol::kSplitterMinDistance &&
          planeDist - bounds.min[type] > tol::kSplitterMinDistance) {
        return true;
      }
    }
  }
  return false;
}

void ModelBuilder::splitNode(GrowingLists& lists, int nodeNum, const Bounds& bounds) {
  int planeType = kNone;
  Real planeDist = 0;
  if (!findSplitter(lists, nodeNum, bounds, planeType, planeDist)) {
    node(nodeNum).planeType = kNone;
    return;
  }
  const int frontNode = allocNode();
  node(frontNode).parent = nodeNum;
  const int backNode = allocNode();
  node(backNode).parent = nodeNum;
  lists.grow(nodes_);
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
  for (auto a = lists.filledAncestors.rbegin(); a != lists.filledAncestors.rend(); ++a) {
    const int ancestor = lists.ancestors[*a];
    if (!lists.filled[static_cast<std::size_t>(ancestor)]) continue;
    lists.path.assign(lists.ancestors.begin() + static_cast<std::ptrdiff_t>(*a + 1), lists.ancestors.end());
    lists.path.push_back(nodeNum);
    pushItemsDown(lists, ancestor, nodeNum);
  }
  const bool filled = lists.filled[static_cast<std::size_t>(nodeNum)] != 0;
  if (filled) lists.filledAncestors.push_back(lists.ancestors.size());
  lists.ancestors.push_back(nodeNum);
  splitNode(lists, frontNode, frontBounds);
  splitNode(lists, backNode, backBounds);
  lists.ancestors.pop_back();
  if (filled) lists.filledAncestors.pop_back();
}

void ModelBuilder::splitItems(GrowingLists& lists, int splitNum) {
  const BNode& split = node(splitNum);
  const int axis = split.planeType;
  const Real dist = split.planeDist;
  const auto front = static_cast<std::size_t>(split.children[0]);
  const auto back = static_cast<std::size_t>(split.children[1]);
  for (const ItemKind kind : {ItemKind::Polygon, ItemKind::Brush}) {
    GrowingLists::Lists& all = lists.of(kind);
    std::vector<GrowingLists::Item> items = std::move(all[static_cast<std::size_t>(splitNum)]);
    if (items.empty()) continue;
    // One pass without branches (which side an item is on is unpredictable):
    // every item written to all three places, kept by the count of its own.
    // The front items go to the start of the same array (never ahead of the
    // one read).
    const std::size_t n = items.size();
    if (lists.stay.size() < n) lists.stay.resize(n);
    if (lists.back.size() < n) lists.back.resize(n);
    std::size_t numStay = 0, numFront = 0, numBack = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const GrowingLists::Item& it = items[i];
      const bool inside = straddles(it.bounds, axis, dist);
      CMKIT_ASSERT(inside == detail::insideAllChildren(GrowingTree{nodes_}, splitNum, it.bounds));
      const bool inFront = !inside & (it.bounds.min[axis] >= dist);
      lists.stay[numStay] = it;
      lists.back[numBack] = it;
      items[numFront] = it;  // (last: may be the item itself)
      numStay += inside ? 1 : 0;
      numFront += inFront ? 1 : 0;
      numBack += (!inside & !inFront) ? 1 : 0;
    }
    // Each side prepends its items as the list is walked from its head (the
    // end of the array): in reverse array order.
    items.resize(numFront);
    std::reverse(items.begin(), items.end());
    lists.filled[front] = lists.filled[front] || numFront != 0;
    lists.filled[back] = lists.filled[back] || numBack != 0;
    all[front] = std::move(items);
    const auto backEnd = lists.back.begin() + static_cast<std::ptrdiff_t>(numBack);
    all[back].assign(std::make_reverse_iterator(backEnd), std::make_reverse_iterator(lists.back.begin()));
    all[static_cast<std::size_t>(splitNum)].assign(lists.stay.begin(),
                                                   lists.stay.begin() + static_cast<std::ptrdiff_t>(numStay));
  }
  lists.filled[static_cast<std::size_t>(splitNum)] =
      !lists.polygons[static_cast<std::size_t>(splitNum)].empty() ||
      !lists.brushes[static_cast<std::size_t>(splitNum)].empty();
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
    GrowingLists::Lists& all = lists.of(kind);
    if (!lists.filled[static_cast<std::size_t>(nodeNum)]) return;
    auto& here = all[static_cast<std::size_t>(nodeNum)];
    if (here.empty()) continue;
    // Room first: every item that leaves goes to each node off the path
    // and to one side of the split.
    std::size_t numLeaving = 0;
    std::size_t numFront = 0;
    for (const GrowingLists::Item& it : here) {
      const bool leaves = !straddles(it.bounds, axis, dist);
      numLeaving += leaves ? 1 : 0;
      numFront += leaves && it.bounds.min[axis] >= dist ? 1 : 0;
    }
    if (numLeaving == 0) continue;
    auto reserveMore = [&](int n, std::size_t count) {
      auto& items = all[static_cast<std::size_t>(n)];
      // (geometric growth: a node may get items from several ancestors)
      if (items.size() + count > items.capacity())
        items.reserve(std::max(items.size() + count, 2 * items.capacity()));
    };
    for (const int offPath : lists.offPath) reserveMore(offPath, numLeaving);
    reserveMore(split.children[0], numFront);
    reserveMore(split.children[1], numLeaving - numFront);
    // In list order, from the end of the array (the original filters each
    // item as it meets it); the items that stay keep their order.
    std::size_t kept = here.size();
    for (std::size_t i = here.size(); i-- > 0;) {
      const GrowingLists::Item& it = here[i];
      const bool inside = straddles(it.bounds, axis, dist);
      CMKIT_ASSERT(inside == detail::insideAllChildren(GrowingTree{nodes_}, nodeNum, it.bounds));
      if (inside) {
        here[--kept] = it;
        continue;
      }
      // Through each node above the split, the child off the path, then the
      // side of the split it lies on.
      for (const int offPath : lists.offPath) lists.add(all, offPath, it);
      const int side = it.bounds.min[axis] >= dist ? split.children[0] : split.children[1];
      lists.add(all, side, it);
      // the reference moves to one node; the others are new
      (kind == ItemKind::Polygon ? counters_.numPolygonRefs : counters_.numBrushRefs) +=
          static_cast<int>(lists.path.size());
    }
    here.erase(here.begin(), here.begin() + static_cast<std::ptrdiff_t>(kept));
  }
  lists.filled[static_cast<std::size_t>(nodeNum)] =
      !lists.polygons[static_cast<std::size_t>(nodeNum)].empty() ||
      !lists.brushes[static_cast<std::size_t>(nodeNum)].empty();
}

}  // namespace cmkit::detail
