// Convex hull of a small point set, as faces with ordered vertex loops.
//
// Trace models have at most 32 vertices, so a simple exhaustive method is
// both fast enough and easy to trust: every plane through three input points
// that has all points on one side is a face plane; a face's vertices are the
// hull vertices on that plane, sorted by angle around the face centre. A hull
// vertex is a point on at least three face planes (points inside a face or on
// the middle of an edge are dropped). Arithmetic is in double.
#include <algorithm>
#include <cmath>
#include <vector>

#include "geometry/trace_model_builder.h"
#include "math/dvec3.h"

namespace cmkit {
namespace {

using detail::DVec3;

struct FacePlane {
  DVec3 n;
  double d;
};

/// Relative tolerance of the hull: points within this fraction of the point
/// set's size of a plane are on it. Float input has ~1e-7 relative noise.
constexpr double kHullRelativeEpsilon = 1e-5;

}  // namespace

Result<std::vector<std::vector<int>>> detail::TraceModelBuilder::hullFaces(std::span<const Vec3> points) {
  const size_t n = points.size();
  std::vector<DVec3> p(n);
  double scale = 0;
  for (size_t i = 0; i < n; ++i) {
    if (!points[i].isFinite())
      return Error{"degenerate trm (hull point " + std::to_string(i) + " is not finite)"};
    p[i] = {points[i].x, points[i].y, points[i].z};
    scale = std::max({scale, std::fabs(p[i].x), std::fabs(p[i].y), std::fabs(p[i].z)});
  }
  if (n < 4) return Error{"degenerate trm (a convex hull needs at least 4 points)"};
  const double eps = kHullRelativeEpsilon * std::max(scale, 1.0);

  // Exact duplicates are the same point: keep the first.
  std::vector<bool> duplicate(n, false);
  for (size_t i = 0; i < n; ++i)
    for (size_t j = 0; j < i && !duplicate[i]; ++j)
      if ((p[i] - p[j]).length() <= eps) duplicate[i] = true;

  std::vector<FacePlane> planes;
  for (size_t i = 0; i < n; ++i) {
    if (duplicate[i]) continue;
    for (size_t j = i + 1; j < n; ++j) {
      if (duplicate[j]) continue;
      for (size_t k = j + 1; k < n; ++k) {
        if (duplicate[k]) continue;
        DVec3 nrm = (p[j] - p[i]).cross(p[k] - p[i]);
        const double len = nrm.length();
        if (len <= eps * std::max(scale, 1.0)) continue;  // collinear
        nrm = nrm * (1.0 / len);
        const double d = nrm.dot(p[i]);
        bool front = false, back = false;
        for (size_t m = 0; m < n && !(front && back); ++m) {
          const double dist = nrm.dot(p[m]) - d;
          if (dist > eps) front = true;
          if (dist < -eps) back = true;
        }
        if (front && back) continue;
        if (!front && !back) continue;  // all coplanar so far; decided below
        FacePlane f = back ? FacePlane{nrm, d} : FacePlane{nrm * -1.0, -d};
        bool known = false;
        for (const FacePlane& g : planes) {
          if ((g.n - f.n).length() < 1e-9 + eps / std::max(scale, 1.0) && std::fabs(g.d - f.d) <= eps) {
            known = true;
            break;
          }
        }
        if (!known) planes.push_back(f);
      }
    }
  }
  if (planes.size() < 4) {
    return Error{"degenerate trm (the points are coplanar or collinear: no volume)"};
  }

  // Hull vertices: on at least three face planes.
  std::vector<int> incidence(n, 0);
  for (const FacePlane& f : planes)
    for (size_t m = 0; m < n; ++m)
      if (!duplicate[m] && std::fabs(f.n.dot(p[m]) - f.d) <= eps) ++incidence[m];

  std::vector<std::vector<int>> loops;
  for (const FacePlane& f : planes) {
    std::vector<int> verts;
    DVec3 centre{0, 0, 0};
    for (size_t m = 0; m < n; ++m) {
      if (!duplicate[m] && incidence[m] >= 3 && std::fabs(f.n.dot(p[m]) - f.d) <= eps) {
        verts.push_back(int(m));
        centre = centre + p[m];
      }
    }
    if (verts.size() < 3) continue;
    centre = centre * (1.0 / double(verts.size()));
    // Sort counter-clockwise around the outward normal, starting from the
    // lowest-numbered vertex so that the result does not depend on angles.
    const DVec3 u = (p[size_t(verts[0])] - centre) * (1.0 / (p[size_t(verts[0])] - centre).length());
    const DVec3 v = f.n.cross(u);
    auto angle = [&](int m) {
      const DVec3 r = p[size_t(m)] - centre;
      double a = std::atan2(r.dot(v), r.dot(u));
      return a < 0 ? a + 2 * M_PI : a;
    };
    std::sort(verts.begin() + 1, verts.end(), [&](int a, int b) { return angle(a) < angle(b); });
    loops.push_back(std::move(verts));
  }
  // Stable face order: by the lowest vertex of each loop, then the next.
  std::sort(loops.begin(), loops.end());
  return loops;
}

}  // namespace cmkit
