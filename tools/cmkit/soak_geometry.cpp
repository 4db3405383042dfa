// soak_geometry.cpp: the brush faces' cover and the overlap depths of
// `cmkit soak` (soak_geometry.h), in double.
#include "soak_geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace cmkit::cli::soak_geometry {

namespace {

/// A polygon lies on a brush plane when its normal is the plane's and its
/// distance differs by less than this.
constexpr Real kSamePlaneDist = 0.01f;
constexpr Real kSameNormalDot = 0.9999f;
/// Sample points of a brush face checked for a covering polygon: at most
/// this many along each side of the face's box, at least this far apart,
/// and this far inside the face's outline.
constexpr double kFaceSamples = 32;
constexpr double kFaceSampleStep = 1.0;
constexpr double kFaceSampleMargin = 0.1;

/// How far the placed vertices reach into a brush by its planes alone: the
/// smallest push along one of its planes that frees them (> 0: overlap).
Real brushDepth(const CollisionModel& world, const CmBrush& brush, const std::vector<Vec3>& verts,
                Vec3* exitNormal = nullptr) {
  Real depth = std::numeric_limits<Real>::max();
  for (const Plane& plane : world.planesOf(brush)) {
    Real lowest = std::numeric_limits<Real>::max();
    for (const Vec3& v : verts) lowest = std::min(lowest, plane.normal.dot(v) - plane.dist);
    if (-lowest < depth) {
      depth = -lowest;
      if (exitNormal) *exitNormal = plane.normal;
    }
  }
  return depth;
}

}  // namespace

/// The outline of face k of the brush: its plane clipped by the others.
std::vector<D3> faceOutline(const CollisionModel& world, const CmBrush& brush, std::uint32_t k) {
  const auto planes = world.planesOf(brush);
  const D3 n = d3(planes[k].normal);
  const D3 u0 = std::fabs(n[0]) < 0.9 ? D3{1, 0, 0} : D3{0, 1, 0};
  D3 u = cross(n, u0);
  const double ul = std::sqrt(dot(u, u));
  for (double& x : u) x /= ul;
  const D3 v = cross(n, u);
  const double big = 1 << 20;
  D3 c;
  for (int i = 0; i < 3; ++i) c[std::size_t(i)] = n[std::size_t(i)] * double(planes[k].dist);
  std::vector<D3> w;
  for (const auto& [a, b] : {std::pair{-1, -1}, std::pair{1, -1}, std::pair{1, 1}, std::pair{-1, 1}})
    w.push_back({c[0] + big * (a * u[0] + b * v[0]), c[1] + big * (a * u[1] + b * v[1]),
                 c[2] + big * (a * u[2] + b * v[2])});
  for (std::uint32_t j = 0; j < planes.size() && !w.empty(); ++j) {
    if (j == k) continue;
    const D3 pn = d3(planes[j].normal);
    const double pd = planes[j].dist;
    std::vector<D3> out;
    for (std::size_t i = 0; i < w.size(); ++i) {
      const D3& p1 = w[i];
      const D3& p2 = w[(i + 1) % w.size()];
      const double d1 = dot(pn, p1) - pd, d2 = dot(pn, p2) - pd;
      if (d1 <= 0) out.push_back(p1);
      if ((d1 < 0 && d2 > 0) || (d1 > 0 && d2 < 0)) {
        const double t = d1 / (d1 - d2);
        out.push_back(
            {p1[0] + t * (p2[0] - p1[0]), p1[1] + t * (p2[1] - p1[1]), p1[2] + t * (p2[2] - p1[2])});
      }
    }
    w = std::move(out);
  }
  return w;
}

WorldFacts::WorldFacts(const CollisionModel& world, std::uint32_t mask) : world_(world) {
  cover_.resize(world.brushPlanes().size());
  for (const CmBrush& brush : world.brushes()) {
    bool all = true;
    for (std::uint32_t k = 0; k < brush.numPlanes; ++k) {
      const Cover has = cover(brush, k, mask);
      cover_[brush.firstPlane + k] = has;
      all &= has == Cover::Whole;
    }
    numClosed_ += all;
  }
}

bool WorldFacts::inPolygon(const CmPolygon& poly, const D3& p) const {
  const D3 n = d3(poly.plane.normal);
  int pos = 0, neg = 0;
  for (const std::int32_t e : world_.edgesOf(poly)) {
    const D3 a = d3(world_.vertices()[std::size_t(world_.edgeStart(e))]);
    const D3 b = d3(world_.vertices()[std::size_t(world_.edgeStart(-e))]);
    D3 edge{b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    D3 side = cross(n, edge);
    const double len = std::sqrt(dot(side, side));
    if (len == 0) continue;
    const double s = dot(side, D3{p[0] - a[0], p[1] - a[1], p[2] - a[2]}) / len;
    pos += s > kSamePlaneDist;
    neg += s < -kSamePlaneDist;
  }
  return pos == 0 || neg == 0;
}

WorldFacts::Cover WorldFacts::cover(const CmBrush& brush, std::uint32_t k, std::uint32_t mask) const {
  const Plane& plane = world_.brushPlanes()[brush.firstPlane + k];
  std::vector<const CmPolygon*> candidates;
  for (const CmPolygon& p : world_.polygons()) {
    if (!(p.contents & mask) || p.plane.normal.dot(plane.normal) < kSameNormalDot ||
        std::fabs(p.plane.dist - plane.dist) >= kSamePlaneDist ||
        !p.bounds.intersects(brush.bounds.expanded(kSamePlaneDist)))
      continue;
    candidates.push_back(&p);
  }
  const std::vector<D3> outline = faceOutline(world_, brush, k);
  if (outline.size() < 3) return Cover::Whole;  // no face: nothing to cross
  if (candidates.empty()) return Cover::None;
  // Samples: a grid over the outline's box in the face plane, kept inside
  // the outline by the margin.
  const D3 n = d3(plane.normal);
  const D3 u0 = std::fabs(n[0]) < 0.9 ? D3{1, 0, 0} : D3{0, 1, 0};
  D3 u = cross(n, u0);
  const double ul = std::sqrt(dot(u, u));
  for (double& x : u) x /= ul;
  const D3 v = cross(n, u);
  double umin = 1e300, umax = -1e300, vmin = 1e300, vmax = -1e300;
  for (const D3& p : outline) {
    umin = std::min(umin, dot(p, u));
    umax = std::max(umax, dot(p, u));
    vmin = std::min(vmin, dot(p, v));
    vmax = std::max(vmax, dot(p, v));
  }
  const double nd = double(plane.dist);
  auto insideOutline = [&](const D3& p) {
    for (std::size_t i = 0; i < outline.size(); ++i) {
      const D3& a = outline[i];
      const D3& b = outline[(i + 1) % outline.size()];
      D3 side = cross(n, D3{b[0] - a[0], b[1] - a[1], b[2] - a[2]});
      const double len = std::sqrt(dot(side, side));
      if (len == 0) continue;
      if (dot(side, D3{p[0] - a[0], p[1] - a[1], p[2] - a[2]}) / len < kFaceSampleMargin) return false;
    }
    return true;
  };
  const double du = std::max(kFaceSampleStep, (umax - umin) / kFaceSamples);
  const double dv = std::max(kFaceSampleStep, (vmax - vmin) / kFaceSamples);
  bool anyIn = false, anyOut = false;
  for (double a = umin + du / 2; a < umax; a += du) {
    for (double b = vmin + dv / 2; b < vmax; b += dv) {
      const D3 p{n[0] * nd + a * u[0] + b * v[0], n[1] * nd + a * u[1] + b * v[1],
                 n[2] * nd + a * u[2] + b * v[2]};
      if (!insideOutline(p)) continue;
      bool in = false;
      for (const CmPolygon* poly : candidates) in = in || inPolygon(*poly, p);
      (in ? anyIn : anyOut) = true;
      if (anyIn && anyOut) return Cover::Part;
    }
  }
  return anyOut ? Cover::None : Cover::Whole;
}

/// The trace model's vertices placed at `pos` (one vertex for a point).
std::vector<Vec3> placedVertices(const Shape& shape, const Vec3& pos) {
  std::vector<Vec3> out;
  if (shape.trm.isPoint()) return {pos};
  for (const Vec3& v : shape.trm.vertices()) out.push_back(v * shape.axis + pos);
  return out;
}

/// How deep the trace model `shape` at `pos` overlaps a brush: the smallest
/// overlap over every separating axis of two convex bodies (the brush's
/// plane normals, the trace model's polygon normals, and the cross
/// products of their edges); <= 0 when they are apart. (brushDepth alone
/// uses the brush planes only and calls some separated pairs overlapping.)
double overlapDepth(const CollisionModel& world, const CmBrush& brush, const Shape& shape, const Vec3& pos) {
  const std::vector<Vec3> placed = placedVertices(shape, pos);
  double depth = brushDepth(world, brush, placed);
  if (shape.trm.isPoint() || depth <= 0) return depth;
  std::vector<D3> trmVerts;
  for (const Vec3& v : placed) trmVerts.push_back(d3(v));
  std::vector<D3> brushVerts, brushEdges;
  for (std::uint32_t k = 0; k < brush.numPlanes; ++k) {
    const std::vector<D3> outline = faceOutline(world, brush, k);
    for (std::size_t i = 0; i < outline.size(); ++i) {
      const D3& a = outline[i];
      const D3& b = outline[(i + 1) % outline.size()];
      brushVerts.push_back(a);
      brushEdges.push_back({b[0] - a[0], b[1] - a[1], b[2] - a[2]});
    }
  }
  if (brushVerts.empty()) return depth;
  auto overlapAlong = [&](D3 axis) {
    const double len = std::sqrt(dot(axis, axis));
    if (len < 1e-9) return std::numeric_limits<double>::max();
    for (double& x : axis) x /= len;
    double tMin = 1e300, tMax = -1e300, bMin = 1e300, bMax = -1e300;
    for (const D3& v : trmVerts) tMin = std::min(tMin, dot(axis, v)), tMax = std::max(tMax, dot(axis, v));
    for (const D3& v : brushVerts) bMin = std::min(bMin, dot(axis, v)), bMax = std::max(bMax, dot(axis, v));
    return std::min(tMax - bMin, bMax - tMin);
  };
  const TraceModel& t = shape.trm;
  // (The trace model's normals and edges turned by its orientation, as its vertices.)
  for (int i = 0; i < t.numPolygons(); ++i)
    depth = std::min(depth, overlapAlong(d3(t.polygon(i).normal * shape.axis)));
  for (int e = 1; e <= t.numEdges(); ++e) {
    const Vec3 a = (t.vertex(t.edge(e).v[1]) - t.vertex(t.edge(e).v[0])) * shape.axis;
    for (const D3& b : brushEdges) depth = std::min(depth, overlapAlong(cross(d3(a), b)));
  }
  return depth;
}

}  // namespace cmkit::cli::soak_geometry
