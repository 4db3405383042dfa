// A uniform grid of brush boxes for point contents (point_grid.h):
// buildPointGrid.
#include "model/point_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "util/assert.h"

namespace cmkit::detail {

namespace {

/// Cells aimed at per box: about a box a cell on average (a box spans
/// several); a query's cell then lists about ten boxes on lt4's world, where
/// the queries are near its walls. Fewer cells were slower, more a few per
/// cent faster for half as much memory again (docs/performance.md, "Point
/// contents from a grid").
constexpr double kCellsPerBox = 8;
/// At most this many cells (4 bytes each).
constexpr double kMaxCells = double(1 << 20);
/// A grid whose cells would list more than this many boxes per box (boxes
/// much larger than a cell) is made coarser, down to kCoarserTries times.
constexpr std::size_t kMaxListsPerBox = 16;
constexpr int kCoarserTries = 4;

/// Every (node, brush) pair's box: the brush's bounds cut to the region of
/// the points whose walk passes the node (front: coordinate > split, so from
/// the next number up; back: <= split). Empty when the tree is not one.
std::vector<PointBrushBox> seenBoxes(const ModelArrays& m) {
  std::vector<PointBrushBox> out;
  struct Pending {
    std::int32_t node;
    Bounds region;
  };
  constexpr Real inf = std::numeric_limits<Real>::infinity();
  std::vector<Pending> pending;
  pending.push_back({0, Bounds{Vec3{-inf, -inf, -inf}, Vec3{inf, inf, inf}}});
  std::size_t visited = 0;
  while (!pending.empty()) {
    const Pending p = pending.back();
    pending.pop_back();
    if (p.node < 0 || std::size_t(p.node) >= m.nodes.size() || ++visited > m.nodes.size()) return {};
    const CmNode& n = m.nodes[std::size_t(p.node)];
    for (std::uint32_t r = 0; r < n.numBrushRefs; ++r) {
      const std::int32_t b = m.brushRefs[std::size_t(n.firstBrushRef + r)];
      CMKIT_ASSERT(b >= 0 && std::size_t(b) < m.brushes.size());
      const CmBrush& brush = m.brushes[std::size_t(b)];
      Bounds cut;
      bool empty = false;
      for (int k = 0; k < 3; ++k) {
        cut.min[k] = std::max(brush.bounds.min[k], p.region.min[k]);
        cut.max[k] = std::min(brush.bounds.max[k], p.region.max[k]);
        empty |= !(cut.min[k] <= cut.max[k]);
      }
      if (!empty) out.push_back({cut, brush.contents, std::uint32_t(b)});
    }
    if (n.isLeaf()) continue;
    const int axis = n.planeType;
    CMKIT_ASSERT(axis >= 0 && axis < 3);
    Pending front{n.children[0], p.region}, back{n.children[1], p.region};
    front.region.min[axis] = std::max(front.region.min[axis], std::nextafter(n.planeDist, inf));
    back.region.max[axis] = std::min(back.region.max[axis], n.planeDist);
    pending.push_back(back);
    pending.push_back(front);
  }
  return out;
}

/// The grid's cells over g.bounds for about `target` cells (dims, scale).
void placeCells(PointGrid& g, double target) {
  const Vec3 size = g.bounds.max - g.bounds.min;
  double volume = 1;
  for (int k = 0; k < 3; ++k) volume *= std::max(double(size[k]), 1.0);
  const double cell = std::cbrt(volume / target);
  for (int k = 0; k < 3; ++k) {
    g.dims[k] = std::uint32_t(std::clamp(std::ceil(double(size[k]) / cell), 1.0, 1024.0));
    // (One cell: scale 0, every coordinate in it; never 1 / a tiny size.)
    g.scale[k] = g.dims[k] > 1 ? Real(double(g.dims[k]) / double(size[k])) : Real(0);
  }
}

/// Calls f(cell) for every cell box b meets.
template <class F>
void forCells(const PointGrid& g, const Bounds& b, F&& f) {
  std::uint32_t lo[3], hi[3];
  for (int k = 0; k < 3; ++k) {
    lo[k] = g.cellOf(b.min[k], k);
    hi[k] = g.cellOf(b.max[k], k);
  }
  for (std::uint32_t z = lo[2]; z <= hi[2]; ++z)
    for (std::uint32_t y = lo[1]; y <= hi[1]; ++y)
      for (std::uint32_t x = lo[0]; x <= hi[0]; ++x) f(g.cell(x, y, z));
}

}  // namespace

PointGrid buildPointGrid(const ModelArrays& m) {
  PointGrid g;
  if (m.nodes.size() < 2 || m.brushRefs.empty()) return g;
  const std::vector<PointBrushBox> boxes = seenBoxes(m);
  if (boxes.empty()) return g;
  for (const PointBrushBox& b : boxes) {
    g.bounds.addPoint(b.bounds.min);
    g.bounds.addPoint(b.bounds.max);
  }
  // (Cells over a box of infinite or overflowing size would have no size:
  // the walk of the model's nodes then.)
  if (!(g.bounds.max - g.bounds.min).isFinite()) return PointGrid{};
  double target = std::min(kMaxCells, kCellsPerBox * double(boxes.size()));
  for (int tries = 0;; ++tries, target /= 8) {
    if (tries == kCoarserTries) return PointGrid{};  // (the tree's walk then)
    placeCells(g, target);
    const std::size_t cells = std::size_t(g.dims[0]) * g.dims[1] * g.dims[2];
    std::vector<std::uint32_t> first(cells + 1, 0);
    std::size_t lists = 0;
    for (const PointBrushBox& b : boxes)
      forCells(g, b.bounds, [&](std::size_t c) {
        ++first[c + 1];
        ++lists;
      });
    if (lists > kMaxListsPerBox * boxes.size()) continue;
    if (lists > std::numeric_limits<std::uint32_t>::max()) return PointGrid{};  // (firstBox is 32 bits)
    for (std::size_t c = 0; c < cells; ++c) first[c + 1] += first[c];
    g.boxes.resize(lists);
    g.firstBox = first;
    for (const PointBrushBox& b : boxes)
      forCells(g, b.bounds, [&](std::size_t c) { g.boxes[first[c]++] = b; });
    return g;
  }
}

}  // namespace cmkit::detail
