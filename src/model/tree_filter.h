// Internal: putting the polygons and brushes of a loaded .cm model into its
// stored tree, and the model's bounds and contents (spec 3.6 and 4).
#pragma once

#include "cmkit/model.h"

namespace cmkit::detail {

/// Fills model.polygonRefs / model.brushRefs and every node's ranges: each
/// polygon, then each brush, in index order, is filtered into the tree by its
/// bounds (stopping at the first node it is "inside all children" of, else
/// going front if min >= dist, back if max <= dist, else both) and prepended
/// to the list of every node it reaches, as the original's loader does. So
/// each node's list runs in reverse index order.
/// Requires a well-formed tree: nodes[0] the root, children after their
/// parent (pre-order), child indices in range.
void filterItemsIntoTree(CollisionModel& model);

}  // namespace cmkit::detail
