// Robust edges: T-junctions between coplanar polygons split (not the
// original's). Where a vertex of one polygon lies on the edge of a coplanar
// neighbour (brush faces side by side that do not end at the same corners:
// one face against two, or a face chopped in pieces by a brush standing on
// it), the two polygons meet along edges that are different objects. A point
// trace decides "inside" by the sign of a Plücker product per edge; two
// lines through nearly the same points give products that round
// independently, and a point passing within rounding of the seam (or
// through the sliver left where welding moved the vertex off the edge) is
// outside both polygons and crosses the surface. Splitting the polygon at the
// vertex makes the seam out of shared edges, whose one product both
// polygons read with opposite signs: exactly one of them takes the point.
// (Inserting the vertex alone would not do: the polygon would keep two
// edges on one line, whose products again round independently.)
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <unordered_map>
#include <utility>
#include <vector>

#include "compile/builder.h"
#include "math/dvec3.h"

namespace cmkit::detail {

void ModelBuilder::splitPolygonsAtTJunctions() {
  // The junctions: per edge, the coplanar neighbours' vertices found on it
  // (by any polygon using it).
  std::unordered_map<int, std::vector<int>> onEdge;
  const int numPolygons = static_cast<int>(polygons_.size());
  for (int p = 0; p < numPolygons; ++p) {
    if (polygon(p).freed || materials_[polygon(p).material].info.twoSided) continue;
    const std::vector<std::vector<int>> found = tJunctionsOf(p);
    for (std::size_t i = 0; i < found.size(); ++i) {
      if (found[i].empty()) continue;
      std::vector<int>& verts = onEdge[std::abs(polygon(p).edges[i])];
      verts.insert(verts.end(), found[i].begin(), found[i].end());
    }
  }
  if (onEdge.empty()) return;
  soleUse_.assign(edges_.size(), 0);
  for (const BPolygon& poly : polygons_) {
    if (poly.freed) continue;
    for (const int e : poly.edges) soleUse_[std::size_t(std::abs(e))] = e < 0 ? -1 : 1;
  }
  for (std::size_t e = 0; e < edges_.size(); ++e) {
    if (edges_[e].numUsers != 1) soleUse_[e] = 0;
  }
  // Every polygon using a split edge is cut, the coplanar ones and those
  // beside them at an angle alike: a polygon left with the whole edge would
  // meet the pieces at a new T-junction. An edge that a two-sided polygon
  // uses is left whole.
  std::unordered_map<int, std::vector<int>> usersOf;
  for (int p = 0; p < numPolygons; ++p) {
    if (polygon(p).freed) continue;
    for (const int e : polygon(p).edges) {
      if (onEdge.count(std::abs(e))) usersOf[std::abs(e)].push_back(p);
    }
  }
  std::vector<int> toCut;
  for (auto& [e, verts] : onEdge) {
    std::sort(verts.begin(), verts.end());
    verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
    const std::vector<int>& users = usersOf[e];
    if (std::any_of(users.begin(), users.end(),
                    [&](int p) { return materials_[polygon(p).material].info.twoSided; })) {
      verts.clear();
      continue;
    }
    toCut.insert(toCut.end(), users.begin(), users.end());
  }
  std::sort(toCut.begin(), toCut.end());
  toCut.erase(std::unique(toCut.begin(), toCut.end()), toCut.end());
  for (const int p : toCut) {
    std::vector<std::vector<EdgeSplit>> splits(polygon(p).edges.size());
    std::vector<int> inserted;  // a vertex near a corner may lie on both its edges: the first takes it
    bool any = false;
    for (std::size_t i = 0; i < splits.size(); ++i) {
      const int e = polygon(p).edges[i];
      const auto at = onEdge.find(std::abs(e));
      if (at == onEdge.end() || at->second.empty()) continue;
      for (const EdgeSplit& s : splitsAlong(e, at->second)) {
        if (std::find(inserted.begin(), inserted.end(), s.vertexNum) != inserted.end()) continue;
        inserted.push_back(s.vertexNum);
        splits[i].push_back(s);
        any = true;
      }
    }
    if (any) cutPolygon(p, splits);
  }
}

std::vector<std::vector<int>> ModelBuilder::tJunctionsOf(int polygonNum) {
  const BPolygon& poly = polygon(polygonNum);
  // The vertices of the coplanar polygons facing the same way around it.
  std::vector<int> others;
  Bounds near = poly.bounds.expanded(tol::kTJunctionEpsilon);
  walkTouching(0, near, [&](int n) {
    for (const int q : polygonsAt(n)) {
      const BPolygon& other = polygon(q);
      if (q == polygonNum || other.freed || !other.bounds.intersects(near)) continue;
      if (other.plane.normal.dot(poly.plane.normal) <= tol::kRobustEdgeParallelDot ||
          std::fabs(other.plane.dist - poly.plane.dist) > tol::kTJunctionEpsilon)
        continue;
      for (const int e : other.edges) others.push_back(edge(e).v[e < 0 ? 1 : 0]);
    }
    return true;
  });
  std::sort(others.begin(), others.end());
  others.erase(std::unique(others.begin(), others.end()), others.end());
  std::vector<std::vector<int>> found(poly.edges.size());
  for (std::size_t i = 0; i < poly.edges.size(); ++i) {
    for (const EdgeSplit& s : splitsAlong(poly.edges[i], others)) found[i].push_back(s.vertexNum);
  }
  return found;
}

std::vector<ModelBuilder::EdgeSplit> ModelBuilder::splitsAlong(int edgeNum,
                                                               const std::vector<int>& verts) const {
  std::vector<EdgeSplit> splits;
  const int v0 = edge(edgeNum).v[edgeNum < 0 ? 1 : 0], v1 = edge(edgeNum).v[edgeNum < 0 ? 0 : 1];
  const DVec3 a(vertex(v0)), d = DVec3(vertex(v1)) - a;
  const double length = d.length();
  if (!(length > 2 * tol::kTJunctionEpsilon)) return splits;
  for (const int v : verts) {
    if (v == v0 || v == v1) continue;
    const DVec3 p = DVec3(vertex(v)) - a;
    const double along = p.dot(d) / length;
    if (along <= tol::kTJunctionEpsilon || along >= length - tol::kTJunctionEpsilon) continue;
    DVec3 offset = d * along;
    offset /= length;
    offset = p - offset;  // from the edge's line
    if (offset.dot(offset) > double(tol::kTJunctionEpsilon) * tol::kTJunctionEpsilon) continue;
    splits.push_back({along / length, v});
  }
  std::sort(splits.begin(), splits.end(), [](const EdgeSplit& l, const EdgeSplit& r) { return l.t < r.t; });
  return splits;
}

namespace {

/// Distance of c from the line through a and b (0 when a == b).
double distanceFromLine(const Vec3& a, const Vec3& b, const Vec3& c) {
  const DVec3 ab = DVec3(b) - DVec3(a), ac = DVec3(c) - DVec3(a);
  const double len = ab.length();
  return len > 0 ? ab.cross(ac).length() / len : 0;
}

}  // namespace

void ModelBuilder::cutPolygon(int polygonNum, const std::vector<std::vector<EdgeSplit>>& splits) {
  const BPolygon old = polygon(polygonNum);
  // The outline with the junctions' vertices inserted, and the polygon's
  // own edges where nothing splits them (kept as they are).
  std::vector<int> outline, junctions;
  std::vector<std::pair<std::pair<int, int>, int>> keptEdges;  // (from, to) -> signed edge
  for (std::size_t i = 0; i < old.edges.size(); ++i) {
    const int e = old.edges[i];
    const int from = edge(e).v[e < 0 ? 1 : 0], to = edge(e).v[e < 0 ? 0 : 1];
    outline.push_back(from);
    if (splits[i].empty()) keptEdges.push_back({{from, to}, e});
    for (const EdgeSplit& s : splits[i]) {
      outline.push_back(s.vertexNum);
      junctions.push_back(s.vertexNum);
    }
  }
  // Cut the outline into convex pieces, none with two edges on one line: at
  // each junction still flat in its piece, along the chord to the piece's
  // vertex farthest from the junction's neighbours' line. A convex polygon
  // cut by a chord leaves two convex pieces, and the junction a corner of
  // both; with n junctions, n + 1 pieces.
  std::vector<std::vector<int>> pieces{outline};
  for (const int t : junctions) {
    for (std::size_t k = 0; k < pieces.size(); ++k) {
      std::vector<int>& loop = pieces[k];
      const auto at = std::find(loop.begin(), loop.end(), t);
      if (at == loop.end()) continue;
      const std::size_t n = loop.size(), i = std::size_t(at - loop.begin());
      const Vec3 prev = vertex(loop[(i + n - 1) % n]), next = vertex(loop[(i + 1) % n]);
      if (distanceFromLine(prev, next, vertex(t)) > tol::kTJunctionEpsilon) continue;  // a corner here
      std::size_t far = i;
      double farthest = 0;
      for (std::size_t j = 0; j < n; ++j) {
        const double d = distanceFromLine(prev, next, vertex(loop[j]));
        if (j != i && d > farthest) farthest = d, far = j;
      }
      if (farthest <= tol::kTJunctionEpsilon) break;  // a sliver: nothing to cut
      std::vector<int> a, b;
      for (std::size_t j = i;; j = (j + 1) % n) {
        a.push_back(loop[j]);
        if (j == far) break;
      }
      for (std::size_t j = far;; j = (j + 1) % n) {
        b.push_back(loop[j]);
        if (j == i) break;
      }
      loop = std::move(a);
      pieces.push_back(std::move(b));
      break;
    }
  }
  // Every piece a loop of at least three different vertices, else the
  // polygon stays as it is (odd geometry: a junction that welded onto a
  // corner).
  for (std::vector<int> loop : pieces) {
    const std::size_t n = loop.size();
    std::sort(loop.begin(), loop.end());
    if (n < 3 || std::unique(loop.begin(), loop.end()) != loop.end()) return;
  }
  // The pieces as polygons, in place of the old one. pieceEdge shares a
  // junction's pieces of edge, and each chord, with the polygon that uses
  // them the other way.
  for (std::size_t i = 0; i < old.edges.size(); ++i) {
    if (splits[i].empty()) continue;
    const int e = old.edges[i];  // replaced by its pieces: the user left runs it the other way
    soleUse_[std::size_t(std::abs(e))] = --edge(e).numUsers == 1 ? (e < 0 ? 1 : -1) : 0;
  }
  unlinkPolygon(0, polygonNum);
  polygon(polygonNum).freed = true;
  polygon(polygonNum).edges.clear();
  for (const std::vector<int>& loop : pieces) {
    BPolygon piece;
    for (std::size_t j = 0; j < loop.size(); ++j) {
      const int from = loop[j], to = loop[(j + 1) % loop.size()];
      const auto kept = std::find_if(keptEdges.begin(), keptEdges.end(), [&](const auto& k) {
        return k.first == std::pair{from, to};
      });
      piece.edges.push_back(kept != keptEdges.end() ? kept->second : pieceEdge(from, to));
      piece.bounds.addPoint(vertex(from));
    }
    piece.contents = old.contents;
    piece.material = old.material;
    piece.plane = old.plane;
    polygons_.push_back(std::move(piece));
    filterIntoTree(ItemKind::Polygon, 0, static_cast<int>(polygons_.size()) - 1);
  }
}

int ModelBuilder::pieceEdge(int from, int to) {
  for (const int sign : {1, -1}) {
    const int a = sign > 0 ? from : to, b = sign > 0 ? to : from;
    for (int e = edgeHashHead_.find(edgeKey(a, b)); e != kNone; e = edgeHashNext_[std::size_t(e)]) {
      if (edge(e).numUsers != 1 || soleUse_[std::size_t(e)] != -sign) continue;
      edge(e).numUsers++;
      soleUse_[std::size_t(e)] = 0;
      return sign * e;
    }
  }
  const int e = addEdge(from, to);
  soleUse_.push_back(1);
  return e;
}

void ModelBuilder::unlinkPolygon(int nodeNum, int polygonNum) {
  const Bounds& b = polygon(polygonNum).bounds;
  walkTouching(nodeNum, b, [&](int n) {
    int last = kNone;
    for (int r = node(n).polygons, next; r != kNone; r = next) {
      next = polygonRef(r).next;
      if (polygonRef(r).item != polygonNum) {
        last = r;
        continue;
      }
      (last != kNone ? polygonRef(last).next : node(n).polygons) = next;
      polygonRef(r).next = freePolygonRef_;
      freePolygonRef_ = r;
      counters_.numPolygonRefs--;
    }
    return true;
  });
}

}  // namespace cmkit::detail
