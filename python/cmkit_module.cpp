// cmkit_module.cpp: the Python extension module cmkit._cmkit (pybind11):
// its definition, cmkit.Error and the constants (contents, contact types,
// query statuses). The public package (python/cmkit/__init__.py) re-exports
// what is here and adds the Models sequence. The rest of the module:
// module_support (errors, numpy conversions, the wrapped objects),
// trace_model_bindings.cpp (TraceModel), model_bindings.cpp (Model, loading
// and saving), query_bindings.cpp (the Model's batch queries and what the
// World's share with them: query_support.h), world_bindings.cpp (World).
#include <pybind11/eval.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>

#include "cmkit/contents.h"
#include "cmkit/query.h"
#include "module_support.h"

namespace py = pybind11;
using namespace cmkit_python;

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
  m.attr("STATUS_MIXED_MOTION") = int(cmkit::QueryStatus::MixedMotion);
  m.def(
      "status_name",
      [](int status) {
        if (status < int(cmkit::QueryStatus::Ok) || status > int(cmkit::QueryStatus::MixedMotion))
          throw py::value_error("not a query status (STATUS_*): " + std::to_string(status));
        return std::string(cmkit::toString(cmkit::QueryStatus(status)));
      },
      py::arg("status"),
      "A short English description of a query status (STATUS_*; the 'status' result arrays), as C++'s "
      "toString(QueryStatus): 'ok', 'trace-model axis is not a rotation ...'.");
  m.def("content_names", &cmkit::contentsToString, py::arg("contents"),
        "The names of the content flags set in `contents` (e.g. 'solid,playerclip').");

  bindTraceModel(m);
  bindModel(m);
  bindWorld(m);
}
