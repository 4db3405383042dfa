// cmkit_module.cpp: the Python extension module cmkit._cmkit (pybind11).
// The public package (python/cmkit/__init__.py) re-exports what is here and
// adds the Models sequence. Every batch method converts its numpy input with
// the GIL held, runs the C++ batch (cmkit/batch.h) with the GIL released, and
// builds its numpy output with the GIL held again.
#include <pybind11/eval.h>
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "cmkit/batch.h"
#include "cmkit/cm_file.h"
#include "cmkit/manager.h"
#include "cmkit/materials.h"
#include "cmkit/model.h"
#include "cmkit/query.h"
#include "cmkit/ray_index.h"
#include "cmkit/tools/query_format.h"
#include "cmkit/trace_model.h"

namespace py = pybind11;
using cmkit::Real;
using cmkit::Vec3;

namespace {

// ---- errors -------------------------------------------------------------

// cmkit.Error, created when the module is imported (see PYBIND11_MODULE).
py::object& errorClass() {
  static py::object* cls = new py::object();  // never destroyed: outlives the interpreter's teardown order
  return *cls;
}

[[noreturn]] void raise(const cmkit::Error& e) {
  py::object exc = errorClass()(e.toString(), e.file, e.line, e.column);
  PyErr_SetObject(errorClass().ptr(), exc.ptr());
  throw py::error_already_set();
}

template <class T>
T unwrap(cmkit::Result<T>&& r) {
  if (!r.ok()) raise(r.error());
  return std::move(r).value();
}

// ---- numpy in -----------------------------------------------------------

using FloatArray = py::array_t<Real, py::array::c_style | py::array::forcecast>;

// An (N, 3) array (or one (3,) vector: N = 1) as vectors; every number finite.
std::vector<Vec3> vectors(const py::handle& object, const char* name) {
  const auto a = FloatArray::ensure(object);
  if (!a) throw py::value_error(std::string(name) + " must be an array of numbers of shape (N, 3) or (3,)");
  const bool single = a.ndim() == 1 && a.shape(0) == 3;
  if (!single && !(a.ndim() == 2 && a.shape(1) == 3))
    throw py::value_error(std::string(name) + " must have shape (N, 3) or (3,), not " +
                          std::string(py::str(py::make_tuple(a.attr("shape")))));
  const std::size_t n = single ? 1 : std::size_t(a.shape(0));
  const Real* p = a.data();
  std::vector<Vec3> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    out[i] = {p[3 * i], p[3 * i + 1], p[3 * i + 2]};
    if (!out[i].isFinite())
      throw py::value_error(std::string(name) + "[" + std::to_string(i) + "] is not finite");
  }
  return out;
}

// A (3, 3) orientation (rows = axes); None: identity.
cmkit::Mat3 matrix(const py::object& object, const char* name) {
  if (object.is_none()) return {};
  const auto a = FloatArray::ensure(object);
  if (!a || a.ndim() != 2 || a.shape(0) != 3 || a.shape(1) != 3)
    throw py::value_error(std::string(name) + " must be a 3x3 matrix (rows = axes)");
  const Real* p = a.data();
  cmkit::Mat3 m{{p[0], p[1], p[2]}, {p[3], p[4], p[5]}, {p[6], p[7], p[8]}};
  if (!m.isFinite()) throw py::value_error(std::string(name) + " is not finite");
  return m;
}

Vec3 vector3(const py::object& object, const char* name) {
  const auto v = vectors(object, name);
  if (v.size() != 1) throw py::value_error(std::string(name) + " must be one vector of 3 numbers");
  return v[0];
}

std::uint32_t maskOf(std::int64_t mask) {
  if (mask < 0 || mask > 0xFFFFFFFFll) throw py::value_error("mask must be a 32-bit unsigned content mask");
  return std::uint32_t(mask);
}

// ---- trace models -------------------------------------------------------

// A trace model and how it was made (the recipe: a factory name and its
// arguments), which is how it is pickled.
struct PyTraceModel {
  cmkit::TraceModel trm;
  py::tuple recipe;
};

PyTraceModel makeTrm(cmkit::Result<cmkit::TraceModel>&& r, py::tuple recipe) {
  return {unwrap(std::move(r)), std::move(recipe)};
}

cmkit::Bounds boundsOf(const py::object& mins, const py::object& maxs) {
  return {vector3(mins, "mins"), vector3(maxs, "maxs")};
}

// The class method making a bounds-based shape (box, octahedron, ...), and
// one with a number of sides (cylinder, cone); the recipe is its name and
// arguments.
auto boundsFactory(const char* name, cmkit::Result<cmkit::TraceModel> (*make)(const cmkit::Bounds&)) {
  return [name, make](py::object mins, py::object maxs) {
    return makeTrm(make(boundsOf(mins, maxs)), py::make_tuple(name, py::make_tuple(mins, maxs)));
  };
}

auto sidedFactory(const char* name, cmkit::Result<cmkit::TraceModel> (*make)(const cmkit::Bounds&, int)) {
  return [name, make](py::object mins, py::object maxs, int sides) {
    return makeTrm(make(boundsOf(mins, maxs), sides),
                   py::make_tuple(name, py::make_tuple(mins, maxs, sides)));
  };
}

// A query's trace model argument: None (a point), a TraceModel or a spec string.
struct TrmArg {
  std::optional<cmkit::TraceModel> parsed;
  const cmkit::TraceModel* trm = nullptr;
};

TrmArg trmArg(const py::object& object) {
  TrmArg arg;
  if (object.is_none()) return arg;
  if (py::isinstance<py::str>(object)) {
    arg.parsed = unwrap(cmkit::TraceModel::parse(object.cast<std::string>()));
    arg.trm = &*arg.parsed;
  } else if (py::isinstance<PyTraceModel>(object)) {
    arg.trm = &object.cast<const PyTraceModel&>().trm;
  } else {
    throw py::type_error("trm must be a cmkit.TraceModel, a trace-model spec string or None (a point), not " +
                         std::string(py::str(object.get_type().attr("__name__"))));
  }
  return arg;
}

// ---- models -------------------------------------------------------------

struct PyModel {
  cmkit::ModelPtr model;
  std::mutex rayMutex;
  std::shared_ptr<const cmkit::RayIndex> rays;  // built on the first cast_rays

  explicit PyModel(cmkit::ModelPtr m) : model(std::move(m)) {}
  const cmkit::RayIndex& rayIndex() {  // call without the GIL
    const std::lock_guard lock(rayMutex);
    if (!rays) rays = std::make_shared<const cmkit::RayIndex>(*model);
    return *rays;
  }
};

cmkit::Placement placementOf(const py::object& origin, const py::object& axis) {
  cmkit::Placement p;
  if (!origin.is_none()) p.origin = vector3(origin, "origin");
  p.axis = matrix(axis, "model_axis");
  return p;
}

// Batch options with the progress hook: the Python callable (if any) is
// called with the GIL; Ctrl-C (a pending signal) cancels the batch.
struct Hook {
  py::object callback;
  cmkit::BatchOptions options;

  Hook(int threads, py::object cb) : callback(std::move(cb)) {
    if (threads < 0) throw py::value_error("threads must be 0 (all cores) or more");
    options.threads = threads;
    options.progress = [this](std::size_t done, std::size_t total) {
      py::gil_scoped_acquire gil;
      if (PyErr_CheckSignals() != 0) return false;  // the exception stays set
      if (callback.is_none()) return true;
      try {
        const py::object r = callback(done, total);
        return r.is_none() || r.cast<bool>();
      } catch (py::error_already_set& e) {
        e.restore();  // re-raised when the batch returns
        return false;
      }
    };
  }
};

// Runs a batch without the GIL; a Python exception from the hook (or a
// signal) wins over the batch's "cancelled" error.
template <class F>
void runBatch(F&& run) {
  cmkit::Status s = cmkit::Ok{};
  {
    py::gil_scoped_release release;
    s = run();
  }
  if (PyErr_Occurred()) throw py::error_already_set();
  if (!s.ok()) raise(s.error());
}

template <class T, std::size_t K>
py::array_t<T> array(std::size_t n, const std::array<std::size_t, K>& inner = {}) {
  std::vector<py::ssize_t> shape{py::ssize_t(n)};
  for (auto d : inner) shape.push_back(py::ssize_t(d));
  return py::array_t<T>(shape);
}

void put(Real* p, const Vec3& v) {
  p[0] = v.x;
  p[1] = v.y;
  p[2] = v.z;
}

// The fields of a contact, for rows n of (n, m) arrays.
struct ContactArrays {
  py::array_t<Real> point, normal, dist;
  py::array_t<std::uint32_t> contents;
  py::array_t<std::uint8_t> type;
  py::array_t<std::int32_t> material, modelFeature, trmFeature;

  ContactArrays(std::vector<py::ssize_t> shape) {
    auto vec = shape;
    vec.push_back(3);
    point = py::array_t<Real>(vec);
    normal = py::array_t<Real>(vec);
    dist = py::array_t<Real>(shape);
    contents = py::array_t<std::uint32_t>(shape);
    type = py::array_t<std::uint8_t>(shape);
    material = py::array_t<std::int32_t>(shape);
    modelFeature = py::array_t<std::int32_t>(shape);
    trmFeature = py::array_t<std::int32_t>(shape);
  }
  void set(std::size_t i, const cmkit::ContactInfo& c) {
    put(point.mutable_data() + 3 * i, c.point);
    put(normal.mutable_data() + 3 * i, c.normal);
    dist.mutable_data()[i] = c.dist;
    contents.mutable_data()[i] = c.contents;
    type.mutable_data()[i] = std::uint8_t(c.type);
    material.mutable_data()[i] = c.material;
    modelFeature.mutable_data()[i] = c.modelFeature;
    trmFeature.mutable_data()[i] = c.trmFeature;
  }
  void into(py::dict& d) const {
    d["point"] = point;
    d["normal"] = normal;
    d["dist"] = dist;
    d["contents"] = contents;
    d["type"] = type;
    d["material"] = material;
    d["model_feature"] = modelFeature;
    d["trm_feature"] = trmFeature;
  }
};

// The (N,) uint8 array of the results' QueryStatus values (STATUS_*).
template <class R>
py::array_t<std::uint8_t> statusArray(const std::vector<R>& results) {
  auto status = py::array_t<std::uint8_t>(py::ssize_t(results.size()));
  for (std::size_t i = 0; i < results.size(); ++i) status.mutable_data()[i] = std::uint8_t(results[i].status);
  return status;
}

py::dict traceArrays(const std::vector<cmkit::TraceResult>& results) {
  const std::size_t n = results.size();
  auto fraction = py::array_t<Real>(py::ssize_t(n));
  auto endpos = py::array_t<Real>({py::ssize_t(n), py::ssize_t(3)});
  auto endaxis = py::array_t<Real>({py::ssize_t(n), py::ssize_t(3), py::ssize_t(3)});
  auto startSolid = py::array_t<bool>(py::ssize_t(n));
  ContactArrays contact({py::ssize_t(n)});
  for (std::size_t i = 0; i < n; ++i) {
    const auto& r = results[i];
    fraction.mutable_data()[i] = r.fraction;
    put(endpos.mutable_data() + 3 * i, r.endPos);
    for (int k = 0; k < 3; ++k) put(endaxis.mutable_data() + 9 * i + 3 * k, r.endAxis.rows[k]);
    startSolid.mutable_data()[i] = r.startSolid;
    contact.set(i, r.contact);
  }
  py::dict d;
  d["fraction"] = fraction;
  d["endpos"] = endpos;
  d["endaxis"] = endaxis;
  d["start_solid"] = startSolid;
  d["status"] = statusArray(results);
  contact.into(d);
  return d;
}

py::dict translateBatch(PyModel& self, const py::object& trm, const py::object& starts,
                        const py::object& ends, std::int64_t mask, const py::object& axis, bool startSolid,
                        const py::object& origin, const py::object& modelAxis, int threads,
                        const py::object& progress) {
  const TrmArg t = trmArg(trm);
  const auto s = vectors(starts, "starts"), e = vectors(ends, "ends");
  cmkit::TranslationBatch b;
  b.query.trm = t.trm;
  b.query.trmAxis = matrix(axis, "axis");
  b.query.contentMask = maskOf(mask);
  b.query.placement = placementOf(origin, modelAxis);
  b.query.detectStartSolid = startSolid;
  b.starts = s;
  b.ends = e;
  const auto n = unwrap(cmkit::batchSize(s.size(), e.size(), "starts and ends"));
  std::vector<cmkit::TraceResult> out(n);
  Hook hook(threads, progress);
  runBatch([&] { return cmkit::translateBatch(*self.model, b, out, hook.options); });
  return traceArrays(out);
}

py::dict rotateBatch(PyModel& self, const py::object& trm, const py::object& starts,
                     const py::object& origins, const py::object& axes, const py::object& angles,
                     std::int64_t mask, const py::object& axis, bool startSolid, const py::object& origin,
                     const py::object& modelAxis, int threads, const py::object& progress) {
  const TrmArg t = trmArg(trm);
  const auto s = vectors(starts, "starts"), o = vectors(origins, "origins"), a = vectors(axes, "axes");
  const auto deg = py::array_t<Real, py::array::c_style | py::array::forcecast>::ensure(angles);
  if (!deg || deg.ndim() > 1) throw py::value_error("angles must be a number or an array of shape (N,)");
  const std::size_t numAngles = deg.ndim() == 0 ? 1 : std::size_t(deg.shape(0));
  std::size_t n = unwrap(cmkit::batchSize(o.size(), a.size(), "origins and axes"));
  n = unwrap(cmkit::batchSize(n, numAngles, "rotations (origins, axes) and angles"));
  std::vector<cmkit::Rotation> rotations(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Real angle = deg.data()[numAngles == 1 ? 0 : i];
    const Vec3 ax = a[a.size() == 1 ? 0 : i];
    if (!std::isfinite(angle)) throw py::value_error("angles[" + std::to_string(i) + "] is not finite");
    const Real len = ax.length();
    if (!(std::abs(len - 1) < Real(1e-3)))
      throw py::value_error("axes[" + std::to_string(i) + "] must be a unit vector");
    rotations[i] = cmkit::Rotation(o[o.size() == 1 ? 0 : i], ax, angle);
  }
  cmkit::RotationBatch b;
  b.query.trm = t.trm;
  b.query.trmAxis = matrix(axis, "axis");
  b.query.contentMask = maskOf(mask);
  b.query.placement = placementOf(origin, modelAxis);
  b.query.detectStartSolid = startSolid;
  b.starts = s;
  b.rotations = rotations;
  std::vector<cmkit::TraceResult> out(unwrap(cmkit::batchSize(s.size(), n, "starts and rotations")));
  Hook hook(threads, progress);
  runBatch([&] { return cmkit::rotateBatch(*self.model, b, out, hook.options); });
  return traceArrays(out);
}

py::dict castRays(PyModel& self, const py::object& starts, const py::object& ends, std::int64_t mask,
                  const py::object& origin, const py::object& modelAxis, int threads,
                  const py::object& progress) {
  const auto s = vectors(starts, "origins"), e = vectors(ends, "ends");
  cmkit::RayBatch b;
  b.query.contentMask = maskOf(mask);
  b.query.placement = placementOf(origin, modelAxis);
  b.starts = s;
  b.ends = e;
  const std::size_t n = unwrap(cmkit::batchSize(s.size(), e.size(), "origins and ends"));
  std::vector<cmkit::RayHit> out(n);
  Hook hook(threads, progress);
  runBatch([&] { return cmkit::castRayBatch(self.rayIndex(), b, out, hook.options); });
  auto fraction = py::array_t<Real>(py::ssize_t(n));
  auto point = py::array_t<Real>({py::ssize_t(n), py::ssize_t(3)});
  auto normal = py::array_t<Real>({py::ssize_t(n), py::ssize_t(3)});
  auto dist = py::array_t<Real>(py::ssize_t(n));
  auto polygon = py::array_t<std::int32_t>(py::ssize_t(n));
  auto contents = py::array_t<std::uint32_t>(py::ssize_t(n));
  auto material = py::array_t<std::int32_t>(py::ssize_t(n));
  auto hit = py::array_t<bool>(py::ssize_t(n));
  for (std::size_t i = 0; i < n; ++i) {
    const auto& h = out[i];
    fraction.mutable_data()[i] = h.fraction;
    put(point.mutable_data() + 3 * i, h.point);
    put(normal.mutable_data() + 3 * i, h.normal);
    dist.mutable_data()[i] = h.dist;
    polygon.mutable_data()[i] = h.polygon;
    contents.mutable_data()[i] = h.contents;
    material.mutable_data()[i] = h.material;
    hit.mutable_data()[i] = h.hit();
  }
  py::dict d;
  d["fraction"] = fraction;
  d["endpos"] = point;
  d["normal"] = normal;
  d["dist"] = dist;
  d["contents"] = contents;
  d["material"] = material;
  d["polygon"] = polygon;
  d["hit"] = hit;
  return d;
}

py::dict pointContents(PyModel& self, const py::object& points, const py::object& origin,
                       const py::object& modelAxis, int threads, const py::object& progress) {
  const auto p = vectors(points, "points");
  cmkit::PointContentsBatch b;
  b.query.placement = placementOf(origin, modelAxis);
  b.points = p;
  std::vector<cmkit::PointContentsResult> out(p.size());
  Hook hook(threads, progress);
  runBatch([&] { return cmkit::pointContentsBatch(*self.model, b, out, hook.options); });
  auto contents = py::array_t<std::uint32_t>(py::ssize_t(out.size()));
  for (std::size_t i = 0; i < out.size(); ++i) contents.mutable_data()[i] = out[i].contents;
  py::dict d;
  d["contents"] = contents;
  d["status"] = statusArray(out);
  return d;
}

py::dict contentsBatch(PyModel& self, const py::object& trm, const py::object& positions, std::int64_t mask,
                       const py::object& axis, const py::object& origin, const py::object& modelAxis,
                       int threads, const py::object& progress) {
  const TrmArg t = trmArg(trm);
  const auto p = vectors(positions, "positions");
  cmkit::ContentsBatch b;
  b.query.trm = t.trm;
  b.query.trmAxis = matrix(axis, "axis");
  b.query.contentMask = maskOf(mask);
  b.query.placement = placementOf(origin, modelAxis);
  b.positions = p;
  std::vector<cmkit::ContentsResult> out(p.size());
  Hook hook(threads, progress);
  runBatch([&] { return cmkit::contentsBatch(*self.model, b, out, hook.options); });
  std::vector<cmkit::TraceResult> traces(out.size());
  auto contents = py::array_t<std::uint32_t>(py::ssize_t(out.size()));
  for (std::size_t i = 0; i < out.size(); ++i) {
    traces[i] = out[i].trace;
    contents.mutable_data()[i] = out[i].contents;
  }
  py::dict d = traceArrays(traces);
  d["contact_contents"] = d["contents"];
  d["contents"] = contents;
  d["status"] = statusArray(out);
  return d;
}

py::dict contactsBatch(PyModel& self, const py::object& trm, const py::object& starts, const py::object& dirs,
                       double depth, int maxContacts, std::int64_t mask, const py::object& axis,
                       const py::object& origin, const py::object& modelAxis, int threads,
                       const py::object& progress) {
  const TrmArg t = trmArg(trm);
  const auto s = vectors(starts, "starts"), dv = vectors(dirs, "dirs");
  if (!std::isfinite(depth) || depth < 0) throw py::value_error("depth must be finite and not negative");
  if (maxContacts < 1 || maxContacts > 1024) throw py::value_error("max_contacts must be 1..1024");
  cmkit::ContactsBatch b;
  b.query.trm = t.trm;
  b.query.trmAxis = matrix(axis, "axis");
  b.query.depth = Real(depth);
  b.query.maxContacts = maxContacts;
  b.query.contentMask = maskOf(mask);
  b.query.placement = placementOf(origin, modelAxis);
  b.starts = s;
  b.dirs = dv;
  const std::size_t n = unwrap(cmkit::batchSize(s.size(), dv.size(), "starts and dirs"));
  std::vector<cmkit::ContactsResult> out(n);
  Hook hook(threads, progress);
  runBatch([&] { return cmkit::contactsBatch(*self.model, b, out, hook.options); });
  const std::size_t m = std::size_t(maxContacts);
  auto count = py::array_t<std::int32_t>(py::ssize_t(n));
  ContactArrays arrays({py::ssize_t(n), py::ssize_t(m)});
  const cmkit::ContactInfo none;
  for (std::size_t i = 0; i < n; ++i) {
    const auto& list = out[i].contacts;
    count.mutable_data()[i] = std::int32_t(list.size());
    for (std::size_t k = 0; k < m; ++k) arrays.set(i * m + k, k < list.size() ? list[k] : none);
  }
  py::dict d;
  d["count"] = count;
  d["status"] = statusArray(out);
  arrays.into(d);
  return d;
}

// ---- loading --------------------------------------------------------------

std::vector<std::shared_ptr<PyModel>> wrap(const std::vector<cmkit::ModelPtr>& models) {
  std::vector<std::shared_ptr<PyModel>> out;
  for (const auto& m : models) out.push_back(std::make_shared<PyModel>(m));
  return out;
}

py::tuple loadMap(const std::string& path, bool forceRebuild, bool useProc) {
  cmkit::LoadMapOptions options;
  options.forceRebuild = forceRebuild;
  options.useProcFile = useProc;
  cmkit::ModelManager manager;
  std::optional<cmkit::Result<cmkit::LoadMapResult>> r;
  {
    py::gil_scoped_release release;
    r.emplace(manager.loadMap(path, cmkit::MaterialTable{}, options));
  }
  const cmkit::LoadMapResult info = unwrap(std::move(*r));
  std::vector<cmkit::ModelPtr> models;
  for (const auto h : info.handles) models.push_back(manager.get(h));
  py::dict d;
  d["from_cm"] = info.fromCmFile;
  d["cm_path"] = info.cmPath;
  d["crc"] = info.geometryCrc;
  d["proc_path"] = info.procPath;
  d["proc_polygons_removed"] = info.procPolygonsRemoved;
  return py::make_tuple(wrap(models), d);
}

py::tuple parseCm(const std::string& text, const std::string& name) {
  std::optional<cmkit::Result<cmkit::CmFile>> r;
  {
    py::gil_scoped_release release;
    r.emplace(cmkit::parseCmText(text, name, cmkit::MaterialTable{}));
  }
  cmkit::CmFile file = unwrap(std::move(*r));
  return py::make_tuple(wrap(file.models), file.crc);
}

py::tuple loadCm(const std::string& path) {
  std::optional<cmkit::Result<cmkit::CmFile>> r;
  {
    py::gil_scoped_release release;
    r.emplace(cmkit::loadCmFile(path, cmkit::MaterialTable{}));
  }
  cmkit::CmFile file = unwrap(std::move(*r));
  return py::make_tuple(wrap(file.models), file.crc);
}

std::vector<cmkit::ModelPtr> unwrapModels(const std::vector<std::shared_ptr<PyModel>>& models) {
  std::vector<cmkit::ModelPtr> out;
  for (const auto& m : models) out.push_back(m->model);
  return out;
}

// The query-format line parser and runner of the C++ API, for the tests that
// check the Python methods against it (tests/python).
py::array_t<Real> vecArray(const Vec3& v) {
  auto a = py::array_t<Real>(py::ssize_t(3));
  put(a.mutable_data(), v);
  return a;
}

py::array_t<Real> matArray(const cmkit::Mat3& m) {
  auto a = py::array_t<Real>({py::ssize_t(3), py::ssize_t(3)});
  for (int k = 0; k < 3; ++k) put(a.mutable_data() + 3 * k, m.rows[k]);
  return a;
}

py::object parseQueryLine(const std::vector<std::shared_ptr<PyModel>>& models, const std::string& line) {
  const auto ms = unwrapModels(models);
  auto r = cmkit::parseQueryLine(ms, line);
  if (!r.ok()) return py::none();
  const cmkit::ParsedQuery& q = *r;
  py::dict d;
  d["op"] = cmkit::toString(q.op);
  d["trm"] = q.trm ? py::cast(q.trmSpec) : py::none();
  d["trm_axis"] = matArray(q.trmAxis);
  d["start"] = vecArray(q.position);
  d["end"] = vecArray(q.end);
  d["dir"] = vecArray(q.dir);
  d["depth"] = q.depth;
  d["max_contacts"] = q.maxContacts;
  d["rot_origin"] = vecArray(q.rotation.origin);
  d["rot_axis"] = vecArray(q.rotation.axis);
  d["angle"] = q.rotation.angle;
  d["mask"] = q.contentMask;
  d["model"] = q.model;
  d["origin"] = vecArray(q.placement.origin);
  d["model_axis"] = matArray(q.placement.axis);
  return d;
}

py::array_t<Real> boundsArray(const cmkit::Bounds& b) {
  auto a = py::array_t<Real>({py::ssize_t(2), py::ssize_t(3)});
  put(a.mutable_data(), b.min);
  put(a.mutable_data() + 3, b.max);
  return a;
}

}  // namespace

PYBIND11_MODULE(_cmkit, m) {
  m.doc() = "The C++ core of the cmkit package (use `import cmkit`).";

  py::exec(R"(
class Error(Exception):
    """A cmkit error: bad input file, bad trace model, refused batch.

    str(error) is "file:line:column: message" where those are known; the
    parts are also attributes: message, file, line, column (0 when unknown).
    """
    def __init__(self, text, file="", line=0, column=0):
        super().__init__(text)
        self.file = file
        self.line = line
        self.column = column
)",
           m.attr("__dict__"));
  errorClass() = m.attr("Error");
  m.attr("Error").attr("__module__") = "cmkit";

  namespace c = cmkit::contents;
  m.attr("CONTENTS_SOLID") = c::kSolid;
  m.attr("MASK_ALL") = c::kMaskAll;
  m.attr("MASK_SOLID") = c::kMaskSolid;
  m.attr("MASK_PLAYER_SOLID") = c::kMaskPlayerSolid;
  m.attr("MASK_MONSTER_SOLID") = c::kMaskMonsterSolid;
  m.attr("MASK_WATER") = c::kMaskWater;
  m.attr("MASK_OPAQUE") = c::kMaskOpaque;
  m.attr("CONTACT_NONE") = int(cmkit::ContactType::None);
  m.attr("CONTACT_EDGE") = int(cmkit::ContactType::Edge);
  m.attr("CONTACT_MODEL_VERTEX") = int(cmkit::ContactType::ModelVertex);
  m.attr("CONTACT_TRM_VERTEX") = int(cmkit::ContactType::TrmVertex);
  m.attr("STATUS_OK") = int(cmkit::QueryStatus::Ok);
  m.attr("STATUS_BAD_TRM_AXIS") = int(cmkit::QueryStatus::BadTrmAxis);
  m.attr("STATUS_BAD_MODEL_AXIS") = int(cmkit::QueryStatus::BadModelAxis);
  m.attr("STATUS_NON_FINITE") = int(cmkit::QueryStatus::NonFinite);
  m.attr("STATUS_OUT_OF_RANGE") = int(cmkit::QueryStatus::OutOfRange);
  m.attr("STATUS_BAD_ROTATION_AXIS") = int(cmkit::QueryStatus::BadRotationAxis);
  m.def(
      "status_name",
      [](int status) {
        if (status < int(cmkit::QueryStatus::Ok) || status > int(cmkit::QueryStatus::BadRotationAxis))
          throw py::value_error("not a query status (STATUS_*): " + std::to_string(status));
        return std::string(cmkit::toString(cmkit::QueryStatus(status)));
      },
      py::arg("status"),
      "A short English description of a query status (STATUS_*; the 'status' result arrays), as C++'s "
      "toString(QueryStatus): 'ok', 'trace-model axis is not a rotation ...'.");
  m.def("content_names", &cmkit::contentsToString, py::arg("contents"),
        "The names of the content flags set in `contents` (e.g. 'solid,playerclip').");

  py::class_<PyTraceModel>(m, "TraceModel",
                           R"(A shape to move through collision models (the original's idTraceModel).

Make one with the class methods (box, cylinder, ...) or from_spec("box:-16,-16,0,16,16,72").
Coordinates are relative to the trace model's position in a query.)")
      .def_static(
          "point",
          [] {
            return PyTraceModel{cmkit::TraceModel::point(), py::make_tuple("point", py::tuple())};
          },
          "A single point (queries with it are point traces).")
      .def_static("box", boundsFactory("box", &cmkit::TraceModel::box), py::arg("mins"), py::arg("maxs"),
                  "An axis-aligned box from corner `mins` to corner `maxs`.")
      .def_static("octahedron", boundsFactory("octahedron", &cmkit::TraceModel::octahedron), py::arg("mins"),
                  py::arg("maxs"), "An octahedron with its vertices at the face centres of the bounds.")
      .def_static("dodecahedron", boundsFactory("dodecahedron", &cmkit::TraceModel::dodecahedron),
                  py::arg("mins"), py::arg("maxs"), "A dodecahedron scaled per axis to the bounds.")
      .def_static("cylinder", sidedFactory("cylinder", &cmkit::TraceModel::cylinder), py::arg("mins"),
                  py::arg("maxs"), py::arg("sides") = 8,
                  "A prism with `sides` (3..10) vertical faces on the ellipse inscribed in the bounds.")
      .def_static("cone", sidedFactory("cone", &cmkit::TraceModel::cone), py::arg("mins"), py::arg("maxs"),
                  py::arg("sides") = 8,
                  "A cone with `sides` (3..15) faces: base at mins.z, apex above the centre at maxs.z.")
      .def_static(
          "bone",
          [](double length, double width) {
            return makeTrm(cmkit::TraceModel::bone(Real(length), Real(width)),
                           py::make_tuple("bone", py::make_tuple(length, width)));
          },
          py::arg("length"), py::arg("width"), "The original's bone: two tetrahedra sharing a triangle.")
      .def_static(
          "polygon",
          [](py::object vertices) {
            const auto v = vectors(vertices, "vertices");
            return makeTrm(cmkit::TraceModel::polygon(v),
                           py::make_tuple("polygon", py::make_tuple(vertices)));
          },
          py::arg("vertices"),
          "A planar convex polygon, (N, 3) vertices counter-clockwise around its normal.")
      .def_static(
          "polygon_volume",
          [](py::object vertices, double thickness) {
            const auto v = vectors(vertices, "vertices");
            return makeTrm(cmkit::TraceModel::polygonVolume(v, Real(thickness)),
                           py::make_tuple("polygon_volume", py::make_tuple(vertices, thickness)));
          },
          py::arg("vertices"), py::arg("thickness"), "A polygon extruded backwards by `thickness`.")
      .def_static(
          "convex_hull",
          [](py::object points) {
            const auto v = vectors(points, "points");
            return makeTrm(cmkit::TraceModel::convexHull(v),
                           py::make_tuple("convex_hull", py::make_tuple(points)));
          },
          py::arg("points"), "The convex hull of (N, 3) points.")
      .def_static(
          "from_spec",
          [](const std::string& spec) {
            return makeTrm(cmkit::TraceModel::parse(spec), py::make_tuple("from_spec", py::make_tuple(spec)));
          },
          py::arg("spec"),
          "A trace model in the query format's spelling: 'point', 'box:x0,y0,z0,x1,y1,z1', 'cylinder:N:...', "
          "'cone:N:...', 'octahedron:...', 'dodecahedron:...', 'bone:length,width', 'polygon:x,y,z;...', "
          "'polygonvolume:T:x,y,z;...', 'hull:x,y,z;...'.")
      .def_property_readonly(
          "shape", [](const PyTraceModel& t) { return std::string(cmkit::toString(t.trm.shape())); },
          "The kind of shape ('box', 'cylinder', ...).")
      .def_property_readonly(
          "is_point", [](const PyTraceModel& t) { return t.trm.isPoint(); }, "True for a single point.")
      .def_property_readonly(
          "is_convex", [](const PyTraceModel& t) { return t.trm.isConvex(); },
          "True for a closed convex solid.")
      .def_property_readonly(
          "num_vertices", [](const PyTraceModel& t) { return t.trm.numVertices(); }, "Number of vertices.")
      .def_property_readonly(
          "num_edges", [](const PyTraceModel& t) { return t.trm.numEdges(); }, "Number of edges.")
      .def_property_readonly(
          "num_polygons", [](const PyTraceModel& t) { return t.trm.numPolygons(); }, "Number of polygons.")
      .def_property_readonly(
          "bounds", [](const PyTraceModel& t) { return boundsArray(t.trm.bounds()); },
          "(2, 3) array: the bounds' minimum and maximum corners.")
      .def_property_readonly(
          "vertices",
          [](const PyTraceModel& t) {
            const auto v = t.trm.vertices();
            auto a = py::array_t<Real>({py::ssize_t(v.size()), py::ssize_t(3)});
            for (std::size_t i = 0; i < v.size(); ++i) put(a.mutable_data() + 3 * i, v[i]);
            return a;
          },
          "(N, 3) array of the vertices.")
      .def("__repr__",
           [](const PyTraceModel& t) {
             return "<cmkit.TraceModel " + std::string(cmkit::toString(t.trm.shape())) + ", " +
                    std::to_string(t.trm.numVertices()) + " vertices>";
           })
      .def("__eq__", [](const PyTraceModel& a, const PyTraceModel& b) { return a.trm == b.trm; })
      .def(py::pickle([](const PyTraceModel& t) { return t.recipe; },
                      [](const py::tuple& recipe) {
                        if (recipe.size() != 2) throw py::value_error("not a pickled cmkit.TraceModel");
                        const py::object cls = py::module_::import("cmkit._cmkit").attr("TraceModel");
                        return cls.attr(recipe[0])(*recipe[1]).cast<PyTraceModel>();
                      }));

  const char* batchNote =
      "\n\nEvery batch method takes threads= (0: all cores; results are identical at any count) and "
      "progress= (a callable(done, total) called now and then on the calling thread; return False "
      "to cancel: cmkit.Error is raised). The GIL is released while it runs; Ctrl-C cancels it. "
      "Coordinates are float32 (float64 input is rounded). origin=/model_axis= place the model in "
      "the world (default: where it was built).";

  py::class_<PyModel, std::shared_ptr<PyModel>>(
      m, "Model", R"(A collision model (immutable): the world or one entity of a map.

Queries are methods taking numpy arrays; see translate, rotate, cast_rays, point_contents,
contents, contacts. Models pickle as .cm text, so they travel to worker processes.)")
      .def_property_readonly(
          "name", [](const PyModel& s) { return s.model->name(); },
          "The model's name ('worldMap', an entity name).")
      .def_property_readonly(
          "bounds", [](const PyModel& s) { return boundsArray(s.model->bounds()); },
          "(2, 3) array: the minimum and maximum corners.")
      .def_property_readonly(
          "content_flags", [](const PyModel& s) { return s.model->contents(); },
          "The OR of the contents of all polygons and brushes (contents() is the position test).")
      .def_property_readonly(
          "materials",
          [](const PyModel& s) {
            const auto names = s.model->materials();
            return std::vector<std::string>(names.begin(), names.end());
          },
          "Material names; the 'material' result arrays index this list (-1: none).")
      .def_property_readonly(
          "num_polygons", [](const PyModel& s) { return s.model->polygons().size(); }, "Number of polygons.")
      .def_property_readonly(
          "num_brushes", [](const PyModel& s) { return s.model->brushes().size(); }, "Number of brushes.")
      .def_property_readonly(
          "num_vertices", [](const PyModel& s) { return s.model->vertices().size(); }, "Number of vertices.")
      .def(
          "to_cm",
          [](const PyModel& s) { return cmkit::writeCmText(std::vector<cmkit::ModelPtr>{s.model}, 0); },
          "The model as .cm text (CRC 0).")
      .def("__repr__",
           [](const PyModel& s) {
             return "<cmkit.Model '" + s.model->name() + "', " + std::to_string(s.model->polygons().size()) +
                    " polygons, " + std::to_string(s.model->brushes().size()) + " brushes>";
           })
      .def(py::pickle(
          [](const PyModel& s) { return cmkit::writeCmText(std::vector<cmkit::ModelPtr>{s.model}, 0); },
          [](const std::string& text) {
            auto file = unwrap(cmkit::parseCmText(text, "<pickled model>", cmkit::MaterialTable{}));
            if (file.models.size() != 1) throw py::value_error("not a pickled cmkit.Model");
            return std::make_shared<PyModel>(file.models[0]);
          }))
      .def("translate", &translateBatch, py::arg("trm"), py::arg("starts"), py::arg("ends"), py::kw_only(),
           py::arg("mask") = c::kMaskSolid, py::arg("axis") = py::none(), py::arg("start_solid") = false,
           py::arg("origin") = py::none(), py::arg("model_axis") = py::none(), py::arg("threads") = 0,
           py::arg("progress") = py::none(),
           (std::string(
                R"(Moves a trace model from starts (N, 3) to ends (N, 3) (either may be one (3,) point).

trm: a TraceModel, a spec string or None (a point trace). axis: the trace model's
orientation (3x3, rows = axes). start_solid=True also tests the start positions.
Returns a dict of arrays: fraction (N,), endpos (N, 3), endaxis (N, 3, 3), start_solid (N,),
status (N,) (STATUS_*: STATUS_OK, or why the query was refused), and the contact: point (N, 3), normal (N, 3), dist (N,), contents (N,), type (N,) (CONTACT_*),
material (N,), model_feature (N,), trm_feature (N,).)") +
            batchNote)
               .c_str())
      .def("rotate", &rotateBatch, py::arg("trm"), py::arg("starts"), py::arg("origins"), py::arg("axes"),
           py::arg("angles"), py::kw_only(), py::arg("mask") = c::kMaskSolid, py::arg("axis") = py::none(),
           py::arg("start_solid") = false, py::arg("origin") = py::none(), py::arg("model_axis") = py::none(),
           py::arg("threads") = 0, py::arg("progress") = py::none(),
           (std::string(R"(Turns a trace model at starts (N, 3) about the lines through origins (N, 3)
along the unit vectors axes (N, 3) by angles (N,) degrees (positive: clockwise seen from the
axis tip). Any of them may be given once for all. Returns the fields of translate();
fraction is the fraction of the angle turned.)") +
            batchNote)
               .c_str())
      .def("cast_rays", &castRays, py::arg("origins"), py::arg("ends"), py::kw_only(),
           py::arg("mask") = c::kMaskSolid, py::arg("origin") = py::none(),
           py::arg("model_axis") = py::none(), py::arg("threads") = 0, py::arg("progress") = py::none(),
           (std::string(
                R"(Casts rays (segments origins -> ends) through the model's ray index (built on first use).

Returns a dict of arrays: fraction (N,) (1: no hit), endpos (N, 3) (the surface crossing),
normal (N, 3), dist (N,), contents (N,), material (N,), polygon (N,) (-1: no hit), hit (N,).
Unlike translate() with a point it reports the surface crossing itself (no 0.25 unit stop).)") +
            batchNote)
               .c_str())
      .def("point_contents", &pointContents, py::arg("points"), py::kw_only(), py::arg("origin") = py::none(),
           py::arg("model_axis") = py::none(), py::arg("threads") = 0, py::arg("progress") = py::none(),
           (std::string(
                R"(The contents of the brushes containing each point of points (N, 3).

Returns a dict: contents (N,) uint32 (0: in no brush), status (N,) (STATUS_*; a refused point,
e.g. NaN or beyond 1e9 units, has contents 0).)") +
            batchNote)
               .c_str())
      .def("contents", &contentsBatch, py::arg("trm"), py::arg("positions"), py::kw_only(),
           py::arg("mask") = c::kMaskSolid, py::arg("axis") = py::none(), py::arg("origin") = py::none(),
           py::arg("model_axis") = py::none(), py::arg("threads") = 0, py::arg("progress") = py::none(),
           (std::string(R"(Position tests: what the trace model overlaps at each of positions (N, 3).

Returns a dict: contents (N,) (the first brush or polygon found overlapping, 0: free),
status (N,) (STATUS_*), fraction (N,) (0: stuck, 1: free), and the contact fields of translate() (its contents as
contact_contents).)") +
            batchNote)
               .c_str())
      .def("contacts", &contactsBatch, py::arg("trm"), py::arg("starts"), py::arg("dirs"), py::arg("depth"),
           py::kw_only(), py::arg("max_contacts") = 16, py::arg("mask") = c::kMaskSolid,
           py::arg("axis") = py::none(), py::arg("origin") = py::none(), py::arg("model_axis") = py::none(),
           py::arg("threads") = 0, py::arg("progress") = py::none(),
           (std::string(
                R"(Every surface the trace model touches moved from starts (N, 3) along dirs (N, 3) by depth.

Returns a dict: count (N,), status (N,) (STATUS_*), and the contact fields of translate() with shape (N, max_contacts, ...);
entries past count[i] hold type CONTACT_NONE, material -1 and zeros.)") +
            batchNote)
               .c_str());

  m.def("_load_map", &loadMap, py::arg("path"), py::arg("force_rebuild"), py::arg("use_proc"));
  m.def("_load_cm", &loadCm, py::arg("path"));
  m.def("_parse_cm", &parseCm, py::arg("text"), py::arg("name"));
  m.def(
      "_write_cm",
      [](const std::vector<std::shared_ptr<PyModel>>& models, std::uint32_t crc) {
        return cmkit::writeCmText(unwrapModels(models), crc);
      },
      py::arg("models"), py::arg("crc"));
  m.def(
      "_save_cm",
      [](const std::string& path, const std::vector<std::shared_ptr<PyModel>>& models, std::uint32_t crc) {
        const auto ms = unwrapModels(models);
        std::optional<cmkit::Status> s;
        {
          py::gil_scoped_release release;
          s.emplace(cmkit::saveCmFile(path, ms, crc));
        }
        if (!s->ok()) raise(s->error());
      },
      py::arg("path"), py::arg("models"), py::arg("crc"));
  m.def("_parse_query_line", &parseQueryLine, py::arg("models"), py::arg("line"),
        "A query-format line parsed by the C++ API (a dict), or None when it cannot be run (tests).");
  m.def(
      "_answer_query_line",
      [](const std::vector<std::shared_ptr<PyModel>>& models, const std::string& line) {
        cmkit::QueryWork work;
        return cmkit::answerQueryLine(unwrapModels(models), line, work);
      },
      py::arg("models"), py::arg("line"), "The C++ API's result line for a query-format line (tests).");
}
