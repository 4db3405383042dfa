// ray_index_data.h: what a RayIndex holds (private to src/ray): the layout's
// arrays, shared by the build (ray_index_build.cpp) and the casts
// (ray_index.cpp). Not included by ray_index_avx2.cpp, which reads the
// arrays through ray_index_kernel.h's plain pointers only.
#pragma once

#include <vector>

#include "cmkit/model.h"
#include "ray/ray_index_layout.h"

namespace cmkit::detail {

/// What a RayIndex holds (built once, then shared by its copies).
struct RayIndexData : RayLayout {
  std::vector<Node> nodes;
  std::vector<LeafChunk> leafChunks;   ///< the leaves, each a LeafHead and its CornerRows
  std::vector<PolygonRecord> records;  ///< the polygons indexed, in leaf order
  bool avx2 = false;
};

/// Fills `d` (empty, its avx2 flag set) with the index of the model's
/// polygons that can be crossed (ray_index_build.cpp); leaves it empty when
/// there is none.
void buildRayIndex(const CollisionModel& model, RayIndexData& d);

}  // namespace cmkit::detail
