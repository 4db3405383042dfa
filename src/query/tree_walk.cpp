// Walking the axial BSP tree along a movement (the original's
// TraceThroughAxialBSPTree_r and TraceTrmThroughNode), and the scratch set-up.
#include <algorithm>
#include <cmath>

#include "query/trace_work.h"

namespace cmkit {

QueryWork::QueryWork() : scratch_(std::make_unique<detail::QueryScratch>()) {}
QueryWork::~QueryWork() = default;
QueryWork::QueryWork(QueryWork&&) noexcept = default;
QueryWork& QueryWork::operator=(QueryWork&&) noexcept = default;

}  // namespace cmkit

namespace cmkit::detail {

void QueryScratch::begin(const CollisionModel& model) {
  auto grow = [](auto& v, std::size_t n) {
    if (v.size() < n) v.resize(n);
  };
  const std::size_t np = model.polygons.size(), nb = model.brushes.size();
  const std::size_t ne = model.edges.size(), nv = model.vertices.size();
  grow(polygonChecked, np);
  grow(brushChecked, nb);
  grow(edges, ne);
  grow(vertices, nv);
  if (++generation == 0) {  // wrapped: clear every mark once every 2^32 queries
    std::fill(polygonChecked.begin(), polygonChecked.end(), 0u);
    std::fill(brushChecked.begin(), brushChecked.end(), 0u);
    std::fill(edges.begin(), edges.end(), Feature{});
    std::fill(vertices.begin(), vertices.end(), Feature{});
    generation = 1;
  }
}

namespace {

// Tests the items referenced at one node.
void traceTrmThroughNode(TraceWork& tw, const CmNode& node) {
  const CollisionModel& m = tw.model;
  if (tw.positionTest) {
    if (tw.fraction == 0) return;  // already stuck
    for (std::int32_t b : m.brushesAt(node))
      if (testTrmVertsInBrush(tw, b)) return;
    if (tw.pointTrace) return;
    for (std::int32_t p : m.polygonsAt(node))
      if (testTrmInPolygon(tw, p)) return;
    return;
  }
  if (tw.rotation) {
    for (std::int32_t p : m.polygonsAt(node))
      if (rotateTrmThroughPolygon(tw, p)) return;
    return;
  }
  if (tw.pointTrace) {
    translatePointThroughPolygons(tw, m.polygonsAt(node));
    return;
  }
  translateTrmThroughPolygons(tw, m.polygonsAt(node));
}

// Visits every node whose region the box touches (closed: a box touching a
// split plane visits both sides), testing the items at each.
void traceBoxThroughTree(TraceWork& tw, std::int32_t nodeNum, const Bounds& box) {
  while (nodeNum >= 0) {
    if (tw.quickExit || tw.fraction == 0) return;  // fraction 0: blocked completely
    const CmNode& node = tw.model.nodes[std::size_t(nodeNum)];
    if (node.numPolygonRefs) traceTrmThroughNode(tw, node);
    if (node.isLeaf() || tw.quickExit || tw.fraction == 0) return;
    const int axis = node.planeType;
    const bool front = box.max[axis] >= node.planeDist;
    const bool back = box.min[axis] <= node.planeDist;
    if (front && back) traceBoxThroughTree(tw, node.children[0], box);
    nodeNum = back ? node.children[1] : node.children[0];
  }
}

// The walk along the segment, near side before far side at every split, as
// the original's recursion does. The far sides wait on a stack in the
// caller's scratch (no recursion: a degenerate deep tree cannot overflow the
// thread's stack, and a point trace saves the calls).
void traceThroughTree(TraceWork& tw) {
  using Segment = detail::QueryScratch::WalkSegment;
  std::vector<Segment>& pending = tw.scratch.walkStack;
  pending.clear();
  Segment cur{0, 0, 1, tw.start, tw.end};
  for (;;) {
    std::int32_t nodeNum = cur.node;
    while (nodeNum >= 0) {
      if (tw.quickExit) return;
      if (tw.fraction <= cur.p1f) break;  // something nearer was hit already
      const CmNode& node = tw.model.nodes[std::size_t(nodeNum)];
      // The walk goes on to one child or both: start loading the back one
      // (the front one follows in memory) while this node's items are tested.
      if (!node.isLeaf()) prefetch(&tw.model.nodes[std::size_t(node.children[1])]);
      if (node.numPolygonRefs || (tw.positionTest && node.numBrushRefs)) traceTrmThroughNode(tw, node);
      if (tw.positionTest && tw.fraction == 0) break;
      if (node.isLeaf()) break;

      // Distances of the segment ends to the split plane, and the trace
      // model's extent along its axis: both ends farther than the extent on
      // one side visit that side only.
      const int axis = node.planeType;
      const Real t1 = cur.p1[axis] - node.planeDist;
      const Real t2 = cur.p2[axis] - node.planeDist;
      const Real offset = tw.extents[axis];
      if (t1 >= offset && t2 >= offset) {
        nodeNum = node.children[0];
        continue;
      }
      if (t1 < -offset && t2 < -offset) {
        nodeNum = node.children[1];
        continue;
      }
      // The segment crosses the slab around the plane: the near side up to
      // where the trace leaves the slab's far face (now), the far side from
      // where it enters the near face (later).
      int side;
      Real frac, frac2;
      if (t1 < t2) {
        const Real idist = Real(1) / (t1 - t2);
        side = 1;
        frac2 = (t1 + offset) * idist;
        frac = (t1 - offset) * idist;
      } else if (t1 > t2) {
        const Real idist = Real(1) / (t1 - t2);
        side = 0;
        frac2 = (t1 - offset) * idist;
        frac = (t1 + offset) * idist;
      } else {
        side = 0;
        frac = 1;
        frac2 = 0;
      }
      const Vec3 p1 = cur.p1, p2 = cur.p2;
      frac2 = std::clamp(frac2, Real(0), Real(1));
      pending.push_back(
          {node.children[side ^ 1],
           cur.p1f + (cur.p2f - cur.p1f) * frac2,
           cur.p2f,
           {p1.x + frac2 * (p2.x - p1.x), p1.y + frac2 * (p2.y - p1.y), p1.z + frac2 * (p2.z - p1.z)},
           p2});
      frac = std::clamp(frac, Real(0), Real(1));
      cur.p2f = cur.p1f + (cur.p2f - cur.p1f) * frac;
      cur.p2 = {p1.x + frac * (p2.x - p1.x), p1.y + frac * (p2.y - p1.y), p1.z + frac * (p2.z - p1.z)};
      nodeNum = node.children[side];
    }
    if (pending.empty()) return;
    cur = pending.back();
    pending.pop_back();
  }
}

}  // namespace

PlaneCull cullByPolygonPlane(TraceWork& tw, const Plane& plane) {
  switch (tw.bounds.planeSide(plane)) {
    case Side::Cross:
      return PlaneCull::Test;
    case Side::Front:
      if (tw.model.isConvex) {
        tw.quickExit = true;
        return PlaneCull::Stop;
      }
      return PlaneCull::Skip;
    default:
      return PlaneCull::Skip;
  }
}

void setPolygonEdgeLines(const CollisionModel& m, std::span<const std::int32_t> edges,
                         detail::QueryScratch& s) {
  if (s.polygonEdgeLines.size() < edges.size()) s.polygonEdgeLines.resize(edges.size());
  for (std::size_t i = 0; i < edges.size(); ++i)
    s.polygonEdgeLines[i] = modelEdgeLine(m, std::size_t(std::abs(edges[i])));
}

void placeTrmVertices(TraceWork& tw, const TraceModel& trm, const Mat3& trmAxis, bool modelRotated,
                      const Mat3& modelAxis, bool used) {
  const bool trmRotated = isRotated(trmAxis);
  tw.numVerts = trm.numVertices();
  tw.numEdges = trm.numEdges();
  tw.numPolys = trm.numPolygons();
  for (int i = 0; i < tw.numVerts; ++i) {
    Vec3 p = trm.vertex(i);
    if (trmRotated) p = p * trmAxis;
    p += tw.start;
    if (modelRotated) p = modelAxis * p;  // into the model's frame
    WorkVertex& v = tw.vertices[std::size_t(i)];
    v.p = p;
    v.used = used;  // endp and pl are set by the query kinds that use them
  }
}

WorkEdge& placeTrmEdge(TraceWork& tw, const TraceModel& trm, int i) {
  WorkEdge& e = tw.edges[std::size_t(i)];
  e.vertexNum[0] = trm.edge(i).v[0];
  e.vertexNum[1] = trm.edge(i).v[1];
  e.start = tw.vertices[std::size_t(e.vertexNum[0])].p;
  e.end = tw.vertices[std::size_t(e.vertexNum[1])].p;
  e.pl = Pluecker::fromLine(e.start, e.end);
  e.used = true;
  return e;
}

void traceBoxThroughModel(TraceWork& tw, const Bounds& box) {
  if (tw.model.nodes.empty()) return;
  traceBoxThroughTree(tw, 0, box);
}

void traceThroughModel(TraceWork& tw) {
  if (tw.model.nodes.empty()) return;
  traceThroughTree(tw);
}

}  // namespace cmkit::detail
