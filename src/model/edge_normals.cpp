// Edge normals (docs/algorithms.md): see edge_normals.h for the order and the
// formulas.
#include "model/edge_normals.h"

#include <cstdint>
#include <vector>

namespace cmkit::detail {

namespace {

// Adds one polygon's contribution to the normals of its edges.
void addPolygonToEdgeNormals(ModelArrays& model, const CmPolygon& polygon, int& sharpEdges) {
  const Vec3& n = polygon.plane.normal;
  // The original computes the sharp-edge scale in float: 0.5 / (0.5 + 0.5 * -0.7).
  const Real sharpScale = Real(0.5) / (Real(0.5) + Real(0.5) * tol::kSharpEdgeDot);
  for (const std::int32_t signedEdge : model.edgesOf(polygon)) {
    const std::size_t e = std::size_t(signedEdge < 0 ? -signedEdge : signedEdge);
    if (e == 0 || e >= model.edges.size()) continue;  // defensive: validated models never have these
    CmEdge& edge = model.edges[e];
    const std::size_t nv = model.vertices.size();
    const auto v0 = std::size_t(edge.vertex[0]), v1 = std::size_t(edge.vertex[1]);
    if (v0 >= nv || v1 >= nv) continue;
    // t: the edge direction as this polygon walks it.
    const Vec3 t =
        signedEdge > 0 ? model.vertices[v1] - model.vertices[v0] : model.vertices[v0] - model.vertices[v1];
    if (edge.normal.isZero()) {
      if (edge.numUsers == 1) {
        edge.normal = t.cross(n);  // outward in the polygon's plane
        edge.normal.normalize();
      } else {
        edge.normal = n;
      }
      continue;
    }
    const Real dot = edge.normal.dot(n);
    if (dot < tol::kSharpEdgeDot) {
      // The faces fold back on each other: the longest normal that still
      // points out of both (the bisector would be nearly zero).
      Vec3 folded = edge.normal.cross(t) + n.cross(-t);
      const Real length = folded.length();
      folded *= safeDivide(sharpScale, length);
      edge.normal = folded;
      ++sharpEdges;
    } else {
      const Real s = Real(0.5) / (Real(0.5) + Real(0.5) * dot);
      edge.normal = (edge.normal + n) * s;
    }
  }
}

}  // namespace

int computeEdgeNormals(ModelArrays& model) {
  for (CmEdge& edge : model.edges) edge.normal = Vec3{};
  if (model.nodes.empty()) return 0;
  int sharpEdges = 0;
  std::vector<char> visited(model.polygons.size(), 0);
  // Pre-order walk: node list, back subtree, front subtree. The stack holds
  // nodes still to visit; pushing front before back pops back first.
  std::vector<std::int32_t> stack{0};
  std::vector<char> nodeSeen(model.nodes.size(), 0);  // guards against malformed child links
  while (!stack.empty()) {
    const std::int32_t nodeNum = stack.back();
    stack.pop_back();
    if (nodeNum < 0 || std::size_t(nodeNum) >= model.nodes.size() || nodeSeen[std::size_t(nodeNum)]) continue;
    nodeSeen[std::size_t(nodeNum)] = 1;
    const CmNode& node = model.nodes[std::size_t(nodeNum)];
    for (const std::int32_t p : model.polygonsAt(node)) {
      if (p < 0 || std::size_t(p) >= model.polygons.size() || visited[std::size_t(p)]) continue;
      visited[std::size_t(p)] = 1;
      addPolygonToEdgeNormals(model, model.polygons[std::size_t(p)], sharpEdges);
    }
    if (node.isLeaf()) continue;
    stack.push_back(node.children[0]);  // front: visited after the whole back subtree
    stack.push_back(node.children[1]);  // back: next
  }
  return sharpEdges;
}

void computeModelBoundsAndContents(ModelArrays& model) {
  Bounds bounds;
  std::uint32_t contents = 0;
  for (const CmPolygon& p : model.polygons) {
    bounds.addPoint(p.bounds.min);
    bounds.addPoint(p.bounds.max);
    contents |= p.contents;
  }
  for (const CmBrush& b : model.brushes) {
    bounds.addPoint(b.bounds.min);
    bounds.addPoint(b.bounds.max);
    contents |= b.contents;
  }
  if (bounds.isCleared()) bounds = Bounds(Vec3{}, Vec3{});
  model.bounds = bounds;
  model.contents = contents;
}

}  // namespace cmkit::detail
