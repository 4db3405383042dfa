// Internal: the per-feature data of one rotation part (below 180 degrees),
// shared by the set-up (rotate_setup.cpp) and the tests (rotate.cpp,
// rotate_edges.cpp).
//
// Every exact test is an equation in u = tan(|t| / 2), where t is the angle
// turned so far in the direction of the rotation (u = 0 at the start of the
// part, u = maxTan at its end). A distance that depends on the angle is a
// sinusoid v2 cos t + v1 sin t + v0 (Sinusoid below, with v1 already
// multiplied by the sign of the rotation so that t >= 0 moves forward);
// substituting cos t = (1 - u^2)/(1 + u^2), sin t = 2u/(1 + u^2) gives the
// quadratic (v0 - v2) u^2 + 2 v1 u + (v0 + v2) = 0.
#pragma once

#include <array>
#include <vector>

#include "math/dvec3.h"
#include "query/trace_work.h"
#include "util/simd.h"

namespace cmkit::detail {

/// The rotation equations are solved in double (inputs are Real).
using DVec = DVec3;

/// Two vectors a and b, their components interleaved (a.x, b.x, a.y, b.y,
/// a.z, b.z): the operands of pairDotDifference.
struct alignas(16) VectorPair {
  double v[6];
  void set(const DVec& a, const DVec& b) {
    v[0] = a.x, v[1] = b.x, v[2] = a.y, v[3] = b.y, v[4] = a.z, v[5] = b.z;
  }
};

/// a . m - b . n for the pairs (a, b) and (m, n): the two dot products in
/// the two lanes of one register where there are double lanes, each lane
/// computing DVec3::dot's products and sums in its order, so the same bits
/// as a.dot(m) - b.dot(n).
inline double pairDotDifference(const VectorPair& ab, const VectorPair& mn) {
#ifdef CMKIT_SIMD_SSE2
  using simd::D2;
  const D2 d = D2::load(ab.v) * D2::load(mn.v) + D2::load(ab.v + 2) * D2::load(mn.v + 2) +
               D2::load(ab.v + 4) * D2::load(mn.v + 4);
  return d.low() - d.high();
#else
  const double* x = ab.v;
  const double* y = mn.v;
  return (x[0] * y[0] + x[2] * y[2] + x[4] * y[4]) - (x[1] * y[1] + x[3] * y[3] + x[5] * y[5]);
#endif
}

/// A trace-model edge s -> e turning about the axis (unit a through o), for
/// its line products with model edges (rotate_edges.h, ModelEdgeLine): the edge
/// vector u = e - s and q = (s - o) x u, each split as R(t) x = axial +
/// cos t across + sin t turned (axial = a (a . x), across = x - axial,
/// turned = x x a: the library's direction of positive angles); each part of
/// u beside the same part of q (VectorPair), for pairDotDifference.
struct EdgeTurn {
  VectorPair start;   ///< (u, q)
  VectorPair axial;   ///< (u's axial part, q's)
  VectorPair across;  ///< (u's across part, q's)
  VectorPair turned;  ///< (u's turned part, q's)
};

/// Rotation data of a trace-model vertex.
struct RotVertex {
  Vec3 rotationOrigin;  ///< the axis point in the plane of the vertex's circle
  bool used = false;    ///< farther than tol::kRotationAxisEpsilon from the axis
};

/// Boxes of up to 32 trace-model features, one array per bound coordinate:
/// the per-polygon culls test them all in one branch-free loop
/// (boxesCrossing, boxesTouching).
struct FeatureBoxes {
  // Zeroed once: the SIMD test reads whole groups of four, past the features in use.
  alignas(16) std::array<Real, 32> minX{}, minY{}, minZ{}, maxX{}, maxY{}, maxZ{};
  void set(std::size_t i, const Bounds& b) {
    minX[i] = b.min.x, minY[i] = b.min.y, minZ[i] = b.min.z;
    maxX[i] = b.max.x, maxY[i] = b.max.y, maxZ[i] = b.max.z;
  }
  Bounds get(std::size_t i) const { return {{minX[i], minY[i], minZ[i]}, {maxX[i], maxY[i], maxZ[i]}}; }
  /// Grows `b` by box i, a coordinate at a time from the arrays (the selects
  /// of Bounds::addBounds, with no Bounds made of box i).
  void uniteInto(Bounds& b, std::size_t i) const {
    b.min.x = minX[i] < b.min.x ? minX[i] : b.min.x;
    b.min.y = minY[i] < b.min.y ? minY[i] : b.min.y;
    b.min.z = minZ[i] < b.min.z ? minZ[i] : b.min.z;
    b.max.x = maxX[i] > b.max.x ? maxX[i] : b.max.x;
    b.max.y = maxY[i] > b.max.y ? maxY[i] : b.max.y;
    b.max.z = maxZ[i] > b.max.z ? maxZ[i] : b.max.z;
  }
};

/// The arcs of a part's trace-model vertices, one array per coordinate (for
/// vertexArcBoxes): vertex i turns from p to e about its circle centre r.
struct VertexArcs {
  alignas(16) std::array<Real, kMaxTrmVertices> px, py, pz, ex, ey, ez, rx, ry, rz;
  void set(std::size_t i, const Vec3& p, const Vec3& e, const Vec3& r) {
    px[i] = p.x, py[i] = p.y, pz[i] = p.z;
    ex[i] = e.x, ey[i] = e.y, ez[i] = e.z;
    rx[i] = r.x, ry[i] = r.y, rz[i] = r.z;
  }
};

/// The box of each arc 0..n-1 (arcBounds about `axis`, padded by
/// tol::kBoxEpsilon) into `boxes`; returns their union. (May overwrite arcs
/// past n, up to a multiple of four.)
Bounds vertexArcBoxes(VertexArcs& arcs, int n, const Vec3& axis, FeatureBoxes& boxes);

/// Bit i (i < n): box i touches `bounds` (Bounds::intersects) and straddles
/// `plane` (Bounds::planeSide(plane) == Side::Cross, the same arithmetic).
std::uint32_t boxesCrossing(const FeatureBoxes& boxes, int n, const Bounds& bounds, const Plane& plane);
/// Of the boxes whose bits are set in `candidates`, those touching `bounds`.
std::uint32_t boxesTouching(const FeatureBoxes& boxes, std::uint32_t candidates, const Bounds& bounds);

/// Rotation data of a trace-model edge.
struct RotEdge {
  EdgeTurn turn;  ///< RotationWork::edgeTurn
};

/// Rotation data of a trace-model polygon.
struct RotPolygon {
  Bounds bounds;  ///< union of its edges' boxes (RotationWork::polygonBounds)
};

/// True when the line origin + s * axis passes through the convex trace
/// model (the intersection of its polygons' back half-spaces).
bool axisThroughConvexTrm(const TraceWork& tw, const Vec3& origin, const Vec3& axis);

/// A contact found by rotational contacts(): a polygon's earliest contact
/// in one part (ContactInfo::angle set, model frame), with that polygon.
struct RotationContact {
  ContactInfo contact;
  std::int32_t polygon = 0;
};

/// Rotational contacts (rotate_setup.cpp): the rotation walked part by part
/// in contacts mode, every polygon's earliest contact of each part into the
/// scratch's RotationWork::found (model frame; cleared first), returned.
/// `modelRotated`: whether the model's frame is rotated (for
/// contactToWorld). The query has passed guardRotation.
std::vector<RotationContact>& collectRotationContacts(const CollisionModel& model, const RotationQuery& q,
                                                      QueryWork& work, bool& modelRotated);

/// One part of a rotation, in the model's frame.
struct RotationWork {
  Vec3 origin;        ///< a point of the axis (model frame)
  Vec3 axis;          ///< unit axis (model frame)
  Real sign = 1;      ///< +1 for a positive angle, -1 for a negative one
  double maxTan = 0;  ///< tangent of half the angle still free (lowered by every hit)
  /// Whether the axis line passes through the (convex) trace model, when the
  /// original's per-feature back-face culls apply: -1 not known yet (made
  /// when a polygon first needs it, axisIntersectsTrm), 0 no, 1 yes.
  int axisThroughTrm = -1;
  Vec3 centre;  ///< trace-model centre at the start of the part
  /// Turns model points by minus the part's angle (v * backMatrix about
  /// origin): where a model vertex ends relative to the trace model.
  Mat3 backMatrix;
  std::array<RotVertex, kMaxTrmVertices> vertices{};
  std::array<RotEdge, kMaxTrmEdges + 1> edges{};
  std::array<RotPolygon, kMaxTrmPolygons> polygons{};
  /// Box around each vertex's arc, padded by tol::kBoxEpsilon (index: vertex).
  FeatureBoxes vertexBoxes;
  /// Box around each edge's sweep: the union of its vertices' boxes (index:
  /// edge number - 1; made by makeEdgeBoxes when a polygon first needs them).
  FeatureBoxes edgeBoxes;
  bool edgeBoxesSet = false;
  std::uint32_t usedVertices = 0;  ///< bit i: vertices[i].used
  std::uint32_t usedEdges = 0;     ///< bit j - 1: edge j has a used vertex
  // The edge and polygon boxes are made when a polygon's culls first need
  // them: most rotations meet few polygons, and making every box up front
  // was a large part of a short rotation's cost.
  std::uint32_t polygonBoundsSet = 0;  ///< bit j: polygons[j].bounds is made
  std::uint64_t edgeTurnSet = 0;       ///< bit j: edges[j].turn is made

  /// Contacts mode (rotational contacts(), contacts.cpp): every polygon's
  /// earliest contact within the part is appended here, and maxTan goes
  /// back to the part's limit after each polygon; null for rotate().
  std::vector<RotationContact>* contactsFound = nullptr;
  Real partStartAngle = 0;  ///< contacts mode: degrees turned at the start of the part (signed)
  /// Contacts mode's lists, kept with the scratch so that their memory
  /// serves every query: the contacts found (collectRotationContacts), and
  /// the polygons already listed when contacts() picks the earliest of each.
  std::vector<RotationContact> found;
  std::vector<std::int32_t> listedPolygons;

  /// Trace-model edge j's turning parts (made on first use, by makeEdgeTurn:
  /// once per part, out of line, while this test runs for every edge pair).
  const EdgeTurn& edgeTurn(const TraceWork& tw, int j) {
    if (!(edgeTurnSet >> j & 1u)) makeEdgeTurn(tw, j);
    return edges[std::size_t(j)].turn;
  }
  /// Makes edges[j].turn (rotate_edges.cpp).
  void makeEdgeTurn(const TraceWork& tw, int j);

  bool edgeLinesSet = false;  ///< the trace-model edges' lines (WorkEdge::pl) are made

  /// Makes the trace-model edges' lines (once per part, for the first model
  /// vertex that reaches a trace-model polygon's plane in time).
  void makeEdgeLines(TraceWork& tw) {
    if (edgeLinesSet) return;
    edgeLinesSet = true;
    for (int j = 1; j <= tw.numEdges; ++j) {
      WorkEdge& e = tw.edges[std::size_t(j)];
      e.pl = Pluecker::fromLine(e.start, e.end);
    }
  }

  /// True when the axis line passes through the (convex) trace model: the
  /// original's per-feature back-face culls apply.
  bool axisIntersectsTrm(const TraceWork& tw) {
    if (axisThroughTrm < 0) axisThroughTrm = tw.isConvex && axisThroughConvexTrm(tw, origin, axis);
    return axisThroughTrm != 0;
  }

  /// Makes edgeBoxes (once per part).
  void makeEdgeBoxes(const TraceWork& tw) {
    if (edgeBoxesSet) return;
    edgeBoxesSet = true;
    for (int j = 1; j <= tw.numEdges; ++j) {
      const WorkEdge& e = tw.edges[std::size_t(j)];
      Bounds b = vertexBoxes.get(std::size_t(e.vertexNum[0]));
      vertexBoxes.uniteInto(b, std::size_t(e.vertexNum[1]));
      edgeBoxes.set(std::size_t(j - 1), b);
    }
  }
  /// Box around trace-model polygon j's sweep (the union of its edges' boxes;
  /// after makeEdgeBoxes).
  const Bounds& polygonBounds(const TraceWork& tw, int j) {
    RotPolygon& rp = polygons[std::size_t(j)];
    if (!(polygonBoundsSet >> j & 1u)) {
      polygonBoundsSet |= std::uint32_t(1) << j;
      const WorkPolygon& wp = tw.polys[std::size_t(j)];
      Bounds b;
      for (int k = 0; k < wp.source->numEdges; ++k)
        edgeBoxes.uniteInto(b, std::size_t(std::abs(wp.source->edges[std::size_t(k)]) - 1));
      rp.bounds = b;
    }
    return rp.bounds;
  }
};

/// v2 cos t + v1 sin t + v0, t >= 0 in the direction of the rotation.
struct Sinusoid {
  double v0 = 0, v1 = 0, v2 = 0;
};

/// The smallest root u of a u^2 + 2 b u + c = 0 with lo <= u < hi, in
/// `root`. False when there is none. Numerically careful (no cancellation,
/// no division by zero): never produces NaN or Inf. A double root (the
/// curve only touches zero) is no crossing. `later` (when given and a root
/// is found) gets the root after `root` when there is one below hi, else
/// NaN (left as it was when there is no root): the same value
/// calling again from lo = std::nextafter(root, +inf) would find (the same
/// roots, solved the same way), without solving again.
bool firstQuadraticRoot(double a, double b, double c, double lo, double hi, double& root,
                        double* later = nullptr);

/// p turned about the line (origin, unit axis) by the angle whose half has
/// the tangent `tanHalf` (signed: positive = the positive-angle direction).
Vec3 rotateByTanHalf(const Vec3& p, const Vec3& origin, const Vec3& axis, double tanHalf);

/// The positive root of -v1 u^2 - 2 v2 u + v1 = 0 for v1 > 0: where the
/// sinusoid v2 cos t + v1 sin t + v0 has its first extremum ahead (the two
/// roots multiply to -1, so exactly one is positive).
inline double firstExtremumTan(double v1, double v2) {
  const double k = v2 / v1;
  const double s = std::sqrt(k * k + 1);
  return k >= 0 ? 1 / (k + s) : s - k;  // the cancellation-free form of -k + s
}

/// First u in [lo, maxTan) where the sinusoid is zero (`later`: the next
/// one, as firstQuadraticRoot's).
inline bool sinusoidRoot(const Sinusoid& s, double lo, double maxTan, double& u, double* later = nullptr) {
  return firstQuadraticRoot(s.v0 - s.v2, s.v1, s.v0 + s.v2, lo, maxTan, u, later);
}

/// Records the contact a rotation test found on `poly` as the query's.
inline void setRotationContact(TraceWork& tw, const CmPolygon& poly, ContactType type, const Vec3& normal,
                               Real dist, const Vec3& point, std::int32_t modelFeature, int trmFeature) {
  ContactInfo& c = tw.c;
  c.type = type;
  c.normal = normal;
  c.dist = dist;
  c.point = point;
  c.contents = poly.contents;
  c.material = poly.material;
  c.modelFeature = modelFeature;
  c.trmFeature = trmFeature;
}

/// Box of the arc of `p` turned to `end` about the line through
/// `rotationOrigin` (p's own circle centre) along `axis`, for an arc below
/// 180 degrees; not padded.
Bounds arcBounds(const Vec3& rotationOrigin, const Vec3& axis, const Vec3& p, const Vec3& end);

}  // namespace cmkit::detail
