// The C API (include/cmkit/cmkit.h) over the C++ World: handles, status codes
// and a thread-local error message; no exception leaves a function here.
#include "cmkit/cmkit.h"

#include <algorithm>
#include <cstring>
#include <exception>
#include <filesystem>
#include <new>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "cmkit/batch.h"
#include "cmkit/cm_file.h"
#include "cmkit/map.h"
#include "cmkit/materials.h"
#include "cmkit/movement.h"
#include "cmkit/version.h"
#include "cmkit/world.h"

struct cmkit_world {
  cmkit::World world;
};

struct cmkit_trace_model {
  cmkit::TraceModel trm;
};

struct cmkit_player {
  cmkit::PlayerShape shape;
  cmkit::PlayerState state;
};

namespace {

using cmkit::Real;
using cmkit::Vec3;

// The calling thread's last error and its query scratch: each thread has its
// own, so concurrent queries share nothing.
thread_local std::string tLastError;

cmkit::WorldQueryWork& threadWork() {
  thread_local cmkit::WorldQueryWork work;
  return work;
}

cmkit_status fail(cmkit_status status, std::string message) {
  tLastError = std::move(message);
  return status;
}

cmkit_status failWith(const cmkit::Error& error, cmkit_status status = CMKIT_ERROR_INVALID_ARGUMENT) {
  return fail(status, error.toString());
}

// Runs `body` with every exception turned into a status.
template <class F>
cmkit_status guarded(const char* function, F&& body) {
  try {
    return body();
  } catch (const std::bad_alloc&) {
    return fail(CMKIT_ERROR_OUT_OF_MEMORY, std::string(function) + ": out of memory");
  } catch (const std::exception& e) {
    return fail(CMKIT_ERROR_INTERNAL, std::string(function) + ": " + e.what());
  } catch (...) {
    return fail(CMKIT_ERROR_INTERNAL, std::string(function) + ": unknown exception");
  }
}

// A C function's body: `fn` names the function in messages (inside the
// lambda __func__ would name the lambda).
#define CMKIT_API_BODY             \
  const char* const fn = __func__; \
  return guarded(fn, [&]() -> cmkit_status

#define CMKIT_REQUIRE(pointer)                                                               \
  do {                                                                                       \
    if ((pointer) == nullptr)                                                                \
      return fail(CMKIT_ERROR_INVALID_ARGUMENT, std::string(fn) + ": " #pointer " is NULL"); \
  } while (false)

Vec3 vec(const float v[3]) { return Vec3(Real(v[0]), Real(v[1]), Real(v[2])); }

void put(float out[3], const Vec3& v) {
  out[0] = float(v.x);
  out[1] = float(v.y);
  out[2] = float(v.z);
}

cmkit::Mat3 axisOrIdentity(const float axis[9]) {
  cmkit::Mat3 m;
  if (axis != nullptr)
    for (int r = 0; r < 3; ++r) m.rows[r] = vec(axis + 3 * r);
  return m;
}

void putAxis(float out[9], const cmkit::Mat3& m) {
  for (int r = 0; r < 3; ++r) put(out + 3 * r, m.rows[r]);
}

const cmkit::TraceModel* trmOf(const cmkit_trace_model_t* trm) {
  return trm != nullptr ? &trm->trm : nullptr;
}

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

cmkit_status refused(cmkit::QueryStatus status, const char* function) {
  return fail(CMKIT_ERROR_REFUSED, std::string(function) + ": refused: " + cmkit::toString(status));
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

cmkit_status boundsShape(float x0, float y0, float z0, float x1, float y1, float z1, int sides, char kind,
                         cmkit_trace_model_t** out, const char* fn) {
  CMKIT_REQUIRE(out);
  const cmkit::Bounds bounds{Vec3(Real(x0), Real(y0), Real(z0)), Vec3(Real(x1), Real(y1), Real(z1))};
  cmkit::Result<cmkit::TraceModel> trm = kind == 'b'   ? cmkit::TraceModel::box(bounds)
                                         : kind == 'c' ? cmkit::TraceModel::cylinder(bounds, sides)
                                                       : cmkit::TraceModel::cone(bounds, sides);
  if (!trm) return fail(CMKIT_ERROR_INVALID_ARGUMENT, std::string(fn) + ": " + trm.error().toString());
  *out = new cmkit_trace_model{std::move(*trm)};
  return CMKIT_OK;
}

// The world of a .cm file: its models placed by NAME.map beside it when
// that map has as many primitive-owning entities as the file has models,
// else every model at the origin (entity 0 the file's first model).
cmkit::Result<cmkit::World> worldFromCm(const std::string& path, const cmkit::MaterialTable& materials) {
  cmkit::Result<cmkit::CmFile> cm = cmkit::loadCmFile(path, materials);
  if (!cm) return cm.error();
  std::filesystem::path mapPath(path);
  mapPath.replace_extension(".map");
  std::error_code ec;
  if (std::filesystem::exists(mapPath, ec)) {
    cmkit::Result<cmkit::MapFile> map = cmkit::loadMapFile(mapPath.string());
    if (!map) return map.error();
    cmkit::Result<cmkit::LoadedWorld> loaded = cmkit::World::fromMap(*map, cm->models);
    if (loaded) return std::move(loaded->world);
  }
  cmkit::World world;
  for (const cmkit::ModelPtr& model : cm->models) {
    cmkit::EntityDesc desc;
    desc.name = model->name();
    desc.model = model;
    cmkit::Result<cmkit::EntityId> id = world.addEntity(std::move(desc));
    if (!id) return id.error();
  }
  return world;
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

const char* cmkit_last_error(void) { return tLastError.c_str(); }

const char* cmkit_version(void) { return CMKIT_VERSION_STRING; }

cmkit_status cmkit_load_map(const char* path, cmkit_world_t** out) {
  CMKIT_API_BODY {
    CMKIT_REQUIRE(path);
    CMKIT_REQUIRE(out);
    const cmkit::MaterialTable materials;
    const std::string p(path);
    const bool isCm = p.size() >= 3 && p.compare(p.size() - 3, 3, ".cm") == 0;
    if (isCm) {
      cmkit::Result<cmkit::World> world = worldFromCm(p, materials);
      if (!world) return failWith(world.error(), CMKIT_ERROR_FILE);
      *out = new cmkit_world{std::move(*world)};
      return CMKIT_OK;
    }
    cmkit::Result<cmkit::LoadedWorld> loaded = cmkit::World::loadMap(p, materials);
    if (!loaded) return failWith(loaded.error(), CMKIT_ERROR_FILE);
    *out = new cmkit_world{std::move(loaded->world)};
    return CMKIT_OK;
  });
}

void cmkit_world_free(cmkit_world_t* world) { delete world; }

int32_t cmkit_world_entity_limit(const cmkit_world_t* world) {
  return world != nullptr ? world->world.idLimit() : 0;
}

cmkit_status cmkit_world_find_entity(const cmkit_world_t* world, const char* name, cmkit_entity_t* out) {
  CMKIT_API_BODY {
    CMKIT_REQUIRE(world);
    CMKIT_REQUIRE(name);
    CMKIT_REQUIRE(out);
    const cmkit::EntityId id = world->world.find(name);
    if (id == cmkit::kNoEntity) return fail(CMKIT_ERROR_NOT_FOUND, std::string("no entity named ") + name);
    *out = id;
    return CMKIT_OK;
  });
}

const char* cmkit_world_entity_name(const cmkit_world_t* world, cmkit_entity_t entity) {
  if (world == nullptr) return nullptr;
  const cmkit::WorldEntity* e = world->world.entity(entity);
  return e != nullptr ? e->name.c_str() : nullptr;
}

cmkit_status cmkit_world_get_placement(const cmkit_world_t* world, cmkit_entity_t entity, float origin[3],
                                       float axis[9]) {
  CMKIT_API_BODY {
    CMKIT_REQUIRE(world);
    CMKIT_REQUIRE(origin);
    const cmkit::WorldEntity* e = world->world.entity(entity);
    if (e == nullptr) return fail(CMKIT_ERROR_NOT_FOUND, "no entity " + std::to_string(entity));
    put(origin, e->placement.origin);
    if (axis != nullptr) putAxis(axis, e->placement.axis);
    return CMKIT_OK;
  });
}

cmkit_status cmkit_world_set_placement(cmkit_world_t* world, cmkit_entity_t entity, const float origin[3],
                                       const float axis[9]) {
  CMKIT_API_BODY {
    CMKIT_REQUIRE(world);
    CMKIT_REQUIRE(origin);
    if (world->world.entity(entity) == nullptr)
      return fail(CMKIT_ERROR_NOT_FOUND, "no entity " + std::to_string(entity));
    cmkit::Status s = world->world.setPlacement(entity, cmkit::Placement{vec(origin), axisOrIdentity(axis)});
    if (!s) return failWith(s.error());
    return CMKIT_OK;
  });
}

cmkit_status cmkit_world_set_contents(cmkit_world_t* world, cmkit_entity_t entity, uint32_t contents) {
  CMKIT_API_BODY {
    CMKIT_REQUIRE(world);
    if (world->world.entity(entity) == nullptr)
      return fail(CMKIT_ERROR_NOT_FOUND, "no entity " + std::to_string(entity));
    cmkit::Status s = world->world.setContents(entity, contents);
    if (!s) return failWith(s.error());
    return CMKIT_OK;
  });
}

cmkit_status cmkit_trace_model_box(float x0, float y0, float z0, float x1, float y1, float z1,
                                   cmkit_trace_model_t** out) {
  const char* const fn = __func__;
  return guarded(fn, [&] { return boundsShape(x0, y0, z0, x1, y1, z1, 0, 'b', out, fn); });
}

cmkit_status cmkit_trace_model_cylinder(float x0, float y0, float z0, float x1, float y1, float z1, int sides,
                                        cmkit_trace_model_t** out) {
  const char* const fn = __func__;
  return guarded(fn, [&] { return boundsShape(x0, y0, z0, x1, y1, z1, sides, 'c', out, fn); });
}

cmkit_status cmkit_trace_model_cone(float x0, float y0, float z0, float x1, float y1, float z1, int sides,
                                    cmkit_trace_model_t** out) {
  const char* const fn = __func__;
  return guarded(fn, [&] { return boundsShape(x0, y0, z0, x1, y1, z1, sides, 'k', out, fn); });
}

cmkit_status cmkit_trace_model_from_spec(const char* spec, cmkit_trace_model_t** out) {
  CMKIT_API_BODY {
    CMKIT_REQUIRE(spec);
    CMKIT_REQUIRE(out);
    cmkit::Result<cmkit::TraceModel> trm = cmkit::TraceModel::parse(spec);
    if (!trm) return failWith(trm.error());
    *out = new cmkit_trace_model{std::move(*trm)};
    return CMKIT_OK;
  });
}

void cmkit_trace_model_free(cmkit_trace_model_t* trm) { delete trm; }

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

namespace {

void fillRay(const cmkit::WorldRayHit& r, cmkit_ray_hit_t* out) {
  *out = cmkit_ray_hit_t{};
  out->fraction = float(r.hit.fraction);
  put(out->point, r.hit.point);
  put(out->normal, r.hit.normal);
  out->contents = r.hit.contents;
  out->material = r.hit.material;
  out->entity = r.entity;
}

}  // namespace

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

namespace {

void fillPlayer(const cmkit::PlayerState& state, cmkit_player_state_t* out) {
  *out = cmkit_player_state_t{};
  put(out->origin, state.origin);
  put(out->velocity, state.velocity);
  put(out->ground_normal, state.groundNormal);
  out->ground_entity = state.groundEntity;
  out->on_ground = state.onGround ? 1 : 0;
  out->crouched = state.crouched ? 1 : 0;
  out->stuck = state.stuck ? 1 : 0;
  out->steps = state.steps;
}

}  // namespace

cmkit_status cmkit_player_create(const cmkit_trace_model_t* shape, const float origin[3],
                                 cmkit_player_t** out) {
  CMKIT_API_BODY {
    CMKIT_REQUIRE(origin);
    CMKIT_REQUIRE(out);
    cmkit::PlayerShape playerShape = cmkit::PlayerShape::standard();
    if (shape != nullptr) {
      cmkit::Result<cmkit::PlayerShape> made = cmkit::PlayerShape::fromTraceModel(shape->trm);
      if (!made) return failWith(made.error());
      playerShape = std::move(*made);
    }
    cmkit::PlayerState state;
    state.origin = vec(origin);
    *out = new cmkit_player{std::move(playerShape), state};
    return CMKIT_OK;
  });
}

void cmkit_player_free(cmkit_player_t* player) { delete player; }

cmkit_status cmkit_player_set_origin(cmkit_player_t* player, const float origin[3]) {
  CMKIT_API_BODY {
    CMKIT_REQUIRE(player);
    CMKIT_REQUIRE(origin);
    cmkit::PlayerState state;
    state.origin = vec(origin);
    state.steps = player->state.steps;
    player->state = state;
    return CMKIT_OK;
  });
}

cmkit_status cmkit_player_step(const cmkit_world_t* world, cmkit_player_t* player, const float wish[3],
                               uint32_t buttons, int32_t steps, cmkit_player_state_t* out) {
  CMKIT_API_BODY {
    CMKIT_REQUIRE(world);
    CMKIT_REQUIRE(player);
    CMKIT_REQUIRE(wish);
    if (steps < 0) return fail(CMKIT_ERROR_INVALID_ARGUMENT, std::string(fn) + ": steps < 0");
    cmkit::PlayerInput input;
    input.wishDir = vec(wish);
    input.jump = (buttons & CMKIT_PLAYER_JUMP) != 0;
    input.crouch = (buttons & CMKIT_PLAYER_CROUCH) != 0;
    input.run = (buttons & CMKIT_PLAYER_RUN) != 0;
    player->state = cmkit::runPlayer(world->world, player->shape, player->state, input, steps,
                                     cmkit::move::kTimeStep, threadWork());
    if (out != nullptr) fillPlayer(player->state, out);
    return CMKIT_OK;
  });
}

cmkit_status cmkit_player_state(const cmkit_player_t* player, cmkit_player_state_t* out) {
  CMKIT_API_BODY {
    CMKIT_REQUIRE(player);
    CMKIT_REQUIRE(out);
    fillPlayer(player->state, out);
    return CMKIT_OK;
  });
}

}  // extern "C"
