// Which polygons a translation tests (translate.cpp has the tests of one
// polygon): the culls of contents, bounds, back faces and the heart planes
// (the planes along the move), one polygon at a time, four at a time from a
// BSP node's cull blocks, or from a leaf of the polygon hierarchy (with its
// polygons' planes against the trace bounds), the walks of bvh_walk.cpp and
// tree_walk.cpp calling them.
#include <bit>
#include <cmath>

#include "model/query_data.h"  // CMKIT_QUERY_LANES: SSE2, float lanes
#include "query/cull_lanes.h"
#include "query/trace_work.h"

#ifdef CMKIT_QUERY_LANES
#include "util/simd.h"
#define CMKIT_CULL_LANES 1
#endif

namespace cmkit::detail {
namespace {

// Culling: contents, bounds, back faces, distance from the heart planes.
// True when the polygon may be touched. Point traces make each test only
// when the ones before passed: a point's thin bounds reject most polygons at
// once, predictably.
inline bool pointMayTouch(TraceWork& tw, const CmPolygon& poly) {
  if (!(poly.contents & tw.contentMask) || !tw.bounds.intersects(poly.bounds) ||
      poly.plane.normal.dot(tw.dir) > 0)  // only front faces collide
    return false;
  if (!tw.heartPlanesMade) makeTranslationHeartPlanes(tw);
  return !(std::fabs(boundsPlaneDistance(poly.bounds, tw.heartPlane1)) > tw.maxDistFromHeartPlane1) &&
         !(std::fabs(boundsPlaneDistance(poly.bounds, tw.heartPlane2)) > tw.maxDistFromHeartPlane2);
}

// The same culls for a trace model: after contents and bounds, the rest
// without branches between them.
inline bool mayTouch(TraceWork& tw, const CmPolygon& poly) {
  if (!(poly.contents & tw.contentMask) || !boxesTouch(tw.bounds, poly.bounds)) return false;
  if (!tw.heartPlanesMade) makeTranslationHeartPlanes(tw);
  const bool backFace = poly.plane.normal.dot(tw.dir) > 0;  // only front faces collide
  // (int | int on purpose: all three tests run, no branch between them.)
  return (int(backFace) | int(boxBeyondPlane(poly.bounds, tw.heartPlane1, tw.maxDistFromHeartPlane1)) |
          int(boxBeyondPlane(poly.bounds, tw.heartPlane2, tw.maxDistFromHeartPlane2))) == 0;
}

// A point's polygon: the culls, then the test; the bounds shrink at a hit.
// True when the point is blocked completely.
bool pointThroughPolygon(TraceWork& tw, std::int32_t polyNum, const CmPolygon& poly) {
  if (!pointMayTouch(tw, poly)) return false;
  count(tw.scratch, &QueryStats::polygonsTested);
  count(tw.scratch, &QueryStats::vertexTests);
  const Real before = tw.fraction;
  const std::size_t contactsBefore = contactCount(tw);
  translatePointThroughPolygon(tw, polyNum, poly);
  countCloser(tw, before, contactsBefore);
  if (tw.fraction == before) return false;
  shrinkTraceBounds(tw);
  return tw.fraction == 0;
}

}  // namespace

bool translatePointThroughPolygons(TraceWork& tw, std::span<const std::int32_t> polygons) {
  QueryScratch& s = tw.scratch;
  return forEachNewItem(s, s.polygonChecked, &QueryStats::polygonsMet, polygons, [&](std::int32_t polyNum) {
    return pointThroughPolygon(tw, polyNum, tw.model.polygons()[std::size_t(polyNum)]);
  });
}

#ifdef CMKIT_CULL_LANES
namespace {

/// The lanes of a cull block that pass the back-face and heart-plane culls:
/// `front` those whose polygon faces the move, `back` those whose polygon's
/// reversed twin would (a lane of the polygons' hierarchy may hold one:
/// BvhLeaf::twinLanes; the caller keeps the lanes that do).
struct FacingLanes {
  unsigned front, back;
};

// (Each lane mayTouch's arithmetic, operation for operation, so the same
// answers; a twin's normal . dir is exactly the lane's negated, its bounds
// the same.)
[[gnu::noinline]] FacingLanes blockFacing(TraceWork& tw, const CullBlock& b) {
  if (!tw.heartPlanesMade) makeTranslationHeartPlanes(tw);
  // Back faces: normal . dir > 0 (a twin's: normal . dir < 0).
  const F4 facing = F4::load(b.normal[0]) * F4::all(tw.dir.x) + F4::load(b.normal[1]) * F4::all(tw.dir.y) +
                    F4::load(b.normal[2]) * F4::all(tw.dir.z);
  // The heart planes.
  F4 centre[3], reach[3];
  blockBoxes(b, centre, reach);
  const F4 far = boxesBeyondPlane(centre, reach, tw.heartPlane1, tw.maxDistFromHeartPlane1) |
                 boxesBeyondPlane(centre, reach, tw.heartPlane2, tw.maxDistFromHeartPlane2);
  return {~simd::bits(far | (facing > F4::zero())) & 0xFu, ~simd::bits(far | (facing < F4::zero())) & 0xFu};
}

unsigned blockFacesPass(TraceWork& tw, const CullBlock& b) { return blockFacing(tw, b).front; }

}  // namespace

// translateTrmThroughPolygons for a node of a model with query data: the
// culls four polygons at a time from the cull blocks of the node's entries
// of polygonRefs (the first and last block may hold other nodes' entries:
// those lanes are masked off), then the polygons past them in list order.
// Only those are marked: a polygon culled here and listed at another node is
// culled there again (the culls only get stricter as the bounds shrink), so
// the polygons tested, and their order, are those of
// translateTrmThroughPolygons.
/// What the translation adds to walkCullBlocks: the back-face and heart-plane
/// culls, the polygon test, and bounds that shrink at a hit.
struct TranslationCullBlocks {
  static constexpr bool kShrinks = true;
  static unsigned blockPass(TraceWork& tw, const CullBlock& b) { return blockFacesPass(tw, b); }
  static bool test(TraceWork& tw, std::int32_t polyNum, const CmPolygon& poly) {
    return translateTrmThroughPolygon(tw, polyNum, poly);
  }
};

bool translateTrmThroughCullBlocks(TraceWork& tw, const QueryData& d, const CmNode& node) {
  return walkCullBlocks<TranslationCullBlocks>(tw, d, node);
}

namespace {

// The lanes of a leaf whose polygon's plane the trace bounds straddle
// (cullByPolygonPlane's Cross: Bounds::planeSide's arithmetic in each lane,
// operation for operation); every lane for a convex model, where the plane
// test may also end the walk (translateTrmThroughPolygon makes it).
unsigned leafPlanesCrossed(const TraceWork& tw, const BvhLeaf& b) {
  if (tw.model.isConvex()) return 0xFu;
  const Vec3 c = tw.bounds.center();
  const Vec3 reach = tw.bounds.max - c;
  const F4 nx = F4::load(b.normal[0]), ny = F4::load(b.normal[1]), nz = F4::load(b.normal[2]);
  const F4 d1 = nx * F4::all(c.x) + ny * F4::all(c.y) + nz * F4::all(c.z) - F4::load(b.dist);
  const F4 d2 =
      simd::abs(F4::all(reach.x) * nx) + simd::abs(F4::all(reach.y) * ny) + simd::abs(F4::all(reach.z) * nz);
  const F4 epsilon = F4::all(tol::kOnEpsilon);
  const F4 culled = (d1 - d2 > epsilon) | (d1 + d2 < simd::negate(epsilon));
  return ~simd::bits(culled) & 0xFu;
}

}  // namespace

bool translateTrmThroughBvhLeaf(TraceWork& tw, const PolygonBvh& bvh, std::size_t leaf, unsigned pass) {
  const BvhLeaf& b = bvh.leaves[leaf];
  pass &= leafPlanesCrossed(tw, b);
  if (!pass) return false;
  // Each lane's polygon if it faces the move, its twin if that does (both
  // when the move runs along their plane), in lane order.
  const FacingLanes facing = blockFacing(tw, b);
  unsigned front = pass & facing.front, back = pass & facing.back & b.twinLanes();
  // The lanes' edge uses, asked for together (each polygon's test waits for
  // its own first: this overlaps the waits of the lanes after the first).
  const BvhLeaf::UseStarts uses = b.useStarts();
  // (A twin's corners: stored after its polygon's, or made from them.)
  const auto cornersOf = [&](std::size_t lane, bool twin) {
    return bvh.uses.data() + (twin && !b.twinMade(lane) ? uses.twinOf(lane) : uses.of(lane));
  };
  for (unsigned lanes = front | back; lanes; lanes &= lanes - 1) {
    const std::size_t lane = std::size_t(std::countr_zero(lanes));
    prefetch(cornersOf(lane, !((front >> lane) & 1u)));
  }
  // A polygon's tests; false when the query is over (blocked completely).
  // The trace bounds shrank at a hit: the lanes left are culled again.
  // What the tests read of the polygon, the leaf holds (not the model's
  // record, read at random): its plane (a twin's exactly negated), contents,
  // material, edge count and edge uses; not its bounds, which a
  // translation's tests do not read past the culls.
  const auto test = [&](std::size_t lane, bool twin) {
    CmPolygon poly;
    const Real sign = twin ? Real(-1) : Real(1);
    poly.plane.normal = {sign * b.normal[0][lane], sign * b.normal[1][lane], sign * b.normal[2][lane]};
    poly.plane.dist = sign * b.dist[lane];
    poly.contents = b.contents[lane];
    poly.material = twin ? b.twinMaterial[lane] : b.material[lane];
    poly.numEdges = b.numEdges[lane];
    const std::int32_t polyNum = twin ? b.twin[lane] : b.polygonAt(lane);
    const Real before = tw.fraction;
    bool blocked;
    if (twin && b.twinMade(lane)) {  // (the twin's corners made from its polygon's)
      PolygonCorner made[BvhLeaf::kMaxMadeTwinEdges];
      b.twinCorners(lane, cornersOf(lane, false), made);
      blocked = translateTrmThroughPolygon(tw, polyNum, poly, made);
    } else {
      blocked = translateTrmThroughPolygon(tw, polyNum, poly, cornersOf(lane, twin));
    }
    if (blocked) return false;
    if (tw.fraction != before && (front | back)) {
      const BoundsLanes bounds(tw);
      const unsigned left = bounds.pass(b) & leafPlanesCrossed(tw, b);
      front &= left;
      back &= left;
    }
    return true;
  };
  while (front | back) {
    const int lane = std::countr_zero(front | back);
    const unsigned bit = 1u << lane;
    if (front & bit) {
      front &= ~bit;
      if (!test(std::size_t(lane), false)) return true;
    }
    if (back & bit) {
      back &= ~bit;
      if (!test(std::size_t(lane), true)) return true;
    }
  }
  return false;
}
#endif

bool translatePointThroughBvhLeaf(TraceWork& tw, const PolygonBvh& bvh, std::size_t leaf, unsigned pass) {
  const BvhLeaf& b = bvh.leaves[leaf];
  const unsigned twins = b.twinLanes();
  while (pass) {
    const std::size_t lane = std::size_t(std::countr_zero(pass));
    pass &= pass - 1;
    std::int32_t polyNum = b.polygonAt(lane);
    if (pointThroughPolygon(tw, polyNum, tw.model.polygons()[std::size_t(polyNum)])) return true;
    if (!(twins >> lane & 1u)) continue;
    polyNum = b.twin[lane];  // (the polygon or its twin faces away: its cull)
    if (pointThroughPolygon(tw, polyNum, tw.model.polygons()[std::size_t(polyNum)])) return true;
  }
  return false;
}

bool translateTrmThroughNode(TraceWork& tw, const CmNode& node) {
#ifdef CMKIT_CULL_LANES
  if (tw.queryData) return translateTrmThroughCullBlocks(tw, *tw.queryData, node);
#endif
  return translateTrmThroughPolygons(tw, tw.model.polygonsAt(node));
}

bool translateTrmThroughPolygons(TraceWork& tw, std::span<const std::int32_t> polygons) {
  QueryScratch& s = tw.scratch;
  // The culls' loads, started together (a mispredicted cull would otherwise
  // hold up the next polygon's).
  for (const std::int32_t polyNum : polygons) prefetch(&tw.model.polygons()[std::size_t(polyNum)]);
  return forEachNewItem(s, s.polygonChecked, &QueryStats::polygonsMet, polygons, [&](std::int32_t polyNum) {
    const CmPolygon& poly = tw.model.polygons()[std::size_t(polyNum)];
    return mayTouch(tw, poly) && translateTrmThroughPolygon(tw, polyNum, poly);
  });
}

}  // namespace cmkit::detail
