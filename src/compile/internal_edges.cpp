// Internal edges: edges that a trace can never touch first (a concave
// crease between two faces, or an edge lying on another face) are marked so
// that queries skip them (the original's FindInternalEdges and helpers).
#include <cmath>
#include <cstdlib>

#include "compile/builder.h"

namespace cmkit::detail {

void ModelBuilder::markInternalEdges() {
  if (robustEdges_) {
    // An edge is one object for all its users; the rule below decides it
    // within one contents group, so an edge that a clip face marks internal
    // would be hidden from the solid face sharing it as well.
    std::vector<std::uint32_t> firstContents(edges_.size(), 0);
    mixedContentsEdge_.assign(edges_.size(), 0);
    for (const BPolygon& p : polygons_) {
      if (p.freed) continue;
      for (const int e : p.edges) {
        std::uint32_t& first = firstContents[static_cast<std::size_t>(std::abs(e))];
        if (first == 0) first = p.contents;
        if (first != p.contents) mixedContentsEdge_[static_cast<std::size_t>(std::abs(e))] = 1;
      }
    }
  }
  // Two-sided polygons mark no edges (findInternalPolygonEdges): a model of
  // them only needs no walk.
  bool anyOneSided = false;
  for (const BPolygon& p : polygons_)
    anyOneSided = anyOneSided || (!p.freed && !materials_[p.material].info.twoSided);
  if (!anyOneSided) return;
  ++checkCount_;
  findInternalEdges(0);
}

void ModelBuilder::findInternalEdges(int nodeNum) {
  for (;;) {
    for (const int p : polygonsAt(nodeNum)) {
      if (polygon(p).checkcount == checkCount_) continue;
      polygon(p).checkcount = checkCount_;
      findInternalPolygonEdges(0, p);
    }
    const BNode& here = node(nodeNum);
    if (here.isLeaf()) break;
    findInternalEdges(here.children[1]);
    nodeNum = here.children[0];
  }
}

void ModelBuilder::findInternalPolygonEdges(int nodeNum, int polygonNum) {
  const BPolygon& poly = polygon(polygonNum);
  if (materials_[poly.material].info.twoSided) return;
  walkTouching(nodeNum, poly.bounds, [&](int n) {
    for (const int p : polygonsAt(n)) {
      // (polygons reached through several nodes are tested several times,
      // as in the original)
      if (polygon(p).contents != poly.contents) continue;
      if (p == polygonNum) continue;
      findInternalEdgesOnPolygon(polygonNum, p);
    }
    return true;
  });
}

void ModelBuilder::findInternalEdgesOnPolygon(int p1Num, int p2Num) {
  const BPolygon& p1 = polygon(p1Num);
  const BPolygon& p2 = polygon(p2Num);
  if (!p2.bounds.intersects(p1.bounds)) return;
  // Robust edges: a parallel polygon (an overlapping copy of a face, or a
  // face touching it back to back) marks no edge of p1 that it does not
  // share. The original marks them (the facing test below gives 0 there),
  // so both copies of a corner edge where two brushes overlap with coplanar
  // faces get hidden.
  const bool parallel = std::fabs(p1.plane.normal.dot(p2.plane.normal)) > tol::kRobustEdgeParallelDot;
  for (const int edgeNum : p1.edges) {
    BEdge& e = edge(edgeNum);
    if (e.internal) continue;
    if (robustEdges_ && mixedContentsEdge_[static_cast<std::size_t>(std::abs(edgeNum))]) continue;
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
      if (e.numUsers > 2) continue;          // would need all users tested
      if (edgeNum == p2.edges[j]) continue;  // same direction: overlapping polygons
    } else {
      if (robustEdges_ && parallel) continue;
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
    e.internal = true;
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
