// The rotation test of a trace-model edge against a model edge once its
// root search (rotate_edges.h, inline) has found the first root of the two
// lines' product against the model edge moved out by the clip epsilon (or,
// within the band, the far side of the band): the meeting checked within
// both edges as the original checks it, and the second root when the first
// falls beyond an edge's end.
#include "query/rotate_edges.h"

#include <cmath>
#include <cstdlib>

namespace cmkit::detail {
namespace {

/// The original's CollisionBetweenEdgeBounds: at tangent u, do the turned
/// trace-model edge and the model edge (c, d) really meet within both
/// segments (each edge's end points, moved along the motion, straddle the
/// other edge's line)? Gives the contact point and the turned edge.
bool collisionBetweenEdgeBounds(const RotationWork& rw, const Vec3& s, const Vec3& e, const Vec3& c,
                                const Vec3& d, double u, Vec3& a, Vec3& b, Vec3& point) {
  a = u == 0 ? s : rotateByTanHalf(s, rw.origin, rw.axis, double(rw.sign) * u);
  b = u == 0 ? e : rotateByTanHalf(e, rw.origin, rw.axis, double(rw.sign) * u);
  const Vec3 dirA = (a - rw.origin).cross(rw.axis);
  const Vec3 dirB = (b - rw.origin).cross(rw.axis);
  const Vec3 dir = (dirA.lengthSquared() > dirB.lengthSquared() ? dirA : dirB) * rw.sign;
  auto sameSide = [](Real d1, Real d2) {  // (& and |: the signs are the data's)
    return bool((unsigned(d1 > 0) & unsigned(d2 > 0)) | (unsigned(d1 < 0) & unsigned(d2 < 0)));
  };
  const Pluecker trmLine = Pluecker::fromLine(a, b);
  if (sameSide(trmLine.permutedInnerProduct(Pluecker::fromRay(c, dir)),
               trmLine.permutedInnerProduct(Pluecker::fromRay(d, dir))))
    return false;
  const Pluecker modelLine = Pluecker::fromLine(c, d);
  if (sameSide(modelLine.permutedInnerProduct(Pluecker::fromRay(a, dir)),
               modelLine.permutedInnerProduct(Pluecker::fromRay(b, dir))))
    return false;
  // Where the turned edge cuts the plane through the model edge along the motion.
  const DVec m = (DVec(d) - DVec(c)).cross(DVec(dir));
  const double da = m.dot(DVec(a) - DVec(c));
  const double db = m.dot(DVec(b) - DVec(c));
  const double t = std::fabs(da - db) > 0 ? da / (da - db) : 0.0;
  point = (DVec(a) + (DVec(b) - DVec(a)) * t).toVec3();
  if (!point.isFinite()) return false;
  // Points on the axis do not move: no collision there.
  DVec w = DVec(point) - DVec(rw.origin);
  w = w - DVec(rw.axis) * DVec(rw.axis).dot(w);
  return w.dot(w) >= double(tol::kRotationAxisEpsilon) * double(tol::kRotationAxisEpsilon);
}

/// Where segments a-b and c-d, on lines that meet (a root of their line
/// product), meet: false when the lines are parallel (no single point) or
/// the point lies beyond an end of either segment (by more than
/// kSegmentEndSlack of its length).
bool segmentsMeetAt(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, Vec3& point) {
  /// Rounding of the root's angle moves the meeting point along the edges
  /// by a tiny fraction of their lengths: ends are met within this much.
  constexpr double kSegmentEndSlack = 1e-6;
  const DVec r = DVec(b) - DVec(a), w = DVec(d) - DVec(c), ac = DVec(c) - DVec(a);
  const DVec n = r.cross(w);
  const double nn = n.dot(n);
  if (!(nn > 0)) return false;
  const double s = ac.cross(w).dot(n) / nn;
  const double t = ac.cross(r).dot(n) / nn;
  if (!(s >= -kSegmentEndSlack && s <= 1 + kSegmentEndSlack && t >= -kSegmentEndSlack &&
        t <= 1 + kSegmentEndSlack))
    return false;
  point = (DVec(a) + r * s).toVec3();
  return point.isFinite();
}

/// The sign of an edge-edge contact's normal: against the motion of the
/// contact point along the arc at the contact, v = sign * (point - origin) x
/// axis (the trace model's motion, model frame), as every contact of a
/// translation opposes the motion; that holds whether the trace model
/// started free or in solid. When the motion runs within the contact plane
/// (cosine within tol::kRotationContactTangentCosine) neither side is
/// approached: then out of the solid (the model edge's normal), else the
/// side of the turned trace-model edge. (The original took the sign from a
/// test at the start of the rotation; starting in solid it often followed
/// the motion.)
Vec3 edgeContactNormal(const RotationWork& rw, const Vec3& unitNormal, const Vec3& point,
                       const Vec3& edgeNormal, const Vec3& trmEdgeFromModelEdge) {
  const Vec3 motion = (point - rw.origin).cross(rw.axis) * rw.sign;
  const Real along = unitNormal.dot(motion);
  if (std::fabs(along) > tol::kRotationContactTangentCosine * motion.length())
    return along > 0 ? -unitNormal : unitNormal;
  const Real facing = unitNormal.dot(edgeNormal);
  if (facing < 0 || (facing == 0 && unitNormal.dot(trmEdgeFromModelEdge) < 0)) return -unitNormal;
  return unitNormal;
}

}  // namespace

void RotationWork::makeEdgeTurn(const TraceWork& tw, int j) {
  edgeTurnSet |= std::uint64_t(1) << j;
  EdgeTurn& t = edges[std::size_t(j)].turn;
  const WorkEdge& e = tw.edges[std::size_t(j)];
  const DVec a(axis), s(e.start);
  const DVec u = DVec(e.end) - s;
  const DVec q = (s - DVec(origin)).cross(u);
  const DVec uAxial = a * a.dot(u), qAxial = a * a.dot(q);
  t.start.set(u, q);
  t.axial.set(uAxial, qAxial);
  t.across.set(u - uAxial, q - qAxial);
  t.turned.set(u.cross(a), q.cross(a));
}

void edgePairContact(TraceWork& tw, RotationWork& rw, const CmPolygon& poly, std::int32_t edgeNum,
                     int trmEdgeNum, double u, double later, bool inBand) {
  const CollisionModel& m = tw.model;
  const CmEdge& edge = m.edges()[std::size_t(std::abs(edgeNum))];
  const WorkEdge& te = tw.edges[std::size_t(trmEdgeNum)];
  const Vec3& c0 = m.vertices()[std::size_t(edge.vertex[0])];
  const Vec3& d0 = m.vertices()[std::size_t(edge.vertex[1])];
  const double sign = rw.sign;
  Vec3 a, b, point;
  if (!collisionBetweenEdgeBounds(rw, te.start, te.end, c0, d0, u, a, b, point)) {
    // The lines met beyond the ends of an edge. Turning on, they can meet
    // once more (the product is a sinusoid of the angle: two roots a turn),
    // within both edges: the contact is then that second root. (The
    // original stopped at the first root: a trace-model edge swept past the
    // model edge's line outside it, then across the edge itself, went
    // through the corner unseen.)
    // (The product's next root, found with u: what solving it again from
    // just after u gives, rw.maxTan unchanged since; NaN when there is none.)
    if (!(later < rw.maxTan)) return;
    u = later;
    a = rotateByTanHalf(te.start, rw.origin, rw.axis, sign * u);
    b = rotateByTanHalf(te.end, rw.origin, rw.axis, sign * u);
    // At a root the two lines meet: whether within both segments is decided
    // exactly, on the line whose root it is (the edge moved out).
    const Vec3 shift =
        edge.normal * (inBand ? tol::kClipEpsilon + tol::kPluckerRangeEpsilon : tol::kClipEpsilon);
    if (!segmentsMeetAt(a, b, c0 + shift, d0 + shift, point)) return;
  }

  // Contact plane: through the model edge, containing both edge directions.
  // Parallel edges have no such plane and no crossing: their product is
  // zero at every angle, so its roots are noise (vertex-polygon tests see
  // those contacts).
  Vec3 normal = (b - a).cross(d0 - c0);
  const Real sinSq = normal.lengthSquared() / ((b - a).lengthSquared() * (d0 - c0).lengthSquared());
  if (!(sinSq > tol::kRotationParallelEdgeSine * tol::kRotationParallelEdgeSine)) return;
  normal.normalize();
  rw.maxTan = u;
  normal = edgeContactNormal(rw, normal, point, edge.normal, a - c0);
  setRotationContact(tw, poly, ContactType::Edge, normal, normal.dot(c0), point, edgeNum, trmEdgeNum);
}

}  // namespace cmkit::detail
