// The public contacts(): a translation that collects every contact instead
// of stopping at the first (the original's Contacts), in world space.
#include <vector>

#include "query/query_guards.h"
#include "query/trace_work.h"

namespace cmkit {

using namespace detail;  // the query internals (trace_work.h)

QueryStatus contacts(const CollisionModel& model, const ContactsQuery& query, QueryWork& work,
                     std::vector<ContactInfo>& out) {
  out.clear();
  ContactsQuery q = query;
  if (const QueryStatus status = guardContacts(q); status != QueryStatus::Ok) return status;
  const Vec3 end = q.start + q.dir * q.depth;
  if (end == q.start || q.maxContacts <= 0) return QueryStatus::Ok;  // a position test finds no contacts
  detail::QueryScratch& s = detail::scratchOf(work);
  s.begin(model);
  count(s, &QueryStats::queries);
  TraceWork tw(model, s);
  const TranslationQuery tq{q.trm, q.trmAxis, q.start, end, q.contentMask, q.placement, false};
  const Orientation o(q.trmAxis, q.placement);
  runTranslation(tw, tq, o, &out, q.maxContacts);
  // Unlike the original, point contacts are moved to world space too.
  for (ContactInfo& c : out) contactToWorld(c, q.placement, o.modelRotated);
  return QueryStatus::Ok;
}

ContactsResult contacts(const CollisionModel& model, const ContactsQuery& query, QueryWork& work) {
  ContactsResult result;
  result.status = contacts(model, query, work, result.contacts);
  return result;
}

}  // namespace cmkit
