// Internal: the per-model build state of the map -> collision model pipeline
// (the original's build-time globals, as members of one object per model).
//
// While building, the model is mutable and linked like the original's: nodes
// hold singly linked lists of polygon and brush references, new references
// are prepended, merged polygons replace references in place. The list order
// decides the order of polygons in .cm files and of several results, so it is
// reproduced exactly. build() (build.cpp) lists the steps; the last ones
// flatten everything into the arrays of a CollisionModel.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "cmkit/compile.h"
#include "cmkit/contents.h"
#include "cmkit/map.h"
#include "cmkit/materials.h"
#include "cmkit/mesh.h"
#include "cmkit/model.h"
#include "compile/edge_list.h"
#include "compile/int_hash.h"
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

/// Content bits that make a material take part in collision (the original's
/// CONTENTS_REMOVE_UTIL: everything but the compile-time flags).
inline constexpr std::uint32_t kUsefulContents = ~(contents::kAreaPortal | contents::kNoCsg);

/// The original's unguarded vector normalisation: only an exactly zero
/// vector has length 0 (tiny vectors still get a direction).
inline Real normalizeLikeOriginal(Vec3& v) {
  const Real sq = v.lengthSquared();
  if (!(sq > 0) || !std::isfinite(sq)) {
    v = Vec3{};
    return 0;
  }
  const Real inv = compatInvSqrt(sq);
  v *= inv;
  return inv * sq;
}

/// The edge hash's key of the directed vertex pair (v0, v1).
inline std::uint64_t edgeKey(int v0, int v1) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(v0)) << 32) | static_cast<std::uint32_t>(v1);
}

/// "None" for the int indices of the build state: no node, no reference, no
/// material, the end of a reference list.
inline constexpr int kNone = -1;

struct BEdge {
  std::int32_t v[2] = {0, 0};
  bool internal = false;
  int numUsers = 0;
};

struct BPolygon {
  Bounds bounds;
  Plane plane;
  std::uint32_t contents = 0;
  int material = kNone;
  int checkcount = 0;
  bool freed = false;
  EdgeList edges;  ///< signed edge numbers (negative: used from v[1] to v[0])
};

struct BBrush {
  Bounds bounds;
  std::uint32_t contents = 0;
  int material = kNone;
  int primitiveNum = 0;
  int checkcount = 0;
  std::vector<Plane> planes;
};

struct BNode {
  int planeType = kNone;  ///< kNone for a leaf, else the axis of the split plane
  Real planeDist = 0;
  int children[2] = {kNone, kNone};
  int parent = kNone;
  int polygons = kNone;  ///< head of the polygon reference list (index into the refs)
  int brushes = kNone;   ///< head of the brush reference list
  bool isLeaf() const { return planeType == kNone; }
};

/// A reference to a polygon or brush in a node's list.
struct BRef {
  int item = kNone;
  int next = kNone;
};

/// The items (polygon or brush indices) of one node's reference list, in
/// list order, for range-for.
class RefList {
 public:
  class Iterator {
   public:
    Iterator(const std::vector<BRef>& refs, int r) : refs_(&refs), r_(r) {}
    int operator*() const { return (*refs_)[static_cast<std::size_t>(r_)].item; }
    Iterator& operator++() {
      r_ = (*refs_)[static_cast<std::size_t>(r_)].next;
      return *this;
    }
    bool operator!=(const Iterator& o) const { return r_ != o.r_; }

   private:
    const std::vector<BRef>* refs_;
    int r_;
  };
  RefList(const std::vector<BRef>& refs, int head) : refs_(refs), head_(head) {}
  Iterator begin() const { return {refs_, head_}; }
  Iterator end() const { return {refs_, kNone}; }

 private:
  const std::vector<BRef>& refs_;
  int head_;
};

/// Lists of ints by int key in one pool (no allocation per key): add()
/// prepends, forEach() visits a key's items newest first.
class PooledLists {
 public:
  void clear() {
    head_.clear();
    pool_.clear();
  }
  /// Room for keys 0 .. numKeys - 1 and numItems items without growing.
  void reserve(std::size_t numKeys, std::size_t numItems) {
    if (head_.size() < numKeys) head_.resize(numKeys, kNone);
    pool_.reserve(numItems);
  }
  void add(int key, int item) {
    const auto k = static_cast<std::size_t>(key);
    if (head_.size() <= k) head_.resize(k + 1, kNone);
    pool_.push_back({item, head_[k]});
    head_[k] = static_cast<int>(pool_.size()) - 1;
  }
  template <class Visit>
  void forEach(int key, Visit&& visit) const {
    const auto k = static_cast<std::size_t>(key);
    if (head_.size() <= k) return;
    for (int i = head_[k]; i != kNone; i = pool_[static_cast<std::size_t>(i)].next)
      visit(pool_[static_cast<std::size_t>(i)].item);
  }

 private:
  struct Entry {
    int item;
    int next;
  };
  std::vector<int> head_;
  std::vector<Entry> pool_;
};

/// Counters the original prints (PrintModelInfo).
struct BuildCounters {
  int numPolygonRefs = 0;
  int numBrushRefs = 0;
  int numNodes = 0;  ///< nodes besides the root
  int numInternalEdges = 0;
  int numRemovedPolys = 0;
  int numMergedPolys = 0;
  int numProcRemovedPolys = 0;  ///< of numRemovedPolys: in solid leaves of the .proc BSP
};

/// Builds one collision model from one map entity or one triangle mesh.
class ModelBuilder {
 public:
  /// `proc`: the .proc BSP that prunes this model's windings (the world
  /// model's only), or null.
  ModelBuilder(const MapEntity& entity, std::string name, MaterialCache& materials,
               std::vector<std::string>* warnings, const ProcBsp* proc = nullptr);
  /// BuildOptions::robustEdges: internal edges only from non-parallel polygons.
  void setRobustEdges(bool on) { robustEdges_ = on; }
  /// A render model's triangles (checked by the caller: indices in range).
  ModelBuilder(const TriangleMesh& mesh, std::string name, MaterialCache& materials,
               std::vector<std::string>* warnings);
  /// Runs the whole pipeline (the list of steps) and returns the flattened model.
  ModelPtr build();
  /// Whether the edge table scattered its keys (int_hash.h; for tests: a
  /// real mesh's edges should keep the near layout).
  bool edgeTableScattered() const { return edgeHashHead_.scattered(); }

 private:
  // ---- brushes.cpp
  struct BrushPrimitive {
    int primitiveNum = 0;
    std::vector<Plane> planes;      ///< after FixDegeneracies
    std::vector<Winding> windings;  ///< of sides 0..n-2 (the bounds pass)
  };
  /// Brushes with collision contents, linked into the root; per primitive the
  /// planes and windings convertBrushSides uses later.
  std::vector<BrushPrimitive> convertBrushes();
  void convertBrush(const MapBrush& brush, int primitiveNum, BrushPrimitive& out);
  /// Brush sides and patches -> polygons, in primitive order.
  void convertPrimitivesToPolygons(std::vector<BrushPrimitive>& brushPrims);
  void convertBrushSides(const MapBrush& brush, BrushPrimitive& prim);
  void convertPatch(const MapPatch& patch, int primitiveNum);

  // ---- triangles.cpp
  /// The mesh's triangles -> polygons (the collision surfaces only, when
  /// there are any), then the axial BSP tree over them.
  void convertMeshSurfaces();

  // ---- polygons.cpp
  /// The vertex welding hash, over the bounds of the brushes (or a default box).
  void prepareVertexHash();
  /// Empties the hashes; the vertex hash's minimum at bounds.min, with room
  /// for about `expectedVertices` (see vertexHashSize_).
  void clearHash(const Bounds& bounds, std::size_t expectedVertices = 0);
  /// The welded vertex of v (true: an existing one).
  bool getVertex(const Vec3& v, int& vertexNum);
  /// getVertex's answer when v is one of the recent lookups that still
  /// holds (no side effects); false otherwise.
  bool recentVertex(const Vec3& v, int& vertexNum) const;
  /// getVertex of a snapped point without the recent lookups: the hash
  /// search, a new vertex if none matches.
  bool findOrAddVertex(const Vec3& vert, int& vertexNum);
  bool getEdge(const Vec3& v1, const Vec3& v2, int& edgeNum, int v1num);
  /// A new edge from v1num to v2num with one user, in the edge hash.
  int addEdge(int v1num, int v2num);
  void createPolygon(const Winding& w, const Plane& plane, int material, int primitiveNum);
  /// A new polygon of these edges and values, filtered into the tree.
  void addPolygon(EdgeList&& edges, std::uint32_t contents, int material, const Plane& plane,
                  const Bounds& bounds);
  /// createPolygon of w reversed (plane flipped), when polygon `original`
  /// was just made of w and the reversed copy would take each of its edges
  /// (see polygons.cpp): made from the original's edges. False (nothing
  /// done) otherwise.
  bool createReversedCopy(const Winding& w, const Plane& plane, std::size_t original);
  void polygonFromWinding(Winding& w, const Plane& plane, int material, int primitiveNum);
  void warn(const std::string& message);

  // ---- chop.cpp
  /// nullptr when the winding is contained in brushes, else the winding to use.
  const Winding* windingOutsideBrushes(const Winding& w, const Plane& plane, std::uint32_t contents,
                                       int primitiveNum);
  void chopWindingListWithTreeBrushes(int node);
  bool chopWindingListWithBrush(const BBrush& b);

  // ---- proc_prune.cpp
  /// True when a solid winding lies entirely in opaque solid leaves of the
  /// .proc BSP (the original's ChoppedAwayByProcBSP); false without one.
  bool choppedAwayByProcBsp(const Winding& w, const Plane& plane, std::uint32_t contents) const;

  // ---- bsp.cpp
  /// The axial BSP tree, only for models with more than a few brushes.
  void createBSPTreeForBrushes();
  int allocNode();
  void addPolygonToNode(int node, int polygon);
  void addBrushToNode(int node, int brush);
  /// The tree as model/tree_filter.h walks it, while it grows.
  struct GrowingTree {
    const std::vector<BNode>& nodes;
    const BNode& at(std::int32_t n) const { return nodes[static_cast<std::size_t>(n)]; }
    bool isLeaf(std::int32_t n) const { return at(n).isLeaf(); }
    int axis(std::int32_t n) const { return at(n).planeType; }
    Real dist(std::int32_t n) const { return at(n).planeDist; }
    std::int32_t child(std::int32_t n, int side) const { return at(n).children[side]; }
    bool insideAllChildren(std::int32_t n, const Bounds& b) const {
      return detail::insideAllChildren(*this, n, b);
    }
  };
  enum class ItemKind { Polygon, Brush };
  /// Prepends an item to the node's list of its kind (a polygon reference
  /// taken from the free list first), counting nothing: add*ToNode count.
  void linkToNode(ItemKind kind, int node, int item);
  /// Links a new polygon or brush into every node below `node` its bounds
  /// reach by the tree-filter rule (model/tree_filter.h).
  void filterIntoTree(ItemKind kind, int node, int item);

  // ---- axial_tree.cpp
  /// The axial BSP tree (the original's R_CreateAxialBSPTree) below the
  /// root, while it is the only node, over the items linked into it.
  void createAxialBSPTree(const Bounds& bounds);
  struct GrowingLists;
  /// The root's lists onto the stacks; the references emptied.
  void readLists(GrowingLists& lists);
  /// Prepends an item to a node's list: its chain while it waits to be
  /// split, its references once its subtree is finished.
  void prependToList(GrowingLists& lists, ItemKind kind, int node, const Bounds& bounds, int item);
  /// A node whose subtree is finished: its lists into the references.
  void finishList(GrowingLists& lists, int node);
  bool findSplitter(GrowingLists& lists, int node, const Bounds& bounds, int& planeType,
                    Real& planeDist) const;
  void splitNode(GrowingLists& lists, int node, const Bounds& bounds);
  /// The items of a node just split: those straddling its plane stay, the
  /// others go to the child on their side.
  void splitItems(GrowingLists& lists, int split);
  /// The items of `node` (an ancestor of `split`) that `split`'s
  /// new plane leaves no longer inside all children of `node`, down the tree.
  void pushItemsDown(GrowingLists& lists, int node, int split);
  Bounds nodeBounds() const;

  // ---- merge.cpp
  /// Coplanar polygons that share an edge, merged into one convex polygon.
  void mergePolygons();
  /// The merge index below, for the polygons and tree as they are (made
  /// only when some pair may merge).
  void prepareEdgeUsers();
  void prepareMergeIndex();
  /// Whether two live polygons that share an edge may pass mayMerge (false:
  /// none does; merge.cpp).
  bool anyPairMayMerge() const;
  void mergeTreePolygons(int node);
  bool mergePolygonWithTreePolygons(int polygon);
  /// True when walkTouching(0, bounds, ...) visits the node.
  bool walkReaches(int node, const Bounds& bounds) const;
  int tryMergePolygons(int p1, int p2);
  void replacePolygons(int node, int p1, int p2, int newp);

  // ---- t_junctions.cpp (robust edges only)
  /// A vertex to insert into a polygon's edge: where along it (0..1), which.
  struct EdgeSplit {
    double t = 0;
    int vertexNum = kNone;
  };
  /// Polygons with a vertex of a coplanar neighbour on an edge, replaced by
  /// convex pieces whose outlines include that vertex.
  void splitPolygonsAtTJunctions();
  /// Per edge of the polygon, the coplanar neighbours' vertices on it.
  std::vector<std::vector<int>> tJunctionsOf(int polygon);
  /// Those of `verts` on the edge (within kTJunctionEpsilon, away from its
  /// ends), in order along it as the signed edge number runs.
  std::vector<EdgeSplit> splitsAlong(int edgeNum, const std::vector<int>& verts) const;
  void cutPolygon(int polygon, const std::vector<std::vector<EdgeSplit>>& splits);
  /// The edge a piece runs along from vertex `from` to `to`: one whose only
  /// user runs the other way (shared), else a new one. (getEdge assumes an
  /// edge's one user runs it as stored; once cut polygons have given up
  /// their edges, the one left may run it backwards.)
  int pieceEdge(int from, int to);
  /// Per edge, while T-junctions are split: +1 or -1, the direction its one
  /// user runs it (0: not one user).
  std::vector<std::int8_t> soleUse_;
  /// Drops the polygon from the reference lists of the nodes below `node`.
  void unlinkPolygon(int node, int polygon);

  // ---- internal_edges.cpp
  /// Edges that a trace can never touch first, marked internal.
  void markInternalEdges();
  void findInternalEdges(int node);
  void findInternalPolygonEdges(int node, int polygon);
  void findInternalEdgesOnPolygon(int p1, int p2);
  bool pointInsidePolygon(const BPolygon& p, const Vec3& v) const;

  // ---- flatten.cpp: the model's arrays (the original's OptimizeArrays and
  // the layout of model.h)
  struct Remap {
    std::vector<int> vertices;  ///< build vertex -> model vertex
    std::vector<int> edges;     ///< build edge -> model edge (0: dropped)
  };
  /// Vertices used by an edge, edges used by a polygon, into the model.
  Remap compactVerticesAndEdges(ModelArrays& model) const;
  /// Nodes in pre-order; polygons and brushes in the order of their first reference.
  void flattenTree(ModelArrays& model, const Remap& remap) const;
  /// Bounds, contents, edge normals and statistics of the flattened model.
  void finishModel(ModelArrays& model) const;

  // ---- typed access to the build state (int indices, as in the original)
  Vec3& vertex(int v) { return vertices_[static_cast<std::size_t>(v)]; }
  const Vec3& vertex(int v) const { return vertices_[static_cast<std::size_t>(v)]; }
  /// The edge of a signed edge number (the sign is the direction of use).
  BEdge& edge(int edgeNum) { return edges_[static_cast<std::size_t>(std::abs(edgeNum))]; }
  const BEdge& edge(int edgeNum) const { return edges_[static_cast<std::size_t>(std::abs(edgeNum))]; }
  BPolygon& polygon(int p) { return polygons_[static_cast<std::size_t>(p)]; }
  const BPolygon& polygon(int p) const { return polygons_[static_cast<std::size_t>(p)]; }
  BBrush& brush(int b) { return brushes_[static_cast<std::size_t>(b)]; }
  const BBrush& brush(int b) const { return brushes_[static_cast<std::size_t>(b)]; }
  BNode& node(int n) { return nodes_[static_cast<std::size_t>(n)]; }
  const BNode& node(int n) const { return nodes_[static_cast<std::size_t>(n)]; }
  BRef& polygonRef(int r) { return polygonRefs_[static_cast<std::size_t>(r)]; }
  BRef& brushRef(int r) { return brushRefs_[static_cast<std::size_t>(r)]; }
  const BRef& polygonRef(int r) const { return polygonRefs_[static_cast<std::size_t>(r)]; }
  const BRef& brushRef(int r) const { return brushRefs_[static_cast<std::size_t>(r)]; }
  /// The polygons / brushes linked into a node, in list order.
  RefList polygonsAt(int n) const { return {polygonRefs_, node(n).polygons}; }
  RefList brushesAt(int n) const { return {brushRefs_, node(n).brushes}; }

  /// Visits `node` and the nodes below it that the bounds reach, where only
  /// bounds entirely beyond a plane skip a child (touching reaches both):
  /// each node before those below it, the back subtree before the front one
  /// (the original's recursion). visit(n) returns false to stop the walk;
  /// the result is false when it was stopped.
  template <class Visit>
  bool walkTouching(int nodeNum, const Bounds& bounds, Visit&& visit) {
    for (;;) {
      if (!visit(nodeNum)) return false;
      const BNode& here = node(nodeNum);
      if (here.isLeaf()) return true;
      if (bounds.min[here.planeType] > here.planeDist) {
        nodeNum = here.children[0];
      } else if (bounds.max[here.planeType] < here.planeDist) {
        nodeNum = here.children[1];
      } else {
        const int front = here.children[0];
        if (!walkTouching(here.children[1], bounds, visit)) return false;
        nodeNum = front;
      }
    }
  }

  /// True when each edge starts at the vertex where the one before it ends
  /// (cyclically): the edges outline a polygon.
  bool edgesFormLoop(std::span<const int> edgeNums) const {
    auto startVertex = [&](int e) { return edge(e).v[e > 0 ? 0 : 1]; };
    for (std::size_t k = 0; k < edgeNums.size(); ++k) {
      const int prev = edgeNums[k == 0 ? edgeNums.size() - 1 : k - 1];
      if (startVertex(-prev) != startVertex(edgeNums[k])) return false;
    }
    return true;
  }
  Vec3 edgeStart(int edgeNum) const { return vertex(edge(edgeNum).v[edgeNum < 0 ? 1 : 0]); }
  Vec3 edgeEnd(int edgeNum) const { return vertex(edge(edgeNum).v[edgeNum < 0 ? 0 : 1]); }

  const MapEntity* entity_ = nullptr;   ///< the map entity, or
  const TriangleMesh* mesh_ = nullptr;  ///< the mesh being built
  std::string name_;
  MaterialCache& materials_;
  std::vector<std::string>* warnings_;
  const ProcBsp* proc_ = nullptr;  ///< usable, or null
  bool robustEdges_ = false;       ///< see setRobustEdges
  /// Robust edges: per edge, 1 when the live polygons using it differ in
  /// contents (a solid face and a clip face sharing a corner).
  std::vector<std::uint8_t> mixedContentsEdge_;
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
  int freePolygonRef_ = kNone;
  BuildCounters counters_;
  int checkCount_ = 0;
  std::vector<std::int32_t> filterStack_;  ///< scratch of filterIntoTree

  // vertex and edge hashes (polygons.cpp)
  /// The original's vertex hash size (a power of two): the least
  /// vertexHashSize_.
  static constexpr int kVertexHashSize = 4096;
  /// Buckets of the vertex hash: kVertexHashSize, or for a mesh of many
  /// vertices the power of two from twice their number (up to
  /// kMaxVertexHashSize). Any power of two from 256 on finds the same
  /// vertices: a cell that findOrAddVertex searches (the point's, or one
  /// next to it) and the cell of any vertex that can match the point (within
  /// kVertexEpsilon, below the 4-unit cells: the point's cell or one next to
  /// it) lie at most two cells apart along each axis, so their keys
  /// (combineCells before the mask: k0 + 64 k1 + k2) differ by at most 132
  /// and share a bucket exactly when they are equal, whatever the size. More
  /// buckets only leave out of a chain vertices of far cells, which never
  /// match, and keep the chain's order (newest first).
  int vertexHashSize_ = kVertexHashSize;
  static constexpr int kMaxVertexHashSize = 1 << 20;
  Vec3 hashMin_;
  std::vector<int> vertexHashHead_;
  /// Per vertex, what a search of its chain reads, side by side (one cache
  /// line per vertex met instead of two): its position (vertices never move)
  /// and the next older vertex of its chain.
  struct VertexHashNode {
    Vec3 position;
    int next = kNone;
  };
  std::vector<VertexHashNode> vertexHashNodes_;
  int& hashHead(int key) { return vertexHashHead_[static_cast<std::size_t>(key)]; }
  const VertexHashNode& hashNode(int vertexNum) const {
    return vertexHashNodes_[static_cast<std::size_t>(vertexNum)];
  }
  /// The last kRecent getVertex lookups, coordinate by coordinate (a
  /// lookup compares its point with all of them at once, without a branch
  /// per entry): the point, the point welded (snapped), and its vertex
  /// (kNone: no entry, or dropped since).
  struct RecentVertices {
    static constexpr std::size_t kRecent = 8;
    alignas(16) std::array<Real, kRecent> x{}, y{}, z{};
    alignas(16) std::array<Real, kRecent> weldedX{}, weldedY{}, weldedZ{};
    std::array<int, kRecent> vertexNum{};
    unsigned valid = 0;  ///< bit k: entry k holds a vertex
    std::size_t next = 0;
    void clear() { *this = RecentVertices{}; }
  };
  RecentVertices recent_;
  IntHashMap edgeHashHead_;  ///< directed (v0, v1) -> newest edge
  std::vector<int> edgeHashNext_;

  // merge index (merge.cpp): only polygons sharing an edge can merge, so a
  // polygon looks up those instead of testing every polygon its bounds touch
  PooledLists edgeUsers_;       ///< per edge: the polygons made with it (freed ones too)
  PooledLists polygonNodes_;    ///< per live polygon: the nodes whose lists hold it
  std::vector<int> walkOrder_;  ///< per node: its place in walkTouching's order
  std::vector<int> mergeMark_;  ///< per polygon: the mergeStamp_ of a candidate
  int mergeStamp_ = 0;
  std::vector<int> mergeNodes_;   ///< scratch: the nodes to search, in walk order
  std::vector<int> linkedNodes_;  ///< scratch of replacePolygons: where newp went

  // winding list of windingOutsideBrushes
  struct WindingList {
    std::vector<Winding> w;  ///< kMaxWindings slots
    std::size_t numWindings = 0;
    Bounds bounds;
    Vec3 origin;
    Real radius = 0;
    Vec3 normal;
    std::uint32_t contents = 0;
    int primitiveNum = 0;
  };
  static constexpr std::size_t kMaxWindings = tol::kMaxWindingList;
  WindingList list_;
  std::vector<Winding> outList_;
  std::vector<Winding> tmpList_;
  Winding reversed_;  ///< scratch of polygonFromWinding: a two-sided polygon's back
};

}  // namespace cmkit::detail
