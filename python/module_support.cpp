// module_support.cpp: cmkit.Error, the numpy conversions and the trace-model
// argument of the extension module (module_support.h).
#include "module_support.h"

#include <string>

namespace cmkit_python {

py::object& errorClass() {
  static py::object* cls = new py::object();  // never destroyed: outlives the interpreter's teardown order
  return *cls;
}

[[noreturn]] void raise(const cmkit::Error& e) {
  py::object exc = errorClass()(e.toString(), e.file, e.line, e.column);
  PyErr_SetObject(errorClass().ptr(), exc.ptr());
  throw py::error_already_set();
}

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

void put(Real* p, const Vec3& v) {
  p[0] = v.x;
  p[1] = v.y;
  p[2] = v.z;
}

py::array_t<Real> boundsArray(const cmkit::Bounds& b) {
  auto a = py::array_t<Real>({py::ssize_t(2), py::ssize_t(3)});
  put(a.mutable_data(), b.min);
  put(a.mutable_data() + 3, b.max);
  return a;
}

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

}  // namespace cmkit_python
