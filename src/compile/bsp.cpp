// The axial BSP tree of a model (the original's CM_FindSplitter,
// R_CreateAxialBSPTree, CM_R_InsideAllChildren and the filtering of polygons
// and brushes into the tree).
#include <cmath>

#include "compile/builder.h"
#include "model/tree_filter.h"

namespace cmkit::detail {

void ModelBuilder::createBSPTreeForBrushes() {
  int brushCount = 0;
  Bounds rootBounds;
  for (const int b : brushesAt(0)) {
    ++brushCount;
    rootBounds = unionBounds(rootBounds, brush(b).bounds);
  }
  if (brushCount > 4) createAxialBSPTree(0, rootBounds);
}

int ModelBuilder::allocNode() {
  nodes_.emplace_back();
  return static_cast<int>(nodes_.size()) - 1;
}

void ModelBuilder::addPolygonToNode(int nodeNum, int polygonNum) {
  int r;
  if (freePolygonRef_ != kNone) {
    r = freePolygonRef_;
    freePolygonRef_ = polygonRef(r).next;
  } else {
    r = static_cast<int>(polygonRefs_.size());
    polygonRefs_.emplace_back();
  }
  BRef& ref = polygonRef(r);
  ref.item = polygonNum;
  ref.next = node(nodeNum).polygons;
  node(nodeNum).polygons = r;
  counters_.numPolygonRefs++;
}

void ModelBuilder::addBrushToNode(int nodeNum, int brushNum) {
  const int r = static_cast<int>(brushRefs_.size());
  brushRefs_.push_back({brushNum, node(nodeNum).brushes});
  node(nodeNum).brushes = r;
  counters_.numBrushRefs++;
}

bool ModelBuilder::insideAllChildren(int nodeNum, const Bounds& bounds) const {
  return detail::insideAllChildren(GrowingTree{nodes_}, nodeNum, bounds);
}

void ModelBuilder::filterIntoTree(ItemKind kind, int nodeNum, int ref, int item) {
  const bool isPolygon = kind == ItemKind::Polygon;
  const Bounds bounds = isPolygon ? polygon(item).bounds : brush(item).bounds;
  detail::filterIntoTree(GrowingTree{nodes_}, nodeNum, bounds, filterStack_, [&](int reached) {
    if (ref != kNone) {  // move the existing reference: prepend it to the node's list
      int& head = isPolygon ? node(reached).polygons : node(reached).brushes;
      (isPolygon ? polygonRef(ref) : brushRef(ref)).next = head;
      head = ref;
      ref = kNone;  // new references for the other nodes
    } else if (isPolygon) {
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
    for ([[maybe_unused]] const int p : polygonsAt(nodeNum)) ++polyCount;
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
    for (int n = nodeNum; n != kNone; n = node(n).parent) {
      for (const int b : brushesAt(n)) consider(brush(b).bounds);
    }
    for (int n = nodeNum; n != kNone; n = node(n).parent) {
      for (const int p : polygonsAt(n)) consider(polygon(p).bounds);
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
  int planeType = kNone;
  Real planeDist = 0;
  if (!findSplitter(nodeNum, bounds, planeType, planeDist)) {
    node(nodeNum).planeType = kNone;
    return;
  }
  const int frontNode = allocNode();
  node(frontNode).parent = nodeNum;
  const int backNode = allocNode();
  node(backNode).parent = nodeNum;
  counters_.numNodes += 2;
  Bounds frontBounds = bounds;
  frontBounds.min[planeType] = planeDist;
  Bounds backBounds = bounds;
  backBounds.max[planeType] = planeDist;
  BNode& split = node(nodeNum);
  split.planeType = planeType;
  split.planeDist = planeDist;
  split.children[0] = frontNode;
  split.children[1] = backNode;
  // The new split can leave items of this node and of every ancestor no
  // longer inside all children.
  for (int n = nodeNum; n != kNone; n = node(n).parent) pushItemsDown(n);
  createAxialBSPTree(frontNode, frontBounds);
  createAxialBSPTree(backNode, backBounds);
}

void ModelBuilder::pushItemsDown(int nodeNum) {
  for (const ItemKind kind : {ItemKind::Polygon, ItemKind::Brush}) {
    const bool isPolygon = kind == ItemKind::Polygon;
    auto ref = [&](int r) -> BRef& { return isPolygon ? polygonRef(r) : brushRef(r); };
    int& head = isPolygon ? node(nodeNum).polygons : node(nodeNum).brushes;
    int prev = kNone;
    for (int r = head, next; r != kNone; r = next) {
      next = ref(r).next;
      const int item = ref(r).item;
      if (insideAllChildren(nodeNum, isPolygon ? polygon(item).bounds : brush(item).bounds)) {
        prev = r;
        continue;
      }
      filterIntoTree(kind, nodeNum, r, item);
      (prev != kNone ? ref(prev).next : head) = next;  // unlink it here
    }
  }
}

Bounds ModelBuilder::nodeBounds() const {
  // The original's CM_GetNodeBounds: both corners of every item as points
  // (so a cleared item bounds makes the result +-infinity), zero if empty.
  Bounds b;
  for (int n = 0; n < static_cast<int>(nodes_.size()); ++n) {
    for (const int p : polygonsAt(n)) {
      b.addPoint(polygon(p).bounds.min);
      b.addPoint(polygon(p).bounds.max);
    }
    for (const int br : brushesAt(n)) {
      b.addPoint(brush(br).bounds.min);
      b.addPoint(brush(br).bounds.max);
    }
  }
  if (b.min.x > b.max.x) b = Bounds{Vec3{}, Vec3{}};
  return b;
}

}  // namespace cmkit::detail
