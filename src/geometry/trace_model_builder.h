// Internal: filling in a TraceModel's features. The factories in
// trace_model.cpp describe a shape's vertices, edges and polygon edge loops;
// finish() derives planes, bounds and edge normals the way the original does.
#pragma once

#include <span>
#include <utility>
#include <vector>

#include "cmkit/trace_model.h"

namespace cmkit::detail {

class TraceModelBuilder {
 public:
  explicit TraceModelBuilder(TrmShape shape) { trm_.shape_ = shape; }

  /// Appends a vertex; returns its index.
  int addVertex(const Vec3& v) {
    trm_.vertices_[size_t(trm_.numVertices_)] = v;
    return trm_.numVertices_++;
  }
  /// Appends edge number numEdges+1 from a to b; returns its number.
  int addEdge(int a, int b) {
    TrmEdge& e = trm_.edges_[size_t(++trm_.numEdges_)];
    e.v[0] = a;
    e.v[1] = b;
    return trm_.numEdges_;
  }
  /// Appends a polygon with the given signed edge loop; returns its index.
  int addPolygon(std::span<const int> edgeLoop) {
    TrmPolygon& p = trm_.polygons_[size_t(trm_.numPolygons_)];
    p.numEdges = int(edgeLoop.size());
    for (size_t i = 0; i < edgeLoop.size(); ++i) p.edges[i] = edgeLoop[i];
    return trm_.numPolygons_++;
  }
  TraceModel& model() { return trm_; }

  /// Derives the polygon planes from their first three loop vertices
  /// (normal = (v1 - v0) x (v2 - v0), normalised), polygon bounds, the
  /// model bounds, and - for solids - the edge normals. `offset` is the
  /// shape's centre; `convex` marks a closed convex solid.
  TraceModel finish(const Vec3& offset, bool convex, bool computePlanes = true);

  /// Sets the edge normals from the polygon normals (the original's
  /// GenerateEdgeNormals); returns the number of sharp edges.
  static int generateEdgeNormals(TraceModel& trm);

  /// Builds the convex hull of `points` as edge loops: on success `loops`
  /// holds, per face, the indices (into `points`) of its vertices counter-
  /// clockwise around the outward normal, and `used` marks hull vertices.
  static Result<std::vector<std::vector<int>>> hullFaces(std::span<const Vec3> points);

  /// Makes a trace model from vertex positions and faces given as vertex
  /// loops: vertices keep their order (unused ones are dropped), edges are
  /// numbered in the order the loops first meet them.
  static Result<TraceModel> fromFaceLoops(TrmShape shape, std::span<const Vec3> points,
                                          const std::vector<std::vector<int>>& loops, const Vec3& offset);

 private:
  TraceModel trm_;
};

}  // namespace cmkit::detail
