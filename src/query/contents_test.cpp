// The public contentsTest(): a position test of a trace model (the
// original's ContentsTrm) through position_test.cpp's brush and polygon
// tests, or point contents with a mask for a point.
#include "query/query_guards.h"
#include "query/trace_work.h"

namespace cmkit {

using namespace detail;  // the query internals (trace_work.h)

ContentsResult contentsTest(const CollisionModel& model, const ContentsQuery& query, QueryWork& work) {
  if (passesGuardUnchanged(query)) return contentsTestGuarded(model, query, work);
  ContentsQuery q = query;
  if (const QueryStatus st = guardContents(q); st != QueryStatus::Ok) {
    ContentsResult r;
    r.trace = refusedTrace(query.position, query.trmAxis, st);
    r.status = st;
    return r;
  }
  return contentsTestGuarded(model, q, work);
}

}  // namespace cmkit

namespace cmkit::detail {

ContentsResult contentsTestGuarded(const CollisionModel& model, const ContentsQuery& q, QueryWork& work) {
  ContentsResult r;
  r.trace.endPos = q.position;
  r.trace.endAxis = q.trmAxis;
  if (isPointTrm(q.trm)) {
    // Unlike the original, a point honours the mask like any trace model.
    r.contents = pointContentsMasked(model, q.position, q.placement, q.contentMask);
    r.trace.contact.contents = r.contents;
    r.trace.fraction = r.contents == 0 ? 1 : 0;
    return r;
  }
  detail::QueryScratch& s = detail::scratchOf(work);
  s.begin(model);
  count(s, &QueryStats::queries);
  TraceWork tw(model, s);
  const Orientation o(q.trmAxis, q.placement);
  setupPositionTest(tw, *q.trm, o, q.position, q.contentMask);
  positionTestThroughModel(tw);
  r.contents = tw.c.contents;
  r.trace.contact = tw.c;
  r.trace.fraction = r.contents == 0 ? 1 : 0;
  r.trace.startSolid = r.contents != 0;
  return r;
}

}  // namespace cmkit::detail
