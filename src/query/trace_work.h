// Internal: the state of one query (the original's cm_traceWork_t) and the
// caller-owned scratch memory it uses (the original kept those marks and
// caches inside the shared model).
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "cmkit/query.h"
#include "math/axis_lanes.h"
#include "model/query_data.h"
#include "util/assert.h"

namespace cmkit::detail {

/// A trace-model vertex during a query (model space).
struct WorkVertex {
  Vec3 p;     ///< position at the start
  Vec3 endp;  ///< position at the end of the full move
  /// The line of its movement: a point trace's; a trace model's only in
  /// portable builds (else TrmFeatures::vertexLines holds them).
  Pluecker pl;
  bool used = false;
};

/// A trace-model edge during a query.
struct WorkEdge {
  Vec3 start, end;
  int vertexNum[2] = {0, 0};
  Pluecker pl;  ///< the edge line start -> end
  Vec3 cross;   ///< normal of the plane swept by the edge (translation)
};

/// A trace-model polygon during a query.
struct WorkPolygon {
  Plane plane;
  /// The trace model's polygon (its edge list: source->numEdges signed edge
  /// numbers), not a copy: a query reads few polygons' edges, and the set-up
  /// reads only the packed normals (TraceModel::polygonNormal).
  const TrmPolygon* source = nullptr;
  int planeVertex = 0;  ///< TraceModel::polygonPlaneVertex
  bool used = false;
};

struct RotationWork;

/// Four planes as rows: lane j plane j.
struct alignas(16) TrmPlaneRows {
  Real x[kLanes], y[kLanes], z[kLanes], dist[kLanes];
};

/// The trace-model features of a query. They live in the caller's scratch
/// (about 6 KB: constructing and zeroing them per query cost more than a
/// short point trace). Every query's set-up writes the fields it uses for the
/// first numVerts / numEdges / numPolys entries; the rest is stale.
struct TrmFeatures {
  std::array<WorkVertex, kMaxTrmVertices> vertices;
  std::array<WorkEdge, kMaxTrmEdges + 1> edges;
  std::array<WorkPolygon, kMaxTrmPolygons> polys;
  /// A translation's moving vertices' paths (WorkVertex::pl) kLanes at a
  /// time: lane v % kLanes of block v / kLanes is vertex v's, 0 for a vertex
  /// that does not move (translate.cpp's SSE2 edge sides; other builds
  /// leave it unused).
  std::array<LineBlock, kMaxTrmVertices / kLanes> vertexLines;
  /// A position test's polygon planes (WorkPolygon::plane) kLanes at a
  /// time: lane i % kLanes of block i / kLanes is polygon i's; the lanes past
  /// numPolys stale (position_test.cpp's float lanes; other builds leave it
  /// unused).
  std::array<TrmPlaneRows, kMaxTrmPolygons / kLanes> planeRows;
};

/// Polygon edges per bit mask in the translation's edge tests.
inline constexpr std::size_t kEdgeGroup = 64;
/// Number of kEdgeGroup-edge groups (bit masks) a polygon's edges take.
inline constexpr std::size_t edgeGroups(std::size_t numEdges) {
  return (numEdges + kEdgeGroup - 1) / kEdgeGroup;
}

/// One query's marks of a kind of model feature (its polygons, brushes,
/// edges or vertices): a 16-bit stamp per feature, marked when it equals the
/// current one. clear() starts the next query's marks by a new stamp (every
/// stamp cleared when they run out: once every 65 535 queries, a few bytes a
/// query however large the model). Two bytes, not four: a large mesh's
/// marks, read at random by its sweeps, take half the memory.
class FeatureMarks {
 public:
  /// Room for n features (grown only).
  void grow(std::size_t n) {
    if (stamps_.size() < n) stamps_.resize(n);
  }
  bool isSet(std::size_t i) const {
    CMKIT_ASSERT(i < stamps_.size());
    return stamps_[i] == current_;
  }
  /// Marks feature i; true when it was marked already.
  bool testAndSet(std::size_t i) {
    CMKIT_ASSERT(i < stamps_.size());
    if (stamps_[i] == current_) return true;
    stamps_[i] = current_;
    return false;
  }
  /// The same without a branch: the stamp is stored either way (for loops
  /// where whether a feature was met before is unpredictable).
  bool testAndSetStoring(std::size_t i) {
    CMKIT_ASSERT(i < stamps_.size());
    const bool was = stamps_[i] == current_;
    stamps_[i] = current_;
    return was;
  }
  /// Clears every mark.
  void clear() {
    if (++current_ == 0) {  // the stamps ran out: start again from 1
      std::fill(stamps_.begin(), stamps_.end(), std::uint16_t(0));
      current_ = 1;
    }
  }

 private:
  std::vector<std::uint16_t> stamps_;  ///< 0: never marked
  std::uint16_t current_ = 1;
};

/// Per-model-feature marks and caches, valid for one query (what a QueryWork
/// holds). A mark or cache entry is valid when its stamp or generation
/// equals the current one (FeatureMarks), so starting a query costs nothing
/// but a counter increment per kind.
struct QueryScratch {
  /// What a rotation keeps about one model edge: the trace-model edges
  /// already tested against it (bit trmEdgeBit(j)). (Apart from the edge's
  /// mark, edgeChecked: a translation reads only the mark.) Side
  /// tests are computed where they are needed, in one operand order per
  /// test, not cached: a scattered cache entry cost more than the products
  /// it saved.
  struct EdgePairs {
    std::uint32_t pairsGen = 0;     ///< testedPairs valid (== generation)
    std::uint32_t testedPairs = 0;  ///< rotation: trace-model edges tested against this edge
  };
  static_assert(kMaxTrmEdges <= 32, "EdgePairs has one bit per trace-model edge");

  std::uint32_t generation = 0;            ///< of the caches (EdgePairs)
  FeatureMarks polygonChecked;             ///< polygon tested this query
  FeatureMarks polygonMet;                 ///< polygon counted as met (QueryStats builds only)
  FeatureMarks brushChecked;               ///< brush tested this query
  FeatureMarks edgeChecked;                ///< model edge tested this query
  std::vector<EdgePairs> edgePairs;        ///< per model edge (rotations)
  FeatureMarks vertexChecked;              ///< model vertex tested this query
  std::vector<Pluecker> polygonEdgeLines;  ///< per edge of the current polygon (polygonEdges)
  // Translation: the current polygon's edges in groups of kEdgeGroup, bit i
  // of a group's mask standing for edge kEdgeGroup * group + i.
  /// Bit i of vertexEdgeSides[group * kMaxTrmVertices + v]: the path of
  /// trace-model vertex v passes edge i's line on the negative side.
  std::vector<std::uint64_t> vertexEdgeSides;
  std::vector<std::uint64_t> edgesToTest;  ///< per group: edges to test against the trace-model edges
  /// The current polygon's edge uses (model/query_data.h), for a model
  /// without query data (ModelAccess::withoutQueryData: tests of that path).
  std::vector<EdgeUse> edgeUses;
  /// A part of the move still to walk: node, fractions and points at its ends.
  struct WalkSegment {
    std::int32_t node;
    Real p1f, p2f;
    Vec3 p1, p2;
  };
  std::vector<WalkSegment> walkStack;   ///< the far sides the tree walk has still to visit
  std::vector<std::int32_t> nodeStack;  ///< nodes a box walk has still to visit (penetration)
  /// Point-tree nodes a position test or a rotation's box walk has still to visit.
  std::vector<std::uint32_t> pointStack;
  /// A child of the polygons' hierarchy still to visit, and the fraction at
  /// which the move reaches its (grown) box.
  struct BvhEntry {
    std::int32_t child;
    float near;
  };
  std::vector<BvhEntry> bvhStack;  ///< the hierarchy walk's children still to visit
  TrmFeatures trm;                 ///< the trace model of the current query
  QueryStats stats;                ///< work counters (count(), CMKIT_QUERY_STATS builds)
  /// A rotation part's per-feature data (rotate_work.h), made on the first
  /// rotation: about 3 KB that a rotation part would otherwise construct.
  std::unique_ptr<RotationWork> rotation;

  /// Starts a query on `model`: sizes the arrays and invalidates all marks.
  void begin(const CollisionModel& model);

  // (The marks are grown to the model by begin(): an index past them is a
  // number of the model out of range, which create() refuses.)
  bool isChecked(const FeatureMarks& marks, std::size_t i) const { return marks.isSet(i); }
  void mark(FeatureMarks& marks, std::size_t i) { marks.testAndSet(i); }
  bool testAndMark(FeatureMarks& marks, std::size_t i) { return marks.testAndSet(i); }
  /// testAndMark without a branch (FeatureMarks::testAndSetStoring).
  bool testAndMarkStoring(FeatureMarks& marks, std::size_t i) { return marks.testAndSetStoring(i); }
  /// The rotation's tested pairs of an edge for this query (zeroed on first use).
  std::uint32_t& testedPairs(EdgePairs& f) {
    if (f.pairsGen != generation) {
      f.pairsGen = generation;
      f.testedPairs = 0;
    }
    return f.testedPairs;
  }
};

/// True in a library built with -DCMKIT_QUERY_STATS=ON: the queries count
/// their work in QueryScratch::stats.
#ifdef CMKIT_QUERY_STATS
inline constexpr bool kQueryStats = true;
#else
inline constexpr bool kQueryStats = false;
#endif

/// Adds n to one work counter; compiled out unless kQueryStats.
inline void count(QueryScratch& s, std::uint64_t QueryStats::*counter, std::uint64_t n = 1) {
  if constexpr (kQueryStats) s.stats.*counter += n;
}

/// The loop of every item test: for each of `items` (polygon or brush
/// numbers) not met before in this query, marks it, counts it in `met` and
/// calls test(item), which returns true when the query is over (stuck or
/// stopped); returns whether one did.
template <class Test>
bool forEachNewItem(QueryScratch& s, FeatureMarks& marks, std::uint64_t QueryStats::*met,
                    std::span<const std::int32_t> items, Test test) {
  for (const std::int32_t item : items) {
    if (s.testAndMark(marks, std::size_t(item))) continue;
    count(s, met);
    if (test(item)) return true;
  }
  return false;
}

/// The library's way into a QueryWork (its scratch is private to users).
struct QueryWorkAccess {
  static QueryScratch& scratch(QueryWork& work) { return *work.scratch_; }
};
inline QueryScratch& scratchOf(QueryWork& work) { return QueryWorkAccess::scratch(work); }

/// A hint to start loading the cache line at p (no effect on results).
inline void prefetch(const void* p) {
#if defined(__GNUC__)
  __builtin_prefetch(p);
#else
  (void)p;
#endif
}

/// The side-cache bit of trace-model edge n (signed or not; 1 <= |n| <= 32).
inline unsigned trmEdgeBit(int n) { return unsigned(std::abs(n) - 1); }

struct Orientation;

/// The state of one translation / position test / contacts query.
struct TraceWork {
  TraceWork(const CollisionModel& m, QueryScratch& s)
      : model(m),
        queryData(queryDataOf(m)),
        scratch(s),
        vertices(s.trm.vertices),
        edges(s.trm.edges),
        polys(s.trm.polys) {}

  const CollisionModel& model;
  /// The model's derived data, when made for it (else null: computed per polygon).
  const QueryData* queryData;
  QueryScratch& scratch;

  int numVerts = 0, numEdges = 0, numPolys = 0;
  std::array<WorkVertex, kMaxTrmVertices>& vertices;  ///< scratch.trm.vertices
  std::array<WorkEdge, kMaxTrmEdges + 1>& edges;      ///< scratch.trm.edges
  std::array<WorkPolygon, kMaxTrmPolygons>& polys;    ///< scratch.trm.polys

  /// A position test's or translation's trace model, and a position test's
  /// orientations (they outlive the query), for the parts placed only when
  /// a polygon needs them.
  const TraceModel* placedTrm = nullptr;
  const Orientation* placedOrientation = nullptr;

  Vec3 start, end, dir;  ///< of the trace model's centre, model space
  Bounds bounds;         ///< of the whole move, padded
  Bounds size;           ///< trace-model bounds relative to start
  Vec3 extents;          ///< per-axis half size for the tree walk
  std::uint32_t contentMask = 0;
  bool isConvex = true;
  bool pointTrace = false;
  bool quickExit = false;
  /// The trace-model data that only a polygon past its culls needs (edge
  /// lines, polygon planes; translations also the vertices' paths) is placed:
  /// made on the first such polygon, since most queries meet few or none.
  bool featuresPlaced = false;
  /// Position tests: bit i, trace-model edge i's line is made (each when a
  /// polygon test first reads it: most read a few edges). None at the start
  /// of a query (a TraceWork is made per query; the lines in the scratch
  /// are the last query's).
  std::uint64_t edgeLinesPlaced = 0;
  // Translation: the trace-model features used (facing the movement), as
  // bit masks set up once: bit v for vertex v (whose movement line
  // WorkVertex::pl is set), bit i for edge i, bit j for polygon j.
  std::uint32_t movingVertices = 0;
  std::uint64_t movingEdges = 0;
  std::uint32_t movingPolygons = 0;

  // the result so far
  Real fraction = 1;
  ContactInfo c;

  // heart planes: along the movement, for culling far polygons (a
  // translation makes them for its first polygon past the box cull:
  // makeTranslationHeartPlanes)
  Plane heartPlane1, heartPlane2;
  Real maxDistFromHeartPlane1 = 0, maxDistFromHeartPlane2 = 0;
  bool heartPlanesMade = false;

  // rotations (rotate.cpp): the per-feature rotation data; null otherwise
  RotationWork* rotation = nullptr;

  // contacts mode
  std::vector<ContactInfo>* contacts = nullptr;
  int maxContacts = 0;

  bool gettingContacts() const { return contacts != nullptr; }
  /// Records the current contact (contacts mode) and resets the fraction so
  /// that the walk finds every other one.
  void addContact() {
    if (int(contacts->size()) >= maxContacts) return;
    // One allocation for the usual handful of contacts, made on the first.
    if (contacts->capacity() == 0) contacts->reserve(std::size_t(std::min(maxContacts, 16)));
    contacts->push_back(c);
    fraction = 1;
  }
};

/// The contacts a query has collected so far (0 when it does not collect).
inline std::size_t contactCount(const TraceWork& tw) { return tw.contacts ? tw.contacts->size() : 0; }
/// Counts a tested polygon whose tests brought the nearest contact closer
/// than `before` or added to the `contactsBefore` collected
/// (QueryStats::polygonsCloser; nothing unless counted).
inline void countCloser(TraceWork& tw, Real before, std::size_t contactsBefore) {
  if constexpr (kQueryStats)
    if (tw.fraction < before || contactCount(tw) > contactsBefore) ++tw.scratch.stats.polygonsCloser;
}

// ---- shared steps (tree_walk.cpp, translate.cpp, position_test.cpp) --------

/// Walks the model's tree along tw.start -> tw.end testing the polygons met
/// for a translation (a point's or a trace model's, by tw.pointTrace).
void translateThroughModel(TraceWork& tw);
/// translateThroughModel through the polygons' hierarchy (bvh_walk.cpp);
/// false, doing nothing, when the model has none (no query data, or a build
/// without float lanes).
bool translateThroughBvh(TraceWork& tw);
/// Walks the model's tree around tw.start for a position test (brushes, then
/// polygons), stopping once stuck.
void positionTestThroughModel(TraceWork& tw);
/// Walks the model's tree with a box (every node the box touches) testing
/// the polygons met for a rotation part (the box of a piece of the arc).
void rotateThroughBox(TraceWork& tw, const Bounds& box);

/// A translation's heart planes and the trace model's greatest distances
/// from them (translate_setup.cpp), made when a polygon first needs them (most queries'
/// polygons fail the box cull before).
void makeTranslationHeartPlanes(TraceWork& tw);
/// Runs a translation (start != end) into tw, set up from the query
/// (translate_setup.cpp); contacts mode, collecting up to maxContacts
/// contacts, when `out` is set (contacts.cpp).
void runTranslation(TraceWork& tw, const TranslationQuery& q, const Orientation& o,
                    std::vector<ContactInfo>* out, int maxContacts);
/// The OR of the contents matching `mask` of every brush containing a world
/// point (point_contents.cpp; contentsTest's points and pointContents). The
/// placement must have passed a guard (its axis a rotation): it is not
/// checked again.
std::uint32_t pointContentsMasked(const CollisionModel& model, const Vec3& point, const Placement& placement,
                                  std::uint32_t mask);

/// Translation tests of a list of polygons (a node's) for a trace model;
/// true when one blocks completely.
bool translateTrmThroughPolygons(TraceWork& tw, std::span<const std::int32_t> polygons);
/// The same for a node's polygons (from the model's query data when it has it).
bool translateTrmThroughNode(TraceWork& tw, const CmNode& node);
/// The same for a point trace and a list of polygons (a node's).
bool translatePointThroughPolygons(TraceWork& tw, std::span<const std::int32_t> polygons);
/// The tests of one polygon past a translation's culls (translate.cpp): the
/// plane test, then the trace-model vertices, edges and the model vertices
/// against it; true when the trace model is blocked completely. `corners`:
/// the polygon's corners (poly.numEdges of them; the polygons' hierarchy's;
/// poly.firstEdge then not read), or null for the model's edge uses.
bool translateTrmThroughPolygon(TraceWork& tw, std::int32_t polyNum, const CmPolygon& poly,
                                const PolygonCorner* corners = nullptr);
/// A point trace (no edges, no polygons) through a polygon. The edge sides
/// are not cached: a point meets few polygons, and computing a side costs
/// less than reading a cache entry of a large model.
void translatePointThroughPolygon(TraceWork& tw, std::int32_t polyNum, const CmPolygon& poly);
/// A nearer hit shrinks a translation's trace bounds (not when collecting
/// contacts).
void shrinkTraceBounds(TraceWork& tw);
/// The lanes `pass` of leaf `leaf` of the polygons' hierarchy (those whose
/// contents and bounds passed), culled further and tested in lane order, by
/// a trace model's or a point's translation. True when the trace model is
/// blocked completely (or the walk may stop: tw.quickExit).
bool translateTrmThroughBvhLeaf(TraceWork& tw, const PolygonBvh& bvh, std::size_t leaf, unsigned pass);
bool translatePointThroughBvhLeaf(TraceWork& tw, const PolygonBvh& bvh, std::size_t leaf, unsigned pass);

/// Rotation tests of a list of polygons (a node's; rotate.cpp); true when
/// one blocks completely.
bool rotateTrmThroughPolygons(TraceWork& tw, std::span<const std::int32_t> polygons);
/// The same for a node's polygons (from the model's query data when it has it).
bool rotateTrmThroughNode(TraceWork& tw, const CmNode& node);

/// Position tests (position_test.cpp); true when stuck.
/// testTrmVertsInBrushes: a trace-model vertex inside one of the brushes?
/// testTrmInPolygons: the trace model crossing one of the polygons? True
/// (stuck, tw.c set) at the first; items met before in the query are skipped.
bool testTrmVertsInBrushes(TraceWork& tw, std::span<const std::int32_t> brushes);
bool testTrmInPolygons(TraceWork& tw, std::span<const std::int32_t> polygons);
/// testTrmInPolygons of a node's polygons, from the query data's cull blocks
/// where the model has them.
bool testTrmInNodePolygons(TraceWork& tw, const CmNode& node);

/// A box against a plane: the distance of its centre (`centre`) and the
/// half extent of the box along the plane's normal (`extent`).
struct BoxPlaneSpan {
  Real centre, extent;
};
inline BoxPlaneSpan boxPlaneSpan(const Bounds& b, const Plane& plane) {
  const Vec3 c = b.center();
  return {plane.distance(c), std::fabs((b.max.x - c.x) * plane.normal.x) +
                                 std::fabs((b.max.y - c.y) * plane.normal.y) +
                                 std::fabs((b.max.z - c.z) * plane.normal.z)};
}

/// Distance of a box to a plane: 0 when it straddles the plane.
inline Real boundsPlaneDistance(const Bounds& b, const Plane& plane) {
  const auto [d1, d2] = boxPlaneSpan(b, plane);
  if (d1 - d2 > 0) return d1 - d2;
  if (d1 + d2 < 0) return d1 + d2;
  return 0;
}

/// fabs(boundsPlaneDistance(b, plane)) > maxDist for maxDist >= 0, without
/// branches: the whole box is farther than maxDist from the plane.
inline bool boxBeyondPlane(const Bounds& b, const Plane& plane, Real maxDist) {
  const auto [d1, d2] = boxPlaneSpan(b, plane);
  return (d1 - d2 > maxDist) | (-(d1 + d2) > maxDist);
}

/// Bounds::intersects and Bounds::containsPoint with all six comparisons
/// made (| rather than ||): for a trace model's bounds which polygons and
/// vertices pass is unpredictable, and a mispredicted branch costs more than
/// the comparisons it would skip. (Point traces keep the short-circuit forms:
/// their thin bounds reject most items at the first comparison.)
inline bool boxesTouch(const Bounds& a, const Bounds& b) {
  return !((b.max.x < a.min.x) | (b.max.y < a.min.y) | (b.max.z < a.min.z) | (b.min.x > a.max.x) |
           (b.min.y > a.max.y) | (b.min.z > a.max.z));
}
inline bool insideBox(const Bounds& b, const Vec3& p) {
  return !((p.x < b.min.x) | (p.y < b.min.y) | (p.z < b.min.z) | (p.x > b.max.x) | (p.y > b.max.y) |
           (p.z > b.max.z));
}

/// What the plane test of a polygon against the trace bounds decides.
enum class PlaneCull {
  Test,  ///< the bounds straddle the plane: test the polygon
  Skip,  ///< the bounds are entirely on one side: nothing to test
  Stop,  ///< in front of a convex model's face: nothing of the model can be hit
};
/// The plane test shared by translations, rotations and position tests
/// (sets tw.quickExit for Stop).
inline PlaneCull cullByPolygonPlane(TraceWork& tw, const Plane& plane) {
  switch (tw.bounds.planeSide(plane)) {
    case Side::Cross:
      return PlaneCull::Test;
    case Side::Front:
      if (tw.model.isConvex()) {
        tw.quickExit = true;
        return PlaneCull::Stop;
      }
      return PlaneCull::Skip;
    default:
      return PlaneCull::Skip;
  }
}

// ---- placing the trace model (placement.cpp) ------------------------------

/// A query's two orientations, the trace model's and the model's
/// placement, with whether each differs from the identity (asked once per
/// query: the placement functions below and contactToWorld read the flags).
/// It refers to the query's own axes, which outlive the query's work.
struct Orientation {
  Orientation(const Mat3& trm, const Placement& model)
      : trmAxis(&trm), placement(&model), trmRotated(isRotated(trm)), modelRotated(isRotated(model)) {}
  const Mat3* trmAxis;
  const Placement* placement;
  bool trmRotated;
  bool modelRotated;
};

/// The trace model's centre (position + its offset) in the model's frame.
/// (Inline: returned from another unit, the vector went through the stack
/// and stalled its reader.)
inline Vec3 trmCentreInModel(const TraceModel& trm, const Orientation& o, const Vec3& position) {
  Vec3 c = position - o.placement->origin;
  c += o.trmRotated ? trm.offset() * *o.trmAxis : trm.offset();
  if (o.modelRotated) c = o.placement->axis * c;
  return c;
}

/// What turns a trace-model polygon's normal into the model's frame when
/// the trace model is turned: local -> world (n * trmAxis) -> model frame
/// (n * axis^T), as one matrix, made in `both` when both are turned, else
/// the trace model's axis itself. (Not a copy: the placement loops read it
/// back in wide loads, which waited for a copy's narrow stores to land.)
inline const Mat3& trmPlaneAxis(const Orientation& o, Mat3& both) {
  if (!(o.trmRotated && o.modelRotated)) return *o.trmAxis;
  both = *o.trmAxis * o.placement->axis.transposed();
  return both;
}
/// Trace-model polygon i's work polygon: its source, plane vertex and normal
/// in the model's frame (planeAxis: trmPlaneAxis(o, ...)); returns the normal.
inline Vec3 placeTrmPolygon(WorkPolygon& wp, const TraceModel& trm, int i, const Orientation& o,
                            const Mat3& planeAxis) {
  wp.source = &trm.polygon(i);  // (its address only: not read here)
  wp.planeVertex = trm.polygonPlaneVertex(i);
  const Vec3& local = trm.polygonNormal(i);
  const Vec3 n = o.trmRotated ? local * planeAxis : (o.modelRotated ? o.placement->axis * local : local);
  wp.plane.normal = n;
  return n;
}
/// Trace-model vertex i in the model's frame, the trace model at `relative`
/// (its position - the model's origin: made once by the caller's loop).
inline Vec3 placedTrmVertex(const TraceModel& trm, const Orientation& o, int i, const Vec3& relative) {
  Vec3 p = trm.vertex(i);
  if (o.trmRotated) p = p * *o.trmAxis;
  p += relative;
  if (o.modelRotated) p = o.placement->axis * p;
  return p;
}

/// Bits 0 .. n - 1 set (n <= 32): the first n vertices, polygons or lanes.
inline std::uint32_t lowBits(int n) { return n >= 32 ? ~std::uint32_t(0) : (std::uint32_t(1) << n) - 1; }
/// The mask of a trace model's vertices 0..numVerts-1.
inline std::uint32_t allTrmVertices(int numVerts) { return lowBits(numVerts); }
/// One past the highest bit of `mask` (0 for none): how many of a trace
/// model's vertices reach its last one that `mask` names.
inline int bitsThrough(std::uint32_t mask) { return 32 - std::countl_zero(mask); }

/// Placing `trm` (turned by its axis) at `position` in the model's frame,
/// the set-up every query kind starts from, in three parts that a kind may
/// take separately (a translation places only the vertices of the polygons
/// facing the move; a position test places the edges and polygons only for
/// a polygon past its culls). The kinds add what they use (used flags, edge
/// lines, plane distances, motion).
/// The frame: tw's feature counts and tw.start (the centre).
void placeTrmFrame(TraceWork& tw, const TraceModel& trm, const Orientation& o, const Vec3& position);
/// The positions of the vertices in the mask `vertices`.
void placeTrmVertices(TraceWork& tw, const TraceModel& trm, const Orientation& o, const Vec3& position,
                      std::uint32_t vertices);
/// The edges' vertex numbers, the polygons' edges and normals.
void placeTrmTopology(TraceWork& tw, const TraceModel& trm, const Orientation& o);
/// All three, every vertex.
void placeTrm(TraceWork& tw, const TraceModel& trm, const Orientation& o, const Vec3& position);

/// Moves a contact from the model's frame to the world; `rotated`: the
/// placement's axis is not the identity.
void contactToWorld(ContactInfo& c, const Placement& placement, bool rotated);

/// Sets up tw for a position test of `trm` (not a point) at `position`.
/// `o` must outlive the test (the edges and polygons are placed on demand).
void setupPositionTest(TraceWork& tw, const TraceModel& trm, const Orientation& o, const Vec3& position,
                       std::uint32_t mask);

/// True for a missing trace model or one with zero size on every axis.
inline bool isPointTrm(const TraceModel* trm) {
  if (!trm || trm->isPoint()) return true;
  const Vec3 s = trm->bounds().size();
  return s.x <= 0 && s.y <= 0 && s.z <= 0;
}

}  // namespace cmkit::detail
