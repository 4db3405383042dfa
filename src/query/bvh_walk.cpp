// A translation's walk of the polygons' hierarchy (model/polygon_bvh.h):
// cmkit's own query layout, walked instead of the .cm file's BSP tree. The
// children of a node are culled four at a time: their boxes against the
// trace bounds and, grown by the trace model's bounds, against the path of
// the trace model's centre up to the nearest hit so far (a slab test); those
// left are visited nearest first, and a child whose box the move reaches only
// after a hit found meanwhile is skipped. Every polygon is in one leaf, so
// none is met twice (no marks). The polygons left are tested by the same
// culls and tests as on the BSP walk; only the order differs, which decides
// nothing but ties (equally near hits: the first one found is kept).
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "query/cull_lanes.h"
#include "query/trace_work.h"

#ifdef CMKIT_QUERY_LANES

namespace cmkit::detail {

namespace {

using simd::F4;

/// How far the grown boxes reach past the trace model's bounds: a polygon
/// that stops the trace model at fraction f is within the clip epsilon
/// (tol::kClipEpsilon, 0.25) of it there; one unit (tol::kBoxEpsilon, the
/// trace bounds' own margin) dwarfs that and the rounding of the slab test
/// in float at coordinates up to the world's size, so the slab test never
/// culls a box holding a polygon the move can touch before the nearest hit.
constexpr float kGrowMargin = float(tol::kBoxEpsilon);
/// A direction component closer to 0 than this is replaced by it (same
/// sign), so that the slab test's reciprocal is finite: the move then spans
/// at least 1e20 fractions per unit, which keeps every box it does not reach
/// along that axis out, and every box it starts in, in.
constexpr float kTinyDirection = 1e-20f;

/// What the slab test reads of the query, broadcast once. Along each axis
/// the move enters a box through its near face (min when the direction is
/// positive, max when negative) and leaves through its far face: nearRow /
/// farRow are the byte offsets of those rows in a node, and nearGrow / farGrow how far
/// the trace model's bounds (and kGrowMargin) grow it, less the start. An
/// inverted box (an unused lane) is entered after it is left: never met.
struct PathLanes {
  std::size_t nearRow[3], farRow[3];  ///< byte offsets of the rows in a node
  F4 nearGrow[3], farGrow[3];
  F4 inv[3];  ///< 1 / direction
  explicit PathLanes(const TraceWork& tw) {
    for (int k = 0; k < 3; ++k) {
      float d = float(tw.dir[k]);
      if (std::fabs(d) < kTinyDirection) d = std::copysign(kTinyDirection, d);
      inv[k] = F4::all(1.0f / d);
      // The box grown by the trace model: [min - size.max - margin, max - size.min + margin].
      const F4 lo = F4::all(float(-tw.size.max[k]) - kGrowMargin - float(tw.start[k]));
      const F4 hi = F4::all(float(-tw.size.min[k]) + kGrowMargin - float(tw.start[k]));
      const bool negative = d < 0;
      const std::size_t minRow = offsetof(BvhNode, min) + std::size_t(k) * sizeof(BvhNode::min[0]);
      const std::size_t maxRow = offsetof(BvhNode, max) + std::size_t(k) * sizeof(BvhNode::max[0]);
      nearRow[k] = negative ? maxRow : minRow;
      farRow[k] = negative ? minRow : maxRow;
      nearGrow[k] = negative ? hi : lo;
      farGrow[k] = negative ? lo : hi;
    }
  }
  /// The row at byte offset `row` of a node (by address, not a branch per
  /// axis and node).
  static F4 rowOf(const BvhNode& n, std::size_t row) {
    return F4::load(reinterpret_cast<const float*>(reinterpret_cast<const char*>(&n) + row));
  }
};

/// A trace model's translation: its leaf test.
struct TrmLeaves {
  static bool test(TraceWork& tw, const PolygonBvh& bvh, std::size_t leaf, unsigned pass) {
    return translateTrmThroughBvhLeaf(tw, bvh, leaf, pass);
  }
};

/// A point's translation: its leaf test.
struct PointLeaves {
  static bool test(TraceWork& tw, const PolygonBvh& bvh, std::size_t leaf, unsigned pass) {
    return translatePointThroughBvhLeaf(tw, bvh, leaf, pass);
  }
};

/// Starts loading a child of the hierarchy (both cache lines of a node; the
/// three a leaf's culls read: bounds and contents, normals, plane distances):
/// the walk is otherwise bound by their loads. (A node's third line is the
/// next node's first, often a sibling's. The leaf's fourth line, read only
/// for the polygons that pass the culls, prefetched too: slower.)
inline void prefetchChild(const PolygonBvh& bvh, std::int32_t child) {
  // (The address chosen by arithmetic: a branch on whether a child is a
  // leaf is mispredicted often.)
  // (In integers: the address of the kind the child is not is out of range,
  // and only the other one is used.)
  const std::uintptr_t nodeAt = reinterpret_cast<std::uintptr_t>(bvh.nodes.data()) +
                                std::uintptr_t(std::uint32_t(child)) * sizeof(BvhNode);
  const std::uintptr_t leafAt = reinterpret_cast<std::uintptr_t>(bvh.leaves.data()) +
                                std::uintptr_t(std::uint32_t(~child)) * sizeof(BvhLeaf);
  const std::uintptr_t leafMask = std::uintptr_t(0) - std::uintptr_t(child < 0);
  const char* p = reinterpret_cast<const char*>((nodeAt & ~leafMask) | (leafAt & leafMask));
  prefetch(p);
  prefetch(p + 64);
  prefetch(p + 128);
}

template <class Leaves>
void walkPolygonBvh(TraceWork& tw, const PolygonBvh& bvh) {
  using Entry = QueryScratch::BvhEntry;
  std::vector<Entry>& stack = tw.scratch.bvhStack;
  if (stack.size() < bvh.stackSize()) stack.resize(bvh.stackSize());
  const PathLanes path(tw);
  const simd::U4 contentMask = simd::U4::all(tw.contentMask);
  BoundsLanes bounds(tw);
  Real boundsFraction = tw.fraction;
  std::size_t size = 0;
  std::int32_t child = 0;  // the root
  for (;;) {
    if (child < 0) {
      if (tw.fraction != boundsFraction) {  // the trace bounds shrank
        bounds.load(tw);
        boundsFraction = tw.fraction;
      }
      const std::size_t leaf = std::size_t(~child);
      const unsigned pass = bounds.pass(bvh.leaves[leaf]);
      count(tw.scratch, &QueryStats::polygonsMet,
            unsigned(std::popcount(pass) + std::popcount(pass & bvh.leaves[leaf].twinLanes())));
      if (pass && Leaves::test(tw, bvh, leaf, pass)) return;
    } else {
      const BvhNode& node = bvh.nodes[std::size_t(child)];
      count(tw.scratch, &QueryStats::nodesVisited);
      F4 near = F4::zero(), far = F4::all(float(tw.fraction));
      for (int k = 0; k < 3; ++k) {
        near = simd::max(near, (PathLanes::rowOf(node, path.nearRow[k]) + path.nearGrow[k]) * path.inv[k]);
        far = simd::min(far, (PathLanes::rowOf(node, path.farRow[k]) + path.farGrow[k]) * path.inv[k]);
      }
      const F4 culled = (near > far) | simd::noCommonBits(simd::U4::load(node.contents), contentMask);
      unsigned pass = ~simd::bits(culled) & 0xFu;
      if (pass != 0) {
        alignas(16) float nears[kLanes];
        near.store(nears);
        const int first = std::countr_zero(pass);
        pass &= pass - 1;
        if (pass == 0) {  // one child: on to it
          child = node.child[first];
          prefetchChild(bvh, child);
          continue;
        }
        // More: all but the nearest wait, farthest first below it (sorted
        // by insertion in place on the stack), each started loading.
        Entry* order = stack.data() + size;
        std::size_t n = 0;
        for (pass |= 1u << first; pass; pass &= pass - 1) {
          const int lane = std::countr_zero(pass);
          const Entry e{node.child[lane], nears[lane]};
          prefetchChild(bvh, e.child);
          std::size_t i = n++;
          for (; i > 0 && order[i - 1].near < e.near; --i) order[i] = order[i - 1];
          order[i] = e;
        }
        size += n - 1;
        child = stack[size].child;
        continue;
      }
    }
    // The next waiting child the move reaches before the nearest hit so far.
    for (;;) {
      if (size == 0) return;
      const Entry e = stack[--size];
      if (!(e.near > float(tw.fraction))) {
        child = e.child;
        break;
      }
    }
  }
}

}  // namespace

bool translateThroughBvh(TraceWork& tw) {
  if (!tw.queryData || tw.queryData->bvh.empty()) return false;
  if (tw.pointTrace)
    walkPolygonBvh<PointLeaves>(tw, tw.queryData->bvh);
  else
    walkPolygonBvh<TrmLeaves>(tw, tw.queryData->bvh);
  return true;
}

}  // namespace cmkit::detail

#else

namespace cmkit::detail {

bool translateThroughBvh(TraceWork&) { return false; }

}  // namespace cmkit::detail

#endif
