// reference.h: the exact answers every engine is compared with, by brute
// force in double precision (slow: run once per scene and kind, not timed).
#pragma once

#include <span>
#include <vector>

#include "peers.h"

namespace peers {

/// cmkit's clip epsilon: a translation stops this far in front of a surface,
/// measured along the surface's normal (tol::kClipEpsilon).
inline constexpr double kClipEpsilon = 0.25;

/// The exact answer for one query.
struct RefAnswer {
  /// The shape overlaps (or touches) a triangle at the start: such queries
  /// are left out of the agreement (each engine answers them its own way).
  bool startOverlap = false;
  /// The shape (or the point) touches a triangle during the move, first at
  /// `dist` units along it.
  bool hit = false;
  double dist = 0;
  /// What cmkit's translate() may answer. cmkit stops kClipEpsilon in front
  /// of surfaces: a trace-model vertex stops that far from a polygon's plane
  /// along its normal, a model vertex that far from a trace-model face, and
  /// an edge pair when the trace-model edge, shifted by kClipEpsilon times
  /// the edge's normal (the bisector of its faces, scaled to a component of 1
  /// along each), meets the polygon edge. That is the exact contact of the
  /// shapes with every separating plane pushed out by a margin: kClipEpsilon
  /// on face normals, between kClipEpsilon and kClipEpsilon x the longest
  /// edge normal (ShapeSpec::edgeNormalMax) on edge-pair planes, depending
  /// on the edge pair. So cmkit's answer is bracketed by two contacts: with
  /// kClipEpsilon on every plane (`late`: cmkit must hit if it does, and stop
  /// no later) and with the larger margin on edge planes (`early`: cmkit may
  /// hit only if it does, and stops no earlier). Stops at 0 at the least.
  bool cmkitMustHit = false;
  bool cmkitMayHit = false;
  double cmkitLatest = 0;    // the stop of the `late` contact, or the move's length
  double cmkitEarliest = 0;  // the stop of the `early` contact
};

/// The scene's triangles in double, with their bounds for culling.
struct RefScene {
  explicit RefScene(const Scene& scene);
  std::vector<double> v;                                  // 9 per triangle: a, b, c
  std::vector<float> minX, minY, minZ, maxX, maxY, maxZ;  // per triangle
};

/// The exact answers of every query for one shape, on `threads` threads.
std::vector<RefAnswer> exactReference(const RefScene& scene, const ShapeSpec& shape,
                                      std::span<const Query> queries, int threads);

}  // namespace peers
