// Internal: a polygon's edges as a query's polygon tests read them (the
// query data's edge uses with their lines made in the scratch), and the walk
// over the model vertices of a polygon's edges that a query meets first.
// Translations, rotations and position tests (translate.cpp, rotate.cpp,
// position_test.cpp; made in tree_walk.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <utility>
#include <vector>

#include "query/trace_work.h"

namespace cmkit::detail {

/// A polygon's edges as its tests read them: edge i's entry, vertices and
/// internal flag at uses[i] (model/query_data.h), its line (in the edge's
/// stored direction) at lines[i].
struct PolygonEdges {
  const EdgeUse* uses;
  const Pluecker* lines;
  std::size_t size;
  const EdgeUse& operator[](std::size_t i) const { return uses[i]; }
  const Pluecker& line(std::size_t i) const { return lines[i]; }
};
/// The uses of a polygon's edges made in the scratch (edgeUses), for a
/// model without query data; the lines' array sized for them.
const EdgeUse* makePolygonEdgeUses(TraceWork& tw, const CmPolygon& poly);
/// Sizes the scratch's lines for a polygon of `numEdges` edges.
void sizePolygonEdgeLines(TraceWork& tw, std::size_t numEdges);
/// A polygon's edges whose uses are `uses[0 .. numEdges - 1]`: their lines
/// made in the scratch (polygonEdgeLines) from the vertices, as
/// modelEdgeLine makes them (the same bits). Valid until the next call.
/// (Inline: every tested polygon's.)
inline PolygonEdges polygonEdges(TraceWork& tw, const EdgeUse* uses, std::size_t numEdges) {
  std::vector<Pluecker>& lines = tw.scratch.polygonEdgeLines;
  if (lines.size() < numEdges) [[unlikely]]
    sizePolygonEdgeLines(tw, numEdges);
  const Vec3* vertices = tw.model.vertices().data();
  Pluecker* out = lines.data();
  for (std::size_t i = 0; i < numEdges; ++i)
    out[i] = Pluecker::fromLine(vertices[uses[i].vertex[0]], vertices[uses[i].vertex[1]]);
  return {uses, out, numEdges};
}
/// A polygon's edges: the model's uses (query data), or made in the scratch
/// (edgeUses) for a model without them; their lines as above.
inline PolygonEdges polygonEdges(TraceWork& tw, const CmPolygon& poly) {
  const EdgeUse* uses =
      tw.queryData ? tw.queryData->edgeUses.data() + poly.firstEdge : makePolygonEdgeUses(tw, poly);
  return polygonEdges(tw, uses, poly.numEdges);
}

/// Calls f(vertex number, position) for the vertices of a polygon's edges
/// that the query meets for the first time and that lie in the trace bounds:
/// every model edge and vertex once per query (marked as met), internal
/// edges skipped. The box test makes all six comparisons (which vertices lie
/// in the bounds is unpredictable: insideBox).
/// (edgeAt(i), i < count, gives edge i's number, vertices and internal flag:
/// an EdgeUse or a CmEdge.)
template <class EdgeAt, class F>
void forEachNewModelVertex(TraceWork& tw, std::size_t count, EdgeAt edgeAt, F f) {
  const CollisionModel& m = tw.model;
  QueryScratch& s = tw.scratch;
  for (std::size_t i = 0; i < count; ++i) {
    const auto [edgeNum, edge] = edgeAt(i);
    const std::size_t e = std::size_t(std::abs(edgeNum));
    if (s.testAndMark(s.edgeChecked, e)) continue;
    if (edge.internal) continue;
    for (int k = 0; k < 2; ++k) {
      const std::size_t vn = std::size_t(edge.vertex[k ^ int(edgeNum < 0)]);
      if (s.testAndMark(s.vertexChecked, vn)) continue;
      const Vec3& p = m.vertices()[vn];
      if (insideBox(tw.bounds, p)) f(vn, p);
    }
  }
}
/// The same over a polygon's edge list (reading each edge's record).
template <class F>
void forEachNewModelVertex(TraceWork& tw, std::span<const std::int32_t> edges, F f) {
  const CollisionModel& m = tw.model;
  forEachNewModelVertex(
      tw, edges.size(),
      [&](std::size_t i) {
        return std::pair<std::int32_t, const CmEdge&>(edges[i], m.edges()[std::size_t(std::abs(edges[i]))]);
      },
      f);
}
/// The same over a polygon's edge uses.
template <class F>
void forEachNewModelVertex(TraceWork& tw, const PolygonEdges& uses, F f) {
  forEachNewModelVertex(
      tw, uses.size,
      [&](std::size_t i) { return std::pair<std::int32_t, const EdgeUse&>(uses[i].edgeNum, uses[i]); }, f);
}

/// Fills scratch.polygonEdgeLines with the lines of a polygon's edges, one
/// Pluecker each (for the loops that read a polygon's lines many times): as
/// polygonEdges does.
void setPolygonEdgeLines(TraceWork& tw, const CmPolygon& poly);

}  // namespace cmkit::detail
