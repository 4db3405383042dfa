// Internal: tessellating Bézier patches for collision (the original's
// idSurface_Patch Subdivide / SubdivideExplicit as used by the collision
// model builder).
#pragma once

#include <vector>

#include "cmkit/map.h"

namespace cmkit {

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
/// The patch must have odd width and height >= 3 (the parser guarantees it).
PatchGrid subdividePatchForCollision(const MapPatch& patch);

}  // namespace cmkit
