// Placing the trace model in the model's frame, the one set-up every query
// kind starts from (translation, position test, rotation), and moving a
// contact back to the world.
#include <bit>

#include "query/trace_work.h"

namespace cmkit::detail {

Vec3 trmCentreInModel(const TraceModel& trm, const Mat3& trmAxis, const Vec3& position,
                      const Placement& placement) {
  Vec3 c = position - placement.origin;
  c += isRotated(trmAxis) ? trm.offset() * trmAxis : trm.offset();
  if (isRotated(placement.axis)) c = placement.axis * c;
  return c;
}

void placeTrmVertices(TraceWork& tw, const TraceModel& trm, const Mat3& trmAxis, const Vec3& position,
                      const Placement& placement, std::uint32_t vertices) {
  const bool trmRotated = isRotated(trmAxis);
  const bool modelRotated = isRotated(placement.axis);
  const Vec3 relative = position - placement.origin;
  for (; vertices; vertices &= vertices - 1) {
    const int i = std::countr_zero(vertices);
    Vec3 p = trm.vertex(i);
    if (trmRotated) p = p * trmAxis;
    p += relative;
    if (modelRotated) p = placement.axis * p;  // into the model's frame
    tw.vertices[std::size_t(i)].p = p;
  }
}

void placeTrmFrame(TraceWork& tw, const TraceModel& trm, const Mat3& trmAxis, const Vec3& position,
                   const Placement& placement) {
  tw.numVerts = trm.numVertices();
  tw.numEdges = trm.numEdges();
  tw.numPolys = trm.numPolygons();
  tw.start = trmCentreInModel(trm, trmAxis, position, placement);
}

void placeTrmTopology(TraceWork& tw, const TraceModel& trm, const Mat3& trmAxis, const Placement& placement) {
  const bool trmRotated = isRotated(trmAxis);
  const bool modelRotated = isRotated(placement.axis);
  for (int i = 1; i <= tw.numEdges; ++i) {
    WorkEdge& e = tw.edges[std::size_t(i)];
    e.vertexNum[0] = trm.edge(i).v[0];
    e.vertexNum[1] = trm.edge(i).v[1];
  }
  // Normals: local -> world (n * trmAxis) -> model frame (n * axis^T), as one matrix.
  const Mat3 planeAxis = trmRotated && modelRotated ? trmAxis * placement.axis.transposed() : trmAxis;
  for (int i = 0; i < tw.numPolys; ++i) {
    const TrmPolygon& tp = trm.polygon(i);
    WorkPolygon& wp = tw.polys[std::size_t(i)];
    wp.numEdges = tp.numEdges;
    wp.edges = tp.edges.data();
    Vec3 n = tp.normal;
    if (trmRotated)
      n = n * planeAxis;
    else if (modelRotated)
      n = placement.axis * n;
    wp.plane.normal = n;
  }
}

void placeTrm(TraceWork& tw, const TraceModel& trm, const Mat3& trmAxis, const Vec3& position,
              const Placement& placement) {
  placeTrmFrame(tw, trm, trmAxis, position, placement);
  placeTrmVertices(tw, trm, trmAxis, position, placement, allTrmVertices(tw.numVerts));
  placeTrmTopology(tw, trm, trmAxis, placement);
}

WorkEdge& placeTrmEdge(TraceWork& tw, int i) {
  WorkEdge& e = tw.edges[std::size_t(i)];
  e.start = tw.vertices[std::size_t(e.vertexNum[0])].p;
  e.end = tw.vertices[std::size_t(e.vertexNum[1])].p;
  e.pl = Pluecker::fromLine(e.start, e.end);
  e.used = true;
  return e;
}

void placeTrmEdges(TraceWork& tw) {
  for (int i = 1; i <= tw.numEdges; ++i) placeTrmEdge(tw, i);
}

void contactToWorld(ContactInfo& c, const Placement& placement) {
  if (isRotated(placement.axis)) {
    c.normal = c.normal * placement.axis;
    c.point = c.point * placement.axis;
  }
  c.point += placement.origin;
  c.dist += placement.origin.dot(c.normal);
}

}  // namespace cmkit::detail
