// The axial BSP tree of a model (the original's CM_FindSplitter,
// R_CreateAxialBSPTree, CM_R_InsideAllChildren and the filtering of polygons
// and brushes into the tree).
#include <cmath>

#include "compile/builder.h"
#include "model/tree_filter.h"

namespace cmkit::detail {

int ModelBuilder::allocNode() {
  nodes_.emplace_back();
  return static_cast<int>(nodes_.size()) - 1;
}

void ModelBuilder::addPolygonToNode(int node, int polygon) {
  int r;
  if (freePolygonRef_ >= 0) {
    r = freePolygonRef_;
    freePolygonRef_ = polygonRefs_[static_cast<std::size_t>(r)].next;
  } else {
    r = static_cast<int>(polygonRefs_.size());
    polygonRefs_.emplace_back();
  }
  BRef& ref = polygonRefs_[static_cast<std::size_t>(r)];
  ref.item = polygon;
  ref.next = nodes_[static_cast<std::size_t>(node)].polygons;
  nodes_[static_cast<std::size_t>(node)].polygons = r;
  counters_.numPolygonRefs++;
}

void ModelBuilder::addBrushToNode(int node, int brush) {
  const int r = static_cast<int>(brushRefs_.size());
  brushRefs_.push_back({brush, nodes_[static_cast<std::size_t>(node)].brushes});
  nodes_[static_cast<std::size_t>(node)].brushes = r;
  counters_.numBrushRefs++;
}

bool ModelBuilder::insideAllChildren(int nodeNum, const Bounds& bounds) const {
  return detail::insideAllChildren(GrowingTree{nodes_}, nodeNum, bounds);
}

void ModelBuilder::filterIntoTree(ItemKind kind, int nodeNum, int ref, int item) {
  const bool polygon = kind == ItemKind::Polygon;
  const auto index = static_cast<std::size_t>(item);
  const Bounds bounds = polygon ? polygons_[index].bounds : brushes_[index].bounds;
  detail::filterIntoTree(GrowingTree{nodes_}, nodeNum, bounds, filterStack_, [&](int reached) {
    BNode& node = nodes_[static_cast<std::size_t>(reached)];
    if (ref >= 0) {  // move the existing reference: prepend it to the node's list
      int& head = polygon ? node.polygons : node.brushes;
      (polygon ? polygonRefs_ : brushRefs_)[static_cast<std::size_t>(ref)].next = head;
      head = ref;
      ref = -1;  // new references for the other nodes
    } else if (polygon) {
      addPolygonToNode(reached, item);
    } else {
      addBrushToNode(reached, item);
    }
  });
}

bool ModelBuilder::findSplitter(int nodeNum, const Bounds& bounds, int& planeType, Real& planeDist) const {
  Real size[3];
  int axis[3];
  for (int i = 0; i < 3; ++i) {
    size[i] = bounds.max[i] - bounds.min[i];
    axis[i] = i;
  }
  // Largest axis first (the original's restarting bubble sort).
  for (int i = 0; i < 2; ++i) {
    if (size[i] < size[i + 1]) {
      std::swap(size[i], size[i + 1]);
      std::swap(axis[i], axis[i + 1]);
      i = -1;
    }
  }
  bool forceSplit = false;
  if (size[0] < tol::kMinNodeSize) {
    int polyCount = 0;
    for (int r = nodes_[static_cast<std::size_t>(nodeNum)].polygons; r >= 0;
         r = polygonRefs_[static_cast<std::size_t>(r)].next) {
      ++polyCount;
    }
    if (polyCount > tol::kMaxNodePolygons) forceSplit = true;
  }
  for (int i = 0; i < 3; ++i) {
    const int type = axis[i];
    Real bestt = size[i];
    if (!forceSplit && bestt < tol::kMinNodeSize) break;
    auto consider = [&](const Bounds& b) {
      for (int j = 0; j < 2; ++j) {
        const Real dist = b[j][type];
        if (dist >= bounds.max[type] || dist <= bounds.min[type]) continue;
        // the most centred splitter (dhewm3: not truncated to an integer)
        const Real t = std::fabs((bounds.max[type] - dist) - (dist - bounds.min[type]));
        if (t < bestt) {
          bestt = t;
          planeType = type;
          planeDist = dist;
        }
      }
    };
    // candidates from the brushes and polygons of this node and its ancestors
    for (int n = nodeNum; n >= 0; n = nodes_[static_cast<std::size_t>(n)].parent) {
      for (int r = nodes_[static_cast<std::size_t>(n)].brushes; r >= 0;
           r = brushRefs_[static_cast<std::size_t>(r)].next) {
        consider(brushes_[static_cast<std::size_t>(brushRefs_[static_cast<std::size_t>(r)].item)].bounds);
      }
    }
    for (int n = nodeNum; n >= 0; n = nodes_[static_cast<std::size_t>(n)].parent) {
      for (int r = nodes_[static_cast<std::size_t>(n)].polygons; r >= 0;
           r = polygonRefs_[static_cast<std::size_t>(r)].next) {
        consider(polygons_[static_cast<std::size_t>(polygonRefs_[static_cast<std::size_t>(r)].item)].bounds);
      }
    }
    if (bestt < size[i]) {
      if (forceSplit) return true;
      // not too close to the node bounds
      if (bounds.max[type] - planeDist > tol::kSplitterMinDistance &&
          planeDist - bounds.min[type] > tol::kSplitterMinDistance) {
        return true;
      }
    }
  }
  return false;
}

void ModelBuilder::createAxialBSPTree(int nodeNum, const Bounds& bounds) {
  int planeType = -1;
  Real planeDist = 0;
  if (!findSplitter(nodeNum, bounds, planeType, planeDist)) {
    nodes_[static_cast<std::size_t>(nodeNum)].planeType = -1;
    return;
  }
  const int frontNode = allocNode();
  nodes_[static_cast<std::size_t>(frontNode)].parent = nodeNum;
  const int backNode = allocNode();
  nodes_[static_cast<std::size_t>(backNode)].parent = nodeNum;
  counters_.numNodes += 2;
  Bounds frontBounds = bounds;
  frontBounds.min[planeType] = planeDist;
  Bounds backBounds = bounds;
  backBounds.max[planeType] = planeDist;
  {
    BNode& node = nodes_[static_cast<std::size_t>(nodeNum)];
    node.planeType = planeType;
    node.planeDist = planeDist;
    node.children[0] = frontNode;
    node.children[1] = backNode;
  }
  // Move references that are no longer inside all children down the tree,
  // for this node and every ancestor.
  for (int n = nodeNum; n >= 0; n = nodes_[static_cast<std::size_t>(n)].parent) {
    int prev = -1;
    for (int r = nodes_[static_cast<std::size_t>(n)].polygons, next; r >= 0; r = next) {
      next = polygonRefs_[static_cast<std::size_t>(r)].next;
      const int p = polygonRefs_[static_cast<std::size_t>(r)].item;
      if (!insideAllChildren(n, polygons_[static_cast<std::size_t>(p)].bounds)) {
        filterIntoTree(ItemKind::Polygon, n, r, p);
        if (prev >= 0) {
          polygonRefs_[static_cast<std::size_t>(prev)].next = next;
        } else {
          nodes_[static_cast<std::size_t>(n)].polygons = next;
        }
      } else {
        prev = r;
      }
    }
    prev = -1;
    for (int r = nodes_[static_cast<std::size_t>(n)].brushes, next; r >= 0; r = next) {
      next = brushRefs_[static_cast<std::size_t>(r)].next;
      const int b = brushRefs_[static_cast<std::size_t>(r)].item;
      if (!insideAllChildren(n, brushes_[static_cast<std::size_t>(b)].bounds)) {
        filterIntoTree(ItemKind::Brush, n, r, b);
        if (prev >= 0) {
          brushRefs_[static_cast<std::size_t>(prev)].next = next;
        } else {
          nodes_[static_cast<std::size_t>(n)].brushes = next;
        }
      } else {
        prev = r;
      }
    }
  }
  createAxialBSPTree(frontNode, frontBounds);
  createAxialBSPTree(backNode, backBounds);
}

Bounds ModelBuilder::nodeBounds() const {
  // The original's CM_GetNodeBounds: both corners of every item as points
  // (so a cleared item bounds makes the result +-infinity), zero if empty.
  Bounds b;
  for (const BNode& node : nodes_) {
    for (int r = node.polygons; r >= 0; r = polygonRefs_[static_cast<std::size_t>(r)].next) {
      const BPolygon& p = polygons_[static_cast<std::size_t>(polygonRefs_[static_cast<std::size_t>(r)].item)];
      b.addPoint(p.bounds.min);
      b.addPoint(p.bounds.max);
    }
    for (int r = node.brushes; r >= 0; r = brushRefs_[static_cast<std::size_t>(r)].next) {
      const BBrush& br = brushes_[static_cast<std::size_t>(brushRefs_[static_cast<std::size_t>(r)].item)];
      b.addPoint(br.bounds.min);
      b.addPoint(br.bounds.max);
    }
  }
  if (b.min.x > b.max.x) b = Bounds{Vec3{}, Vec3{}};
  return b;
}

}  // namespace cmkit::detail
