// Internal: the per-feature data of one rotation part (below 180 degrees),
// shared by the set-up (rotate_setup.cpp) and the tests (rotate.cpp).
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

#include "query/trace_work.h"

namespace cmkit::detail {

/// Rotation data of a trace-model vertex.
struct RotVertex {
  Vec3 rotationOrigin;  ///< the axis point in the plane of the vertex's circle
  Bounds bounds;        ///< box around the vertex's arc, padded by tol::kBoxEpsilon
  bool used = false;    ///< farther than tol::kRotationAxisEpsilon from the axis
};

/// Rotation data of a trace-model edge.
struct RotEdge {
  Bounds bounds;  ///< union of its vertices' arc boxes
  bool used = false;
};

/// Rotation data of a trace-model polygon.
struct RotPolygon {
  Bounds bounds;  ///< union of its edges' arc boxes
};

/// One part of a rotation, in the model's frame.
struct RotationWork {
  Vec3 origin;        ///< a point of the axis (model frame)
  Vec3 axis;          ///< unit axis (model frame)
  Real sign = 1;      ///< +1 for a positive angle, -1 for a negative one
  double maxTan = 0;  ///< tangent of half the angle still free (lowered by every hit)
  /// The axis line passes through the (convex) trace model: the original's
  /// per-feature back-face culls apply.
  bool axisIntersectsTrm = false;
  Vec3 centre;  ///< trace-model centre at the start of the part
  /// Turns model points by minus the part's angle (v * backMatrix about
  /// origin): where a model vertex ends relative to the trace model.
  Mat3 backMatrix;
  std::array<RotVertex, kMaxTrmVertices> vertices{};
  std::array<RotEdge, kMaxTrmEdges + 1> edges{};
  std::array<RotPolygon, kMaxTrmPolygons> polygons{};
};

/// v2 cos t + v1 sin t + v0, t >= 0 in the direction of the rotation.
struct Sinusoid {
  double v0 = 0, v1 = 0, v2 = 0;
};

/// The smallest root u of a u^2 + 2 b u + c = 0 with lo <= u < hi, in
/// `root`. False when there is none. Numerically careful (no cancellation,
/// no division by zero): never produces NaN or Inf. A double root (the
/// curve only touches zero) is no crossing.
bool firstQuadraticRoot(double a, double b, double c, double lo, double hi, double& root);

/// p turned about the line (origin, unit axis) by the angle whose half has
/// the tangent `tanHalf` (signed: positive = the positive-angle direction).
Vec3 rotateByTanHalf(const Vec3& p, const Vec3& origin, const Vec3& axis, double tanHalf);

/// Box of the arc of `p` turned to `end` about the line through
/// `rotationOrigin` (p's own circle centre) along `axis`, for an arc below
/// 180 degrees; not padded.
Bounds arcBounds(const Vec3& rotationOrigin, const Vec3& axis, const Vec3& p, const Vec3& end);

}  // namespace cmkit::detail
