// The polygons' hierarchy (polygon_bvh.h): buildPolygonBvh.
#include "model/polygon_bvh.h"

#include <algorithm>
#include <array>
#include <bit>
#include <limits>
#include <numeric>

#include "model/twins.h"
#include "util/assert.h"
#include "util/simd.h"

namespace cmkit::detail {

namespace {

/// Bins per split search (binned surface-area heuristic): enough to find
/// good planes, few enough that a split costs one pass over the set.
constexpr int kBins = 12;
/// From this many items a split fills two sets of bins side by side (see
/// Builder::fillBins); below it, making and folding the second set costs
/// more than it saves.
constexpr std::size_t kTwoBinSetsMin = 128;
/// Below this depth splits search planes; past it (a chain of lopsided
/// splits) they halve the set by count, which bounds the depth.
constexpr std::size_t kMaxCostDepth = 40;

/// A polygon while the hierarchy is made (32 bytes: the builder's passes
/// over a large model's items are bound by memory). Its box's corners each
/// begin four floats, loaded as lanes (the fourth, contents or polygon, is
/// never used as a float).
struct Item {
  float min[3];
  std::uint32_t contents;
  float max[3];
  std::int32_t polygon;
  /// The centre of the box along axis k.
  float centre(std::size_t k) const { return (min[k] + max[k]) * 0.5f; }
};

/// Bounds of item boxes or of their centres (lanes 0 to 2; the fourth
/// is never read). Adding keeps the first of equal values, as std::min and
/// std::max do.
struct Box {
  alignas(16) float min[4] = {std::numeric_limits<float>::max(), std::numeric_limits<float>::max(),
                              std::numeric_limits<float>::max(), 0};
  alignas(16) float max[4] = {-std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(),
                              -std::numeric_limits<float>::max(), 0};
#ifdef CMKIT_SIMD_SSE2
  // simd::min(next, held) is next only where next < held: std::min(held, next).
  void add(simd::F4 lo, simd::F4 hi) {
    simd::min(lo, simd::F4::load(min)).store(min);
    simd::max(hi, simd::F4::load(max)).store(max);
  }
  void add(const Box& b) { add(simd::F4::load(b.min), simd::F4::load(b.max)); }
  /// An item's corners with 0 in the fourth lane (its integer there, read
  /// as a float, would often be denormal: slow in arithmetic).
  static simd::F4 corner(const float* p) {
    const simd::F4 xyz = simd::F4::lanes(1, 1, 1, 0) == simd::F4::all(1);
    return simd::F4::loadUnaligned(p) & xyz;
  }
  void addBox(const Item& it) { add(corner(it.min), corner(it.max)); }
  void addCentre(const Item& it) {
    const simd::F4 c = (corner(it.min) + corner(it.max)) * simd::F4::all(0.5f);
    add(c, c);
  }
#else
  void add(const float* lo, const float* hi) {
    for (int k = 0; k < 3; ++k) {
      min[k] = std::min(min[k], lo[k]);
      max[k] = std::max(max[k], hi[k]);
    }
  }
  void add(const Box& b) { add(b.min, b.max); }
  void addBox(const Item& it) { add(it.min, it.max); }
  void addCentre(const Item& it) {
    const float c[3] = {it.centre(0), it.centre(1), it.centre(2)};
    add(c, c);
  }
#endif
  bool valid() const { return min[0] <= max[0]; }
  /// Half the surface area (the cost heuristic's weight).
  float halfArea() const {
    if (!valid()) return 0;
    const float x = max[0] - min[0], y = max[1] - min[1], z = max[2] - min[2];
    return x * y + y * z + z * x;
  }
};

/// What a node needs of a range of items, gathered while they are binned:
/// their boxes' bounds and contents (the node's lanes) and their centres'
/// bounds (the range's next split).
struct Summary {
  Box box;
  Box centres;
  std::uint32_t contents = 0;
  void add(const Item& it) {
    box.addBox(it);
    centres.addCentre(it);
    contents |= it.contents;
  }
  void add(const Summary& s) {
    box.add(s.box);
    centres.add(s.centres);
    contents |= s.contents;
  }
  /// True when a bound is 0: folded in another order its sign (0 or -0)
  /// could differ (std::min keeps the first of equal values; any other
  /// equal values have the same bits).
  bool hasZero() const {
    for (const Box* b : {&box, &centres}) {
      for (int k = 0; k < 3; ++k)
        if (b->min[k] == 0 || b->max[k] == 0) return true;
    }
    return false;
  }
};

class Builder {
 public:
  Builder(const ModelArrays& m, PolygonBvh& out) : m_(m), out_(out) {
    // (A leaf holds a polygon's edge count in 16 bits: a model with a longer
    // polygon, which no map or mesh has, gets no hierarchy. The corners need
    // each polygon's edges to close a loop, which every sealed model's do:
    // CollisionModel::create refuses others, structureViolations.)
    fits_ = m.edges.size() < (std::size_t(1) << 30) &&  // (PolygonCorner's 2 * entry)
            std::all_of(m.polygons.begin(), m.polygons.end(), [&](const CmPolygon& p) {
              CMKIT_ASSERT(m.brokenEdgeLoopAt(p) < 0);
              return p.numEdges <= std::numeric_limits<std::uint16_t>::max();
            });
    if (!fits_) return;
    // A polygon and its reversed twin of the same bounds are one item (the
    // lower number's), the twin held beside it in the leaf.
    std::vector<std::uint32_t> all(m.polygons.size());
    std::iota(all.begin(), all.end(), 0u);
    // (Polygon numbers below BvhLeaf::kHasTwin: always, in practice.)
    twin_ = m.polygons.size() < std::size_t(BvhLeaf::kHasTwin) ? findTwins(m, all)
                                                               : std::vector<std::int32_t>(all.size(), -1);
    for (std::size_t i = 0; i < twin_.size(); ++i)
      if (twin_[i] >= 0 && !sameBounds(m.polygons[i].bounds, m.polygons[std::size_t(twin_[i])].bounds))
        twin_[i] = -1;  // (then its twin's entry is cleared too: the test is symmetric)
    items_.reserve(m.polygons.size());
    planes_.reserve(m.polygons.size());
    polygonUses_.reserve(m.polygons.size());
    for (std::size_t i = 0; i < m.polygons.size(); ++i) {
      const CmPolygon& p = m.polygons[i];
      planes_.push_back(p.plane);  // (by polygon number: a twin's too)
      polygonUses_.push_back({p.material, p.firstEdge, p.numEdges});
      if (twin_[i] >= 0 && std::size_t(twin_[i]) < i) continue;  // in its twin's item
      Item item;
      for (int k = 0; k < 3; ++k) {
        item.min[k] = float(p.bounds.min[k]);
        item.max[k] = float(p.bounds.max[k]);
      }
      item.polygon = std::int32_t(i);
      item.contents = p.contents;
      items_.push_back(item);
    }
  }

  void build(std::span<const EdgeUse> uses) {
    if (!fits_ || items_.empty()) return;
    out_.nodes.reserve(items_.size() / 2 + 1);
    out_.leaves.reserve(items_.size() / 2 + 1);
    const Range all{0, items_.size()};
    (void)node(all, summaryOf(all), 1);
    addPlanes();
    addUses(uses);
  }

 private:
  struct Range {
    std::size_t first, end;
    std::size_t size() const { return end - first; }
  };

  /// The summary of r's items, folded in their order.
  Summary summaryOf(Range r) const {
    Summary sum;
    for (std::size_t i = r.first; i < r.end; ++i) sum.add(items_[i]);
    return sum;
  }

  /// Bins r's items by binOf: each bin's summary and count. With two sets,
  /// neighbouring items (which mostly fall in the same bin) go to different
  /// sets, halving the chains of updates to one bin in memory; the sets are
  /// folded after. (Bounds and counts are the same in any order.)
  template <std::size_t Sets, class BinOf>
  void fillBins(Range r, const BinOf& binOf, std::array<Summary, kBins>& bins,
                std::array<std::size_t, kBins>& counts) const {
    std::array<std::array<Summary, kBins>, Sets - 1> more;
    std::array<std::array<std::uint32_t, kBins>, Sets> countSets{};
    for (std::size_t i = r.first; i < r.end; ++i) {
      const std::size_t set = i % Sets;
      const auto b = std::size_t(binOf(items_[i]));
      if constexpr (Sets == 1)
        bins[b].add(items_[i]);
      else
        (set == 0 ? bins : more[set - 1])[b].add(items_[i]);
      ++countSets[set][b];
    }
    for (std::size_t b = 0; b < std::size_t(kBins); ++b) {
      for (std::size_t set = 1; set < Sets; ++set) bins[b].add(more[set - 1][b]);
      for (std::size_t set = 0; set < Sets; ++set) counts[b] += countSets[set][b];
    }
  }

  /// Splits r (summary `sum`) in two non-empty ranges (r.size() > 1):
  /// returns where the second starts, with the summaries of both.
  std::size_t split(Range r, const Summary& sum, std::size_t depth, Summary& left, Summary& right) {
    const Box& centres = sum.centres;
    int axis = 0;
    for (int k = 1; k < 3; ++k)
      if (centres.max[k] - centres.min[k] > centres.max[axis] - centres.min[axis]) axis = k;
    const float lo = centres.min[std::size_t(axis)], extent = centres.max[std::size_t(axis)] - lo;
    if (extent > 0 && depth < kMaxCostDepth) {
      const float scale = float(kBins) / extent;
      auto binOf = [&](const Item& it) {
        return std::min(kBins - 1, int((it.centre(std::size_t(axis)) - lo) * scale));
      };
      // Each bin gathers what the two sides' summaries need.
      std::array<Summary, kBins> bins;
      std::array<std::size_t, kBins> counts{};
      if (r.size() >= kTwoBinSetsMin)
        fillBins<2>(r, binOf, bins, counts);
      else
        fillBins<1>(r, binOf, bins, counts);
      // Cost of splitting after bin s: area(left) * count(left) + area(right) * count(right).
      std::array<float, kBins> rightCost{};
      Box rightBox;
      std::size_t rightCount = 0;
      for (int s = kBins - 1; s > 0; --s) {
        rightBox.add(bins[std::size_t(s)].box);
        rightCount += counts[std::size_t(s)];
        rightCost[std::size_t(s)] = rightBox.halfArea() * float(rightCount);
      }
      Box leftBox;
      std::size_t leftCount = 0;
      int best = -1;
      float bestCost = std::numeric_limits<float>::max();
      for (int s = 0; s + 1 < kBins; ++s) {
        leftBox.add(bins[std::size_t(s)].box);
        leftCount += counts[std::size_t(s)];
        if (leftCount == 0 || leftCount == r.size()) continue;
        const float cost = leftBox.halfArea() * float(leftCount) + rightCost[std::size_t(s + 1)];
        if (cost < bestCost) {
          bestCost = cost;
          best = s;
        }
      }
      if (best >= 0) {
        const auto mid =
            std::partition(items_.begin() + std::ptrdiff_t(r.first), items_.begin() + std::ptrdiff_t(r.end),
                           [&](const Item& it) { return binOf(it) <= best; });
        const std::size_t m = std::size_t(mid - items_.begin());
        left = Summary{};
        right = Summary{};
        for (int s = 0; s < kBins; ++s) (s <= best ? left : right).add(bins[std::size_t(s)]);
        // (a bound of 0 folded in the items' order, as before bins)
        if (left.hasZero()) left = summaryOf({r.first, m});
        if (right.hasZero()) right = summaryOf({m, r.end});
        return m;
      }
    }
    // All centres at one place (or too deep): halve by count, in polygon order along the axis.
    const std::size_t mid = r.first + r.size() / 2;
    std::nth_element(items_.begin() + std::ptrdiff_t(r.first), items_.begin() + std::ptrdiff_t(mid),
                     items_.begin() + std::ptrdiff_t(r.end), [&](const Item& a, const Item& b) {
                       const float ca = a.centre(std::size_t(axis)), cb = b.centre(std::size_t(axis));
                       return ca < cb || (ca == cb && a.polygon < b.polygon);
                     });
    left = summaryOf({r.first, mid});
    right = summaryOf({mid, r.end});
    return mid;
  }

  /// A leaf of the (up to kLanes) items of r: its number.
  std::size_t leaf(Range r) {
    CMKIT_ASSERT(r.size() >= 1 && r.size() <= kLanes);
    // Within a leaf, in polygon order.
    std::sort(items_.begin() + std::ptrdiff_t(r.first), items_.begin() + std::ptrdiff_t(r.end),
              [](const Item& a, const Item& b) { return a.polygon < b.polygon; });
    const std::size_t number = out_.leaves.size();
    BvhLeaf& b = out_.leaves.emplace_back();
    for (std::size_t j = 0; j < kLanes; ++j) {
      const bool used = j < r.size();
      const std::int32_t polyNum = used ? items_[r.first + j].polygon : -1;
      const std::int32_t twin = used ? twin_[std::size_t(polyNum)] : -1;
      b.polygon[j] = twin >= 0 ? polyNum | BvhLeaf::kHasTwin : polyNum;
      b.twin[j] = twin;
      b.material[j] = b.twinMaterial[j] = -1;  // (addUses)
      b.numEdges[j] = 0;
      if (!used) {
        for (int k = 0; k < 3; ++k) {
          b.min[k][j] = std::numeric_limits<float>::max();
          b.max[k][j] = -std::numeric_limits<float>::max();
          b.normal[k][j] = 0;
        }
        b.dist[j] = 0;
        b.contents[j] = 0;
        continue;
      }
      // (the item's bounds and contents are the polygon's: Real is float in
      // the builds that make the hierarchy)
      static_assert(!kCullBlocks || sizeof(Real) == sizeof(float));
      const Item& it = items_[r.first + j];
      for (std::size_t k = 0; k < 3; ++k) {
        b.min[k][j] = it.min[k];
        b.max[k][j] = it.max[k];
      }
      b.contents[j] = it.contents;  // (the plane: addPlanes)
    }
    return number;
  }

  /// The leaves' planes, after the hierarchy: the leaves hold the items in
  /// their final order, lane by lane, so each plane can be fetched some items
  /// ahead (read by polygon number while each leaf was made, every read
  /// waited for memory).
  void addPlanes() {
    constexpr std::size_t kFetchAhead = 32;
    std::size_t i = 0;  // (items_[i]: the item in the lane being filled)
    for (BvhLeaf& b : out_.leaves) {
      for (std::size_t j = 0; j < kLanes; ++j) {
        if (b.polygon[j] < 0) continue;  // unused (its plane was cleared)
        if (i + kFetchAhead < items_.size())
          __builtin_prefetch(&planes_[std::size_t(items_[i + kFetchAhead].polygon)]);
        const Plane& plane = planes_[std::size_t(items_[i].polygon)];
        for (std::size_t k = 0; k < 3; ++k) b.normal[k][j] = plane.normal[int(k)];
        b.dist[j] = plane.dist;
        ++i;
      }
    }
    CMKIT_ASSERT(i == items_.size());
  }

  /// BvhLeaf::twinStart of a polygon's twin (edge lists `a` and `b`): where
  /// the builders' reversed copy starts (model/twins.h, reversedFrom), for at
  /// most BvhLeaf::kMaxMadeTwinEdges edges; else kStoredTwin (isTwin also
  /// pairs the same edges in another order, whose corners are stored).
  static std::uint8_t twinStart(std::span<const std::int32_t> a, std::span<const std::int32_t> b) {
    static_assert(BvhLeaf::kMaxMadeTwinEdges < BvhLeaf::kStoredTwin);
    const std::ptrdiff_t s = a.size() <= BvhLeaf::kMaxMadeTwinEdges ? reversedFrom(a, b) : -1;
    return s < 0 ? BvhLeaf::kStoredTwin : std::uint8_t(s);
  }

  /// The leaves' materials, edge counts and edge uses (copied from the
  /// model's, `uses`, in the leaves' order; a twin's only where they are
  /// not made from its polygon's, BvhLeaf::twinStart), after the hierarchy,
  /// each polygon's fetched some lanes ahead as in addPlanes.
  void addUses(std::span<const EdgeUse> uses) {
    constexpr std::size_t kFetchAhead = 16;
    std::vector<std::int32_t> order;  // the polygons in the order their uses are copied
    order.reserve(items_.size() * 2);
    std::size_t total = 0;
    for (BvhLeaf& b : out_.leaves) {
      b.firstUse = std::uint32_t(total);
      for (std::size_t j = 0; j < kLanes; ++j) {
        b.twinStart[j] = 0;  // (no twin, or its corners made: none stored)
        if (b.polygon[j] < 0) continue;
        const PolygonUses& e = polygonUses_[std::size_t(b.polygonAt(j))];
        b.numEdges[j] = std::uint16_t(e.numEdges);
        b.material[j] = e.material;
        order.push_back(b.polygonAt(j));
        total += BvhLeaf::usesStride(e.numEdges);
        if (b.twin[j] < 0) continue;
        const PolygonUses& t = polygonUses_[std::size_t(b.twin[j])];
        b.twinMaterial[j] = t.material;
        b.twinStart[j] = twinStart(std::span(m_.polygonEdges).subspan(e.firstEdge, e.numEdges),
                                   std::span(m_.polygonEdges).subspan(t.firstEdge, t.numEdges));
        if (b.twinMade(j)) continue;
        order.push_back(b.twin[j]);
        total += BvhLeaf::usesStride(e.numEdges);  // (a twin's edges are its polygon's: model/twins.h)
      }
    }
    out_.uses.resize(total);  // (the entries past a polygon's, up to a line's end, stay zero)
    std::size_t at = 0;
    for (std::size_t i = 0; i < order.size(); ++i) {
      if (i + kFetchAhead < order.size())
        __builtin_prefetch(uses.data() + polygonUses_[std::size_t(order[i + kFetchAhead])].firstEdge);
      const PolygonUses& e = polygonUses_[std::size_t(order[i])];
      for (std::size_t k = 0; k < e.numEdges; ++k) {
        const EdgeUse& u = uses[e.firstEdge + k];
        PolygonCorner& c = out_.uses[at + k];
        c.entry = PolygonCorner::encode(u.edgeNum, u.internal != 0);
        c.p = m_.vertices[std::size_t(u.start())];
      }
      at += BvhLeaf::usesStride(e.numEdges);
    }
    CMKIT_ASSERT(at == total && total <= std::numeric_limits<std::uint32_t>::max());
  }

  /// An inner node of the items of r (more than kLanes; summary `sum`): its number.
  std::size_t node(Range r, const Summary& sum, std::size_t depth) {
    out_.depth = std::max(out_.depth, depth);
    // Up to kLanes children: split the largest child until there are
    // kLanes or every child fits a leaf.
    struct Child {
      Range range;
      Summary sum;
    };
    std::array<Child, kLanes> children{};
    std::size_t numChildren = 1;
    children[0] = {r, sum};
    while (numChildren < kLanes) {
      std::size_t widest = kLanes;
      for (std::size_t c = 0; c < numChildren; ++c)
        if (children[c].range.size() > kLanes &&
            (widest == kLanes || children[c].range.size() > children[widest].range.size()))
          widest = c;
      if (widest == kLanes) break;
      const Child whole = children[widest];
      Summary left, right;
      const std::size_t mid = split(whole.range, whole.sum, depth, left, right);
      children[widest] = {{whole.range.first, mid}, left};
      children[numChildren++] = {{mid, whole.range.end}, right};
    }
    // Children in the order of their items (the near-far order is the walk's).
    std::sort(children.begin(), children.begin() + std::ptrdiff_t(numChildren),
              [](const Child& a, const Child& b) { return a.range.first < b.range.first; });
    const std::size_t number = out_.nodes.size();
    out_.nodes.emplace_back();
    for (std::size_t j = 0; j < kLanes; ++j) {
      Box box;
      std::int32_t child = 0;
      std::uint32_t contents = 0;
      if (j < numChildren) {
        const Child& c = children[j];
        box = c.sum.box;
        contents = c.sum.contents;
        child = c.range.size() <= kLanes ? ~std::int32_t(leaf(c.range))
                                         : std::int32_t(node(c.range, c.sum, depth + 1));
      }
      BvhNode& n = out_.nodes[number];  // (node() may have moved the array)
      for (std::size_t k = 0; k < 3; ++k) {
        n.min[k][j] = box.min[k];
        n.max[k][j] = box.max[k];
      }
      n.child[j] = child;
      n.contents[j] = contents;
    }
    return number;
  }

  /// Whether two bounds have the same bits (a twin's lane shares its culls).
  static bool sameBounds(const Bounds& a, const Bounds& b) {
    for (int k = 0; k < 3; ++k)
      if (std::bit_cast<std::uint32_t>(float(a.min[k])) != std::bit_cast<std::uint32_t>(float(b.min[k])) ||
          std::bit_cast<std::uint32_t>(float(a.max[k])) != std::bit_cast<std::uint32_t>(float(b.max[k])))
        return false;
    return true;
  }

  const ModelArrays& m_;
  PolygonBvh& out_;
  std::vector<Item> items_;
  std::vector<std::int32_t> twin_;  ///< per polygon: its reversed twin of the same bounds, or -1
  bool fits_ = true;                ///< every polygon's edge count fits a leaf's 16 bits (and more)
  /// The polygons' planes, by number (the leaves read them in the items'
  /// order, at random: a compact array instead of the model's polygons).
  std::vector<Plane> planes_;
  /// What addUses reads of a polygon, by number (compact, as planes_).
  struct PolygonUses {
    std::int32_t material;
    std::uint32_t firstEdge, numEdges;
  };
  std::vector<PolygonUses> polygonUses_;
};

}  // namespace

PolygonBvh buildPolygonBvh(const ModelArrays& m, std::span<const EdgeUse> uses) {
  PolygonBvh bvh;
  if (m.polygons.size() > kBvhMinPolygons) Builder(m, bvh).build(uses);
  return bvh;
}

}  // namespace cmkit::detail
