// The public queries: translate, contents, pointContents, contacts,
// penetration. Set-up of the trace work (the original's Translation and
// ContentsTrm) and the transformation of results back to world space.
#include <bit>
#include <cmath>
#include <vector>

#include "query/query_guards.h"
#include "query/trace_work.h"
#include "util/simd.h"

namespace cmkit::detail {

void makeTranslationHeartPlanes(TraceWork& tw) {
  tw.heartPlanesMade = true;
  // Two planes through the move, at right angles to each other (the
  // original's normalVectors of the move's direction). They only cull, each
  // with the trace model's greatest distance from it, so they need not be
  // the original's bit for bit: plain square roots, not its reciprocal
  // square root (whose Newton steps are a long chain of multiplications).
  // (The two square roots do not wait for each other: n1 needs only the
  // direction's x and y, not the unit direction.)
  const Vec3& dir = tw.dir;
  const Real len2 = dir.lengthSquared();
  const Real d = dir.x * dir.x + dir.y * dir.y;
  const Real invLength = len2 > 0 ? Real(1) / std::sqrt(len2) : Real(0);
  const Vec3 n1 = d == 0 ? Vec3{1, 0, 0} : Vec3{-dir.y, dir.x, 0} * (Real(1) / std::sqrt(d));
  const Vec3 n2 = n1.cross(dir) * invLength;
  tw.heartPlane1 = Plane{n1, n1.dot(tw.start)};
  tw.heartPlane2 = Plane{n2, n2.dot(tw.start)};
  if (tw.pointTrace) {
    tw.maxDistFromHeartPlane1 = tol::kBoxEpsilon;
    tw.maxDistFromHeartPlane2 = tol::kBoxEpsilon;
    return;
  }
  // The farthest moving vertex from each.
  Real max1 = 0, max2 = 0;
  for (std::uint32_t moving = tw.movingVertices; moving; moving &= moving - 1) {
    const WorkVertex& v = tw.vertices[std::size_t(std::countr_zero(moving))];
    max1 = std::max(max1, std::fabs(tw.heartPlane1.distance(v.p)));
    max2 = std::max(max2, std::fabs(tw.heartPlane2.distance(v.p)));
  }
  tw.maxDistFromHeartPlane1 = max1 + tol::kBoxEpsilon;
  tw.maxDistFromHeartPlane2 = max2 + tol::kBoxEpsilon;
}

namespace {

// Point trace set-up (no trace model).
void setupPointTrace(TraceWork& tw) {
  for (int i = 0; i < 3; ++i) {
    tw.bounds.min[i] = std::min(tw.start[i], tw.end[i]) - tol::kBoxEpsilon;
    tw.bounds.max[i] = std::max(tw.start[i], tw.end[i]) + tol::kBoxEpsilon;
  }
  tw.extents = {tol::kBoxEpsilon, tol::kBoxEpsilon, tol::kBoxEpsilon};
  tw.size = Bounds{{0, 0, 0}, {0, 0, 0}};
  tw.heartPlanesMade = false;
  tw.numVerts = 1;
  tw.vertices[0].p = tw.start;
  tw.vertices[0].endp = tw.start + tw.dir;
  tw.vertices[0].pl = Pluecker::fromRay(tw.start, tw.dir);
  tw.vertices[0].used = true;
  tw.numEdges = tw.numPolys = 0;
  tw.pointTrace = true;
}

// Trace-model translation set-up: the trace model at the start, only the
// features facing the movement used (as masks; only their vertices placed;
// the edges' vertex numbers when a polygon first needs them,
// placeTranslationFeatures).
void setupTrmTranslation(TraceWork& tw, const TranslationQuery& q, const Orientation& o) {
  const TraceModel& trm = *q.trm;
  placeTrmFrame(tw, trm, o, q.start);
  tw.placedTrm = &trm;  // (placeTranslationFeatures reads its edges' vertex numbers)
  tw.end = trmCentreInModel(trm, o, q.end);
  tw.dir = q.end - q.start;
  if (o.modelRotated) tw.dir = q.placement.axis * tw.dir;
  // The polygons (placeTrmPolygon, as placeTrmTopology), and which face the
  // movement (or, for a flat trm, lie along it): those collide. (Masks, not
  // branches: which polygons face the move is unpredictable.)
  Mat3 both;
  const Mat3& planeAxis = trmPlaneAxis(o, both);
  const unsigned flat = unsigned(!trm.isConvex());
  const Vec3 dir = tw.dir;
  std::uint32_t movingPolygons = 0, movingVertices = 0;
  std::uint64_t movingEdges = 0;
  for (int i = 0; i < tw.numPolys; ++i) {
    const Real d = placeTrmPolygon(tw.polys[std::size_t(i)], trm, i, o, planeAxis).dot(dir);
    const unsigned facing = unsigned(d > 0) | (flat & unsigned(d == 0));
    movingPolygons |= std::uint32_t(facing) << i;
    movingEdges |= trm.polygonEdgeBits(i) & (std::uint64_t(0) - facing);
    movingVertices |= trm.polygonVertexBits(i) & (std::uint32_t(0) - facing);
  }
  tw.movingPolygons = movingPolygons;
  tw.movingEdges = movingEdges;
  tw.movingVertices = movingVertices;
  // The moving vertices, their ends and their extent from the centre. (In
  // locals: through tw, the size would go to memory and back at every
  // vertex, since the vertices' stores might overlap it.)
  const Vec3 start = tw.start, relative = q.start - q.placement.origin;
  Bounds size;
  for (std::uint32_t moving = movingVertices; moving; moving &= moving - 1) {
    const int i = std::countr_zero(moving);
    WorkVertex& v = tw.vertices[std::size_t(i)];
    const Vec3 p = placedTrmVertex(trm, o, i, relative);
    // (Coordinate by coordinate: stored as a whole, the vectors were built
    // on the stack with 4-byte stores and copied with an 8-byte load, which
    // waits for both stores to land: a stall per vertex.)
    v.p.x = p.x;
    v.p.y = p.y;
    v.p.z = p.z;
    v.used = true;
    size.addPoint(p - start);
    v.endp.x = p.x + dir.x;
    v.endp.y = p.y + dir.y;
    v.endp.z = p.z + dir.z;
  }
  tw.size = size;
  tw.featuresPlaced = false;  // the paths, edge lines and planes: placeTranslationFeatures
  // (min/max, not branches: the same values, the move's direction along an
  // axis being unpredictable.)
  for (int i = 0; i < 3; ++i) {
    tw.bounds.min[i] = std::min(tw.start[i], tw.end[i]) + tw.size.min[i] - tol::kBoxEpsilon;
    tw.bounds.max[i] = std::max(tw.start[i], tw.end[i]) + tw.size.max[i] + tol::kBoxEpsilon;
    tw.extents[i] = std::max(std::fabs(tw.size.min[i]), std::fabs(tw.size.max[i])) + tol::kBoxEpsilon;
  }
  tw.heartPlanesMade = false;
}

// Runs a translation (start != end) into tw; contacts mode when `out` set.
void runTranslation(TraceWork& tw, const TranslationQuery& q, const Orientation& o,
                    std::vector<ContactInfo>* out, int maxContacts) {
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
    if (o.modelRotated) {
      tw.start = q.placement.axis * tw.start;
      tw.end = q.placement.axis * tw.end;
      tw.dir = q.placement.axis * tw.dir;
    }
    setupPointTrace(tw);
  } else {
    tw.pointTrace = false;
    tw.isConvex = q.trm->isConvex();
    setupTrmTranslation(tw, q, o);
  }
  translateThroughModel(tw);
}

}  // namespace

/// Models with more brushes than this (40 bytes each: 40 KiB, about an L1
/// data cache) have their brushes prefetched on pointContents' way down; for
/// smaller ones that only costs. A speed choice only: the same brushes are
/// tested either way.
constexpr std::size_t kPointContentsCachedBrushes = 1024;

/// Whether p is behind every plane (distance < 0): inside the brush they
/// bound. Four planes at a time where SSE2 float lanes are available, each
/// lane computing Plane::distance's products and sums in its order (the
/// same distances).
inline bool behindAllPlanes(std::span<const Plane> planes, const Vec3& p) {
  std::size_t i = 0;
#ifdef CMKIT_QUERY_LANES
  using simd::F4;
  static_assert(sizeof(Plane) == 4 * sizeof(float), "a Plane is four floats: normal, dist");
  const F4 px = F4::all(p.x), py = F4::all(p.y), pz = F4::all(p.z);
  for (; i + 4 <= planes.size(); i += 4) {
    const float* f = &planes[i].normal.x;
    F4 nx = F4::loadUnaligned(f), ny = F4::loadUnaligned(f + 4), nz = F4::loadUnaligned(f + 8),
       d = F4::loadUnaligned(f + 12);
    simd::transpose(nx, ny, nz, d);
    const F4 dist = nx * px + ny * py + nz * pz - d;
    if (simd::bits(dist >= F4::zero()) != 0) return false;
  }
#endif
  for (; i < planes.size(); ++i)
    if (planes[i].distance(p) >= 0) return false;
  return true;
}

std::uint32_t pointContentsMasked(const CollisionModel& model, const Vec3& point, const Placement& placement,
                                  std::uint32_t mask) {
  // The range check waits for a point found inside something: the walk is
  // safe for any input (NaN goes down the back sides and is inside no brush)
  // and most points are in no brush. A turned model's axis is checked first:
  // an axis that is no rotation would move the point anywhere.
  const bool rotated = isRotated(placement.axis);
  if (model.nodes().empty() || (rotated && !validateAxis(placement.axis).ok())) return 0;
  Vec3 p = point - placement.origin;
  if (rotated) p = placement.axis * p;    // world -> model frame
  const Real coord[3] = {p.x, p.y, p.z};  // indexed by split axis below
  const bool prefetchBrushes = model.brushes().size() > kPointContentsCachedBrushes;

  // Every brush on the path from the root to the point's leaf: brushes
  // straddling a split are stored at interior nodes (the original looked at
  // the leaf only, and stopped at the first brush containing the point).
  // The nodes with brushes are collected on the way down (up to kPath at a
  // time) and their brushes tested from the leaf up: the deepest, smallest
  // brushes first, and a brush that could add no flag to those found is not
  // tested (the OR does not depend on the order).
  constexpr int kPath = 64;
  const CmNode* withBrushes[kPath];
  std::uint32_t contents = 0;
  std::int32_t n = 0;
  bool atLeaf = false;
  while (!atLeaf) {
    int count = 0;
    while (count < kPath) {
      const CmNode& node = model.nodes()[std::size_t(n)];
      if (node.numBrushRefs != 0) {
        withBrushes[count++] = &node;
        if (prefetchBrushes)
          for (std::int32_t b : model.brushesAt(node)) prefetch(&model.brushes()[std::size_t(b)]);
      }
      if (node.isLeaf()) {
        atLeaf = true;
        break;
      }
      n = coord[node.planeType] > node.planeDist ? node.children[0] : node.children[1];
    }
    while (count > 0) {
      for (std::int32_t brushNum : model.brushesAt(*withBrushes[--count])) {
        const CmBrush& b = model.brushes()[std::size_t(brushNum)];
        if (!(b.contents & mask & ~contents) || !b.bounds.containsPoint(p) || b.numPlanes == 0) continue;
        if (behindAllPlanes(model.planesOf(b), p)) contents |= b.contents;
      }
    }
  }
  if (contents == 0 || (withinQueryRange(point) && withinQueryRange(placement.origin))) return contents;
  return 0;  // out of range (a turned model's axis was checked first)
}

}  // namespace cmkit::detail

namespace cmkit {

using namespace detail;  // the query internals (trace_work.h)

ContentsResult contentsTest(const CollisionModel& model, const ContentsQuery& query, QueryWork& work) {
  ContentsQuery q = query;
  ContentsResult r;
  if (const QueryStatus st = guardContents(q); st != QueryStatus::Ok) {
    r.trace = refusedTrace(query.position, query.trmAxis, st);
    r.status = st;
    return r;
  }
  r.trace.endPos = q.position;
  r.trace.endAxis = q.trmAxis;
  if (isPointTrm(q.trm)) {
    // Unlike the original, a point honours the mask like any trace model.
    r.contents = pointContentsMasked(model, q.position, q.placement, q.contentMask);
    r.trace.contact.contents = r.contents;
    r.trace.fraction = r.contents == 0 ? 1 : 0;
    return r;
  }
  detail::QueryScratch& s = detail::scratchOf(work);
  s.begin(model);
  count(s, &QueryStats::queries);
  TraceWork tw(model, s);
  const Orientation o(q.trmAxis, q.placement);
  setupPositionTest(tw, *q.trm, o, q.position, q.contentMask);
  positionTestThroughModel(tw);
  r.contents = tw.c.contents;
  r.trace.contact = tw.c;
  r.trace.fraction = r.contents == 0 ? 1 : 0;
  r.trace.startSolid = r.contents != 0;
  return r;
}

TraceResult translate(const CollisionModel& model, const TranslationQuery& query, QueryWork& work) {
  // (One result object, returned on every path: made in the caller's place,
  // not copied there. A copy read back, in wide loads, fields just stored
  // one at a time: a stall per query.)
  TraceResult r;
  TranslationQuery q = query;
  if (const QueryStatus st = guardTranslation(q); st != QueryStatus::Ok) {
    r = refusedTrace(query.start, query.trmAxis, st);
    return r;
  }
  if (q.start == q.end) {
    ContentsQuery cq{q.trm, q.trmAxis, q.start, q.contentMask, q.placement};
    r = contentsTest(model, cq, work).trace;
    r.startSolid = r.fraction == 0;
    return r;
  }
  if (q.detectStartSolid) {
    ContentsQuery cq{q.trm, q.trmAxis, q.start, q.contentMask, q.placement};
    r.startSolid = contentsTest(model, cq, work).contents != 0;
  }
  detail::QueryScratch& s = detail::scratchOf(work);
  s.begin(model);
  count(s, &QueryStats::queries);
  TraceWork tw(model, s);
  const Orientation o(q.trmAxis, q.placement);
  runTranslation(tw, q, o, nullptr, 0);
  r.fraction = tw.fraction;
  r.contact = tw.c;
  r.endPos = q.start + (q.end - q.start) * r.fraction;
  r.endAxis = isPointTrm(q.trm) ? Mat3::identity() : q.trmAxis;
  if (r.fraction < 1) {
    // A tiny fraction whose movement rounds to nothing is no movement.
    if (r.fraction > 0 && r.endPos == q.start) r.fraction = 0;
    contactToWorld(r.contact, q.placement, o.modelRotated);
  }
  return r;
}

QueryStatus contacts(const CollisionModel& model, const ContactsQuery& query, QueryWork& work,
                     std::vector<ContactInfo>& out) {
  out.clear();
  ContactsQuery q = query;
  if (const QueryStatus status = guardContacts(q); status != QueryStatus::Ok) return status;
  const Vec3 end = q.start + q.dir * q.depth;
  if (end == q.start || q.maxContacts <= 0) return QueryStatus::Ok;  // a position test finds no contacts
  detail::QueryScratch& s = detail::scratchOf(work);
  s.begin(model);
  count(s, &QueryStats::queries);
  TraceWork tw(model, s);
  const TranslationQuery tq{q.trm, q.trmAxis, q.start, end, q.contentMask, q.placement, false};
  const Orientation o(q.trmAxis, q.placement);
  runTranslation(tw, tq, o, &out, q.maxContacts);
  // Unlike the original, point contacts are moved to world space too.
  for (ContactInfo& c : out) contactToWorld(c, q.placement, o.modelRotated);
  return QueryStatus::Ok;
}

ContactsResult contacts(const CollisionModel& model, const ContactsQuery& query, QueryWork& work) {
  ContactsResult result;
  result.status = contacts(model, query, work, result.contacts);
  return result;
}

PointContentsResult pointContents(const CollisionModel& model, const PointContentsQuery& query, QueryWork&) {
  PointContentsResult r;
  // The guard only decides the status: the contents are computed from the
  // query as given (a slightly drifted axis is not re-orthonormalised), so
  // that they stay what they were before pointContents had a status (every
  // input the guard refuses already gave 0).
  PointContentsQuery checked = query;
  r.status = guardPointContents(checked);
  if (r.status != QueryStatus::Ok) return r;
  r.contents = pointContentsMasked(model, query.point, query.placement, ~std::uint32_t(0));
  return r;
}

PenetrationResult penetration(const CollisionModel& model, const PenetrationQuery& query, QueryWork& work) {
  PenetrationQuery q = query;
  PenetrationResult result;
  result.status = guardPenetration(q);
  if (result.status != QueryStatus::Ok) return result;
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
