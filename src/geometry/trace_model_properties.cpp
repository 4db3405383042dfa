// Trace model mass properties, invariant checks and listing.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "cmkit/trace_model.h"
#include "math/dvec3.h"

namespace cmkit {

MassProperties TraceModel::massProperties(Real density) const {
  MassProperties mp;
  if (!isConvex_ || numPolygons_ == 0) {
    Vec3 c;
    for (int i = 0; i < numVertices_; ++i) c += vertices_[size_t(i)];
    mp.centerOfMass = numVertices_ ? c * (Real(1) / Real(numVertices_)) : Vec3{};
    return mp;
  }
  // Split the solid into tetrahedra (reference point, a polygon's fan
  // triangle). Each contributes its volume det/6, first moment and second
  // moment det/120 * (aa' + bb' + cc' + ss'), s = a + b + c, relative to the
  // reference point. Accumulated in double.
  const Vec3 ref = offset_;
  double vol = 0, second[3][3] = {{0}};
  detail::DVec3 first;
  for (int i = 0; i < numPolygons_; ++i) {
    const TrmPolygon& p = polygons_[size_t(i)];
    const Vec3 a = vertices_[size_t(p.startVertex(*this, 0))] - ref;
    for (int j = 1; j + 1 < p.numEdges; ++j) {
      const Vec3 b = vertices_[size_t(p.startVertex(*this, j))] - ref;
      const Vec3 c = vertices_[size_t(p.startVertex(*this, j + 1))] - ref;
      const double det = double(a.x) * (double(b.y) * c.z - double(b.z) * c.y) -
                         double(a.y) * (double(b.x) * c.z - double(b.z) * c.x) +
                         double(a.z) * (double(b.x) * c.y - double(b.y) * c.x);
      const detail::DVec3 s(double(a.x) + b.x + c.x, double(a.y) + b.y + c.y, double(a.z) + b.z + c.z);
      vol += det / 6;
      for (int k = 0; k < 3; ++k) first[k] += det / 24 * s[k];
      for (int r = 0; r < 3; ++r)
        for (int q = 0; q < 3; ++q)
          second[r][q] +=
              det / 120 * (double(a[r]) * a[q] + double(b[r]) * b[q] + double(c[r]) * c[q] + s[r] * s[q]);
    }
  }
  if (!(vol > 0)) return mp;
  const detail::DVec3 com(first.x / vol, first.y / vol, first.z / vol);
  mp.volume = Real(vol);
  mp.mass = Real(vol * density);
  mp.centerOfMass = ref + com.toVec3();
  // Second moment about the centre of mass, then I = trace(C) Id - C.
  double c[3][3];
  for (int r = 0; r < 3; ++r)
    for (int q = 0; q < 3; ++q) c[r][q] = density * (second[r][q] - vol * com[r] * com[q]);
  const double tr = c[0][0] + c[1][1] + c[2][2];
  for (int r = 0; r < 3; ++r)
    for (int q = 0; q < 3; ++q) mp.inertiaTensor[r][q] = Real((r == q ? tr : 0.0) - c[r][q]);
  return mp;
}

std::string TraceModel::checkInvariants() const {
  auto fail = [](const std::string& s) { return s; };
  if (numVertices_ < 1 || numVertices_ > kMaxTrmVertices) return fail("vertex count out of range");
  if (numEdges_ < 0 || numEdges_ > kMaxTrmEdges) return fail("edge count out of range");
  if (numPolygons_ < 0 || numPolygons_ > kMaxTrmPolygons) return fail("polygon count out of range");
  Real scale = 1;
  for (int i = 0; i < numVertices_; ++i) {
    const Vec3& v = vertices_[size_t(i)];
    if (!v.isFinite()) return fail("vertex " + std::to_string(i) + " not finite");
    scale = std::max({scale, std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
  }
  const Real eps = tol::kTrmPlanarEpsilon * scale * Real(0.01);
  for (int e = 1; e <= numEdges_; ++e) {
    const TrmEdge& ed = edges_[size_t(e)];
    if (ed.v[0] < 0 || ed.v[0] >= numVertices_ || ed.v[1] < 0 || ed.v[1] >= numVertices_)
      return fail("edge " + std::to_string(e) + " references a missing vertex");
    if ((vertices_[size_t(ed.v[0])] - vertices_[size_t(ed.v[1])]).length() <= eps)
      return fail("edge " + std::to_string(e) + " has zero length");
    if (edgeVertices_[size_t(e)][0] != ed.v[0] || edgeVertices_[size_t(e)][1] != ed.v[1])
      return fail("edge " + std::to_string(e) + " packed vertices differ from its own");
  }
  std::vector<int> forward(size_t(numEdges_ + 1), 0), backward(size_t(numEdges_ + 1), 0);
  for (int i = 0; i < numPolygons_; ++i) {
    const TrmPolygon& p = polygons_[size_t(i)];
    const std::string name = "polygon " + std::to_string(i);
    if (p.numEdges < 3 || p.numEdges > kMaxTrmPolygonEdges) return fail(name + " edge count out of range");
    if (std::fabs(p.normal.lengthSquared() - 1) > Real(1e-4)) return fail(name + " normal not unit length");
    Vec3 newell;
    for (int j = 0; j < p.numEdges; ++j) {
      const int num = p.edges[size_t(j)];
      if (num == 0 || std::abs(num) > numEdges_) return fail(name + " references a missing edge");
      (num > 0 ? forward : backward)[size_t(std::abs(num))]++;
      const TrmEdge& ed = edges_[size_t(std::abs(num))];
      const int end = num > 0 ? ed.v[1] : ed.v[0];
      if (end != p.startVertex(*this, (j + 1) % p.numEdges)) return fail(name + " edge loop not closed");
      const Vec3& a = vertices_[size_t(p.startVertex(*this, j))];
      const Vec3& b = vertices_[size_t(end)];
      newell += a.cross(b);
      if (std::fabs(p.normal.dot(a) - p.dist) > eps) return fail(name + " vertex not on its plane");
      if (!p.bounds.expanded(eps).containsPoint(a)) return fail(name + " bounds do not contain its vertex");
    }
    if (newell.dot(p.normal) <= 0) return fail(name + " edges not counter-clockwise around its normal");
    std::uint64_t edgeBits = 0;
    std::uint32_t vertexBits = 0;
    for (int j = 0; j < p.numEdges; ++j) {
      edgeBits |= std::uint64_t(1) << std::abs(p.edges[size_t(j)]);
      vertexBits |= std::uint32_t(1) << p.startVertex(*this, j);
    }
    const PolygonFacing& f = facing_[size_t(i)];
    if (edgeBits != f.edgeBits || vertexBits != f.vertexBits)
      return fail(name + " edge or vertex bits differ from its edges");
    if (f.normal != p.normal || f.planeVertex != edges_[size_t(std::abs(p.edges[0]))].v[0])
      return fail(name + " packed normal or plane vertex differs from the polygon's");
    if (isConvex_) {
      bool behind = false;
      for (int v = 0; v < numVertices_; ++v) {
        const Real d = p.normal.dot(vertices_[size_t(v)]) - p.dist;
        if (d > eps) return fail(name + " is not outward facing / the solid is not convex");
        if (d < -eps) behind = true;
      }
      if (!behind) return fail(name + " has no vertex behind it (flat solid)");
    }
  }
  if (numPolygons_ > 0) {
    for (int e = 1; e <= numEdges_; ++e) {
      if (forward[size_t(e)] != 1 || backward[size_t(e)] != 1)
        return fail("edge " + std::to_string(e) + " is not used once in each direction");
    }
  }
  if (isConvex_ && numVertices_ - numEdges_ + numPolygons_ != 2) return fail("Euler characteristic is not 2");
  Bounds b;
  for (int i = 0; i < numVertices_; ++i) b.addPoint(vertices_[size_t(i)]);
  for (int k = 0; k < 3; ++k) {
    if (std::fabs(b.min[k] - bounds_.min[k]) > eps || std::fabs(b.max[k] - bounds_.max[k]) > eps)
      return fail("bounds do not match the vertices");
  }
  return {};
}

std::string TraceModel::describe() const {
  std::string s;
  char buf[256];
  auto add = [&](const char* fmt, auto... args) {
    std::snprintf(buf, sizeof buf, fmt, args...);
    s += buf;
  };
  add("%s trace model%s: %d vertices, %d edges, %d polygons\n", std::string(toString(shape_)).c_str(),
      isConvex_ ? " (convex)" : "", numVertices_, numEdges_, numPolygons_);
  add("bounds (%g %g %g) - (%g %g %g), centre (%g %g %g)\n", double(bounds_.min.x), double(bounds_.min.y),
      double(bounds_.min.z), double(bounds_.max.x), double(bounds_.max.y), double(bounds_.max.z),
      double(offset_.x), double(offset_.y), double(offset_.z));
  s += "vertices:\n";
  for (int i = 0; i < numVertices_; ++i) {
    const Vec3& v = vertices_[size_t(i)];
    add("  %2d  (%g %g %g)\n", i, double(v.x), double(v.y), double(v.z));
  }
  if (numEdges_) s += "edges (from -> to):\n";
  for (int e = 1; e <= numEdges_; ++e)
    add("  %2d  %d -> %d\n", e, edges_[size_t(e)].v[0], edges_[size_t(e)].v[1]);
  if (numPolygons_) s += "polygons (signed edges, counter-clockwise; plane normal and dist):\n";
  for (int i = 0; i < numPolygons_; ++i) {
    const TrmPolygon& p = polygons_[size_t(i)];
    add("  %2d  (", i);
    for (int j = 0; j < p.numEdges; ++j) add(j ? " %d" : "%d", p.edges[size_t(j)]);
    add(")  normal (%g %g %g) dist %g\n", double(p.normal.x), double(p.normal.y), double(p.normal.z),
        double(p.dist));
  }
  return s;
}

}  // namespace cmkit
