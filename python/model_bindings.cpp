// model_bindings.cpp: the Model class of cmkit._cmkit (properties, .cm
// text, pickling; its queries are added by query_bindings.cpp) and the module
// functions that load and save models (.map through the model manager, .cm
// text and files) and parse and answer query-format lines (for the tests).
#include <pybind11/stl.h>

#include <optional>
#include <string>
#include <vector>

#include "cmkit/cm_file.h"
#include "cmkit/manager.h"
#include "cmkit/materials.h"
#include "cmkit/query.h"
#include "cmkit/tools/query_format.h"
#include "module_support.h"

namespace cmkit_python {

namespace {

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
  d["rotational"] = q.rotational;  // contacts along the rotation
  d["mask"] = q.contentMask;
  d["model"] = q.model;
  d["origin"] = vecArray(q.placement.origin);
  d["model_axis"] = matArray(q.placement.axis);
  return d;
}

}  // namespace

void bindModel(py::module_& m) {
  PyModelClass cls(m, "Model", R"(A collision model (immutable): the world or one entity of a map.

Queries are methods taking numpy arrays; see translate, rotate, cast_rays, point_contents,
contents, contacts. Models pickle as .cm text, so they travel to worker processes.)");
  cls.def_property_readonly(
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
          }));
  addQueryMethods(cls);

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

}  // namespace cmkit_python
