// The queries' derived data of a model (query_data.h) and prepareQueries.
#include "model/query_data.h"

#include <algorithm>
#include <cstdlib>
#include <limits>

namespace cmkit::detail {

void writeEdgeLines(const CollisionModel& m, std::span<const std::int32_t> edges, LineBlock* out) {
  std::fill(out, out + blocksSpanned(0, edges.size()), LineBlock{});
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const Pluecker l = modelEdgeLine(m, std::size_t(std::abs(edges[i])));
    for (std::size_t k = 0; k < 6; ++k) out[i / kLanes].c[k][i % kLanes] = l[int(k)];
  }
}

}  // namespace cmkit::detail

namespace cmkit {

namespace {

// Whether every number the query data is made from is in range: the edges'
// vertices, the polygons' edge lists and edge numbers, the polygon references.
bool queryDataSources(const CollisionModel& m) {
  for (const CmEdge& e : m.edges)
    for (const std::int32_t v : e.vertex)
      if (v < 0 || std::size_t(v) >= m.vertices.size()) return false;
  for (const CmPolygon& p : m.polygons)
    if (p.firstEdge > m.polygonEdges.size() || p.numEdges > m.polygonEdges.size() - p.firstEdge) return false;
  for (const std::int32_t e : m.polygonEdges)
    if (e == std::numeric_limits<std::int32_t>::min() || std::size_t(std::abs(e)) >= m.edges.size())
      return false;
  for (const std::int32_t p : m.polygonRefs)
    if (p < 0 || std::size_t(p) >= m.polygons.size()) return false;
  return true;
}

}  // namespace

void prepareQueries(CollisionModel& model) {
  model.queryData.reset();
  if (!queryDataSources(model)) return;  // a broken hand-made model: none (validate() says what is wrong)
  auto d = std::make_shared<detail::QueryData>();
  d->source = detail::modelArrays(model);
  d->lines.resize(detail::blocksSpanned(0, model.polygonEdges.size()));
  detail::writeEdgeLines(model, model.polygonEdges, d->lines.data());
  if constexpr (detail::kCullBlocks) {
    d->culls.resize(detail::blocksSpanned(0, model.polygonRefs.size()));
    for (std::size_t r = 0; r < model.polygonRefs.size(); ++r) {
      const CmPolygon& p = model.polygons[std::size_t(model.polygonRefs[r])];
      detail::CullBlock& b = d->culls[r / detail::kLanes];
      const std::size_t j = r % detail::kLanes;
      for (int k = 0; k < 3; ++k) {
        b.min[k][j] = p.bounds.min[k];
        b.max[k][j] = p.bounds.max[k];
        b.normal[k][j] = p.plane.normal[k];
      }
      b.contents[j] = p.contents;
    }
  }
  model.queryData = std::move(d);
}

ModelMemory modelMemory(const CollisionModel& model) {
  const auto bytes = [](const auto& v) { return v.size() * sizeof(v[0]); };
  ModelMemory m;
  m.arrays = bytes(model.vertices) + bytes(model.edges) + bytes(model.polygonEdges) + bytes(model.polygons) +
             bytes(model.brushPlanes) + bytes(model.brushes) + bytes(model.nodes) + bytes(model.polygonRefs) +
             bytes(model.brushRefs);
  if (const detail::QueryData* d = model.queryData.get()) m.queryData = bytes(d->lines) + bytes(d->culls);
  return m;
}

}  // namespace cmkit
