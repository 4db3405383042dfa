// Internal: the per-model build state of the map -> collision model pipeline
// (the original's build-time globals, as members of one object per model).
//
// While building, the model is mutable and linked like the original's: nodes
// hold singly linked lists of polygon and brush references, new references
// are prepended, merged polygons replace references in place. The list order
// decides the order of polygons in .cm files and of several results, so it is
// reproduced exactly. finish() flattens everything into a CollisionModel.
#pragma once

#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "cmkit/compile.h"
#include "cmkit/map.h"
#include "cmkit/materials.h"
#include "cmkit/model.h"
#include "geometry/winding.h"
#include "model/material_cache.h"
#include "model/tree_filter.h"

namespace cmkit::detail {

/// Union of two boxes as the original's idBounds::operator+= (component-wise;
/// a cleared box adds nothing).
inline Bounds unionBounds(const Bounds& a, const Bounds& b) {
  Bounds r = a;
  for (int i = 0; i < 3; ++i) {
    if (b.min[i] < r.min[i]) r.min[i] = b.min[i];
    if (b.max[i] > r.max[i]) r.max[i] = b.max[i];
  }
  return r;
}

struct BEdge {
  std::int32_t v[2] = {0, 0};
  bool internal = false;
  int numUsers = 0;
};

struct BPolygon {
  Bounds bounds;
  Plane plane;
  std::uint32_t contents = 0;
  int material = -1;
  int checkcount = 0;
  bool freed = false;
  std::vector<int> edges;
};

struct BBrush {
  Bounds bounds;
  std::uint32_t contents = 0;
  int material = -1;
  int primitiveNum = 0;
  int checkcount = 0;
  std::vector<Plane> planes;
};

struct BNode {
  int planeType = -1;
  Real planeDist = 0;
  int children[2] = {-1, -1};
  int parent = -1;
  int polygons = -1;  ///< head of the polygon reference list (index into refs), -1 = empty
  int brushes = -1;   ///< head of the brush reference list
};

/// A reference to a polygon or brush in a node's list.
struct BRef {
  int item = -1;
  int next = -1;
};

/// Counters the original prints (PrintModelInfo).
struct BuildCounters {
  int numPolygonRefs = 0;
  int numBrushRefs = 0;
  int numNodes = 0;  ///< nodes besides the root
  int numInternalEdges = 0;
  int numRemovedPolys = 0;
  int numMergedPolys = 0;
};

/// Builds one collision model from one map entity.
class ModelBuilder {
 public:
  ModelBuilder(const MapEntity& entity, std::string name, MaterialCache& materials,
               std::vector<std::string>* warnings);
  /// Runs the whole pipeline and returns the flattened model.
  CollisionModel build();

 private:
  // ---- brushes.cpp
  struct BrushPrimitive {
    int primitiveNum = 0;
    std::vector<Plane> planes;      ///< after FixDegeneracies
    std::vector<Winding> windings;  ///< of sides 0..n-2 (the bounds pass)
  };
  void convertBrush(const MapBrush& brush, int primitiveNum, BrushPrimitive& out);
  void convertBrushSides(const MapBrush& brush, BrushPrimitive& prim);
  void convertPatch(const MapPatch& patch, int primitiveNum);

  // ---- polygons.cpp
  void clearHash(const Bounds& bounds);
  bool getVertex(const Vec3& v, int& vertexNum);
  bool getEdge(const Vec3& v1, const Vec3& v2, int& edgeNum, int v1num);
  void createPolygon(const Winding& w, const Plane& plane, int material, int primitiveNum);
  void polygonFromWinding(Winding& w, const Plane& plane, int material, int primitiveNum);
  void warn(const std::string& message);

  // ---- chop.cpp
  /// nullptr when the winding is contained in brushes, else the winding to use.
  const Winding* windingOutsideBrushes(const Winding& w, const Plane& plane, std::uint32_t contents,
                                       int primitiveNum);
  void chopWindingListWithTreeBrushes(int node);
  bool chopWindingListWithBrush(const BBrush& b);

  // ---- bsp.cpp
  int allocNode();
  void addPolygonToNode(int node, int polygon);
  void addBrushToNode(int node, int brush);
  /// The tree as model/tree_filter.h walks it, while it grows.
  struct GrowingTree {
    const std::vector<BNode>& nodes;
    const BNode& at(std::int32_t n) const { return nodes[static_cast<std::size_t>(n)]; }
    bool isLeaf(std::int32_t n) const { return at(n).planeType == -1; }
    int axis(std::int32_t n) const { return at(n).planeType; }
    Real dist(std::int32_t n) const { return at(n).planeDist; }
    std::int32_t child(std::int32_t n, int side) const { return at(n).children[side]; }
    bool insideAllChildren(std::int32_t n, const Bounds& b) const {
      return detail::insideAllChildren(*this, n, b);
    }
  };
  bool insideAllChildren(int node, const Bounds& bounds) const;
  enum class ItemKind { Polygon, Brush };
  /// Links a polygon or brush into every node below `node` its bounds reach
  /// by the tree-filter rule (model/tree_filter.h); `ref` >= 0 moves that
  /// existing reference (to one of the nodes) instead of making a new one.
  void filterIntoTree(ItemKind kind, int node, int ref, int item);
  std::vector<std::int32_t> filterStack_;  ///< scratch of filterIntoTree
  bool findSplitter(int node, const Bounds& bounds, int& planeType, Real& planeDist) const;
  void createAxialBSPTree(int node, const Bounds& bounds);
  Bounds nodeBounds() const;

  // ---- merge.cpp
  void mergeTreePolygons(int node);
  bool mergePolygonWithTreePolygons(int node, int polygon);
  int tryMergePolygons(int p1, int p2);
  void replacePolygons(int node, int p1, int p2, int newp);

  // ---- internal_edges.cpp
  void findInternalEdges(int node);
  void findInternalPolygonEdges(int node, int polygon);
  void findInternalEdgesOnPolygon(int p1, int p2);
  bool pointInsidePolygon(const BPolygon& p, const Vec3& v) const;

  // ---- finish.cpp
  CollisionModel finish();

  /// True when each edge starts at the vertex where the one before it ends
  /// (cyclically): the edges outline a polygon.
  bool edgesFormLoop(const std::vector<int>& edgeNums) const {
    auto startVertex = [&](int e) { return edges_[static_cast<std::size_t>(std::abs(e))].v[e > 0 ? 0 : 1]; };
    for (std::size_t k = 0; k < edgeNums.size(); ++k) {
      const int prev = edgeNums[k == 0 ? edgeNums.size() - 1 : k - 1];
      if (startVertex(-prev) != startVertex(edgeNums[k])) return false;
    }
    return true;
  }
  Vec3 edgeStart(int edgeNum) const {
    const BEdge& e = edges_[static_cast<std::size_t>(edgeNum < 0 ? -edgeNum : edgeNum)];
    return vertices_[static_cast<std::size_t>(edgeNum < 0 ? e.v[1] : e.v[0])];
  }
  Vec3 edgeEnd(int edgeNum) const {
    const BEdge& e = edges_[static_cast<std::size_t>(edgeNum < 0 ? -edgeNum : edgeNum)];
    return vertices_[static_cast<std::size_t>(edgeNum < 0 ? e.v[0] : e.v[1])];
  }

  const MapEntity& entity_;
  std::string name_;
  MaterialCache& materials_;
  std::vector<std::string>* warnings_;
  struct WarningSlot {
    std::size_t index;  ///< of its line in *warnings_
    int count;          ///< how often this model gave it
  };
  std::unordered_map<std::string, WarningSlot> warningSlots_;  ///< by message (see warn)

  std::vector<Vec3> vertices_;
  std::vector<BEdge> edges_;  ///< edges_[0] is the dummy once an edge exists
  std::vector<BPolygon> polygons_;
  std::vector<BBrush> brushes_;
  std::vector<BNode> nodes_;  ///< nodes_[0] is the root
  std::vector<BRef> polygonRefs_;
  std::vector<BRef> brushRefs_;
  int freePolygonRef_ = -1;
  BuildCounters counters_;
  int checkCount_ = 0;

  // vertex and edge hashes
  static constexpr int kVertexHashSize = 4096;
  Vec3 hashMin_;
  std::vector<int> vertexHashHead_;
  std::vector<int> vertexHashNext_;
  std::unordered_map<std::uint64_t, int> edgeHashHead_;  ///< directed (v0, v1) -> newest edge
  std::vector<int> edgeHashNext_;

  // winding list of windingOutsideBrushes
  struct WindingList {
    std::vector<Winding> w;
    int numWindings = 0;
    Bounds bounds;
    Vec3 origin;
    Real radius = 0;
    Vec3 normal;
    std::uint32_t contents = 0;
    int primitiveNum = 0;
  };
  WindingList list_;
  std::vector<Winding> outList_;
  std::vector<Winding> tmpList_;
};

}  // namespace cmkit::detail
