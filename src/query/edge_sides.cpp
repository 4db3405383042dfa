// The edge sides of a translation's polygon tests (edge_sides.h): the
// per-vertex masks of edges, in SSE2 float lanes or one vertex at a time, and
// the moving vertices' paths in lanes.
#include "query/edge_sides.h"

#include <algorithm>

namespace cmkit::detail {
namespace {

/// Room in the scratch for the masks of a polygon's `groups` edge groups.
void sizeEdgeMasks(QueryScratch& s, std::size_t groups) {
  if (s.vertexEdgeSides.size() < groups * kMaxTrmVertices) {
    s.vertexEdgeSides.resize(groups * kMaxTrmVertices);
    s.edgesToTest.resize(groups);
  }
}

}  // namespace

#ifdef CMKIT_QUERY_LANES
namespace {

/// The 8 x 8 bit matrix whose row r is byte r of x (column c its bit c),
/// transposed: bit 8r + c of the result is bit 8c + r of x. (Three exchanges
/// of ever larger blocks across the diagonal.)
constexpr std::uint64_t transposeBits8x8(std::uint64_t x) {
  std::uint64_t t = (x ^ (x >> 7)) & 0x00AA00AA00AA00AAull;
  x ^= t ^ (t << 7);
  t = (x ^ (x >> 14)) & 0x0000CCCC0000CCCCull;
  x ^= t ^ (t << 14);
  t = (x ^ (x >> 28)) & 0x00000000F0F0F0F0ull;
  x ^= t ^ (t << 28);
  return x;
}
/// The transposition is linear over XOR, so the 64 one-bit matrices prove it.
constexpr bool transposesEveryBit() {
  for (int r = 0; r < 8; ++r)
    for (int c = 0; c < 8; ++c)
      if (transposeBits8x8(std::uint64_t(1) << (8 * r + c)) != std::uint64_t(1) << (8 * c + r)) return false;
  return true;
}
static_assert(transposesEveryBit());

}  // namespace

// Edge by edge, four vertices at a time: each edge's line broadcast against
// the blocks of vertex paths (TrmFeatures::vertexLines, made with the
// features), one mask of vertices per edge, then transposed into the
// per-vertex masks of edges that the edge pairs read, eight by eight. Each
// lane computes Pluecker::permutedInnerProduct's terms in its order (a
// product of two floats is the same either way round), so the same sign
// bits as one product at a time. For a box against a quadrilateral about a
// third of the instructions of four edges at a time per vertex (the
// polygon's lines, then in blocks of four, started at any lane, so its four
// edges mostly straddled two blocks).
std::uint32_t sidesOfPolygonEdges(TraceWork& tw, const PolygonEdges& edges) {
  QueryScratch& s = tw.scratch;
  const std::size_t groups = edgeGroups(edges.size);
  sizeEdgeMasks(s, groups);
  using simd::F4;
  static_assert(kLanes == 4 && kMaxTrmVertices <= 32);
  const std::uint32_t moving = tw.movingVertices;
  // The vertex blocks up to the last moving vertex.
  const int numVerts = bitsThrough(moving);
  const std::size_t vertexBlocks = std::size_t(numVerts + 3) / 4;
  const LineBlock* vertexLines = tw.scratch.trm.vertexLines.data();
  std::uint32_t outside = 0;  // bit v: vertex v passes outside an edge
  // The 8-vertex rows of the transposition.
  const int vertexRows = (numVerts + 7) / 8;
  for (std::size_t g = 0; g < groups; ++g) {
    const std::size_t first = g * kEdgeGroup;
    const std::size_t count = std::min(kEdgeGroup, edges.size - first);
    std::uint64_t* sides = &s.vertexEdgeSides[g * kMaxTrmVertices];
    // Per row of eight vertices, the sides of up to eight edges: byte j for
    // edge j of the eight, its bit k for vertex k of the row.
    // (Four stores, not a loop to vertexRows: GCC made such loops calls of
    // memset, one or two a polygon.)
    static_assert(kMaxTrmVertices / 8 == 4);
    std::uint64_t rows[kMaxTrmVertices / 8];
    rows[0] = rows[1] = rows[2] = rows[3] = 0;
    for (std::size_t i = 0; i < count; ++i) {
      const BroadcastLine line(edges.line(first + i));
      std::uint32_t bits = 0;  // bit v: vertex v's side
      for (std::size_t k = 0; k < vertexBlocks; ++k) bits |= line.sides(vertexLines[k]) << (4 * k);
      // Outside edge i: the side is not the one its use asks.
      outside |= bits ^ (std::uint32_t(0) - std::uint32_t(edges.edgeNum(first + i) < 0));
      for (int r = 0; r < vertexRows; ++r)
        rows[r] |= std::uint64_t((bits >> (8 * r)) & 0xFFu) << (8 * (i % 8));
      // After every eighth edge and the last: the rows transposed into the
      // vertices' masks of edges (the first eight edges written, the others
      // added; entries past the last vertex, up to a multiple of eight, are
      // written and never read).
      if (i % 8 == 7 || i + 1 == count) {
        const std::size_t e0 = i - i % 8;
        for (int r = 0; r < vertexRows; ++r) {
          const std::uint64_t m = transposeBits8x8(rows[r]);
          std::uint64_t* out = sides + 8 * r;
          if (e0 == 0) {
            for (int k = 0; k < 8; ++k) out[k] = (m >> (8 * k)) & 0xFFu;
          } else {
            for (int k = 0; k < 8; ++k) out[k] |= ((m >> (8 * k)) & 0xFFu) << e0;
          }
        }
        rows[0] = rows[1] = rows[2] = rows[3] = 0;
      }
    }
  }
  return moving & ~outside;
}

void placeVertexLines(TraceWork& tw) {
  const std::uint32_t moving = tw.movingVertices;
  const int numVerts = bitsThrough(moving);
  const F4 dx = F4::all(tw.dir.x), dy = F4::all(tw.dir.y), dz = F4::all(tw.dir.z);
  for (int k = 0; 4 * k < numVerts; ++k) {
    F4 x, y, z;
    trmVertexRows(tw, k, x, y, z);
    const F4 still = trmVertexLanesOutside(moving, k);  // (and the stale entries past the last)
    LineBlock& b = tw.scratch.trm.vertexLines[std::size_t(k)];
    simd::andNot(still, x * dy - y * dx).store(b.c[0]);
    simd::andNot(still, x * dz - z * dx).store(b.c[1]);
    simd::andNot(still, simd::negate(dx)).store(b.c[2]);
    simd::andNot(still, y * dz - z * dy).store(b.c[3]);
    simd::andNot(still, simd::negate(dz)).store(b.c[4]);
    simd::andNot(still, dy).store(b.c[5]);
  }
}

#else  // one vertex at a time, edge by edge

std::uint32_t sidesOfPolygonEdges(TraceWork& tw, const PolygonEdges& edges) {
  QueryScratch& s = tw.scratch;
  const std::size_t groups = edgeGroups(edges.size);
  sizeEdgeMasks(s, groups);
  std::uint32_t outside = 0;  // bit v: vertex v passes outside an edge
  for (std::size_t g = 0; g < groups; ++g) {
    const std::size_t first = g * kEdgeGroup;
    const std::size_t count = std::min(kEdgeGroup, edges.size - first);
    std::uint64_t reversed = 0;
    for (std::size_t i = 0; i < count; ++i) reversed |= std::uint64_t(edges.edgeNum(first + i) < 0) << i;
    std::uint64_t* sides = &s.vertexEdgeSides[g * kMaxTrmVertices];
    for (std::uint32_t moving = tw.movingVertices; moving; moving &= moving - 1) {
      const int v = std::countr_zero(moving);
      const Pluecker& r = tw.vertices[std::size_t(v)].pl;
      std::uint64_t bits = 0;
      for (std::size_t i = 0; i < count; ++i) {
        // Pluecker::permutedInnerProduct, term for term in the same order.
        const Pluecker& c = edges.line(first + i);
        const Real product =
            c[0] * r[4] + c[1] * r[5] + c[2] * r[3] + c[4] * r[0] + c[5] * r[1] + c[3] * r[2];
        bits |= std::uint64_t(signBitSet(product)) << i;
      }
      sides[v] = bits;
      outside |= std::uint32_t((bits ^ reversed) != 0) << v;
    }
  }
  return tw.movingVertices & ~outside;
}

#endif

}  // namespace cmkit::detail
