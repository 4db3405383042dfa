// Translation tests of one model polygon (the original's
// TranslateTrmThroughPolygon and the tests it runs): trace-model vertex
// through polygon, trace-model edge through polygon edge, model vertex
// through trace-model polygon; a point's test. Model space throughout.
// Which polygons a translation tests (the culls, through the BSP tree's
// nodes or the polygon hierarchy's leaves) is translate_culls.cpp's.
#include <algorithm>
#include <bit>
#include <cmath>

#include "query/edge_sides.h"
#include "query/polygon_edges.h"
#include "query/trace_work.h"

// With float lanes (CMKIT_QUERY_LANES: SSE2, a float build) the edge sides
// of the common small cases come as one word of slots (edge_sides.h); any
// other build takes the general masks, which give the same pairs.

namespace cmkit::detail {
namespace {

/// Fraction of the move a-> b at which a point first gets within
/// tol::kClipEpsilon of the plane, approaching from the front; 1 when it
/// does not (ends farther than the epsilon, starts behind, or moves away).
/// May be negative when the start is already within the epsilon.
/// (Inline, as modelVertexSide: GCC otherwise calls both out of line from
/// every vertex test and edge pair, ~1-2% of a translation.)
inline Real translationPlaneFraction(const Plane& plane, const Vec3& a, const Vec3& b) {
  const Real d2 = plane.distance(b);
  if (!signBitSet(d2 - tol::kClipEpsilon)) return 1;
  const Real d1 = plane.distance(a);
  if (signBitSet(d1)) return 1;  // behind (or -0)
  if (d1 - d2 <= 0) return 1;    // not approaching
  return (d1 - tol::kClipEpsilon) / (d1 - d2);
}

/// Fraction at which the trace-model edge line l1, moving along the
/// direction encoded in `cross`, meets the line l2. False when the moving
/// line stays parallel to l2.
bool translateEdgeThroughEdge(const Vec3& cross, const Pluecker& l1, const Pluecker& l2, Real& fraction) {
  const Real d = l2[4] * cross[0] + l2[5] * cross[1] + l2[2] * cross[2];
  if (d == 0) {
    fraction = 0;
    return false;
  }
  const Real t = -l1.permutedInnerProduct(l2);
  if (t == 0) {  // the lines meet at the start already
    fraction = 0;
    return true;
  }
  fraction = t / d;
  return true;
}

void setContact(TraceWork& tw, const CmPolygon& poly, ContactType type, std::int32_t modelFeature,
                int trmFeature) {
  tw.c.contents = poly.contents;
  tw.c.material = poly.material;
  tw.c.type = type;
  tw.c.modelFeature = modelFeature;
  tw.c.trmFeature = trmFeature;
}

}  // namespace

void translatePointThroughPolygon(TraceWork& tw, std::int32_t polyNum, const CmPolygon& poly) {
  const CollisionModel& m = tw.model;
  const WorkVertex& v = tw.vertices[0];
  const Real f = translationPlaneFraction(poly.plane, v.p, v.endp);
  if (!(f < tw.fraction)) return;
  for (std::int32_t edgeNum : m.edgesOf(poly)) {
    const Real product = modelEdgeLine(m, std::size_t(std::abs(edgeNum))).permutedInnerProduct(v.pl);
    if (unsigned(edgeNum < 0) ^ unsigned(signBitSet(product))) return;  // passes the edge on the outside
  }
  tw.fraction = f < 0 ? Real(0) : f;
  tw.c.normal = poly.plane.normal;
  tw.c.dist = poly.plane.dist;
  tw.c.point = v.p + (v.endp - v.p) * tw.fraction;
  setContact(tw, poly, ContactType::TrmVertex, polyNum, 0);
  if (tw.gettingContacts()) tw.addContact();
}

namespace {

// A trace-model vertex reaches the polygon at fraction f: the nearest hit so
// far. (The hits are out of line, kept off the tests' path: most tested
// features hit nothing.)
[[gnu::cold, gnu::noinline]] void hitByTrmVertex(TraceWork& tw, std::int32_t polyNum, const CmPolygon& poly,
                                                 int vertexNum, Real f) {
  WorkVertex& v = tw.vertices[std::size_t(vertexNum)];
  tw.fraction = f < 0 ? Real(0) : f;
  tw.c.normal = poly.plane.normal;
  tw.c.dist = poly.plane.dist;
  tw.c.point = v.p + (v.endp - v.p) * tw.fraction;
  setContact(tw, poly, ContactType::TrmVertex, polyNum, vertexNum);
  if (tw.gettingContacts()) {
    tw.addContact();
    v.used = false;  // one contact per trace-model vertex is enough
  }
}

// The trace-model vertices through a polygon, in vertex order: those whose
// paths pass inside every polygon edge (`inside`, from sidesOfPolygonEdges)
// and reach the plane before the nearest hit so far.
void translateTrmVerticesThroughPolygon(TraceWork& tw, std::int32_t polyNum, const CmPolygon& poly,
                                        std::uint32_t inside) {
  count(tw.scratch, &QueryStats::vertexTests, unsigned(std::popcount(tw.movingVertices)));
  for (; inside; inside &= inside - 1) {
    const int vertexNum = std::countr_zero(inside);
    WorkVertex& v = tw.vertices[std::size_t(vertexNum)];
    if (!v.used) continue;
    const Real f = translationPlaneFraction(poly.plane, v.p, v.endp);
    if (!(f < tw.fraction)) continue;
    hitByTrmVertex(tw, polyNum, poly, vertexNum, f);
  }
}

// Which side of trace-model edge te's line the path of a model vertex
// (moving by -dir relative to the trace model) passes: the sign bit of
// te's line . the path's line, always in this order, so that the edge pair
// and the vertex tests agree on every vertex. Computed each time: a
// per-vertex cache cost more (a scattered load and its bookkeeping) than
// the two products.
inline unsigned modelVertexSide(const WorkEdge& te, const Pluecker& path) {
  return unsigned(signBitSet(te.pl.permutedInnerProduct(path)));
}
inline unsigned modelVertexSide(const WorkEdge& te, const Vec3& vertex, const Vec3& dir) {
  return modelVertexSide(te, Pluecker::fromRay(vertex, -dir));
}

// Trace-model edge trmEdgeNum meets model edge edgeNum (of poly) at fraction
// f2: the nearest hit so far.
[[gnu::cold, gnu::noinline]] void hitByEdge(TraceWork& tw, const CmPolygon& poly, std::int32_t edgeNum,
                                            int trmEdgeNum, Real f2) {
  const CollisionModel& m = tw.model;
  const WorkEdge& te = tw.edges[std::size_t(trmEdgeNum)];
  const CmEdge& edge = m.edges()[std::size_t(std::abs(edgeNum))];
  const Vec3& start = m.vertices()[std::size_t(edge.vertex[0])];
  const Vec3& end = m.vertices()[std::size_t(edge.vertex[1])];
  tw.fraction = f2;
  // Contact plane: through the model edge, orthogonal to both edges, facing the trm.
  Vec3 normal = (end - start).cross(te.end - te.start);
  normal.normalize();
  Real dist = normal.dot(start);
  if (normal.dot(te.start) - dist < 0) {
    normal = -normal;
    dist = -dist;
  }
  tw.c.normal = normal;
  tw.c.dist = dist;
  // Contact point on the model edge: where the plane swept by the trm edge cuts it.
  const Vec3 sweepNormal{te.cross[2], -te.cross[1], te.cross[0]};
  const Real sweepDist = sweepNormal.dot(te.start);
  const Real d1 = sweepNormal.dot(start) - sweepDist;
  const Real d2 = sweepNormal.dot(end) - sweepDist;
  const Real t = std::fabs(d1 - d2) > std::numeric_limits<Real>::epsilon() ? d1 / (d1 - d2) : Real(0);
  tw.c.point = start + (end - start) * t;
  setContact(tw, poly, ContactType::Edge, edgeNum, trmEdgeNum);
  if (tw.gettingContacts()) tw.addContact();
}

// Trace-model edge trmEdgeNum against edge i of the polygon (from v1 to v2
// in the polygon's order), whose line both pairs of vertices pass on
// different sides: where they meet.
[[gnu::noinline]] void translateTrmEdgeThroughCrossedEdge(TraceWork& tw, const CmPolygon& poly,
                                                          const PolygonEdges& edges, int trmEdgeNum,
                                                          std::size_t i, const Vec3& v1, const Vec3& v2) {
  const CollisionModel& m = tw.model;
  const WorkEdge& te = tw.edges[std::size_t(trmEdgeNum)];
  const std::int32_t edgeNum = edges.edgeNum(i);
  const auto [start, end] = swappedIf(edgeNum < 0, v1, v2);  // (the edge's stored direction)
  Real f1;
  if (!translateEdgeThroughEdge(te.cross, te.pl, edges.line(i), f1)) return;
  if (f1 < 0) return;  // moving away from the edge
  // The same against the edge moved out along its normal by the clip epsilon.
  const CmEdge& edge = m.edges()[std::size_t(std::abs(edgeNum))];
  const Pluecker epsPl =
      Pluecker::fromLine(start + edge.normal * tol::kClipEpsilon, end + edge.normal * tol::kClipEpsilon);
  Real f2;
  if (!translateEdgeThroughEdge(te.cross, te.pl, epsPl, f2)) return;
  if (f2 > 1 || f1 < f2) return;
  if (f2 < 0) f2 = 0;
  if (!(f2 < tw.fraction)) return;

  hitByEdge(tw, poly, edgeNum, trmEdgeNum, f2);
}

// Trace-model edge trmEdgeNum against edge i of the polygon, whose line
// its two vertices pass on different sides. (The polygon edge's side test
// inline: about half the pairs end there.)
inline void translateTrmEdgeThroughEdge(TraceWork& tw, const CmPolygon& poly, const PolygonEdges& edges,
                                        int trmEdgeNum, std::size_t i) {
  count(tw.scratch, &QueryStats::edgePairs);
  const WorkEdge& te = tw.edges[std::size_t(trmEdgeNum)];
  // The polygon edge's two vertices must pass the trm edge on different sides.
  const Vec3& v1 = edges.from(i);
  const Vec3& v2 = edges.to(i);
  if (modelVertexSide(te, v1, tw.dir) == modelVertexSide(te, v2, tw.dir)) return;
  translateTrmEdgeThroughCrossedEdge(tw, poly, edges, trmEdgeNum, i, v1, v2);
}

/// The pairs of one mask of polygon edges: each moving trace-model edge's
/// crossed polygon edges (crossed(te), a mask) found first, without a branch
/// per trace-model edge (most edges cross none of a polygon's edge lines,
/// unpredictably), then tested trace-model edge by edge, bit b of a mask
/// standing for polygon edge edgeOf(b).
template <class Crossed, class EdgeOf>
void testCrossedEdgePairs(TraceWork& tw, const CmPolygon& poly, const PolygonEdges& edges, Crossed crossed,
                          EdgeOf edgeOf) {
  std::uint64_t crossing[kMaxTrmEdges + 1];
  std::uint8_t crossingEdge[kMaxTrmEdges + 1];
  std::size_t n = 0;
  for (std::uint64_t moving = tw.movingEdges; moving; moving &= moving - 1) {
    const int e = std::countr_zero(moving);
    const std::uint64_t c = crossed(tw.edges[std::size_t(e)]);
    crossing[n] = c;
    crossingEdge[n] = std::uint8_t(e);
    n += c != 0;
  }
  for (std::size_t k = 0; k < n; ++k)
    for (std::uint64_t c = crossing[k]; c; c &= c - 1)
      translateTrmEdgeThroughEdge(tw, poly, edges, crossingEdge[k], edgeOf(std::countr_zero(c)));
}

// The moving trace-model edges against the polygon edges to test, trace-model
// edge by edge, each against the polygon edges whose line its two vertices
// pass on different sides, in their order (testCrossedEdgePairs, group by
// group of the per-vertex masks).
void translateTrmEdgesThroughPolygon(TraceWork& tw, const CmPolygon& poly, const PolygonEdges& edges) {
  const QueryScratch& s = tw.scratch;
  const std::size_t groups = edgeGroups(edges.size);
  for (std::size_t g = 0; g < groups; ++g) {
    const std::uint64_t* sides = &s.vertexEdgeSides[g * kMaxTrmVertices];
    const std::uint64_t toTest = s.edgesToTest[g];
    testCrossedEdgePairs(
        tw, poly, edges,
        [sides, toTest](const WorkEdge& te) {
          return (sides[std::size_t(te.vertexNum[0])] ^ sides[std::size_t(te.vertexNum[1])]) & toTest;
        },
        [first = g * kEdgeGroup](int b) { return first + std::size_t(b); });
  }
}

// A model vertex (at p, moving to endp relative to the trace model; its
// number, the contact's feature, from its edge's record) reaches trace-model
// polygon trmPolyNum at fraction f: the nearest hit so far.
[[gnu::cold, gnu::noinline]] void hitByModelVertex(TraceWork& tw, const CmPolygon& poly, int trmPolyNum,
                                                   ModelVertexRef vertex, const Vec3& p, const Vec3& endp,
                                                   Real f) {
  const std::size_t vertexNum = modelVertexNumber(tw.model, vertex);
  const WorkPolygon& tp = tw.polys[std::size_t(trmPolyNum)];
  tw.fraction = f < 0 ? Real(0) : f;
  tw.c.normal = -tp.plane.normal;
  tw.c.dist = -tp.plane.dist;
  // The original reports the vertex moved back by the fraction: the model
  // vertex relative to the trace model at its start (see docs/fidelity.md).
  tw.c.point = p + (endp - p) * tw.fraction;
  setContact(tw, poly, ContactType::ModelVertex, std::int32_t(vertexNum), trmPolyNum);
  if (tw.gettingContacts()) tw.addContact();
}

// The last of a polygon's tests (below).
bool testModelVerticesThroughTrm(TraceWork& tw, const CmPolygon& poly, const PolygonEdges& edges);

#ifdef CMKIT_QUERY_LANES
// translateTrmEdgesThroughPolygon for the small path: a trace-model edge
// crosses polygon edge i's line when its vertices' bits in slot i differ
// (shifted down by a vertex number, slot i's bit lands at its first bit, the
// slots above landing above it); `toTest` has slot i's first bit for each
// edge to test. The same pairs in the same order.
template <unsigned kShift>
void translateTrmEdgesThroughSmallPolygon(TraceWork& tw, const CmPolygon& poly, const PolygonEdges& edges,
                                          const SmallSides& sides, std::uint64_t toTest) {
  testCrossedEdgePairs(
      tw, poly, edges,
      [slots = sides.slots, toTest](const WorkEdge& te) {
        return ((slots >> te.vertexNum[0]) ^ (slots >> te.vertexNum[1])) & toTest;
      },
      [](int b) { return std::size_t(b) >> kShift; });
}

/// The polygon's tests on the small path (slots of 1 << kShift bits); true
/// when it blocks completely.
template <unsigned kShift>
bool translateTrmThroughSmallPolygon(TraceWork& tw, std::int32_t polyNum, const CmPolygon& poly,
                                     const PolygonEdges& edges) {
  const QueryScratch& s = tw.scratch;
  const SmallSides sides = sidesOfSmallPolygonEdges<kShift>(tw, edges);
  std::uint64_t toTest = 0;  // slot i's first bit: edge i (as the general path's masks)
  if (tw.numEdges > 0)
    for (std::size_t i = 0; i < edges.size; ++i) {
      const std::size_t e = std::size_t(std::abs(edges.edgeNum(i)));
      toTest |= std::uint64_t(unsigned(!s.isChecked(s.edgeChecked, e)) & unsigned(!edges.internal(i)))
                << (i << kShift);
    }
  translateTrmVerticesThroughPolygon(tw, polyNum, poly, sides.inside);
  if (toTest) translateTrmEdgesThroughSmallPolygon<kShift>(tw, poly, edges, sides, toTest);
  return testModelVerticesThroughTrm(tw, poly, edges);
}
#endif

// (The vertex's path line only for a trace-model polygon it reaches in time:
// most reach none.)
void translateVertexThroughTrmPolygon(TraceWork& tw, const CmPolygon& poly, int trmPolyNum,
                                      ModelVertexRef vertex, const Vec3& p, const Vec3& endp) {
  QueryScratch& s = tw.scratch;
  count(s, &QueryStats::vertexTests);
  const WorkPolygon& tp = tw.polys[std::size_t(trmPolyNum)];
  const Real f = translationPlaneFraction(tp.plane, p, endp);
  if (!(f < tw.fraction)) return;
  const Pluecker pl = Pluecker::fromRay(p, -tw.dir);
  for (int i = 0; i < tp.source->numEdges; ++i) {
    const int edgeNum = tp.source->edges[std::size_t(i)];
    const WorkEdge& te = tw.edges[std::size_t(std::abs(edgeNum))];
    if (unsigned(edgeNum < 0) ^ modelVertexSide(te, pl)) return;
  }
  hitByModelVertex(tw, poly, trmPolyNum, vertex, p, endp, f);
}

}  // namespace

void shrinkTraceBounds(TraceWork& tw) {
  if (tw.fraction < 1 && !tw.gettingContacts()) {
    const Vec3 endp = tw.start + tw.dir * tw.fraction;
    for (int i = 0; i < 3; ++i) {  // (as in the set-up: min/max, not branches)
      tw.bounds.min[i] = std::min(tw.start[i], endp[i]) + tw.size.min[i] - tol::kBoxEpsilon;
      tw.bounds.max[i] = std::max(tw.start[i], endp[i]) + tw.size.max[i] + tol::kBoxEpsilon;
    }
  }
}

namespace {

// The moving features' data that only a polygon past its culls needs, once
// per query: the vertices' paths, the edges' vertex numbers, lines and sweep
// directions, the front polygons' planes.
void placeTranslationFeatures(TraceWork& tw) {
  if (tw.featuresPlaced) return;
  tw.featuresPlaced = true;
#ifdef CMKIT_QUERY_LANES
  placeVertexLines(tw);  // (WorkVertex::pl unused: the edge sides read the lanes)
#else
  for (std::uint32_t moving = tw.movingVertices; moving; moving &= moving - 1) {
    WorkVertex& v = tw.vertices[std::size_t(std::countr_zero(moving))];
    v.pl = Pluecker::fromRay(v.p, tw.dir);
  }
#endif
  const TraceModel& trm = *tw.placedTrm;
  for (std::uint64_t moving = tw.movingEdges; moving; moving &= moving - 1) {
    const int i = std::countr_zero(moving);
    WorkEdge& e = tw.edges[std::size_t(i)];
    e.vertexNum[0] = trm.edgeVertex(i, 0);
    e.vertexNum[1] = trm.edgeVertex(i, 1);
    // (Locals: read back through e, the ends would be reloaded after every
    // store, the compiler assuming the arrays may overlap.)
    const Vec3 start = tw.vertices[std::size_t(e.vertexNum[0])].p;
    const Vec3 end = tw.vertices[std::size_t(e.vertexNum[1])].p;
    e.start = start;
    e.end = end;
    e.pl = Pluecker::fromLine(start, end);
    const Vec3 a = start - end;
    e.cross = {a[0] * tw.dir[1] - a[1] * tw.dir[0], a[0] * tw.dir[2] - a[2] * tw.dir[0],
               a[1] * tw.dir[2] - a[2] * tw.dir[1]};
  }
  for (std::uint32_t moving = tw.movingPolygons; moving; moving &= moving - 1) {
    WorkPolygon& wp = tw.polys[std::size_t(std::countr_zero(moving))];
    wp.plane.fitThroughPoint(tw.vertices[std::size_t(wp.planeVertex)].p);
  }
}

}  // namespace

bool translateTrmThroughPolygon(TraceWork& tw, std::int32_t polyNum, const CmPolygon& poly,
                                const PolygonCorner* corners) {
  if (const PlaneCull cull = cullByPolygonPlane(tw, poly.plane); cull != PlaneCull::Test)
    return cull == PlaneCull::Stop;
  count(tw.scratch, &QueryStats::polygonsTested);
  // (Counts the polygon when its tests bring the nearest contact closer:
  // only in a QueryStats build, where countCloser does anything.)
  const Real before = tw.fraction;
  const std::size_t contactsBefore = contactCount(tw);
  const auto finish = [&](bool blocked) {
    countCloser(tw, before, contactsBefore);
    return blocked;
  };
  QueryScratch& s = tw.scratch;
  placeTranslationFeatures(tw);
  // The sides of the polygon's edge lines the trace-model vertices pass.
  const PolygonEdges edges = corners ? polygonEdges(tw, corners, poly.numEdges) : polygonEdges(tw, poly);
#ifdef CMKIT_QUERY_LANES
  switch (smallSidesShift(tw, edges.size)) {
    case 3:
      return finish(translateTrmThroughSmallPolygon<3>(tw, polyNum, poly, edges));
    case 4:
      return finish(translateTrmThroughSmallPolygon<4>(tw, polyNum, poly, edges));
    default:
      break;
  }
#endif
  const std::uint32_t inside = sidesOfPolygonEdges(tw, edges);
  // The polygon edges the trace-model edges are tested against: not
  // internal, not tested with an earlier polygon (the marks are set below,
  // after the edge tests, so these masks hold for every trace-model edge).
  bool anyToTest = false;
  if (tw.numEdges > 0) {
    for (std::size_t first = 0; first < edges.size; first += kEdgeGroup) {
      std::uint64_t toTest = 0;
      for (std::size_t i = first; i < std::min(first + kEdgeGroup, edges.size); ++i) {
        const std::size_t e = std::size_t(std::abs(edges.edgeNum(i)));
        // (& not &&: whether an edge was met before is unpredictable.)
        toTest |= std::uint64_t(unsigned(!s.isChecked(s.edgeChecked, e)) & unsigned(!edges.internal(i)))
                  << (i - first);
      }
      s.edgesToTest[first / kEdgeGroup] = toTest;
      anyToTest |= toTest != 0;
    }
  }

  translateTrmVerticesThroughPolygon(tw, polyNum, poly, inside);
  if (anyToTest) translateTrmEdgesThroughPolygon(tw, poly, edges);
  return finish(testModelVerticesThroughTrm(tw, poly, edges));
}

namespace {

// The last of a polygon's tests: the model vertices through the trace
// model's front polygons; then the bounds shrink to a nearer hit. True when
// the polygon blocks completely.
bool testModelVerticesThroughTrm(TraceWork& tw, const CmPolygon& poly, const PolygonEdges& edges) {
  // Model vertices through the trace model's front polygons. A vertex
  // farther from a heart plane than its limit is left out: its path (along
  // the move, so parallel to both planes) stays at that distance, and every
  // point of a front polygon is within the farthest moving vertex's distance,
  // a kBoxEpsilon (one unit) short of the limit, so the path meets none of
  // them (the margin dwarfs the rounding of the side products). On the shared
  // reference translations this leaves out one test in eight of a model vertex
  // against a front polygon (a plane fraction and its unpredictable branch):
  // translations about 1.02x-1.03x with bench/ab.py. (Every caller's culls
  // made the heart planes already; the guard keeps this cull from ever
  // reading planes not made.)
  if (!tw.heartPlanesMade) makeTranslationHeartPlanes(tw);
  forEachNewModelVertex(tw, edges, [&](ModelVertexRef vn, const Vec3& p) {
    // (| not ||: which vertices are left out is unpredictable.)
    if (int(std::fabs(tw.heartPlane1.distance(p)) > tw.maxDistFromHeartPlane1) |
        int(std::fabs(tw.heartPlane2.distance(p)) > tw.maxDistFromHeartPlane2))
      return;
    const Vec3 endp = p - tw.dir;
    for (std::uint32_t moving = tw.movingPolygons; moving; moving &= moving - 1)
      translateVertexThroughTrmPolygon(tw, poly, std::countr_zero(moving), vn, p, endp);
  });

  shrinkTraceBounds(tw);
  return tw.fraction == 0;
}

}  // namespace

}  // namespace cmkit::detail
