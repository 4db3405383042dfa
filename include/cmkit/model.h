// model.h: collision models, the static geometry that trace models collide
// with (the original's cm_model_t).
//
// A collision model is built from a map entity (compile.h) or read from a
// .cm file (cm_file.h) and is IMMUTABLE afterwards: it is handed out as
// std::shared_ptr<const CollisionModel>, and every query is a const function
// of it, so any number of threads may query one model at once.
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
struct QueryData;  // model/query_data.h
}

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

/// A collision model. Build it with buildCollisionModels (compile.h) or read it with loadCmFile (cm_file.h);
/// treat it as immutable afterwards.
struct CollisionModel {
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

  /// What the queries derive from the arrays above once instead of per query
  /// (the polygons' edge lines and what the culls read of them, laid out for
  /// SIMD: less memory than the arrays above), made by
  /// prepareQueries(): the compiler, the .cm reader and the conversions call
  /// it. Not part of the .cm format. It serves only the model whose arrays it
  /// was made from: a copy, or a model whose arrays changed size, is queried
  /// without it (the same results, a little slower) until prepareQueries()
  /// is called on it.
  std::shared_ptr<const detail::QueryData> queryData;

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
  /// Number of real edges (edges.size() - 1, or 0).
  std::size_t numEdges() const { return edges.empty() ? 0 : edges.size() - 1; }
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

/// Makes model.queryData from the model as it is now. Call it on a model
/// made or changed by hand for the queries' full speed; they are right
/// without it. A model with an edge, vertex or polygon number out of range
/// gets none (validate() says what is wrong).
void prepareQueries(CollisionModel& model);

/// The memory a model takes in cmkit, in bytes (modelMemory()).
struct ModelMemory {
  /// Its arrays: vertices, edges, polygon edges, polygons, brush planes,
  /// brushes, nodes, polygon and brush references (not names, materials or
  /// spare capacity).
  std::size_t arrays = 0;
  /// Its query data (CollisionModel::queryData; 0 without).
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
