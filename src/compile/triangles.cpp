// Triangle meshes -> collision models (the original's conversion of a render
// model in LoadModel): buildCollisionModelFromTriangles and the builder step
// that turns the triangles into polygons.
#include <cmath>
#include <new>

#include "cmkit/contents.h"
#include "cmkit/mesh.h"
#include "compile/builder.h"

namespace cmkit {

namespace detail {

void ModelBuilder::convertMeshSurfaces() {
  const TriangleMesh& mesh = *mesh_;
  // Any collision surface: only collision surfaces collide.
  bool anyCollisionSurface = false;
  for (const MeshSurface& s : mesh.surfaces) {
    if (materials_[materials_.find(s.material)].info.collision) anyCollisionSurface = true;
  }
  // The vertex hash spans the mesh (the original: the render model's bounds).
  Bounds bounds;
  for (const Vec3& p : mesh.positions) bounds.addPoint(p);
  if (mesh.positions.empty()) bounds = Bounds{Vec3{}, Vec3{}};
  clearHash(bounds, mesh.positions.size());
  std::size_t numIndices = 0;
  for (const MeshSurface& s : mesh.surfaces) numIndices += s.indices.size();
  edgeHashHead_.reserve(numIndices);  // each index starts an edge (the table grows for two-sided ones)
  // Room for every triangle on both sides (two-sided materials) and its
  // edges: the arrays then never move while they fill.
  const std::size_t numTriangles = numIndices / 3;
  vertices_.reserve(mesh.positions.size());
  vertexHashNodes_.reserve(mesh.positions.size());
  edges_.reserve(numIndices +
                 1);  // a new edge per index at most (the reversed side shares them), and the dummy
  edgeHashNext_.reserve(numIndices + 1);
  polygons_.reserve(2 * numTriangles);
  polygonRefs_.reserve(2 * numTriangles);
  int zeroNormals = 0;
  Winding w;  // (one for all triangles: its points keep their room)
  for (const MeshSurface& s : mesh.surfaces) {
    const int material = materials_.find(s.material);
    const MaterialInfo& info = materials_[material].info;
    if ((info.contents & kUsefulContents) == 0) continue;
    if (anyCollisionSurface && !info.collision) continue;
    for (std::size_t t = 0; t + 2 < s.indices.size(); t += 3) {
      const Vec3& a = mesh.positions[s.indices[t]];
      const Vec3& b = mesh.positions[s.indices[t + 1]];
      const Vec3& c = mesh.positions[s.indices[t + 2]];
      Plane plane;
      plane.normal = (b - a).cross(c - a);
      if (normalizeLikeOriginal(plane.normal) == 0) {
        ++zeroNormals;
        continue;
      }
      plane.fixDegeneracies(0);  // the original's Normalize fixes degenerate normals
      plane.fitThroughPoint(a);
      w.clear();
      w.add(a);
      w.add(b);
      w.add(c);
      polygonFromWinding(w, plane, material, 1);  // the original's primitive number for render models
    }
  }
  if (zeroNormals > 0) {
    warn(std::to_string(zeroNormals) + " triangle" + (zeroNormals == 1 ? "" : "s") +
         " without area (no normal) skipped");
  }
  // The axial BSP tree over the polygons (the original builds it for every
  // render model, after the polygons).
  createAxialBSPTree(nodeBounds());
}

}  // namespace detail

namespace {

Status checkMesh(const TriangleMesh& mesh, const std::string& name) {
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const Vec3& p = mesh.positions[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) ||
        std::fabs(p.x) >= tol::kMaxWorldCoord || std::fabs(p.y) >= tol::kMaxWorldCoord ||
        std::fabs(p.z) >= tol::kMaxWorldCoord) {
      return Error("position " + std::to_string(i) + " is not finite or lies beyond the world limit (+-" +
                       std::to_string(static_cast<long long>(tol::kMaxWorldCoord)) + ")",
                   name);
    }
  }
  for (std::size_t s = 0; s < mesh.surfaces.size(); ++s) {
    const MeshSurface& surface = mesh.surfaces[s];
    if (surface.indices.size() % 3 != 0) {
      return Error("surface " + std::to_string(s) + " (\"" + surface.material + "\") has " +
                       std::to_string(surface.indices.size()) + " indices: not a multiple of 3 (triangles)",
                   name);
    }
    for (const std::uint32_t i : surface.indices) {
      if (i >= mesh.positions.size()) {
        return Error("surface " + std::to_string(s) + " (\"" + surface.material + "\") uses position " +
                         std::to_string(i) + " of " + std::to_string(mesh.positions.size()),
                     name);
      }
    }
  }
  return Ok{};
}

}  // namespace

Result<MeshBuildResult> buildCollisionModelFromTriangles(const TriangleMesh& mesh, std::string name,
                                                         const MaterialTable& materials,
                                                         const MeshBuildOptions& options) {
  if (Status s = checkMesh(mesh, name); !s) return s.error();
  const std::string fileName = name;
  try {
    detail::MaterialCache cache(materials, options.contents);
    MeshBuildResult result;
    detail::ModelBuilder builder(mesh, std::move(name), cache, &result.warnings);
    builder.setRobustEdges(options.robustEdges);
    result.model = builder.build();
    return result;
  } catch (const std::bad_alloc&) {
    return Error("out of memory while building the model of a mesh", fileName);
  }
}

}  // namespace cmkit
