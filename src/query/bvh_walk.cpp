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

/// What the slab test reads of the query, broadcast once.
struct PathLanes {
  F4 lo[3];   ///< node min + lo - start: where the grown box begins, from the start
  F4 hi[3];   ///< node max + hi - start
  F4 inv[3];  ///< 1 / direction
  explicit PathLanes(const TraceWork& tw) {
    for (int k = 0; k < 3; ++k) {
      float d = float(tw.dir[k]);
      if (std::fabs(d) < kTinyDirection) d = std::copysign(kTinyDirection, d);
      inv[k] = F4::all(1.0f / d);
      lo[k] = F4::all(float(-tw.size.max[k]) - kGrowMargin - float(tw.start[k]));
      hi[k] = F4::all(float(-tw.size.min[k]) + kGrowMargin - float(tw.start[k]));
    }
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

template <class Leaves>
void walkPolygonBvh(TraceWork& tw, const PolygonBvh& bvh) {
  using Entry = QueryScratch::BvhEntry;
  std::vector<Entry>& stack = tw.scratch.bvhStack;
  if (stack.size() < bvh.stackSize()) stack.resize(bvh.stackSize());
  const PathLanes path(tw);
  BoundsLanes bounds(tw);
  Real boundsFraction = tw.fraction;
  std::size_t size = 0;
  stack[size++] = Entry{0, 0.0f};
  while (size > 0) {
    const Entry e = stack[--size];
    if (e.near > float(tw.fraction)) continue;  // a hit found meanwhile is nearer
    if (tw.fraction != boundsFraction) {        // the trace bounds shrank
      bounds.load(tw);
      boundsFraction = tw.fraction;
    }
    if (e.child < 0) {
      const std::size_t leaf = std::size_t(~e.child);
      const unsigned pass = bounds.pass(bvh.leaves[leaf]);
      count(tw.scratch, &QueryStats::polygonsMet, unsigned(std::popcount(pass)));
      if (pass && Leaves::test(tw, bvh, leaf, pass)) return;
      continue;
    }
    const BvhNode& node = bvh.nodes[std::size_t(e.child)];
    count(tw.scratch, &QueryStats::nodesVisited);
    F4 culled = F4::zero();
    F4 near = F4::zero(), far = F4::all(float(tw.fraction));
    for (int k = 0; k < 3; ++k) {
      const F4 min = F4::load(node.min[k]), max = F4::load(node.max[k]);
      culled = culled | (max < bounds.min[k]) | (min > bounds.max[k]);
      const F4 t0 = (min + path.lo[k]) * path.inv[k];
      const F4 t1 = (max + path.hi[k]) * path.inv[k];
      near = simd::max(near, simd::min(t0, t1));
      far = simd::min(far, simd::max(t0, t1));
    }
    culled = culled | (near > far);
    unsigned pass = ~simd::bits(culled) & 0xFu;
    if (pass == 0) continue;
    alignas(16) float nears[kLanes];
    near.store(nears);
    // Pushed farthest first, so that the nearest is visited next.
    int order[kLanes];
    int n = 0;
    for (; pass; pass &= pass - 1) {
      const int lane = std::countr_zero(pass);
      int i = n++;
      for (; i > 0 && nears[order[i - 1]] < nears[lane]; --i) order[i] = order[i - 1];
      order[i] = lane;
    }
    for (int i = 0; i < n; ++i) {
      const std::int32_t child = node.child[order[i]];
      // Start loading the children now (every one the walk will visit):
      // each its two cache lines. The walk is otherwise bound by their loads.
      const char* p = child >= 0 ? reinterpret_cast<const char*>(&bvh.nodes[std::size_t(child)])
                                 : reinterpret_cast<const char*>(&bvh.leaves[std::size_t(~child)]);
      prefetch(p);
      prefetch(p + 64);
      stack[size++] = Entry{child, nears[order[i]]};
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
