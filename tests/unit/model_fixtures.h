// Collision models built in code for query tests: each convex piece (a box
// or any convex trace model shape) becomes polygons, edges and a brush of a
// one-leaf model. Edges are shared within a piece, not between pieces.
#pragma once

#include <cmath>
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
#include "test_support.h"

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

/// A world model of 60 two-sided axial boxes (quad faces) and a two-sided
/// prism whose caps have `sides` edges, through the map API: every face
/// with its reversed twin.
inline ModelPtr twoSidedPrismWorld(int sides, bool robustEdges = false) {
  constexpr const char* kSheet = "textures/test/sheet";
  std::string text = "Version 2\n{\n\"classname\" \"worldspawn\"\n";
  for (int b = 0; b < 60; ++b) {
    const Vec3 lo{Real(64 * (b % 10)), Real(64 * (b / 10)), 0};
    text += axialBrush({lo, lo + Vec3{32, 32, 32}}, kSheet);
  }
  text += "{\n brushDef3\n {\n";
  for (int k = 0; k < sides; ++k) {  // around (320, 800), radius 100, z 0 .. 64
    const double a = 2 * 3.14159265358979 * k / sides, nx = std::cos(a), ny = std::sin(a);
    text += brushSide(nx, ny, 0, -(100 + nx * 320 + ny * 800), kSheet);
  }
  text += brushSide(0, 0, 1, -64, kSheet) + brushSide(0, 0, -1, 0, kSheet);
  text += " }\n}\n}\n";
  auto map = parseMapText(text);
  EXPECT_TRUE(map.ok()) << (map.ok() ? "" : map.error().toString());
  if (!map) return nullptr;
  MaterialTable materials;
  materials.addMtrText(std::string(kSheet) + " { twosided }\n", "prism_test.mtr");
  BuildOptions options;
  options.robustEdges = robustEdges;
  auto built = buildCollisionModels(*map, materials, options);
  EXPECT_TRUE(built.ok());
  return built && !built->models.empty() ? built->models.front() : nullptr;
}

}  // namespace cmkit::test
