// Point contents: the brushes containing a point (every brush on the path
// from the root to the point's leaf, including those stored at interior
// nodes, unlike the original; for a model with a tree, from the point's cell
// of its point grid, which lists the same), and the public pointContents().
#include <span>

#include "query/query_guards.h"
#include "query/trace_work.h"
#include "util/simd.h"

namespace cmkit::detail {

/// Models with more brushes than this (40 bytes each: 40 KiB, about an L1
/// data cache) have them prefetched on pointContents' way down their nodes;
/// for smaller ones that only costs. A speed choice only: the same brushes
/// are tested either way.
constexpr std::size_t kPointContentsCachedBrushes = 1024;

/// Whether p is behind every plane (distance < 0): inside the brush they
/// bound. Four planes at a time where SSE2 float lanes are available, each
/// lane computing Plane::distance's products and sums in its order (the
/// same distances).
inline bool behindAllPlanes(std::span<const Plane> planes, const Vec3& p) {
  std::size_t i = 0;
#ifdef CMKIT_QUERY_LANES
  using simd::F4;
  static_assert(sizeof(Plane) == 4 * sizeof(float), "a Plane is four floats: normal, dist");
  const F4 px = F4::all(p.x), py = F4::all(p.y), pz = F4::all(p.z);
  for (; i + 4 <= planes.size(); i += 4) {
    const float* f = &planes[i].normal.x;
    F4 nx = F4::loadUnaligned(f), ny = F4::loadUnaligned(f + 4), nz = F4::loadUnaligned(f + 8),
       d = F4::loadUnaligned(f + 12);
    simd::transpose(nx, ny, nz, d);
    const F4 dist = nx * px + ny * py + nz * pz - d;
    if (simd::bits(dist >= F4::zero()) != 0) return false;
  }
#endif
  for (; i < planes.size(); ++i)
    if (planes[i].distance(p) >= 0) return false;
  return true;
}

namespace {

/// Whether a brush of these contents and bounds is worth its planes' test
/// at p: it matches `mask`, has a flag not in `found` and its bounds hold p.
/// (Any flag not found yet, not only one of the mask's: with a mask the OR
/// is then every matching brush's, whatever the order the walk meets them
/// in.)
inline bool mayAdd(std::uint32_t brushContents, const Bounds& bounds, const Vec3& p, std::uint32_t mask,
                   std::uint32_t found) {
  return (brushContents & ~found) && (brushContents & mask) && bounds.containsPoint(p);
}

/// Whether brush b adds its flags to `found` at p: mayAdd, and p is behind
/// all its planes.
inline bool brushAdds(const CollisionModel& model, const CmBrush& b, const Vec3& p, std::uint32_t mask,
                      std::uint32_t found) {
  return mayAdd(b.contents, b.bounds, p, mask, found) && b.numPlanes != 0 &&
         behindAllPlanes(model.planesOf(b), p);
}

/// Nodes with brushes collected on the way down at a time (their brushes
/// are tested from the deepest up when the path is that long, then the walk
/// goes on).
constexpr int kPath = 64;

/// pointContentsMasked through the model's point grid (model/point_grid.h):
/// the boxes of the point's cell are the parts of brushes the walk of the
/// model's nodes would meet there, so the brushes whose planes are tested
/// are those the walk tests (the same contents; the OR does not depend on
/// the order). One cell's list in place of about 20 levels of the
/// tree, each level's way a guess the processor often got wrong: lt4's point
/// contents took about 1.4x less time.
[[gnu::always_inline]] inline std::uint32_t pointContentsThroughGrid(const CollisionModel& model,
                                                                     const PointGrid& grid, const Vec3& p,
                                                                     std::uint32_t mask) {
  if (!grid.bounds.containsPoint(p)) return 0;
  const std::size_t cell = grid.cellOf(p);
  const std::span<const CmBrush> brushes = model.brushes();
  const PointBrushBox* box = grid.boxes.data() + grid.firstBox[cell];
  const PointBrushBox* end = grid.boxes.data() + grid.firstBox[cell + 1];
  std::uint32_t contents = 0;
  for (; box != end; ++box) {
    if (!mayAdd(box->contents, box->bounds, p, mask, contents)) continue;
    const CmBrush& b = brushes[box->brush];
    if (b.numPlanes != 0 && behindAllPlanes(model.planesOf(b), p)) contents |= box->contents;
  }
  return contents;
}

/// pointContentsMasked for a model without a point grid (a copy without
/// query data, or boxes too large or too far apart for cells).
[[gnu::always_inline]] inline std::uint32_t pointContentsThroughNodes(const CollisionModel& model,
                                                                      const Vec3& p, std::uint32_t mask) {
  const std::span<const CmNode> nodes = model.nodes();
  const std::span<const CmBrush> brushes = model.brushes();
  const Real coord[3] = {p.x, p.y, p.z};  // indexed by split axis below
  const bool prefetchBrushes = brushes.size() > kPointContentsCachedBrushes;

  // Every brush on the path from the root to the point's leaf: brushes
  // straddling a split are stored at interior nodes (the original looked at
  // the leaf only, and stopped at the first brush containing the point).
  // The nodes with brushes are collected on the way down (up to kPath at a
  // time) and their brushes tested from the leaf up: the deepest, smallest
  // brushes first, and a brush that could add no flag to those found is not
  // tested (the OR does not depend on the order: with a mask, a point's
  // contentsTest, it is that of every brush matching the mask).
  const CmNode* withBrushes[kPath];
  std::uint32_t contents = 0;
  std::int32_t n = 0;
  bool atLeaf = false;
  while (!atLeaf) {
    int count = 0;
    while (count < kPath) {
      const CmNode& node = nodes[std::size_t(n)];
      if (node.numBrushRefs != 0) {
        withBrushes[count++] = &node;
        if (prefetchBrushes)
          for (std::int32_t b : model.brushesAt(node)) prefetch(&brushes[std::size_t(b)]);
      }
      if (node.isLeaf()) {
        atLeaf = true;
        break;
      }
      n = coord[node.planeType] > node.planeDist ? node.children[0] : node.children[1];
    }
    while (count > 0) {
      for (std::int32_t brushNum : model.brushesAt(*withBrushes[--count])) {
        const CmBrush& b = brushes[std::size_t(brushNum)];
        if (brushAdds(model, b, p, mask, contents)) contents |= b.contents;
      }
    }
  }
  return contents;
}

/// pointContentsMasked for a point already in the model's frame. Inline in
/// its two callers, pointContents' usual query and pointContentsMasked, with
/// both walks: a point query takes a few tens of nanoseconds, and a call
/// more, with a frame of its own, was a tenth of that.
[[gnu::always_inline]] inline std::uint32_t pointContentsInModel(const CollisionModel& model, const Vec3& p,
                                                                 std::uint32_t mask) {
  const std::size_t numNodes = model.nodes().size();
  // No brush, nothing to be inside (a model of patches or meshes alone).
  if (numNodes == 0 || model.brushes().empty()) return 0;
  if (numNodes == 1) {
    // One leaf (a model of up to four brushes, or one the compiler found no
    // split for): its list is every brush, tested in turn without the walk's
    // path (1.16x-1.18x less time on the shared files of that kind).
    std::uint32_t contents = 0;
    for (std::int32_t brushNum : model.brushesAt(model.nodes()[0])) {
      const CmBrush& b = model.brushes()[std::size_t(brushNum)];
      if (brushAdds(model, b, p, mask, contents)) contents |= b.contents;
    }
    return contents;
  }
  if (const QueryData* d = queryDataOf(model); d && !d->pointGrid.empty())
    return pointContentsThroughGrid(model, d->pointGrid, p, mask);
  return pointContentsThroughNodes(model, p, mask);
}

}  // namespace

std::uint32_t pointContentsMasked(const CollisionModel& model, const Vec3& point, const Placement& placement,
                                  std::uint32_t mask) {
  // The point, the origin and a turned model's axis were checked by the
  // caller's guard (query_guards.cpp): they are not checked again.
  Vec3 p = point - placement.origin;
  if (isRotated(placement)) p = placement.axis * p;  // world -> model frame
  return pointContentsInModel(model, p, mask);
}

}  // namespace cmkit::detail

namespace cmkit {

using namespace detail;  // the query internals (trace_work.h)

PointContentsResult pointContents(const CollisionModel& model, const PointContentsQuery& query, QueryWork&) {
  PointContentsResult r;
  // The guard only decides the status: the contents are computed from the
  // query as given (a slightly drifted axis is not re-orthonormalised), so
  // that they stay what they were before pointContents had a status (every
  // input the guard refuses already gave 0). The usual query, a point and an
  // origin in range and no turn, needs no more than the range test (a point
  // query costs a few tens of nanoseconds: the guard's copy and calls
  // showed).
  const Placement& placement = query.placement;
  if (!withinQueryRange(query.point) || !withinQueryRange(placement.origin) || isRotated(placement)) {
    PointContentsQuery checked = query;
    r.status = guardPointContents(checked);
    if (r.status == QueryStatus::Ok)
      r.contents = pointContentsMasked(model, query.point, placement, ~std::uint32_t(0));
    return r;
  }
  r.contents = pointContentsInModel(model, query.point - placement.origin, ~std::uint32_t(0));
  return r;
}

}  // namespace cmkit
