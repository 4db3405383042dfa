// Internal edges: edges that a trace can never touch first (a concave
// crease between two faces, or an edge lying on another face) are marked so
// that queries skip them (the original's FindInternalEdges and helpers).
#include <cmath>
#include <cstdlib>

#include "compile/builder.h"

namespace cmkit::detail {

void ModelBuilder::findInternalEdges(int nodeNum) {
  for (;;) {
    for (int r = nodes_[static_cast<std::size_t>(nodeNum)].polygons; r >= 0;
         r = polygonRefs_[static_cast<std::size_t>(r)].next) {
      const int p = polygonRefs_[static_cast<std::size_t>(r)].item;
      BPolygon& poly = polygons_[static_cast<std::size_t>(p)];
      if (poly.checkcount == checkCount_) continue;
      poly.checkcount = checkCount_;
      findInternalPolygonEdges(0, p);
    }
    const BNode& node = nodes_[static_cast<std::size_t>(nodeNum)];
    if (node.planeType == -1) break;
    findInternalEdges(node.children[1]);
    nodeNum = node.children[0];
  }
}

void ModelBuilder::findInternalPolygonEdges(int nodeNum, int polygon) {
  const BPolygon& poly = polygons_[static_cast<std::size_t>(polygon)];
  if (materials_[poly.material].info.twoSided) return;
  for (;;) {
    for (int r = nodes_[static_cast<std::size_t>(nodeNum)].polygons; r >= 0;
         r = polygonRefs_[static_cast<std::size_t>(r)].next) {
      const int p = polygonRefs_[static_cast<std::size_t>(r)].item;
      // (polygons reached through several nodes are tested several times,
      // as in the original)
      if (polygons_[static_cast<std::size_t>(p)].contents != poly.contents) continue;
      if (p == polygon) continue;
      findInternalEdgesOnPolygon(polygon, p);
    }
    const BNode& node = nodes_[static_cast<std::size_t>(nodeNum)];
    if (node.planeType == -1) break;
    if (poly.bounds.min[node.planeType] > node.planeDist) {
      nodeNum = node.children[0];
    } else if (poly.bounds.max[node.planeType] < node.planeDist) {
      nodeNum = node.children[1];
    } else {
      findInternalPolygonEdges(node.children[1], polygon);
      nodeNum = node.children[0];
    }
  }
}

void ModelBuilder::findInternalEdgesOnPolygon(int p1Num, int p2Num) {
  const BPolygon& p1 = polygons_[static_cast<std::size_t>(p1Num)];
  const BPolygon& p2 = polygons_[static_cast<std::size_t>(p2Num)];
  for (int i = 0; i < 3; ++i) {
    if (p1.bounds.min[i] > p2.bounds.max[i]) return;
    if (p1.bounds.max[i] < p2.bounds.min[i]) return;
  }
  for (const int edgeNum : p1.edges) {
    BEdge& edge = edges_[static_cast<std::size_t>(std::abs(edgeNum))];
    if (edge.internal) continue;
    const Vec3 v1 = edgeStart(edgeNum);
    const Vec3 v2 = edgeEnd(edgeNum);
    // both vertices within the other polygon's bounds (expanded)
    int k = 0;
    for (; k < 3; ++k) {
      Real d = p2.bounds.max[k] + tol::kVertexEpsilon;
      if (v1[k] > d || v2[k] > d) break;
      d = p2.bounds.min[k] - tol::kVertexEpsilon;
      if (v1[k] < d || v2[k] < d) break;
    }
    if (k < 3) continue;
    std::size_t j = 0;
    for (; j < p2.edges.size(); ++j) {
      if (std::abs(edgeNum) == std::abs(p2.edges[j])) break;
    }
    const bool shared = j < p2.edges.size();
    if (shared) {
      if (edge.numUsers > 2) continue;       // would need all users tested
      if (edgeNum == p2.edges[j]) continue;  // same direction: overlapping polygons
    } else {
      // both vertices on the other polygon's plane
      if (std::fabs(p2.plane.distance(v1)) > tol::kVertexEpsilon) continue;
      if (std::fabs(p2.plane.distance(v2)) > tol::kVertexEpsilon) continue;
    }
    // the polygons must face each other; if not, stop testing p1 against p2
    const Vec3 dir1 = v2 - v1;
    const Vec3 dir2 = p1.plane.normal.cross(dir1);
    if (p2.plane.normal.dot(dir2) < 0) break;
    if (!shared) {
      if (!pointInsidePolygon(p2, v1)) continue;
      if (!pointInsidePolygon(p2, v2)) continue;
    }
    edge.internal = true;
    counters_.numInternalEdges++;
  }
}

bool ModelBuilder::pointInsidePolygon(const BPolygon& p, const Vec3& v) const {
  for (const int edgeNum : p.edges) {
    const Vec3 v1 = edgeStart(edgeNum);
    const Vec3 v2 = edgeEnd(edgeNum);
    const Vec3 dir1 = v2 - v1;
    const Vec3 vec = v - v1;
    const Vec3 dir2 = dir1.cross(p.plane.normal);
    if (vec.dot(dir2) > tol::kVertexEpsilon) return false;
  }
  return true;
}

}  // namespace cmkit::detail
