// Internal: which side of each edge line of a polygon the paths of a
// translation's moving trace-model vertices pass (the edge sides of the
// original's vertex and edge-pair tests), as translate.cpp's polygon tests
// read them: per-vertex masks of edges in the scratch (sidesOfPolygonEdges,
// every build), or for the common small cases one word of slots
// (sidesOfSmallPolygonEdges, float lanes); and the vertices' paths in lanes
// (placeVertexLines). Made in edge_sides.cpp.
#pragma once

#include <bit>
#include <cstdint>

#include "model/query_data.h"  // CMKIT_QUERY_LANES: SSE2, float lanes
#include "query/polygon_edges.h"
#include "query/trace_work.h"

#ifdef CMKIT_QUERY_LANES
#include "query/cull_lanes.h"
#include "util/simd.h"
#endif

namespace cmkit::detail {

// Which side of each edge line of the current polygon the path of every
// moving trace-model vertex passes (see the masks in QueryScratch). A side is
// the sign bit of (edge i's line, stored direction) . (vertex v's line), the
// product the original caches per model edge. It depends only on the edge
// and the vertex, so computing all of a polygon's at once gives the same
// bits as the cache, without its branches and scattered memory. Returns the
// moving vertices whose paths pass inside every edge (on the negative side of
// the edges used backwards, the positive of the others): those the vertex
// test tries. (Two ways: SSE2 float lanes, else one vertex at a time.)
std::uint32_t sidesOfPolygonEdges(TraceWork& tw, const PolygonEdges& edges);

#ifdef CMKIT_QUERY_LANES

/// A polygon edge's line broadcast to four lanes, and the sides of it that
/// four vertices' paths (a block of TrmFeatures::vertexLines) pass: the sign
/// bits of Pluecker::permutedInnerProduct's terms in its order in each lane
/// (a product of two floats is the same either way round), so the same bits
/// as one product at a time; bit j for lane j.
struct BroadcastLine {
  F4 c0, c1, c2, c3, c4, c5;
  explicit BroadcastLine(const Pluecker& l)
      : c0(F4::all(l[0])),
        c1(F4::all(l[1])),
        c2(F4::all(l[2])),
        c3(F4::all(l[3])),
        c4(F4::all(l[4])),
        c5(F4::all(l[5])) {}
  std::uint32_t sides(const LineBlock& r) const {
    F4 p = c0 * F4::load(r.c[4]);
    p = p + c1 * F4::load(r.c[5]);
    p = p + c2 * F4::load(r.c[3]);
    p = p + c4 * F4::load(r.c[0]);
    p = p + c5 * F4::load(r.c[1]);
    p = p + c3 * F4::load(r.c[2]);
    return std::uint32_t(simd::bits(p));
  }
};

// The common cases, a trace model of at most eight vertices (a box) and a
// polygon of at most eight edges, or at most sixteen vertices (an 8-sided
// cylinder) and four edges, without the transposition: the sides as one
// word, slot i (8 or 16 bits from bit i << shift) for polygon edge i, its bit
// v for vertex v, which the edge pairs read as they are (SmallSides). The
// same products as sidesOfPolygonEdges, so the same bits.
struct SmallSides {
  std::uint64_t slots;   ///< slot i, bit v: vertex v's side of edge i's line
  std::uint32_t inside;  ///< the moving vertices inside every edge
};
/// The slots' width as a shift (3: 8 bits, 4: 16 bits) for a polygon of
/// `numEdges` edges, or 0 when it takes the general path.
inline unsigned smallSidesShift(const TraceWork& tw, std::size_t numEdges) {
  if (numEdges <= 8 && tw.movingVertices < (1u << 8)) return 3;
  if (numEdges <= 4 && tw.movingVertices < (1u << 16)) return 4;
  return 0;
}
template <unsigned kShift>
SmallSides sidesOfSmallPolygonEdges(TraceWork& tw, const PolygonEdges& edges) {
  static_assert(kShift == 3 || kShift == 4);
  const std::uint32_t moving = tw.movingVertices;
  const LineBlock* vertexLines = tw.scratch.trm.vertexLines.data();
  // The vertex blocks up to the last moving vertex's (one or two; up to four
  // with 16-bit slots).
  const int blocks = kShift == 3 ? 1 + int(moving >= (1u << 4)) : (35 - std::countl_zero(moving | 1u)) / 4;
  std::uint64_t slots = 0;
  std::uint32_t outside = 0;  // bit v: vertex v passes outside an edge
  for (std::size_t i = 0; i < edges.size; ++i) {
    const BroadcastLine line(edges.line(i));
    std::uint32_t bits = line.sides(vertexLines[0]);
    if constexpr (kShift == 3) {
      if (blocks == 2) bits |= line.sides(vertexLines[1]) << 4;
    } else {
      for (int k = 1; k < blocks; ++k) bits |= line.sides(vertexLines[k]) << (4 * k);
    }
    outside |= bits ^ (std::uint32_t(0) - std::uint32_t(edges.edgeNum(i) < 0));
    slots |= std::uint64_t(bits) << (i << kShift);
  }
  return {slots, moving & ~outside};
}

/// TrmFeatures::vertexLines up to the last moving vertex's block: lane
/// v % kLanes of block v / kLanes the path of vertex v, made four vertices
/// at a time (Pluecker::fromRay's arithmetic in each lane, so the same
/// bits as one vertex at a time); 0 in the lanes of vertices that do not
/// move.
void placeVertexLines(TraceWork& tw);

#endif  // CMKIT_QUERY_LANES

}  // namespace cmkit::detail
