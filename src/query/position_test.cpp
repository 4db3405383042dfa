// Position tests (the original's TestTrmVertsInBrush, TestTrmInPolygon and
// the position-test set-up of ContentsTrm).
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <span>

#include "query/cull_lanes.h"
#include "query/polygon_edges.h"
#include "query/trace_work.h"

namespace cmkit::detail {

namespace {

/// The trace model's edges' vertex numbers and its polygons' planes for a
/// position test, once (most position tests meet no polygon past its
/// culls); the edges' lines each when first read (placedEdge).
void placePositionTestFeatures(TraceWork& tw) {
  if (tw.featuresPlaced) return;
  tw.featuresPlaced = true;
  placeTrmTopology(tw, *tw.placedTrm, *tw.placedOrientation);
  for (int i = 0; i < tw.numPolys; ++i) {
    WorkPolygon& wp = tw.polys[std::size_t(i)];
    wp.used = true;
    wp.plane.fitThroughPoint(tw.vertices[std::size_t(wp.planeVertex)].p);
#ifdef CMKIT_QUERY_LANES
    // (And as rows, four planes at a time, for the polygon test's edges.)
    TrmPlaneRows& rows = tw.scratch.trm.planeRows[std::size_t(i / 4)];
    rows.x[i % 4] = wp.plane.normal.x;
    rows.y[i % 4] = wp.plane.normal.y;
    rows.z[i % 4] = wp.plane.normal.z;
    rows.dist[i % 4] = wp.plane.dist;
#endif
  }
}

/// Trace-model edge i with its line (Pluecker::fromLine from its first
/// vertex to its second), made on first use. (A position test reads no
/// edge's ends.)
const WorkEdge& placedEdge(TraceWork& tw, int i) {
  WorkEdge& e = tw.edges[std::size_t(i)];
  if (!((tw.edgeLinesPlaced >> i) & 1u)) {
    tw.edgeLinesPlaced |= std::uint64_t(1) << i;
    e.pl = Pluecker::fromLine(tw.vertices[std::size_t(e.vertexNum[0])].p,
                              tw.vertices[std::size_t(e.vertexNum[1])].p);
  }
  return e;
}

/// Which side of trace-model edge te's line a model edge's line passes: the
/// sign bit of their product, always in this order (both tests of a
/// polygon ask it). Computed each time: a per-edge cache cost more (a
/// scattered load and its bookkeeping) than the product.
unsigned edgeLineSide(const WorkEdge& te, const Pluecker& modelEdge) {
  return unsigned(signBitSet(te.pl.permutedInnerProduct(modelEdge)));
}

// "A point inside a convex set of planes" (a trace-model vertex in a brush,
// a model vertex in a convex trace model): behind every plane (a distance
// >= 0 on any puts it outside; a NaN distance does not), and where it is,
// the plane nearest it (the first of the largest distances), as the
// original's loops find them.

/// Whether p is behind every plane planeAt(0 .. numPlanes - 1).
template <class PlaneAt>
bool behindEveryPlane(const Vec3& p, int numPlanes, PlaneAt planeAt) {
  for (int i = 0; i < numPlanes; ++i)
    if (planeAt(i).distance(p) >= 0) return false;
  return true;
}

/// The plane nearest p, a point behind every plane: the first of the
/// largest distances (0 when none is above -kBoundsInfinity).
template <class PlaneAt>
int nearestPlaneBehind(const Vec3& p, int numPlanes, PlaneAt planeAt) {
  int best = 0;
  Real bestd = -tol::kBoundsInfinity;
  for (int i = 0; i < numPlanes; ++i) {
    const Real d = planeAt(i).distance(p);
    if (d > bestd) {
      bestd = d;
      best = i;
    }
  }
  return best;
}

#ifdef CMKIT_QUERY_LANES
/// Four points at once (rows x, y, z; lane j point j): the lanes (bit j)
/// that some plane has on or in front of it, from `out` (lanes already
/// out: unused ones), Plane::distance's arithmetic in each lane; stops at
/// the plane that puts the last lane out.
template <class PlaneAt>
unsigned lanesNotBehindPlanes(F4 x, F4 y, F4 z, unsigned out, int numPlanes, PlaneAt planeAt) {
  for (int i = 0; i < numPlanes && out != 0xFu; ++i) {
    const Plane& pl = planeAt(i);
    const F4 d =
        F4::all(pl.normal.x) * x + F4::all(pl.normal.y) * y + F4::all(pl.normal.z) * z - F4::all(pl.dist);
    out |= simd::bits(d >= F4::zero());
  }
  return out;
}
#endif

}  // namespace

namespace {

// A brush past the culls of testTrmVertsInBrushes: true (stuck) when a
// trace-model vertex is inside it (the first in vertex order; four at a
// time where there are float lanes).
bool trmVertexInBrush(TraceWork& tw, const CmBrush& b) {
  const auto planes = tw.model.planesOf(b);
  if (planes.empty()) return false;
  const auto planeAt = [&planes](int i) -> const Plane& { return planes[std::size_t(i)]; };
  const int numPlanes = int(planes.size());
  const int numVerts = tw.numVerts;  // a position test always has a trace model (points: pointContents)
  int j = 0;
#ifdef CMKIT_QUERY_LANES
  for (; j < numVerts; j += 4) {
    F4 x, y, z;
    trmVertexRows(tw, j / 4, x, y, z);
    const unsigned out =
        lanesNotBehindPlanes(x, y, z, ~lowBits(std::min(numVerts - j, 4)) & 0xFu, numPlanes, planeAt);
    if (out != 0xFu) {
      j += std::countr_zero(~out);
      break;
    }
  }
#else
  while (j < numVerts && !behindEveryPlane(tw.vertices[std::size_t(j)].p, numPlanes, planeAt)) ++j;
#endif
  if (j >= numVerts) return false;
  const Vec3& p = tw.vertices[std::size_t(j)].p;
  const Plane& nearest = planes[std::size_t(nearestPlaneBehind(p, numPlanes, planeAt))];
  tw.fraction = 0;
  tw.c.type = ContactType::TrmVertex;
  tw.c.normal = nearest.normal;
  tw.c.dist = nearest.dist;
  tw.c.contents = b.contents;
  tw.c.material = b.material;
  tw.c.point = p;
  tw.c.modelFeature = 0;
  tw.c.trmFeature = j;
  return true;
}

// A polygon past the culls of testTrmInPolygons: true when the trace model
// crosses it (stuck).
bool trmCrossesPolygon(TraceWork& tw, std::int32_t polyNum, const CmPolygon& poly) {
  const CollisionModel& m = tw.model;
  QueryScratch& s = tw.scratch;
  count(s, &QueryStats::polygonsTested);
  placePositionTestFeatures(tw);
  const auto edges = m.edgesOf(poly);
  auto stuck = [&](ContactType type, const Vec3& normal, Real dist, const Vec3& point,
                   std::int32_t modelFeature, int trmFeature) {
    count(s, &QueryStats::polygonsCloser);
    tw.fraction = 0;
    tw.c.type = type;
    tw.c.normal = normal;
    tw.c.dist = dist;
    tw.c.contents = poly.contents;
    tw.c.material = poly.material;
    tw.c.point = point;
    tw.c.modelFeature = modelFeature;
    tw.c.trmFeature = trmFeature;
    return true;
  };
  const auto trmPlane = [&tw](int k) -> const Plane& { return tw.polys[std::size_t(k)].plane; };

  // 1. (convex trm) a polygon vertex strictly behind every trm polygon
  // plane: the first such in the order of the polygon's edges.
  if (tw.isConvex) {
    std::size_t inside = 0;
    bool found = false;
#ifdef CMKIT_QUERY_LANES
    // Four vertices at a time, in that order.
    alignas(16) float xs[4] = {}, ys[4] = {}, zs[4] = {};
    std::size_t numbers[4] = {};
    int n = 0;
    const auto testBlock = [&] {
      const unsigned out = lanesNotBehindPlanes(F4::load(xs), F4::load(ys), F4::load(zs), ~lowBits(n) & 0xFu,
                                                tw.numPolys, trmPlane);
      n = 0;
      if (out == 0xFu) return false;
      inside = numbers[std::countr_zero(~out)];
      return found = true;
    };
#endif
    for (std::size_t i = 0; i < edges.size() && !found; ++i) {
      const std::size_t e = std::size_t(std::abs(edges[i]));
      if (s.isChecked(s.edgeChecked, e)) continue;
      for (int j = 0; j < 2 && !found; ++j) {
        const std::size_t vn = std::size_t(m.edges()[e].vertex[j]);
        if (s.isChecked(s.vertexChecked, vn)) continue;
#ifdef CMKIT_QUERY_LANES
        const Vec3& p = m.vertices()[vn];
        xs[n] = p.x;
        ys[n] = p.y;
        zs[n] = p.z;
        numbers[n] = vn;
        if (++n == 4) testBlock();
#else
        if (behindEveryPlane(m.vertices()[vn], tw.numPolys, trmPlane)) {
          inside = vn;
          found = true;
        }
#endif
      }
    }
#ifdef CMKIT_QUERY_LANES
    if (!found && n > 0) testBlock();
#endif
    if (found) {
      const Vec3& p = m.vertices()[inside];
      const Plane& pl = trmPlane(nearestPlaneBehind(p, tw.numPolys, trmPlane));
      return stuck(ContactType::ModelVertex, -pl.normal, -pl.dist, p, std::int32_t(inside), 0);
    }
  }
  setPolygonEdgeLines(tw, poly);
  for (const std::int32_t edgeNum : edges) s.mark(s.vertexChecked, std::size_t(m.edgeStart(edgeNum)));

  // 2. a trm edge crossing the polygon plane inside all polygon edges. Bit
  // v of `behind`: trace-model vertex v lies behind the polygon's plane.
  std::uint32_t behind = 0;
#ifdef CMKIT_QUERY_LANES
  {
    const F4 nx = F4::all(poly.plane.normal.x), ny = F4::all(poly.plane.normal.y),
             nz = F4::all(poly.plane.normal.z), dist = F4::all(poly.plane.dist);
    for (int k = 0; 4 * k < tw.numVerts; ++k) {
      F4 x, y, z;
      trmVertexRows(tw, k, x, y, z);
      behind |= std::uint32_t(simd::bits(nx * x + ny * y + nz * z - dist < F4::zero())) << (4 * k);
    }
    behind &= allTrmVertices(tw.numVerts);
  }
#else
  for (int i = 0; i < tw.numVerts; ++i)
    behind |= std::uint32_t(poly.plane.distance(tw.vertices[std::size_t(i)].p) < 0) << i;
#endif
  for (int i = 1; i <= tw.numEdges; ++i) {
    const WorkEdge& topology = tw.edges[std::size_t(i)];
    const unsigned flip = (behind >> topology.vertexNum[0]) & 1u;
    if (flip == ((behind >> topology.vertexNum[1]) & 1u)) continue;
    const WorkEdge& te = placedEdge(tw, i);
    std::size_t j = 0;
    for (; j < edges.size(); ++j) {
      const std::int32_t edgeNum = edges[j];
      const unsigned side = edgeLineSide(te, s.polygonEdgeLines[j]);
      if (unsigned(edgeNum < 0) ^ side ^ flip) break;
    }
    if (j >= edges.size()) {
      return stuck(ContactType::Edge, poly.plane.normal, poly.plane.dist,
                   tw.vertices[std::size_t(te.vertexNum[flip ? 0 : 1])].p, polyNum, i);
    }
  }

  // 3. a polygon edge crossing a trm polygon plane inside that polygon's
  // edges (trm polygons in order; where there are float lanes, each edge's
  // two ends against four planes at a time).
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const std::int32_t edgeNum = edges[i];
    const std::size_t e = std::size_t(std::abs(edgeNum));
    if (s.testAndMark(s.edgeChecked, e)) continue;
    const CmEdge& edge = m.edges()[e];
    const std::size_t v1 = std::size_t(edge.vertex[0]), v2 = std::size_t(edge.vertex[1]);
    // Trace-model polygon j, whose plane the edge crosses (flip: from
    // behind): true when it crosses inside the polygon's edges.
    const auto crossesInside = [&](int j, unsigned flip) {
      const WorkPolygon& tp = tw.polys[std::size_t(j)];
      for (int k = 0; k < tp.source->numEdges; ++k) {
        const int trmEdgeNum = tp.source->edges[std::size_t(k)];
        const WorkEdge& te = placedEdge(tw, std::abs(trmEdgeNum));
        const unsigned side = edgeLineSide(te, s.polygonEdgeLines[i]);
        if (unsigned(trmEdgeNum < 0) ^ side ^ flip) return false;
      }
      return true;
    };
    // (side = distance < 0, not the sign bit: -0 counts as in front)
#ifdef CMKIT_QUERY_LANES
    const Vec3& p1 = m.vertices()[v1];
    const Vec3& p2 = m.vertices()[v2];
    const F4 x1 = F4::all(p1.x), y1 = F4::all(p1.y), z1 = F4::all(p1.z);
    const F4 x2 = F4::all(p2.x), y2 = F4::all(p2.y), z2 = F4::all(p2.z);
    for (int first = 0; first < tw.numPolys; first += 4) {
      const TrmPlaneRows& rows = tw.scratch.trm.planeRows[std::size_t(first / 4)];
      const F4 nx = F4::load(rows.x), ny = F4::load(rows.y), nz = F4::load(rows.z), d = F4::load(rows.dist);
      const unsigned s1 = simd::bits(nx * x1 + ny * y1 + nz * z1 - d < F4::zero());
      const unsigned s2 = simd::bits(nx * x2 + ny * y2 + nz * z2 - d < F4::zero());
      for (unsigned crossing = (s1 ^ s2) & lowBits(std::min(tw.numPolys - first, 4)); crossing;
           crossing &= crossing - 1) {
        const int lane = std::countr_zero(crossing);
        const unsigned flip = (s1 >> lane) & 1u;
        const int j = first + lane;
        if (crossesInside(j, flip))
          return stuck(ContactType::Edge, -trmPlane(j).normal, -trmPlane(j).dist,
                       m.vertices()[flip ? v2 : v1], edgeNum, j);
      }
    }
#else
    for (int j = 0; j < tw.numPolys; ++j) {
      const unsigned s1 = unsigned(trmPlane(j).distance(m.vertices()[v1]) < 0);
      const unsigned s2 = unsigned(trmPlane(j).distance(m.vertices()[v2]) < 0);
      if (s1 == s2) continue;
      if (crossesInside(j, s1))
        return stuck(ContactType::Edge, -trmPlane(j).normal, -trmPlane(j).dist, m.vertices()[s1 ? v2 : v1],
                     edgeNum, j);
    }
#endif
  }
  return false;
}

}  // namespace

bool testTrmVertsInBrushes(TraceWork& tw, std::span<const std::int32_t> brushes) {
  QueryScratch& s = tw.scratch;
  return forEachNewItem(s, s.brushChecked, &QueryStats::brushesMet, brushes, [&](std::int32_t brushNum) {
    const CmBrush& b = tw.model.brushes()[std::size_t(brushNum)];
    return (b.contents & tw.contentMask) && b.bounds.intersects(tw.bounds) && trmVertexInBrush(tw, b);
  });
}

bool testTrmInPolygons(TraceWork& tw, std::span<const std::int32_t> polygons) {
  QueryScratch& s = tw.scratch;
  return forEachNewItem(s, s.polygonChecked, &QueryStats::polygonsMet, polygons, [&](std::int32_t polyNum) {
    const CmPolygon& poly = tw.model.polygons()[std::size_t(polyNum)];
    if (!(poly.contents & tw.contentMask) || !poly.bounds.intersects(tw.bounds)) return false;
    if (const PlaneCull cull = cullByPolygonPlane(tw, poly.plane); cull != PlaneCull::Test)
      return cull == PlaneCull::Stop;
    return trmCrossesPolygon(tw, polyNum, poly);
  });
}

#ifdef CMKIT_QUERY_LANES
namespace {

/// What a position test adds to walkCullBlocks: the plane test and the
/// polygon test (a position test's bounds never change).
struct PositionCullBlocks {
  static constexpr bool kShrinks = false;
  static unsigned blockPass(const TraceWork&, const CullBlock&) { return 0xFu; }
  static bool test(TraceWork& tw, std::int32_t polyNum, const CmPolygon& poly) {
    if (const PlaneCull cull = cullByPolygonPlane(tw, poly.plane); cull != PlaneCull::Test)
      return cull == PlaneCull::Stop;
    return trmCrossesPolygon(tw, polyNum, poly);
  }
};

}  // namespace
#endif

bool testTrmInNodePolygons(TraceWork& tw, const CmNode& node) {
#ifdef CMKIT_QUERY_LANES
  // The contents and bounds culls four polygons at a time from the node's
  // cull blocks. Only the polygons past them are marked: a position test's
  // bounds do not change, so a polygon culled here is culled at every node
  // listing it, and the polygons tested, and their order, are those of
  // testTrmInPolygons.
  if (tw.queryData) return walkCullBlocks<PositionCullBlocks>(tw, *tw.queryData, node);
#endif
  return testTrmInPolygons(tw, tw.model.polygonsAt(node));
}

namespace {

/// Places the trace model's vertices at the position (placeTrmVertices)
/// and returns their extent from the centre: Bounds::addPoint of each
/// p - start, from empty bounds. An unturned trace model's in one loop, in
/// locals (read back through tw, each vertex would wait for its stores).
Bounds placeVerticesAndExtent(TraceWork& tw, const TraceModel& trm, const Orientation& o,
                              const Vec3& position) {
  Bounds size;
  const Vec3 start = tw.start;
  if (o.trmRotated || o.modelRotated) {
    placeTrmVertices(tw, trm, o, position, allTrmVertices(tw.numVerts));
    for (int i = 0; i < tw.numVerts; ++i) size.addPoint(tw.vertices[std::size_t(i)].p - start);
    return size;
  }
  const Vec3 relative = position - o.placement->origin;
  for (int i = 0; i < tw.numVerts; ++i) {
    const Vec3 p = placedTrmVertex(trm, o, i, relative);
    Vec3& v = tw.vertices[std::size_t(i)].p;
    v.x = p.x;
    v.y = p.y;
    v.z = p.z;
    size.addPoint(p - start);
  }
  return size;
}

}  // namespace

void setupPositionTest(TraceWork& tw, const TraceModel& trm, const Orientation& o, const Vec3& position,
                       std::uint32_t mask) {
  tw.fraction = 1;
  tw.c = ContactInfo{};
  tw.contentMask = mask;
  tw.isConvex = trm.isConvex();
  tw.pointTrace = false;
  tw.quickExit = false;
  placeTrmFrame(tw, trm, o, position);
  tw.placedTrm = &trm;  // the edges and polygons: placePositionTestFeatures
  tw.placedOrientation = &o;
  tw.end = tw.start;
  tw.size = placeVerticesAndExtent(tw, trm, o, position);
  tw.featuresPlaced = false;
  for (int i = 0; i < 3; ++i) {
    tw.extents[i] = (std::fabs(tw.size.min[i]) > std::fabs(tw.size.max[i]) ? std::fabs(tw.size.min[i])
                                                                           : std::fabs(tw.size.max[i])) +
                    tol::kBoxEpsilon;
    tw.bounds.min[i] = tw.start[i] + tw.size.min[i] - tol::kBoxEpsilon;
    tw.bounds.max[i] = tw.start[i] + tw.size.max[i] + tol::kBoxEpsilon;
  }
}

}  // namespace cmkit::detail
