// Walking the axial BSP tree along a movement (the original's
// TraceThroughAxialBSPTree_r and TraceTrmThroughNode) or with a box (a
// rotation's arc), with the node test of the query kind.
#include <algorithm>
#include <cmath>

#include "model/point_tree.h"
#include "model/query_data.h"
#include "query/polygon_edges.h"
#include "query/trace_work.h"

namespace cmkit::detail {

namespace {

// What each query kind tests at a node (the node test is chosen once per
// query kind: the walks below are instantiated per kind).

/// A trace model's translation: the node's polygons.
struct TranslateTrmItems {
  static bool has(const CmNode& node) { return node.numPolygonRefs != 0; }
  static void test(TraceWork& tw, const CmNode& node) { translateTrmThroughNode(tw, node); }
  static constexpr bool kStopWhenStuck = false;
};

/// A point's translation: the node's polygons.
struct TranslatePointItems {
  static bool has(const CmNode& node) { return node.numPolygonRefs != 0; }
  static void test(TraceWork& tw, const CmNode& node) {
    translatePointThroughPolygons(tw, tw.model.polygonsAt(node));
  }
  static constexpr bool kStopWhenStuck = false;
};

/// A position test: the node's brushes (every vertex inside one?), then its
/// polygons (crossing the trace model?).
struct PositionItems {
  static bool has(const CmNode& node) { return node.numPolygonRefs != 0 || node.numBrushRefs != 0; }
  static void test(TraceWork& tw, const CmNode& node) {
    if (tw.fraction == 0) return;  // already stuck
    if (!testTrmVertsInBrushes(tw, tw.model.brushesAt(node))) testTrmInNodePolygons(tw, node);
  }
  static constexpr bool kStopWhenStuck = true;
};

/// A rotation part: the node's polygons.
struct RotateItems {
  static bool has(const CmNode& node) { return node.numPolygonRefs != 0; }
  static void test(TraceWork& tw, const CmNode& node) { rotateTrmThroughNode(tw, node); }
};

// Visits every node whose region the box touches (closed: a box touching a
// split plane visits both sides), testing the items at each.
template <class Items>
void walkBox(TraceWork& tw, std::int32_t nodeNum, const Bounds& box) {
  while (nodeNum >= 0) {
    if (tw.quickExit || tw.fraction == 0) return;  // fraction 0: blocked completely
    const CmNode& node = tw.model.nodes()[std::size_t(nodeNum)];
    count(tw.scratch, &QueryStats::nodesVisited);
    if (Items::has(node)) Items::test(tw, node);
    if (node.isLeaf() || tw.quickExit || tw.fraction == 0) return;
    const int axis = node.planeType;
    const bool front = box.max[axis] >= node.planeDist;
    const bool back = box.min[axis] <= node.planeDist;
    if (front && back) walkBox<Items>(tw, node.children[0], box);
    nodeNum = back ? node.children[1] : node.children[0];
  }
}

// The model's point tree (model/point_tree.h) where the walks below read it
// instead of the model's nodes: a model of more than kPointTreeMinNodes nodes.
const PointTree* pointTreeOf(const TraceWork& tw) {
  if (tw.queryData == nullptr || tw.model.nodes().size() <= kPointTreeMinNodes) return nullptr;
  const PointTree& t = tw.queryData->pointTree;
  return t.empty() ? nullptr : &t;
}

// A walk of the point tree visiting the nodes that walkBox<Items> or a
// position test's walkSegment<PositionItems> visits, in the same order (a
// node's items, its front subtree, then its back one), with the same tests,
// reading a node's 8 bytes (near its parent's) instead of the model's 36,
// and a model node only where items are listed. sides(axis, dist) says
// which sides of a split the walk goes on to: bit 0 the front, bit 1 the
// back (none: the front, as walkBox does for an inverted box). The back
// sides wait on a stack in the caller's scratch. The walk is over once the
// trace model is blocked (both walks return at every level then).
template <class Items, class Sides>
void walkPointTree(TraceWork& tw, const PointTree& t, Sides sides) {
  std::vector<std::uint32_t>& pending = tw.scratch.pointStack;
  std::size_t numPending = 0;
  std::uint32_t n = 0;
  for (;;) {
    for (;;) {
      if (tw.quickExit || tw.fraction == 0) return;
      const PointNode node = t.nodes[n];
      count(tw.scratch, &QueryStats::nodesVisited);
      if (node.hasItems()) {
        const CmNode& items = tw.model.nodes()[t.modelNodes[n]];
        if (Items::has(items)) Items::test(tw, items);
      }
      const std::uint32_t axis = node.axis();
      if (axis == PointNode::kLeafAxis) break;
      const unsigned go = sides(int(axis), node.dist);
      if (go == 3) {
        if (numPending == pending.size()) pending.resize(2 * numPending + 32);
        pending[numPending++] = node.front() + 1;
      }
      n = go == 2 ? node.front() + 1 : node.front();
    }
    if (numPending == 0) return;
    n = pending[--numPending];
  }
}

// walkBox's sides of a split: those the box touches.
void walkBoxThroughPointTree(TraceWork& tw, const PointTree& t, const Bounds& box) {
  walkPointTree<RotateItems>(tw, t, [&box](int axis, Real dist) {
    return unsigned(box.max[axis] >= dist) | unsigned(box.min[axis] <= dist) << 1;
  });
}

// walkSegment's sides of a split for a segment of no length (a position
// test's, from tw.start to tw.start): farther than the extent on one side,
// that side only, else both.
void positionWalkThroughPointTree(TraceWork& tw, const PointTree& t) {
  const Real start[3] = {tw.start.x, tw.start.y, tw.start.z};
  walkPointTree<PositionItems>(tw, t, [&](int axis, Real dist) {
    const Real d = start[axis] - dist;
    const Real offset = tw.extents[axis];
    return d >= offset ? 1u : d < -offset ? 2u : 3u;
  });
}

// The walk along the segment, near side before far side at every split, as
// the original's recursion does. The far sides wait on a stack in the
// caller's scratch (no recursion: a degenerate deep tree cannot overflow the
// thread's stack, and a point trace saves the calls).
template <class Items>
void walkSegment(TraceWork& tw) {
  using Segment = detail::QueryScratch::WalkSegment;
  // (Indexed by hand: the vector only grows, by resize, when a deeper tree
  // needs it; push_back's out-of-line growth path cost a call per split.)
  std::vector<Segment>& pending = tw.scratch.walkStack;
  std::size_t numPending = 0;
  Segment cur{0, 0, 1, tw.start, tw.end};
  for (;;) {
    std::int32_t nodeNum = cur.node;
    while (nodeNum >= 0) {
      if (tw.quickExit) return;
      if (tw.fraction <= cur.p1f) break;  // something nearer was hit already
      const CmNode& node = tw.model.nodes()[std::size_t(nodeNum)];
      count(tw.scratch, &QueryStats::nodesVisited);
      // The walk goes on to one child or both: start loading the back one
      // (the front one follows in memory) while this node's items are tested.
      if (!node.isLeaf()) prefetch(&tw.model.nodes()[std::size_t(node.children[1])]);
      if (Items::has(node)) Items::test(tw, node);
      if (Items::kStopWhenStuck && tw.fraction == 0) break;
      if (node.isLeaf()) break;

      // Distances of the segment ends to the split plane, and the trace
      // model's extent along its axis: both ends farther than the extent on
      // one side visit that side only.
      const int axis = node.planeType;
      const Real t1 = cur.p1[axis] - node.planeDist;
      const Real t2 = cur.p2[axis] - node.planeDist;
      const Real offset = tw.extents[axis];
      if (t1 >= offset && t2 >= offset) {
        nodeNum = node.children[0];
        continue;
      }
      if (t1 < -offset && t2 < -offset) {
        nodeNum = node.children[1];
        continue;
      }
      // The segment crosses the slab around the plane: the near side up to
      // where the trace leaves the slab's far face (now), the far side from
      // where it enters the near face (later).
      int side;
      Real frac, frac2;
      if (t1 < t2) {
        const Real idist = Real(1) / (t1 - t2);
        side = 1;
        frac2 = (t1 + offset) * idist;
        frac = (t1 - offset) * idist;
      } else if (t1 > t2) {
        const Real idist = Real(1) / (t1 - t2);
        side = 0;
        frac2 = (t1 - offset) * idist;
        frac = (t1 + offset) * idist;
      } else {
        side = 0;
        frac = 1;
        frac2 = 0;
      }
      const Vec3 p1 = cur.p1, p2 = cur.p2;
      frac2 = std::clamp(frac2, Real(0), Real(1));
      if (numPending == pending.size()) pending.resize(2 * numPending + 32);
      pending[numPending++] =
          Segment{node.children[side ^ 1],
                  cur.p1f + (cur.p2f - cur.p1f) * frac2,
                  cur.p2f,
                  {p1.x + frac2 * (p2.x - p1.x), p1.y + frac2 * (p2.y - p1.y), p1.z + frac2 * (p2.z - p1.z)},
                  p2};
      frac = std::clamp(frac, Real(0), Real(1));
      cur.p2f = cur.p1f + (cur.p2f - cur.p1f) * frac;
      cur.p2 = {p1.x + frac * (p2.x - p1.x), p1.y + frac * (p2.y - p1.y), p1.z + frac * (p2.z - p1.z)};
      nodeNum = node.children[side];
    }
    if (numPending == 0) return;
    cur = pending[--numPending];
  }
}

}  // namespace

void sizePolygonEdgeLines(TraceWork& tw, std::size_t numEdges) {
  std::vector<Pluecker>& lines = tw.scratch.polygonEdgeLines;
  if (lines.size() < numEdges) lines.resize(numEdges);
}

const EdgeUse* makePolygonEdgeUses(TraceWork& tw, const CmPolygon& poly) {
  const auto edges = tw.model.edgesOf(poly);
  std::vector<EdgeUse>& made = tw.scratch.edgeUses;
  if (made.size() < edges.size()) made.resize(edges.size());
  writeEdgeUses(tw.model.arrays(), edges, made.data());
  return made.data();
}

void setPolygonEdgeLines(TraceWork& tw, const CmPolygon& poly) { polygonEdges(tw, poly); }

void translateThroughModel(TraceWork& tw) {
  if (translateThroughBvh(tw)) return;  // the polygons' hierarchy, where the model has one
  if (tw.model.nodes().empty()) return;
  if (tw.pointTrace)
    walkSegment<TranslatePointItems>(tw);
  else
    walkSegment<TranslateTrmItems>(tw);
}

void positionTestThroughModel(TraceWork& tw) {
  if (tw.model.nodes().empty()) return;
  if (const PointTree* t = pointTreeOf(tw))
    positionWalkThroughPointTree(tw, *t);
  else
    walkSegment<PositionItems>(tw);
}

void rotateThroughBox(TraceWork& tw, const Bounds& box) {
  if (tw.model.nodes().empty()) return;
  if (const PointTree* t = pointTreeOf(tw))
    walkBoxThroughPointTree(tw, *t, box);
  else
    walkBox<RotateItems>(tw, 0, box);
}

}  // namespace cmkit::detail
