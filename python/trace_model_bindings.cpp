// trace_model_bindings.cpp: the TraceModel class of cmkit._cmkit: its
// factories (each remembers its recipe, which is how it pickles), its
// properties and pickling.
#include <pybind11/stl.h>

#include <string>

#include "module_support.h"

namespace cmkit_python {

namespace {

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

}  // namespace

void bindTraceModel(py::module_& m) {
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
}

}  // namespace cmkit_python
