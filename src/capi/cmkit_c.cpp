// The C API (include/cmkit/cmkit.h) over the C++ World: its errors, version,
// worlds and trace models (the queries: capi_queries.cpp; the player:
// capi_player.cpp). No exception leaves a function here (capi_support.h).
#include <filesystem>
#include <string>
#include <utility>

#include "capi/capi_support.h"
#include "cmkit/cm_file.h"
#include "cmkit/map.h"
#include "cmkit/materials.h"
#include "cmkit/version.h"

namespace {

using cmkit::Real;
using cmkit::Vec3;
using namespace cmkit::detail::capi;

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

}  // extern "C"
