// Internal: tessellating Bézier patches for collision (the original's
// idSurface_Patch Subdivide / SubdivideExplicit as used by the collision
// model builder).
#pragma once

#include <vector>

#include "cmkit/map.h"

namespace cmkit::detail {

/// A grid of points after subdivision: point (column j, row i) at
/// i * width + j, with the same meaning of width/height as MapPatch.
struct PatchGrid {
  int width = 0;
  int height = 0;
  std::vector<Vec3> points;
};

/// Subdivides a patch as the original does for collision: explicit
/// subdivisions for patchDef3, else max error tol::kCurveMaxErrorCollision
/// (no max length), then removal of nearly straight rows/columns.
/// The patch must have odd width and height >= 3 (the parser guarantees it);
/// anything else, or an explicit grid over tol::kMaxPatchGridPoints, gives
/// an empty grid.
PatchGrid subdividePatchForCollision(const MapPatch& patch);

/// One point of a 3x3 quadratic Bézier block (ctrl[column][row]) at
/// parameters (u along the columns, v along the rows), evaluated as the
/// original's patchDef3 sampling does: each coordinate of the three rows
/// along u first, then along v, with q(t) = (a - 2b + c)t^2 + (2b - 2a)t + a
/// in float, in that operation order.
Vec3 sampleBezierPatchPoint(const Vec3 (&ctrl)[3][3], Real u, Real v);

}  // namespace cmkit::detail
