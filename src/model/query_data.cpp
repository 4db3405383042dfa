// The queries' derived data of a model (query_data.h) and prepareQueries.
#include "model/query_data.h"

#include <cstdlib>

namespace cmkit::detail {

void writeEdgeLineBlocks(const CollisionModel& m, std::span<const std::int32_t> edges, Real* out) {
  std::fill(out, out + lineBlocks(edges.size()) * kLineBlockSize, Real(0));
  for (std::size_t j = 0; j < edges.size(); ++j) {
    const CmEdge& edge = m.edges[std::size_t(std::abs(edges[j]))];
    const Pluecker l =
        Pluecker::fromLine(m.vertices[std::size_t(edge.vertex[0])], m.vertices[std::size_t(edge.vertex[1])]);
    Real* b = out + (j / kLineBlock) * kLineBlockSize + j % kLineBlock;
    for (std::size_t k = 0; k < 6; ++k) b[k * kLineBlock] = l[int(k)];
  }
}

}  // namespace cmkit::detail

namespace cmkit {

void prepareQueries(CollisionModel& model) {
  auto d = std::make_shared<detail::QueryData>();
  d->vertices = model.vertices.data();
  d->edges = model.edges.data();
  d->polygonEdges = model.polygonEdges.data();
  d->polygons = model.polygons.data();
  d->numVertices = model.vertices.size();
  d->numEdges = model.edges.size();
  d->numPolygonEdges = model.polygonEdges.size();
  d->numPolygons = model.polygons.size();
  d->firstLine.resize(model.polygons.size());
  std::size_t total = 0;
  for (std::size_t p = 0; p < model.polygons.size(); ++p) {
    d->firstLine[p] = total;
    total += detail::lineBlocks(model.polygons[p].numEdges) * detail::kLineBlockSize;
  }
  d->lines.resize(total);
  for (std::size_t p = 0; p < model.polygons.size(); ++p)
    detail::writeEdgeLineBlocks(model, model.edgesOf(model.polygons[p]), d->lines.data() + d->firstLine[p]);
  model.queryData = std::move(d);
}

}  // namespace cmkit
