// The polygons' hierarchy (polygon_bvh.h): buildPolygonBvh.
#include "model/polygon_bvh.h"

#include <algorithm>
#include <array>
#include <limits>
#include <numeric>

#include "util/assert.h"

namespace cmkit::detail {

namespace {

/// Bins per split search (binned surface-area heuristic): enough to find
/// good planes, few enough that a split costs one pass over the set.
constexpr int kBins = 12;
/// Sets of bins filled side by side (see split).
constexpr std::size_t kBinSets = 2;
/// Below this depth splits search planes; past it (a chain of lopsided
/// splits) they halve the set by count, which bounds the depth.
constexpr std::size_t kMaxCostDepth = 40;

struct Box {
  std::array<float, 3> min{std::numeric_limits<float>::max(), std::numeric_limits<float>::max(),
                           std::numeric_limits<float>::max()};
  std::array<float, 3> max{-std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(),
                           -std::numeric_limits<float>::max()};
  void add(const Box& b) {
    for (int k = 0; k < 3; ++k) {
      min[k] = std::min(min[k], b.min[k]);
      max[k] = std::max(max[k], b.max[k]);
    }
  }
  void add(const std::array<float, 3>& p) {
    for (int k = 0; k < 3; ++k) {
      min[k] = std::min(min[k], p[k]);
      max[k] = std::max(max[k], p[k]);
    }
  }
  bool valid() const { return min[0] <= max[0]; }
  /// Half the surface area (the cost heuristic's weight).
  float halfArea() const {
    if (!valid()) return 0;
    const float x = max[0] - min[0], y = max[1] - min[1], z = max[2] - min[2];
    return x * y + y * z + z * x;
  }
};

/// A polygon while the hierarchy is made (32 bytes: the builder's passes
/// over a large model's items are bound by memory).
struct Item {
  Box box;
  std::uint32_t contents;
  std::int32_t polygon;
  /// The centre of the box along axis k.
  float centre(std::size_t k) const { return (box.min[k] + box.max[k]) * 0.5f; }
  std::array<float, 3> centre() const { return {centre(0), centre(1), centre(2)}; }
};

class Builder {
 public:
  Builder(const ModelArrays& m, PolygonBvh& out) : out_(out), model_(m) {
    items_.reserve(m.polygons.size());
    for (std::size_t i = 0; i < m.polygons.size(); ++i) {
      const CmPolygon& p = m.polygons[i];
      Item item;
      for (int k = 0; k < 3; ++k) {
        item.box.min[k] = float(p.bounds.min[k]);
        item.box.max[k] = float(p.bounds.max[k]);
      }
      item.polygon = std::int32_t(i);
      item.contents = p.contents;
      items_.push_back(item);
    }
  }

  void build() {
    if (items_.empty()) return;
    out_.nodes.reserve(items_.size() / 2 + 1);
    out_.leaves.reserve(items_.size() / 2 + 1);
    (void)node(0, items_.size(), 1);
  }

 private:
  struct Range {
    std::size_t first, end;
    std::size_t size() const { return end - first; }
  };

  /// The bounds of r's items, and their contents OR'ed.
  Box boundsOf(Range r, std::uint32_t& contents) const {
    Box b;
    contents = 0;
    for (std::size_t i = r.first; i < r.end; ++i) {
      b.add(items_[i].box);
      contents |= items_[i].contents;
    }
    return b;
  }

  /// Splits r in two non-empty ranges (r.size() > 1).
  std::size_t split(Range r, std::size_t depth) {
    Box centres;
    for (std::size_t i = r.first; i < r.end; ++i) centres.add(items_[i].centre());
    int axis = 0;
    for (int k = 1; k < 3; ++k)
      if (centres.max[k] - centres.min[k] > centres.max[axis] - centres.min[axis]) axis = k;
    const float lo = centres.min[std::size_t(axis)], extent = centres.max[std::size_t(axis)] - lo;
    if (extent > 0 && depth < kMaxCostDepth) {
      const float scale = float(kBins) / extent;
      auto binOf = [&](const Item& it) {
        return std::min(kBins - 1, int((it.centre(std::size_t(axis)) - lo) * scale));
      };
      // Neighbouring items mostly fall in the same bin: two sets of bins
      // (even and odd items) halve the chains of updates to one bin in
      // memory. (Bounds and counts are the same in any order.)
      std::array<std::array<Box, kBins>, kBinSets> binSets;
      std::array<std::array<std::uint32_t, kBins>, kBinSets> countSets{};
      for (std::size_t i = r.first; i < r.end; ++i) {
        const std::size_t set = i % kBinSets;
        const auto b = std::size_t(binOf(items_[i]));
        binSets[set][b].add(items_[i].box);
        ++countSets[set][b];
      }
      std::array<Box, kBins>& bins = binSets[0];
      std::array<std::size_t, kBins> counts{};
      for (std::size_t b = 0; b < std::size_t(kBins); ++b) {
        for (std::size_t set = 1; set < kBinSets; ++set) bins[b].add(binSets[set][b]);
        for (std::size_t set = 0; set < kBinSets; ++set) counts[b] += countSets[set][b];
      }
      // Cost of splitting after bin s: area(left) * count(left) + area(right) * count(right).
      std::array<float, kBins> rightCost{};
      Box right;
      std::size_t rightCount = 0;
      for (int s = kBins - 1; s > 0; --s) {
        right.add(bins[std::size_t(s)]);
        rightCount += counts[std::size_t(s)];
        rightCost[std::size_t(s)] = right.halfArea() * float(rightCount);
      }
      Box left;
      std::size_t leftCount = 0;
      int best = -1;
      float bestCost = std::numeric_limits<float>::max();
      for (int s = 0; s + 1 < kBins; ++s) {
        left.add(bins[std::size_t(s)]);
        leftCount += counts[std::size_t(s)];
        if (leftCount == 0 || leftCount == r.size()) continue;
        const float cost = left.halfArea() * float(leftCount) + rightCost[std::size_t(s + 1)];
        if (cost < bestCost) {
          bestCost = cost;
          best = s;
        }
      }
      if (best >= 0) {
        const auto mid =
            std::partition(items_.begin() + std::ptrdiff_t(r.first), items_.begin() + std::ptrdiff_t(r.end),
                           [&](const Item& it) { return binOf(it) <= best; });
        return std::size_t(mid - items_.begin());
      }
    }
    // All centres at one place (or too deep): halve by count, in polygon order along the axis.
    const std::size_t mid = r.first + r.size() / 2;
    std::nth_element(items_.begin() + std::ptrdiff_t(r.first), items_.begin() + std::ptrdiff_t(mid),
                     items_.begin() + std::ptrdiff_t(r.end), [&](const Item& a, const Item& b) {
                       const float ca = a.centre(std::size_t(axis)), cb = b.centre(std::size_t(axis));
                       return ca < cb || (ca == cb && a.polygon < b.polygon);
                     });
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
      out_.polygons.push_back(polyNum);
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
      const CmPolygon& p = model_.polygons[std::size_t(polyNum)];
      for (int k = 0; k < 3; ++k) {
        b.min[k][j] = p.bounds.min[k];
        b.max[k][j] = p.bounds.max[k];
        b.normal[k][j] = p.plane.normal[k];
      }
      b.dist[j] = p.plane.dist;
      b.contents[j] = p.contents;
    }
    return number;
  }

  /// An inner node of the items of r (more than kLanes): its number.
  std::size_t node(std::size_t first, std::size_t end, std::size_t depth) {
    out_.depth = std::max(out_.depth, depth);
    // Up to kLanes children: split the largest child until there are
    // kLanes or every child fits a leaf.
    std::array<Range, kLanes> children{};
    std::size_t numChildren = 1;
    children[0] = {first, end};
    while (numChildren < kLanes) {
      std::size_t widest = kLanes;
      for (std::size_t c = 0; c < numChildren; ++c)
        if (children[c].size() > kLanes && (widest == kLanes || children[c].size() > children[widest].size()))
          widest = c;
      if (widest == kLanes) break;
      const Range r = children[widest];
      const std::size_t mid = split(r, depth);
      children[widest] = {r.first, mid};
      children[numChildren++] = {mid, r.end};
    }
    // Children in the order of their items (the near-far order is the walk's).
    std::sort(children.begin(), children.begin() + std::ptrdiff_t(numChildren),
              [](const Range& a, const Range& b) { return a.first < b.first; });
    const std::size_t number = out_.nodes.size();
    out_.nodes.emplace_back();
    for (std::size_t j = 0; j < kLanes; ++j) {
      Box box;
      std::int32_t child = 0;
      std::uint32_t contents = 0;
      if (j < numChildren) {
        box = boundsOf(children[j], contents);
        child = children[j].size() <= kLanes
                    ? ~std::int32_t(leaf(children[j]))
                    : std::int32_t(node(children[j].first, children[j].end, depth + 1));
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

  PolygonBvh& out_;
  const ModelArrays& model_;
  std::vector<Item> items_;
};

}  // namespace

PolygonBvh buildPolygonBvh(const ModelArrays& m) {
  PolygonBvh bvh;
  if (m.polygons.size() > kBvhMinPolygons) Builder(m, bvh).build();
  return bvh;
}

}  // namespace cmkit::detail
