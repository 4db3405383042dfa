// Position tests (the original's TestTrmVertsInBrush, TestTrmInPolygon and
// the position-test set-up of ContentsTrm).
#include <cmath>
#include <span>

#include "query/cull_lanes.h"
#include "query/polygon_edges.h"
#include "query/trace_work.h"

namespace cmkit::detail {

namespace {

/// The trace model's edges, edge lines and polygon planes for a position
/// test, once (most position tests meet no polygon past its culls).
void placePositionTestFeatures(TraceWork& tw) {
  if (tw.featuresPlaced) return;
  tw.featuresPlaced = true;
  placeTrmTopology(tw, *tw.placedTrm, *tw.placedOrientation);
  placeTrmEdges(tw);
  for (int i = 0; i < tw.numPolys; ++i) {
    WorkPolygon& wp = tw.polys[std::size_t(i)];
    wp.used = true;
    wp.plane.fitThroughPoint(tw.vertices[std::size_t(wp.planeVertex)].p);
  }
}

/// Which side of trace-model edge te's line a model edge's line passes: the
/// sign bit of their product, always in this order (both tests of a
/// polygon ask it). Computed each time: a per-edge cache cost more (a
/// scattered load and its bookkeeping) than the product.
unsigned edgeLineSide(const WorkEdge& te, const Pluecker& modelEdge) {
  return unsigned(signBitSet(te.pl.permutedInnerProduct(modelEdge)));
}

}  // namespace

namespace {

// A brush past the culls of testTrmVertsInBrushes: true (stuck) when a
// trace-model vertex is inside it.
bool trmVertexInBrush(TraceWork& tw, const CmBrush& b) {
  const auto planes = tw.model.planesOf(b);
  const int numVerts = tw.numVerts;  // a position test always has a trace model (points: pointContents)
  for (int j = 0; j < numVerts; ++j) {
    const Vec3& p = tw.vertices[std::size_t(j)].p;
    // Inside when behind every plane; remember the nearest plane.
    std::size_t bestPlane = 0;
    Real bestd = -tol::kBoundsInfinity;
    std::size_t i = 0;
    for (; i < planes.size(); ++i) {
      const Real d = planes[i].distance(p);
      if (d >= 0) break;
      if (d > bestd) {
        bestd = d;
        bestPlane = i;
      }
    }
    if (i < planes.size() || planes.empty()) continue;
    tw.fraction = 0;
    tw.c.type = ContactType::TrmVertex;
    tw.c.normal = planes[bestPlane].normal;
    tw.c.dist = planes[bestPlane].dist;
    tw.c.contents = b.contents;
    tw.c.material = b.material;
    tw.c.point = p;
    tw.c.modelFeature = 0;
    tw.c.trmFeature = j;
    return true;
  }
  return false;
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

  // 1. (convex trm) a polygon vertex strictly behind every trm polygon plane.
  if (tw.isConvex) {
    for (std::int32_t edgeNum : edges) {
      const std::size_t e = std::size_t(std::abs(edgeNum));
      if (s.isChecked(s.edgeChecked, e)) continue;
      for (int j = 0; j < 2; ++j) {
        const std::size_t vn = std::size_t(m.edges()[e].vertex[j]);
        if (s.isChecked(s.vertexChecked, vn)) continue;
        const Vec3& p = m.vertices()[vn];
        int bestPlane = 0;
        Real bestd = -tol::kBoundsInfinity;
        int k = 0;
        for (; k < tw.numPolys; ++k) {
          const Real d = tw.polys[std::size_t(k)].plane.distance(p);
          if (d >= 0) break;
          if (d > bestd) {
            bestd = d;
            bestPlane = k;
          }
        }
        if (k >= tw.numPolys) {
          const Plane& pl = tw.polys[std::size_t(bestPlane)].plane;
          return stuck(ContactType::ModelVertex, -pl.normal, -pl.dist, p, std::int32_t(vn), 0);
        }
      }
    }
  }
  setPolygonEdgeLines(tw, poly);
  for (const std::int32_t edgeNum : edges) s.mark(s.vertexChecked, std::size_t(m.edgeStart(edgeNum)));

  // 2. a trm edge crossing the polygon plane inside all polygon edges.
  int sides[kMaxTrmVertices];
  for (int i = 0; i < tw.numVerts; ++i)
    sides[i] = poly.plane.distance(tw.vertices[std::size_t(i)].p) < 0 ? -1 : 1;
  for (int i = 1; i <= tw.numEdges; ++i) {
    const WorkEdge& te = tw.edges[std::size_t(i)];
    if (sides[te.vertexNum[0]] == sides[te.vertexNum[1]]) continue;
    const unsigned flip = sides[te.vertexNum[0]] < 0 ? 1u : 0u;
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

  // 3. a polygon edge crossing a trm polygon plane inside that polygon's edges.
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const std::int32_t edgeNum = edges[i];
    const std::size_t e = std::size_t(std::abs(edgeNum));
    if (s.testAndMark(s.edgeChecked, e)) continue;
    const CmEdge& edge = m.edges()[e];
    const std::size_t v1 = std::size_t(edge.vertex[0]), v2 = std::size_t(edge.vertex[1]);
    for (int j = 0; j < tw.numPolys; ++j) {
      const WorkPolygon& tp = tw.polys[std::size_t(j)];
      // side = distance < 0 (not the sign bit: -0 counts as in front)
      const unsigned s1 = unsigned(tp.plane.distance(m.vertices()[v1]) < 0);
      const unsigned s2 = unsigned(tp.plane.distance(m.vertices()[v2]) < 0);
      if (s1 == s2) continue;
      const unsigned flip = s1;
      int k = 0;
      for (; k < tp.source->numEdges; ++k) {
        const int trmEdgeNum = tp.source->edges[std::size_t(k)];
        const WorkEdge& te = tw.edges[std::size_t(std::abs(trmEdgeNum))];
        const unsigned side = edgeLineSide(te, s.polygonEdgeLines[i]);
        if (unsigned(trmEdgeNum < 0) ^ side ^ flip) break;
      }
      if (k >= tp.source->numEdges) {
        return stuck(ContactType::Edge, -tp.plane.normal, -tp.plane.dist, m.vertices()[flip ? v2 : v1],
                     edgeNum, j);
      }
    }
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

void setupPositionTest(TraceWork& tw, const TraceModel& trm, const Orientation& o, const Vec3& position,
                       std::uint32_t mask) {
  tw.fraction = 1;
  tw.c = ContactInfo{};
  tw.contentMask = mask;
  tw.isConvex = trm.isConvex();
  tw.pointTrace = false;
  tw.quickExit = false;
  placeTrmFrame(tw, trm, o, position);
  placeTrmVertices(tw, trm, o, position, allTrmVertices(tw.numVerts));
  tw.placedTrm = &trm;  // the edges and polygons: placePositionTestFeatures
  tw.placedOrientation = &o;
  tw.end = tw.start;
  tw.size.clear();
  for (int i = 0; i < tw.numVerts; ++i) tw.size.addPoint(tw.vertices[std::size_t(i)].p - tw.start);
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
