// Compiled by check_sealed_model.cmake (ctest api_sealed_model_does_not_compile_edits)
// once with EDIT=0, which must compile (it reads the model), and once per
// EDIT=1.. with one line that changes a model from outside, which must not: a
// CollisionModel is sealed (include/cmkit/model.h). Even the non-const
// reference below (what a const_cast would give) has no way to edit it.
#include <cmkit/model.h>
#include <cmkit/trace_model.h>

#include <cstddef>

int main() {
  const auto box = cmkit::TraceModel::box({{-1, -1, -1}, {1, 1, 1}});
  const cmkit::ModelPtr sealed = cmkit::collisionModelFromTraceModel(*box);
  auto& model = const_cast<cmkit::CollisionModel&>(*sealed);
  std::size_t read = model.vertices().size() + model.polygons().size() + model.arrays().edges.size();
  read += model.polygons()[0].plane.normal.x > 0 ? 1 : 0;
  const cmkit::CollisionModel copy = model;  // copies are sealed too
  read += copy.brushes().size();
#if EDIT == 1
  model.vertices.push_back({});
#elif EDIT == 2
  model.vertices().push_back({});
#elif EDIT == 3
  model.polygons()[0].plane = {};
#elif EDIT == 4
  model.arrays().vertices.push_back({});
#elif EDIT == 5
  cmkit::CollisionModel made;
#elif EDIT == 6
  cmkit::CollisionModel made(cmkit::ModelArrays{});
#elif EDIT == 7
  cmkit::CollisionModel made{cmkit::ModelArrays{}};
#endif
  return read == 0;
}
