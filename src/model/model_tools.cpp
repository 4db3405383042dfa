// Conversions between trace models and collision models (the original's
// SetupTrmModel and TrmFromModel), windings and PrintModel statistics.
#include <algorithm>
#include <cstdio>

#include "cmkit/model.h"
#include "model/model_access.h"

namespace cmkit {

ModelPtr collisionModelFromTraceModel(const TraceModel& trm, std::uint32_t contents, std::string material) {
  ModelArrays m;
  m.name = "trace model";
  m.isConvex = true;
  m.vertices.assign(trm.vertices().begin(), trm.vertices().end());
  // Edges keep the trace model's numbering (1..n) and its edge normals.
  m.edges.resize(std::size_t(trm.numEdges()) + 1);
  for (int e = 1; e <= trm.numEdges(); ++e) {
    CmEdge& edge = m.edges[std::size_t(e)];
    edge.vertex[0] = trm.edge(e).v[0];
    edge.vertex[1] = trm.edge(e).v[1];
    edge.normal = trm.edge(e).normal;
  }
  std::int32_t materialIndex = -1;
  if (!material.empty()) {
    m.materials.push_back(std::move(material));
    materialIndex = 0;
  }
  for (const TrmPolygon& tp : trm.polygons()) {
    CmPolygon p;
    p.bounds = tp.bounds;
    p.plane = Plane(tp.normal, tp.dist);
    p.contents = contents;
    p.material = materialIndex;
    p.firstEdge = std::uint32_t(m.polygonEdges.size());
    p.numEdges = std::uint32_t(tp.numEdges);
    for (const int e : tp.edgeList()) {
      m.polygonEdges.push_back(e);
      CmEdge& edge = m.edges[std::size_t(e < 0 ? -e : e)];
      if (edge.numUsers < 255) ++edge.numUsers;
    }
    m.polygons.push_back(p);
  }
  // One leaf holding every polygon in order.
  CmNode leaf;
  leaf.numPolygonRefs = std::uint32_t(m.polygons.size());
  m.nodes.push_back(leaf);
  for (std::size_t i = 0; i < m.polygons.size(); ++i) m.polygonRefs.push_back(std::int32_t(i));
  m.bounds = trm.bounds();
  m.contents = m.polygons.empty() ? 0 : contents;
  return detail::ModelAccess::seal(std::move(m));
}

Result<TraceModel> traceModelFromCollisionModel(const CollisionModel& model) {
  const std::string who = "model \"" + model.name() + "\"";
  if (model.polygons().empty()) return Error(who + " has no polygons: it cannot be a trace model");
  // The vertices the polygons use, and how often each edge is used.
  std::vector<char> used(model.vertices().size(), 0);
  std::vector<int> users(model.edges().size(), 0);
  for (const CmPolygon& p : model.polygons()) {
    if (p.numEdges > std::uint32_t(kMaxTrmPolygonEdges)) {
      return Error(who + " has a polygon with " + std::to_string(p.numEdges) +
                   " edges; a trace model allows " + std::to_string(kMaxTrmPolygonEdges));
    }
    for (const std::int32_t e : model.edgesOf(p)) {
      const std::size_t edge = std::size_t(e < 0 ? -std::int64_t(e) : e);
      if (edge == 0 || edge >= model.edges().size())
        return Error(who + " has a polygon with a bad edge number");
      ++users[edge];
      const std::int32_t v = model.edgeStart(e);
      if (v < 0 || std::size_t(v) >= model.vertices().size())
        return Error(who + " has an edge with a bad vertex");
      used[std::size_t(v)] = 1;
    }
  }
  std::vector<Vec3> points;
  for (std::size_t v = 0; v < model.vertices().size(); ++v)
    if (used[v]) points.push_back(model.vertices()[v]);
  int numEdges = 0;
  for (std::size_t e = 1; e < users.size(); ++e) {
    if (users[e] == 0) continue;
    ++numEdges;
    if (users[e] != 2) {
      return Error(who + " is not closed: edge " + std::to_string(e) + " is used by " +
                   std::to_string(users[e]) + " polygon(s) instead of 2");
    }
  }
  if (points.size() > std::size_t(kMaxTrmVertices) || numEdges > kMaxTrmEdges ||
      model.polygons().size() > std::size_t(kMaxTrmPolygons)) {
    return Error(who + " is too big for a trace model: " + std::to_string(points.size()) + " vertices, " +
                 std::to_string(numEdges) + " edges, " + std::to_string(model.polygons().size()) +
                 " polygons (limits " + std::to_string(kMaxTrmVertices) + ", " +
                 std::to_string(kMaxTrmEdges) + ", " + std::to_string(kMaxTrmPolygons) + ")");
  }
  for (std::size_t i = 0; i < model.polygons().size(); ++i) {
    const Plane& plane = model.polygons()[i].plane;
    for (const Vec3& p : points) {
      if (plane.distance(p) > tol::kTrmFromModelConvexEpsilon) {
        return Error(who + " is not convex: a vertex lies in front of polygon " + std::to_string(i));
      }
    }
  }
  Result<TraceModel> hull = TraceModel::convexHull(points);
  if (!hull) return Error(who + ": " + hull.error().message);
  return hull;
}

std::vector<Vec3> polygonWinding(const CollisionModel& model, std::size_t polygon) {
  std::vector<Vec3> winding;
  if (polygon >= model.polygons().size()) return winding;
  for (const std::int32_t e : model.edgesOf(model.polygons()[polygon])) {
    const std::size_t edge = std::size_t(e < 0 ? -std::int64_t(e) : e);
    if (edge == 0 || edge >= model.edges().size()) continue;
    const std::int32_t v = model.edgeStart(e);
    if (v >= 0 && std::size_t(v) < model.vertices().size())
      winding.push_back(model.vertices()[std::size_t(v)]);
  }
  return winding;
}

std::string modelStatistics(const CollisionModel& model) {
  // Sizes of the original's structures in a 64-bit build: vertex 24, edge 36,
  // node 48, node reference 16 bytes; polygons 60 + 4 per edge, brushes 48 +
  // 16 per plane.
  const long long vertices = static_cast<long long>(model.vertices().size());
  const long long edges = static_cast<long long>(model.edges().size());
  const long long nodes = model.nodes().empty() ? 0 : static_cast<long long>(model.nodes().size()) - 1;
  const long long polygonRefs = static_cast<long long>(model.polygonRefs().size());
  const long long brushRefs = static_cast<long long>(model.brushRefs().size());
  long long polygonBytes = 0, brushBytes = 0;
  for (const CmPolygon& p : model.polygons()) polygonBytes += 60 + 4 * static_cast<long long>(p.numEdges);
  for (const CmBrush& b : model.brushes()) brushBytes += 48 + 16 * static_cast<long long>(b.numPlanes);
  const long long vertexBytes = vertices * 24, edgeBytes = edges * 36, nodeBytes = nodes * 48;
  const long long refBytes = (polygonRefs + brushRefs) * 16;
  const long long total = vertexBytes + edgeBytes + polygonBytes + brushBytes + nodeBytes + refBytes;
  std::string s = model.name() + "\n";
  char line[128];
  auto add = [&](long long n, const char* what, long long bytes) {
    if (bytes >= 0) {
      std::snprintf(line, sizeof line, "%6lld %s (%lld KB)\n", n, what, bytes >> 10);
    } else {
      std::snprintf(line, sizeof line, "%6lld %s\n", n, what);
    }
    s += line;
  };
  add(vertices, "vertices", vertexBytes);
  add(edges, "edges", edgeBytes);
  add(static_cast<long long>(model.polygons().size()), "polygons", polygonBytes);
  add(static_cast<long long>(model.brushes().size()), "brushes", brushBytes);
  add(nodes, "nodes", nodeBytes);
  add(polygonRefs, "polygon refs", polygonRefs * 16);
  add(brushRefs, "brush refs", brushRefs * 16);
  add(model.stats().internalEdges, "internal edges", -1);
  add(model.stats().sharpEdges, "sharp edges", -1);
  add(model.stats().containedPolygonsRemoved, "contained polygons removed", -1);
  add(model.stats().polygonsMerged, "polygons merged", -1);
  std::snprintf(line, sizeof line, "%6lld KB total memory used\n", total >> 10);
  s += line;
  return s;
}

}  // namespace cmkit
