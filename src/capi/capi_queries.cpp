// The C API's queries and their batches (include/cmkit/cmkit.h): each a
// World query on the calling thread's scratch, its answer copied into the C
// structs.
#include <algorithm>
#include <span>
#include <string>
#include <vector>

#include "capi/capi_support.h"
#include "cmkit/batch.h"

namespace {

using cmkit::Real;
using cmkit::Vec3;
using namespace cmkit::detail::capi;

void fillTrace(const cmkit::WorldTraceResult& r, cmkit_trace_t* out) {
  *out = cmkit_trace_t{};
  out->fraction = float(r.trace.fraction);
  put(out->end, r.trace.endPos);
  putAxis(out->end_axis, r.trace.endAxis);
  put(out->point, r.trace.contact.point);
  put(out->normal, r.trace.contact.normal);
  out->dist = float(r.trace.contact.dist);
  out->contents = r.trace.contact.contents;
  out->material = r.trace.contact.material;
  out->entity = r.entity;
  out->contact_type = int32_t(r.trace.contact.type);
  out->start_solid = r.trace.startSolid ? 1 : 0;
}

void fillRay(const cmkit::WorldRayHit& r, cmkit_ray_hit_t* out) {
  *out = cmkit_ray_hit_t{};
  out->fraction = float(r.hit.fraction);
  put(out->point, r.hit.point);
  put(out->normal, r.hit.normal);
  out->contents = r.hit.contents;
  out->material = r.hit.material;
  out->entity = r.entity;
}

cmkit::BatchOptions batchOptions(int threads) {
  cmkit::BatchOptions options;
  options.threads = std::max(threads, 0);
  return options;
}

std::vector<Vec3> vectors(const float* xyz, size_t n) {
  std::vector<Vec3> v(n);
  for (size_t i = 0; i < n; ++i) v[i] = vec(xyz + 3 * i);
  return v;
}

// Runs a world batch (`run` fills a span of n answers) and hands answer i to
// fill(i, answer): the batch functions' common tail.
template <class Answer, class Run, class Fill>
cmkit_status runWorldBatch(std::size_t n, Run&& run, Fill&& fill) {
  std::vector<Answer> answers(n);
  const cmkit::Status st = run(std::span<Answer>(answers));
  if (!st) return failWith(st.error());
  for (std::size_t i = 0; i < n; ++i) fill(i, answers[i]);
  return CMKIT_OK;
}

}  // namespace

extern "C" {

cmkit_status cmkit_translate(const cmkit_world_t* world, const cmkit_trace_model_t* trm,
                             const float trm_axis[9], const float start[3], const float end[3], uint32_t mask,
                             cmkit_trace_t* out) {
  CMKIT_API_BODY {
    CMKIT_REQUIRE(world);
    CMKIT_REQUIRE(start);
    CMKIT_REQUIRE(end);
    CMKIT_REQUIRE(out);
    cmkit::TranslationQuery q;
    q.trm = trmOf(trm);
    q.trmAxis = axisOrIdentity(trm_axis);
    q.start = vec(start);
    q.end = vec(end);
    q.contentMask = mask;
    q.detectStartSolid = true;
    const cmkit::WorldTraceResult r = world->world.translate(q, threadWork());
    fillTrace(r, out);
    if (r.trace.status != cmkit::QueryStatus::Ok) return refused(r.trace.status, fn);
    return CMKIT_OK;
  });
}

cmkit_status cmkit_rotate(const cmkit_world_t* world, const cmkit_trace_model_t* trm, const float trm_axis[9],
                          const float start[3], const float rot_origin[3], const float rot_axis[3],
                          float angle, uint32_t mask, cmkit_trace_t* out) {
  CMKIT_API_BODY {
    CMKIT_REQUIRE(world);
    CMKIT_REQUIRE(start);
    CMKIT_REQUIRE(rot_origin);
    CMKIT_REQUIRE(rot_axis);
    CMKIT_REQUIRE(out);
    cmkit::RotationQuery q;
    q.trm = trmOf(trm);
    q.trmAxis = axisOrIdentity(trm_axis);
    q.start = vec(start);
    q.rotation = cmkit::Rotation(vec(rot_origin), vec(rot_axis), Real(angle));
    q.contentMask = mask;
    const cmkit::WorldTraceResult r = world->world.rotate(q, threadWork());
    fillTrace(r, out);
    if (r.trace.status != cmkit::QueryStatus::Ok) return refused(r.trace.status, fn);
    return CMKIT_OK;
  });
}

cmkit_status cmkit_contents(const cmkit_world_t* world, const cmkit_trace_model_t* trm,
                            const float trm_axis[9], const float position[3], uint32_t mask,
                            uint32_t* contents, cmkit_entity_t* entity) {
  CMKIT_API_BODY {
    CMKIT_REQUIRE(world);
    CMKIT_REQUIRE(position);
    CMKIT_REQUIRE(contents);
    cmkit::ContentsQuery q;
    q.trm = trmOf(trm);
    q.trmAxis = axisOrIdentity(trm_axis);
    q.position = vec(position);
    q.contentMask = mask;
    const cmkit::WorldContentsResult r = world->world.contentsTest(q, threadWork());
    if (r.result.status != cmkit::QueryStatus::Ok) return refused(r.result.status, fn);
    *contents = r.result.contents;
    if (entity != nullptr) *entity = r.entity;
    return CMKIT_OK;
  });
}

cmkit_status cmkit_point_contents(const cmkit_world_t* world, const float point[3], uint32_t* contents,
                                  cmkit_entity_t* entity) {
  CMKIT_API_BODY {
    CMKIT_REQUIRE(world);
    CMKIT_REQUIRE(point);
    CMKIT_REQUIRE(contents);
    cmkit::PointContentsQuery q;
    q.point = vec(point);
    const cmkit::WorldPointContentsResult r = world->world.pointContents(q, threadWork());
    if (r.status != cmkit::QueryStatus::Ok) return refused(r.status, fn);
    *contents = r.contents;
    if (entity != nullptr) *entity = r.entity;
    return CMKIT_OK;
  });
}

cmkit_status cmkit_contacts(const cmkit_world_t* world, const cmkit_trace_model_t* trm,
                            const float trm_axis[9], const float start[3], const float dir[3], float depth,
                            uint32_t mask, cmkit_contact_t* out, int32_t capacity, int32_t* count) {
  CMKIT_API_BODY {
    CMKIT_REQUIRE(world);
    CMKIT_REQUIRE(start);
    CMKIT_REQUIRE(dir);
    CMKIT_REQUIRE(count);
    if (capacity < 0 || (capacity > 0 && out == nullptr))
      return fail(CMKIT_ERROR_INVALID_ARGUMENT, "cmkit_contacts: capacity < 0, or out is NULL");
    cmkit::ContactsQuery q;
    q.trm = trmOf(trm);
    q.trmAxis = axisOrIdentity(trm_axis);
    q.start = vec(start);
    q.dir = vec(dir);
    q.depth = Real(depth);
    q.contentMask = mask;
    q.maxContacts = capacity;
    const cmkit::WorldContactsResult r = world->world.contacts(q, threadWork());
    if (r.status != cmkit::QueryStatus::Ok) return refused(r.status, fn);
    const int32_t n = std::min<int32_t>(capacity, int32_t(r.contacts.size()));
    for (int32_t i = 0; i < n; ++i) {
      const cmkit::ContactInfo& c = r.contacts[size_t(i)].contact;
      cmkit_contact_t& o = out[i];
      o = cmkit_contact_t{};
      put(o.point, c.point);
      put(o.normal, c.normal);
      o.dist = float(c.dist);
      o.contents = c.contents;
      o.material = c.material;
      o.entity = r.contacts[size_t(i)].entity;
      o.contact_type = int32_t(c.type);
    }
    *count = n;
    return CMKIT_OK;
  });
}

cmkit_status cmkit_cast_ray(const cmkit_world_t* world, const float start[3], const float end[3],
                            uint32_t mask, cmkit_ray_hit_t* out) {
  CMKIT_API_BODY {
    CMKIT_REQUIRE(world);
    CMKIT_REQUIRE(start);
    CMKIT_REQUIRE(end);
    CMKIT_REQUIRE(out);
    cmkit::RayCastQuery q;
    q.start = vec(start);
    q.end = vec(end);
    q.contentMask = mask;
    fillRay(world->world.castRay(q, threadWork()), out);
    return CMKIT_OK;
  });
}

cmkit_status cmkit_translate_batch(const cmkit_world_t* world, const cmkit_trace_model_t* trm,
                                   const float trm_axis[9], const float* starts, const float* ends, size_t n,
                                   uint32_t mask, int threads, cmkit_trace_t* out) {
  CMKIT_API_BODY {
    CMKIT_REQUIRE(world);
    if (n == 0) return CMKIT_OK;
    CMKIT_REQUIRE(starts);
    CMKIT_REQUIRE(ends);
    CMKIT_REQUIRE(out);
    const std::vector<Vec3> s = vectors(starts, n), e = vectors(ends, n);
    cmkit::TranslationBatch batch;
    batch.query.trm = trmOf(trm);
    batch.query.trmAxis = axisOrIdentity(trm_axis);
    batch.query.contentMask = mask;
    batch.query.detectStartSolid = true;
    batch.starts = s;
    batch.ends = e;
    return runWorldBatch<cmkit::WorldTraceResult>(
        n,
        [&](auto answers) {
          return cmkit::translateBatch(world->world, batch, answers, batchOptions(threads));
        },
        [&](std::size_t i, const cmkit::WorldTraceResult& r) { fillTrace(r, &out[i]); });
  });
}

cmkit_status cmkit_point_contents_batch(const cmkit_world_t* world, const float* points, size_t n,
                                        int threads, uint32_t* contents, cmkit_entity_t* entities) {
  CMKIT_API_BODY {
    CMKIT_REQUIRE(world);
    if (n == 0) return CMKIT_OK;
    CMKIT_REQUIRE(points);
    CMKIT_REQUIRE(contents);
    const std::vector<Vec3> p = vectors(points, n);
    cmkit::PointContentsBatch batch;
    batch.points = p;
    return runWorldBatch<cmkit::WorldPointContentsResult>(
        n,
        [&](auto answers) {
          return cmkit::pointContentsBatch(world->world, batch, answers, batchOptions(threads));
        },
        [&](std::size_t i, const cmkit::WorldPointContentsResult& r) {
          contents[i] = r.contents;
          if (entities != nullptr) entities[i] = r.entity;
        });
  });
}

cmkit_status cmkit_cast_ray_batch(const cmkit_world_t* world, const float* starts, const float* ends,
                                  size_t n, uint32_t mask, int threads, cmkit_ray_hit_t* out) {
  CMKIT_API_BODY {
    CMKIT_REQUIRE(world);
    if (n == 0) return CMKIT_OK;
    CMKIT_REQUIRE(starts);
    CMKIT_REQUIRE(ends);
    CMKIT_REQUIRE(out);
    const std::vector<Vec3> s = vectors(starts, n), e = vectors(ends, n);
    cmkit::RayBatch batch;
    batch.query.contentMask = mask;
    batch.starts = s;
    batch.ends = e;
    return runWorldBatch<cmkit::WorldRayHit>(
        n,
        [&](auto answers) {
          return cmkit::castRayBatch(world->world, batch, answers, batchOptions(threads));
        },
        [&](std::size_t i, const cmkit::WorldRayHit& r) { fillRay(r, &out[i]); });
  });
}

}  // extern "C"
