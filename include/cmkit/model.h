// model.h: collision models, the static geometry that trace models collide
// with (the original's cm_model_t).
//
// A collision model is built from a map entity (compile.h), a mesh (mesh.h)
// or a trace model, read from a .cm file (cm_file.h), or made from arrays
// (ModelArrays) by CollisionModel::create, and is SEALED: nothing can change
// its arrays afterwards. It is handed out as std::shared_ptr<const
// CollisionModel>, and every query is a const function of it, so any number
// of threads may query one model at once.
//
// Storage is flat: arrays indexed by 32-bit numbers instead of pointers.
//  - vertices: 0..n-1.
//  - edges: 1..n-1; edges[0] is a dummy so that a signed edge number -e means
//    "edge e walked from vertex[1] to vertex[0]".
//  - polygons and brushes are stored in .cm file order (tree pre-order, front
//    child first, each item at its first reference), so a polygon's index is
//    its index in the .cm file the model is written to.
//  - nodes: nodes[0] is the root; the axial BSP tree in pre-order, front child
//    first. Each node lists the polygons and brushes referenced there, as
//    ranges of polygonRefs / brushRefs, in traversal order.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cmkit/contents.h"
#include "cmkit/math.h"
#include "cmkit/result.h"
#include "cmkit/trace_model.h"

namespace cmkit {

namespace detail {
struct QueryData;    // model/query_data.h
struct ModelAccess;  // model/model_access.h: the library's own way to seal arrays
}  // namespace detail

/// An edge between two model vertices.
struct CmEdge {
  /// Indices of its two vertices.
  std::int32_t vertex[2] = {0, 0};
  /// Internal edges can never be touched first by a trace (a concave crease
  /// between faces, or an edge lying on another face): queries skip them.
  bool internal = false;
  /// Number of polygons using the edge (1 or 2; more only in odd .cm files).
  std::uint8_t numUsers = 0;
  /// Direction the edge faces: the bisector of its polygons' normals scaled
  /// so that its component along each normal is 1 (the original's edge
  /// normal). Times tol::kClipEpsilon it gives the "epsilon expanded" edge.
  Vec3 normal;
};

/// A convex polygon of the model.
struct CmPolygon {
  /// Bounds of the polygon's vertices.
  Bounds bounds;
  Plane plane;  ///< normal points out of the solid
  /// Content flags (from its material).
  std::uint32_t contents = 0;
  std::int32_t material = -1;   ///< index into CollisionModel::materials, -1 = none
  std::uint32_t firstEdge = 0;  ///< into CollisionModel::polygonEdges
  /// Number of edges (entries of polygonEdges).
  std::uint32_t numEdges = 0;
};

/// A convex volume (a map brush) used by position tests and point contents.
struct CmBrush {
  /// Bounds of the brush.
  Bounds bounds;
  /// Content flags.
  std::uint32_t contents = 0;
  std::int32_t material = -1;     ///< index into CollisionModel::materials, -1 = none
  std::int32_t primitiveNum = 0;  ///< the brush's primitive number in its entity
  std::uint32_t firstPlane = 0;   ///< into CollisionModel::brushPlanes
  /// Number of planes (entries of brushPlanes).
  std::uint32_t numPlanes = 0;
};

/// A node of the axial BSP tree.
struct CmNode {
  /// -1 for a leaf; 0, 1, 2 for a split plane normal to x, y, z.
  std::int8_t planeType = -1;
  /// The split plane: coordinate[planeType] == planeDist.
  Real planeDist = 0;
  /// children[0]: front (coordinate > planeDist), children[1]: back. -1 in leaves.
  std::int32_t children[2] = {-1, -1};
  /// Parent node index, -1 for the root.
  std::int32_t parent = -1;
  /// First entry of the node's polygon list in CollisionModel::polygonRefs.
  std::uint32_t firstPolygonRef = 0;
  /// Number of polygons listed at the node.
  std::uint32_t numPolygonRefs = 0;
  /// First entry of the node's brush list in CollisionModel::brushRefs.
  std::uint32_t firstBrushRef = 0;
  /// Number of brushes listed at the node.
  std::uint32_t numBrushRefs = 0;

  /// True for a leaf (no split plane).
  bool isLeaf() const { return planeType < 0; }
};

/// Statistics of building or loading a model (the original's PrintModel).
struct ModelStats {
  /// Edges marked internal.
  int internalEdges = 0;
  /// Edges whose polygons meet at a sharp angle (tol::kSharpEdgeDot).
  int sharpEdges = 0;
  /// Polygons removed because they lay inside brushes.
  int containedPolygonsRemoved = 0;
  /// Polygons merged into coplanar neighbours.
  int polygonsMerged = 0;
  /// Of containedPolygonsRemoved: the windings dropped because they lie in
  /// solid leaves of the .proc BSP (BuildOptions::procBsp; world model only).
  int procPolygonsRemoved = 0;
};

/// The arrays of a collision model as plain, editable data: what the
/// compiler and the .cm reader fill in, and what a tool or test fills in to
/// make a model of its own (CollisionModel::create checks it and seals it).
/// Fields as CollisionModel's read accessors describe them.
struct ModelArrays {
  /// The model's name ("worldMap", an entity's model or name key, ...).
  std::string name;
  /// Bounds of all polygons and brushes.
  Bounds bounds;
  std::uint32_t contents = 0;  ///< OR of all polygon and brush contents
  bool isConvex = false;       ///< true only for models made from a trace model

  /// Vertex positions.
  std::vector<Vec3> vertices;
  std::vector<CmEdge> edges;               ///< edges[0] is a dummy
  std::vector<std::int32_t> polygonEdges;  ///< signed edge numbers of all polygons
  /// The polygons.
  std::vector<CmPolygon> polygons;
  std::vector<Plane> brushPlanes;  ///< planes of all brushes, normals out of the brush
  /// The brushes.
  std::vector<CmBrush> brushes;
  std::vector<CmNode> nodes;              ///< nodes[0] is the root
  std::vector<std::int32_t> polygonRefs;  ///< node polygon lists
  std::vector<std::int32_t> brushRefs;    ///< node brush lists
  std::vector<std::string> materials;     ///< material names used by polygons and brushes

  /// Statistics of the build (or load).
  ModelStats stats;

  /// The signed edge numbers of a polygon.
  std::span<const std::int32_t> edgesOf(const CmPolygon& p) const {
    return {polygonEdges.data() + p.firstEdge, p.numEdges};
  }
  /// The planes of a brush.
  std::span<const Plane> planesOf(const CmBrush& b) const {
    return {brushPlanes.data() + b.firstPlane, b.numPlanes};
  }
  /// The polygons listed at a node (indices into polygons).
  std::span<const std::int32_t> polygonsAt(const CmNode& n) const {
    return {polygonRefs.data() + n.firstPolygonRef, n.numPolygonRefs};
  }
  /// The brushes listed at a node (indices into brushes).
  std::span<const std::int32_t> brushesAt(const CmNode& n) const {
    return {brushRefs.data() + n.firstBrushRef, n.numBrushRefs};
  }
  /// The vertex a signed edge number starts at.
  std::int32_t edgeStart(std::int32_t signedEdge) const {
    return signedEdge > 0 ? edges[std::size_t(signedEdge)].vertex[0]
                          : edges[std::size_t(-signedEdge)].vertex[1];
  }
  /// Where a polygon's edges stop outlining it: the index in edgesOf(p) of
  /// the first edge that does not start where the one before it ends, or -1
  /// when they form a loop. Edge and vertex numbers must be in range.
  std::ptrdiff_t brokenEdgeLoopAt(const CmPolygon& p) const {
    const auto list = edgesOf(p);
    for (std::size_t k = 0; k < list.size(); ++k) {
      const std::int32_t prev = list[k == 0 ? list.size() - 1 : k - 1];
      if (edgeStart(list[k]) != edgeStart(-prev)) return std::ptrdiff_t(k);  // -prev starts where prev ends
    }
    return -1;
  }
  /// Material name, or "" for none.
  std::string_view materialName(std::int32_t material) const {
    return material >= 0 ? std::string_view(materials[std::size_t(material)]) : std::string_view();
  }
};

/// A collision model: SEALED. Its arrays cannot be changed once it is made;
/// it is made only by the map compiler (buildCollisionModels), the .cm reader
/// (cm_file.h), the mesh builder (mesh.h), collisionModelFromTraceModel, or
/// create() from arrays of the caller's, which checks them first. What the
/// queries derive from the arrays (edge lines, cull blocks) is made once,
/// when the model is made, and shared by its copies: no query checks whether
/// it is up to date, because nothing can make it stale.
///
/// Read access is through spans and const references (for drawing, export,
/// validation); arrays() gives the whole ModelArrays read-only, e.g. to copy
/// it, change the copy and create() a new model from it.
class CollisionModel {
 public:
  /// A model from the caller's arrays, sealed. The arrays are taken as
  /// given (no bounds, contents or edge normals are computed), after a check
  /// of their STRUCTURE: every index, range, link and loop validateModel
  /// checks (a model whose numbers are out of range would make queries read
  /// the wrong memory). Odd geometry (a degenerate polygon, an empty brush)
  /// is allowed, as real maps have some. Error: the first structural
  /// violations found (validateModel's messages).
  static Result<std::shared_ptr<const CollisionModel>> create(ModelArrays arrays);

  /// The model's name ("worldMap", an entity's model or name key, ...).
  const std::string& name() const { return data_.name; }
  /// Bounds of all polygons and brushes.
  const Bounds& bounds() const { return data_.bounds; }
  /// OR of all polygon and brush contents.
  std::uint32_t contents() const { return data_.contents; }
  /// True only for models made from a trace model.
  bool isConvex() const { return data_.isConvex; }

  /// Vertex positions.
  std::span<const Vec3> vertices() const { return data_.vertices; }
  /// Edges; edges()[0] is a dummy.
  std::span<const CmEdge> edges() const { return data_.edges; }
  /// Signed edge numbers of all polygons.
  std::span<const std::int32_t> polygonEdges() const { return data_.polygonEdges; }
  /// The polygons.
  std::span<const CmPolygon> polygons() const { return data_.polygons; }
  /// Planes of all brushes, normals out of the brush.
  std::span<const Plane> brushPlanes() const { return data_.brushPlanes; }
  /// The brushes.
  std::span<const CmBrush> brushes() const { return data_.brushes; }
  /// Tree nodes; nodes()[0] is the root.
  std::span<const CmNode> nodes() const { return data_.nodes; }
  /// Node polygon lists.
  std::span<const std::int32_t> polygonRefs() const { return data_.polygonRefs; }
  /// Node brush lists.
  std::span<const std::int32_t> brushRefs() const { return data_.brushRefs; }
  /// Material names used by polygons and brushes.
  std::span<const std::string> materials() const { return data_.materials; }
  /// Statistics of the build (or load).
  const ModelStats& stats() const { return data_.stats; }
  /// All of the above, read-only (a copy of it can be changed and given to
  /// create()).
  const ModelArrays& arrays() const { return data_; }

  /// The signed edge numbers of a polygon.
  std::span<const std::int32_t> edgesOf(const CmPolygon& p) const { return data_.edgesOf(p); }
  /// The planes of a brush.
  std::span<const Plane> planesOf(const CmBrush& b) const { return data_.planesOf(b); }
  /// The polygons listed at a node (indices into polygons()).
  std::span<const std::int32_t> polygonsAt(const CmNode& n) const { return data_.polygonsAt(n); }
  /// The brushes listed at a node (indices into brushes()).
  std::span<const std::int32_t> brushesAt(const CmNode& n) const { return data_.brushesAt(n); }
  /// The vertex a signed edge number starts at.
  std::int32_t edgeStart(std::int32_t signedEdge) const { return data_.edgeStart(signedEdge); }
  /// Where a polygon's edges stop outlining it (see ModelArrays::brokenEdgeLoopAt).
  std::ptrdiff_t brokenEdgeLoopAt(const CmPolygon& p) const { return data_.brokenEdgeLoopAt(p); }
  /// Material name, or "" for none.
  std::string_view materialName(std::int32_t material) const { return data_.materialName(material); }
  /// Number of real edges (edges().size() - 1, or 0).
  std::size_t numEdges() const { return data_.edges.empty() ? 0 : data_.edges.size() - 1; }

 private:
  friend struct detail::ModelAccess;
  explicit CollisionModel(ModelArrays arrays);

  ModelArrays data_;
  /// What the queries derive from the arrays (model/query_data.h); made by
  /// the constructor, shared by copies (it is as immutable as the arrays).
  std::shared_ptr<const detail::QueryData> queryData_;
};

using ModelPtr = std::shared_ptr<const CollisionModel>;

// ---- conversions and reports ----

/// The collision model of a trace model (the original's SetupTrmModel): its
/// vertices, edges (with the trace model's edge normals and numbering) and
/// polygons, every polygon with `contents` and `material`, one leaf holding
/// all polygons in order, no brushes, isConvex = true, named "trace model".
ModelPtr collisionModelFromTraceModel(const TraceModel& trm, std::uint32_t contents = contents::kSolid,
                                      std::string material = {});

/// A convex collision model as a trace model (the original's TrmFromModel):
/// the convex hull of its polygons' vertices. Errors: the model has no
/// polygons, is not closed (an edge not used by exactly two polygons), is
/// concave (a vertex more than tol::kTrmFromModelConvexEpsilon in front of a
/// polygon), or exceeds the trace model limits (vertices, edges, polygons,
/// edges per polygon).
Result<TraceModel> traceModelFromCollisionModel(const CollisionModel& model);

/// The memory a model takes in cmkit, in bytes (modelMemory()).
struct ModelMemory {
  /// Its arrays: vertices, edges, polygon edges, polygons, brush planes,
  /// brushes, nodes, polygon and brush references (not names, materials or
  /// spare capacity).
  std::size_t arrays = 0;
  /// What the queries derive from the arrays (edge lines, cull blocks).
  std::size_t queryData = 0;
};
/// The memory `model` takes in cmkit (`cmkit info FILE --memory` prints it).
ModelMemory modelMemory(const CollisionModel& model);

/// A polygon's vertex loop, in edge order.
std::vector<Vec3> polygonWinding(const CollisionModel& model, std::size_t polygon);

/// The original's PrintModel lines for one model: its name, then vertices,
/// edges, polygons, brushes, nodes, polygon refs, brush refs (each with the
/// memory the original's 64-bit structures take, in KB), internal and sharp
/// edges, contained polygons removed, polygons merged, total memory in KB.
std::string modelStatistics(const CollisionModel& model);

}  // namespace cmkit
