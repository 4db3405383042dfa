// The public rotate(): splitting the angle into parts below 180 degrees
// (the original's Rotation), setting up each part (Rotation180: per-feature
// rotation data, arc boxes, heart plane, maxTan), walking the tree and
// turning the result back into the world.
//
// The tree walk differs from the original on purpose: the original walks a
// single chord of the arc (its step count rounds to 0), so long arcs can skip
// leaves. Here the tree is walked with boxes that hold the whole swept
// volume: the union of every trace-model vertex's arc box, cut into pieces
// along the centre's arc when the centre travels far (see the walk below),
// in order, stopping once a hit lies before the next piece.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "query/query_guards.h"
#include "query/rotate_work.h"

namespace cmkit::detail {

// (rotate_work.h) Where the line meets each polygon's plane bounds the part
// of it behind every plane.
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

namespace {

constexpr double kPi = std::numbers::pi;

/// What every part of a rotation shares: the frame (the model's), the
/// matrices and the tangent of half a part's angle. Every part turns by the
/// same `step` (see rotate below), so the matrix that turns a part's end
/// back to its start is the same for all: the inverse (the transpose) of the
/// rotation by `step`, the first part's end matrix.
struct RotationFrame {
  RotationFrame(const RotationQuery& q, Real step)
      : orientation(q.trmAxis, q.placement), modelRotated(orientation.modelRotated) {
    const Mat3& modelAxis = q.placement.axis;
    // The axis point in the plane of the trace start, in the model's frame.
    start = q.start - q.placement.origin;
    const Vec3& worldAxis = q.rotation.axis;
    origin = q.rotation.origin - q.placement.origin;
    origin = origin + worldAxis * (worldAxis.dot(start) - worldAxis.dot(origin));
    axis = worldAxis;
    if (modelRotated) {
      start = modelAxis * start;
      origin = modelAxis * origin;
      axis = modelAxis * axis;
    }
    stepMatrix = Rotation(origin, axis, step).matrix();
    backMatrix = stepMatrix.transposed();
    partTan = std::fabs(std::tan(double(step) * kPi / 360));
  }
  Orientation orientation;
  bool modelRotated;
  Vec3 start, origin, axis;
  Mat3 stepMatrix;  ///< the rotation by one part's angle (the first part's end)
  Mat3 backMatrix;  ///< a part's end back to its start
  double partTan;   ///< |tan| of half a part's angle
};

/// One part of a rotation (|endAngle - startAngle| = |step| < 180):
/// `startM` turns the query's start to the part's start (null for the first
/// part), `endM` to its end. Returns the fraction of the part turned before
/// the first contact (1: none), the contact in world space in `contact`.
/// Contacts mode (`found` set): every polygon's earliest contact is
/// appended there instead (model frame), and the part returns 1.
Real rotatePart(const CollisionModel& model, const RotationQuery& q, const RotationFrame& frame,
                Real startAngle, Real endAngle, const Mat3* startM, const Mat3& endM, QueryWork& work,
                ContactInfo& contact, std::vector<RotationContact>* found = nullptr) {
  QueryScratch& s = scratchOf(work);
  s.begin(model);
  TraceWork tw(model, s);
  if (!s.rotation) s.rotation = std::make_unique<RotationWork>();
  RotationWork& rw = *s.rotation;
  rw.edgeBoxesSet = false;
  rw.usedVertices = rw.usedEdges = 0;
  rw.polygonBoundsSet = 0;
  rw.edgeTurnSet = 0;
  rw.axisThroughTrm = -1;
  rw.contactsFound = found;
  rw.partStartAngle = startAngle;
  tw.rotation = &rw;
  tw.fraction = 1;
  tw.c = ContactInfo{};
  tw.contentMask = q.contentMask;
  tw.quickExit = false;

  const Orientation& orientation = frame.orientation;
  const bool modelRotated = frame.modelRotated;
  const Vec3& start = frame.start;
  const Vec3& origin = frame.origin;
  const Vec3& axis = frame.axis;
  rw.origin = origin;
  rw.axis = axis;
  rw.sign = endAngle > startAngle ? Real(1) : Real(-1);
  rw.backMatrix = frame.backMatrix;
  const bool atZero = startM == nullptr;
  auto turn = [&](const Vec3& p, const Mat3& m) { return origin + (p - origin) * m; };
  auto turnStart = [&](const Vec3& p) { return atZero ? p : turn(p, *startM); };
  const double initialTan = frame.partTan;
  rw.maxTan = initialTan;

  // The trace model at the start of the rotation (the query's start), model
  // frame; its vertices then turned to the start and end of this part.
  const bool point = isPointTrm(q.trm);
  Vec3 centre = start;
  if (point) {
    tw.pointTrace = true;
    tw.isConvex = false;
    tw.numVerts = 1;
    tw.numEdges = tw.numPolys = 0;
    tw.vertices[0].p = start;
  } else {
    tw.pointTrace = false;
    tw.isConvex = q.trm->isConvex();
    placeTrm(tw, *q.trm, orientation, q.start);
    centre = tw.start;
  }
  rw.centre = turnStart(centre);

  // The vertices turned to the start and end of the part and their circle
  // centres, into arrays by coordinate for the arc boxes (vertexArcBoxes,
  // four vertices at a time).
  VertexArcs arcs;
  for (int i = 0; i < tw.numVerts; ++i) {
    WorkVertex& v = tw.vertices[std::size_t(i)];
    RotVertex& rv = rw.vertices[std::size_t(i)];
    const Vec3 placed = v.p;
    const Vec3 p = turnStart(placed), endp = turn(placed, endM);
    const Vec3 rotationOrigin = origin + axis * axis.dot(p - origin);
    const bool used =
        (p - rotationOrigin).lengthSquared() > tol::kRotationAxisEpsilon * tol::kRotationAxisEpsilon;
    arcs.set(std::size_t(i), p, endp, rotationOrigin);
    v.used = true;
    rv.used = used;
    rw.usedVertices |= std::uint32_t(used) << i;
  }
  // Copied from the arrays in a loop of their own: stored straight from the
  // loop above, the vectors went through the stack a coordinate at a time
  // and were read back whole before those stores landed (a stall per vertex).
  for (std::size_t i = 0; i < std::size_t(tw.numVerts); ++i) {
    tw.vertices[i].p = {arcs.px[i], arcs.py[i], arcs.pz[i]};
    tw.vertices[i].endp = {arcs.ex[i], arcs.ey[i], arcs.ez[i]};
    rw.vertices[i].rotationOrigin = {arcs.rx[i], arcs.ry[i], arcs.rz[i]};
  }
  tw.bounds = vertexArcBoxes(arcs, tw.numVerts, axis, rw.vertexBoxes);
  if (!point) {
    // The edges' ends (from the arrays, as above); their lines only when a
    // model vertex first needs them (RotationWork::makeEdgeLines).
    for (int i = 1; i <= tw.numEdges; ++i) {
      WorkEdge& e = tw.edges[std::size_t(i)];
      const std::size_t a = std::size_t(e.vertexNum[0]), b = std::size_t(e.vertexNum[1]);
      e.start = {arcs.px[a], arcs.py[a], arcs.pz[a]};
      e.end = {arcs.px[b], arcs.py[b], arcs.pz[b]};
      rw.usedEdges |= (((rw.usedVertices >> a) | (rw.usedVertices >> b)) & 1u) << (i - 1);
    }
    rw.edgeLinesSet = false;
    for (int i = 0; i < tw.numPolys; ++i) {
      WorkPolygon& wp = tw.polys[std::size_t(i)];
      wp.used = true;
      if (!atZero) wp.plane.normal = wp.plane.normal * *startM;
      wp.plane.fitThroughPoint(tw.vertices[std::size_t(wp.planeVertex)].p);
    }
  }

  // Heart plane: the plane of the rotation through the centre; nothing of
  // the trace model leaves the slab around it.
  tw.heartPlane1 = Plane{axis, axis.dot(rw.centre)};
  tw.maxDistFromHeartPlane1 = 0;
  for (int i = 0; i < tw.numVerts; ++i)
    tw.maxDistFromHeartPlane1 = std::max(tw.maxDistFromHeartPlane1,
                                         std::fabs(tw.heartPlane1.distance(tw.vertices[std::size_t(i)].p)));
  tw.maxDistFromHeartPlane1 += tol::kBoxEpsilon;

  // The walk: the part's arc in pieces, in order, stopping once a hit lies
  // before the next piece. A piece's box holds every vertex's arc within it:
  // the motion is rigid, so every vertex stays within `reach` of the centre,
  // inside the box of the centre's arc grown by `reach`; cut to the part's
  // box (tw.bounds: the union of the vertices' whole arcs). Pieces pay off
  // only when the centre travels far compared with the trace model's size;
  // a trace model turning about its own centre walks once.
  Real reachSq = 0;
  for (int i = 0; i < tw.numVerts; ++i)
    reachSq = std::max(reachSq, (tw.vertices[std::size_t(i)].p - rw.centre).lengthSquared());
  const Real reach = std::sqrt(reachSq);
  const Vec3 centreRo = origin + axis * axis.dot(rw.centre - origin);
  const double partRadians = std::fabs(double(endAngle - startAngle)) * kPi / 180;
  // (A plain square root: the original's approximate one, which Vec3::length
  // reproduces, costs more and the pieces are cmkit's own.)
  const double centreArc = std::sqrt(double((rw.centre - centreRo).lengthSquared())) * partRadians;
  const double pieceLength = std::max(double(tol::kCircleApproximationLength), 2 * double(reach));
  // (A NaN ratio, from a trace model too large for its arithmetic, walks
  // once: the comparison is false.)
  const double ratio = centreArc / pieceLength;
  const int pieces = ratio > 1 ? int(std::min(std::ceil(ratio), double(tol::kMaxRotationWalkPieces))) : 1;
  if (pieces == 1) {
    rotateThroughBox(tw, tw.bounds);
  } else {
    // The pieces' ends: the centre turned by k pieces' angle, in double, the
    // cosine and sine of k pieces' angle from the last ones' (no function
    // call per piece; the rounding stays far inside the boxes' padding).
    const double pieceRadians = partRadians / double(pieces);
    const double pieceCos = std::cos(pieceRadians), pieceSin = double(rw.sign) * std::sin(pieceRadians);
    const DVec a(axis), o(origin), v = DVec(rw.centre) - DVec(origin);
    const DVec along = a * a.dot(v), across = v - along, turned = a.cross(across);
    double cosK = 1, sinK = 0;
    Vec3 from = rw.centre;
    for (int k = 0; k < pieces; ++k) {
      // A hit before this piece starts cannot be bettered by it. (Without a
      // hit, maxTan is the whole part's, beyond every piece's start: no
      // tangent to take.)
      if (tw.fraction == 0 || tw.quickExit) break;
      if (rw.maxTan != initialTan && rw.maxTan <= std::tan(partRadians * 0.5 * double(k) / double(pieces)))
        break;
      const double cosNext = cosK * pieceCos - sinK * pieceSin;
      sinK = sinK * pieceCos + cosK * pieceSin;
      cosK = cosNext;
      const Vec3 to = (o + along + across * cosK - turned * sinK).toVec3();  // as rotateByTanHalf
      const Bounds box = arcBounds(centreRo, axis, from, to).expanded(reach + tol::kBoxEpsilon);
      from = to;
      rotateThroughBox(tw, box.intersection(tw.bounds));
    }
  }

  if (rw.maxTan == initialTan) return 1;
  contact = tw.c;
  contactToWorld(contact, q.placement, modelRotated);
  const double f = std::fabs(std::atan(rw.maxTan) * 360 / kPi / double(endAngle - startAngle));
  return Real(std::min(f, 1.0));
}

/// How rotate() splits an angle into parts below 180 degrees: a full turn
/// (and more) in three 120-degree parts, other angles of 180 or more in two
/// halves. `total` is the angle the parts cover, `step` each part's.
void splitAngle(Real angle, Real& total, Real& step) {
  total = angle;
  step = angle;
  if (angle >= 360) {
    total = 360;
    step = 120;
  } else if (angle <= -360) {
    total = -360;
    step = -120;
  } else if (std::fabs(angle) >= 180) {
    step = angle * Real(0.5);
  }
}

/// Calls part(a, startM, endM) for each part of a rotation by `total` in
/// parts of `step` degrees, in order (startM null for the first part), until
/// it returns true.
template <class Part>
void forEachPart(const RotationFrame& frame, Real total, Real step, Part part) {
  Mat3 startM, endM = frame.stepMatrix;  // a part's start and end matrices
  for (Real a = 0; std::fabs(a) < std::fabs(total); a += step) {
    if (a != 0) {  // the next part starts where the last one ended
      startM = endM;
      endM = Rotation(frame.origin, frame.axis, a + step).matrix();
    }
    if (part(a, a != 0 ? &startM : nullptr, endM)) return;
  }
}

}  // namespace

std::vector<RotationContact>& collectRotationContacts(const CollisionModel& model, const RotationQuery& q,
                                                      QueryWork& work, bool& modelRotated) {
  QueryScratch& s = scratchOf(work);
  if (!s.rotation) s.rotation = std::make_unique<RotationWork>();
  std::vector<RotationContact>& found = s.rotation->found;
  found.clear();
  Real total, step;
  splitAngle(q.rotation.angle, total, step);
  count(s, &QueryStats::queries);
  const RotationFrame frame(q, step);
  forEachPart(frame, total, step, [&](Real a, const Mat3* startM, const Mat3& endM) {
    ContactInfo unused;
    rotatePart(model, q, frame, a, a + step, startM, endM, work, unused, &found);
    return false;
  });
  modelRotated = frame.modelRotated;
  return found;
}

}  // namespace cmkit::detail

namespace cmkit {

using namespace detail;  // the query internals (trace_work.h)

TraceResult rotate(const CollisionModel& model, const RotationQuery& query, QueryWork& work) {
  RotationQuery q = query;
  if (const QueryStatus st = guardRotation(q); st != QueryStatus::Ok)
    return refusedTrace(query.start, query.trmAxis, st);
  return rotateGuarded(model, q, work);
}

}  // namespace cmkit

namespace cmkit::detail {

TraceResult rotateGuarded(const CollisionModel& model, const RotationQuery& q, QueryWork& work) {
  TraceResult r;  // (returned on every path, as translate's: no copy)
  const Real angle = q.rotation.angle;
  const bool point = isPointTrm(q.trm);
  if (angle == 0) {  // a position test
    const ContentsQuery cq{q.trm, q.trmAxis, q.start, q.contentMask, q.placement};
    r = contentsTest(model, cq, work).trace;
    r.startSolid = r.fraction == 0;
    r.endPos = q.start;
    r.endAxis = point ? Mat3::identity() : q.trmAxis;
    return r;
  }
  if (q.detectStartSolid) {
    const ContentsQuery cq{q.trm, q.trmAxis, q.start, q.contentMask, q.placement};
    r.startSolid = contentsTest(model, cq, work).contents != 0;
  }
  // Parts below 180 degrees (splitAngle).
  Real total, step;
  splitAngle(angle, total, step);
  count(scratchOf(work), &QueryStats::queries);
  Real turned = angle;  // no hit: the whole angle
  r.fraction = 1;
  const RotationFrame frame(q, step);
  forEachPart(frame, total, step, [&](Real a, const Mat3* startM, const Mat3& endM) {
    ContactInfo c;
    const Real f = rotatePart(model, q, frame, a, a + step, startM, endM, work, c);
    if (!(f < 1)) return false;
    turned = a + step * f;
    r.fraction = turned / angle;
    r.contact = c;
    return true;
  });
  const Rotation done(q.rotation.origin, q.rotation.axis, turned);
  r.endPos = done.rotatePoint(q.start);
  r.endAxis = point ? Mat3::identity() : done.rotateAxis(q.trmAxis);
  return r;
}

}  // namespace cmkit::detail
