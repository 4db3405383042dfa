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
  d->nodes = model.nodes.data();
  d->polygonRefs = model.polygonRefs.data();
  d->numNodes = model.nodes.size();
  d->numPolygonRefs = model.polygonRefs.size();
  d->firstLine.resize(model.polygons.size());
  std::size_t total = 0;
  for (std::size_t p = 0; p < model.polygons.size(); ++p) {
    d->firstLine[p] = total;
    total += detail::lineBlocks(model.polygons[p].numEdges) * detail::kLineBlockSize;
  }
  d->lines.resize(total);
  for (std::size_t p = 0; p < model.polygons.size(); ++p)
    detail::writeEdgeLineBlocks(model, model.edgesOf(model.polygons[p]), d->lines.data() + d->firstLine[p]);
  d->firstCullBlock.reserve(model.nodes.size() + 1);
  for (const CmNode& node : model.nodes) {
    d->firstCullBlock.push_back(d->cullBlocks.size());
    const auto polygons = model.polygonsAt(node);
    for (std::size_t first = 0; first < polygons.size(); first += detail::kCullBlock) {
      detail::PolygonCullBlock b{};
      std::fill(std::begin(b.polygon), std::end(b.polygon), -1);
      for (std::size_t j = 0; j < detail::kCullBlock && first + j < polygons.size(); ++j) {
        const CmPolygon& p = model.polygons[std::size_t(polygons[first + j])];
        for (int k = 0; k < 3; ++k) {
          b.min[k][j] = p.bounds.min[k];
          b.max[k][j] = p.bounds.max[k];
          b.normal[k][j] = p.plane.normal[k];
        }
        b.contents[j] = p.contents;
        b.polygon[j] = polygons[first + j];
      }
      d->cullBlocks.push_back(b);
    }
  }
  d->firstCullBlock.push_back(d->cullBlocks.size());
  model.queryData = std::move(d);
}

}  // namespace cmkit
