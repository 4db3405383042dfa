// Internal: edge normals, bounds and contents of a collision model (the original's edge normal
// pass, docs/algorithms.md). Used by the map builder on freshly built models
// and by the .cm reader after loading.
#pragma once

#include "cmkit/model.h"

namespace cmkit::detail {

/// Computes every edge's `normal` from the polygons that use it and returns
/// the number of "sharp" events (an edge whose second face bends back more
/// than tol::kSharpEdgeDot), the original's numSharpEdges.
///
/// All normals are reset to zero first. Then every polygon is visited once,
/// in the original's tree order: starting at the root, a node's own polygon
/// list (in list order), then its back subtree (children[1]), then its front
/// subtree (children[0]). A polygon referenced from several nodes is handled
/// at its first visit. For each of its edges, with t = the edge direction as
/// the polygon walks it and n = the polygon normal:
///  - normal still zero, one user:   normalize(t x n) (outward in-plane normal);
///  - normal still zero, more users: n;
///  - otherwise, dot = normal . n; if dot < kSharpEdgeDot (sharp):
///    normal = normal x t + n x (-t), rescaled to length
///    0.5 / (0.5 + 0.5 kSharpEdgeDot); else the bisector
///    (0.5 / (0.5 + 0.5 dot)) (normal + n).
/// The order only matters for edges with more than two users. Polygons not
/// referenced from the tree get no visit (as in the original).
///
/// EdgeNormalRule::TwoSidedSheets (BuildOptions::robustEdges,
/// MeshBuildOptions::robustEdges; not the original's) treats a two-sided
/// sheet as one surface. A two-sided material gives every polygon a reversed
/// copy; the original sees the line they share as a fold of dot -1, "sharp",
/// and makes its normal (t x n doubled) rescaled to 1/0.3: the epsilon edge
/// lies 0.83 units out instead of 0.25, and further faces at the line add to
/// that in visiting order. Here the uses of a line (every edge between the
/// same two vertices: the builder gives a third polygon at a line an edge of
/// its own) are paired into twins: faces with opposite normals (|dot| above
/// kRobustEdgeParallelDot) walking the line opposite ways. A line without
/// twins keeps the original's normals, edge by edge. Otherwise one normal,
/// for every edge of the line, from the faces chosen as follows, added in
/// visiting order by the rule above (one face alone: its outward in-plane
/// normal):
///  - one pair only (a sheet's boundary): its first face alone, so the edge is
///    an ordinary boundary edge, normalize(t x n) (the same from either face);
///  - two pairs only (two sheets meet, or one sheet bends, the tiles of a
///    two-sided floor, the cells of a two-sided patch): of each pair the faces
///    walking the line opposite ways (one consistently oriented surface), on
///    the side from which that surface is convex (flat: the first face's
///    side); the normal is their bisector, as a one-sided surface's. One
///    epsilon edge serves both sides: from the convex side a trace meets
///    the crease before either face and needs it; from the concave side the
///    faces stop the trace first (a one-sided surface marks such a crease
///    internal);
///  - otherwise (three or more pairs, or a sheet meeting one-sided faces):
///    every unpaired face and, of each pair, the face whose normal is nearer
///    the first unpaired face's (with none, the first face's).
/// The returned count is then the genuinely sharp folds only. The rule is
/// applied here, where the normals are built, not at query time: a built
/// model does not know its build options, the queries read edge normals as
/// data (no cost per query), and the default build never takes this path
/// (the original's normals, and answers, unchanged). The .cm file does not
/// store edge normals, and its reader uses the original rule.
enum class EdgeNormalRule { Original, TwoSidedSheets };
int computeEdgeNormals(ModelArrays& model, EdgeNormalRule rule = EdgeNormalRule::Original);

/// Sets model.bounds and model.contents from the polygons and brushes (the
/// original's CM_GetNodeBounds: both corners of every item as points, so an
/// empty brush's cleared bounds count; no items gives zero bounds).
void computeModelBoundsAndContents(ModelArrays& model);

}  // namespace cmkit::detail
