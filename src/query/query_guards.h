// Input checks of the public queries (QueryStatus in cmkit/query.h): each
// public query calls its guard first, on a copy of its query, and returns a
// refused result when the guard says no. A guard may normalise the copy
// (re-orthonormalise a slightly drifted axis, normalise a nearly unit
// rotation axis). On valid input the cost is a few comparisons per query
// (identity axes are not examined further).
#pragma once

#include "cmkit/query.h"

namespace cmkit::detail {

/// Checks (and may normalise) a translation or position test.
QueryStatus guardTranslation(TranslationQuery& q);
/// Checks (and may normalise) a position test.
QueryStatus guardContents(ContentsQuery& q);
/// Checks (and may normalise) a contacts query.
QueryStatus guardContacts(ContactsQuery& q);
/// Checks (and may normalise) a rotation.
QueryStatus guardRotation(RotationQuery& q);
/// True when a point and its placement are usable by pointContents.
bool pointUsable(const Vec3& point, const Placement& placement);

/// The result of a refused query: fraction 0, endPos = start, endAxis =
/// trmAxis, no contact.
TraceResult refusedTrace(const Vec3& start, const Mat3& trmAxis, QueryStatus status);

}  // namespace cmkit::detail
