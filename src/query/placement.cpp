// Placing the trace model in the model's frame, the one set-up every query
// kind starts from (translation, position test, rotation), and moving a
// contact back to the world.
#include <bit>

#include "query/cull_lanes.h"
#include "query/trace_work.h"

namespace cmkit::detail {

void placeTrmVertices(TraceWork& tw, const TraceModel& trm, const Orientation& o, const Vec3& position,
                      std::uint32_t vertices) {
  const Vec3 relative = position - o.placement->origin;
#ifdef CMKIT_QUERY_LANES
  if ((o.trmRotated || o.modelRotated) && vertices) {  // turned: four at a time
    alignas(16) float x[kMaxTrmVertices], y[kMaxTrmVertices], z[kMaxTrmVertices];
    placedTrmVerticesInLanes(trm, o, relative, bitsThrough(vertices), x, y, z);
    for (; vertices; vertices &= vertices - 1) {
      const std::size_t i = std::size_t(std::countr_zero(vertices));
      tw.vertices[i].p = {x[i], y[i], z[i]};
    }
    return;
  }
#endif
  for (; vertices; vertices &= vertices - 1) {
    const int i = std::countr_zero(vertices);
    tw.vertices[std::size_t(i)].p = placedTrmVertex(trm, o, i, relative);
  }
}

void placeTrmFrame(TraceWork& tw, const TraceModel& trm, const Orientation& o, const Vec3& position) {
  tw.numVerts = trm.numVertices();
  tw.numEdges = trm.numEdges();
  tw.numPolys = trm.numPolygons();
  tw.start = trmCentreInModel(trm, o, position);
}

void placeTrmTopology(TraceWork& tw, const TraceModel& trm, const Orientation& o) {
  for (int i = 1; i <= tw.numEdges; ++i) {
    WorkEdge& e = tw.edges[std::size_t(i)];
    e.vertexNum[0] = trm.edgeVertex(i, 0);
    e.vertexNum[1] = trm.edgeVertex(i, 1);
  }
  Mat3 both;
  const Mat3& planeAxis = trmPlaneAxis(o, both);
#ifdef CMKIT_QUERY_LANES
  if (o.trmRotated || o.modelRotated) {  // turned: the normals four at a time
    alignas(16) float x[kMaxTrmPolygons], y[kMaxTrmPolygons], z[kMaxTrmPolygons];
    placeTurnedTrmPolygons(tw, trm, o, planeAxis, x, y, z);
    return;
  }
#endif
  for (int i = 0; i < tw.numPolys; ++i) placeTrmPolygon(tw.polys[std::size_t(i)], trm, i, o, planeAxis);
}

void placeTrm(TraceWork& tw, const TraceModel& trm, const Orientation& o, const Vec3& position) {
  placeTrmFrame(tw, trm, o, position);
  placeTrmVertices(tw, trm, o, position, allTrmVertices(tw.numVerts));
  placeTrmTopology(tw, trm, o);
}

void contactToWorld(ContactInfo& c, const Placement& placement, bool rotated) {
  if (rotated) {
    c.normal = c.normal * placement.axis;
    c.point = c.point * placement.axis;
  }
  c.point += placement.origin;
  c.dist += placement.origin.dot(c.normal);
}

}  // namespace cmkit::detail
