// trace_model.h: trace models, the convex shapes that are moved through the
// world (the original's idTraceModel).
//
// A trace model is a small polyhedron (or a single polygon, or a point) given
// by its vertices, edges and polygons:
//  - vertices are numbered 0..numVertices-1;
//  - edges are numbered 1..numEdges (number 0 is unused, as in the original,
//    so that a signed edge number -e means "edge e walked backwards");
//  - polygons are numbered 0..numPolygons-1; each lists signed edge numbers
//    counter-clockwise seen from the front (right-hand rule around the
//    outward normal).
// Feature numbers follow the original's numbering for box, octahedron,
// cylinder, cone, bone and polygon, because query results report them.
//
// Shapes are built by the factory functions below, which validate their input
// and return an Error naming the problem for degenerate shapes. Trace models
// are plain values: copy them freely; they are thread-compatible.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "cmkit/math.h"
#include "cmkit/result.h"

namespace cmkit {

namespace detail {
class TraceModelBuilder;  // builds the shapes (internal)
}  // namespace detail

/// Limits of a trace model (the original's MAX_TRACEMODEL_*). Queries cache
/// per-feature side bits in 32-bit words, which is what bounds these.
inline constexpr int kMaxTrmVertices = 32;
inline constexpr int kMaxTrmEdges = 32;
inline constexpr int kMaxTrmPolygons = 16;
inline constexpr int kMaxTrmPolygonEdges = 16;
static_assert(kMaxTrmEdges < 64 && kMaxTrmVertices <= 32,
              "TraceModel::polygonEdgeBits and polygonVertexBits");
/// The convex hull builder accepts at most this many input points.
inline constexpr int kMaxTrmHullInputPoints = 256;

/// The kind of shape a trace model was built as.
enum class TrmShape {
  Point,
  Box,
  Octahedron,
  Dodecahedron,
  Cylinder,
  Cone,
  Bone,
  Polygon,
  PolygonVolume,
  Custom,
};

/// Name of a shape ("box", "polygon volume", ...).
std::string_view toString(TrmShape shape);

/// An edge of a trace model: from vertex v[0] to vertex v[1].
struct TrmEdge {
  /// Start and end vertex indices.
  int v[2] = {0, 0};
  /// Unit-ish direction the edge "faces": the bisector of the normals of its
  /// two polygons (scaled so its component along each normal is 1), or the
  /// outward in-plane normal for the boundary edges of a lone polygon.
  Vec3 normal;
};

/// A polygon of a trace model.
/// (The fields a query reads, the normal to the edge list, come first and
/// next to each other; the bounds, which queries do not read, last.)
struct TrmPolygon {
  Vec3 normal;    ///< outward unit normal
  Real dist = 0;  ///< normal . p = dist on the polygon
  /// Number of edges in `edges`.
  int numEdges = 0;
  /// Signed edge numbers, counter-clockwise around the normal.
  std::array<int, kMaxTrmPolygonEdges> edges{};
  /// Bounds of the polygon's vertices.
  Bounds bounds;

  /// The signed edge numbers in use.
  std::span<const int> edgeList() const { return {edges.data(), size_t(numEdges)}; }
  /// The vertex the signed edge `edges[i]` starts at.
  int startVertex(const class TraceModel& trm, int i) const;
};

/// Mass properties of a solid trace model for a uniform density.
struct MassProperties {
  /// Volume of the solid.
  Real volume = 0;
  /// Mass (volume times density).
  Real mass = 0;
  /// Centre of mass in the trace model's frame.
  Vec3 centerOfMass;
  /// Inertia tensor about the centre of mass, in the trace model's frame.
  Mat3 inertiaTensor = Mat3{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
};

/// A convex shape to move through collision models.
class TraceModel {
 public:
  /// A single point at the origin (no edges, no polygons, zero bounds).
  static TraceModel point();
  /// An axis-aligned box. Error if max < min on an axis or the box is flat.
  static Result<TraceModel> box(const Bounds& bounds);
  /// An octahedron with its six vertices at the face centres of bounds.
  static Result<TraceModel> octahedron(const Bounds& bounds);
  /// A dodecahedron (20 vertices, 12 pentagons) scaled per axis to bounds.
  static Result<TraceModel> dodecahedron(const Bounds& bounds);
  /// A prism with `sides` (3..10) vertical faces whose vertices lie on the
  /// ellipse inscribed in the bounds' xy extent.
  static Result<TraceModel> cylinder(const Bounds& bounds, int sides);
  /// A cone with `sides` (3..15) faces: base at bounds.min.z on the
  /// inscribed ellipse, apex above the bounds' centre at bounds.max.z.
  /// (The original puts the apex at x = y = 0 whatever the bounds; the two
  /// agree for bounds centred on the z axis, as all shipped uses are.)
  static Result<TraceModel> cone(const Bounds& bounds, int sides);
  /// The original's bone: two tetrahedra sharing a triangle of the given
  /// width in the z = 0 plane, apexes at z = +-length/2.
  static Result<TraceModel> bone(Real length, Real width);
  /// A planar convex polygon (3..16 vertices, counter-clockwise around its
  /// front normal). Two polygons, front and back; not convex as a solid.
  static Result<TraceModel> polygon(std::span<const Vec3> vertices);
  /// A polygon extruded backwards (against its normal) by `thickness`: a
  /// convex prism (3..10 polygon vertices).
  static Result<TraceModel> polygonVolume(std::span<const Vec3> vertices, Real thickness);
  /// The convex hull of a point set (at most kMaxTrmHullInputPoints points);
  /// error if the points are coplanar or the hull exceeds the limits.
  static Result<TraceModel> convexHull(std::span<const Vec3> points);

  /// Parses the query format's trace model syntax: "point",
  /// "box:x0,y0,z0,x1,y1,z1", "octahedron:...", "dodecahedron:...",
  /// "cylinder:N:...", "cone:N:...", "bone:length,width",
  /// "polygon:x,y,z;x,y,z;...", plus cmkit's "polygonvolume:T:x,y,z;..." and
  /// "hull:x,y,z;x,y,z;...". A bounds-based shape whose bounds have zero size
  /// on all axes is a point.
  static Result<TraceModel> parse(std::string_view spec);

  /// The kind of shape.
  TrmShape shape() const { return shape_; }
  /// True for a single point (a point trace).
  bool isPoint() const { return shape_ == TrmShape::Point; }
  /// True when the shape is a closed convex solid (not a polygon or point).
  bool isConvex() const { return isConvex_; }
  /// Number of vertices.
  int numVertices() const { return numVertices_; }
  /// Number of edges (numbered 1..numEdges()).
  int numEdges() const { return numEdges_; }
  /// Number of polygons.
  int numPolygons() const { return numPolygons_; }
  /// The vertices, relative to the trace model's origin.
  std::span<const Vec3> vertices() const { return {vertices_.data(), size_t(numVertices_)}; }
  /// Vertex i.
  const Vec3& vertex(int i) const { return vertices_[size_t(i)]; }
  /// Edge number n, 1 <= n <= numEdges().
  const TrmEdge& edge(int n) const { return edges_[size_t(n)]; }
  /// The polygons.
  std::span<const TrmPolygon> polygons() const { return {polygons_.data(), size_t(numPolygons_)}; }
  /// Polygon i.
  const TrmPolygon& polygon(int i) const { return polygons_[size_t(i)]; }
  /// The edges of polygon i as bits: bit e for edge number e (1..numEdges()).
  std::uint64_t polygonEdgeBits(int i) const { return facing_[size_t(i)].edgeBits; }
  /// The vertices of polygon i as bits: bit v for vertex v.
  std::uint32_t polygonVertexBits(int i) const { return facing_[size_t(i)].vertexBits; }
  /// polygon(i).normal, from the packed per-polygon data a query's set-up
  /// reads (a few cache lines, where the polygons take one or two each).
  const Vec3& polygonNormal(int i) const { return facing_[size_t(i)].normal; }
  /// The vertex the queries fit polygon i's plane through: the start of its
  /// first edge (edge(|polygon(i).edges[0]|).v[0]).
  int polygonPlaneVertex(int i) const { return facing_[size_t(i)].planeVertex; }
  /// edge(n).v[k] (k = 0: start, 1: end), from the packed array a query's
  /// set-up reads.
  int edgeVertex(int n, int k) const { return edgeVertices_[size_t(n)][size_t(k)]; }
  /// Bounds of all vertices.
  const Bounds& bounds() const { return bounds_; }
  /// The shape's centre: the point that follows the trace start and end.
  const Vec3& offset() const { return offset_; }

  /// Moves every feature by t.
  void translate(const Vec3& t);
  /// Turns the shape by an orientation (rows = axes): v -> v * axis.
  void rotate(const Mat3& axis);
  /// Same shape, same features at the same places.
  bool operator==(const TraceModel& other) const;

  /// Volume, mass, centre of mass and inertia tensor for a uniform density.
  /// Polygons and points have no volume: all zero but the centre (the
  /// polygon's centroid).
  MassProperties massProperties(Real density) const;

  /// Checks the invariants (indices in range, loops closed and consistent,
  /// each closed-solid edge used by exactly two polygons in opposite
  /// directions, vertices on their polygons' planes, outward normals,
  /// convexity, bounds). An empty string means all hold; otherwise the
  /// first violation.
  std::string checkInvariants() const;

  /// A human-readable listing (features, planes, bounds).
  std::string describe() const;

 private:
  friend class detail::TraceModelBuilder;
  // What a query's set-up reads first is at the front (the counts, bounds,
  // offset and vertices): the fixed-size arrays are mostly unused, and a
  // query should touch few of their cache lines.
  TrmShape shape_ = TrmShape::Point;
  bool isConvex_ = false;
  int numVertices_ = 0;
  int numEdges_ = 0;
  int numPolygons_ = 0;
  Bounds bounds_;
  Vec3 offset_;
  std::array<Vec3, kMaxTrmVertices> vertices_{};
  // Derived from the polygons and edges when the shape is made (normals
  // again when it is turned), packed for a query's set-up, which reads every
  // polygon's normal (which ones face the move) and every edge's vertices: a
  // translation takes the features of the polygons facing the move.
  struct PolygonFacing {
    Vec3 normal;
    std::uint32_t vertexBits = 0;
    std::uint64_t edgeBits = 0;
    std::uint8_t planeVertex = 0;
  };
  std::array<PolygonFacing, kMaxTrmPolygons> facing_{};
  std::array<std::array<std::uint8_t, 2>, kMaxTrmEdges + 1> edgeVertices_{};
  std::array<TrmEdge, kMaxTrmEdges + 1> edges_{};
  std::array<TrmPolygon, kMaxTrmPolygons> polygons_{};
};

inline int TrmPolygon::startVertex(const TraceModel& trm, int i) const {
  const int e = edges[size_t(i)];
  return e > 0 ? trm.edge(e).v[0] : trm.edge(-e).v[1];
}

}  // namespace cmkit
