// Trace model shapes (the original's idTraceModel::Setup*), with the
// original's feature numbering where query results report it.
#include "cmkit/trace_model.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "geometry/trace_model_builder.h"

namespace cmkit {

using detail::TraceModelBuilder;

std::string_view toString(TrmShape shape) {
  switch (shape) {
    case TrmShape::Point:
      return "point";
    case TrmShape::Box:
      return "box";
    case TrmShape::Octahedron:
      return "octahedron";
    case TrmShape::Dodecahedron:
      return "dodecahedron";
    case TrmShape::Cylinder:
      return "cylinder";
    case TrmShape::Cone:
      return "cone";
    case TrmShape::Bone:
      return "bone";
    case TrmShape::Polygon:
      return "polygon";
    case TrmShape::PolygonVolume:
      return "polygon volume";
    case TrmShape::Custom:
      return "convex hull";
  }
  return "?";
}

// ---- TraceModelBuilder ------------------------------------------------------

TraceModel detail::TraceModelBuilder::finish(const Vec3& offset, bool convex, bool computePlanes) {
  TraceModel& t = trm_;
  t.offset_ = offset;
  t.isConvex_ = convex;
  t.bounds_.clear();
  for (int i = 0; i < t.numVertices_; ++i) t.bounds_.addPoint(t.vertices_[size_t(i)]);
  for (int i = 0; i < t.numPolygons_; ++i) {
    TrmPolygon& p = t.polygons_[size_t(i)];
    const Vec3& v0 = t.vertices_[size_t(p.startVertex(t, 0))];
    if (computePlanes) {
      const Vec3& v1 = t.vertices_[size_t(p.startVertex(t, 1))];
      const Vec3& v2 = t.vertices_[size_t(p.startVertex(t, 2))];
      p.normal = (v1 - v0).cross(v2 - v0);
      p.normal.normalize();
    }
    p.dist = p.normal.dot(v0);
    p.bounds.clear();
    std::uint64_t edgeBits = 0;
    std::uint32_t vertexBits = 0;
    for (int j = 0; j < p.numEdges; ++j) {
      p.bounds.addPoint(t.vertices_[size_t(p.startVertex(t, j))]);
      edgeBits |= std::uint64_t(1) << std::abs(p.edges[size_t(j)]);
      vertexBits |= std::uint32_t(1) << p.startVertex(t, j);
    }
    t.facing_[size_t(i)] = {p.normal, vertexBits, edgeBits,
                            std::uint8_t(t.edges_[size_t(std::abs(p.edges[0]))].v[0])};
  }
  for (int e = 0; e <= t.numEdges_; ++e)
    t.edgeVertices_[size_t(e)] = {std::uint8_t(t.edges_[size_t(e)].v[0]),
                                  std::uint8_t(t.edges_[size_t(e)].v[1])};
  if (convex) generateEdgeNormals(t);
  return t;
}

int detail::TraceModelBuilder::generateEdgeNormals(TraceModel& t) {
  int sharp = 0;
  for (int i = 0; i <= t.numEdges_; ++i) t.edges_[size_t(i)].normal = Vec3{};
  for (int i = 0; i < t.numPolygons_; ++i) {
    const TrmPolygon& p = t.polygons_[size_t(i)];
    for (int j = 0; j < p.numEdges; ++j) {
      const int num = p.edges[size_t(j)];
      TrmEdge& e = t.edges_[size_t(std::abs(num))];
      if (e.normal.isZero()) {
        e.normal = p.normal;
        continue;
      }
      const Real dot = e.normal.dot(p.normal);
      if (dot < tol::kSharpEdgeDot) {
        // Nearly opposite faces: the bisector is ill-defined, use the vector
        // pointing out of both faces, at the length a bisector would have.
        const Vec3 dir =
            t.vertices_[size_t(e.v[num > 0 ? 1 : 0])] - t.vertices_[size_t(e.v[num > 0 ? 0 : 1])];
        Vec3 n = e.normal.cross(dir) + p.normal.cross(-dir);
        n.normalize();
        e.normal = n * (Real(0.5) / (Real(0.5) + Real(0.5) * tol::kSharpEdgeDot));
        ++sharp;
      } else {
        e.normal = (e.normal + p.normal) * (Real(0.5) / (Real(0.5) + Real(0.5) * dot));
      }
    }
  }
  return sharp;
}

Result<TraceModel> detail::TraceModelBuilder::fromFaceLoops(TrmShape shape, std::span<const Vec3> points,
                                                            const std::vector<std::vector<int>>& loops,
                                                            const Vec3& offset) {
  // Vertices keep their relative order; points on no face are dropped.
  std::vector<int> remap(points.size(), -1);
  for (const auto& loop : loops)
    for (int v : loop) remap[size_t(v)] = 0;
  int numVerts = 0;
  for (int& r : remap)
    if (r == 0) r = numVerts++;
  if (numVerts > kMaxTrmVertices) {
    return Error{"convex shape has " + std::to_string(numVerts) + " vertices (at most " +
                 std::to_string(kMaxTrmVertices) + ")"};
  }
  if (loops.size() > size_t(kMaxTrmPolygons)) {
    return Error{"convex shape has " + std::to_string(loops.size()) + " polygons (at most " +
                 std::to_string(kMaxTrmPolygons) + ")"};
  }
  TraceModelBuilder b(shape);
  for (size_t i = 0; i < points.size(); ++i)
    if (remap[i] >= 0) b.addVertex(points[i]);
  // Edges: each undirected vertex pair once, numbered in order of first use.
  std::vector<std::pair<int, int>> edgeEnds;
  for (const auto& loop : loops) {
    if (loop.size() > size_t(kMaxTrmPolygonEdges)) {
      return Error{"convex shape has a polygon with " + std::to_string(loop.size()) + " edges (at most " +
                   std::to_string(kMaxTrmPolygonEdges) + ")"};
    }
    std::vector<int> signedEdges;
    for (size_t i = 0; i < loop.size(); ++i) {
      const int a = remap[size_t(loop[i])];
      const int c = remap[size_t(loop[(i + 1) % loop.size()])];
      int num = 0;
      for (size_t e = 0; e < edgeEnds.size(); ++e) {
        if (edgeEnds[e] == std::pair{a, c}) num = int(e) + 1;
        if (edgeEnds[e] == std::pair{c, a}) num = -(int(e) + 1);
      }
      if (num == 0) {
        if (edgeEnds.size() >= size_t(kMaxTrmEdges)) {
          return Error{"convex shape has more than " + std::to_string(kMaxTrmEdges) + " edges"};
        }
        edgeEnds.emplace_back(a, c);
        num = b.addEdge(a, c);
      }
      signedEdges.push_back(num);
    }
    b.addPolygon(signedEdges);
  }
  return b.finish(offset, true);
}

// ---- Shapes -----------------------------------------------------------------

namespace {

// Checks the bounds of a bounds-based shape. Returns an empty string when
// they are usable; `allowFlat` admits zero size on one or two axes.
std::string checkShapeBounds(std::string_view what, const Bounds& b, bool allowFlat) {
  static constexpr const char* kAxis[3] = {"x", "y", "z"};
  if (!b.min.isFinite() || !b.max.isFinite()) return std::string(what) + " bounds are not finite";
  for (int i = 0; i < 3; ++i) {
    if (b.max[i] < b.min[i]) {
      return std::string(what) + " bounds have max below min on " + kAxis[i];
    }
  }
  if (!allowFlat) {
    for (int i = 0; i < 3; ++i) {
      if (b.max[i] == b.min[i]) {
        return std::string(what) + " bounds have zero size on " + kAxis[i] + " (a flat shape: use a polygon)";
      }
    }
  }
  return {};
}

bool isPointBounds(const Bounds& b) { return b.min == b.max; }

Error degenerate(const std::string& why) { return Error{"degenerate trm (" + why + ")"}; }

}  // namespace

TraceModel TraceModel::point() {
  TraceModelBuilder b(TrmShape::Point);
  b.addVertex(Vec3{});
  return b.finish(Vec3{}, false);
}

Result<TraceModel> TraceModel::box(const Bounds& bounds) {
  if (auto why = checkShapeBounds("box", bounds, true); !why.empty()) return degenerate(why);
  if (isPointBounds(bounds)) {
    TraceModel p = point();
    p.translate(bounds.min);
    return p;
  }
  TraceModelBuilder b(TrmShape::Box);
  // Vertex i: x from bit (i ^ (i >> 1)) & 1, y from bit 1, z from bit 2, so
  // that 0..3 run counter-clockwise around the bottom seen from above.
  for (int i = 0; i < 8; ++i) {
    b.addVertex({bounds[(i ^ (i >> 1)) & 1].x, bounds[(i >> 1) & 1].y, bounds[(i >> 2) & 1].z});
  }
  for (int i = 0; i < 4; ++i) b.addEdge(i, (i + 1) & 3);            // 1-4: bottom loop
  for (int i = 0; i < 4; ++i) b.addEdge(4 + i, 4 + ((i + 1) & 3));  // 5-8: top loop
  for (int i = 0; i < 4; ++i) b.addEdge(i, 4 + i);                  // 9-12: verticals
  const int bottom[4] = {-4, -3, -2, -1};
  const int top[4] = {5, 6, 7, 8};
  b.addPolygon(bottom);
  b.addPolygon(top);
  for (int i = 0; i < 4; ++i) {  // sides: -y, +x, +y, -x
    const int side[4] = {i + 1, 9 + ((i + 1) & 3), -(5 + i), -(9 + i)};
    b.addPolygon(side);
  }
  // The box's normals are exact, not derived from its vertices.
  const Vec3 normals[6] = {{0, 0, -1}, {0, 0, 1}, {0, -1, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}};
  for (int i = 0; i < 6; ++i) b.model().polygons_[size_t(i)].normal = normals[i];
  return b.finish(bounds.center(), true, false);
}

Result<TraceModel> TraceModel::octahedron(const Bounds& bounds) {
  if (auto why = checkShapeBounds("octahedron", bounds, false); !why.empty()) return degenerate(why);
  const Vec3 c = bounds.center();
  const Vec3 h = bounds.max - c;
  TraceModelBuilder b(TrmShape::Octahedron);
  b.addVertex({c.x + h.x, c.y, c.z});  // 0: +x
  b.addVertex({c.x - h.x, c.y, c.z});  // 1: -x
  b.addVertex({c.x, c.y + h.y, c.z});  // 2: +y
  b.addVertex({c.x, c.y - h.y, c.z});  // 3: -y
  b.addVertex({c.x, c.y, c.z + h.z});  // 4: +z
  b.addVertex({c.x, c.y, c.z - h.z});  // 5: -z
  const int ends[12][2] = {{4, 0}, {0, 2}, {2, 4}, {2, 1}, {1, 4}, {1, 3},
                           {3, 4}, {3, 0}, {5, 2}, {5, 1}, {5, 3}, {5, 0}};
  for (const auto& e : ends) b.addEdge(e[0], e[1]);
  const int loops[8][3] = {{1, 2, 3},    {-3, 4, 5},   {-5, 6, 7},    {-7, 8, -1},
                           {9, -2, -12}, {10, -4, -9}, {11, -6, -10}, {12, -8, -11}};
  for (const auto& l : loops) b.addPolygon(l);
  return b.finish(c, true);
}

Result<TraceModel> TraceModel::dodecahedron(const Bounds& bounds) {
  if (auto why = checkShapeBounds("dodecahedron", bounds, false); !why.empty()) return degenerate(why);
  // The regular dodecahedron with circumradius 1: cube corners 1/sqrt(3) and
  // the golden-ratio points (0, 1/(phi sqrt 3), phi/sqrt 3) cyclically; then
  // scaled per axis so that its extent fills the bounds.
  constexpr Real kA = 0.5773502691896257f;  // 1 / sqrt(3)
  constexpr Real kB = 0.3568220897730899f;  // 1 / (phi sqrt(3))
  constexpr Real kC = 0.9341723589729214f;  // phi / sqrt(3)
  const Real d = Real(0.5) / kC;
  Vec3 a, bb, cc;
  for (int i = 0; i < 3; ++i) {
    const Real s = (bounds.max[i] - bounds.min[i]) * d;
    a[i] = kA * s;
    bb[i] = kB * s;
    cc[i] = kC * s;
  }
  const Vec3 o = bounds.center();
  Vec3 pts[20];
  for (int i = 0; i < 8; ++i) {  // 0..7: cube corners, x major
    pts[i] = {o.x + ((i & 4) ? -a.x : a.x), o.y + ((i & 2) ? -a.y : a.y), o.z + ((i & 1) ? -a.z : a.z)};
  }
  pts[8] = {o.x + bb.x, o.y + cc.y, o.z};
  pts[9] = {o.x - bb.x, o.y + cc.y, o.z};
  pts[10] = {o.x + bb.x, o.y - cc.y, o.z};
  pts[11] = {o.x - bb.x, o.y - cc.y, o.z};
  pts[12] = {o.x + cc.x, o.y, o.z + bb.z};
  pts[13] = {o.x + cc.x, o.y, o.z - bb.z};
  pts[14] = {o.x - cc.x, o.y, o.z + bb.z};
  pts[15] = {o.x - cc.x, o.y, o.z - bb.z};
  pts[16] = {o.x, o.y + bb.y, o.z + cc.z};
  pts[17] = {o.x, o.y - bb.y, o.z + cc.z};
  pts[18] = {o.x, o.y + bb.y, o.z - cc.z};
  pts[19] = {o.x, o.y - bb.y, o.z - cc.z};
  auto faces = TraceModelBuilder::hullFaces(pts);
  if (!faces) return faces.error();
  if (faces->size() != 12) return degenerate("dodecahedron bounds too thin");
  auto trm = TraceModelBuilder::fromFaceLoops(TrmShape::Dodecahedron, pts, *faces, o);
  if (!trm) return trm.error();
  trm->bounds_ = bounds;  // the extreme points touch the bounds exactly
  return trm;
}

namespace {
constexpr Real kTwoPi = 2 * std::numbers::pi_v<Real>;
}

Result<TraceModel> TraceModel::cylinder(const Bounds& bounds, int sides) {
  if (auto why = checkShapeBounds("cylinder", bounds, false); !why.empty()) return degenerate(why);
  if (sides < 3 || sides > 10) {
    return degenerate("a cylinder needs 3 to 10 sides, got " + std::to_string(sides));
  }
  const int n = sides;
  const Vec3 o = bounds.center();
  const Vec3 h = bounds.max - o;
  TraceModelBuilder b(TrmShape::Cylinder);
  for (int i = 0; i < n; ++i) {
    const Real angle = kTwoPi * Real(i) / Real(n);
    b.addVertex({std::cos(angle) * h.x + o.x, std::sin(angle) * h.y + o.y, -h.z + o.z});
  }
  for (int i = 0; i < n; ++i) {
    const Vec3 v = b.model().vertex(i);
    b.addVertex({v.x, v.y, h.z + o.z});
  }
  for (int i = 0; i < n; ++i) b.addEdge(i, (i + 1) % n);          // 1..n: bottom
  for (int i = 0; i < n; ++i) b.addEdge(n + i, n + (i + 1) % n);  // n+1..2n: top
  for (int i = 0; i < n; ++i) b.addEdge(i, n + i);                // 2n+1..3n: verticals
  for (int i = 0; i < n; ++i) {
    const int ii = i + 1;
    const int side[4] = {ii, 2 * n + (ii % n) + 1, -(n + ii), -(2 * n + ii)};
    b.addPolygon(side);
  }
  int bottom[10], top[10];
  for (int i = 0; i < n; ++i) {
    bottom[i] = -(n - i);
    top[i] = n + i + 1;
  }
  b.addPolygon({bottom, size_t(n)});
  b.addPolygon({top, size_t(n)});
  return b.finish(o, true);
}

Result<TraceModel> TraceModel::cone(const Bounds& bounds, int sides) {
  if (auto why = checkShapeBounds("cone", bounds, false); !why.empty()) return degenerate(why);
  if (sides < 3 || sides > 15) {
    return degenerate("a cone needs 3 to 15 sides, got " + std::to_string(sides));
  }
  const int n = sides;
  const Vec3 o = bounds.center();
  const Vec3 h = bounds.max - o;
  TraceModelBuilder b(TrmShape::Cone);
  for (int i = 0; i < n; ++i) {
    const Real angle = kTwoPi * Real(i) / Real(n);
    b.addVertex({std::cos(angle) * h.x + o.x, std::sin(angle) * h.y + o.y, -h.z + o.z});
  }
  b.addVertex({o.x, o.y, h.z + o.z});                     // n: apex
  for (int i = 0; i < n; ++i) b.addEdge(i, (i + 1) % n);  // 1..n: base
  for (int i = 0; i < n; ++i) b.addEdge(i, n);            // n+1..2n: to the apex
  for (int i = 0; i < n; ++i) {
    const int ii = i + 1;
    const int side[3] = {ii, n + (ii % n) + 1, -(n + ii)};
    b.addPolygon(side);
  }
  int base[15];
  for (int i = 0; i < n; ++i) base[i] = -(n - i);
  b.addPolygon({base, size_t(n)});
  return b.finish(o, true);
}

Result<TraceModel> TraceModel::bone(Real length, Real width) {
  if (!std::isfinite(length) || !std::isfinite(width) || !(length > 0) || !(width > 0)) {
    return degenerate("a bone needs a length and width above 0");
  }
  const Real half = length * Real(0.5);
  TraceModelBuilder b(TrmShape::Bone);
  b.addVertex({0, 0, -half});
  b.addVertex({0, width * Real(-0.5), 0});
  b.addVertex({width * Real(0.5), width * Real(0.25), 0});
  b.addVertex({width * Real(-0.5), width * Real(0.25), 0});
  b.addVertex({0, 0, half});
  for (int i = 0; i < 3; ++i) b.addEdge(0, i + 1);                // 1-3: lower apex
  for (int i = 0; i < 3; ++i) b.addEdge(i + 1, 1 + (i + 1) % 3);  // 4-6: middle triangle
  for (int i = 0; i < 3; ++i) b.addEdge(i + 1, 4);                // 7-9: upper apex
  const int loops[6][3] = {{2, -4, -1}, {3, -5, -2}, {1, -6, -3}, {4, 8, -7}, {5, 9, -8}, {6, 7, -9}};
  for (const auto& l : loops) b.addPolygon(l);
  return b.finish(Vec3{}, true);
}

namespace {

// Validates a polygon's vertex loop: count, finite, no repeated points,
// planar, convex and counter-clockwise around the normal from its first three
// vertices. Returns that normal.
Result<Vec3> checkPolygon(std::span<const Vec3> v, size_t maxVerts) {
  if (v.size() < 3) return degenerate("a polygon needs at least 3 vertices");
  if (v.size() > maxVerts) {
    return degenerate("a polygon may have at most " + std::to_string(maxVerts) + " vertices, got " +
                      std::to_string(v.size()));
  }
  Real scale = 1;
  for (const Vec3& p : v) {
    if (!p.isFinite()) return degenerate("polygon vertex is not finite");
    scale = std::max({scale, std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)});
  }
  for (size_t i = 0; i < v.size(); ++i) {
    if ((v[(i + 1) % v.size()] - v[i]).length() <= tol::kTrmPointEpsilon) {
      return degenerate("polygon vertices " + std::to_string(i) + " and " +
                        std::to_string((i + 1) % v.size()) + " coincide");
    }
  }
  Vec3 normal = (v[1] - v[0]).cross(v[2] - v[0]);
  if (normal.normalize() == 0) return degenerate("polygon has a zero normal");
  const Real planarTol = tol::kTrmPlanarEpsilon * scale;
  for (size_t i = 0; i < v.size(); ++i) {
    const Vec3& a = v[i];
    const Vec3& b = v[(i + 1) % v.size()];
    const Vec3& c = v[(i + 2) % v.size()];
    if (std::fabs(normal.dot(a - v[0])) > planarTol) {
      return degenerate("polygon is not planar (vertex " + std::to_string(i) + ")");
    }
    if ((b - a).cross(c - b).dot(normal) < -planarTol) {
      return degenerate("polygon is not convex (at vertex " + std::to_string((i + 1) % v.size()) + ")");
    }
  }
  return normal;
}

}  // namespace

Result<TraceModel> TraceModel::polygon(std::span<const Vec3> v) {
  auto normal = checkPolygon(v, size_t(kMaxTrmPolygonEdges));
  if (!normal) return normal.error();
  const int n = int(v.size());
  TraceModelBuilder b(TrmShape::Polygon);
  Vec3 mid;
  for (int i = 0; i < n; ++i) {
    b.addVertex(v[size_t(i)]);
    mid += v[size_t(i)];
  }
  for (int i = 0; i < n; ++i) b.addEdge(i, (i + 1) % n);
  int front[kMaxTrmPolygonEdges], back[kMaxTrmPolygonEdges];
  for (int i = 0; i < n; ++i) {
    front[i] = i + 1;
    back[i] = -(n - i);
  }
  b.addPolygon({front, size_t(n)});
  b.addPolygon({back, size_t(n)});
  b.model().polygons_[0].normal = *normal;
  b.model().polygons_[1].normal = -*normal;
  TraceModel trm = b.finish(mid * (Real(1) / Real(n)), false, false);
  // A lone polygon's edges face outward in its plane.
  for (int i = 0; i < n; ++i) {
    TrmEdge& e = trm.edges_[size_t(i + 1)];
    e.normal = normal->cross(trm.vertices_[size_t(e.v[0])] - trm.vertices_[size_t(e.v[1])]).normalized();
  }
  return trm;
}

Result<TraceModel> TraceModel::polygonVolume(std::span<const Vec3> v, Real thickness) {
  if (!std::isfinite(thickness) || !(thickness > 0)) {
    return degenerate("a polygon volume needs a thickness above 0");
  }
  // Three edges per polygon vertex must fit: at most kMaxTrmEdges / 3.
  auto normal = checkPolygon(v, size_t(kMaxTrmEdges / 3));
  if (!normal) return normal.error();
  const int n = int(v.size());
  TraceModelBuilder b(TrmShape::PolygonVolume);
  Vec3 mid;
  for (int i = 0; i < n; ++i) b.addVertex(v[size_t(i)]);
  for (int i = 0; i < n; ++i) b.addVertex(v[size_t(i)] - *normal * thickness);
  for (int i = 0; i < 2 * n; ++i) mid += b.model().vertex(i);
  for (int i = 0; i < n; ++i) b.addEdge(i, (i + 1) % n);          // 1..n: front loop
  for (int i = 0; i < n; ++i) b.addEdge(n + i, n + (i + 1) % n);  // n+1..2n: back loop
  for (int i = 0; i < n; ++i) b.addEdge(i, n + i);                // 2n+1..3n: sides
  int front[kMaxTrmEdges / 3], back[kMaxTrmEdges / 3];
  for (int i = 0; i < n; ++i) {
    front[i] = i + 1;
    back[i] = -(n + n - i);
  }
  b.addPolygon({front, size_t(n)});
  b.addPolygon({back, size_t(n)});
  for (int i = 0; i < n; ++i) {
    const int side[4] = {-(i + 1), 2 * n + i + 1, n + i + 1, -(2 * n + (i + 1) % n + 1)};
    b.addPolygon(side);
  }
  return b.finish(mid * (Real(1) / Real(2 * n)), true);
}

Result<TraceModel> TraceModel::convexHull(std::span<const Vec3> points) {
  if (points.size() > size_t(kMaxTrmHullInputPoints)) {
    return degenerate("a convex hull takes at most " + std::to_string(kMaxTrmHullInputPoints) +
                      " points, got " + std::to_string(points.size()));
  }
  auto faces = TraceModelBuilder::hullFaces(points);
  if (!faces) return faces.error();
  Bounds bb;
  for (const Vec3& p : points) bb.addPoint(p);
  return TraceModelBuilder::fromFaceLoops(TrmShape::Custom, points, *faces, bb.center());
}

// ---- Transformations ----------------------------------------------------------

void TraceModel::translate(const Vec3& t) {
  for (int i = 0; i < numVertices_; ++i) vertices_[size_t(i)] += t;
  for (int i = 0; i < numPolygons_; ++i) {
    TrmPolygon& p = polygons_[size_t(i)];
    p.dist += p.normal.dot(t);
    p.bounds = p.bounds.translated(t);
  }
  bounds_ = bounds_.translated(t);
  offset_ += t;
}

void TraceModel::rotate(const Mat3& axis) {
  for (int i = 0; i < numVertices_; ++i) vertices_[size_t(i)] = vertices_[size_t(i)] * axis;
  for (int i = 1; i <= numEdges_; ++i) edges_[size_t(i)].normal = edges_[size_t(i)].normal * axis;
  bounds_.clear();
  for (int i = 0; i < numVertices_; ++i) bounds_.addPoint(vertices_[size_t(i)]);
  for (int i = 0; i < numPolygons_; ++i) {
    TrmPolygon& p = polygons_[size_t(i)];
    p.normal = p.normal * axis;
    facing_[size_t(i)].normal = p.normal;
    p.bounds.clear();
    for (int j = 0; j < p.numEdges; ++j) p.bounds.addPoint(vertices_[size_t(p.startVertex(*this, j))]);
    p.dist = p.normal.dot(vertices_[size_t(p.startVertex(*this, 0))]);
  }
  offset_ = offset_ * axis;
}

bool TraceModel::operator==(const TraceModel& o) const {
  if (shape_ != o.shape_ || numVertices_ != o.numVertices_ || numEdges_ != o.numEdges_ ||
      numPolygons_ != o.numPolygons_ || isConvex_ != o.isConvex_ || offset_ != o.offset_) {
    return false;
  }
  for (int i = 0; i < numVertices_; ++i)
    if (vertices_[size_t(i)] != o.vertices_[size_t(i)]) return false;
  for (int i = 1; i <= numEdges_; ++i) {
    if (edges_[size_t(i)].v[0] != o.edges_[size_t(i)].v[0] ||
        edges_[size_t(i)].v[1] != o.edges_[size_t(i)].v[1])
      return false;
  }
  for (int i = 0; i < numPolygons_; ++i) {
    const TrmPolygon& a = polygons_[size_t(i)];
    const TrmPolygon& b = o.polygons_[size_t(i)];
    if (a.numEdges != b.numEdges || a.normal != b.normal) return false;
    for (int j = 0; j < a.numEdges; ++j)
      if (a.edges[size_t(j)] != b.edges[size_t(j)]) return false;
  }
  return true;
}

}  // namespace cmkit
