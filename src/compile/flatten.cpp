// The end of a model build (the original's FinishModel after merging and
// internal edges): compaction of vertices and edges (OptimizeArrays) and
// flattening of the linked build state into the immutable CollisionModel
// layout of model.h.
#include <cstdlib>

#include "compile/builder.h"
#include "model/edge_normals.h"

namespace cmkit::detail {

ModelBuilder::Remap ModelBuilder::compactVerticesAndEdges(ModelArrays& model) const {
  Remap remap;
  // Vertices: those referenced by any edge slot, including the dummy edge 0
  // and edges without users (they are compacted only afterwards).
  remap.vertices.assign(vertices_.size(), 0);
  model.vertices.reserve(vertices_.size());
  model.edges.reserve(edges_.size());
  std::vector<char> used(vertices_.size(), 0);
  for (const BEdge& e : edges_) {
    used[static_cast<std::size_t>(e.v[0])] = 1;
    used[static_cast<std::size_t>(e.v[1])] = 1;
  }
  for (std::size_t i = 0; i < vertices_.size(); ++i) {
    if (!used[i]) continue;
    remap.vertices[i] = static_cast<int>(model.vertices.size());
    model.vertices.push_back(vertices_[i]);
  }
  // Edges: those with users (edge 0 stays as the dummy).
  remap.edges.assign(edges_.size(), 0);
  if (edges_.empty()) return remap;
  model.edges.emplace_back();
  for (std::size_t i = 1; i < edges_.size(); ++i) {
    const BEdge& e = edges_[i];
    if (e.numUsers == 0) continue;
    remap.edges[i] = static_cast<int>(model.edges.size());
    CmEdge ce;
    ce.vertex[0] = remap.vertices[static_cast<std::size_t>(e.v[0])];
    ce.vertex[1] = remap.vertices[static_cast<std::size_t>(e.v[1])];
    ce.internal = e.internal;
    ce.numUsers = static_cast<std::uint8_t>(e.numUsers > 255 ? 255 : e.numUsers);
    model.edges.push_back(ce);
  }
  return remap;
}

namespace {

/// Build indices -> model indices, given out in the order items are first met.
class IndexMap {
 public:
  explicit IndexMap(std::size_t size) : index_(size, kNone) {}
  /// The model index of the item; add() makes it (and returns it) the first time.
  template <class Add>
  int get(int buildIndex, Add&& add) {
    const auto i = static_cast<std::size_t>(buildIndex);
    if (index_.size() <= i) index_.resize(i + 1, kNone);
    if (index_[i] == kNone) index_[i] = add();
    return index_[i];
  }

 private:
  std::vector<int> index_;
};

template <class T>
int appended(std::vector<T>& v, const T& item) {
  v.push_back(item);
  return static_cast<int>(v.size()) - 1;
}

}  // namespace

void ModelBuilder::flattenTree(ModelArrays& model, const Remap& remap) const {
  // Nodes in pre-order (front child first); polygons, brushes and materials
  // in the order they are first met in that walk. The walk makes the nodes
  // and their lists, numbering each polygon and brush when first met; the
  // polygons and brushes are made afterwards in that order (and their
  // materials numbered as they come), each polygon's record fetched a few
  // ahead: in tree order they lie all over the builder's array, and made one
  // by one in the walk each waited for memory.
  struct FirstMet {
    int item;
    bool brush;
  };
  std::vector<FirstMet> met;
  met.reserve(polygons_.size() + brushes_.size());
  int numPolygons = 0, numBrushes = 0;
  IndexMap polygonIndex(polygons_.size());
  IndexMap brushIndex(brushes_.size());
  struct Pending {
    int buildNode;
    int parent;
    int childSlot;
  };
  model.nodes.reserve(nodes_.size());
  model.polygonRefs.reserve(polygonRefs_.size());
  model.brushRefs.reserve(brushRefs_.size());
  std::vector<Pending> stack;
  stack.push_back({0, kNone, kNone});
  while (!stack.empty()) {
    const Pending cur = stack.back();
    stack.pop_back();
    const BNode& bn = node(cur.buildNode);
    const int index = static_cast<int>(model.nodes.size());
    if (cur.parent != kNone)
      model.nodes[static_cast<std::size_t>(cur.parent)].children[cur.childSlot] = index;
    CmNode cn;
    cn.planeType = static_cast<std::int8_t>(bn.planeType);
    cn.planeDist = bn.isLeaf() ? Real(0) : bn.planeDist;
    cn.parent = cur.parent;
    cn.firstPolygonRef = static_cast<std::uint32_t>(model.polygonRefs.size());
    for (const int p : polygonsAt(cur.buildNode)) {
      model.polygonRefs.push_back(polygonIndex.get(p, [&] {
        met.push_back({p, false});
        return numPolygons++;
      }));
    }
    cn.numPolygonRefs = static_cast<std::uint32_t>(model.polygonRefs.size()) - cn.firstPolygonRef;
    cn.firstBrushRef = static_cast<std::uint32_t>(model.brushRefs.size());
    for (const int b : brushesAt(cur.buildNode)) {
      model.brushRefs.push_back(brushIndex.get(b, [&] {
        met.push_back({b, true});
        return numBrushes++;
      }));
    }
    cn.numBrushRefs = static_cast<std::uint32_t>(model.brushRefs.size()) - cn.firstBrushRef;
    model.nodes.push_back(cn);
    if (!bn.isLeaf()) {
      // pushed back child first so that the front child is numbered first
      stack.push_back({bn.children[1], index, 1});
      stack.push_back({bn.children[0], index, 0});
    }
  }

  IndexMap materialIndex(0);
  auto modelMaterial = [&](int m) -> std::int32_t {
    if (m == kNone) return kNone;
    return materialIndex.get(m, [&] { return appended(model.materials, materials_[m].name); });
  };
  model.polygons.reserve(static_cast<std::size_t>(numPolygons));
  model.brushes.reserve(static_cast<std::size_t>(numBrushes));
  std::size_t numPolygonEdges = 0;
  for (const BPolygon& p : polygons_) numPolygonEdges += p.freed ? 0 : p.edges.size();
  model.polygonEdges.reserve(numPolygonEdges);
  // (far enough ahead to overlap a few fetches, near enough that the
  // fetched lines are still there)
  constexpr std::size_t kFetchAhead = 8;
  for (std::size_t i = 0; i < met.size(); ++i) {
    if (i + kFetchAhead < met.size() && !met[i + kFetchAhead].brush) {
      const BPolygon* ahead = &polygon(met[i + kFetchAhead].item);
      __builtin_prefetch(ahead);
      __builtin_prefetch(reinterpret_cast<const char*>(ahead) + sizeof(BPolygon) - 1);
    }
    if (met[i].brush) {
      const BBrush& bb = brush(met[i].item);
      CmBrush cb;
      cb.bounds = bb.bounds;
      cb.contents = bb.contents;
      cb.material = modelMaterial(bb.material);
      cb.primitiveNum = bb.primitiveNum;
      cb.firstPlane = static_cast<std::uint32_t>(model.brushPlanes.size());
      cb.numPlanes = static_cast<std::uint32_t>(bb.planes.size());
      model.brushPlanes.insert(model.brushPlanes.end(), bb.planes.begin(), bb.planes.end());
      model.brushes.push_back(cb);
      continue;
    }
    const BPolygon& bp = polygon(met[i].item);
    CmPolygon cp;
    cp.bounds = bp.bounds;
    cp.plane = bp.plane;
    cp.contents = bp.contents;
    cp.material = modelMaterial(bp.material);
    cp.firstEdge = static_cast<std::uint32_t>(model.polygonEdges.size());
    cp.numEdges = static_cast<std::uint32_t>(bp.edges.size());
    for (const int e : bp.edges) {
      const int m = remap.edges[static_cast<std::size_t>(std::abs(e))];
      model.polygonEdges.push_back(e < 0 ? -m : m);
    }
    model.polygons.push_back(cp);
  }
}

void ModelBuilder::finishModel(ModelArrays& model) const {
  computeModelBoundsAndContents(model);
  // Robust edges: a two-sided polygon and its reversed copy are one sheet,
  // not a sharp fold (edge_normals.h).
  model.stats.sharpEdges =
      computeEdgeNormals(model, robustEdges_ ? EdgeNormalRule::TwoSidedSheets : EdgeNormalRule::Original);
  model.stats.internalEdges = counters_.numInternalEdges;
  model.stats.containedPolygonsRemoved = counters_.numRemovedPolys;
  model.stats.procPolygonsRemoved = counters_.numProcRemovedPolys;
  model.stats.polygonsMerged = counters_.numMergedPolys;
}

}  // namespace cmkit::detail
