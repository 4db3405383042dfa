// query.h: moving trace models through collision models.
//
// CONTRACT
// - Units are map units; angles in degrees. Every query names the model's
//   place in the world `placement` (a Placement: `origin`, and `axis` whose
//   rows are the model's axes); a trace model is at a position with
//   orientation `trmAxis`. Results are in world space unless stated.
// - translate(): the trace model's centre moves from `start` to `end`; the
//   result's `fraction` in [0, 1] says how far it got before the first
//   surface whose contents match `contentMask`. Collision is exact and
//   continuous (Plücker-coordinate tests of trace-model vertices against model
//   polygons, trace-model edges against model edges, model vertices against
//   trace-model polygons), and the move stops tol::kClipEpsilon (0.25 units)
//   in front of the surface along its normal, so that the next move starts
//   free. Only the front faces of polygons collide; internal edges (concave
//   creases, edges lying on other faces) are never hit.
// - start == end is a POSITION TEST: it reports whether the trace model
//   overlaps anything (fraction 0) or not (fraction 1). Position tests and
//   contentsTest() have no epsilon: exactly touching is not stuck.
// - Starting inside solid: translations follow the original's rules (a move
//   that starts in solid is not necessarily stopped), so fractions stay
//   comparable with it; `startSolid` on the result tells that the start
//   position overlaps solid (when TranslationQuery::detectStartSolid), and
//   penetration() tells how deep and which way out.
// - Any translation length works (the original refused trace-model moves
//   over 4096 units).
// - rotate(): exact rotations about an arbitrary axis; see RotationQuery.
// - Cost order (cheapest first): pointContents, contentsTest, translate with a
//   point, translate with a trace model, contacts. For many point rays that
//   need the surface crossing rather than the original's point trace, a
//   RayIndex (ray_index.h) is about three times faster than translate().
// THREAD SAFETY
// - A CollisionModel is immutable; all queries are const functions of it.
//   Per-query scratch state (visited marks, the placed trace model) lives in a
//   QueryWork that the caller owns. Use one QueryWork per thread; reuse it
//   across queries and models (it grows to the largest model and never
//   shrinks). Results are deterministic: the same query gives the same bits on
//   any thread.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "cmkit/contents.h"
#include "cmkit/math.h"
#include "cmkit/model.h"
#include "cmkit/rotation.h"
#include "cmkit/trace_model.h"

namespace cmkit {

/// Whether a query ran, or which of its inputs made it refuse. Every public
/// query checks its input first (src/query/query_guards.cpp). A REFUSED
/// query does nothing: fraction 0, endPos = start and endAxis = trmAxis as
/// given, no contact, contents 0, no contacts, not stuck; only `status`
/// says why. Accepted but normalised: an orientation (trmAxis,
/// placement.axis) off orthonormal by at most tol::kAxisRejectTolerance is
/// re-orthonormalised when off by more than tol::kAxisDriftEpsilon
/// (validateAxis), a rotation axis within tol::kRotationAxisUnitTolerance of
/// unit length is normalised (when off by more than kAxisDriftEpsilon).
enum class QueryStatus : std::uint8_t {
  Ok,               ///< the query ran
  BadTrmAxis,       ///< trmAxis (of a trace model that is not a point) is not a rotation:
                    ///< non-finite, scaled or sheared, or mirrored (determinant < 0)
  BadModelAxis,     ///< placement.axis is not a rotation (as above)
  NonFinite,        ///< a position, origin, direction, depth or angle is NaN or infinite
  OutOfRange,       ///< a coordinate, the end of the move or the trace model's bounds lie beyond
                    ///< tol::kMaxQueryCoordinate
  BadRotationAxis,  ///< the rotation axis is zero or not of unit length
  MixedMotion,      ///< a contacts query given both a translation (dir * depth not zero) and a rotation
};

/// A short English description of a status ("ok", "trace-model axis is not a
/// rotation", ...): the text of the CLI's "error=refused: ..." lines.
const char* toString(QueryStatus status);

/// Which features touched.
enum class ContactType : std::uint8_t {
  None,         ///< no contact
  Edge,         ///< a trace-model edge hit a model edge
  ModelVertex,  ///< a model vertex hit a trace-model polygon
  TrmVertex,    ///< a trace-model vertex hit a model polygon
};

/// The name of a contact type, as written in query-format result lines:
/// "none", "edge", "modelvertex", "trmvertex" (parseContactType in
/// cmkit/tools/query_format.h reads it back).
const char* toString(ContactType type);

/// The contact of a trace. Every field is defined on every path; on a miss
/// everything is zero, material -1.
struct ContactInfo {
  /// Which features touched.
  ContactType type = ContactType::None;
  Vec3 point;  ///< contact point (see the per-type notes in docs/fidelity.md)
  /// Normal of the contact plane, facing the trace model: against the motion
  /// of the contact point (translations; rotations along the arc at the
  /// contact), for starts in solid too; see RotationQuery.
  Vec3 normal;
  Real dist = 0;               ///< normal . p = dist on the contact plane
  std::uint32_t contents = 0;  ///< contents of the surface hit
  std::int32_t material = -1;  ///< index into the model's materials, -1 = none
  /// Model feature: polygon index (TrmVertex), signed edge number (Edge) or
  /// vertex index (ModelVertex). Position tests: see docs/fidelity.md.
  std::int32_t modelFeature = 0;
  /// Trace-model feature: vertex index (TrmVertex), edge number (Edge) or
  /// polygon index (ModelVertex).
  std::int32_t trmFeature = 0;
  /// Degrees turned when the contact is met, signed as the rotation's angle:
  /// set by contacts() with a rotation (ContactsQuery::rotation); 0 for every
  /// other query (rotate() reports its stop as TraceResult::fraction).
  Real angle = 0;
};

/// The result of a translation, rotation or position test.
struct TraceResult {
  Real fraction = 1;  ///< fraction of the movement completed, 1 = no contact
  Vec3 endPos;        ///< position of the trace model after the move
  Mat3 endAxis;       ///< orientation of the trace model after the move
  /// The contact (all zero, material -1, when fraction is 1).
  ContactInfo contact;
  /// True when the start position overlaps a brush or polygon matching the
  /// mask (only computed when the query asks for it).
  bool startSolid = false;
  /// QueryStatus::Ok, or why the query was refused (see QueryStatus).
  QueryStatus status = QueryStatus::Ok;
};

namespace detail {
struct QueryScratch;
struct QueryWorkAccess;
}  // namespace detail

/// Work counters of the queries run with one QueryWork, summed since it was
/// made or last reset: where a query's time goes, independent of the
/// machine. They are counted only by a library built with
/// -DCMKIT_QUERY_STATS=ON (queryStatsEnabled()); in other builds the
/// counting code is not compiled in and every counter stays 0.
struct QueryStats {
  std::uint64_t queries = 0;         ///< translations, rotations, contents tests and contacts queries
  std::uint64_t nodesVisited = 0;    ///< tree nodes entered by the walks
  std::uint64_t polygonsMet = 0;     ///< polygons met at those nodes for the first time in a query
  std::uint64_t polygonsTested = 0;  ///< of those, polygons past every polygon cull (features tested)
  /// Of those, polygons whose tests brought the nearest contact closer (a
  /// translation's or rotation's; a position test's: the polygon it found
  /// crossed). Collecting contacts, each polygon that adds one.
  std::uint64_t polygonsCloser = 0;
  std::uint64_t brushesMet = 0;  ///< brushes met for the first time by position tests
  std::uint64_t vertexTests =
      0;                        ///< trace-model vertex / polygon and model vertex / trace-model polygon tests
  std::uint64_t edgePairs = 0;  ///< trace-model edge / model edge tests
};

/// True when the library counts QueryStats (built with -DCMKIT_QUERY_STATS=ON).
bool queryStatsEnabled();

/// Caller-owned scratch memory for queries (one per thread; reusable). Its
/// contents are the library's own business: a QueryWork is only created,
/// moved and handed to queries (and asked for its work counters).
class QueryWork {
 public:
  QueryWork();
  ~QueryWork();
  /// Moves the scratch memory.
  QueryWork(QueryWork&&) noexcept;
  /// Moves the scratch memory.
  QueryWork& operator=(QueryWork&&) noexcept;
  QueryWork(const QueryWork&) = delete;
  QueryWork& operator=(const QueryWork&) = delete;

  /// The work counters of the queries run with this QueryWork (all 0 unless
  /// queryStatsEnabled()).
  const QueryStats& stats() const;
  /// Sets every work counter back to 0.
  void resetStats();

 private:
  friend struct detail::QueryWorkAccess;
  std::unique_ptr<detail::QueryScratch> scratch_;
};

/// Where a model is placed in the world.
struct Placement {
  /// Position of the model's origin in the world.
  Vec3 origin;
  Mat3 axis;  ///< rows = the model's axes in world space
};

/// A translation (or, with start == end, a position test).
struct TranslationQuery {
  const TraceModel* trm = nullptr;  ///< nullptr or a point shape: a point trace
  /// Orientation of the trace model (rows: its axes).
  Mat3 trmAxis;
  /// Position of the trace model at the start.
  Vec3 start;
  /// Position of the trace model at the end of the move.
  Vec3 end;
  /// Content flags the queries collide with.
  std::uint32_t contentMask = contents::kMaskSolid;
  /// Where the model is placed in the world.
  Placement placement;
  /// Also run a position test at the start and set TraceResult::startSolid.
  bool detectStartSolid = false;
};

/// Moves a trace model (or a point) from start to end through a placed model.
TraceResult translate(const CollisionModel& model, const TranslationQuery& query, QueryWork& work);

/// A position test: what does a placed trace model overlap?
struct ContentsQuery {
  const TraceModel* trm = nullptr;  ///< nullptr or a point shape: point contents
  /// Orientation of the trace model.
  Mat3 trmAxis;
  /// Position of the trace model.
  Vec3 position;
  /// Content flags the queries collide with.
  std::uint32_t contentMask = contents::kMaskSolid;
  /// Where the model is placed in the world.
  Placement placement;
};

/// Result of contentsTest(): the contents of the first brush or polygon found
/// overlapping that matches the mask (that item's whole contents; 0 when
/// free), and the trace describing that contact (fraction 0 when stuck, 1
/// when free). For a point (no trace model, or a point shape): the OR of the
/// contents of every brush containing the point that matches the mask (the
/// original ignored the mask for a point and took the first brush found).
/// A refused query (`status`, also in trace.status) has contents 0.
struct ContentsResult {
  /// Contents of what the trace model overlaps (0: free).
  std::uint32_t contents = 0;
  /// The contact found (fraction 0 when stuck, 1 when free); its status is
  /// `status`.
  TraceResult trace;
  QueryStatus status = QueryStatus::Ok;  ///< refused: contents 0 (see QueryStatus)
};

/// The original's Contents: what the placed trace model overlaps.
ContentsResult contentsTest(const CollisionModel& model, const ContentsQuery& query, QueryWork& work);

/// Which brushes contain a world point (no trace model, no mask).
struct PointContentsQuery {
  /// The point (world space).
  Vec3 point;
  /// Where the model is placed in the world.
  Placement placement;
};

/// Result of pointContents().
struct PointContentsResult {
  /// The OR of the contents of every brush containing the point (0: none).
  std::uint32_t contents = 0;
  QueryStatus status = QueryStatus::Ok;  ///< refused: contents 0 (see QueryStatus)
};

/// The contents of the brushes containing a world point (no mask): the OR of
/// every brush the point is strictly inside. Unlike the original (which
/// returns the first brush found in the leaf), all brushes are seen,
/// including those stored at interior tree nodes, and a rotated model is
/// handled correctly. A point or placement origin that is not finite
/// (NonFinite) or beyond tol::kMaxQueryCoordinate (OutOfRange), or a
/// placement axis that is no rotation (BadModelAxis), is refused: contents 0.
/// `work` is not used today (the signature is that of every query, for
/// layouts that will need scratch).
PointContentsResult pointContents(const CollisionModel& model, const PointContentsQuery& query,
                                  QueryWork& work);

/// All contacts of a trace model moved up to `depth` along `dir`, or turned
/// up to an angle about an axis (`rotation`).
struct ContactsQuery {
  /// The trace model moved (nullptr or a point shape: a point).
  const TraceModel* trm = nullptr;
  /// Orientation of the trace model.
  Mat3 trmAxis;
  /// Position of the trace model at the start.
  Vec3 start;
  Vec3 dir;  ///< direction of the move (need not be unit: end = start + dir * depth)
  /// How far to move along dir.
  Real depth = 0;
  /// Content flags the queries collide with.
  std::uint32_t contentMask = contents::kMaskSolid;
  /// Where the model is placed in the world.
  Placement placement;
  /// At most this many contacts are returned.
  int maxContacts = 16;
  /// Set: ROTATIONAL contacts. The trace model turns from `start` by
  /// `rotation.angle` degrees about the line through `rotation.origin` along
  /// `rotation.axis`, as RotationQuery describes (same sign, same parts,
  /// same input checks, angle 0: no contacts); dir * depth must then be zero
  /// (QueryStatus::MixedMotion otherwise). See contacts().
  std::optional<Rotation> rotation;
};

/// Result of contacts(): the contacts found (order: see contacts()).
struct ContactsResult {
  /// The contacts found.
  std::vector<ContactInfo> contacts;
  QueryStatus status = QueryStatus::Ok;  ///< refused: no contacts (see QueryStatus)
};

/// The original's Contacts: every surface the trace model touches when moved
/// from start up to start + dir * depth, at most maxContacts of them, in the
/// order the walk met them.
///
/// With ContactsQuery::rotation (cmkit's own; the original left contacts
/// along a rotation unfinished): for every model polygon the turning trace
/// model meets within the angle, its EARLIEST contact (as rotate() would
/// stop there: tol::kClipEpsilon in front), with ContactInfo::angle the
/// degrees turned to it (signed as rotation.angle). Each polygon is tested
/// with its own edges and vertices, behind its own culls (its box, its
/// plane, the back-face culls): a contact at an edge or vertex that several
/// polygons share is listed for each of them whose culls reach it, which
/// need not be all of them. The contacts are
/// ordered by |angle| (ties: the order the walk met them), and the
/// maxContacts earliest are kept. Normals oppose the motion of the contact
/// point along the arc, as rotate()'s (RotationQuery).
ContactsResult contacts(const CollisionModel& model, const ContactsQuery& query, QueryWork& work);
/// contacts() into the caller's vector (the one form that fills a caller's
/// container): `out` is cleared, then holds the same contacts in the same
/// order as ContactsResult::contacts. Its memory is kept, so a caller that
/// asks for contacts every frame with one vector allocates only the first
/// time. Returns what ContactsResult::status would be (refused: `out` left
/// empty).
QueryStatus contacts(const CollisionModel& model, const ContactsQuery& query, QueryWork& work,
                     std::vector<ContactInfo>& out);

/// Which way out of solid: the trace model placed as for a position test.
struct PenetrationQuery {
  const TraceModel* trm = nullptr;  ///< nullptr or a point shape: a point
  /// Orientation of the trace model.
  Mat3 trmAxis;
  /// Position of the trace model.
  Vec3 position;
  /// Content flags of the brushes considered.
  std::uint32_t contentMask = contents::kMaskSolid;
  /// Where the model is placed in the world.
  Placement placement;
};

/// Result of penetration(): how a trace model overlapping solid can get out.
struct PenetrationResult {
  bool stuck = false;                    ///< the trace model overlaps a matching brush
  Real depth = 0;                        ///< distance to move along `direction` to be free of that brush
  Vec3 direction;                        ///< unit direction out (a brush plane normal, world space)
  std::uint32_t contents = 0;            ///< contents of the deepest brush
  QueryStatus status = QueryStatus::Ok;  ///< refused: not stuck (see QueryStatus)
};

/// Estimates the way out of solid: for every matching brush the trace model
/// overlaps, the brush plane along which the shortest move separates them
/// (separating-plane test on the brush planes); the deepest brush decides.
/// Input is checked as contentsTest() checks it.
PenetrationResult penetration(const CollisionModel& model, const PenetrationQuery& query, QueryWork& work);

/// A rotation of a trace model (or a point) about an arbitrary axis.
///
/// CONTRACT
/// - `rotation` is in world space: the trace model turns by `rotation.angle`
///   degrees about the line through `rotation.origin` along the unit vector
///   `rotation.axis`. A POSITIVE angle turns CLOCKWISE seen from the axis tip
///   (as Rotation documents): about +z by +90, (100,0,10) goes to (0,-100,10).
/// - The result's `fraction` is the fraction of the ANGLE turned before the
///   first contact (0..1); `endPos` is `start` turned by angle * fraction and
///   `endAxis` is `trmAxis` turned by it (identity for a point). On a hit the
///   trace model stops tol::kClipEpsilon (0.25 units) in front of the surface
///   (measured along the surface normal, as for translations).
/// - Collision is exact (all tests are solved in the tangent of half the
///   angle): trace-model vertices through model polygons, trace-model edges
///   through model edges, model vertices through trace-model polygons. Unlike
///   the original, no collision is skipped because of polygon order or a
///   chord approximation of the arc in the tree walk.
/// - |angle| >= 180 is traced in parts below 180 degrees (|angle| >= 360:
///   one full turn in three 120-degree parts, as the original: a full turn
///   meets every orientation); angle == 0 is a POSITION TEST (fraction 0 when
///   the trace model overlaps anything, else 1; startSolid set accordingly).
/// - Starting in solid is handled as the original does; `startSolid` tells it
///   when `detectStartSolid` is set.
/// - The contact normal opposes the motion of the contact point along the arc
///   at the contact, v = s * (point - origin) x axis (s = 1 for a positive
///   angle, -1 for a negative one): normal . v <= 0, or the motion runs within
///   the contact plane (|cosine| <= tol::kRotationContactTangentCosine), the
///   same for starts in solid. A model-vertex contact's normal is that of the
///   trace-model polygon turned to the contact. Both differ from the original
///   (docs/fidelity.md, "Rotation contact normals").
struct RotationQuery {
  const TraceModel* trm = nullptr;  ///< nullptr or a point shape: a point rotation
  Mat3 trmAxis;                     ///< orientation of the trace model at the start
  Vec3 start;                       ///< position of the trace model at the start
  Rotation rotation;                ///< world-space rotation (origin, unit axis, degrees)
  /// Content flags the queries collide with.
  std::uint32_t contentMask = contents::kMaskSolid;
  /// Where the model is placed in the world.
  Placement placement;
  /// Also run a position test at the start and set TraceResult::startSolid.
  bool detectStartSolid = false;
};

/// Rotates a trace model (or a point) through a placed model; see
/// RotationQuery for the contract.
TraceResult rotate(const CollisionModel& model, const RotationQuery& query, QueryWork& work);

}  // namespace cmkit
