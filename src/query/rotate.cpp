// Rotation tests of one model polygon (the original's RotateTrmThroughPolygon
// and the tests it runs): trace-model vertex through polygon, trace-model
// edge through model edge, model vertex through trace-model polygon. Every
// test is solved exactly in the tangent of half the angle (see
// rotate_work.h); model frame throughout.
//
// Unlike the original, the edge-edge and model-vertex tests of a model edge
// run with the first polygon that reaches it through culls that are valid for
// the edge itself, so the result does not depend on polygon order. The boxes
// of the arcs and the feature-box culls are rotate_boxes.cpp's; the
// edge-edge test is rotate_edges.cpp's.
#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <numbers>
#include <type_traits>

#include "query/cull_lanes.h"
#include "query/polygon_edges.h"
#include "query/rotate_edges.h"
#include "query/rotate_work.h"

#include "util/simd.h"

namespace cmkit::detail {
namespace {

constexpr double kPi = std::numbers::pi;

/// The sinusoid of the signed distance of point p (turning about the circle
/// centre `ro`, direction `sign`) to the plane n.x = dist.
Sinusoid pointPlaneSinusoid(const Vec3& p, const Vec3& ro, const Vec3& axis, double sign, const Vec3& n,
                            double dist) {
  const DVec nd(n), v = DVec(p) - DVec(ro);
  Sinusoid s;
  s.v0 = nd.dot(DVec(ro)) - dist;
  s.v2 = nd.dot(v);
  s.v1 = -sign * nd.dot(DVec(axis).cross(v));
  return s;
}

/// The original's RotatePointThroughEpsilonPlane: when does p (turning in
/// direction `sign` about its circle centre `ro`) first get within
/// tol::kClipEpsilon of the front of `plane`? Gives the tangent, the point
/// there and its direction of motion.
bool rotatePointThroughEpsilonPlane(const RotationWork& rw, const Vec3& p, const Vec3& endp, const Vec3& ro,
                                    Real sign, const Plane& plane, double& u, Vec3& point, Vec3& dir) {
  const double epsDist = double(plane.dist) + double(tol::kClipEpsilon);
  const DVec n(plane.normal);
  // The circle cannot reach the epsilon plane.
  const double dOrigin = n.dot(DVec(ro)) - epsDist;
  const DVec v = DVec(p) - DVec(ro);
  if (dOrigin * dOrigin > v.dot(v)) return false;
  // Moving away at the start, and ending in front or moving away at the end
  // too: the distance (one hump below 180 degrees) never comes down through
  // the epsilon plane.
  const Vec3 startDir = (p - ro).cross(rw.axis) * sign;
  if (startDir.dot(plane.normal) >= 0) {
    if (double(plane.normal.dot(endp)) - epsDist >= 0) return false;
    const Vec3 endDir = (endp - ro).cross(rw.axis) * sign;
    if (endDir.dot(plane.normal) > 0) return false;
  }
  const Sinusoid s = pointPlaneSinusoid(p, ro, rw.axis, sign, plane.normal, epsDist);
  if (s.v0 + s.v2 <= double(tol::kPluckerRangeEpsilon)) {
    // Already within the epsilon range: moving toward the plane stops at
    // once; moving away, the point can only come back after its furthest.
    if (s.v1 <= 0) {
      u = 0;
    } else {
      const double furthest = firstExtremumTan(s.v1, s.v2);
      if (!(furthest < rw.maxTan)) return false;
      if (!sinusoidRoot(s, furthest, rw.maxTan, u)) return false;
    }
  } else if (!sinusoidRoot(s, 0, rw.maxTan, u)) {
    return false;
  }
  point = u == 0 ? p : rotateByTanHalf(p, rw.origin, rw.axis, double(sign) * u);
  dir = (point - ro).cross(rw.axis) * sign;
  return true;
}

/// True when the line through `point` along `dir` passes inside every edge
/// line (forward edges: product not negative; reversed: not positive).
template <class EdgeLine>
bool rayInsideEdges(const Vec3& point, const Vec3& dir, int numEdges, EdgeLine edgeLine) {
  const Pluecker ray = Pluecker::fromRay(point, dir);
  for (int k = 0; k < numEdges; ++k) {
    bool reversed;
    const Real d = edgeLine(k, reversed).permutedInnerProduct(ray);
    if ((unsigned(reversed) & unsigned(d > 0)) | (unsigned(!reversed) & unsigned(d < 0))) return false;
  }
  return true;
}

/// `edgeLinesSet`: the polygon's edge lines are in the scratch already (they
/// are made when a vertex first reaches the polygon's plane in time).
void rotateTrmVertexThroughPolygon(TraceWork& tw, RotationWork& rw, std::int32_t polyNum,
                                   const CmPolygon& poly, int vertexNum, bool& edgeLinesSet) {
  count(tw.scratch, &QueryStats::vertexTests);
  const WorkVertex& v = tw.vertices[std::size_t(vertexNum)];
  const RotVertex& rv = rw.vertices[std::size_t(vertexNum)];
  double u;
  Vec3 point, dir;
  if (!rotatePointThroughEpsilonPlane(rw, v.p, v.endp, rv.rotationOrigin, rw.sign, poly.plane, u, point, dir))
    return;
  if (!(u < rw.maxTan)) return;
  const auto edges = tw.model.edgesOf(poly);
  QueryScratch& s = tw.scratch;
  if (!edgeLinesSet) {
    setPolygonEdgeLines(tw, poly);
    edgeLinesSet = true;
  }
  if (!rayInsideEdges(point, dir, int(edges.size()), [&](int k, bool& reversed) -> const Pluecker& {
        reversed = edges[std::size_t(k)] < 0;
        return s.polygonEdgeLines[std::size_t(k)];
      }))
    return;
  rw.maxTan = u;
  setRotationContact(tw, poly, ContactType::TrmVertex, poly.plane.normal, poly.plane.dist, point, polyNum,
                     vertexNum);
}

void rotateVertexThroughTrmPolygon(TraceWork& tw, RotationWork& rw, const CmPolygon& poly, int trmPolyNum,
                                   std::size_t vertexNum, const Vec3& p, const Vec3& endp, const Vec3& ro) {
  count(tw.scratch, &QueryStats::vertexTests);
  const WorkPolygon& tp = tw.polys[std::size_t(trmPolyNum)];
  double u;
  Vec3 point, dir;
  // Relative to the trace model the model vertex turns the other way.
  if (!rotatePointThroughEpsilonPlane(rw, p, endp, ro, -rw.sign, tp.plane, u, point, dir)) return;
  if (!(u < rw.maxTan)) return;
  rw.makeEdgeLines(tw);
  if (!rayInsideEdges(point, dir, tp.source->numEdges, [&](int k, bool& reversed) -> const Pluecker& {
        const int e = tp.source->edges[std::size_t(k)];
        reversed = e < 0;
        return tw.edges[std::size_t(std::abs(e))].pl;
      }))
    return;
  rw.maxTan = u;
  // The contact plane is the trace-model polygon's where it meets the
  // vertex, turned on by the contact angle (the original reported it at the
  // start of the rotation, which can face along the motion once the polygon
  // has turned further than the angle at which the vertex approaches it).
  // Facing the trace model: its motion at the vertex runs into the polygon.
  const Vec3 normal =
      u == 0 ? -tp.plane.normal : -rotateByTanHalf(tp.plane.normal, Vec3{}, rw.axis, rw.sign * u);
  setRotationContact(tw, poly, ContactType::ModelVertex, normal, normal.dot(p), p, std::int32_t(vertexNum),
                     trmPolyNum);
}

// Contacts mode, a polygon's tests done: its earliest contact, if it has
// one below the part's limit `limit`, is recorded with its angle, and the
// limit restored for the next polygon.
[[gnu::noinline]] void recordPolygonContact(TraceWork& tw, RotationWork& rw, std::int32_t polyNum,
                                            double limit) {
  if (rw.maxTan < limit) {
    RotationContact& found = rw.contactsFound->emplace_back();
    found.contact = tw.c;
    found.contact.angle =
        Real(double(rw.partStartAngle) + double(rw.sign) * std::atan(rw.maxTan) * 360 / kPi);
    found.polygon = polyNum;
    rw.maxTan = limit;
  }
}

// A polygon's tests are done: a hit at the very start blocks completely.
// Contacts mode: recordPolygonContact (nothing blocks: the walk goes on).
// (Always inline: GCC called it, a call for every polygon tested.)
[[gnu::always_inline]] inline bool finishPolygon(TraceWork& tw, RotationWork& rw, std::int32_t polyNum,
                                                 double limit) {
  if (rw.maxTan < limit) count(tw.scratch, &QueryStats::polygonsCloser);
  if (rw.contactsFound) {
    recordPolygonContact(tw, rw, polyNum, limit);
    return false;
  }
  if (rw.maxTan != 0) return false;
  tw.fraction = 0;
  return true;
}

}  // namespace

/// How far from zero, relative to the size of its terms, the quadratic must
/// be at both ends of an interval for firstQuadraticRoot to rule out a root
/// there without solving: a million times the rounding of those sums, so
/// that the roots computed below (accurate to about 1e-8 relative even for a
/// near-double root) could not fall inside either.
constexpr double kNoRootMargin = 1e-9;

/// x, or -x when `flip` (the sign bit flipped: exact).
inline double flipSignIf(double x, bool flip) {
  return std::bit_cast<double>(std::bit_cast<std::uint64_t>(x) ^ (std::uint64_t(flip) << 63));
}

bool firstQuadraticRoot(double a, double b, double c, double lo, double hi, double& root, double* later) {
  // Most calls have no root before hi (the nearest hit so far): the
  // quadratic keeps one sign on [lo, hi] when it has the same sign, clearly,
  // at both ends and no extremum between them (its slope a u + b has one
  // sign). Deciding that takes a few products instead of a square root and
  // two divisions. Not from a subnormal lo (the least double, just after a
  // root at 0: the rotations' second crossing of an edge pair started there
  // before it came from `later`): products of a subnormal take x86
  // processors a microcode assist each, a hundred cycles and more (lt4's
  // reference rotation at line 674 took 26 us so, 12 us solving); the roots
  // below decide those.
  if (std::isfinite(hi) && !(lo > 0 && lo < std::numeric_limits<double>::min())) {
    const double gLo = (a * lo + 2 * b) * lo + c, gHi = (a * hi + 2 * b) * hi + c;
    const double sizeLo = (std::fabs(a) * lo + 2 * std::fabs(b)) * lo + std::fabs(c);
    const double sizeHi = (std::fabs(a) * hi + 2 * std::fabs(b)) * hi + std::fabs(c);
    // (& not &&: every condition is cheap, and which hold is the data's.)
    const unsigned oneSign = unsigned(gLo * gHi > 0) & unsigned((a * lo + b) * (a * hi + b) > 0);
    if (oneSign & unsigned(std::fabs(gLo) > kNoRootMargin * sizeLo) &
        unsigned(std::fabs(gHi) > kNoRootMargin * sizeHi))
      return false;
  }
  // (After that test, which never rules a root out for a coefficient that
  // is not finite: the sizes are then infinite or NaN, and no distance is
  // greater than either.)
  if (!std::isfinite(a) || !std::isfinite(b) || !std::isfinite(c)) return false;
  double r1, r2;
  if (a == 0) {
    if (b == 0) return false;
    r1 = -c / (2 * b);
    r2 = std::numeric_limits<double>::infinity();  // the other root is at 180 degrees
  } else {
    const double disc = b * b - a * c;
    if (!(disc > 0)) return false;  // no crossing (a double root only touches)
    // q has the sign of -b and |q| >= sqrt(disc) > 0: no cancellation, no 0/0.
    // (-b + s with the sign of s flipped when b > 0, by its sign bit: -b - s
    // is -b + (-s) exactly. Not a choice, which GCC made a branch.)
    const double q = -b + flipSignIf(std::sqrt(disc), b > 0);
    r1 = q / a;
    r2 = c / q;
  }
  if (r2 < r1) std::swap(r1, r2);
  if (r1 >= lo && r1 < hi && std::isfinite(r1)) {
    root = r1;
    // (From just after r1 the other root is the first, when below hi; the
    // ends' signs there could not rule it out: the quadratic changes sign
    // at it.)
    if (later)
      *later = r2 > r1 && r2 < hi && std::isfinite(r2) ? r2 : std::numeric_limits<double>::quiet_NaN();
    return true;
  }
  if (r2 >= lo && r2 < hi && std::isfinite(r2)) {
    root = r2;
    if (later) *later = std::numeric_limits<double>::quiet_NaN();
    return true;
  }
  return false;
}

Vec3 rotateByTanHalf(const Vec3& p, const Vec3& origin, const Vec3& axis, double tanHalf) {
  const double t2 = tanHalf * tanHalf;
  const double s = 2 * tanHalf / (1 + t2);
  const double c = (1 - t2) / (1 + t2);
  const DVec a(axis);
  const DVec v = DVec(p) - DVec(origin);
  const DVec proj = a * a.dot(v);
  const DVec perp = v - proj;
  return (DVec(origin) + proj + perp * c - a.cross(perp) * s).toVec3();
}

namespace {

// Culls valid for the polygon and everything on it (its edges and vertices)
// that need nothing but its record: true when it may be touched. Inline in
// the polygon loop, so that the many polygons they reject cost no call.
inline bool rotationMayTouch(const TraceWork& tw, const CmPolygon& poly) {
  return (poly.contents & tw.contentMask) && boxesTouch(tw.bounds, poly.bounds) &&
         !boxBeyondPlane(poly.bounds, tw.heartPlane1, tw.maxDistFromHeartPlane1);
}

// A polygon past rotationMayTouch: its plane cull, then the tests of its
// features. True when it blocks completely.
bool rotateTrmThroughPolygon(TraceWork& tw, std::int32_t polyNum, const CmPolygon& poly) {
  const CollisionModel& m = tw.model;
  QueryScratch& s = tw.scratch;
  RotationWork& rw = *tw.rotation;
  if (const PlaneCull cull = cullByPolygonPlane(tw, poly.plane); cull != PlaneCull::Test)
    return cull == PlaneCull::Stop;

  const auto edges = m.edgesOf(poly);
  bool edgeLinesSet = false;
  // Contacts mode: each polygon is tested against the whole part (its
  // contact lowers maxTan only until finishPolygon restores it), with every
  // feature of its own (no model edge or vertex skipped as tested with an
  // earlier polygon).
  const bool collecting = rw.contactsFound != nullptr;
  const double limit = rw.maxTan;

  // The original's back-face culls, for a convex trace model the axis passes
  // through: the whole polygon when the trace-model centre is behind it, a
  // feature when it is behind the polygon's plane.
  const bool backCull = tw.isConvex && rw.axisIntersectsTrm(tw);
  if (backCull && poly.plane.distance(rw.centre) < 0) return false;
  count(s, &QueryStats::polygonsTested);
  std::uint32_t behind = 0;  // bit i: vertex i behind the polygon's plane (back-face cull)
  if (backCull)
    for (int i = 0; i < tw.numVerts; ++i)
      behind |= std::uint32_t(signBitSet(poly.plane.distance(tw.vertices[std::size_t(i)].p))) << i;

  // Trace-model vertices through the polygon: those whose arc box touches
  // the polygon's box and straddles its plane.
  for (std::uint32_t todo =
           rw.usedVertices & ~behind & boxesCrossing(rw.vertexBoxes, tw.numVerts, poly.bounds, poly.plane);
       todo; todo &= todo - 1)
    rotateTrmVertexThroughPolygon(tw, rw, polyNum, poly, std::countr_zero(todo), edgeLinesSet);
  if (tw.pointTrace) return finishPolygon(tw, rw, polyNum, limit);

  // Trace-model edges through the polygon's edges. A (model edge, trm edge)
  // pair is tested once per query, with the first polygon of the edge whose
  // culls let that trm edge through (the original marked the model edge
  // tested with the first polygon even when its culls had skipped trm
  // edges, so it depended on polygon order and missed collisions). The
  // tested pairs are bits of the edge's scratch entry (testedPairs).
  rw.makeEdgeBoxes(tw);
  // bit trmEdgeBit(j): trm edge j passes this polygon's culls
  std::uint32_t trmEdgesHere =
      rw.usedEdges & boxesCrossing(rw.edgeBoxes, tw.numEdges, poly.bounds, poly.plane);
  if (behind)
    for (std::uint32_t bits = trmEdgesHere; bits; bits &= bits - 1) {
      const WorkEdge& te = tw.edges[std::size_t(std::countr_zero(bits) + 1)];
      if ((behind >> te.vertexNum[0]) & (behind >> te.vertexNum[1]) & 1u)
        trmEdgesHere &= ~(std::uint32_t(1) << std::countr_zero(bits));
    }
  for (std::size_t i = 0; i < edges.size() && trmEdgesHere; ++i) {
    const std::int32_t edgeNum = edges[i];
    const std::size_t e = std::size_t(std::abs(edgeNum));
    const CmEdge& edge = m.edges()[e];
    if (edge.internal) continue;
    std::uint32_t& tested = s.testedPairs(s.edgePairs[e]);
    const std::uint32_t todo = collecting ? trmEdgesHere : trmEdgesHere & ~tested;
    if (!todo) continue;
    tested |= todo;
    const Vec3& v0 = m.vertices()[std::size_t(edge.vertex[0])];
    const Vec3& v1 = m.vertices()[std::size_t(edge.vertex[1])];
    Bounds modelEdgeBox = Bounds::ofPoint(v0);
    modelEdgeBox.addPoint(v1);
    const Vec3 shift = edge.normal * (tol::kClipEpsilon + tol::kPluckerRangeEpsilon);
    const Vec3 v0In = v0 + shift, v1In = v1 + shift;  // the far side of the band
    modelEdgeBox.addPoint(v0In);
    modelEdgeBox.addPoint(v1In);
    std::uint32_t pairs = boxesTouching(rw.edgeBoxes, todo, modelEdgeBox);
    if (!pairs) continue;
    const ModelEdgeLines lines(rw, edge, v0, v1, v0In, v1In);
    for (; pairs; pairs &= pairs - 1)
      rotateTrmEdgeThroughEdge(tw, rw, poly, edgeNum, lines, std::countr_zero(pairs) + 1);
  }

  // Model vertices through the trace model's polygons (these culls do not
  // depend on the polygon).
  auto throughTrmPolygons = [&](std::size_t vn, const Vec3& p) {
    const Vec3 ro = rw.origin + rw.axis * rw.axis.dot(p - rw.origin);
    if ((p - ro).lengthSquared() <= tol::kRotationAxisEpsilon * tol::kRotationAxisEpsilon) return;
    Vec3 endp;  // where the vertex ends: made for the first polygon past the culls (most meet none)
    bool endpSet = false;
    // The used polygons whose boxes hold the vertex, as a mask: no branch a
    // polygon on which boxes do (unpredictable), the same polygons in the
    // same order after.
    std::uint32_t inBox = 0;
    for (int j = 0; j < tw.numPolys; ++j)
      if (tw.polys[std::size_t(j)].used) inBox |= std::uint32_t(insideBox(rw.polygonBounds(tw, j), p)) << j;
    for (; inBox; inBox &= inBox - 1) {
      const int j = std::countr_zero(inBox);
      const WorkPolygon& tp = tw.polys[std::size_t(j)];
      if (backCull && tp.plane.distance(p) < 0) continue;
      if (!endpSet) {
        endp = rw.origin + (p - rw.origin) * rw.backMatrix;
        endpSet = true;
      }
      rotateVertexThroughTrmPolygon(tw, rw, poly, j, vn, p, endp, ro);
    }
  };
  if (collecting) {
    // Both ends of every edge the walk may hit (a vertex of two such edges
    // is tested twice: the second finds no earlier contact).
    for (const std::int32_t edgeNum : edges) {
      const CmEdge& edge = m.edges()[std::size_t(std::abs(edgeNum))];
      if (edge.internal) continue;
      for (const std::int32_t vn : edge.vertex) {
        const Vec3& p = m.vertices()[std::size_t(vn)];
        if (insideBox(tw.bounds, p)) throughTrmPolygons(std::size_t(vn), p);
      }
    }
  } else {
    forEachNewModelVertex(tw, edges, throughTrmPolygons);
  }
  return finishPolygon(tw, rw, polyNum, limit);
}

}  // namespace

bool rotateTrmThroughPolygons(TraceWork& tw, std::span<const std::int32_t> polygons) {
  QueryScratch& s = tw.scratch;
  return forEachNewItem(s, s.polygonChecked, &QueryStats::polygonsMet, polygons, [&](std::int32_t polyNum) {
    const CmPolygon& poly = tw.model.polygons()[std::size_t(polyNum)];
    return rotationMayTouch(tw, poly) && rotateTrmThroughPolygon(tw, polyNum, poly);
  });
}

#ifdef CMKIT_QUERY_LANES
// rotateTrmThroughPolygons for a node of a model with query data:
// rotationMayTouch's culls four polygons at a time from the node's cull
// blocks (contents and bounds of up to 16 blocks before any branch, then the
// heart plane for the blocks with a lane left), then the polygons past them
// in list order. Only those are marked: a rotation part's bounds do not
// change, so a polygon culled here is culled again at any other node that
// lists it, and the polygons tested, and their order, are those of
// rotateTrmThroughPolygons.
/// What a rotation adds to walkCullBlocks: the heart-plane cull and the
/// polygon test (a rotation part's bounds never change).
struct RotationCullBlocks {
  static constexpr bool kShrinks = false;
  static unsigned blockPass(const TraceWork& tw, const CullBlock& b) {
    simd::F4 centre[3], reach[3];
    blockBoxes(b, centre, reach);
    return ~simd::bits(boxesBeyondPlane(centre, reach, tw.heartPlane1, tw.maxDistFromHeartPlane1));
  }
  static bool test(TraceWork& tw, std::int32_t polyNum, const CmPolygon& poly) {
    return rotateTrmThroughPolygon(tw, polyNum, poly);
  }
};

bool rotateTrmThroughCullBlocks(TraceWork& tw, const QueryData& d, const CmNode& node) {
  return walkCullBlocks<RotationCullBlocks>(tw, d, node);
}
#endif

bool rotateTrmThroughNode(TraceWork& tw, const CmNode& node) {
#ifdef CMKIT_QUERY_LANES
  if (tw.queryData) return rotateTrmThroughCullBlocks(tw, *tw.queryData, node);
#endif
  return rotateTrmThroughPolygons(tw, tw.model.polygonsAt(node));
}

}  // namespace cmkit::detail
