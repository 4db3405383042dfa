// The build of a RayIndex (ray_index.cpp has the casts): a binary hierarchy
// by binned surface-area heuristic over the padded boxes of the polygons that
// can be crossed, collapsed into 8-wide nodes whose boxes are padded again
// (float on purpose: ray_index_layout.h), and each leaf's polygons (planes,
// contents, edge lines) in one run of chunks.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <new>
#include <stdexcept>
#include <utility>
#include <vector>

#include "cmkit/tolerances.h"
#include "model/twins.h"
#include "ray/ray_index_data.h"
#include "ray/ray_index_kernel.h"  // kMaxDepth: the walk's stack bounds the depth
#include "util/assert.h"

namespace cmkit::detail {

namespace {

using Node = RayLayout::Node;
constexpr int kWidth = RayLayout::kWidth;

/// Polygons per leaf the builder aims for (the surface-area heuristic may
/// stop earlier); more than this and a node is always split.
constexpr std::uint32_t kMaxLeafPolygons = RayLayout::kLeafLanes;
/// Below this depth splits follow the surface-area heuristic; deeper ones cut
/// at the median, so that no input (at most 2^32 polygons) makes the
/// hierarchy deeper than kSahDepthLimit + 32 = detail::kMaxDepth, which
/// sizes the walk's stack.
constexpr int kSahDepthLimit = 36;
static_assert(kSahDepthLimit + 32 <= detail::kMaxDepth, "the walk's stack is sized by kMaxDepth");
/// The surface-area heuristic's cost of visiting a node (the unit of leafCost).
constexpr Real kNodeCost = 1;
/// The surface-area heuristic's cost of testing `n` polygons in leaves: each
/// leaf of up to kMaxLeafPolygons costs 1 (its head and corner rows are read
/// and tested for all lanes at once, and take the same memory however many
/// lanes are used), and each polygon beyond a leaf's first 0.5 (its share of
/// the crossings and edges that pass). Costing every polygon 1 (before
/// 2026-11-29) made leaves of one or two polygons, half their memory unused;
/// costing each leaf 1 whatever it holds filled them but slowed the casts
/// through lt4's triangles. This middle: lt4.map's world index 5.4 MB ->
/// 3.4 MB (and a quarter less time to build), cmkit_peers' generated scene's
/// 18.7 MB -> 15.3 MB and its 100 000 casts about 7 % faster, lt4's scene
/// unchanged (docs/performance.md, "The ray index's leaves fuller").
Real leafCost(std::uint32_t n) {
  const std::uint32_t leaves = (n + kMaxLeafPolygons - 1) / kMaxLeafPolygons;
  return Real(leaves) + Real(0.5) * Real(n - leaves);
}
/// Bins of the surface-area heuristic per axis.
constexpr int kBins = 16;

Real maxAbs(const Bounds& b) {
  Real m = 0;
  for (int k = 0; k < 3; ++k) m = std::max({m, std::fabs(b.min[k]), std::fabs(b.max[k])});
  return m;
}

/// The box padded by `relative` times its largest coordinate magnitude plus one.
Bounds padded(const Bounds& b, Real relative) { return b.expanded(relative * (maxAbs(b) + 1)); }

Real halfArea(const Bounds& b) {
  const Vec3 d = b.max - b.min;
  return d.x * d.y + d.y * d.z + d.z * d.x;
}

/// The temporary binary hierarchy.
struct BinaryNode {
  Bounds bounds;
  std::uint32_t first = 0, count = 0;  ///< polygons (leaves)
  std::uint32_t left = 0, right = 0;   ///< children (inner nodes: count == 0)
  std::uint32_t contents = 0;
};

class BinaryBuilder {
 public:
  BinaryBuilder(std::vector<Bounds> boxes, std::vector<std::uint32_t> contents)
      : boxes_(std::move(boxes)), contents_(std::move(contents)) {
    order_.resize(boxes_.size());
    centres_.resize(boxes_.size());
    for (std::uint32_t i = 0; i < order_.size(); ++i) {
      order_[i] = i;
      centres_[i] = boxes_[i].center();
    }
    nodes_.reserve(2 * boxes_.size() + 1);
    nodes_.emplace_back();
    build(0, 0, std::uint32_t(order_.size()), 0);
  }
  const std::vector<BinaryNode>& nodes() const { return nodes_; }
  const std::vector<std::uint32_t>& order() const { return order_; }

 private:
  void build(std::uint32_t nodeIndex, std::uint32_t first, std::uint32_t count, int depth) {
    Bounds box, centres;
    std::uint32_t contents = 0;
    for (std::uint32_t i = first; i < first + count; ++i) {
      box.addBounds(boxes_[order_[i]]);
      centres.addPoint(centres_[order_[i]]);
      contents |= contents_[order_[i]];
    }
    nodes_[nodeIndex].bounds = box;
    nodes_[nodeIndex].contents = contents;
    const auto leaf = [&] {
      nodes_[nodeIndex].first = first;
      nodes_[nodeIndex].count = count;
    };
    if (count <= 1) return leaf();

    std::uint32_t leftCount = 0;
    if (depth < kSahDepthLimit) {
      const Split split = bestSplit(first, count, centres);
      if (count <= kMaxLeafPolygons &&
          (split.axis < 0 || split.cost + kNodeCost * halfArea(box) >= halfArea(box) * leafCost(count)))
        return leaf();
      if (split.axis >= 0) {
        const auto mid = std::partition(
            order_.begin() + first, order_.begin() + first + count,
            [&](std::uint32_t p) { return binOf(centres_[p], centres, split.axis) < split.bin; });
        leftCount = std::uint32_t(mid - (order_.begin() + first));
      }
    } else if (count <= kMaxLeafPolygons) {
      return leaf();
    }
    if (leftCount == 0 || leftCount == count) {  // no useful split: halves along the widest axis
      const Vec3 extent = centres.max - centres.min;
      const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
      leftCount = count / 2;
      std::nth_element(
          order_.begin() + first, order_.begin() + first + leftCount, order_.begin() + first + count,
          [&](std::uint32_t a, std::uint32_t b) { return centres_[a][axis] < centres_[b][axis]; });
    }
    const auto left = std::uint32_t(nodes_.size());
    nodes_.emplace_back();
    build(left, first, leftCount, depth + 1);
    const auto right = std::uint32_t(nodes_.size());
    nodes_.emplace_back();
    build(right, first + leftCount, count - leftCount, depth + 1);
    nodes_[nodeIndex].left = left;
    nodes_[nodeIndex].right = right;
  }

  struct Split {
    int axis = -1;
    int bin = 0;
    Real cost = std::numeric_limits<Real>::max();
  };
  static int binOf(const Vec3& c, const Bounds& centres, int axis) {
    const Real lo = centres.min[axis], hi = centres.max[axis];
    return std::clamp(int((c[axis] - lo) / (hi - lo) * kBins), 0, kBins - 1);
  }
  Split bestSplit(std::uint32_t first, std::uint32_t count, const Bounds& centres) const {
    Split best;
    for (int axis = 0; axis < 3; ++axis) {
      if (!(centres.max[axis] > centres.min[axis])) continue;
      std::array<Bounds, kBins> bins;
      std::array<std::uint32_t, kBins> binCount{};
      for (std::uint32_t i = first; i < first + count; ++i) {
        const int b = binOf(centres_[order_[i]], centres, axis);
        bins[std::size_t(b)].addBounds(boxes_[order_[i]]);
        ++binCount[std::size_t(b)];
      }
      // Areas and counts left of each cut, then sweep from the right.
      std::array<Real, kBins> leftArea{};
      std::array<std::uint32_t, kBins> leftCount{};
      Bounds acc;
      std::uint32_t n = 0;
      for (int b = 0; b < kBins - 1; ++b) {
        if (binCount[std::size_t(b)]) acc.addBounds(bins[std::size_t(b)]);
        n += binCount[std::size_t(b)];
        leftArea[std::size_t(b)] = n ? halfArea(acc) : 0;
        leftCount[std::size_t(b)] = n;
      }
      acc.clear();
      n = 0;
      for (int b = kBins - 1; b > 0; --b) {
        if (binCount[std::size_t(b)]) acc.addBounds(bins[std::size_t(b)]);
        n += binCount[std::size_t(b)];
        const std::uint32_t nl = leftCount[std::size_t(b - 1)];
        if (nl == 0 || n == 0) continue;
        const Real cost = leftArea[std::size_t(b - 1)] * leafCost(nl) + halfArea(acc) * leafCost(n);
        if (cost < best.cost) best = {axis, b, cost};
      }
    }
    return best;
  }

  std::vector<Bounds> boxes_;
  std::vector<std::uint32_t> contents_;
  std::vector<Vec3> centres_;
  std::vector<std::uint32_t> order_;
  std::vector<BinaryNode> nodes_;
};

bool isFinite(const Bounds& b) { return b.min.isFinite() && b.max.isFinite() && !b.isCleared(); }

}  // namespace

void buildRayIndex(const CollisionModel& model, RayIndexData& d) {
  using Index = RayIndexData;
  // The polygons that can be crossed: finite plane and bounds, an outline.
  std::vector<std::uint32_t> usable;
  std::vector<Bounds> boxes;
  std::vector<std::uint32_t> contents;
  for (std::size_t i = 0; i < model.polygons().size(); ++i) {
    const CmPolygon& p = model.polygons()[i];
    if (p.numEdges < 3 || !isFinite(p.bounds) || !p.plane.normal.isFinite() || !std::isfinite(p.plane.dist))
      continue;
    usable.push_back(std::uint32_t(i));
    boxes.push_back(padded(p.bounds, tol::kRayAcceptPadding));
    contents.push_back(p.contents);
  }
  if (usable.empty()) return;

  // What the hierarchy sorts: each polygon without a twin, and each pair of
  // twins (the one first in `usable` with its twin) as one item of both
  // boxes.
  const std::vector<std::int32_t> twin = findTwins(model.arrays(), usable);
  std::vector<std::uint32_t> items;  ///< positions in `usable`
  std::vector<Bounds> itemBoxes;
  std::vector<std::uint32_t> itemContents;
  for (std::uint32_t i = 0; i < usable.size(); ++i) {
    if (twin[i] >= 0 && std::uint32_t(twin[i]) < i) continue;  // with its twin
    Bounds box = boxes[i];
    if (twin[i] >= 0) box.addBounds(boxes[std::size_t(twin[i])]);
    items.push_back(i);
    itemBoxes.push_back(box);
    itemContents.push_back(contents[i]);
  }
  const BinaryBuilder binary(std::move(itemBoxes), std::move(itemContents));
  const std::vector<BinaryNode>& bn = binary.nodes();
  const auto recordOf = [&](std::uint32_t k) -> Index::PolygonRecord {
    return {boxes[k], std::int32_t(usable[k]), model.polygons()[usable[k]].material};
  };

  // Each leaf: its head and corner rows in whole chunks, its polygons'
  // records in leaf order.
  d.records.reserve(usable.size());
  const auto addLeaf = [&](const BinaryNode& leaf) {
    using Head = Index::LeafHead;
    using Row = Index::CornerRow;
    const auto edgesOfLane = [&](std::uint32_t lane) {
      return std::uint32_t(model.polygons()[usable[items[binary.order()[leaf.first + lane]]]].numEdges);
    };
    std::uint32_t edges = 0;
    for (std::uint32_t lane = 0; lane < leaf.count; ++lane) edges = std::max(edges, edgesOfLane(lane));
    // A closing row only where some lane's loop would not close at row 0.
    bool closing = false;
    for (std::uint32_t lane = 0; lane < leaf.count; ++lane) closing |= edges % edgesOfLane(lane) != 0;
    const std::uint32_t rows = edges + std::uint32_t(closing);
    const std::size_t chunk = d.leafChunks.size();
    if (chunk >= (Index::kLeaf >> Index::kLeafCountBits))  // (over 500 million leaves)
      throw std::length_error("RayIndex: too many polygons");
    const std::size_t bytes = sizeof(Head) + rows * sizeof(Row);
    d.leafChunks.resize(chunk + (bytes + sizeof(Index::LeafChunk) - 1) / sizeof(Index::LeafChunk));
    auto* head = new (d.leafChunks.data() + chunk) Head{};
    auto* row = new (head + 1) Row[rows]{};
    head->firstRecord = std::uint32_t(d.records.size());
    head->numEdges = edges;
    head->closingRow = closing ? edges : 0;
    for (std::uint32_t lane = 0; lane < leaf.count; ++lane) {
      const std::uint32_t k = items[binary.order()[leaf.first + lane]];
      const CmPolygon& p = model.polygons()[usable[k]];
      head->x[lane] = p.plane.normal.x;
      head->y[lane] = p.plane.normal.y;
      head->z[lane] = p.plane.normal.z;
      head->dist[lane] = p.plane.dist;
      head->contents[lane] = p.contents;
      // Corner j: where edge j mod n starts (a sealed model's polygon's
      // edges close a loop, so it is where edge j - 1 ends).
      CMKIT_ASSERT(model.arrays().brokenEdgeLoopAt(p) < 0);
      const auto list = model.edgesOf(p);
      for (std::uint32_t j = 0; j < rows; ++j) {
        const std::int32_t e = list[j % list.size()];
        const Vec3& corner = model.vertices()[std::size_t(model.arrays().edgeStart(e))];
        for (int c = 0; c < 3; ++c) row[j].v[c][lane] = corner[c];
        if (j < edges) row[j].reversed |= std::uint32_t(e < 0) << lane;
      }
      d.records.push_back(recordOf(k));
      if (twin[k] >= 0) head->twins |= 1u << lane;
    }
    // The twins' records after the lanes', in lane order (twinRecord).
    for (std::uint32_t lane = 0; lane < leaf.count; ++lane) {
      const std::uint32_t k = items[binary.order()[leaf.first + lane]];
      if (twin[k] >= 0) d.records.push_back(recordOf(std::uint32_t(twin[k])));
    }
    return Index::kLeaf | std::uint32_t(chunk) << Index::kLeafCountBits | (leaf.count - 1);
  };

  // Collapse: each 8-wide node takes the binary node's children, then opens
  // the largest inner child until it has eight.
  const auto collapse = [&](auto&& self, std::uint32_t b) -> std::uint32_t {
    std::array<std::uint32_t, kWidth> kids{};
    std::size_t n = 0;
    if (bn[b].count) {
      kids[n++] = b;
    } else {
      kids[n++] = bn[b].left;
      kids[n++] = bn[b].right;
    }
    while (n < kWidth) {
      std::size_t open = n;
      for (std::size_t k = 0; k < n; ++k)
        if (!bn[kids[k]].count &&
            (open == n || halfArea(bn[kids[k]].bounds) > halfArea(bn[kids[open]].bounds)))
          open = k;
      if (open == n) break;
      const std::uint32_t inner = kids[open];
      kids[open] = bn[inner].left;
      kids[n++] = bn[inner].right;
    }
    const auto me = std::uint32_t(d.nodes.size());
    d.nodes.emplace_back();
    std::array<std::uint32_t, kWidth> refs{};
    for (std::size_t k = 0; k < n; ++k) {
      const BinaryNode& c = bn[kids[k]];
      if (c.count) {
        refs[k] = addLeaf(c);
      } else {
        refs[k] = self(self, kids[k]);
      }
    }
    Node& node = d.nodes[me];
    for (std::size_t k = 0; k < kWidth; ++k) {
      if (k >= n) {  // an empty slot: a box nothing enters, no contents
        for (int a = 0; a < 3; ++a) {
          node.min[a][k] = std::numeric_limits<float>::max();
          node.max[a][k] = -std::numeric_limits<float>::max();
        }
        node.child[k] = Index::kLeaf;
        node.contents[k] = 0;
        continue;
      }
      const Bounds box = padded(bn[kids[k]].bounds, tol::kRayNodePadding);
      for (int a = 0; a < 3; ++a) {
        node.min[a][k] = float(box.min[a]);
        node.max[a][k] = float(box.max[a]);
      }
      node.child[k] = refs[k];
      node.contents[k] = bn[kids[k]].contents;
    }
    return me;
  };
  collapse(collapse, 0);
  // The leaves grew chunk by chunk: up to twice their size was reserved
  // (and RayIndex::memoryBytes counts what is held).
  d.leafChunks.shrink_to_fit();
  d.nodes.shrink_to_fit();
}

}  // namespace cmkit::detail
