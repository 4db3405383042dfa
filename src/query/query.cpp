// The public queries: translate, contents, pointContents, contacts,
// penetration. Set-up of the trace work (the original's Translation and
// ContentsTrm) and the transformation of results back to world space.
#include <cmath>
#include <vector>

#include "query/trace_work.h"

namespace cmkit::detail {

namespace {

// Heart planes: two planes containing the movement, for culling polygons far
// to the side of the swept volume.
void setupTranslationHeartPlanes(TraceWork& tw) {
  Vec3 dir = tw.dir;
  dir.normalize();
  Vec3 n1, n2;
  normalVectors(dir, n1, n2);
  tw.heartPlane1 = Plane{n1, n1.dot(tw.start)};
  tw.heartPlane2 = Plane{n2, n2.dot(tw.start)};
}

// Point trace set-up (no trace model).
void setupPointTrace(TraceWork& tw) {
  for (int i = 0; i < 3; ++i) {
    tw.bounds.min[i] = std::min(tw.start[i], tw.end[i]) - tol::kBoxEpsilon;
    tw.bounds.max[i] = std::max(tw.start[i], tw.end[i]) + tol::kBoxEpsilon;
  }
  tw.extents = {tol::kBoxEpsilon, tol::kBoxEpsilon, tol::kBoxEpsilon};
  tw.size = Bounds{{0, 0, 0}, {0, 0, 0}};
  setupTranslationHeartPlanes(tw);
  tw.maxDistFromHeartPlane1 = tol::kBoxEpsilon;
  tw.maxDistFromHeartPlane2 = tol::kBoxEpsilon;
  tw.numVerts = 1;
  tw.vertices[0].p = tw.start;
  tw.vertices[0].endp = tw.start + tw.dir;
  tw.vertices[0].pl = Pluecker::fromRay(tw.start, tw.dir);
  tw.vertices[0].used = true;
  tw.numEdges = tw.numPolys = 0;
  tw.pointTrace = true;
}

// Trace-model translation set-up: the trace model at the start, only the
// features facing the movement used.
void setupTrmTranslation(TraceWork& tw, const TranslationQuery& q) {
  const TraceModel& trm = *q.trm;
  placeTrm(tw, trm, q.trmAxis, q.start, q.placement);
  tw.end = trmCentreInModel(trm, q.trmAxis, q.end, q.placement);
  tw.dir = q.end - q.start;
  if (isRotated(q.placement.axis)) tw.dir = q.placement.axis * tw.dir;
  for (int i = 0; i < tw.numVerts; ++i) tw.vertices[std::size_t(i)].used = false;
  for (int i = 1; i <= tw.numEdges; ++i) tw.edges[std::size_t(i)].used = false;
  for (int i = 0; i < tw.numPolys; ++i) {
    WorkPolygon& wp = tw.polys[std::size_t(i)];
    const Vec3& n = wp.plane.normal;
    // Polygons facing the movement (or, for a flat trm, along it) collide.
    const Real d = n.dot(tw.dir);
    wp.used = d > 0 || (!trm.isConvex() && d == 0);
    if (!wp.used) continue;
    for (int j = 0; j < wp.numEdges; ++j) {
      WorkEdge& e = tw.edges[std::size_t(std::abs(wp.edges[std::size_t(j)]))];
      e.used = true;
      tw.vertices[std::size_t(e.vertexNum[0])].used = true;
      tw.vertices[std::size_t(e.vertexNum[1])].used = true;
    }
  }
  tw.size.clear();
  tw.movingVertices = 0;
  for (int i = 0; i < tw.numVerts; ++i) {
    WorkVertex& v = tw.vertices[std::size_t(i)];
    if (!v.used) continue;
    tw.movingVertices |= std::uint32_t(1) << i;
    tw.size.addPoint(v.p - tw.start);
    v.endp = v.p + tw.dir;
  }
  tw.movingEdges = 0;
  for (int i = 1; i <= tw.numEdges; ++i) {
    WorkEdge& e = tw.edges[std::size_t(i)];
    if (!e.used) continue;
    tw.movingEdges |= std::uint64_t(1) << i;
  }
  tw.movingPolygons = 0;
  for (int i = 0; i < tw.numPolys; ++i) {
    WorkPolygon& wp = tw.polys[std::size_t(i)];
    if (!wp.used) continue;
    tw.movingPolygons |= std::uint32_t(1) << i;
  }
  tw.featuresPlaced = false;  // the paths, edge lines and planes: placeTranslationFeatures
  for (int i = 0; i < 3; ++i) {
    if (tw.start[i] < tw.end[i]) {
      tw.bounds.min[i] = tw.start[i] + tw.size.min[i] - tol::kBoxEpsilon;
      tw.bounds.max[i] = tw.end[i] + tw.size.max[i] + tol::kBoxEpsilon;
    } else {
      tw.bounds.min[i] = tw.end[i] + tw.size.min[i] - tol::kBoxEpsilon;
      tw.bounds.max[i] = tw.start[i] + tw.size.max[i] + tol::kBoxEpsilon;
    }
    tw.extents[i] = (std::fabs(tw.size.min[i]) > std::fabs(tw.size.max[i]) ? std::fabs(tw.size.min[i])
                                                                           : std::fabs(tw.size.max[i])) +
                    tol::kBoxEpsilon;
  }
  setupTranslationHeartPlanes(tw);
  tw.maxDistFromHeartPlane1 = tw.maxDistFromHeartPlane2 = 0;
  for (int i = 0; i < tw.numVerts; ++i) {
    const WorkVertex& v = tw.vertices[std::size_t(i)];
    if (!v.used) continue;
    tw.maxDistFromHeartPlane1 = std::max(tw.maxDistFromHeartPlane1, std::fabs(tw.heartPlane1.distance(v.p)));
    tw.maxDistFromHeartPlane2 = std::max(tw.maxDistFromHeartPlane2, std::fabs(tw.heartPlane2.distance(v.p)));
  }
  tw.maxDistFromHeartPlane1 += tol::kBoxEpsilon;
  tw.maxDistFromHeartPlane2 += tol::kBoxEpsilon;
}

// Runs a translation (start != end) into tw; contacts mode when `out` set.
void runTranslation(TraceWork& tw, const TranslationQuery& q, std::vector<ContactInfo>* out,
                    int maxContacts) {
  tw.fraction = 1;
  tw.c = ContactInfo{};
  tw.contentMask = q.contentMask;
  tw.isConvex = true;
  tw.quickExit = false;
  tw.contacts = out;
  tw.maxContacts = maxContacts;
  if (isPointTrm(q.trm)) {
    tw.start = q.start - q.placement.origin;
    tw.end = q.end - q.placement.origin;
    tw.dir = q.end - q.start;
    if (isRotated(q.placement.axis)) {
      tw.start = q.placement.axis * tw.start;
      tw.end = q.placement.axis * tw.end;
      tw.dir = q.placement.axis * tw.dir;
    }
    setupPointTrace(tw);
  } else {
    tw.pointTrace = false;
    tw.isConvex = q.trm->isConvex();
    setupTrmTranslation(tw, q);
  }
  translateThroughModel(tw);
}

}  // namespace

}  // namespace cmkit::detail

namespace cmkit {

using namespace detail;  // the query internals (trace_work.h)

ContentsResult contentsTest(const CollisionModel& model, const ContentsQuery& q, QueryWork& work) {
  ContentsResult r;
  r.trace.endPos = q.position;
  r.trace.endAxis = q.trmAxis;
  if (isPointTrm(q.trm)) {
    r.contents = pointContents(model, q.position, q.placement);
    r.trace.contact.contents = r.contents;
    r.trace.fraction = r.contents == 0 ? 1 : 0;
    return r;
  }
  detail::QueryScratch& s = detail::scratchOf(work);
  s.begin(model);
  count(s, &QueryStats::queries);
  TraceWork tw(model, s);
  setupPositionTest(tw, *q.trm, q.trmAxis, q.position, q.contentMask, q.placement);
  positionTestThroughModel(tw);
  r.contents = tw.c.contents;
  r.trace.contact = tw.c;
  r.trace.fraction = r.contents == 0 ? 1 : 0;
  r.trace.startSolid = r.contents != 0;
  return r;
}

TraceResult translate(const CollisionModel& model, const TranslationQuery& q, QueryWork& work) {
  if (q.start == q.end) {
    ContentsQuery cq{q.trm, q.trmAxis, q.start, q.contentMask, q.placement};
    TraceResult r = contentsTest(model, cq, work).trace;
    r.startSolid = r.fraction == 0;
    return r;
  }
  TraceResult r;
  if (q.detectStartSolid) {
    ContentsQuery cq{q.trm, q.trmAxis, q.start, q.contentMask, q.placement};
    r.startSolid = contentsTest(model, cq, work).contents != 0;
  }
  detail::QueryScratch& s = detail::scratchOf(work);
  s.begin(model);
  count(s, &QueryStats::queries);
  TraceWork tw(model, s);
  runTranslation(tw, q, nullptr, 0);
  r.fraction = tw.fraction;
  r.contact = tw.c;
  r.endPos = q.start + (q.end - q.start) * r.fraction;
  r.endAxis = isPointTrm(q.trm) ? Mat3::identity() : q.trmAxis;
  if (r.fraction < 1) {
    // A tiny fraction whose movement rounds to nothing is no movement.
    if (r.fraction > 0 && r.endPos == q.start) r.fraction = 0;
    contactToWorld(r.contact, q.placement);
  }
  return r;
}

ContactsResult contacts(const CollisionModel& model, const ContactsQuery& q, QueryWork& work) {
  ContactsResult result;
  std::vector<ContactInfo>& out = result.contacts;
  const Vec3 end = q.start + q.dir * q.depth;
  if (end == q.start || q.maxContacts <= 0) return result;  // a position test finds no contacts
  detail::QueryScratch& s = detail::scratchOf(work);
  s.begin(model);
  count(s, &QueryStats::queries);
  TraceWork tw(model, s);
  const TranslationQuery tq{q.trm, q.trmAxis, q.start, end, q.contentMask, q.placement, false};
  runTranslation(tw, tq, &out, q.maxContacts);
  // Unlike the original, point contacts are moved to world space too.
  for (ContactInfo& c : out) contactToWorld(c, q.placement);
  return result;
}

std::uint32_t pointContents(const CollisionModel& model, const Vec3& point, const Placement& placement) {
  if (model.nodes.empty()) return 0;
  Vec3 p = point - placement.origin;
  if (isRotated(placement.axis)) p = placement.axis * p;  // world -> model frame
  auto inside = [&](std::int32_t brushNum) {
    const CmBrush& b = model.brushes[std::size_t(brushNum)];
    if (!b.bounds.containsPoint(p)) return false;
    for (const Plane& plane : model.planesOf(b))
      if (plane.distance(p) >= 0) return false;
    return b.numPlanes > 0;
  };
  // Walk to the leaf, remembering the path: brushes straddling a split are
  // stored at interior nodes and must be seen too (the original missed
  // them). The leaf is searched first so that where the original finds a
  // brush, the same brush is found. The path fits a small buffer on the
  // stack in any practical tree; a deeper one (a .cm can hold any tree)
  // continues on the heap.
  constexpr std::size_t kInlinePath = 128;
  std::int32_t path[kInlinePath];
  std::vector<std::int32_t> deeper;  // the nodes below path's end, top down
  std::size_t depth = 0;
  std::int32_t n = 0;
  while (true) {
    if (depth < kInlinePath)
      path[depth++] = n;
    else
      deeper.push_back(n);
    const CmNode& node = model.nodes[std::size_t(n)];
    if (node.isLeaf()) break;
    n = p[node.planeType] > node.planeDist ? node.children[0] : node.children[1];
  }
  // The first brush at `node` containing the point, -1 when none.
  const auto brushAt = [&](std::int32_t node) -> std::int32_t {
    for (std::int32_t b : model.brushesAt(model.nodes[std::size_t(node)]))
      if (inside(b)) return b;
    return -1;
  };
  std::int32_t found = -1;
  for (std::size_t i = deeper.size(); found < 0 && i-- > 0;) found = brushAt(deeper[i]);
  for (std::size_t i = depth; found < 0 && i-- > 0;) found = brushAt(path[i]);
  return found < 0 ? 0 : model.brushes[std::size_t(found)].contents;
}

Penetration penetration(const CollisionModel& model, const ContentsQuery& q, QueryWork& work) {
  Penetration result;
  // The trace model's vertices in the model frame.
  Vec3 verts[kMaxTrmVertices];
  int numVerts = 1;
  const bool modelRotated = isRotated(q.placement.axis);
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
    const CmBrush& b = model.brushes[std::size_t(bi)];
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
  if (model.nodes.empty()) {  // no tree (a hand-made model): every brush
    for (std::size_t bi = 0; bi < model.brushes.size(); ++bi) testBrush(std::int32_t(bi));
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
      const CmNode& node = model.nodes[std::size_t(n)];
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
