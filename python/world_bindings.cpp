// world_bindings.cpp: cmkit.World (cmkit/world.h: a map's placed entities
// queried as one, and the player move of cmkit/movement.h) and
// cmkit._load_world. The queries take the arguments of cmkit.Model's and give
// its dicts (query_support.h), plus the entity hit. A shared mutex orders
// set_transform (the one writer) against queries and walks, which run
// without the GIL: a writer waits for the running queries, queries wait for
// it; every lock is taken with the GIL released, so a progress callback that
// needs the GIL never waits on a thread that holds it.
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <shared_mutex>
#include <string>
#include <vector>

#include "cmkit/audit.h"
#include "cmkit/map.h"
#include "cmkit/materials.h"
#include "cmkit/movement.h"
#include "cmkit/world.h"
#include "module_support.h"
#include "query_support.h"

namespace cmkit_python {

namespace {

struct PyWorld {
  cmkit::World world;
  cmkit::WorldLoadReport report;
  std::string path;
  std::shared_mutex mutex;  // shared: queries, walks, reads; exclusive: set_transform
};
using PyWorldClass = py::class_<PyWorld, std::shared_ptr<PyWorld>>;

// Runs `read` (plain C++, no Python objects) under the shared lock with the
// GIL released.
template <class F>
auto readLocked(PyWorld& w, F&& read) {
  py::gil_scoped_release release;
  const std::shared_lock lock(w.mutex);
  return read();
}

std::shared_ptr<PyWorld> loadWorld(const std::string& path, bool forceRebuild, bool useProc) {
  cmkit::LoadMapOptions options;
  options.forceRebuild = forceRebuild;
  options.useProcFile = useProc;
  std::optional<cmkit::Result<cmkit::LoadedWorld>> r;
  {
    py::gil_scoped_release release;
    r.emplace(cmkit::World::loadMap(path, cmkit::MaterialTable{}, options));
  }
  cmkit::LoadedWorld loaded = unwrap(std::move(*r));
  auto w = std::make_shared<PyWorld>();
  w->world = std::move(loaded.world);
  w->report = std::move(loaded.report);
  w->path = path;
  return w;
}

// An entity named by its id (int) or name (str, the first of that name);
// KeyError when there is none.
cmkit::EntityId entityOf(PyWorld& w, const py::handle& nameOrId) {
  if (py::isinstance<py::int_>(nameOrId)) {
    const auto id = nameOrId.cast<std::int64_t>();
    const bool live = id >= 0 && id < std::int64_t(INT32_MAX) &&
                      readLocked(w, [&] { return w.world.entity(cmkit::EntityId(id)) != nullptr; });
    if (!live) throw py::key_error("no entity with id " + std::to_string(id));
    return cmkit::EntityId(id);
  }
  if (py::isinstance<py::str>(nameOrId)) {
    const auto name = nameOrId.cast<std::string>();
    const cmkit::EntityId id = readLocked(w, [&] { return w.world.find(name); });
    if (id == cmkit::kNoEntity) throw py::key_error("no entity named '" + name + "'");
    return id;
  }
  throw py::type_error("an entity is given by its id (int) or name (str), not " +
                       std::string(py::str(nameOrId.get_type().attr("__name__"))));
}

// The entities a query leaves out: None, or an iterable of ids and names
// (each as entityOf reads it).
std::vector<cmkit::EntityId> ignoreList(PyWorld& w, const py::object& ignore) {
  std::vector<cmkit::EntityId> ids;
  if (ignore.is_none()) return ids;
  if (py::isinstance<py::str>(ignore) || py::isinstance<py::int_>(ignore))
    ids.push_back(entityOf(w, ignore));
  else
    for (const py::handle item : py::iter(ignore)) {
      // numpy integers (an id array) are ids too: anything with __index__.
      const bool index = !py::isinstance<py::str>(item) && py::hasattr(item, "__index__");
      ids.push_back(entityOf(w, index ? py::int_(py::reinterpret_borrow<py::object>(item)) : item));
    }
  return ids;
}

// The (N,) int32 array of the results' entities (-1: none).
template <class R>
py::array_t<std::int32_t> entityArray(const std::vector<R>& results) {
  auto a = py::array_t<std::int32_t>(py::ssize_t(results.size()));
  for (std::size_t i = 0; i < results.size(); ++i) a.mutable_data()[i] = results[i].entity;
  return a;
}

std::vector<cmkit::TraceResult> tracesOf(const std::vector<cmkit::WorldTraceResult>& out) {
  std::vector<cmkit::TraceResult> traces(out.size());
  for (std::size_t i = 0; i < out.size(); ++i) traces[i] = out[i].trace;
  return traces;
}

// ---- the queries ----------------------------------------------------------

// Runs one world batch: the entities of `ignore` left out, the GIL released,
// the World read-locked (set_transform waits), progress and threads as for
// a Model's batches. `batch(options, filter)` calls the cmkit batch function.
template <class Batch>
void runWorldBatch(PyWorld& self, int threads, const py::object& progress, const py::object& ignore,
                   const Batch& batch) {
  const std::vector<cmkit::EntityId> ignored = ignoreList(self, ignore);
  const cmkit::EntityFilter filter{ignored, {}};
  Hook hook(threads, progress);
  runBatch([&] {
    const std::shared_lock lock(self.mutex);
    return batch(hook.options, filter);
  });
}

py::dict translateWorld(PyWorld& self, const py::object& trm, const py::object& starts,
                        const py::object& ends, std::int64_t mask, const py::object& axis, bool startSolid,
                        int threads, const py::object& progress, const py::object& ignore) {
  TranslationArgs a(trm, starts, ends, mask, axis, startSolid);
  std::vector<cmkit::WorldTraceResult> out(a.size);
  runWorldBatch(self, threads, progress, ignore,
                [&](const cmkit::BatchOptions& options, const cmkit::EntityFilter& filter) {
                  return cmkit::translateBatch(self.world, a.batch, out, options, filter);
                });
  py::dict d = traceArrays(tracesOf(out));
  d["entity"] = entityArray(out);
  return d;
}

py::dict rotateWorld(PyWorld& self, const py::object& trm, const py::object& starts,
                     const py::object& origins, const py::object& axes, const py::object& angles,
                     std::int64_t mask, const py::object& axis, bool startSolid, int threads,
                     const py::object& progress, const py::object& ignore) {
  RotationArgs a(trm, starts, origins, axes, angles, mask, axis, startSolid);
  std::vector<cmkit::WorldTraceResult> out(a.size);
  runWorldBatch(self, threads, progress, ignore,
                [&](const cmkit::BatchOptions& options, const cmkit::EntityFilter& filter) {
                  return cmkit::rotateBatch(self.world, a.batch, out, options, filter);
                });
  py::dict d = traceArrays(tracesOf(out));
  d["entity"] = entityArray(out);
  return d;
}

py::dict castRaysWorld(PyWorld& self, const py::object& starts, const py::object& ends, std::int64_t mask,
                       int threads, const py::object& progress, const py::object& ignore) {
  RayArgs a(starts, ends, mask);
  std::vector<cmkit::WorldRayHit> out(a.size);
  runWorldBatch(self, threads, progress, ignore,
                [&](const cmkit::BatchOptions& options, const cmkit::EntityFilter& filter) {
                  return cmkit::castRayBatch(self.world, a.batch, out, options, filter);
                });
  std::vector<cmkit::RayHit> hits(out.size());
  for (std::size_t i = 0; i < out.size(); ++i) hits[i] = out[i].hit;
  py::dict d = rayArrays(hits);
  d["entity"] = entityArray(out);
  return d;
}

py::dict pointContentsWorld(PyWorld& self, const py::object& points, int threads, const py::object& progress,
                            const py::object& ignore) {
  PointArgs a(points);
  std::vector<cmkit::WorldPointContentsResult> out(a.size);
  runWorldBatch(self, threads, progress, ignore,
                [&](const cmkit::BatchOptions& options, const cmkit::EntityFilter& filter) {
                  return cmkit::pointContentsBatch(self.world, a.batch, out, options, filter);
                });
  std::vector<std::uint32_t> contents(out.size());
  std::vector<cmkit::QueryStatus> status(out.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    contents[i] = out[i].contents;
    status[i] = out[i].status;
  }
  py::dict d = pointContentsArrays(contents, status);
  d["entity"] = entityArray(out);
  return d;
}

py::dict contentsWorld(PyWorld& self, const py::object& trm, const py::object& positions, std::int64_t mask,
                       const py::object& axis, int threads, const py::object& progress,
                       const py::object& ignore) {
  ContentsArgs a(trm, positions, mask, axis);
  std::vector<cmkit::WorldContentsResult> out(a.size);
  runWorldBatch(self, threads, progress, ignore,
                [&](const cmkit::BatchOptions& options, const cmkit::EntityFilter& filter) {
                  return cmkit::contentsBatch(self.world, a.batch, out, options, filter);
                });
  std::vector<cmkit::ContentsResult> results(out.size());
  for (std::size_t i = 0; i < out.size(); ++i) results[i] = out[i].result;
  py::dict d = contentsArrays(results);
  d["entity"] = entityArray(out);
  return d;
}

py::dict contactsWorld(PyWorld& self, const py::object& trm, const py::object& starts, const py::object& dirs,
                       double depth, int maxContacts, const py::object& origins, const py::object& axes,
                       const py::object& angles, std::int64_t mask, const py::object& axis, int threads,
                       const py::object& progress, const py::object& ignore) {
  ContactsArgs a(trm, starts, dirs, depth, maxContacts, origins, axes, angles, mask, axis);
  std::vector<cmkit::WorldContactsResult> out(a.size);
  runWorldBatch(self, threads, progress, ignore,
                [&](const cmkit::BatchOptions& options, const cmkit::EntityFilter& filter) {
                  return cmkit::contactsBatch(self.world, a.batch, out, options, filter);
                });
  const std::size_t m = std::size_t(maxContacts);
  std::vector<cmkit::ContactsResult> results(out.size());
  auto entity = py::array_t<std::int32_t>({py::ssize_t(out.size()), py::ssize_t(m)});
  for (std::size_t i = 0; i < out.size(); ++i) {
    results[i].status = out[i].status;
    for (std::size_t k = 0; k < m; ++k)
      entity.mutable_data()[i * m + k] =
          k < out[i].contacts.size() ? out[i].contacts[k].entity : cmkit::kNoEntity;
    for (const cmkit::WorldContact& c : out[i].contacts) results[i].contacts.push_back(c.contact);
  }
  py::dict d = contactsArrays(results, maxContacts);
  d["entity"] = entity;
  return d;
}

// ---- the entities ---------------------------------------------------------

void setTransform(PyWorld& self, const py::object& nameOrId, const py::object& origin,
                  const py::object& axis) {
  const cmkit::EntityId id = entityOf(self, nameOrId);
  cmkit::Placement p;
  p.origin = vector3(origin, "origin");
  p.axis = matrix(axis, "axis");
  cmkit::Status s = cmkit::Ok{};
  {
    py::gil_scoped_release release;
    const std::unique_lock lock(self.mutex);
    s = self.world.setPlacement(id, p);
  }
  // The entity was found above and Python removes none: what is left to
  // refuse is the axis (not a rotation).
  if (!s.ok()) throw py::value_error("axis: " + s.error().message);
}

py::tuple transformOf(PyWorld& self, const py::object& nameOrId) {
  const cmkit::EntityId id = entityOf(self, nameOrId);
  const cmkit::Placement p = readLocked(self, [&] { return self.world.entity(id)->placement; });
  auto origin = py::array_t<Real>(py::ssize_t(3));
  put(origin.mutable_data(), p.origin);
  auto axis = py::array_t<Real>({py::ssize_t(3), py::ssize_t(3)});
  for (int k = 0; k < 3; ++k) put(axis.mutable_data() + 3 * k, p.axis.rows[k]);
  return py::make_tuple(origin, axis);
}

py::list entityNames(PyWorld& self) {
  const auto names = readLocked(self, [&] {
    std::vector<std::optional<std::string>> out(std::size_t(self.world.idLimit()));
    for (cmkit::EntityId id = 0; id < self.world.idLimit(); ++id)
      if (const cmkit::WorldEntity* e = self.world.entity(id)) out[std::size_t(id)] = e->name;
    return out;
  });
  py::list list;
  for (const auto& n : names) list.append(n ? py::object(py::str(*n)) : py::object(py::none()));
  return list;
}

py::dict loadInfo(const PyWorld& self) {
  const cmkit::WorldLoadReport& r = self.report;
  py::dict d;
  d["path"] = self.path;
  d["from_cm"] = r.models.fromCmFile;
  d["cm_path"] = r.models.cmPath;
  d["crc"] = r.models.geometryCrc;
  d["proc_path"] = r.models.procPath;
  d["proc_polygons_removed"] = r.models.procPolygonsRemoved;
  d["warnings"] = r.models.warnings;
  d["entities_placed"] = r.entitiesPlaced;
  d["noclip_skipped"] = r.noclipSkipped;
  d["mesh_models_skipped"] = r.meshModelsSkipped;
  d["func_groups_in_world"] = r.funcGroupsInWorld;
  return d;
}

// ---- the player move ------------------------------------------------------

// The longest walk: an hour of steps (as `cmkit walk`).
constexpr double kMaxWalkSeconds = 3600;

// A wished direction of 2 or 3 finite numbers (z ignored by the move).
Vec3 wishOf(const py::object& object) {
  const auto a = FloatArray::ensure(object);
  if (!a || a.ndim() != 1 || (a.shape(0) != 2 && a.shape(0) != 3))
    throw py::value_error("wish must be 2 or 3 numbers (dx, dy[, dz])");
  const Vec3 v{a.data()[0], a.data()[1], a.shape(0) == 3 ? a.data()[2] : Real(0)};
  if (!v.isFinite()) throw py::value_error("wish is not finite");
  return v;
}

cmkit::PlayerShape shapeOf(const py::object& object) {
  if (object.is_none()) return cmkit::PlayerShape::standard();
  if (!py::isinstance<py::str>(object) && !py::isinstance<PyTraceModel>(object))
    throw py::type_error(
        "shape must be a cmkit.TraceModel, a trace-model spec string or None (the player box)");
  const TrmArg t = trmArg(object);
  return unwrap(cmkit::PlayerShape::fromTraceModel(*t.get()));
}

py::dict walk(PyWorld& self, const py::object& start, const py::object& wish, double seconds,
              const py::object& shapeObject, bool run, bool crouch, const std::optional<double>& jumpAt,
              const py::object& startVelocity) {
  cmkit::PlayerState first;
  first.origin = vector3(start, "start");
  if (!startVelocity.is_none()) first.velocity = vector3(startVelocity, "velocity");
  if (!first.origin.isFinite() || !first.velocity.isFinite())
    throw py::value_error("start and velocity must be finite");
  cmkit::PlayerInput input;
  input.wishDir = wishOf(wish);
  input.run = run;
  input.crouch = crouch;
  if (!std::isfinite(seconds) || seconds < 0 || seconds > kMaxWalkSeconds)
    throw py::value_error("seconds must be finite, 0..3600");
  const cmkit::PlayerShape shape = shapeOf(shapeObject);
  const Real dt = cmkit::move::kTimeStep;
  const int steps = int(std::llround(seconds / double(dt)));
  int jumpStep = -1;
  if (jumpAt) {
    const double t = *jumpAt;
    if (!std::isfinite(t) || t < 0) throw py::value_error("jump_at must be finite and not negative");
    jumpStep = int(std::llround(std::min(t, kMaxWalkSeconds) / double(dt)));
  }

  std::vector<cmkit::PlayerState> path;
  path.reserve(std::size_t(steps));
  cmkit::PlayerState end;
  {
    py::gil_scoped_release release;
    const std::shared_lock lock(self.mutex);
    cmkit::WorldQueryWork work;
    if (jumpStep < 0 || jumpStep >= steps) {
      end = cmkit::runPlayer(self.world, shape, first, input, steps, dt, work, {}, &path);
    } else {  // jump pressed for the one step jumpStep (as `cmkit walk --jump-at`)
      end = cmkit::runPlayer(self.world, shape, first, input, jumpStep, dt, work, {}, &path);
      input.jump = true;
      end = cmkit::runPlayer(self.world, shape, end, input, 1, dt, work, {}, &path);
      input.jump = false;
      end = cmkit::runPlayer(self.world, shape, end, input, steps - jumpStep - 1, dt, work, {}, &path);
    }
  }

  auto origins = py::array_t<Real>({py::ssize_t(path.size()), py::ssize_t(3)});
  int stuckSteps = 0;
  for (std::size_t i = 0; i < path.size(); ++i) {
    put(origins.mutable_data() + 3 * i, path[i].origin);
    stuckSteps += path[i].stuck ? 1 : 0;
  }
  auto origin = py::array_t<Real>(py::ssize_t(3));
  put(origin.mutable_data(), end.origin);
  auto velocity = py::array_t<Real>(py::ssize_t(3));
  put(velocity.mutable_data(), end.velocity);
  const std::optional<std::string> ground = readLocked(self, [&]() -> std::optional<std::string> {
    const cmkit::WorldEntity* e = end.onGround ? self.world.entity(end.groundEntity) : nullptr;
    if (!e) return std::nullopt;
    return e->name;
  });
  py::dict d;
  d["end"] = origin;
  d["velocity"] = velocity;
  d["path"] = origins;
  d["on_ground"] = end.onGround;
  d["ground_entity"] = ground ? py::object(py::str(*ground)) : py::object(py::none());
  d["ground_entity_id"] = end.onGround ? end.groundEntity : cmkit::kNoEntity;
  d["crouched"] = end.crouched;
  d["stuck"] = end.stuck;
  d["stuck_steps"] = stuckSteps;
  d["steps"] = steps;
  return d;
}

// ---- the audit --------------------------------------------------------------

py::dict findingDict(const cmkit::AuditFinding& f, int number) {
  py::dict d;
  d["number"] = number;
  d["kind"] = std::string(cmkit::toString(f.kind));
  d["severity"] = std::string(cmkit::toString(f.severity));
  d["position"] = py::make_tuple(double(f.position.x), double(f.position.y), double(f.position.z));
  d["what"] = f.what;
  d["merged"] = f.merged;
  py::list path;
  for (const Vec3& p : f.path) path.append(py::make_tuple(double(p.x), double(p.y), double(p.z)));
  d["path"] = path;
  return d;
}

// world.audit(): cmkit/audit.h on the world, its spots read again from the
// map file it was loaded from. A writer (movers' contents are set and
// restored), so it takes the lock exclusively.
py::dict auditWorld(PyWorld& self, double grid, int threads, const py::object& starts, bool ignoreMovers,
                    bool openShells) {
  cmkit::AuditOptions options;
  options.grid = Real(grid);
  options.threads = threads;
  options.ignoreMovers = ignoreMovers;
  options.openShells = openShells;
  if (!starts.is_none()) {
    const auto a = FloatArray::ensure(starts);
    if (!a || a.ndim() != 2 || a.shape(1) != 3) throw py::value_error("starts must be an (N, 3) array");
    for (py::ssize_t i = 0; i < a.shape(0); ++i)
      options.extraStarts.push_back({a.data()[3 * i], a.data()[3 * i + 1], a.data()[3 * i + 2]});
  }
  std::optional<cmkit::Result<cmkit::AuditReport>> r;
  {
    py::gil_scoped_release release;
    cmkit::Result<cmkit::MapFile> map = cmkit::loadMapFile(self.path);
    if (!map) {
      r.emplace(map.error());
    } else {
      const std::vector<cmkit::AuditSpot> spots = cmkit::auditSpotsFromMap(*map);
      const std::unique_lock lock(self.mutex);
      r.emplace(cmkit::auditWorld(self.world, spots, options));
    }
  }
  const cmkit::AuditReport report = unwrap(std::move(*r));
  auto cells = py::array_t<Real>({py::ssize_t(report.cells.size()), py::ssize_t(3)});
  for (std::size_t i = 0; i < report.cells.size(); ++i)
    put(cells.mutable_data() + 3 * i, report.cells[i].position);
  py::dict d;
  d["reachable_cells"] = report.cells.size();
  d["cells"] = cells;
  py::list startList;
  for (const Vec3& p : report.starts) startList.append(py::make_tuple(double(p.x), double(p.y), double(p.z)));
  d["starts"] = startList;
  d["high_severity"] = report.hasHighSeverity();
  d["truncated"] = report.truncated;
  d["movers_ignored"] = report.moversIgnored;
  d["triggers_ignored"] = report.triggersIgnored;
  d["moves_tried"] = report.movesTried;
  int number = 1;
  const std::pair<const char*, const std::vector<cmkit::AuditFinding>*> lists[] = {
      {"fallouts", &report.fallOuts},
      {"stuck", &report.stuck},
      {"tunnels", &report.tunnels},
      {"embedded", &report.embedded},
      {"open_shells", &report.openShells}};
  for (const auto& [name, list] : lists) {
    py::list out;
    for (const cmkit::AuditFinding& f : *list) out.append(findingDict(f, number++));
    d[name] = out;
  }
  return d;
}

}  // namespace

void bindWorld(py::module_& m) {
  namespace c = cmkit::contents;
  PyWorldClass cls(m, "World", R"(A map's collision models placed as its entities, queried as one.

Entity 0 is the world model ('worldspawn'); then every entity with brushes or patches, placed by
its origin / rotation / angle keys. The query methods take the arguments of cmkit.Model's (less
origin= and model_axis=: each entity has its own placement) and return the same dicts plus
'entity', the id of the entity whose answer was kept (-1: none). set_transform() moves an
entity; walk() walks a player through the world. Load with cmkit.load_world(path).)");
  const std::string note =
      std::string(kBatchNote) +
      " The answer is the closest entity's (ties: the lowest id); 'entity' (N,) int32 is "
      "its id (-1: none), and 'material' and 'polygon' index that entity's model "
      "(world.model(id)). ignore: entities left out (an id or name, or a list of them: e.g. a "
      "player's own entity). See cmkit.Model's method of the same name.";
  cls.def("translate", &translateWorld, py::arg("trm"), py::arg("starts"), py::arg("ends"), py::kw_only(),
          py::arg("mask") = c::kMaskSolid, py::arg("axis") = py::none(), py::arg("start_solid") = false,
          py::arg("threads") = 0, py::arg("progress") = py::none(), py::arg("ignore") = py::none(),
          ("Moves a trace model from starts (N, 3) to ends (N, 3) through the world: the fields of "
           "Model.translate and entity (N,)." +
           note)
              .c_str())
      .def("rotate", &rotateWorld, py::arg("trm"), py::arg("starts"), py::arg("origins"), py::arg("axes"),
           py::arg("angles"), py::kw_only(), py::arg("mask") = c::kMaskSolid, py::arg("axis") = py::none(),
           py::arg("start_solid") = false, py::arg("threads") = 0, py::arg("progress") = py::none(),
           py::arg("ignore") = py::none(),
           ("Turns a trace model through the world (arguments as Model.rotate): the fields of "
            "Model.rotate and entity (N,)." +
            note)
               .c_str())
      .def("cast_rays", &castRaysWorld, py::arg("origins"), py::arg("ends"), py::kw_only(),
           py::arg("mask") = c::kMaskSolid, py::arg("threads") = 0, py::arg("progress") = py::none(),
           py::arg("ignore") = py::none(),
           ("Casts rays (segments origins -> ends) through the world (each entity's ray index): the "
            "fields of Model.cast_rays and entity (N,)." +
            note)
               .c_str())
      .def("point_contents", &pointContentsWorld, py::arg("points"), py::kw_only(), py::arg("threads") = 0,
           py::arg("progress") = py::none(), py::arg("ignore") = py::none(),
           ("The contents of the brushes containing each point, over the world: contents (N,) (the OR "
            "over the entities), status (N,) and entity (N,) (the lowest id with contents; -1: none)." +
            note)
               .c_str())
      .def("contents", &contentsWorld, py::arg("trm"), py::arg("positions"), py::kw_only(),
           py::arg("mask") = c::kMaskSolid, py::arg("axis") = py::none(), py::arg("threads") = 0,
           py::arg("progress") = py::none(), py::arg("ignore") = py::none(),
           ("Position tests over the world: the fields of Model.contents (contents: the OR over the "
            "entities; the trace fields: the lowest-id entity overlapped) and entity (N,) (that entity; "
            "-1: free)." +
            note)
               .c_str())
      .def("contacts", &contactsWorld, py::arg("trm"), py::arg("starts"), py::arg("dirs") = py::none(),
           py::arg("depth") = 0.0, py::kw_only(), py::arg("max_contacts") = 16,
           py::arg("origins") = py::none(), py::arg("axes") = py::none(), py::arg("angles") = py::none(),
           py::arg("mask") = c::kMaskSolid, py::arg("axis") = py::none(), py::arg("threads") = 0,
           py::arg("progress") = py::none(), py::arg("ignore") = py::none(),
           ("Every contact of a move or turn over the world (arguments as Model.contacts): its fields, "
            "and entity (N, max_contacts) int32, each contact's entity (-1 past count[i]); contacts in "
            "entity-id order (along rotations: by the angle, then the id), at most max_contacts in all." +
            note)
               .c_str())
      .def("set_transform", &setTransform, py::arg("entity"), py::arg("origin"), py::arg("axis") = py::none(),
           R"(Moves an entity (its id or name) to origin (3,) turned by axis (3x3, rows = axes; None:
identity): world = origin + local * axis. A writer: it waits for queries and walks running in
other threads and they wait for it (never call it from a progress callback). KeyError for an
unknown entity, ValueError for an axis that is not a rotation.)")
      .def("transform", &transformOf, py::arg("entity"),
           "(origin (3,), axis (3, 3)): where an entity (its id or name) is placed. KeyError when unknown.")
      .def(
          "find", [](PyWorld& self, const std::string& name) { return entityOf(self, py::str(name)); },
          py::arg("name"), "The id of the first entity (lowest id) named exactly `name`; KeyError when none.")
      .def(
          "model",
          [](PyWorld& self, const py::object& nameOrId) {
            const cmkit::EntityId id = entityOf(self, nameOrId);
            return std::make_shared<PyModel>(readLocked(self, [&] { return self.world.entity(id)->model; }));
          },
          py::arg("entity"),
          "The cmkit.Model of an entity (its id or name), in the entity's own frame (place it with "
          "origin=/model_axis= from transform()). KeyError when unknown.")
      .def_property_readonly("entity_names", &entityNames,
                             "Entity names, indexed by entity id ('worldspawn' first; '#N' for map entity N "
                             "without a name); None for an id no longer in use (none in a loaded world).")
      .def_property_readonly("info", &loadInfo,
                             "How the world was loaded: path, from_cm, cm_path, crc, proc_path, "
                             "proc_polygons_removed, warnings, entities_placed, noclip_skipped, "
                             "mesh_models_skipped, func_groups_in_world.")
      .def("__len__", [](PyWorld& self) { return readLocked(self, [&] { return self.world.size(); }); })
      .def("__repr__",
           [](PyWorld& self) {
             return "<cmkit.World '" + self.path + "', " +
                    std::to_string(readLocked(self, [&] { return self.world.size(); })) + " entities>";
           })
      .def("walk", &walk, py::arg("start"), py::arg("wish"), py::arg("seconds"), py::kw_only(),
           py::arg("shape") = py::none(), py::arg("run") = false, py::arg("crouch") = false,
           py::arg("jump_at") = py::none(), py::arg("velocity") = py::none(),
           R"(Walks a player (cmkit/movement.h, Doom 3's player physics) from start (3,), its feet (the
bottom centre of its shape), wishing to go along wish (dx, dy[, dz]; z ignored; length = fraction
of full speed, at most 1) for `seconds` (at most 3600) in steps of 1/60 s. The world does not
change during the walk.

shape: None (the original's box, 32 x 32 x 74, crouched 38), a TraceModel or spec string whose
origin is at the feet (crouching keeps it). run: 220 units/s instead of 140. crouch: crouched the
whole walk. jump_at: press jump once, at this time (seconds). velocity: the player's velocity
(3,) at the start (None: at rest), e.g. the last walk's, to go on from where it ended.

Returns a dict: end (3,), velocity (3,), path (steps, 3) (the feet after each step), on_ground,
ground_entity (the name of the entity stood on, or None), ground_entity_id (-1: none), crouched,
stuck (the last step started in solid and could not be freed), stuck_steps, steps. The GIL is
released while it walks.)");

  cls.def("audit", &auditWorld, py::kw_only(), py::arg("grid") = 16.0, py::arg("threads") = 1,
          py::arg("starts") = py::none(), py::arg("ignore_movers") = true, py::arg("open_shells") = true,
          R"(Audits the map (cmkit/audit.h, docs/audit.md, as `cmkit audit`): where the player can stand
from the map's info_player_start entities (and `starts`, an (N, 3) array of feet positions) on a
grid of `grid` units, and the faults found. Movers (doors, lifts, moveables) are ignored unless
ignore_movers=False. The spots (player starts, monsters, items) are read again from the map file
the world was loaded from.

Returns a dict as `cmkit audit --json` writes: reachable_cells (a count), cells (N, 3) (each
cell's standing position), starts, high_severity, truncated, movers_ignored, moves_tried, and
the lists fallouts, stuck, tunnels, embedded, open_shells of dicts (number, kind, severity,
position (x, y, z), what, merged, path). The GIL is released; it waits for running queries
(movers' contents are set for the audit and restored).)");

  m.def("_load_world", &loadWorld, py::arg("path"), py::arg("force_rebuild"), py::arg("use_proc"));
}

}  // namespace cmkit_python
