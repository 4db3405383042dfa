// Translation tests of one model polygon (the original's
// TranslateTrmThroughPolygon and the tests it runs): trace-model vertex
// through polygon, trace-model edge through polygon edge, model vertex
// through trace-model polygon; a point's test. Model space throughout.
// Which polygons a translation tests (the culls, through the BSP tree's
// nodes or the polygon hierarchy's leaves) is translate_culls.cpp's.
#include <algorithm>
#include <bit>
#include <cmath>

#include "query/polygon_edges.h"
#include "query/trace_work.h"

// SSE2 on x86-64 (sidesOfPolygonEdges: four polygon edges at a time); any other target, or
// -DCMKIT_NO_SIMD, uses the portable loops, which do the same arithmetic. The
// lanes are float: a double build (CMKIT_DOUBLE) uses the portable loops.
#include "model/query_data.h"  // CMKIT_QUERY_LANES: SSE2, float lanes
#ifdef CMKIT_QUERY_LANES
#include "query/cull_lanes.h"
#include "util/simd.h"
#define CMKIT_SIDES_SSE2 1
#endif

namespace cmkit::detail {
namespace {

/// Fraction of the move a-> b at which a point first gets within
/// tol::kClipEpsilon of the plane, approaching from the front; 1 when it
/// does not (ends farther than the epsilon, starts behind, or moves away).
/// May be negative when the start is already within the epsilon.
/// (Inline, as modelVertexSide: GCC otherwise calls both out of line from
/// every vertex test and edge pair, ~1-2% of a translation.)
inline Real translationPlaneFraction(const Plane& plane, const Vec3& a, const Vec3& b) {
  const Real d2 = plane.distance(b);
  if (!signBitSet(d2 - tol::kClipEpsilon)) return 1;
  const Real d1 = plane.distance(a);
  if (signBitSet(d1)) return 1;  // behind (or -0)
  if (d1 - d2 <= 0) return 1;    // not approaching
  return (d1 - tol::kClipEpsilon) / (d1 - d2);
}

/// Fraction at which the trace-model edge line l1, moving along the
/// direction encoded in `cross`, meets the line l2. False when the moving
/// line stays parallel to l2.
bool translateEdgeThroughEdge(const Vec3& cross, const Pluecker& l1, const Pluecker& l2, Real& fraction) {
  const Real d = l2[4] * cross[0] + l2[5] * cross[1] + l2[2] * cross[2];
  if (d == 0) {
    fraction = 0;
    return false;
  }
  const Real t = -l1.permutedInnerProduct(l2);
  if (t == 0) {  // the lines meet at the start already
    fraction = 0;
    return true;
  }
  fraction = t / d;
  return true;
}

void setContact(TraceWork& tw, const CmPolygon& poly, ContactType type, std::int32_t modelFeature,
                int trmFeature) {
  tw.c.contents = poly.contents;
  tw.c.material = poly.material;
  tw.c.type = type;
  tw.c.modelFeature = modelFeature;
  tw.c.trmFeature = trmFeature;
}

}  // namespace

void translatePointThroughPolygon(TraceWork& tw, std::int32_t polyNum, const CmPolygon& poly) {
  const CollisionModel& m = tw.model;
  const WorkVertex& v = tw.vertices[0];
  const Real f = translationPlaneFraction(poly.plane, v.p, v.endp);
  if (!(f < tw.fraction)) return;
  for (std::int32_t edgeNum : m.edgesOf(poly)) {
    const Real product = modelEdgeLine(m, std::size_t(std::abs(edgeNum))).permutedInnerProduct(v.pl);
    if (unsigned(edgeNum < 0) ^ unsigned(signBitSet(product))) return;  // passes the edge on the outside
  }
  tw.fraction = f < 0 ? Real(0) : f;
  tw.c.normal = poly.plane.normal;
  tw.c.dist = poly.plane.dist;
  tw.c.point = v.p + (v.endp - v.p) * tw.fraction;
  setContact(tw, poly, ContactType::TrmVertex, polyNum, 0);
  if (tw.gettingContacts()) tw.addContact();
}

namespace {

/// Room in the scratch for the masks of a polygon's `groups` edge groups.
void sizeEdgeMasks(QueryScratch& s, std::size_t groups) {
  if (s.vertexEdgeSides.size() < groups * kMaxTrmVertices) {
    s.vertexEdgeSides.resize(groups * kMaxTrmVertices);
    s.edgesToTest.resize(groups);
  }
}

// Which side of each edge line of the current polygon the path of every
// moving trace-model vertex passes (see the masks in QueryScratch). A side is
// the sign bit of (edge i's line, stored direction) . (vertex v's line), the
// product the original caches per model edge. It depends only on the edge
// and the vertex, so computing all of a polygon's at once gives the same
// bits as the cache, without its branches and scattered memory. Returns the
// moving vertices whose paths pass inside every edge (on the negative side of
// the edges used backwards, the positive of the others): those the vertex
// test tries. (Two ways: SSE2 float lanes, else one vertex at a time.)
#ifdef CMKIT_SIDES_SSE2

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
  const int numVerts = moving ? 32 - std::countl_zero(moving) : 0;
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

// The common cases, a trace model of at most eight vertices (a box) and a
// polygon of at most eight edges, or at most sixteen vertices (an 8-sided
// cylinder) and four edges, without the transposition: the sides as one
// word, slot i (8 or 16 bits from bit i << shift) for polygon edge i, its bit
// v for vertex v, which the edge pairs read as they are (SmallSides). The
// same products as above, so the same bits.
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
void placeVertexLines(TraceWork& tw) {
  const std::uint32_t moving = tw.movingVertices;
  const int numVerts = moving ? 32 - std::countl_zero(moving) : 0;
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

// A trace-model vertex reaches the polygon at fraction f: the nearest hit so
// far. (The hits are out of line, kept off the tests' path: most tested
// features hit nothing.)
[[gnu::cold, gnu::noinline]] void hitByTrmVertex(TraceWork& tw, std::int32_t polyNum, const CmPolygon& poly,
                                                 int vertexNum, Real f) {
  WorkVertex& v = tw.vertices[std::size_t(vertexNum)];
  tw.fraction = f < 0 ? Real(0) : f;
  tw.c.normal = poly.plane.normal;
  tw.c.dist = poly.plane.dist;
  tw.c.point = v.p + (v.endp - v.p) * tw.fraction;
  setContact(tw, poly, ContactType::TrmVertex, polyNum, vertexNum);
  if (tw.gettingContacts()) {
    tw.addContact();
    v.used = false;  // one contact per trace-model vertex is enough
  }
}

// The trace-model vertices through a polygon, in vertex order: those whose
// paths pass inside every polygon edge (`inside`, from sidesOfPolygonEdges)
// and reach the plane before the nearest hit so far.
void translateTrmVerticesThroughPolygon(TraceWork& tw, std::int32_t polyNum, const CmPolygon& poly,
                                        std::uint32_t inside) {
  count(tw.scratch, &QueryStats::vertexTests, unsigned(std::popcount(tw.movingVertices)));
  for (; inside; inside &= inside - 1) {
    const int vertexNum = std::countr_zero(inside);
    WorkVertex& v = tw.vertices[std::size_t(vertexNum)];
    if (!v.used) continue;
    const Real f = translationPlaneFraction(poly.plane, v.p, v.endp);
    if (!(f < tw.fraction)) continue;
    hitByTrmVertex(tw, polyNum, poly, vertexNum, f);
  }
}

// Which side of trace-model edge te's line the path of a model vertex
// (moving by -dir relative to the trace model) passes: the sign bit of
// te's line . the path's line, always in this order, so that the edge pair
// and the vertex tests agree on every vertex. Computed each time: a
// per-vertex cache cost more (a scattered load and its bookkeeping) than
// the two products.
inline unsigned modelVertexSide(const WorkEdge& te, const Pluecker& path) {
  return unsigned(signBitSet(te.pl.permutedInnerProduct(path)));
}
inline unsigned modelVertexSide(const WorkEdge& te, const Vec3& vertex, const Vec3& dir) {
  return modelVertexSide(te, Pluecker::fromRay(vertex, -dir));
}

// Trace-model edge trmEdgeNum meets model edge edgeNum (of poly) at fraction
// f2: the nearest hit so far.
[[gnu::cold, gnu::noinline]] void hitByEdge(TraceWork& tw, const CmPolygon& poly, std::int32_t edgeNum,
                                            int trmEdgeNum, Real f2) {
  const CollisionModel& m = tw.model;
  const WorkEdge& te = tw.edges[std::size_t(trmEdgeNum)];
  const CmEdge& edge = m.edges()[std::size_t(std::abs(edgeNum))];
  const Vec3& start = m.vertices()[std::size_t(edge.vertex[0])];
  const Vec3& end = m.vertices()[std::size_t(edge.vertex[1])];
  tw.fraction = f2;
  // Contact plane: through the model edge, orthogonal to both edges, facing the trm.
  Vec3 normal = (end - start).cross(te.end - te.start);
  normal.normalize();
  Real dist = normal.dot(start);
  if (normal.dot(te.start) - dist < 0) {
    normal = -normal;
    dist = -dist;
  }
  tw.c.normal = normal;
  tw.c.dist = dist;
  // Contact point on the model edge: where the plane swept by the trm edge cuts it.
  const Vec3 sweepNormal{te.cross[2], -te.cross[1], te.cross[0]};
  const Real sweepDist = sweepNormal.dot(te.start);
  const Real d1 = sweepNormal.dot(start) - sweepDist;
  const Real d2 = sweepNormal.dot(end) - sweepDist;
  const Real t = std::fabs(d1 - d2) > std::numeric_limits<Real>::epsilon() ? d1 / (d1 - d2) : Real(0);
  tw.c.point = start + (end - start) * t;
  setContact(tw, poly, ContactType::Edge, edgeNum, trmEdgeNum);
  if (tw.gettingContacts()) tw.addContact();
}

// Trace-model edge trmEdgeNum against edge i of the polygon (from v1 to v2
// in the polygon's order), whose line both pairs of vertices pass on
// different sides: where they meet.
[[gnu::noinline]] void translateTrmEdgeThroughCrossedEdge(TraceWork& tw, const CmPolygon& poly,
                                                          const PolygonEdges& edges, int trmEdgeNum,
                                                          std::size_t i, const Vec3& v1, const Vec3& v2) {
  const CollisionModel& m = tw.model;
  const WorkEdge& te = tw.edges[std::size_t(trmEdgeNum)];
  const std::int32_t edgeNum = edges.edgeNum(i);
  const Vec3& start = edgeNum < 0 ? v2 : v1;  // (the edge's stored direction)
  const Vec3& end = edgeNum < 0 ? v1 : v2;
  Real f1;
  if (!translateEdgeThroughEdge(te.cross, te.pl, edges.line(i), f1)) return;
  if (f1 < 0) return;  // moving away from the edge
  // The same against the edge moved out along its normal by the clip epsilon.
  const CmEdge& edge = m.edges()[std::size_t(std::abs(edgeNum))];
  const Pluecker epsPl =
      Pluecker::fromLine(start + edge.normal * tol::kClipEpsilon, end + edge.normal * tol::kClipEpsilon);
  Real f2;
  if (!translateEdgeThroughEdge(te.cross, te.pl, epsPl, f2)) return;
  if (f2 > 1 || f1 < f2) return;
  if (f2 < 0) f2 = 0;
  if (!(f2 < tw.fraction)) return;

  hitByEdge(tw, poly, edgeNum, trmEdgeNum, f2);
}

// Trace-model edge trmEdgeNum against edge i of the polygon, whose line
// its two vertices pass on different sides. (The polygon edge's side test
// inline: about half the pairs end there.)
inline void translateTrmEdgeThroughEdge(TraceWork& tw, const CmPolygon& poly, const PolygonEdges& edges,
                                        int trmEdgeNum, std::size_t i) {
  count(tw.scratch, &QueryStats::edgePairs);
  const WorkEdge& te = tw.edges[std::size_t(trmEdgeNum)];
  // The polygon edge's two vertices must pass the trm edge on different sides.
  const Vec3& v1 = edges.from(i);
  const Vec3& v2 = edges.to(i);
  if (modelVertexSide(te, v1, tw.dir) == modelVertexSide(te, v2, tw.dir)) return;
  translateTrmEdgeThroughCrossedEdge(tw, poly, edges, trmEdgeNum, i, v1, v2);
}

/// The pairs of one mask of polygon edges: each moving trace-model edge's
/// crossed polygon edges (crossed(te), a mask) found first, without a branch
/// per trace-model edge (most edges cross none of a polygon's edge lines,
/// unpredictably), then tested trace-model edge by edge, bit b of a mask
/// standing for polygon edge edgeOf(b).
template <class Crossed, class EdgeOf>
void testCrossedEdgePairs(TraceWork& tw, const CmPolygon& poly, const PolygonEdges& edges, Crossed crossed,
                          EdgeOf edgeOf) {
  std::uint64_t crossing[kMaxTrmEdges + 1];
  std::uint8_t crossingEdge[kMaxTrmEdges + 1];
  std::size_t n = 0;
  for (std::uint64_t moving = tw.movingEdges; moving; moving &= moving - 1) {
    const int e = std::countr_zero(moving);
    const std::uint64_t c = crossed(tw.edges[std::size_t(e)]);
    crossing[n] = c;
    crossingEdge[n] = std::uint8_t(e);
    n += c != 0;
  }
  for (std::size_t k = 0; k < n; ++k)
    for (std::uint64_t c = crossing[k]; c; c &= c - 1)
      translateTrmEdgeThroughEdge(tw, poly, edges, crossingEdge[k], edgeOf(std::countr_zero(c)));
}

// The moving trace-model edges against the polygon edges to test, trace-model
// edge by edge, each against the polygon edges whose line its two vertices
// pass on different sides, in their order (testCrossedEdgePairs, group by
// group of the per-vertex masks).
void translateTrmEdgesThroughPolygon(TraceWork& tw, const CmPolygon& poly, const PolygonEdges& edges) {
  const QueryScratch& s = tw.scratch;
  const std::size_t groups = edgeGroups(edges.size);
  for (std::size_t g = 0; g < groups; ++g) {
    const std::uint64_t* sides = &s.vertexEdgeSides[g * kMaxTrmVertices];
    const std::uint64_t toTest = s.edgesToTest[g];
    testCrossedEdgePairs(
        tw, poly, edges,
        [sides, toTest](const WorkEdge& te) {
          return (sides[std::size_t(te.vertexNum[0])] ^ sides[std::size_t(te.vertexNum[1])]) & toTest;
        },
        [first = g * kEdgeGroup](int b) { return first + std::size_t(b); });
  }
}

// A model vertex (at p, moving to endp relative to the trace model; its
// number, the contact's feature, from its edge's record) reaches trace-model
// polygon trmPolyNum at fraction f: the nearest hit so far.
[[gnu::cold, gnu::noinline]] void hitByModelVertex(TraceWork& tw, const CmPolygon& poly, int trmPolyNum,
                                                   ModelVertexRef vertex, const Vec3& p, const Vec3& endp,
                                                   Real f) {
  const std::size_t vertexNum = modelVertexNumber(tw.model, vertex);
  const WorkPolygon& tp = tw.polys[std::size_t(trmPolyNum)];
  tw.fraction = f < 0 ? Real(0) : f;
  tw.c.normal = -tp.plane.normal;
  tw.c.dist = -tp.plane.dist;
  // The original reports the vertex moved back by the fraction: the model
  // vertex relative to the trace model at its start (see docs/fidelity.md).
  tw.c.point = p + (endp - p) * tw.fraction;
  setContact(tw, poly, ContactType::ModelVertex, std::int32_t(vertexNum), trmPolyNum);
  if (tw.gettingContacts()) tw.addContact();
}

// The last of a polygon's tests (below).
bool testModelVerticesThroughTrm(TraceWork& tw, const CmPolygon& poly, const PolygonEdges& edges);

#ifdef CMKIT_SIDES_SSE2
// translateTrmEdgesThroughPolygon for the small path: a trace-model edge
// crosses polygon edge i's line when its vertices' bits in slot i differ
// (shifted down by a vertex number, slot i's bit lands at its first bit, the
// slots above landing above it); `toTest` has slot i's first bit for each
// edge to test. The same pairs in the same order.
template <unsigned kShift>
void translateTrmEdgesThroughSmallPolygon(TraceWork& tw, const CmPolygon& poly, const PolygonEdges& edges,
                                          const SmallSides& sides, std::uint64_t toTest) {
  testCrossedEdgePairs(
      tw, poly, edges,
      [slots = sides.slots, toTest](const WorkEdge& te) {
        return ((slots >> te.vertexNum[0]) ^ (slots >> te.vertexNum[1])) & toTest;
      },
      [](int b) { return std::size_t(b) >> kShift; });
}

/// The polygon's tests on the small path (slots of 1 << kShift bits); true
/// when it blocks completely.
template <unsigned kShift>
bool translateTrmThroughSmallPolygon(TraceWork& tw, std::int32_t polyNum, const CmPolygon& poly,
                                     const PolygonEdges& edges) {
  const QueryScratch& s = tw.scratch;
  const SmallSides sides = sidesOfSmallPolygonEdges<kShift>(tw, edges);
  std::uint64_t toTest = 0;  // slot i's first bit: edge i (as the general path's masks)
  if (tw.numEdges > 0)
    for (std::size_t i = 0; i < edges.size; ++i) {
      const std::size_t e = std::size_t(std::abs(edges.edgeNum(i)));
      toTest |= std::uint64_t(unsigned(!s.isChecked(s.edgeChecked, e)) & unsigned(!edges.internal(i)))
                << (i << kShift);
    }
  translateTrmVerticesThroughPolygon(tw, polyNum, poly, sides.inside);
  if (toTest) translateTrmEdgesThroughSmallPolygon<kShift>(tw, poly, edges, sides, toTest);
  return testModelVerticesThroughTrm(tw, poly, edges);
}
#endif

// (The vertex's path line only for a trace-model polygon it reaches in time:
// most reach none.)
void translateVertexThroughTrmPolygon(TraceWork& tw, const CmPolygon& poly, int trmPolyNum,
                                      ModelVertexRef vertex, const Vec3& p, const Vec3& endp) {
  QueryScratch& s = tw.scratch;
  count(s, &QueryStats::vertexTests);
  const WorkPolygon& tp = tw.polys[std::size_t(trmPolyNum)];
  const Real f = translationPlaneFraction(tp.plane, p, endp);
  if (!(f < tw.fraction)) return;
  const Pluecker pl = Pluecker::fromRay(p, -tw.dir);
  for (int i = 0; i < tp.source->numEdges; ++i) {
    const int edgeNum = tp.source->edges[std::size_t(i)];
    const WorkEdge& te = tw.edges[std::size_t(std::abs(edgeNum))];
    if (unsigned(edgeNum < 0) ^ modelVertexSide(te, pl)) return;
  }
  hitByModelVertex(tw, poly, trmPolyNum, vertex, p, endp, f);
}

}  // namespace

void shrinkTraceBounds(TraceWork& tw) {
  if (tw.fraction < 1 && !tw.gettingContacts()) {
    const Vec3 endp = tw.start + tw.dir * tw.fraction;
    for (int i = 0; i < 3; ++i) {  // (as in the set-up: min/max, not branches)
      tw.bounds.min[i] = std::min(tw.start[i], endp[i]) + tw.size.min[i] - tol::kBoxEpsilon;
      tw.bounds.max[i] = std::max(tw.start[i], endp[i]) + tw.size.max[i] + tol::kBoxEpsilon;
    }
  }
}

namespace {

// The moving features' data that only a polygon past its culls needs, once
// per query: the vertices' paths, the edges' vertex numbers, lines and sweep
// directions, the front polygons' planes.
void placeTranslationFeatures(TraceWork& tw) {
  if (tw.featuresPlaced) return;
  tw.featuresPlaced = true;
#ifdef CMKIT_SIDES_SSE2
  placeVertexLines(tw);  // (WorkVertex::pl unused: the edge sides read the lanes)
#else
  for (std::uint32_t moving = tw.movingVertices; moving; moving &= moving - 1) {
    WorkVertex& v = tw.vertices[std::size_t(std::countr_zero(moving))];
    v.pl = Pluecker::fromRay(v.p, tw.dir);
  }
#endif
  const TraceModel& trm = *tw.placedTrm;
  for (std::uint64_t moving = tw.movingEdges; moving; moving &= moving - 1) {
    const int i = std::countr_zero(moving);
    WorkEdge& e = tw.edges[std::size_t(i)];
    e.vertexNum[0] = trm.edgeVertex(i, 0);
    e.vertexNum[1] = trm.edgeVertex(i, 1);
    const Vec3 start = tw.vertices[std::size_t(e.vertexNum[0])].p;  // (locals: as placeTrmEdges)
    const Vec3 end = tw.vertices[std::size_t(e.vertexNum[1])].p;
    e.start = start;
    e.end = end;
    e.pl = Pluecker::fromLine(start, end);
    const Vec3 a = start - end;
    e.cross = {a[0] * tw.dir[1] - a[1] * tw.dir[0], a[0] * tw.dir[2] - a[2] * tw.dir[0],
               a[1] * tw.dir[2] - a[2] * tw.dir[1]};
  }
  for (std::uint32_t moving = tw.movingPolygons; moving; moving &= moving - 1) {
    WorkPolygon& wp = tw.polys[std::size_t(std::countr_zero(moving))];
    wp.plane.fitThroughPoint(tw.vertices[std::size_t(wp.planeVertex)].p);
  }
}

}  // namespace

bool translateTrmThroughPolygon(TraceWork& tw, std::int32_t polyNum, const CmPolygon& poly,
                                const PolygonCorner* corners) {
  QueryScratch& s = tw.scratch;
  if (const PlaneCull cull = cullByPolygonPlane(tw, poly.plane); cull != PlaneCull::Test)
    return cull == PlaneCull::Stop;
  count(s, &QueryStats::polygonsTested);
  placeTranslationFeatures(tw);
  // The sides of the polygon's edge lines the trace-model vertices pass.
  const PolygonEdges edges = corners ? polygonEdges(tw, corners, poly.numEdges) : polygonEdges(tw, poly);
#ifdef CMKIT_SIDES_SSE2
  switch (smallSidesShift(tw, edges.size)) {
    case 3:
      return translateTrmThroughSmallPolygon<3>(tw, polyNum, poly, edges);
    case 4:
      return translateTrmThroughSmallPolygon<4>(tw, polyNum, poly, edges);
    default:
      break;
  }
#endif
  const std::uint32_t inside = sidesOfPolygonEdges(tw, edges);
  // The polygon edges the trace-model edges are tested against: not
  // internal, not tested with an earlier polygon (the marks are set below,
  // after the edge tests, so these masks hold for every trace-model edge).
  bool anyToTest = false;
  if (tw.numEdges > 0) {
    for (std::size_t first = 0; first < edges.size; first += kEdgeGroup) {
      std::uint64_t toTest = 0;
      for (std::size_t i = first; i < std::min(first + kEdgeGroup, edges.size); ++i) {
        const std::size_t e = std::size_t(std::abs(edges.edgeNum(i)));
        // (& not &&: whether an edge was met before is unpredictable.)
        toTest |= std::uint64_t(unsigned(!s.isChecked(s.edgeChecked, e)) & unsigned(!edges.internal(i)))
                  << (i - first);
      }
      s.edgesToTest[first / kEdgeGroup] = toTest;
      anyToTest |= toTest != 0;
    }
  }

  translateTrmVerticesThroughPolygon(tw, polyNum, poly, inside);
  if (anyToTest) translateTrmEdgesThroughPolygon(tw, poly, edges);
  return testModelVerticesThroughTrm(tw, poly, edges);
}

namespace {

// The last of a polygon's tests: the model vertices through the trace
// model's front polygons; then the bounds shrink to a nearer hit. True when
// the polygon blocks completely.
bool testModelVerticesThroughTrm(TraceWork& tw, const CmPolygon& poly, const PolygonEdges& edges) {
  // Model vertices through the trace model's front polygons. A vertex
  // farther from a heart plane than its limit is left out: its path (along
  // the move, so parallel to both planes) stays at that distance, and every
  // point of a front polygon is within the farthest moving vertex's distance,
  // a kBoxEpsilon (one unit) short of the limit, so the path meets none of
  // them (the margin dwarfs the rounding of the side products). On the shared
  // reference translations this leaves out one test in eight of a model vertex
  // against a front polygon (a plane fraction and its unpredictable branch):
  // translations about 1.02x-1.03x with bench/ab.py. (Every caller's culls
  // made the heart planes already; the guard keeps this cull from ever
  // reading planes not made.)
  if (!tw.heartPlanesMade) makeTranslationHeartPlanes(tw);
  forEachNewModelVertex(tw, edges, [&](ModelVertexRef vn, const Vec3& p) {
    // (| not ||: which vertices are left out is unpredictable.)
    if (int(std::fabs(tw.heartPlane1.distance(p)) > tw.maxDistFromHeartPlane1) |
        int(std::fabs(tw.heartPlane2.distance(p)) > tw.maxDistFromHeartPlane2))
      return;
    const Vec3 endp = p - tw.dir;
    for (std::uint32_t moving = tw.movingPolygons; moving; moving &= moving - 1)
      translateVertexThroughTrmPolygon(tw, poly, std::countr_zero(moving), vn, p, endp);
  });

  shrinkTraceBounds(tw);
  return tw.fraction == 0;
}

}  // namespace

}  // namespace cmkit::detail
