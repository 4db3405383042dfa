// reference.cpp: exact times of impact by brute force in double precision.
//
// Rays: the segment against every triangle (closed: edges and end points
// count). Shapes: a convex polytope moving linearly against each triangle,
// by the separating axis theorem over time. On an axis n the projections
// overlap while  pmin + t v <= tmax  and  pmax + t v >= tmin  (p: the
// polytope's vertices at the start, t: the triangle's, v = n . move), an
// interval of t; the shape touches the triangle for the t in the
// intersection of every axis's interval. The axes: the polytope's face
// normals, the triangle's normal and the cross products of the polytope's
// edge directions with the triangle's edges (enough for two convex
// polyhedra, a triangle being a flat one). The first contact is the latest
// entry, if it is no later than the earliest exit; the axis of that entry is
// the contact's normal. Triangles whose bounds miss the swept shape's bounds
// are skipped. cmkit's answers are modelled by the same test with every
// axis's interval widened by a margin (reference.h, RefAnswer).
#include "reference.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <thread>

namespace peers {

namespace {

/// Padding of the culling bounds for the widened tests: beyond the largest
/// margin (0.25 x sqrt(2) for a box), for the sharp corners of the widened
/// shapes.
constexpr double kCullPad = 2;
/// Cross products of nearly parallel edges are no axes (their interval is
/// that of other axes).
constexpr double kParallel = 1e-12;

struct D3 {
  double x, y, z;
};
D3 operator-(const D3& a, const D3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
double dot(const D3& a, const D3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 cross(const D3& a, const D3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

/// The moving polytope: vertices turned (offsets from the moving origin),
/// face normals and edge directions (parallel ones once).
struct Polytope {
  std::vector<D3> vertices, faces, edges;
  D3 lo{0, 0, 0}, hi{0, 0, 0};
};

void addDirection(std::vector<D3>& list, const D3& d) {
  const double dd = dot(d, d);
  if (dd == 0) return;
  for (const D3& e : list) {
    const D3 c = cross(e, d);
    if (dot(c, c) <= kParallel * dd * dot(e, e)) return;
  }
  list.push_back(d);
}

Polytope polytope(const ShapeSpec& s) {
  Polytope p;
  const double* a = nullptr;
  double axis[9];
  for (int i = 0; i < 9; ++i) axis[i] = s.axis[i];
  a = axis;
  for (std::size_t i = 0; i + 2 < s.hull.size(); i += 3) {
    const double x = s.hull[i], y = s.hull[i + 1], z = s.hull[i + 2];
    p.vertices.push_back(
        {x * a[0] + y * a[3] + z * a[6], x * a[1] + y * a[4] + z * a[7], x * a[2] + y * a[5] + z * a[8]});
  }
  p.lo = p.hi = p.vertices.front();
  for (const D3& v : p.vertices) {
    p.lo = {std::min(p.lo.x, v.x), std::min(p.lo.y, v.y), std::min(p.lo.z, v.z)};
    p.hi = {std::max(p.hi.x, v.x), std::max(p.hi.y, v.y), std::max(p.hi.z, v.z)};
  }
  // Faces and edges of the hull: every pair of vertices is a candidate edge
  // direction and every triple a candidate face normal whose plane has all
  // vertices on one side (the hull is small: at most a few hundred triples).
  const std::size_t n = p.vertices.size();
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j)
      for (std::size_t k = j + 1; k < n; ++k) {
        const D3 nrm = cross(p.vertices[j] - p.vertices[i], p.vertices[k] - p.vertices[i]);
        const double len = std::sqrt(dot(nrm, nrm));
        if (len < 1e-9) continue;
        int above = 0, below = 0;
        for (const D3& v : p.vertices) {
          const double d = dot(nrm, v - p.vertices[i]) / len;
          above += d > 1e-6;
          below += d < -1e-6;
        }
        if (above == 0 || below == 0) {
          addDirection(p.faces, nrm);
          // The face's edges: pairs of its vertices on the hull's boundary
          // are found as edges of some face; take every pair on this plane.
          std::vector<std::size_t> on;
          for (std::size_t m = 0; m < n; ++m)
            if (std::abs(dot(nrm, p.vertices[m] - p.vertices[i]) / len) <= 1e-6) on.push_back(m);
          for (std::size_t u = 0; u < on.size(); ++u)
            for (std::size_t w = u + 1; w < on.size(); ++w)
              addDirection(p.edges, p.vertices[on[w]] - p.vertices[on[u]]);
        }
      }
  return p;
}

/// Over-complete edge directions (diagonals of faces) only add axes that
/// never separate more than the true ones; they cost time, not exactness.

struct Contact {
  bool overlapAtStart = false;
  bool touches = false;
  double t = 0;  // in units of the move (1 = its end)
  double cosine = 1;
};

/// The polytope moving by `move` from `start` against triangle (a, b, c), for
/// t in [0, 1], each axis's overlap widened by faceMargin (face normals) or
/// edgeMargin (edge pairs).
Contact sweepTriangle(const Polytope& p, const D3& start, const D3& move, const D3 (&tri)[3],
                      double faceMargin, double edgeMargin) {
  Contact c;
  double enter = -std::numeric_limits<double>::infinity(), exit = std::numeric_limits<double>::infinity();
  D3 enterAxis{0, 0, 1};
  const D3 te[3] = {tri[1] - tri[0], tri[2] - tri[1], tri[0] - tri[2]};
  double margin = faceMargin;
  auto axis = [&](D3 n) {
    const double len = std::sqrt(dot(n, n));
    n = {n.x / len, n.y / len, n.z / len};
    double pmin = 1e300, pmax = -1e300;
    for (const D3& v : p.vertices) {
      const double d = dot(n, v);
      pmin = std::min(pmin, d);
      pmax = std::max(pmax, d);
    }
    const double s = dot(n, start);
    pmin += s;
    pmax += s;
    const double t0 = dot(n, tri[0]), t1 = dot(n, tri[1]), t2 = dot(n, tri[2]);
    const double tmin = std::min({t0, t1, t2}) - margin, tmax = std::max({t0, t1, t2}) + margin;
    const double v = dot(n, move);
    if (v == 0) {
      if (pmin > tmax || pmax < tmin) exit = -1;  // separated for ever
      return;
    }
    double in = (tmin - pmax) / v, out = (tmax - pmin) / v;
    if (v < 0) std::swap(in, out);
    if (in > enter) {
      enter = in;
      enterAxis = n;
    }
    exit = std::min(exit, out);
  };
  auto separated = [&] { return enter > exit || exit < 0 || enter > 1; };
  axis(cross(te[0], te[1]));
  if (separated()) return c;
  for (const D3& f : p.faces) {
    axis(f);
    if (separated()) return c;
  }
  margin = edgeMargin;
  for (const D3& e : p.edges)
    for (const D3& t : te) {
      const D3 n = cross(e, t);
      if (dot(n, n) <= kParallel * dot(e, e) * dot(t, t)) continue;
      axis(n);
      if (separated()) return c;
    }
  c.touches = true;
  c.overlapAtStart = enter <= 0;
  c.t = std::max(enter, 0.0);
  const double ml = std::sqrt(dot(move, move)), nl = std::sqrt(dot(enterAxis, enterAxis));
  c.cosine = std::abs(dot(enterAxis, move)) / (ml * nl);
  return c;
}

/// The segment start -> start + move against a triangle: the fraction, or -1.
double segmentTriangle(const D3& start, const D3& move, const D3 (&tri)[3]) {
  const D3 e1 = tri[1] - tri[0], e2 = tri[2] - tri[0];
  const D3 pv = cross(move, e2);
  const double det = dot(e1, pv);
  if (det == 0) return -1;  // parallel (a segment in the plane: measure zero)
  const D3 tv = start - tri[0];
  const double u = dot(tv, pv) / det;
  if (u < 0 || u > 1) return -1;
  const D3 qv = cross(tv, e1);
  const double w = dot(move, qv) / det;
  if (w < 0 || u + w > 1) return -1;
  const double t = dot(e2, qv) / det;
  return t >= 0 && t <= 1 ? t : -1;
}

RefAnswer answer(const RefScene& scene, const Polytope* p, double edgeNormalMax, const Query& q) {
  RefAnswer r;
  const D3 start{q.start[0], q.start[1], q.start[2]};
  const D3 move = D3{q.end[0], q.end[1], q.end[2]} - start;
  const double length = std::sqrt(dot(move, move));
  if (length == 0) return r;
  const double pad = (p ? kCullPad : 0) + 1e-3;
  const D3 lo = p ? p->lo : D3{0, 0, 0}, hi = p ? p->hi : D3{0, 0, 0};
  const float bx0 = float(std::min(start.x, start.x + move.x) + lo.x - pad);
  const float by0 = float(std::min(start.y, start.y + move.y) + lo.y - pad);
  const float bz0 = float(std::min(start.z, start.z + move.z) + lo.z - pad);
  const float bx1 = float(std::max(start.x, start.x + move.x) + hi.x + pad);
  const float by1 = float(std::max(start.y, start.y + move.y) + hi.y + pad);
  const float bz1 = float(std::max(start.z, start.z + move.z) + hi.z + pad);
  double best = 2, late = 2, early = 2;
  const std::size_t n = scene.minX.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (scene.minX[i] > bx1 || scene.maxX[i] < bx0 || scene.minY[i] > by1 || scene.maxY[i] < by0 ||
        scene.minZ[i] > bz1 || scene.maxZ[i] < bz0)
      continue;
    const double* v = &scene.v[9 * i];
    const D3 tri[3] = {{v[0], v[1], v[2]}, {v[3], v[4], v[5]}, {v[6], v[7], v[8]}};
    if (!p) {
      const double t = segmentTriangle(start, move, tri);
      if (t >= 0) best = std::min(best, t);
      continue;
    }
    const Contact c = sweepTriangle(*p, start, move, tri, 0, 0);
    if (c.touches) {
      r.startOverlap |= c.overlapAtStart;
      best = std::min(best, c.t);
    }
    const Contact e = sweepTriangle(*p, start, move, tri, kClipEpsilon, kClipEpsilon * edgeNormalMax);
    if (!e.touches) continue;  // the widest: nothing narrower touches
    early = std::min(early, e.t);
    const Contact l = sweepTriangle(*p, start, move, tri, kClipEpsilon, kClipEpsilon);
    if (l.touches) late = std::min(late, l.t);
  }
  r.hit = best <= 1;
  r.dist = r.hit ? best * length : 0;
  if (!p) {
    r.cmkitMustHit = r.cmkitMayHit = r.hit;
    r.cmkitLatest = r.cmkitEarliest = r.dist;
  } else {
    r.cmkitMustHit = late <= 1;
    r.cmkitMayHit = early <= 1;
    r.cmkitLatest = r.cmkitMustHit ? late * length : length;
    r.cmkitEarliest = r.cmkitMayHit ? early * length : length;
  }
  return r;
}

}  // namespace

RefScene::RefScene(const Scene& scene) {
  const std::size_t n = scene.numTriangles();
  v.resize(9 * n);
  for (auto* a : {&minX, &minY, &minZ, &maxX, &maxY, &maxZ}) a->resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) {
        const float x = scene.positions[3 * scene.indices[3 * i + std::size_t(k)] + std::size_t(c)];
        v[9 * i + std::size_t(3 * k + c)] = x;
        lo[c] = std::min(lo[c], x);
        hi[c] = std::max(hi[c], x);
      }
    minX[i] = lo[0], minY[i] = lo[1], minZ[i] = lo[2], maxX[i] = hi[0], maxY[i] = hi[1], maxZ[i] = hi[2];
  }
}

std::vector<RefAnswer> exactReference(const RefScene& scene, const ShapeSpec& shape,
                                      std::span<const Query> queries, int threads) {
  std::vector<RefAnswer> out(queries.size());
  Polytope p;
  if (!shape.point) p = polytope(shape);
  const Polytope* pp = shape.point ? nullptr : &p;
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t)
    pool.emplace_back([&, t] {
      for (std::size_t i = std::size_t(t); i < queries.size(); i += std::size_t(threads))
        out[i] = answer(scene, pp, shape.edgeNormalMax, queries[i]);
    });
  for (std::thread& th : pool) th.join();
  return out;
}

}  // namespace peers
