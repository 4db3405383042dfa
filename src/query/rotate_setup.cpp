// The public rotate(): splitting the angle into parts below 180 degrees
// (the original's Rotation), setting up each part (Rotation180: per-feature
// rotation data, arc boxes, heart plane, maxTan), walking the tree and
// turning the result back into the world.
//
// The tree walk differs from the original on purpose: the original walks a
// single chord of the arc (its step count rounds to 0), so long arcs can skip
// leaves. Here the arc is cut into pieces of at most
// tol::kCircleApproximationLength and the tree is walked with the exact box
// of each piece (the union of every trace-model vertex's arc box), in order,
// stopping once a hit lies before the next piece.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "query/query_guards.h"
#include "query/rotate_work.h"

namespace cmkit::detail {
namespace {

constexpr double kPi = std::numbers::pi;

// Moves a contact from the model's frame to the world.
void contactToWorld(ContactInfo& c, const Placement& placement) {
  if (isRotated(placement.axis)) {
    c.normal = c.normal * placement.axis;
    c.point = c.point * placement.axis;
  }
  c.point += placement.origin;
  c.dist += placement.origin.dot(c.normal);
}

// True when the line origin + s * axis passes through the convex trace model
// (the intersection of its polygons' back half-spaces).
bool axisThroughConvexTrm(const TraceWork& tw, const Vec3& origin, const Vec3& axis) {
  double smin = -std::numeric_limits<double>::infinity();
  double smax = std::numeric_limits<double>::infinity();
  for (int i = 0; i < tw.numPolys; ++i) {
    const Plane& pl = tw.polys[std::size_t(i)].plane;
    const double d = double(pl.distance(origin));
    const double rate = double(pl.normal.dot(axis));
    if (rate == 0) {
      if (d > 0) return false;
      continue;
    }
    const double s = -d / rate;
    if (rate > 0)
      smax = std::min(smax, s);
    else
      smin = std::max(smin, s);
    if (smin > smax) return false;
  }
  return true;
}

/// One part of a rotation (|endAngle - startAngle| < 180). Returns the
/// fraction of the part turned before the first contact (1: none), the
/// contact in world space in `contact`.
Real rotatePart(const CollisionModel& model, const RotationQuery& q, Real startAngle, Real endAngle,
                QueryWork& work, ContactInfo& contact) {
  QueryScratch& s = scratchOf(work);
  s.begin(model);
  TraceWork tw(model, s);
  RotationWork rw;
  tw.rotation = &rw;
  tw.fraction = 1;
  tw.c = ContactInfo{};
  tw.contentMask = q.contentMask;
  tw.positionTest = false;
  tw.quickExit = false;

  const bool modelRotated = isRotated(q.placement.axis);
  const Mat3& modelAxis = q.placement.axis;
  // The axis point in the plane of the trace start, in the model's frame.
  Vec3 start = q.start - q.placement.origin;
  const Vec3& worldAxis = q.rotation.axis;
  Vec3 origin = q.rotation.origin - q.placement.origin;
  origin = origin + worldAxis * (worldAxis.dot(start) - worldAxis.dot(origin));
  Vec3 axis = worldAxis;
  if (modelRotated) {
    start = modelAxis * start;
    origin = modelAxis * origin;
    axis = modelAxis * axis;
  }
  rw.origin = origin;
  rw.axis = axis;
  rw.sign = endAngle > startAngle ? Real(1) : Real(-1);
  const Mat3 startM = Rotation(origin, axis, startAngle).matrix();
  const Mat3 endM = Rotation(origin, axis, endAngle).matrix();
  rw.backMatrix = Rotation(origin, axis, startAngle - endAngle).matrix();
  const bool atZero = startAngle == 0;  // skip the (rounding) identity turn
  auto turn = [&](const Vec3& p, const Mat3& m) { return origin + (p - origin) * m; };
  auto turnStart = [&](const Vec3& p) { return atZero ? p : turn(p, startM); };
  const double initialTan = std::fabs(std::tan(double(endAngle - startAngle) * kPi / 360));
  rw.maxTan = initialTan;

  // Trace-model vertices at the start of the rotation (the query's start),
  // model frame; then at the start and end of this part.
  std::array<Vec3, kMaxTrmVertices> base{};
  const bool point = isPointTrm(q.trm);
  Vec3 centre = start;
  if (point) {
    tw.pointTrace = true;
    tw.isConvex = false;
    tw.numVerts = 1;
    tw.numEdges = tw.numPolys = 0;
    base[0] = start;
  } else {
    const TraceModel& trm = *q.trm;
    tw.pointTrace = false;
    tw.isConvex = trm.isConvex();
    tw.numVerts = trm.numVertices();
    tw.numEdges = trm.numEdges();
    tw.numPolys = trm.numPolygons();
    const bool trmRotated = isRotated(q.trmAxis);
    const Vec3 worldStart = q.start - q.placement.origin;
    for (int i = 0; i < tw.numVerts; ++i) {
      Vec3 p = trm.vertex(i);
      if (trmRotated) p = p * q.trmAxis;
      p += worldStart;
      if (modelRotated) p = modelAxis * p;
      base[std::size_t(i)] = p;
    }
    centre = worldStart + (trmRotated ? trm.offset() * q.trmAxis : trm.offset());
    if (modelRotated) centre = modelAxis * centre;
  }
  rw.centre = turnStart(centre);

  tw.bounds.clear();
  Real maxRadiusSq = 0;
  for (int i = 0; i < tw.numVerts; ++i) {
    WorkVertex& v = tw.vertices[std::size_t(i)];
    RotVertex& rv = rw.vertices[std::size_t(i)];
    v.p = turnStart(base[std::size_t(i)]);
    v.endp = turn(base[std::size_t(i)], endM);
    v.used = true;
    rv.rotationOrigin = origin + axis * axis.dot(v.p - origin);
    const Real radiusSq = (v.p - rv.rotationOrigin).lengthSquared();
    maxRadiusSq = std::max(maxRadiusSq, radiusSq);
    rv.used = radiusSq > tol::kRotationAxisEpsilon * tol::kRotationAxisEpsilon;
    rv.bounds = arcBounds(rv.rotationOrigin, axis, v.p, v.endp).expanded(tol::kBoxEpsilon);
    tw.bounds.addBounds(rv.bounds);
  }
  if (!point) {
    const TraceModel& trm = *q.trm;
    for (int i = 1; i <= tw.numEdges; ++i) {
      const WorkEdge& e = placeTrmEdge(tw, trm, i);
      RotEdge& re = rw.edges[std::size_t(i)];
      re.used =
          rw.vertices[std::size_t(e.vertexNum[0])].used || rw.vertices[std::size_t(e.vertexNum[1])].used;
      re.bounds = rw.vertices[std::size_t(e.vertexNum[0])].bounds;
      re.bounds.addBounds(rw.vertices[std::size_t(e.vertexNum[1])].bounds);
    }
    const bool trmRotated = isRotated(q.trmAxis);
    for (int i = 0; i < tw.numPolys; ++i) {
      const TrmPolygon& tp = trm.polygon(i);
      WorkPolygon& wp = tw.polys[std::size_t(i)];
      RotPolygon& rp = rw.polygons[std::size_t(i)];
      wp.numEdges = tp.numEdges;
      wp.edges = tp.edges.data();
      wp.used = true;
      Vec3 n = tp.normal;
      if (trmRotated) n = n * q.trmAxis;
      if (modelRotated) n = modelAxis * n;
      if (!atZero) n = n * startM;
      wp.plane.normal = n;
      wp.plane.fitThroughPoint(tw.edges[std::size_t(std::abs(tp.edges[0]))].start);
      rp.bounds.clear();
      for (int k = 0; k < tp.numEdges; ++k)
        rp.bounds.addBounds(rw.edges[std::size_t(std::abs(tp.edges[std::size_t(k)]))].bounds);
    }
    rw.axisIntersectsTrm = tw.isConvex && axisThroughConvexTrm(tw, origin, axis);
  }

  // Heart plane: the plane of the rotation through the centre; nothing of
  // the trace model leaves the slab around it.
  tw.heartPlane1 = Plane{axis, axis.dot(rw.centre)};
  tw.maxDistFromHeartPlane1 = 0;
  for (int i = 0; i < tw.numVerts; ++i)
    tw.maxDistFromHeartPlane1 = std::max(tw.maxDistFromHeartPlane1,
                                         std::fabs(tw.heartPlane1.distance(tw.vertices[std::size_t(i)].p)));
  tw.maxDistFromHeartPlane1 += tol::kBoxEpsilon;

  // The walk: pieces of the arc, each with the exact box of every vertex's arc.
  const double partRadians = std::fabs(double(endAngle - startAngle)) * kPi / 180;
  const double arcLength = std::sqrt(double(maxRadiusSq)) * partRadians;
  const int pieces = int(std::clamp(std::ceil(arcLength / double(tol::kCircleApproximationLength)), 1.0,
                                    double(tol::kMaxRotationWalkPieces)));
  if (pieces == 1) {
    traceBoxThroughModel(tw, tw.bounds);
  } else {
    std::array<Vec3, kMaxTrmVertices> from{};
    for (int i = 0; i < tw.numVerts; ++i) from[std::size_t(i)] = tw.vertices[std::size_t(i)].p;
    for (int k = 0; k < pieces; ++k) {
      // A hit before this piece starts cannot be bettered by it.
      const double pieceStartTan = std::tan(partRadians * 0.5 * double(k) / double(pieces));
      if (rw.maxTan <= pieceStartTan || tw.fraction == 0 || tw.quickExit) break;
      const Real a1 = startAngle + (endAngle - startAngle) * Real(k + 1) / Real(pieces);
      const Mat3 m1 = Rotation(origin, axis, a1).matrix();
      Bounds box;
      for (int i = 0; i < tw.numVerts; ++i) {
        const Vec3 to = k + 1 == pieces ? tw.vertices[std::size_t(i)].endp : turn(base[std::size_t(i)], m1);
        box.addBounds(arcBounds(rw.vertices[std::size_t(i)].rotationOrigin, axis, from[std::size_t(i)], to));
        from[std::size_t(i)] = to;
      }
      traceBoxThroughModel(tw, box.expanded(tol::kBoxEpsilon));
    }
  }

  if (rw.maxTan == initialTan) return 1;
  contact = tw.c;
  contactToWorld(contact, q.placement);
  const double f = std::fabs(std::atan(rw.maxTan) * 360 / kPi / double(endAngle - startAngle));
  return Real(std::min(f, 1.0));
}

}  // namespace

}  // namespace cmkit::detail

namespace cmkit {

using namespace detail;  // the query internals (trace_work.h)

TraceResult rotate(const CollisionModel& model, const RotationQuery& query, QueryWork& work) {
  RotationQuery q = query;
  if (const QueryStatus st = guardRotation(q); st != QueryStatus::Ok)
    return refusedTrace(query.start, query.trmAxis, st);
  const Real angle = q.rotation.angle;
  const bool point = isPointTrm(q.trm);
  if (angle == 0) {  // a position test
    const ContentsQuery cq{q.trm, q.trmAxis, q.start, q.contentMask, q.placement};
    TraceResult r = contentsTest(model, cq, work).trace;
    r.startSolid = r.fraction == 0;
    r.endPos = q.start;
    r.endAxis = point ? Mat3::identity() : q.trmAxis;
    return r;
  }
  TraceResult r;
  if (q.detectStartSolid) {
    const ContentsQuery cq{q.trm, q.trmAxis, q.start, q.contentMask, q.placement};
    r.startSolid = contentsTest(model, cq, work).contents != 0;
  }
  // Parts below 180 degrees: a full turn (and more) in three 120-degree
  // parts, other angles of 180 or more in two halves.
  Real total = angle, step = angle;
  if (angle >= 360) {
    total = 360;
    step = 120;
  } else if (angle <= -360) {
    total = -360;
    step = -120;
  } else if (std::fabs(angle) >= 180) {
    step = angle * Real(0.5);
  }
  Real turned = angle;  // no hit: the whole angle
  r.fraction = 1;
  for (Real a = 0; std::fabs(a) < std::fabs(total); a += step) {
    ContactInfo c;
    const Real f = rotatePart(model, q, a, a + step, work, c);
    if (f < 1) {
      turned = a + step * f;
      r.fraction = turned / angle;
      r.contact = c;
      break;
    }
  }
  const Rotation done(q.rotation.origin, q.rotation.axis, turned);
  r.endPos = done.rotatePoint(q.start);
  r.endAxis = point ? Mat3::identity() : done.rotateAxis(q.trmAxis);
  return r;
}

}  // namespace cmkit
