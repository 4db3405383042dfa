// Collision models built in code for query tests: each convex piece (a box
// or any convex trace model shape) becomes polygons, edges and a brush of a
// one-leaf model. Edges are shared within a piece, not between pieces.
#pragma once

#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cmkit/contents.h"
#include "cmkit/materials.h"
#include "cmkit/mesh.h"
#include "cmkit/model.h"
#include "cmkit/trace_model.h"
#include "model/edge_normals.h"

namespace cmkit::test {

class ModelMaker {
 public:
  /// Adds a solid convex piece with the given contents.
  ModelMaker& addConvex(const TraceModel& shape,
                        std::uint32_t contents = contents::kSolid | contents::kOpaque,
                        const std::string& material = "textures/test/wall") {
    ModelArrays& m = model_;
    if (m.edges.empty()) m.edges.emplace_back();  // the dummy edge 0
    const auto matIndex = std::int32_t(m.materials.size());
    m.materials.push_back(material);
    const auto vbase = std::int32_t(m.vertices.size());
    for (const Vec3& v : shape.vertices()) m.vertices.push_back(v);
    const auto ebase = std::int32_t(m.edges.size()) - 1;
    for (int e = 1; e <= shape.numEdges(); ++e) {
      CmEdge edge;
      edge.vertex[0] = vbase + shape.edge(e).v[0];
      edge.vertex[1] = vbase + shape.edge(e).v[1];
      edge.numUsers = 2;
      m.edges.push_back(edge);
    }
    CmBrush brush;
    brush.bounds = shape.bounds();
    brush.contents = contents;
    brush.material = matIndex;
    brush.firstPlane = std::uint32_t(m.brushPlanes.size());
    for (const TrmPolygon& p : shape.polygons()) {
      CmPolygon poly;
      poly.bounds = p.bounds;
      poly.plane = Plane{p.normal, p.dist};
      poly.contents = contents;
      poly.material = matIndex;
      poly.firstEdge = std::uint32_t(m.polygonEdges.size());
      poly.numEdges = std::uint32_t(p.numEdges);
      for (int e : p.edgeList()) m.polygonEdges.push_back(e > 0 ? e + ebase : e - ebase);
      m.polygons.push_back(poly);
      m.brushPlanes.push_back(poly.plane);
    }
    brush.numPlanes = std::uint32_t(m.brushPlanes.size()) - brush.firstPlane;
    m.brushes.push_back(brush);
    return *this;
  }
  ModelMaker& addBox(const Bounds& b, std::uint32_t contents = contents::kSolid | contents::kOpaque) {
    return addConvex(*TraceModel::box(b), contents);
  }
  /// Marks edge `e` (a model edge number) internal.
  ModelMaker& markInternal(std::int32_t e) {
    model_.edges[std::size_t(e)].internal = true;
    return *this;
  }
  ModelArrays& model() { return model_; }

  /// The finished arrays: one leaf holding everything, bounds, contents and
  /// edge normals computed.
  ModelArrays buildArrays() const {
    ModelArrays m = model_;
    m.name = "test";
    m.nodes.assign(1, CmNode{});
    for (std::size_t i = 0; i < m.polygons.size(); ++i) m.polygonRefs.push_back(std::int32_t(i));
    for (std::size_t i = 0; i < m.brushes.size(); ++i) m.brushRefs.push_back(std::int32_t(i));
    m.nodes[0].numPolygonRefs = std::uint32_t(m.polygons.size());
    m.nodes[0].numBrushRefs = std::uint32_t(m.brushes.size());
    m.bounds.clear();
    for (const CmPolygon& p : m.polygons) {
      m.bounds.addBounds(p.bounds);
      m.contents |= p.contents;
    }
    detail::computeEdgeNormals(m);
    return m;
  }
  /// The finished model (buildArrays, sealed by CollisionModel::create).
  CollisionModel build() const {
    Result<ModelPtr> m = CollisionModel::create(buildArrays());
    if (!m) {
      ADD_FAILURE() << m.error().toString();
      std::abort();
    }
    return **m;
  }

 private:
  ModelArrays model_;
};

/// A rough two-sided terrain of cells x cells squares of 32 units (two
/// triangles each, heights in [-24, 24] drawn from `rng`) with twelve
/// one-sided closed boxes on it, through the mesh API: two-sided surfaces
/// (pairs of a polygon and its reversed twin) beside one-sided ones.
inline ModelPtr twoSidedTerrainModel(int cells, std::mt19937& rng) {
  TriangleMesh mesh;
  std::uniform_real_distribution<float> height(-24, 24);
  for (int y = 0; y <= cells; ++y)
    for (int x = 0; x <= cells; ++x) mesh.positions.push_back({Real(x * 32), Real(y * 32), height(rng)});
  std::vector<std::uint32_t> terrain, boxes;
  const auto at = [cells](int x, int y) { return std::uint32_t(y * (cells + 1) + x); };
  for (int y = 0; y < cells; ++y)
    for (int x = 0; x < cells; ++x)
      terrain.insert(terrain.end(),
                     {at(x, y), at(x + 1, y), at(x + 1, y + 1), at(x, y), at(x + 1, y + 1), at(x, y + 1)});
  for (int b = 0; b < 12; ++b) {  // a closed box of 12 triangles, outward faces counter-clockwise
    const Vec3 lo{Real(40 + 60 * b), Real(30 + 50 * (b % 5)), Real(10)};
    const auto first = std::uint32_t(mesh.positions.size());
    for (int k = 0; k < 8; ++k)
      mesh.positions.push_back(lo + Vec3{Real(k & 1 ? 24 : 0), Real(k & 2 ? 24 : 0), Real(k & 4 ? 40 : 0)});
    for (const int i : {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                        2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5})
      boxes.push_back(first + std::uint32_t(i));
  }
  mesh.surfaces.push_back({"textures/test/twosided", terrain});
  mesh.surfaces.push_back({"textures/test/solid", boxes});
  MaterialTable materials;
  materials.addMtrText("textures/test/twosided { twosided }\ntextures/test/solid { }\n", "test.mtr");
  auto built = buildCollisionModelFromTriangles(mesh, "two-sided", materials);
  EXPECT_TRUE(built.ok()) << built.error().toString();
  return built.ok() ? built->model : nullptr;
}

}  // namespace cmkit::test
