// Internal: a polygon's edges as a query's polygon tests read them (the
// query data's edge uses, or the polygons' hierarchy's corners, with their
// lines made in the scratch), and the walk
// over the model vertices of a polygon's edges that a query meets first.
// Translations, rotations and position tests (translate.cpp, rotate.cpp,
// position_test.cpp; made in tree_walk.cpp).
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <utility>
#include <vector>

#include "query/trace_work.h"

namespace cmkit::detail {

/// A polygon's edges as its tests read them: edge i's entry, vertices and
/// internal flag at uses[i] (model/query_data.h) or corners[i] (and where
/// it ends: corners[i + 1]; model/query_blocks.h), its line (in the edge's
/// stored direction) at lines[i]. (A branch per read on which: the same one
/// for every read of a query.)
struct PolygonEdges {
  const EdgeUse* uses;  ///< the model's uses, or null (corners)
  const Pluecker* lines;
  std::size_t size;
  const PolygonCorner* corners = nullptr;  ///< the hierarchy's corners, or null (uses)
  const Vec3* vertices = nullptr;          ///< the model's (read with uses)
  std::int32_t edgeNum(std::size_t i) const { return corners ? corners[i].edgeNum() : uses[i].edgeNum; }
  bool internal(std::size_t i) const { return corners ? corners[i].internal() : uses[i].internal != 0; }
  /// Where edge i starts and ends in the polygon's order.
  const Vec3& from(std::size_t i) const { return corners ? corners[i].p : vertices[uses[i].start()]; }
  const Vec3& to(std::size_t i) const {
    return corners ? corners[i + 1 == size ? 0 : i + 1].p : vertices[uses[i].end()];
  }
  const Pluecker& line(std::size_t i) const { return lines[i]; }
};
/// a and b, or b and a when `swap`: by a mask on their addresses, without a
/// branch (GCC made one of a plain choice between two references, and which
/// edges a polygon uses reversed is unpredictable).
struct EdgeEnds {
  const Vec3& first;
  const Vec3& second;
};
inline EdgeEnds swappedIf(bool swap, const Vec3& a, const Vec3& b) {
  const auto pa = reinterpret_cast<std::uintptr_t>(&a), pb = reinterpret_cast<std::uintptr_t>(&b);
  const std::uintptr_t flip = (pa ^ pb) & (std::uintptr_t(0) - std::uintptr_t(swap));
  return {*reinterpret_cast<const Vec3*>(pa ^ flip), *reinterpret_cast<const Vec3*>(pb ^ flip)};
}

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
  return {uses, out, numEdges, nullptr, vertices};
}
/// The same from a polygon's corners (the polygons' hierarchy's): edge i's
/// line from corner i to corner i + 1, or back when the edge is used
/// reversed (its stored direction: the same bits).
inline PolygonEdges polygonEdges(TraceWork& tw, const PolygonCorner* corners, std::size_t numEdges) {
  std::vector<Pluecker>& lines = tw.scratch.polygonEdgeLines;
  if (lines.size() < numEdges) [[unlikely]]
    sizePolygonEdgeLines(tw, numEdges);
  Pluecker* out = lines.data();
  for (std::size_t i = 0; i < numEdges; ++i) {
    const Vec3& a = corners[i].p;
    const Vec3& b = corners[i + 1 == numEdges ? 0 : i + 1].p;
    const EdgeEnds ends = swappedIf(corners[i].entry < 0, a, b);  // (entry < 0: reversed)
    out[i] = Pluecker::fromLine(ends.first, ends.second);
  }
  return {nullptr, out, numEdges, corners, nullptr};
}
/// A polygon's edges: the model's uses (query data), or made in the scratch
/// (edgeUses) for a model without them; their lines as above.
inline PolygonEdges polygonEdges(TraceWork& tw, const CmPolygon& poly) {
  const EdgeUse* uses =
      tw.queryData ? tw.queryData->edgeUses.data() + poly.firstEdge : makePolygonEdgeUses(tw, poly);
  return polygonEdges(tw, uses, poly.numEdges);
}

/// A model vertex met through a polygon's edges: the edge's entry and which
/// of its ends in the polygon's order (0: where it starts). Its number,
/// which only a hit needs, from the edge's record (modelVertexNumber).
struct ModelVertexRef {
  std::int32_t edgeNum;
  int end;
};
inline std::size_t modelVertexNumber(const CollisionModel& m, ModelVertexRef v) {
  const CmEdge& edge = m.edges()[std::size_t(std::abs(v.edgeNum))];
  return std::size_t(edge.vertex[v.end ^ int(v.edgeNum < 0)]);
}

/// Calls f(vertex, vertex number, position) for the vertices of a polygon's
/// edges that the query meets for the first time and that lie in the trace
/// bounds: every model edge and vertex once per query (marked as met),
/// internal edges skipped. The box test makes all six comparisons (which
/// vertices lie in the bounds is unpredictable: insideBox).
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
      if (insideBox(tw.bounds, p)) f(ModelVertexRef{edgeNum, k}, vn, p);
    }
  }
}
/// The same over a polygon's edge list (reading each edge's record),
/// f(vertex number, position).
template <class F>
void forEachNewModelVertex(TraceWork& tw, std::span<const std::int32_t> edges, F f) {
  const CollisionModel& m = tw.model;
  forEachNewModelVertex(
      tw, edges.size(),
      [&](std::size_t i) {
        return std::pair<std::int32_t, const CmEdge&>(edges[i], m.edges()[std::size_t(std::abs(edges[i]))]);
      },
      [&](ModelVertexRef, std::size_t vn, const Vec3& p) { f(vn, p); });
}
/// Polygons of more edges than this take the corner loop edge by edge
/// (forEachNewCornerInOrder): the corners' mask (a 64-bit word) has a bit a
/// corner and one more, for corner 0 met last.
inline constexpr std::size_t kMaxCornerMaskEdges = 63;
/// The corners of forEachNewModelVertex(PolygonEdges) edge by edge, in the
/// same order: for polygons too large for the mask.
template <class F>
void forEachNewCornerInOrder(TraceWork& tw, const PolygonEdges& edges, bool marked, F f) {
  QueryScratch& s = tw.scratch;
  bool lastMet = false, firstMet = false;  // (the edge before; edge 0)
  for (std::size_t i = 0; i < edges.size; ++i) {
    const std::int32_t edgeNum = edges.edgeNum(i);
    if (s.testAndMark(s.edgeChecked, std::size_t(std::abs(edgeNum))) || edges.internal(i)) {
      lastMet = false;
      continue;
    }
    if (!lastMet && !(marked && s.testAndMark(s.vertexChecked, modelVertexNumber(tw.model, {edgeNum, 0})))) {
      const Vec3& a = edges.from(i);
      if (insideBox(tw.bounds, a)) f(ModelVertexRef{edgeNum, 0}, a);
    }
    if (!(i + 1 == edges.size && firstMet) &&
        !(marked && s.testAndMark(s.vertexChecked, modelVertexNumber(tw.model, {edgeNum, 1})))) {
      const Vec3& b = edges.to(i);
      if (insideBox(tw.bounds, b)) f(ModelVertexRef{edgeNum, 1}, b);
    }
    lastMet = true;
    firstMet |= i == 0;
  }
}

/// The same over a polygon's edges, f(ModelVertexRef, position). With
/// corners (the hierarchy's), a translation does not mark a vertex (its
/// number is not at hand): one met again in a later polygon is tested again,
/// which changes nothing: the same products give the same fraction, not
/// nearer than the nearest hit so far, which it already is or beats (a
/// fraction below 0 ends the translation at 0 after the polygon where it was
/// found). Collecting contacts, where each contact starts the nearest hit
/// over (addContact), a vertex met again would be listed again: there each
/// is marked by its number, from its edge's record. Within a polygon each
/// corner is met once, so that the order of the vertices' first tests,
/// which decides between equally near ones, is the marks'.
template <class F>
void forEachNewModelVertex(TraceWork& tw, const PolygonEdges& edges, F f) {
  QueryScratch& s = tw.scratch;
  if (!edges.corners) {
    forEachNewModelVertex(
        tw, edges.size,
        [&](std::size_t i) {
          return std::pair<std::int32_t, const EdgeUse&>(edges.uses[i].edgeNum, edges.uses[i]);
        },
        [&](ModelVertexRef v, std::size_t, const Vec3& p) { f(v, p); });
    return;
  }
  // Corner i is where edge i starts and edge i - 1 ends: met once, by the
  // first of the two the query meets (as the marks would have it).
  const bool marked = tw.gettingContacts();
  const std::size_t n = edges.size;
  if (n > kMaxCornerMaskEdges) [[unlikely]] {
    forEachNewCornerInOrder(tw, edges, marked, f);
    return;
  }
  // The edges met here first (bit i: edge i, not internal), every edge
  // marked, and the corners in the trace bounds, without a branch an edge
  // (whether an edge was met before, or a corner lies in the bounds, is
  // unpredictable); then the corners the new edges reach as a mask, in the
  // order the edges meet them: corner c (c > 0) with edge c or edge c - 1;
  // corner 0 first with edge 0, else last (bit n) with edge n - 1. (The
  // bounds do not change within a polygon's corners: shrinkTraceBounds
  // follows them. A corner outside them is not marked, where contacts mark
  // vertices: their bounds never shrink, so it stays outside.)
  std::uint64_t fresh = 0, inBounds = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const bool met = s.testAndMarkStoring(s.edgeChecked, std::size_t(std::abs(edges.edgeNum(i))));
    fresh |= std::uint64_t(unsigned(!met) & unsigned(!edges.internal(i))) << i;
    inBounds |= std::uint64_t(insideBox(tw.bounds, edges.corners[i].p)) << i;
  }
  inBounds |= (inBounds & 1) << n;
  for (std::uint64_t reached = (fresh | fresh << 1) & ~((fresh & 1) << n) & inBounds; reached;
       reached &= reached - 1) {
    const std::size_t b = std::size_t(std::countr_zero(reached));
    // (Reached by its own edge's start, else by the edge before's end: the
    // same vertex in a closed polygon, named as the edge loop named it.)
    const std::size_t viaStart = std::size_t((fresh >> b) & 1);
    const ModelVertexRef v{edges.edgeNum(b - 1 + viaStart), int(viaStart ^ 1)};
    if (marked && s.testAndMark(s.vertexChecked, modelVertexNumber(tw.model, v))) continue;
    f(v, edges.corners[b == n ? 0 : b].p);
  }
}

/// Fills scratch.polygonEdgeLines with the lines of a polygon's edges, one
/// Pluecker each (for the loops that read a polygon's lines many times): as
/// polygonEdges does.
void setPolygonEdgeLines(TraceWork& tw, const CmPolygon& poly);

}  // namespace cmkit::detail
