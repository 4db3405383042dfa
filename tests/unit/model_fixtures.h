// Collision models built in code for query tests: each convex piece (a box
// or any convex trace model shape) becomes polygons, edges and a brush of a
// one-leaf model. Edges are shared within a piece, not between pieces.
#pragma once

#include <cstdlib>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cmkit/contents.h"
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

}  // namespace cmkit::test
