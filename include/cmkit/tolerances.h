// tolerances.h: every tolerance and limit of cmkit, in one place.
//
// Units are map units (1 unit = 1 inch in Doom 3) unless stated. Each constant
// says why it has its value. Values marked "original" are those of the Doom 3
// collision module; changing them changes results against the reference data.
#pragma once

#include "cmkit/config.h"

namespace cmkit::tol {

// ---- Queries ---------------------------------------------------------------

/// original: translations and rotations stop this far in front of a surface
/// (along its normal), so that the next move does not start touching it.
inline constexpr Real kClipEpsilon = 0.25f;
/// original: trace bounds, BSP walk extents and heart-plane distances are
/// padded by this much, so that float round-off never culls a real contact.
inline constexpr Real kBoxEpsilon = 1.0f;
/// original: rotations treat a feature as already inside the epsilon zone
/// when it is this close to it.
inline constexpr Real kPluckerRangeEpsilon = 1e-4f;
/// original: points this close to a rotation axis barely move and are ignored.
inline constexpr Real kRotationAxisEpsilon = 0.0625f;
/// original: chord length used to approximate rotation arcs in the tree walk.
inline constexpr Real kCircleApproximationLength = 64.0f;
/// original: default epsilon of the bounds/plane side test used to cull
/// polygons whose plane the trace bounds do not cross.
inline constexpr Real kOnEpsilon = 0.1f;
/// cmkit: a rotation walks the tree in pieces along its centre's arc, each
/// at least kCircleApproximationLength (and twice the trace model's reach)
/// long, but with no more than this many pieces per part below 180 degrees
/// (more pieces only make smaller boxes).
inline constexpr int kMaxRotationWalkPieces = 16;
/// cmkit: rotating edges whose directions differ by a sine below this at the
/// contact are parallel: their crossing equation is float noise, no contact.
inline constexpr Real kRotationParallelEdgeSine = 1e-5f;
/// cmkit: a rotation's contact normal opposes the motion of the contact
/// point along the arc; when the cosine of the two is within this, the
/// motion runs within the contact plane (a grazing contact: no side is
/// approached) and the normal's sign comes from the model instead (the model
/// edge's normal for edge contacts). Well above the float rounding of a unit
/// normal built from turned edges (about 1e-6).
inline constexpr Real kRotationContactTangentCosine = 1e-3f;

/// cmkit (RayIndex): a polygon accepts a ray crossing only within its bounds
/// padded by this fraction of its largest coordinate magnitude plus one
/// unit. The Plücker edge tests decide "inside"; this keeps a crossing that
/// rounding lets through (near an edge, or anywhere for a tiny polygon far
/// from the origin) near its polygon, so that the index's boxes provably
/// contain every crossing a polygon accepts. 1/65536 is about 0.06 units at
/// lt4's coordinates, far above float rounding there.
inline constexpr Real kRayAcceptPadding = 1.0f / 65536;
/// cmkit (RayIndex): node boxes are padded by this fraction (of their
/// largest coordinate magnitude plus a unit) beyond the acceptance boxes, to
/// cover the rounding of the float slab test; enough for rays that start
/// within a few hundred model sizes of the model.
inline constexpr Real kRayNodePadding = 1.0f / 16384;
/// cmkit (World): the broad phase pads a query's swept box by this much
/// before it meets the entities' world boxes. A model's own queries pad the
/// trace bounds by tol::kBoxEpsilon along the MODEL's axes, so an entity
/// placed at an angle can be touched up to sqrt(3) * kBoxEpsilon (1.73)
/// outside a world box around the sweep; 2 covers that and float rounding
/// of the placed boxes.
inline constexpr Real kWorldBroadPhasePadding = 2.0f;

// ---- Building models -------------------------------------------------------

/// original: vertex coordinates this close to an integer are snapped to it
/// (editor grids are integral; this removes parser and clipping noise).
inline constexpr Real kIntegralEpsilon = 0.01f;
/// original: vertices closer than this on every axis are welded into one.
inline constexpr Real kVertexEpsilon = 0.1f;
/// original: windings are split by brush planes with this thickness.
inline constexpr Real kChopEpsilon = 0.1f;
/// original: two polygon edges this close to collinear are merged into one.
inline constexpr Real kContinuousEpsilon = 0.005f;
/// BuildOptions::robustEdges: two polygons count as parallel (coplanar when
/// one's edge lies in the other) when |n1 . n2| exceeds this; such a polygon
/// never marks the other's edges internal. 1 - cos(0.5 degrees): compiled
/// brush planes of overlapping brushes are coplanar to float precision, and
/// genuine creases are far steeper.
inline constexpr Real kRobustEdgeParallelDot = 0.99996f;
/// BuildOptions::robustEdges: a vertex of a coplanar polygon (normals as
/// kRobustEdgeParallelDot, planes this close) this near to a polygon's edge,
/// and this far from its ends, splits the polygon there (a T-junction). The
/// welding distance: vertices this close are one vertex elsewhere, and
/// welding moves a junction's vertex off its edge by up to this.
inline constexpr Real kTJunctionEpsilon = kVertexEpsilon;
/// original: polygon planes this close (normal components and distance) are
/// treated as coplanar when merging.
inline constexpr Real kNormalEpsilon = 0.01f;
/// original: edges whose faces meet at a dot product below this are "sharp".
inline constexpr Real kSharpEdgeDot = -0.7f;
/// original: brush planes with axial normals get their distance rounded to
/// an integer when within this of it.
inline constexpr Real kDegenerateDistEpsilon = 1e-4f;
/// original: maximum distance of a patch control point from the curve before
/// the patch is subdivided further, for collision.
inline constexpr Real kCurveMaxErrorCollision = 24.0f;
/// original: axial BSP nodes smaller than this are not split.
inline constexpr Real kMinNodeSize = 64.0f;
/// original: ... unless they hold more than this many polygons.
inline constexpr int kMaxNodePolygons = 128;
/// original: a split plane must be farther than this from both node bounds.
inline constexpr Real kSplitterMinDistance = 32.0f;
/// original: windings with a coordinate at or beyond this are dropped.
inline constexpr Real kMaxWorldCoord = 131072.0f;
/// original: polygons with more edges are truncated (with a warning).
inline constexpr int kMaxPolygonEdges = 64;
/// original: base windings of brush planes are squares this wide (twice
/// kMaxWorldCoord), so that clipping by the other brush planes cuts them down.
inline constexpr Real kMaxWorldSize = 262144.0f;
/// original: at most this many fragments while chopping a polygon by one
/// brush; beyond it the polygon is kept unchopped (with a warning).
inline constexpr int kMaxWindingList = 128;
/// original: a patch grid cell becomes one quad when its fourth point is
/// closer than this to the plane of the first three, else two triangles.
inline constexpr Real kPatchQuadPlanarEpsilon = 0.1f;
/// original (dhewm3): the vertex weld hash puts a vertex in the 4-unit cell of
/// coordinate - modelMin + this offset ...
inline constexpr double kVertexHashOffset = 0.38;
/// ... and searches the cells of offset -+ this spread too, so that vertices
/// within kVertexEpsilon across a cell border are found.
inline constexpr double kVertexHashSpread = 0.1;
/// original: vertex hash bounds (+-) of a model without brushes.
inline constexpr Real kDefaultHashBounds = 256.0f;

// ---- Geometry helpers ------------------------------------------------------

/// "Cleared" bounds use +-this value (the original's idMath::INFINITY).
inline constexpr Real kBoundsInfinity = 1e30f;
/// A vector whose squared length is below this cannot be normalised: its
/// direction is noise. Normalising it yields the zero vector.
inline constexpr Real kMinNormalizeLengthSquared = 1e-30f;
/// A divisor with magnitude below this is treated as zero by safeDivide.
inline constexpr Real kMinDivisor = 1e-30f;
/// Plane::side() default: points closer than this to a plane are "on" it.
inline constexpr Real kPlaneSideEpsilon = 0.1f;

// ---- User-supplied orientations --------------------------------------------

/// Orientation matrices whose rows deviate from orthonormal by more than this
/// (length or pairwise dot) are re-orthonormalised before use: drift from
/// repeated multiplication otherwise skews trace models.
inline constexpr Real kAxisDriftEpsilon = 1e-5f;
/// Orientation matrices that deviate by more than this are rejected: they are
/// not rotations (scaled, sheared or garbage input).
inline constexpr Real kAxisRejectTolerance = 0.05f;
/// Queries refuse positions, origins and move ends with a coordinate beyond
/// this (QueryStatus::OutOfRange). The original's world is +-131072
/// (kMaxWorldCoord); at 1e9 a float's spacing is already 64 units, and the
/// Plucker products of the tests (a coordinate times two coordinate
/// differences, about 1e27 here) stay far from float overflow (3.4e38). A
/// move of 3e38 would otherwise end at infinity.
inline constexpr Real kMaxQueryCoordinate = 1e9f;
/// A rotation axis whose length differs from 1 by at most this is accepted
/// (normalised when off by more than kAxisDriftEpsilon); a longer, shorter
/// or zero axis is refused (QueryStatus::BadRotationAxis). The query-file
/// reader accepts |length^2 - 1| <= 0.01, which is this.
inline constexpr Real kRotationAxisUnitTolerance = 0.005f;

// ---- Trace models ----------------------------------------------------------

/// Trace-model vertices closer than this are the same point (convex hull,
/// polygon validation).
inline constexpr Real kTrmPointEpsilon = 1e-3f;
/// A trace-model polygon vertex may be this far from the polygon's plane.
inline constexpr Real kTrmPlanarEpsilon = 1e-2f;
/// TrmFromModel: a model is convex when no vertex is farther than this in
/// front of any polygon plane (.cm coordinates carry ~1e-3 of print noise).
inline constexpr Real kTrmFromModelConvexEpsilon = 1e-2f;

// ---- Validation (cmkit validate) -------------------------------------------

/// A normal is "unit" when its squared length is within this of 1 (.cm
/// files print normals with 10 decimals).
inline constexpr Real kValidateUnitEpsilon = 1e-3f;
/// A polygon vertex may lie this far off the polygon's plane: vertex
/// welding (kVertexEpsilon) and integral snapping move built vertices (the
/// shared .cm files reach 0.109).
inline constexpr Real kValidatePlanarEpsilon = 0.25f;
/// Bounds (polygon, brush, node region, model) are checked grown by this:
/// the original takes polygon bounds from the winding before welding moves
/// its vertices by up to kVertexEpsilon (the shared .cm files reach 0.096).
inline constexpr Real kValidateBoundsEpsilon = 0.25f;

// ---- Patches (map parser and tessellation) ---------------------------------

/// original: after subdivision, an interior patch row or column whose points
/// all lie closer than this to the line through their neighbours is removed
/// (it adds no shape, only polygons).
inline constexpr Real kPatchStraightEpsilon = 0.2f;
/// cmkit limit: patch control grids wider or higher than this are rejected
/// by the parser (editors write at most a few dozen; protects memory).
inline constexpr int kMaxPatchControlSize = 1023;
/// cmkit limit: patchDef3 subdivisions per span above this are rejected.
inline constexpr int kMaxPatchGridSize = 4096;
/// cmkit limit: a subdivided patch grid never exceeds this many points
/// (automatic subdivision stops refining; explicit ones are rejected), so
/// huge coordinates cannot make subdivision run away.
inline constexpr int kMaxPatchGridPoints = 1 << 20;

// ---- Player movement (movement.h) ------------------------------------------

/// cmkit (stepPlayer): the ground is looked for this far below the feet. A
/// player at rest stands kClipEpsilon (0.25) from its ground along the
/// normal: 0.25 / 0.7 = 0.36 units above it on the steepest walkable slope;
/// 1 unit covers that with room for the rounding of a step's moves (the
/// player is then put down on what was found).
inline constexpr Real kPlayerGroundProbe = 1.0f;
/// cmkit (stepPlayer): a velocity slid along a plane keeps this fraction
/// (1.001, the original's OVERCLIP) of its component into the plane taken
/// off, leaving it a hair (1e-3 of the speed into it) away from the plane,
/// so that float rounding never points the next move into it again.
inline constexpr Real kPlayerOverclip = 1.001f;
/// cmkit (stepPlayer): two planes whose cross product is shorter than this
/// (the sine of their angle) are one plane for the crease rule: their
/// crease has no direction.
inline constexpr Real kPlayerCreaseSine = 1e-3f;
/// cmkit (stepPlayer): a stepped move is kept only when it got at least this
/// much further (units, horizontally) than the move without the step, so
/// that a wall (where both get equally far) never lifts the player.
inline constexpr Real kPlayerStepGain = 0.01f;
/// cmkit (stepPlayer): a player moving away from its ground's plane faster
/// than this (units/s) has left it (a jump: 320 units/s; the projections of
/// a walk onto the ground leave rounding far below it).
inline constexpr Real kPlayerLeaveGroundSpeed = 10.0f;
/// cmkit (stepPlayer): a player that starts a step in solid is tried lifted
/// by kPlayerNudgeStep, 2 * kPlayerNudgeStep, ... up to this (units): out
/// of a floor it sank into or a platform that rose into it by a step's
/// movement; deeper than this it is stuck.
inline constexpr Real kPlayerMaxNudge = 8.0f;
/// cmkit (stepPlayer): the increment of those lifts (units).
inline constexpr Real kPlayerNudgeStep = 0.5f;

}  // namespace cmkit::tol
