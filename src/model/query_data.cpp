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

/// The lines lineOf(e) of the entries e of `edges` (signed edge numbers, the
/// line of |e|), as writeEdgeLines says, each block handed to put(block).
template <class LineOf, class Put>
void makeLines(std::span<const std::int32_t> edges, LineOf&& lineOf, Put&& put) {
  makeBlocks<LineBlock>(
      edges.size(),
      [&](LineBlock& b, std::size_t j, std::size_t i) {
        const Pluecker& l = lineOf(std::size_t(std::abs(edges[i])));
        for (std::size_t k = 0; k < 6; ++k) b.c[k][j] = l[int(k)];
      },
      put);
}

/// The lines of all the model's polygonEdges entries, appended to `out`:
/// each edge's line made once, in the edges' order (most edges are used by
/// two polygons), then each entry copied from it. In the polygons' order an
/// entry read its edge's record and two vertices, all three anywhere in
/// memory.
void makeModelEdgeLines(const ModelArrays& m, std::vector<LineBlock>& out) {
  std::vector<Pluecker> edgeLines(m.edges.size());
  // (from 1: no polygon uses the dummy edge 0, whose vertices are never checked)
  for (std::size_t e = 1; e < m.edges.size(); ++e) edgeLines[e] = modelEdgeLine(m, e);
  out.reserve(blocksSpanned(0, m.polygonEdges.size()));
  makeLines(
      m.polygonEdges, [&](std::size_t e) -> const Pluecker& { return edgeLines[e]; },
      [&](const LineBlock& b) { out.push_back(b); });
}

}  // namespace

void writeEdgeLines(const ModelArrays& m, std::span<const std::int32_t> edges, LineBlock* out) {
  makeLines(
      edges, [&](std::size_t e) { return modelEdgeLine(m, e); }, [&](const LineBlock& b) { *out++ = b; });
}

std::shared_ptr<const QueryData> makeQueryData(const ModelArrays& model) {
  auto d = std::make_shared<QueryData>();
  makeModelEdgeLines(model, d->lines);
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
