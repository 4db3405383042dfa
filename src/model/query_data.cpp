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

/// Writes lineOf(e) for each entry e of `edges` (signed edge numbers, the
/// line of |e|) into the blocks at `out`, as writeEdgeLines says.
template <class LineOf>
void writeLines(std::span<const std::int32_t> edges, LineBlock* out, LineOf&& lineOf) {
  std::fill(out, out + blocksSpanned(0, edges.size()), LineBlock{});
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const Pluecker& l = lineOf(std::size_t(std::abs(edges[i])));
    for (std::size_t k = 0; k < 6; ++k) out[i / kLanes].c[k][i % kLanes] = l[int(k)];
  }
}

/// writeEdgeLines of all the model's polygonEdges entries: each edge's line
/// made once, in the edges' order (most edges are used by two polygons),
/// then each entry copied from it. In the polygons' order an entry read its
/// edge's record and two vertices, all three anywhere in memory.
void writeModelEdgeLines(const ModelArrays& m, LineBlock* out) {
  std::vector<Pluecker> edgeLines(m.edges.size());
  // (from 1: no polygon uses the dummy edge 0, whose vertices are never checked)
  for (std::size_t e = 1; e < m.edges.size(); ++e) edgeLines[e] = modelEdgeLine(m, e);
  writeLines(m.polygonEdges, out, [&](std::size_t e) -> const Pluecker& { return edgeLines[e]; });
}

}  // namespace

void writeEdgeLines(const ModelArrays& m, std::span<const std::int32_t> edges, LineBlock* out) {
  writeLines(edges, out, [&](std::size_t e) { return modelEdgeLine(m, e); });
}

std::shared_ptr<const QueryData> makeQueryData(const ModelArrays& model) {
  auto d = std::make_shared<QueryData>();
  d->lines.resize(blocksSpanned(0, model.polygonEdges.size()));
  writeModelEdgeLines(model, d->lines.data());
  if constexpr (kCullBlocks) {
    d->culls.resize(blocksSpanned(0, model.polygonRefs.size()));
    for (std::size_t r = 0; r < model.polygonRefs.size(); ++r) {
      CMKIT_ASSERT(model.polygonRefs[r] >= 0 && std::size_t(model.polygonRefs[r]) < model.polygons.size());
      const CmPolygon& p = model.polygons[std::size_t(model.polygonRefs[r])];
      CullBlock& b = d->culls[r / kLanes];
      const std::size_t j = r % kLanes;
      for (int k = 0; k < 3; ++k) {
        b.min[k][j] = p.bounds.min[k];
        b.max[k][j] = p.bounds.max[k];
        b.normal[k][j] = p.plane.normal[k];
      }
      b.contents[j] = p.contents;
    }
    d->bvh = buildPolygonBvh(model);
  }
  d->pointTree = buildPointTree(model);
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
    m.queryData = bytes(d->lines) + bytes(d->culls) + bytes(d->bvh.nodes) + bytes(d->bvh.leaves) +
                  bytes(d->bvh.twins) + bytes(d->pointTree.nodes) + bytes(d->pointTree.brushes) +
                  bytes(d->pointTree.modelNodes);
  return m;
}

}  // namespace cmkit
