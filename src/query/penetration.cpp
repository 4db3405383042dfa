// The public penetration(): how a trace model overlapping solid gets out
// (a separating-plane test on the planes of every brush it may overlap; the
// deepest brush decides). Not in the original.
#include <vector>

#include "query/query_guards.h"
#include "query/trace_work.h"

namespace cmkit {

using namespace detail;  // the query internals (trace_work.h)

PenetrationResult penetration(const CollisionModel& model, const PenetrationQuery& query, QueryWork& work) {
  PenetrationQuery q = query;
  PenetrationResult result;
  result.status = guardPenetration(q);
  if (result.status != QueryStatus::Ok) return result;
  // The trace model's vertices in the model frame.
  Vec3 verts[kMaxTrmVertices];
  int numVerts = 1;
  const bool modelRotated = isRotated(q.placement);
  if (isPointTrm(q.trm)) {
    verts[0] = q.position;
  } else {
    numVerts = q.trm->numVertices();
    for (int i = 0; i < numVerts; ++i) verts[i] = q.trm->vertex(i) * q.trmAxis + q.position;
  }
  Bounds tb;
  for (int i = 0; i < numVerts; ++i) {
    verts[i] = verts[i] - q.placement.origin;
    if (modelRotated) verts[i] = q.placement.axis * verts[i];
    tb.addPoint(verts[i]);
  }
  // Every brush whose bounds meet the trace model: separating-plane test on
  // its planes. The trace model is outside the brush along a plane when all
  // its vertices are in front; the depth along that plane is how far the
  // deepest vertex is behind it. The deepest brush wins, the lowest brush
  // index on equal depths (as a scan of all brushes in order would choose).
  std::int32_t chosen = -1;
  const auto testBrush = [&](std::int32_t bi) {
    const CmBrush& b = model.brushes()[std::size_t(bi)];
    if (!(b.contents & q.contentMask) || !b.bounds.intersects(tb) || b.numPlanes == 0) return;
    Real best = tol::kBoundsInfinity;
    Vec3 bestNormal;
    bool separated = false;
    for (const Plane& plane : model.planesOf(b)) {
      Real minDist = tol::kBoundsInfinity;
      for (int i = 0; i < numVerts; ++i) minDist = std::min(minDist, plane.distance(verts[i]));
      if (minDist >= 0) {
        separated = true;
        break;
      }
      if (-minDist < best) {
        best = -minDist;
        bestNormal = plane.normal;
      }
    }
    if (separated) return;
    if (!result.stuck || best > result.depth || (best == result.depth && bi < chosen)) {
      chosen = bi;
      result.stuck = true;
      result.depth = best;
      result.direction = modelRotated ? bestNormal * q.placement.axis : bestNormal;
      result.contents = b.contents;
    }
  };
  if (model.nodes().empty()) {  // no tree (a hand-made model): every brush
    for (std::size_t bi = 0; bi < model.brushes().size(); ++bi) testBrush(std::int32_t(bi));
    return result;
  }
  // The brushes come from the tree: every node whose region the trace
  // model's bounds touch (closed: touching a split plane visits both sides),
  // each brush once.
  detail::QueryScratch& s = detail::scratchOf(work);
  s.begin(model);
  std::vector<std::int32_t>& pending = s.nodeStack;
  pending.assign(1, 0);
  while (!pending.empty()) {
    std::int32_t n = pending.back();
    pending.pop_back();
    while (true) {
      const CmNode& node = model.nodes()[std::size_t(n)];
      for (const std::int32_t b : model.brushesAt(node))
        if (!s.testAndMark(s.brushChecked, std::size_t(b))) testBrush(b);
      if (node.isLeaf()) break;
      const bool front = tb.max[node.planeType] >= node.planeDist;
      const bool back = tb.min[node.planeType] <= node.planeDist;
      if (front && back) pending.push_back(node.children[0]);
      n = back ? node.children[1] : node.children[0];
    }
  }
  return result;
}

}  // namespace cmkit
