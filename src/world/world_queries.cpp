// The World's queries: the broad phase picks the entities a query's sweep
// can touch, each is asked with the single-model query at its placement,
// and the closest answer is kept (world.h's contract says which).
#include <algorithm>
#include <cmath>

#include "cmkit/world.h"
#include "query/query_guards.h"
#include "world/world_data.h"

namespace cmkit {

using detail::EntitySlot;
using detail::WorldData;
using detail::WorldScratch;

namespace {

bool isPoint(const TraceModel* trm) { return trm == nullptr || trm->isPoint(); }

/// World bounds of the trace model at `position` with orientation `axis`.
Bounds trmBoundsAt(const TraceModel* trm, const Mat3& axis, const Vec3& position) {
  if (isPoint(trm)) return Bounds::ofPoint(position);
  if (axis.isIdentity()) return trm->bounds().translated(position);
  return detail::placedBounds(trm->bounds(), {position, axis});
}

/// World bounds of the trace model swept from `start` to `end` with
/// orientation `axis`: its box about its origin, made once, moved to both
/// ends. (The same bits as trmBoundsAt at each end, joined: a rounded sum
/// grows with its terms.)
Bounds sweptTrmBounds(const TraceModel* trm, const Mat3& axis, const Vec3& start, const Vec3& end) {
  const Bounds local = isPoint(trm)        ? Bounds::ofPoint(Vec3{})
                       : axis.isIdentity() ? trm->bounds()
                                           : detail::placedBounds(trm->bounds(), {Vec3{}, axis});
  Bounds b;
  for (int i = 0; i < 3; ++i) {
    b.min[i] = std::min(start[i], end[i]) + local.min[i];
    b.max[i] = std::max(start[i], end[i]) + local.max[i];
  }
  return b;
}

/// Every position a trace model takes while it turns about an axis through
/// `origin` stays as far from `origin` as it started: the box around that
/// sphere (through the corners of its start box, which lie no nearer).
Bounds turnBounds(const TraceModel* trm, const Mat3& axis, const Vec3& start, const Vec3& origin) {
  const Bounds b = trmBoundsAt(trm, axis, start);
  Real reach2 = 0;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 c{b[corner & 1].x, b[(corner >> 1) & 1].y, b[(corner >> 2) & 1].z};
    reach2 = std::max(reach2, (c - origin).lengthSquared());
  }
  const Real reach = std::sqrt(reach2);
  return Bounds(origin, origin).expanded(reach);
}

bool ignored(const EntityFilter& filter, const WorldEntity& e) {
  if (std::find(filter.ignore.begin(), filter.ignore.end(), e.id) != filter.ignore.end()) return true;
  return filter.accept && !filter.accept(e);
}

/// The entities a query asks, ascending by id, into s.candidates: the world
/// model and every entity of the tree that `collect(out)` appends, whose
/// contents meet `mask` (mask 0: whose contents are not 0) and that the
/// filter keeps.
template <class Collect>
void gather(const WorldData& d, const Collect& collect, std::uint32_t mask, const EntityFilter& filter,
            WorldScratch& s) {
  s.candidates.clear();
  if (d.worldModel != kNoEntity) s.candidates.push_back(d.worldModel);
  collect(s.candidates);
  if (s.candidates.size() > 1) std::sort(s.candidates.begin(), s.candidates.end());
  const bool filtering = !filter.ignore.empty() || bool(filter.accept);
  std::size_t kept = 0;
  for (const EntityId id : s.candidates) {
    const WorldEntity& e = d.slot(id)->entity;
    const std::uint32_t c = mask == 0 ? e.contents : (e.contents & mask);
    if (c == 0 || (filtering && ignored(filter, e))) continue;
    s.candidates[kept++] = id;
  }
  s.candidates.resize(kept);
}

/// The broad phase for a swept box: the entities whose boxes meet it padded.
void gatherBox(const WorldData& d, const Bounds& sweep, std::uint32_t mask, const EntityFilter& filter,
               WorldScratch& s) {
  const Bounds padded = sweep.expanded(tol::kWorldBroadPhasePadding);
  gather(
      d, [&](std::vector<EntityId>& out) { d.tree.collectBox(padded, out); }, mask, filter, s);
}

WorldScratch& scratchOf(WorldQueryWork& work) { return detail::WorldWorkAccess::of(work); }

/// The closest of the candidates' answers (ascending ids; at least one),
/// each `ask(slot)`, a single-model translation or rotation at the entity's
/// placement: the smallest fraction (equal fractions: the lowest id), with
/// startSolid the OR over them all; entity kNoEntity when none was hit.
template <class Ask>
WorldTraceResult closest(const WorldData& d, const WorldScratch& s, const Ask& ask) {
  // (The first answer is made in place: most queries ask only the world
  // model, and a copy of the result would read back its fields just stored.)
  WorldTraceResult out{ask(*d.slot(s.candidates[0])), s.candidates[0]};
  bool startSolid = out.trace.startSolid;
  for (std::size_t k = 1; k < s.candidates.size(); ++k) {
    const EntityId id = s.candidates[k];
    const TraceResult r = ask(*d.slot(id));
    startSolid = startSolid || r.startSolid;
    if (r.fraction < out.trace.fraction) {
      out.trace = r;
      out.entity = id;
    }
  }
  out.trace.startSolid = startSolid;
  if (!(out.trace.fraction < 1)) out.entity = kNoEntity;
  return out;
}

}  // namespace

WorldTraceResult World::translate(const TranslationQuery& query, WorldQueryWork& work,
                                  const EntityFilter& filter) const {
  TranslationQuery g = query;  // checked (and normalised) once, for every entity
  g.placement = {};
  if (const QueryStatus st = detail::guardTranslation(g); st != QueryStatus::Ok)
    return {detail::refusedTrace(query.start, query.trmAxis, st), kNoEntity};
  WorldScratch& s = scratchOf(work);
  gatherBox(*data_, sweptTrmBounds(g.trm, g.trmAxis, g.start, g.end), g.contentMask, filter, s);
  if (s.candidates.empty()) {
    // Nothing near: the miss every model gives (translate()'s rules).
    WorldTraceResult out;
    out.trace.fraction = 1;
    if (g.start == g.end) {
      out.trace.endPos = g.start;
      out.trace.endAxis = g.trmAxis;
    } else {
      out.trace.endPos = g.start + (g.end - g.start) * Real(1);
      out.trace.endAxis = isPoint(g.trm) ? Mat3::identity() : g.trmAxis;
    }
    return out;
  }
  return closest(*data_, s, [&](const EntitySlot& slot) {
    const WorldEntity& e = slot.entity;
    if (!slot.placementGuarded) {  // the public query checks (and refuses) it
      TranslationQuery q = query;
      q.placement = e.placement;
      return cmkit::translate(*e.model, q, s.model);
    }
    g.placement = e.placement;
    return detail::translateGuarded(*e.model, g, s.model);
  });
}

WorldTraceResult World::rotate(const RotationQuery& query, WorldQueryWork& work,
                               const EntityFilter& filter) const {
  RotationQuery g = query;
  g.placement = {};
  if (const QueryStatus st = detail::guardRotation(g); st != QueryStatus::Ok)
    return {detail::refusedTrace(query.start, query.trmAxis, st), kNoEntity};
  WorldScratch& s = scratchOf(work);
  gatherBox(*data_, turnBounds(g.trm, g.trmAxis, g.start, g.rotation.origin), g.contentMask, filter, s);
  if (s.candidates.empty()) {
    // Nothing near: the miss every model gives (rotate()'s rules).
    WorldTraceResult out;
    const bool point = isPoint(g.trm);
    out.trace.fraction = 1;
    if (g.rotation.angle == 0) {
      out.trace.endPos = g.start;
      out.trace.endAxis = point ? Mat3::identity() : g.trmAxis;
    } else {
      const Rotation done(g.rotation.origin, g.rotation.axis, g.rotation.angle);
      out.trace.endPos = done.rotatePoint(g.start);
      out.trace.endAxis = point ? Mat3::identity() : done.rotateAxis(g.trmAxis);
    }
    return out;
  }
  return closest(*data_, s, [&](const EntitySlot& slot) {
    const WorldEntity& e = slot.entity;
    if (!slot.placementGuarded) {
      RotationQuery q = query;
      q.placement = e.placement;
      return cmkit::rotate(*e.model, q, s.model);
    }
    g.placement = e.placement;
    return detail::rotateGuarded(*e.model, g, s.model);
  });
}

WorldContentsResult World::contentsTest(const ContentsQuery& query, WorldQueryWork& work,
                                        const EntityFilter& filter) const {
  WorldContentsResult out;
  ContentsQuery g = query;
  g.placement = {};
  if (const QueryStatus st = detail::guardContents(g); st != QueryStatus::Ok) {
    out.result.trace = detail::refusedTrace(query.position, query.trmAxis, st);
    out.result.status = st;
    return out;
  }
  WorldScratch& s = scratchOf(work);
  gatherBox(*data_, trmBoundsAt(g.trm, g.trmAxis, g.position), g.contentMask, filter, s);

  std::uint32_t all = 0;
  bool asked = false;
  for (const EntityId id : s.candidates) {
    const EntitySlot& slot = *data_->slot(id);
    const WorldEntity& e = slot.entity;
    ContentsResult r;
    if (slot.placementGuarded) {
      g.placement = e.placement;
      r = detail::contentsTestGuarded(*e.model, g, s.model);
    } else {
      ContentsQuery q = query;
      q.placement = e.placement;
      r = cmkit::contentsTest(*e.model, q, s.model);
    }
    all |= r.contents;
    if (!asked || (out.entity == kNoEntity && r.contents != 0)) {
      out.result = r;
      out.entity = r.contents != 0 ? id : kNoEntity;
      asked = true;
    }
  }
  if (!asked) {
    out.result.trace.fraction = 1;
    out.result.trace.endPos = g.position;
    out.result.trace.endAxis = g.trmAxis;
  }
  out.result.contents = all;
  return out;
}

WorldPointContentsResult World::pointContents(const PointContentsQuery& query, WorldQueryWork& work,
                                              const EntityFilter& filter) const {
  WorldPointContentsResult out;
  PointContentsQuery g = query;
  g.placement = {};
  if (const QueryStatus st = detail::guardPointContents(g); st != QueryStatus::Ok) {
    out.status = st;
    return out;
  }
  WorldScratch& s = scratchOf(work);
  gatherBox(*data_, Bounds::ofPoint(g.point), 0, filter, s);
  PointContentsQuery q = query;
  for (const EntityId id : s.candidates) {
    const WorldEntity& e = data_->slot(id)->entity;
    q.placement = e.placement;
    const std::uint32_t c = cmkit::pointContents(*e.model, q, s.model).contents;
    if (c != 0 && out.entity == kNoEntity) out.entity = id;
    out.contents |= c;
  }
  return out;
}

WorldContactsResult World::contacts(const ContactsQuery& query, WorldQueryWork& work,
                                    const EntityFilter& filter) const {
  WorldContactsResult out;
  ContactsQuery g = query;
  g.placement = {};
  if (const QueryStatus st = detail::guardContacts(g); st != QueryStatus::Ok) {
    out.status = st;
    return out;
  }
  WorldScratch& s = scratchOf(work);
  Bounds sweep;
  if (g.rotation) {
    sweep = turnBounds(g.trm, g.trmAxis, g.start, g.rotation->origin);
  } else {
    sweep = trmBoundsAt(g.trm, g.trmAxis, g.start);
    sweep.addBounds(trmBoundsAt(g.trm, g.trmAxis, g.start + g.dir * g.depth));
  }
  gatherBox(*data_, sweep, g.contentMask, filter, s);
  ContactsQuery q = query;
  for (const EntityId id : s.candidates) {
    const WorldEntity& e = data_->slot(id)->entity;
    q.placement = e.placement;
    cmkit::contacts(*e.model, q, s.model, s.contacts);
    for (const ContactInfo& c : s.contacts) out.contacts.push_back({c, id});
  }
  if (g.rotation) {
    // By |angle|; ties keep entity order, then each model's (stable).
    std::stable_sort(out.contacts.begin(), out.contacts.end(),
                     [](const WorldContact& a, const WorldContact& b) {
                       return std::fabs(a.contact.angle) < std::fabs(b.contact.angle);
                     });
  }
  if (out.contacts.size() > std::size_t(std::max(0, g.maxContacts)))
    out.contacts.resize(std::size_t(std::max(0, g.maxContacts)));
  return out;
}

WorldRayHit World::castRay(const RayCastQuery& query, WorldQueryWork& work,
                           const EntityFilter& filter) const {
  WorldRayHit out;
  if (!query.start.isFinite() || !query.end.isFinite() || query.start == query.end) return out;
  WorldScratch& s = scratchOf(work);
  // RayIndex accepts a crossing a little outside its polygon (its padding is
  // relative to the model's coordinates): the box is padded by that too.
  const Real pad = tol::kWorldBroadPhasePadding +
                   2 * (tol::kRayAcceptPadding + tol::kRayNodePadding) * (data_->maxLocalMagnitude + 1);
  const Vec3 start = query.start, end = query.end;
  const auto meets = [&](const Bounds& b) { return b.expanded(pad).intersectsSegment(start, end); };
  gather(
      *data_, [&](std::vector<EntityId>& out) { data_->tree.collect(meets, out); }, query.contentMask, filter,
      s);
  RayCastQuery q = query;
  for (const EntityId id : s.candidates) {
    const EntitySlot& slot = *data_->slot(id);
    q.placement = slot.entity.placement;
    const RayHit hit = slot.rays->cast(q);
    if (hit.hit() && (!out.hit.hit() || hit.fraction < out.hit.fraction)) {
      out.hit = hit;
      out.entity = id;
    }
  }
  return out;
}

}  // namespace cmkit
