// The queries' derived data of a model (query_data.h): makeQueryData.
#include "model/query_data.h"

#include "model/model_access.h"
#include "util/assert.h"

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <span>
#include <vector>

namespace cmkit::detail {

namespace {

/// Makes the blocks of `count` entries one at a time, entry i in lane
/// i % kLanes of block i / kLanes by fill(block, lane, i), the lanes past the
/// last entry 0, and hands each to put(block). (Each block is written once:
/// zeroing the whole array first, as a vector's resize does, wrote a large
/// model's few megabytes twice.)
template <class Block, class Fill, class Put>
void makeBlocks(std::size_t count, Fill&& fill, Put&& put) {
  for (std::size_t first = 0; first < count; first += kLanes) {
    Block block{};
    const std::size_t lanes = std::min(kLanes, count - first);
    for (std::size_t j = 0; j < lanes; ++j) fill(block, j, first + j);
    put(block);
  }
}

/// The uses of all the model's polygonEdges entries, in `out`.
void makeModelEdgeUses(const ModelArrays& m, std::vector<EdgeUse>& out) {
  out.reserve(m.polygonEdges.size());
  for (const std::int32_t e : m.polygonEdges) out.push_back(edgeUse(m, e));
}

}  // namespace

void writeEdgeUses(const ModelArrays& m, std::span<const std::int32_t> edges, EdgeUse* out) {
  for (const std::int32_t e : edges) *out++ = edgeUse(m, e);
}

std::shared_ptr<const QueryData> makeQueryData(const ModelArrays& model) {
  auto d = std::make_shared<QueryData>();
  makeModelEdgeUses(model, d->edgeUses);
  if constexpr (kCullBlocks) {
    d->culls.reserve(blocksSpanned(0, model.polygonRefs.size()));
    makeBlocks<CullBlock>(
        model.polygonRefs.size(),
        [&](CullBlock& b, std::size_t j, std::size_t r) {
          CMKIT_ASSERT(model.polygonRefs[r] >= 0 &&
                       std::size_t(model.polygonRefs[r]) < model.polygons.size());
          const CmPolygon& p = model.polygons[std::size_t(model.polygonRefs[r])];
          for (int k = 0; k < 3; ++k) {
            b.min[k][j] = p.bounds.min[k];
            b.max[k][j] = p.bounds.max[k];
            b.normal[k][j] = p.plane.normal[k];
          }
          b.contents[j] = p.contents;
        },
        [&](const CullBlock& b) { d->culls.push_back(b); });
    d->bvh = buildPolygonBvh(model, d->edgeUses);
  }
  d->pointTree = buildPointTree(model);
  d->pointGrid = buildPointGrid(model);
  return d;
}

const QueryData* queryDataOf(const CollisionModel& m) { return ModelAccess::queryData(m); }

}  // namespace cmkit::detail

namespace cmkit {

ModelMemory modelMemory(const CollisionModel& model) {
  const auto bytes = [](const auto& v) { return v.size() * sizeof(v[0]); };
  ModelMemory m;
  m.arrays = bytes(model.vertices()) + bytes(model.edges()) + bytes(model.polygonEdges()) +
             bytes(model.polygons()) + bytes(model.brushPlanes()) + bytes(model.brushes()) +
             bytes(model.nodes()) + bytes(model.polygonRefs()) + bytes(model.brushRefs());
  if (const detail::QueryData* d = detail::queryDataOf(model))
    m.queryData = bytes(d->edgeUses) + bytes(d->culls) + bytes(d->bvh.nodes) + bytes(d->bvh.leaves) +
                  bytes(d->bvh.uses) + bytes(d->pointTree.nodes) + bytes(d->pointTree.modelNodes) +
                  bytes(d->pointGrid.firstBox) + bytes(d->pointGrid.boxes);
  return m;
}

}  // namespace cmkit
