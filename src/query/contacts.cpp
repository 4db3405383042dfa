// The public contacts(): a translation that collects every contact instead
// of stopping at the first (the original's Contacts), in world space; or,
// cmkit's own, a rotation that collects every polygon's earliest contact.
#include <algorithm>
#include <cmath>
#include <vector>

#include "query/query_guards.h"
#include "query/rotate_work.h"

namespace cmkit {

using namespace detail;  // the query internals (trace_work.h)

namespace {

/// Rotational contacts: the rotation walked in contacts mode (rotate_setup.cpp),
/// then each polygon's earliest contact, by |angle|, the maxContacts first.
void rotationContacts(const CollisionModel& model, const ContactsQuery& q, QueryWork& work,
                      std::vector<ContactInfo>& out) {
  const RotationQuery rq{q.trm, q.trmAxis, q.start, *q.rotation, q.contentMask, q.placement, false};
  bool modelRotated = false;
  std::vector<RotationContact>& found = collectRotationContacts(model, rq, work, modelRotated);
  std::vector<std::int32_t>& polygons = scratchOf(work).rotation->listedPolygons;
  polygons.clear();
  // Stable: equal angles keep the walk's order. A polygon met in two parts
  // (a turn of 180 degrees or more) keeps its first contact.
  std::stable_sort(found.begin(), found.end(), [](const RotationContact& a, const RotationContact& b) {
    return std::fabs(a.contact.angle) < std::fabs(b.contact.angle);
  });
  for (const RotationContact& f : found) {
    if (int(out.size()) >= q.maxContacts) break;
    if (std::find(polygons.begin(), polygons.end(), f.polygon) != polygons.end()) continue;
    polygons.push_back(f.polygon);
    out.push_back(f.contact);
    contactToWorld(out.back(), q.placement, modelRotated);
  }
}

}  // namespace

QueryStatus contacts(const CollisionModel& model, const ContactsQuery& query, QueryWork& work,
                     std::vector<ContactInfo>& out) {
  out.clear();
  ContactsQuery q = query;
  if (const QueryStatus status = guardContacts(q); status != QueryStatus::Ok) return status;
  if (q.rotation) {
    // Angle 0 is a position test, which finds no contacts (as start == end).
    if (q.rotation->angle != 0 && q.maxContacts > 0) rotationContacts(model, q, work, out);
    return QueryStatus::Ok;
  }
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
