// module_support.h: what the files of the extension module cmkit._cmkit
// share: cmkit.Error and the unwrapping of the library's Results, numpy
// conversions in (vectors, matrices, masks) and out, the wrapped trace model
// and model, and the binding functions each file defines (cmkit_module.cpp
// calls them in order). query_support.h adds what the Model's and the World's
// queries share.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "cmkit/model.h"
#include "cmkit/ray_index.h"
#include "cmkit/result.h"
#include "cmkit/trace_model.h"

namespace cmkit_python {

namespace py = pybind11;
using cmkit::Real;
using cmkit::Vec3;

// ---- errors (module_support.cpp) ----------------------------------------

// cmkit.Error, created when the module is imported (see PYBIND11_MODULE).
py::object& errorClass();

// Raises cmkit.Error (file:line:column) for a library error.
[[noreturn]] void raise(const cmkit::Error& e);

template <class T>
T unwrap(cmkit::Result<T>&& r) {
  if (!r.ok()) raise(r.error());
  return std::move(r).value();
}

// ---- numpy in and out (module_support.cpp) ------------------------------

using FloatArray = py::array_t<Real, py::array::c_style | py::array::forcecast>;

// An (N, 3) array (or one (3,) vector: N = 1) as vectors; every number finite.
std::vector<Vec3> vectors(const py::handle& object, const char* name);
// A (3, 3) orientation (rows = axes); None: identity.
cmkit::Mat3 matrix(const py::object& object, const char* name);
// One vector of 3 numbers.
Vec3 vector3(const py::object& object, const char* name);
// A 32-bit content mask from a Python int.
std::uint32_t maskOf(std::int64_t mask);
// Writes v to p[0..2].
void put(Real* p, const Vec3& v);
// The (2, 3) array of a bounds' corners.
py::array_t<Real> boundsArray(const cmkit::Bounds& b);

// ---- the wrapped objects ------------------------------------------------

// A trace model and how it was made (the recipe: a factory name and its
// arguments), which is how it is pickled.
struct PyTraceModel {
  cmkit::TraceModel trm;
  py::tuple recipe;
};

// A query's trace model argument: None (a point), a TraceModel or a spec string.
struct TrmArg {
  std::optional<cmkit::TraceModel> parsed;
  const cmkit::TraceModel* trm = nullptr;
  // The trace model (nullptr: a point): `parsed` when a spec was parsed, so
  // a TrmArg copied or moved out of trmArg() never points into the original.
  const cmkit::TraceModel* get() const { return parsed ? &*parsed : trm; }
};
// The argument as a trace model (module_support.cpp).
TrmArg trmArg(const py::object& object);

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
using PyModelClass = py::class_<PyModel, std::shared_ptr<PyModel>>;

// ---- the bindings -------------------------------------------------------

// The TraceModel class (trace_model_bindings.cpp).
void bindTraceModel(py::module_& m);
// The Model class, its queries, loading and saving (model_bindings.cpp).
void bindModel(py::module_& m);
// The Model's query methods: translate, rotate, cast_rays, point_contents,
// contents, contacts (query_bindings.cpp).
void addQueryMethods(PyModelClass& cls);
// The World class: its queries, entities and walk; loading (world_bindings.cpp).
void bindWorld(py::module_& m);

}  // namespace cmkit_python
