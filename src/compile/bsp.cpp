// The nodes of a model's axial BSP tree and the filtering of polygons and
// brushes into it (the tree's growth is axial_tree.cpp).
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
  if (brushCount > 4) createAxialBSPTree(rootBounds);
}

int ModelBuilder::allocNode() {
  nodes_.emplace_back();
  return static_cast<int>(nodes_.size()) - 1;
}

void ModelBuilder::linkToNode(ItemKind kind, int nodeNum, int item) {
  if (kind == ItemKind::Brush) {
    brushRefs_.push_back({item, node(nodeNum).brushes});
    node(nodeNum).brushes = static_cast<int>(brushRefs_.size()) - 1;
    return;
  }
  int r;
  if (freePolygonRef_ != kNone) {
    r = freePolygonRef_;
    freePolygonRef_ = polygonRef(r).next;
  } else {
    r = static_cast<int>(polygonRefs_.size());
    polygonRefs_.emplace_back();
  }
  BRef& ref = polygonRef(r);
  ref.item = item;
  ref.next = node(nodeNum).polygons;
  node(nodeNum).polygons = r;
}

void ModelBuilder::addPolygonToNode(int nodeNum, int polygonNum) {
  linkToNode(ItemKind::Polygon, nodeNum, polygonNum);
  counters_.numPolygonRefs++;
}

void ModelBuilder::addBrushToNode(int nodeNum, int brushNum) {
  linkToNode(ItemKind::Brush, nodeNum, brushNum);
  counters_.numBrushRefs++;
}

void ModelBuilder::filterIntoTree(ItemKind kind, int nodeNum, int item) {
  const bool isPolygon = kind == ItemKind::Polygon;
  const Bounds bounds = isPolygon ? polygon(item).bounds : brush(item).bounds;
  detail::filterIntoTree(GrowingTree{nodes_}, nodeNum, bounds, filterStack_, [&](int reached) {
    if (isPolygon) {
      addPolygonToNode(reached, item);
    } else {
      addBrushToNode(reached, item);
    }
  });
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
