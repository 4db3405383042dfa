// The end of a model build (the original's FinishModel): merging, internal
// edges, compaction of vertices and edges, and flattening of the linked
// build state into the immutable CollisionModel layout of model.h.
#include <cstdlib>

#include "compile/builder.h"
#include "model/edge_normals.h"

namespace cmkit::detail {

CollisionModel ModelBuilder::finish() {
  ++checkCount_;
  mergeTreePolygons(0);
  ++checkCount_;
  findInternalEdges(0);

  // ---- compaction (the original's OptimizeArrays) ----
  // Vertices: those referenced by any edge slot, including the dummy edge 0
  // and edges without users (they are compacted only afterwards).
  std::vector<int> vertexRemap(vertices_.size(), 0);
  std::vector<char> used(vertices_.size(), 0);
  for (const BEdge& e : edges_) {
    used[static_cast<std::size_t>(e.v[0])] = 1;
    used[static_cast<std::size_t>(e.v[1])] = 1;
  }
  CollisionModel model;
  model.name = name_;
  for (std::size_t i = 0; i < vertices_.size(); ++i) {
    if (!used[i]) continue;
    vertexRemap[i] = static_cast<int>(model.vertices.size());
    model.vertices.push_back(vertices_[i]);
  }
  // Edges: those with users (edge 0 stays as the dummy).
  std::vector<int> edgeRemap(edges_.size(), 0);
  if (!edges_.empty()) {
    model.edges.emplace_back();
    for (std::size_t i = 1; i < edges_.size(); ++i) {
      const BEdge& e = edges_[i];
      if (e.numUsers == 0) continue;
      edgeRemap[i] = static_cast<int>(model.edges.size());
      CmEdge ce;
      ce.vertex[0] = vertexRemap[static_cast<std::size_t>(e.v[0])];
      ce.vertex[1] = vertexRemap[static_cast<std::size_t>(e.v[1])];
      ce.internal = e.internal;
      ce.numUsers = static_cast<std::uint8_t>(e.numUsers > 255 ? 255 : e.numUsers);
      model.edges.push_back(ce);
    }
  }

  // ---- flattening: nodes in pre-order (front child first); polygons and
  // brushes in the order of their first reference in that walk ----
  std::vector<int> polygonIndex(polygons_.size(), -1);
  std::vector<int> brushIndex(brushes_.size(), -1);
  std::vector<int> materialIndex;  // build material -> model material
  auto modelMaterial = [&](int m) -> std::int32_t {
    if (m < 0) return -1;
    if (materialIndex.size() <= static_cast<std::size_t>(m))
      materialIndex.resize(static_cast<std::size_t>(m) + 1, -1);
    int& slot = materialIndex[static_cast<std::size_t>(m)];
    if (slot < 0) {
      slot = static_cast<int>(model.materials.size());
      model.materials.push_back(materials_[m].name);
    }
    return slot;
  };
  struct Pending {
    int buildNode;
    int parent;
    int childSlot;
  };
  std::vector<Pending> stack;
  stack.push_back({0, -1, -1});
  while (!stack.empty()) {
    const Pending cur = stack.back();
    stack.pop_back();
    const BNode& bn = nodes_[static_cast<std::size_t>(cur.buildNode)];
    const int index = static_cast<int>(model.nodes.size());
    model.nodes.emplace_back();
    if (cur.parent >= 0) model.nodes[static_cast<std::size_t>(cur.parent)].children[cur.childSlot] = index;
    CmNode& node = model.nodes.back();
    node.planeType = static_cast<std::int8_t>(bn.planeType);
    node.planeDist = bn.planeType >= 0 ? bn.planeDist : Real(0);
    node.parent = cur.parent;
    node.firstPolygonRef = static_cast<std::uint32_t>(model.polygonRefs.size());
    for (int r = bn.polygons; r >= 0; r = polygonRefs_[static_cast<std::size_t>(r)].next) {
      const int p = polygonRefs_[static_cast<std::size_t>(r)].item;
      int& slot = polygonIndex[static_cast<std::size_t>(p)];
      if (slot < 0) {
        const BPolygon& bp = polygons_[static_cast<std::size_t>(p)];
        slot = static_cast<int>(model.polygons.size());
        CmPolygon cp;
        cp.bounds = bp.bounds;
        cp.plane = bp.plane;
        cp.contents = bp.contents;
        cp.material = modelMaterial(bp.material);
        cp.firstEdge = static_cast<std::uint32_t>(model.polygonEdges.size());
        cp.numEdges = static_cast<std::uint32_t>(bp.edges.size());
        for (const int e : bp.edges) {
          const int m = edgeRemap[static_cast<std::size_t>(std::abs(e))];
          model.polygonEdges.push_back(e < 0 ? -m : m);
        }
        model.polygons.push_back(cp);
      }
      model.polygonRefs.push_back(slot);
    }
    model.nodes[static_cast<std::size_t>(index)].numPolygonRefs =
        static_cast<std::uint32_t>(model.polygonRefs.size()) -
        model.nodes[static_cast<std::size_t>(index)].firstPolygonRef;
    model.nodes[static_cast<std::size_t>(index)].firstBrushRef =
        static_cast<std::uint32_t>(model.brushRefs.size());
    for (int r = bn.brushes; r >= 0; r = brushRefs_[static_cast<std::size_t>(r)].next) {
      const int b = brushRefs_[static_cast<std::size_t>(r)].item;
      int& slot = brushIndex[static_cast<std::size_t>(b)];
      if (slot < 0) {
        const BBrush& bb = brushes_[static_cast<std::size_t>(b)];
        slot = static_cast<int>(model.brushes.size());
        CmBrush cb;
        cb.bounds = bb.bounds;
        cb.contents = bb.contents;
        cb.material = modelMaterial(bb.material);
        cb.primitiveNum = bb.primitiveNum;
        cb.firstPlane = static_cast<std::uint32_t>(model.brushPlanes.size());
        cb.numPlanes = static_cast<std::uint32_t>(bb.planes.size());
        model.brushPlanes.insert(model.brushPlanes.end(), bb.planes.begin(), bb.planes.end());
        model.brushes.push_back(cb);
      }
      model.brushRefs.push_back(slot);
    }
    model.nodes[static_cast<std::size_t>(index)].numBrushRefs =
        static_cast<std::uint32_t>(model.brushRefs.size()) -
        model.nodes[static_cast<std::size_t>(index)].firstBrushRef;
    if (bn.planeType >= 0) {
      // pushed back child first so that the front child is numbered first
      stack.push_back({bn.children[1], index, 1});
      stack.push_back({bn.children[0], index, 0});
    }
  }

  computeModelBoundsAndContents(model);

  model.stats.sharpEdges = computeEdgeNormals(model);
  model.stats.internalEdges = counters_.numInternalEdges;
  model.stats.containedPolygonsRemoved = counters_.numRemovedPolys;
  model.stats.polygonsMerged = counters_.numMergedPolys;
  return model;
}

}  // namespace cmkit::detail
