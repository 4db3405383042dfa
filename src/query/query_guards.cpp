// Input checks of the public queries (see query_guards.h and QueryStatus).
#include "query/query_guards.h"

#include <cmath>

#include "cmkit/tolerances.h"
#include "math/axis_lanes.h"
#include "util/simd.h"

namespace cmkit {

const char* toString(QueryStatus status) {
  switch (status) {
    case QueryStatus::Ok:
      return "ok";
    case QueryStatus::BadTrmAxis:
      return "trace-model axis is not a rotation (non-finite, scaled, sheared or mirrored)";
    case QueryStatus::BadModelAxis:
      return "model axis is not a rotation (non-finite, scaled, sheared or mirrored)";
    case QueryStatus::NonFinite:
      return "a position, origin, direction, depth or angle is not finite";
    case QueryStatus::OutOfRange:
      return "a coordinate, the end of the move or the trace model's size is beyond 1e9 units";
    case QueryStatus::BadRotationAxis:
      return "rotation axis is zero or not of unit length";
    case QueryStatus::MixedMotion:
      return "contacts query given both a translation (dir and depth) and a rotation";
  }
  return "unknown status";
}

const char* toString(ContactType type) {
  switch (type) {
    case ContactType::None:
      return "none";
    case ContactType::Edge:
      return "edge";
    case ContactType::ModelVertex:
      return "modelvertex";
    case ContactType::TrmVertex:
      return "trmvertex";
  }
  return "?";
}

}  // namespace cmkit

namespace cmkit::detail {
namespace {

/// Why a point is out of range: NonFinite or OutOfRange.
[[gnu::noinline]] QueryStatus pointOutOfRange(const Vec3& p) {
  return p.isFinite() ? QueryStatus::OutOfRange : QueryStatus::NonFinite;
}

/// Ok when every coordinate is within tol::kMaxQueryCoordinate; else
/// NonFinite or OutOfRange (valid input pays only withinQueryRange, inline:
/// a call of its own was about half a point's check).
inline QueryStatus checkPoint(const Vec3& p) {
  if (withinQueryRange(p)) [[likely]]
    return QueryStatus::Ok;
  return pointOutOfRange(p);
}

/// Whether an axis is orthonormal within tol::kAxisDriftEpsilon:
/// Mat3::orthonormalityError() <= the epsilon, false for NaN and infinity
/// (whose products are not within it). With float lanes the six products
/// four at a time: each row's length squared and the rows' dot products,
/// with Vec3::dot's products and sums in its order, so the same values and
/// the same answer (a turned trace model's sweep asks it every query).
bool withinDrift(const Mat3& m) {
#ifdef CMKIT_FLOAT_LANES
  using simd::F4;
  const Vec3 &a = m.rows[0], &b = m.rows[1], &c = m.rows[2];
  const F4 ra = F4::lanes(a.x, a.y, a.z, 0), rb = F4::lanes(b.x, b.y, b.z, 0),
           rc = F4::lanes(c.x, c.y, c.z, 0);
  // Lanes: a.a, b.b, c.c, a.b, then a.c, b.c (and two zeros).
  F4 x = ra * ra, y = rb * rb, z = rc * rc, unused = ra * rb;
  simd::transpose(x, y, z, unused);  // x: the x products of the four, y, z
  const F4 squares = x + y + z;
  F4 x2 = ra * rc, y2 = rb * rc, z2 = F4::zero(), unused2 = F4::zero();
  simd::transpose(x2, y2, z2, unused2);
  const F4 dots = x2 + y2 + z2;
  const F4 epsilon = F4::all(Real(tol::kAxisDriftEpsilon));
  const F4 within = (simd::abs(squares - F4::lanes(1, 1, 1, 0)) <= epsilon) & (simd::abs(dots) <= epsilon);
  return simd::bits(within) == 0xFu;
#else
  return m.isFinite() && m.orthonormalityError() <= tol::kAxisDriftEpsilon;
#endif
}

/// checkAxis for an axis that is not the identity.
[[gnu::noinline]] bool checkTurnedAxis(Mat3& axis) {
  // The usual input, a rotation within the drift epsilon, passes unchanged
  // (validateAxis's own first checks, without building its Result; a
  // non-finite axis fails withinDrift and is refused there).
  if (withinDrift(axis) && axis.determinant() > 0) return true;
  Result<Mat3> checked = validateAxis(axis);
  if (!checked) return false;
  axis = *checked;
  return true;
}

/// Checks an orientation in place: identity passes at once (inline: most
/// placements and trace models are not turned); otherwise validateAxis
/// (finite, right-handed, orthonormal within tol::kAxisRejectTolerance;
/// re-orthonormalised beyond tol::kAxisDriftEpsilon).
inline bool checkAxis(Mat3& axis) { return !isRotated(axis) || checkTurnedAxis(axis); }

bool hasShape(const TraceModel* trm) { return trm && !trm->isPoint(); }

/// A trace model whose bounds reach beyond tol::kMaxQueryCoordinate (a box
/// of 1e22, say) is refused like a position that far: its vertices' products
/// would overflow.
QueryStatus checkTrmSize(const TraceModel* trm) {
  if (!hasShape(trm)) return QueryStatus::Ok;
  const Bounds& b = trm->bounds();
  if (const QueryStatus s = checkPoint(b.min); s != QueryStatus::Ok) return s;
  return checkPoint(b.max);
}

}  // namespace

QueryStatus guardPlacement(Placement& placement) {
  if (const QueryStatus s = checkPoint(placement.origin); s != QueryStatus::Ok) return s;
  return checkAxis(placement.axis) ? QueryStatus::Ok : QueryStatus::BadModelAxis;
}

namespace {

/// The shared part: position(s), placement, trace-model axis.
QueryStatus checkCommon(const Vec3& position, Placement& placement, const TraceModel* trm, Mat3& trmAxis) {
  if (const QueryStatus s = checkPoint(position); s != QueryStatus::Ok) return s;
  if (const QueryStatus s = guardPlacement(placement); s != QueryStatus::Ok) return s;
  if (hasShape(trm) && !checkAxis(trmAxis)) return QueryStatus::BadTrmAxis;
  return checkTrmSize(trm);
}

}  // namespace

QueryStatus guardTranslation(TranslationQuery& q) {
  if (const QueryStatus s = checkPoint(q.end); s != QueryStatus::Ok) return s;
  return checkCommon(q.start, q.placement, q.trm, q.trmAxis);
}

QueryStatus guardContents(ContentsQuery& q) { return checkCommon(q.position, q.placement, q.trm, q.trmAxis); }

QueryStatus guardPenetration(PenetrationQuery& q) {
  return checkCommon(q.position, q.placement, q.trm, q.trmAxis);
}

QueryStatus guardPointContents(PointContentsQuery& q) {
  if (const QueryStatus s = checkPoint(q.point); s != QueryStatus::Ok) return s;
  return guardPlacement(q.placement);
}

QueryStatus guardContacts(ContactsQuery& q) {
  if (!std::isfinite(q.depth) || !q.dir.isFinite()) return QueryStatus::NonFinite;
  if (q.rotation) {
    // Rotational contacts: no translation beside the rotation, which is
    // checked (and its axis normalised) as rotate() checks it.
    if (q.depth != 0 && q.dir != Vec3{}) return QueryStatus::MixedMotion;
    RotationQuery rq{q.trm, q.trmAxis, q.start, *q.rotation, q.contentMask, q.placement, false};
    const QueryStatus s = guardRotation(rq);
    q.trmAxis = rq.trmAxis;
    q.placement = rq.placement;
    q.rotation = rq.rotation;
    return s;
  }
  if (checkPoint(q.start + q.dir * q.depth) != QueryStatus::Ok && q.start.isFinite())
    return QueryStatus::OutOfRange;  // the end (finite input) is too far or overflows
  return checkCommon(q.start, q.placement, q.trm, q.trmAxis);
}

QueryStatus guardRotation(RotationQuery& q) {
  if (!std::isfinite(q.rotation.angle)) return QueryStatus::NonFinite;
  if (const QueryStatus s = checkPoint(q.rotation.origin); s != QueryStatus::Ok) return s;
  if (!q.rotation.axis.isFinite()) return QueryStatus::NonFinite;
  // The exact length (Vec3::length() uses the original's approximate
  // reciprocal square root, off by up to ~1e-5 on unit vectors).
  const Vec3& a = q.rotation.axis;
  const double length = std::sqrt(double(a.x) * a.x + double(a.y) * a.y + double(a.z) * a.z);
  if (!(std::fabs(length - 1) <= tol::kRotationAxisUnitTolerance)) return QueryStatus::BadRotationAxis;
  if (std::fabs(length - 1) > tol::kAxisDriftEpsilon)
    q.rotation.axis = {Real(a.x / length), Real(a.y / length), Real(a.z / length)};
  return checkCommon(q.start, q.placement, q.trm, q.trmAxis);
}

TraceResult refusedTrace(const Vec3& start, const Mat3& trmAxis, QueryStatus status) {
  TraceResult r;
  r.fraction = 0;
  r.endPos = start;
  r.endAxis = trmAxis;
  r.status = status;
  return r;
}

}  // namespace cmkit::detail
