// query_bindings.cpp: the query methods of cmkit.Model, and what they share
// with cmkit.World's (query_support.h): each converts its numpy input with
// the GIL held, runs the C++ batch (cmkit/batch.h) without it (the progress
// hook takes it back; Ctrl-C cancels), and builds its dict of numpy arrays
// with the GIL again.
#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "cmkit/batch.h"
#include "cmkit/query.h"
#include "module_support.h"
#include "query_support.h"

namespace cmkit_python {

// ---- running a batch ----------------------------------------------------

Hook::Hook(int threads, py::object cb) : callback(std::move(cb)) {
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

// ---- the arguments of each kind -----------------------------------------

namespace {

// The fields every trace-model query shares, from the Python arguments.
template <class Query>
void setTraceModelQuery(Query& q, const TrmArg& t, const py::object& axis, std::int64_t mask) {
  q.trm = t.get();
  q.trmAxis = matrix(axis, "axis");
  q.contentMask = maskOf(mask);
}

// The rotations of origins (N, 3), unit axes (N, 3) and angles (N,) degrees
// (each may be given once for all), checked.
std::vector<cmkit::Rotation> rotationsOf(const py::object& origins, const py::object& axes,
                                         const py::object& angles) {
  const auto o = vectors(origins, "origins"), a = vectors(axes, "axes");
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
  return rotations;
}

}  // namespace

TranslationArgs::TranslationArgs(const py::object& trmObject, const py::object& startsObject,
                                 const py::object& endsObject, std::int64_t mask, const py::object& axis,
                                 bool startSolid)
    : trm(trmArg(trmObject)), starts(vectors(startsObject, "starts")), ends(vectors(endsObject, "ends")) {
  setTraceModelQuery(batch.query, trm, axis, mask);
  batch.query.detectStartSolid = startSolid;
  batch.starts = starts;
  batch.ends = ends;
  size = unwrap(cmkit::batchSize(starts.size(), ends.size(), "starts and ends"));
}

RotationArgs::RotationArgs(const py::object& trmObject, const py::object& startsObject,
                           const py::object& origins, const py::object& axes, const py::object& angles,
                           std::int64_t mask, const py::object& axis, bool startSolid)
    : trm(trmArg(trmObject)),
      starts(vectors(startsObject, "starts")),
      rotations(rotationsOf(origins, axes, angles)) {
  setTraceModelQuery(batch.query, trm, axis, mask);
  batch.query.detectStartSolid = startSolid;
  batch.starts = starts;
  batch.rotations = rotations;
  size = unwrap(cmkit::batchSize(starts.size(), rotations.size(), "starts and rotations"));
}

RayArgs::RayArgs(const py::object& origins, const py::object& endsObject, std::int64_t mask)
    : starts(vectors(origins, "origins")), ends(vectors(endsObject, "ends")) {
  batch.query.contentMask = maskOf(mask);
  batch.starts = starts;
  batch.ends = ends;
  size = unwrap(cmkit::batchSize(starts.size(), ends.size(), "origins and ends"));
}

PointArgs::PointArgs(const py::object& pointsObject) : points(vectors(pointsObject, "points")) {
  batch.points = points;
  size = points.size();
}

ContentsArgs::ContentsArgs(const py::object& trmObject, const py::object& positionsObject, std::int64_t mask,
                           const py::object& axis)
    : trm(trmArg(trmObject)), positions(vectors(positionsObject, "positions")) {
  setTraceModelQuery(batch.query, trm, axis, mask);
  batch.positions = positions;
  size = positions.size();
}

ContactsArgs::ContactsArgs(const py::object& trmObject, const py::object& startsObject,
                           const py::object& dirsObject, double depth, int maxContacts,
                           const py::object& origins, const py::object& axes, const py::object& angles,
                           std::int64_t mask, const py::object& axis)
    : trm(trmArg(trmObject)), starts(vectors(startsObject, "starts")) {
  if (!std::isfinite(depth) || depth < 0) throw py::value_error("depth must be finite and not negative");
  if (maxContacts < 1 || maxContacts > 1024) throw py::value_error("max_contacts must be 1..1024");
  const int rotationArgs = int(!origins.is_none()) + int(!axes.is_none()) + int(!angles.is_none());
  if (rotationArgs != 0 && rotationArgs != 3)
    throw py::value_error("a rotation needs origins, axes and angles (all three)");
  if (rotationArgs == 0 && dirsObject.is_none())
    throw py::value_error("contacts need dirs (or origins, axes and angles)");
  // Along rotations: dirs may be left out (no translation); dirs with a
  // depth beside them is a query the library refuses (STATUS_MIXED_MOTION).
  if (!dirsObject.is_none()) dirs = vectors(dirsObject, "dirs");
  if (rotationArgs == 3) rotations = rotationsOf(origins, axes, angles);
  setTraceModelQuery(batch.query, trm, axis, mask);
  batch.query.depth = Real(depth);
  batch.query.maxContacts = maxContacts;
  batch.starts = starts;
  batch.dirs = dirs;
  batch.rotations = rotations;
  size = starts.size();
  if (!dirs.empty() || rotations.empty())
    size = unwrap(cmkit::batchSize(size, dirs.size(), "starts and dirs"));
  if (!rotations.empty())
    size = unwrap(cmkit::batchSize(size, rotations.size(), "starts, dirs and rotations"));
}

// ---- the answers --------------------------------------------------------

namespace {

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

}  // namespace

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

py::dict rayArrays(const std::vector<cmkit::RayHit>& hits) {
  const std::size_t n = hits.size();
  auto fraction = py::array_t<Real>(py::ssize_t(n));
  auto point = py::array_t<Real>({py::ssize_t(n), py::ssize_t(3)});
  auto normal = py::array_t<Real>({py::ssize_t(n), py::ssize_t(3)});
  auto dist = py::array_t<Real>(py::ssize_t(n));
  auto polygon = py::array_t<std::int32_t>(py::ssize_t(n));
  auto contents = py::array_t<std::uint32_t>(py::ssize_t(n));
  auto material = py::array_t<std::int32_t>(py::ssize_t(n));
  auto hit = py::array_t<bool>(py::ssize_t(n));
  for (std::size_t i = 0; i < n; ++i) {
    const auto& h = hits[i];
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

py::dict pointContentsArrays(const std::vector<std::uint32_t>& contents,
                             const std::vector<cmkit::QueryStatus>& status) {
  auto c = py::array_t<std::uint32_t>(py::ssize_t(contents.size()));
  auto s = py::array_t<std::uint8_t>(py::ssize_t(status.size()));
  for (std::size_t i = 0; i < contents.size(); ++i) c.mutable_data()[i] = contents[i];
  for (std::size_t i = 0; i < status.size(); ++i) s.mutable_data()[i] = std::uint8_t(status[i]);
  py::dict d;
  d["contents"] = c;
  d["status"] = s;
  return d;
}

py::dict contentsArrays(const std::vector<cmkit::ContentsResult>& results) {
  std::vector<cmkit::TraceResult> traces(results.size());
  auto contents = py::array_t<std::uint32_t>(py::ssize_t(results.size()));
  for (std::size_t i = 0; i < results.size(); ++i) {
    traces[i] = results[i].trace;
    contents.mutable_data()[i] = results[i].contents;
  }
  py::dict d = traceArrays(traces);
  d["contact_contents"] = d["contents"];
  d["contents"] = contents;
  d["status"] = statusArray(results);
  return d;
}

py::dict contactsArrays(const std::vector<cmkit::ContactsResult>& results, int maxContacts) {
  const std::size_t n = results.size(), m = std::size_t(maxContacts);
  auto count = py::array_t<std::int32_t>(py::ssize_t(n));
  ContactArrays arrays({py::ssize_t(n), py::ssize_t(m)});
  auto angle = py::array_t<Real>({py::ssize_t(n), py::ssize_t(m)});
  const cmkit::ContactInfo none;
  for (std::size_t i = 0; i < n; ++i) {
    const auto& list = results[i].contacts;
    count.mutable_data()[i] = std::int32_t(list.size());
    for (std::size_t k = 0; k < m; ++k) {
      const cmkit::ContactInfo& c = k < list.size() ? list[k] : none;
      arrays.set(i * m + k, c);
      angle.mutable_data()[i * m + k] = c.angle;
    }
  }
  py::dict d;
  d["count"] = count;
  d["status"] = statusArray(results);
  arrays.into(d);
  d["angle"] = angle;
  return d;
}

const char* const kBatchNote =
    "\n\nEvery batch method takes threads= (0: all cores; results are identical at any count) and "
    "progress= (a callable(done, total) called now and then on the calling thread; return False "
    "to cancel: cmkit.Error is raised). The GIL is released while it runs; Ctrl-C cancels it. "
    "Coordinates are float32 (float64 input is rounded).";

// ---- cmkit.Model's methods ----------------------------------------------

namespace {

cmkit::Placement placementOf(const py::object& origin, const py::object& axis) {
  cmkit::Placement p;
  if (!origin.is_none()) p.origin = vector3(origin, "origin");
  p.axis = matrix(axis, "model_axis");
  return p;
}

py::dict translateBatch(PyModel& self, const py::object& trm, const py::object& starts,
                        const py::object& ends, std::int64_t mask, const py::object& axis, bool startSolid,
                        const py::object& origin, const py::object& modelAxis, int threads,
                        const py::object& progress) {
  TranslationArgs a(trm, starts, ends, mask, axis, startSolid);
  a.batch.query.placement = placementOf(origin, modelAxis);
  std::vector<cmkit::TraceResult> out(a.size);
  Hook hook(threads, progress);
  runBatch([&] { return cmkit::translateBatch(*self.model, a.batch, out, hook.options); });
  return traceArrays(out);
}

py::dict rotateBatch(PyModel& self, const py::object& trm, const py::object& starts,
                     const py::object& origins, const py::object& axes, const py::object& angles,
                     std::int64_t mask, const py::object& axis, bool startSolid, const py::object& origin,
                     const py::object& modelAxis, int threads, const py::object& progress) {
  RotationArgs a(trm, starts, origins, axes, angles, mask, axis, startSolid);
  a.batch.query.placement = placementOf(origin, modelAxis);
  std::vector<cmkit::TraceResult> out(a.size);
  Hook hook(threads, progress);
  runBatch([&] { return cmkit::rotateBatch(*self.model, a.batch, out, hook.options); });
  return traceArrays(out);
}

py::dict castRays(PyModel& self, const py::object& starts, const py::object& ends, std::int64_t mask,
                  const py::object& origin, const py::object& modelAxis, int threads,
                  const py::object& progress) {
  RayArgs a(starts, ends, mask);
  a.batch.query.placement = placementOf(origin, modelAxis);
  std::vector<cmkit::RayHit> out(a.size);
  Hook hook(threads, progress);
  runBatch([&] { return cmkit::castRayBatch(self.rayIndex(), a.batch, out, hook.options); });
  return rayArrays(out);
}

py::dict pointContents(PyModel& self, const py::object& points, const py::object& origin,
                       const py::object& modelAxis, int threads, const py::object& progress) {
  PointArgs a(points);
  a.batch.query.placement = placementOf(origin, modelAxis);
  std::vector<cmkit::PointContentsResult> out(a.size);
  Hook hook(threads, progress);
  runBatch([&] { return cmkit::pointContentsBatch(*self.model, a.batch, out, hook.options); });
  std::vector<std::uint32_t> contents(out.size());
  std::vector<cmkit::QueryStatus> status(out.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    contents[i] = out[i].contents;
    status[i] = out[i].status;
  }
  return pointContentsArrays(contents, status);
}

py::dict contentsBatch(PyModel& self, const py::object& trm, const py::object& positions, std::int64_t mask,
                       const py::object& axis, const py::object& origin, const py::object& modelAxis,
                       int threads, const py::object& progress) {
  ContentsArgs a(trm, positions, mask, axis);
  a.batch.query.placement = placementOf(origin, modelAxis);
  std::vector<cmkit::ContentsResult> out(a.size);
  Hook hook(threads, progress);
  runBatch([&] { return cmkit::contentsBatch(*self.model, a.batch, out, hook.options); });
  return contentsArrays(out);
}

py::dict contactsBatch(PyModel& self, const py::object& trm, const py::object& starts, const py::object& dirs,
                       double depth, int maxContacts, const py::object& origins, const py::object& axes,
                       const py::object& angles, std::int64_t mask, const py::object& axis,
                       const py::object& origin, const py::object& modelAxis, int threads,
                       const py::object& progress) {
  ContactsArgs a(trm, starts, dirs, depth, maxContacts, origins, axes, angles, mask, axis);
  a.batch.query.placement = placementOf(origin, modelAxis);
  std::vector<cmkit::ContactsResult> out(a.size);
  Hook hook(threads, progress);
  runBatch([&] { return cmkit::contactsBatch(*self.model, a.batch, out, hook.options); });
  return contactsArrays(out, maxContacts);
}

}  // namespace

void addQueryMethods(PyModelClass& cls) {
  namespace c = cmkit::contents;
  const std::string batchNote =
      std::string(kBatchNote) +
      " origin=/model_axis= place the model in the world (default: where it was built).";

  cls.def("translate", &translateBatch, py::arg("trm"), py::arg("starts"), py::arg("ends"), py::kw_only(),
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
      .def("contacts", &contactsBatch, py::arg("trm"), py::arg("starts"), py::arg("dirs") = py::none(),
           py::arg("depth") = 0.0, py::kw_only(), py::arg("max_contacts") = 16,
           py::arg("origins") = py::none(), py::arg("axes") = py::none(), py::arg("angles") = py::none(),
           py::arg("mask") = c::kMaskSolid, py::arg("axis") = py::none(), py::arg("origin") = py::none(),
           py::arg("model_axis") = py::none(), py::arg("threads") = 0, py::arg("progress") = py::none(),
           (std::string(
                R"(Every surface the trace model touches moved from starts (N, 3) along dirs (N, 3) by depth,
or, with origins=, axes= and angles= (as rotate() takes them), turned from starts: then every
polygon's earliest contact within the angle, ordered by the angle turned (dirs may be left out;
dirs with a depth beside a rotation: STATUS_MIXED_MOTION).

Returns a dict: count (N,), status (N,) (STATUS_*), the contact fields of translate() with shape (N, max_contacts, ...),
and angle (N, max_contacts): the degrees turned to each contact (signed as the angle; 0 for translations);
entries past count[i] hold type CONTACT_NONE, material -1 and zeros.)") +
            batchNote)
               .c_str());
}

}  // namespace cmkit_python
