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
  /// What cmkit's translate() should answer by the clip-epsilon model: it
  /// stops kClipEpsilon in front of each surface along the surface's normal,
  /// i.e. at d - kClipEpsilon / |cos(move, normal)| for a contact at d (at
  /// 0 at the least), and a move that ends within the epsilon of a surface
  /// stops too. The minimum over every triangle the extended move reaches.
  bool cmkitHit = false;
  double cmkitDist = 0;
};

/// The scene's triangles in double, with their bounds for culling.
struct RefScene {
  explicit RefScene(const Scene& scene);
  std::vector<double> v;                      // 9 per triangle: a, b, c
  std::vector<float> minX, minY, minZ, maxX, maxY, maxZ;  // per triangle
};

/// The exact answers of every query for one shape, on `threads` threads.
std::vector<RefAnswer> exactReference(const RefScene& scene, const ShapeSpec& shape,
                                      std::span<const Query> queries, int threads);

}  // namespace peers
