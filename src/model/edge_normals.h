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
int computeEdgeNormals(ModelArrays& model);

/// Sets model.bounds and model.contents from the polygons and brushes (the
/// original's CM_GetNodeBounds: both corners of every item as points, so an
/// empty brush's cleared bounds count; no items gives zero bounds).
void computeModelBoundsAndContents(ModelArrays& model);

}  // namespace cmkit::detail
