// soak_geometry.h: the geometry `cmkit soak` judges an embedded end by
// (soak.cpp): which brush faces the world's polygons cover (WorldFacts,
// computed once per world) and how deep a trace model overlaps a brush (by
// every separating axis, in double). Plain functions of the model; no query.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "cmkit/model.h"
#include "soak.h"

namespace cmkit::cli::soak_geometry {

/// Double vectors for the face and overlap geometry.
using D3 = std::array<double, 3>;
inline double dot(const D3& a, const D3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline D3 cross(const D3& a, const D3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline D3 d3(const Vec3& v) { return {v.x, v.y, v.z}; }

/// The outline of face k of the brush: its plane clipped by the others.
std::vector<D3> faceOutline(const CollisionModel& world, const CmBrush& brush, std::uint32_t k);

/// Which brush faces are covered by collision polygons, computed once. A
/// face is covered when every sample point of it (a grid over the face,
/// at most kFaceSamples along each side, spacing at least kFaceSampleStep,
/// kept kFaceSampleMargin inside the face's outline) lies in a polygon of
/// the mask in the face's plane (normal dot > 0.9999, |dist difference| <
/// 0.01). A face only partly covered (the compiler drops the parts of faces
/// that other brushes cover) lets a move into the brush through the gap.
/// A bare face has no polygon at any sample point: nothing there can stop
/// a move (a side whose material has no contents, such as a visportal's,
/// makes no polygon, while the brush's other sides make it solid).
class WorldFacts {
 public:
  /// Samples every face of every brush (polygons of `mask` cover faces).
  WorldFacts(const CollisionModel& world, std::uint32_t mask);
  bool faceCovered(const CmBrush& brush, std::uint32_t k) const {
    return cover_[brush.firstPlane + k] == Cover::Whole;
  }
  bool faceBare(const CmBrush& brush, std::uint32_t k) const {
    return cover_[brush.firstPlane + k] == Cover::None;
  }
  /// Brushes every face of which is covered.
  std::size_t numClosed() const { return numClosed_; }

 private:
  /// True when p (in the polygon's plane) is inside the polygon, within kSamePlaneDist.
  bool inPolygon(const CmPolygon& poly, const D3& p) const;
  /// How much of a face its plane's polygons cover, by the samples.
  enum class Cover : std::uint8_t { None, Part, Whole };
  Cover cover(const CmBrush& brush, std::uint32_t k, std::uint32_t mask) const;

  const CollisionModel& world_;
  std::vector<Cover> cover_;
  std::size_t numClosed_ = 0;
};

/// The trace model's vertices placed at `pos` (one vertex for a point).
std::vector<Vec3> placedVertices(const Shape& shape, const Vec3& pos);

/// How deep the trace model `shape` at `pos` overlaps a brush: the smallest
/// overlap over every separating axis of two convex bodies (the brush's
/// plane normals, the trace model's polygon normals, and the cross
/// products of their edges); <= 0 when they are apart. (brushDepth alone
/// uses the brush planes only and calls some separated pairs overlapping.)
double overlapDepth(const CollisionModel& world, const CmBrush& brush, const Shape& shape, const Vec3& pos);

}  // namespace cmkit::cli::soak_geometry
