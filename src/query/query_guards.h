// Input checks of the public queries (QueryStatus in cmkit/query.h): each
// public query calls its guard first, on a copy of its query, and returns a
// refused result when the guard says no. A guard may normalise the copy
// (re-orthonormalise a slightly drifted axis, normalise a nearly unit
// rotation axis). On valid input the cost is a few comparisons per query
// (identity axes are not examined further).
#pragma once

#include <bit>
#include <cstdint>
#include <type_traits>

#include "cmkit/query.h"
#include "cmkit/tolerances.h"
#include "cmkit/trace_model.h"
#include "math/axis_lanes.h"

namespace cmkit::detail {

/// Checks (and may normalise) a translation or position test.
QueryStatus guardTranslation(TranslationQuery& q);
/// Checks (and may normalise) a position test.
QueryStatus guardContents(ContentsQuery& q);
/// Checks (and may normalise) a penetration query (as a position test).
QueryStatus guardPenetration(PenetrationQuery& q);
/// Checks (and may normalise) a point-contents query: the point and the
/// placement, as every other kind checks them.
QueryStatus guardPointContents(PointContentsQuery& q);
/// Checks (and may normalise) a contacts query.
QueryStatus guardContacts(ContactsQuery& q);
/// Checks (and may normalise) a rotation.
QueryStatus guardRotation(RotationQuery& q);
/// Checks (and may normalise) a model's placement as every guard above
/// checks it: the origin within range, the axis a rotation.
QueryStatus guardPlacement(Placement& placement);

// The public queries past their guard, for a caller that checked the input
// once for many models (the World: one guard, then one query per entity).
// Each takes a query its guard accepted, as the guard left it (normalised),
// and answers as the public query does on that input:
//   translate(model, query, work) == translateGuarded(model, q, work)
//   whenever guardTranslation(q = query) is Ok; the same for the others.
// The World also checks each entity's placement once, when it is set
// (guardPlacement must accept it and leave it unchanged, or the World asks
// the public query).

/// translate() on a guarded query.
TraceResult translateGuarded(const CollisionModel& model, const TranslationQuery& q, QueryWork& work);
/// contentsTest() on a guarded query.
ContentsResult contentsTestGuarded(const CollisionModel& model, const ContentsQuery& q, QueryWork& work);
/// rotate() on a guarded query.
TraceResult rotateGuarded(const CollisionModel& model, const RotationQuery& q, QueryWork& work);
/// True when every coordinate's magnitude is within
/// tol::kMaxQueryCoordinate (false for NaN and infinity), on the bit
/// patterns: the shift drops the sign, and NaN and infinity have larger
/// patterns than any finite number. Integer operations, no branch.
inline bool withinQueryRange(const Vec3& p) {
  using Bits = std::conditional_t<sizeof(Real) == 8, std::uint64_t, std::uint32_t>;
  constexpr Bits kMaxBits = Bits(std::bit_cast<Bits>(tol::kMaxQueryCoordinate) << 1);
  auto beyond = [](Real v) { return Bits(std::bit_cast<Bits>(v) << 1) > kMaxBits; };
  return (int(beyond(p.x)) | int(beyond(p.y)) | int(beyond(p.z))) == 0;
}

/// Whether checkCommon (a translation's, a position test's shared checks)
/// would accept a query and leave it as it is: the position and the origin
/// in range, neither the placement nor a shaped trace model turned, the
/// trace model's bounds in range. The usual query; its public call then runs
/// on the caller's query itself, not on a copy (whose wide loads of fields
/// the caller has just stored waited for those stores to reach the cache,
/// and whose stores then stalled the guard's loads the same way).
inline bool passesCommonChecksUnchanged(const Vec3& position, const Placement& placement,
                                        const TraceModel* trm, const Mat3& trmAxis) {
  if (!withinQueryRange(position) || !withinQueryRange(placement.origin) || isRotated(placement))
    return false;
  if (!trm || trm->isPoint()) return true;
  return !isRotated(trmAxis) && withinQueryRange(trm->bounds().min) && withinQueryRange(trm->bounds().max);
}

/// passesCommonChecksUnchanged for a translation: its end in range too
/// (guardTranslation's one check more). translate() and contentsTest() run
/// such queries without the guard's copy.
inline bool passesGuardUnchanged(const TranslationQuery& q) {
  return withinQueryRange(q.end) && passesCommonChecksUnchanged(q.start, q.placement, q.trm, q.trmAxis);
}
/// passesCommonChecksUnchanged for a position test (guardContents' checks).
inline bool passesGuardUnchanged(const ContentsQuery& q) {
  return passesCommonChecksUnchanged(q.position, q.placement, q.trm, q.trmAxis);
}

/// The result of a refused query: fraction 0, endPos = start, endAxis =
/// trmAxis, no contact.
TraceResult refusedTrace(const Vec3& start, const Mat3& trmAxis, QueryStatus status);

}  // namespace cmkit::detail
