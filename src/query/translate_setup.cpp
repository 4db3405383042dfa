// A translation's set-up (the original's Translation: the trace model placed
// at the start, the features facing the move, the bounds of the sweep, the
// heart planes of the culls), the run shared with contacts (runTranslation),
// and the public translate(). The polygon tests are translate.cpp's.
#include <bit>
#include <cmath>
#include <vector>

#include "query/cull_lanes.h"
#include "query/query_guards.h"
#include "query/trace_work.h"

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
  // The farthest moving vertex from each (with float lanes four vertices at
  // a time, Plane::distance's arithmetic in each lane: the same distances,
  // the same greatest).
  Real max1 = 0, max2 = 0;
#ifdef CMKIT_QUERY_LANES
  const std::uint32_t moving = tw.movingVertices;
  const int numVerts = bitsThrough(moving);
  const Plane &h1 = tw.heartPlane1, &h2 = tw.heartPlane2;
  const F4 n1x = F4::all(h1.normal.x), n1y = F4::all(h1.normal.y), n1z = F4::all(h1.normal.z);
  const F4 n2x = F4::all(h2.normal.x), n2y = F4::all(h2.normal.y), n2z = F4::all(h2.normal.z);
  F4 far1 = F4::zero(), far2 = F4::zero();
  for (int k = 0; 4 * k < numVerts; ++k) {
    F4 x, y, z;
    trmVertexRows(tw, k, x, y, z);
    const F4 still = trmVertexLanesOutside(moving, k);  // 0 there: no farther than 0
    const F4 d1 = simd::abs(n1x * x + n1y * y + n1z * z - F4::all(h1.dist));
    const F4 d2 = simd::abs(n2x * x + n2y * y + n2z * z - F4::all(h2.dist));
    far1 = simd::max(far1, simd::andNot(still, d1));
    far2 = simd::max(far2, simd::andNot(still, d2));
  }
  max1 = simd::highest(far1);
  max2 = simd::highest(far2);
#else
  for (std::uint32_t moving = tw.movingVertices; moving; moving &= moving - 1) {
    const WorkVertex& v = tw.vertices[std::size_t(std::countr_zero(moving))];
    max1 = std::max(max1, std::fabs(tw.heartPlane1.distance(v.p)));
    max2 = std::max(max2, std::fabs(tw.heartPlane2.distance(v.p)));
  }
#endif
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
  [[maybe_unused]] const bool turned = o.trmRotated || o.modelRotated;
#ifdef CMKIT_QUERY_LANES
  if (turned) {
    // A turned trace model's (or placement's) polygons, their normals four
    // at a time, and which face the move (normal . dir as in the loop below,
    // in each lane).
    alignas(16) float nx[kMaxTrmPolygons], ny[kMaxTrmPolygons], nz[kMaxTrmPolygons];
    const F4 dx = F4::all(dir.x), dy = F4::all(dir.y), dz = F4::all(dir.z);
    std::uint32_t facing = 0;
    placeTurnedTrmPolygons(tw, trm, o, planeAxis, nx, ny, nz);
    for (int k = 0; 4 * k < tw.numPolys; ++k) {
      const F4 d = F4::load(nx + 4 * k) * dx + F4::load(ny + 4 * k) * dy + F4::load(nz + 4 * k) * dz;
      F4 faces = d > F4::zero();
      if (flat) faces = faces | (d == F4::zero());
      facing |= std::uint32_t(simd::bits(faces)) << (4 * k);
    }
    movingPolygons = facing & lowBits(tw.numPolys);
    for (std::uint32_t f = movingPolygons; f; f &= f - 1) {
      const int i = std::countr_zero(f);
      movingEdges |= trm.polygonEdgeBits(i);
      movingVertices |= trm.polygonVertexBits(i);
    }
  } else
#endif
  {
    for (int i = 0; i < tw.numPolys; ++i) {
      const Real d = placeTrmPolygon(tw.polys[std::size_t(i)], trm, i, o, planeAxis).dot(dir);
      const unsigned facing = unsigned(d > 0) | (flat & unsigned(d == 0));
      movingPolygons |= std::uint32_t(facing) << i;
      movingEdges |= trm.polygonEdgeBits(i) & (std::uint64_t(0) - facing);
      movingVertices |= trm.polygonVertexBits(i) & (std::uint32_t(0) - facing);
    }
  }
  tw.movingPolygons = movingPolygons;
  tw.movingEdges = movingEdges;
  tw.movingVertices = movingVertices;
  // The moving vertices, their ends and their extent from the centre. (In
  // locals: through tw, the size would go to memory and back at every
  // vertex, since the vertices' stores might overlap it.)
  const Vec3 start = tw.start, relative = q.start - q.placement.origin;
#ifdef CMKIT_QUERY_LANES
  // A turned trace model's (or placement's) vertices four at a time up to
  // the last moving one (placedTrmVertex's arithmetic in each lane).
  alignas(16) float placedX[kMaxTrmVertices], placedY[kMaxTrmVertices], placedZ[kMaxTrmVertices];
  if (turned)
    placedTrmVerticesInLanes(trm, o, relative, bitsThrough(movingVertices), placedX, placedY, placedZ);
#endif
  Bounds size;
  for (std::uint32_t moving = movingVertices; moving; moving &= moving - 1) {
    const int i = std::countr_zero(moving);
    WorkVertex& v = tw.vertices[std::size_t(i)];
#ifdef CMKIT_QUERY_LANES
    const Vec3 p = turned ? Vec3{placedX[i], placedY[i], placedZ[i]} : placedTrmVertex(trm, o, i, relative);
#else
    const Vec3 p = placedTrmVertex(trm, o, i, relative);
#endif
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

}  // namespace

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

}  // namespace cmkit::detail

namespace cmkit {

using namespace detail;  // the query internals (trace_work.h)

TraceResult translate(const CollisionModel& model, const TranslationQuery& query, QueryWork& work) {
  if (passesGuardUnchanged(query)) return translateGuarded(model, query, work);
  TranslationQuery q = query;
  if (const QueryStatus st = guardTranslation(q); st != QueryStatus::Ok)
    return refusedTrace(query.start, query.trmAxis, st);
  return translateGuarded(model, q, work);
}

}  // namespace cmkit

namespace cmkit::detail {

TraceResult translateGuarded(const CollisionModel& model, const TranslationQuery& q, QueryWork& work) {
  // (One result object, returned on every path: made in the caller's place,
  // not copied there. A copy read back, in wide loads, fields just stored
  // one at a time: a stall per query.)
  TraceResult r;
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

}  // namespace cmkit::detail
