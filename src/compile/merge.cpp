// Merging coplanar polygons that share an edge into one convex polygon (the
// original's MergeTreePolygons, MergePolygonWithTreePolygons,
// TryMergePolygons and ReplacePolygons).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "compile/builder.h"

namespace cmkit::detail {

namespace {
/// The original's unguarded normalisation (a zero vector stays zero).
void normalizeUnguarded(Vec3& v) {
  const Real sq = v.lengthSquared();
  if (!(sq > 0) || !std::isfinite(sq)) {
    v = Vec3{};
    return;
  }
  v *= compatInvSqrt(sq);
}

/// The first tests of tryMergePolygons: same material, same plane, bounds
/// that meet.
bool mayMerge(const BPolygon& p1, const BPolygon& p2) {
  if (p1.material != p2.material) return false;
  if (std::fabs(p1.plane.dist - p2.plane.dist) > tol::kNormalEpsilon) return false;
  for (int i = 0; i < 3; ++i) {
    if (std::fabs(p1.plane.normal[i] - p2.plane.normal[i]) > tol::kNormalEpsilon) return false;
  }
  return p2.bounds.intersects(p1.bounds);
}

}  // namespace

void ModelBuilder::mergePolygons() {
  ++checkCount_;
  // Every merge starts from two polygons that share an edge and pass
  // mayMerge (tryMergePolygons tests it first). When no such pair exists,
  // nothing merges, and the walk over the tree's lists is left out: a mesh
  // of two-sided triangles, where a triangle shares its edges only with its
  // reversed copy (its neighbours make edges of their own), met ~99 000
  // polygons in turn and merged none.
  if (anyPairMayMerge()) {
    prepareEdgeUsers();
    prepareMergeIndex();
    mergeTreePolygons(0);
  }
  edgeUsers_.clear();
  polygonNodes_.clear();
}

void ModelBuilder::prepareEdgeUsers() {
  edgeUsers_.clear();
  std::size_t numUses = 0;
  for (const BPolygon& p : polygons_) numUses += p.freed ? 0 : p.edges.size();
  // (merged polygons add their uses later: a little more room)
  edgeUsers_.reserve(edges_.size(), numUses + numUses / 4);
  for (int p = 0; p < static_cast<int>(polygons_.size()); ++p) {
    if (polygon(p).freed) continue;
    for (const int e : polygon(p).edges) edgeUsers_.add(std::abs(e), p);
  }
}

bool ModelBuilder::anyPairMayMerge() const {
  // A polygon takes an edge already made only when one other polygon uses it
  // (getEdge), so an edge has at most two users here: each pair is tested at
  // its edge's second user, with the first user's number kept per edge. (An
  // edge with a third live user answers yes: the walk, which was always
  // right to run, then decides.)
  std::vector<int> firstUser(edges_.size(), kNone);
  std::vector<std::uint8_t> users(edges_.size(), 0);
  for (int p = 0; p < static_cast<int>(polygons_.size()); ++p) {
    const BPolygon& poly = polygon(p);
    if (poly.freed) continue;
    for (const int e : poly.edges) {
      const auto edge = static_cast<std::size_t>(std::abs(e));
      switch (users[edge]++) {
        case 0:
          firstUser[edge] = p;
          break;
        case 1:
          if (mayMerge(polygon(firstUser[edge]), poly)) return true;
          break;
        default:
          return true;
      }
    }
  }
  return false;
}

void ModelBuilder::prepareMergeIndex() {
  polygonNodes_.clear();
  // (merged polygons add their nodes later: a little more room)
  polygonNodes_.reserve(polygons_.size(), polygonRefs_.size() + polygonRefs_.size() / 4);
  for (int n = 0; n < static_cast<int>(nodes_.size()); ++n) {
    for (const int p : polygonsAt(n)) polygonNodes_.add(p, n);
  }
  // walkTouching's order: each node before those below it, the back subtree
  // before the front one (the tree does not change while merging).
  walkOrder_.assign(nodes_.size(), 0);
  std::vector<int> stack{0};
  for (int next = 0; !stack.empty();) {
    const int n = stack.back();
    stack.pop_back();
    walkOrder_[static_cast<std::size_t>(n)] = next++;
    if (node(n).isLeaf()) continue;
    stack.push_back(node(n).children[0]);
    stack.push_back(node(n).children[1]);
  }
  mergeMark_.assign(polygons_.size(), 0);
  mergeStamp_ = 0;
}

void ModelBuilder::mergeTreePolygons(int nodeNum) {
  for (;;) {
    bool merged;
    do {
      merged = false;
      for (const int p : polygonsAt(nodeNum)) {
        if (polygon(p).checkcount == checkCount_) continue;
        polygon(p).checkcount = checkCount_;
        if (mergePolygonWithTreePolygons(p)) {
          merged = true;
          break;  // the list changed: start it again
        }
      }
    } while (merged);
    const BNode& here = node(nodeNum);
    if (here.isLeaf()) break;
    const int front = here.children[0];
    mergeTreePolygons(here.children[1]);
    nodeNum = front;
  }
}

bool ModelBuilder::walkReaches(int nodeNum, const Bounds& bounds) const {
  for (int below = nodeNum, up = node(nodeNum).parent; up != kNone; below = up, up = node(up).parent) {
    const BNode& split = node(up);
    const bool beyondFront = bounds.min[split.planeType] > split.planeDist;  // the walk goes front only
    const bool beyondBack = bounds.max[split.planeType] < split.planeDist;   // back only (if not front only)
    const bool reached = below == split.children[0] ? beyondFront || !beyondBack : !beyondFront;
    if (!reached) return false;
  }
  return true;
}

bool ModelBuilder::mergePolygonWithTreePolygons(int polygonNum) {
  // The original tries the polygon with every polygon in the nodes its bounds
  // touch (walkTouching from the root, each node's list in order) and merges
  // with the first that tryMergePolygons accepts. tryMergePolygons returns
  // early, with no effect, for a polygon that shares no edge with it or
  // fails mayMerge; so only the nodes holding other candidates are searched,
  // in the walk's order: the same pairs reach tryMergePolygons' effects in
  // the same order.
  const int stamp = ++mergeStamp_;
  mergeNodes_.clear();
  const BPolygon& poly = polygon(polygonNum);
  const Bounds bounds = poly.bounds;
  for (const int e : poly.edges) {
    edgeUsers_.forEach(std::abs(e), [&](int q) {
      int& mark = mergeMark_[static_cast<std::size_t>(q)];
      if (q == polygonNum || mark == stamp || polygon(q).freed || !mayMerge(poly, polygon(q))) return;
      mark = stamp;
      polygonNodes_.forEach(q, [&](int n) {
        if (walkReaches(n, bounds)) mergeNodes_.push_back(n);
      });
    });
  }
  if (mergeNodes_.empty()) return false;
  std::sort(mergeNodes_.begin(), mergeNodes_.end(), [&](int a, int b) {
    return walkOrder_[static_cast<std::size_t>(a)] < walkOrder_[static_cast<std::size_t>(b)];
  });
  mergeNodes_.erase(std::unique(mergeNodes_.begin(), mergeNodes_.end()), mergeNodes_.end());
  for (const int n : mergeNodes_) {
    for (const int p : polygonsAt(n)) {
      if (p == polygonNum || mergeMark_[static_cast<std::size_t>(p)] != stamp) continue;
      const int newp = tryMergePolygons(polygonNum, p);
      if (newp == kNone) continue;
      counters_.numMergedPolys++;
      linkedNodes_.clear();
      replacePolygons(0, polygonNum, p, newp);
      for (const int old : {polygonNum, p}) {
        for (const int e : polygon(old).edges) edge(e).numUsers--;
        polygon(old).freed = true;
        polygon(old).edges.clear();
      }
      // the new polygon in the merge index
      for (const int e : polygon(newp).edges) edgeUsers_.add(std::abs(e), newp);
      for (const int linked : linkedNodes_) polygonNodes_.add(newp, linked);
      mergeMark_.resize(polygons_.size(), 0);
      return true;
    }
  }
  return false;
}

int ModelBuilder::tryMergePolygons(int p1Num, int p2Num) {
  const BPolygon& p1 = polygon(p1Num);
  const BPolygon& p2 = polygon(p2Num);
  if (!mayMerge(p1, p2)) return kNone;
  const int n1 = static_cast<int>(p1.edges.size());
  const int n2 = static_cast<int>(p2.edges.size());
  auto e1 = [&](int i) { return p1.edges[static_cast<std::size_t>(i)]; };
  auto e2 = [&](int j) { return p2.edges[static_cast<std::size_t>(j)]; };
  // Find the run of shared edges: the edges of each polygon just before and
  // just after it.
  int p1BeforeShare = kNone, p1AfterShare = kNone, p2BeforeShare = kNone, p2AfterShare = kNone;
  for (int i = 0; i < n1; ++i) {
    const int nexti = (i + 1) % n1;
    for (int j = 0; j < n2; ++j) {
      const int prevj = (j + n2 - 1) % n2;
      if (std::abs(e1(i)) == std::abs(e2(j))) {
        if (e1(i) == e2(j)) return kNone;  // used the same way by both
        if (std::abs(e1(nexti)) != std::abs(e2(prevj))) {
          if (p1AfterShare != kNone) return kNone;  // more than one shared run
          p1AfterShare = nexti;
          p2BeforeShare = prevj;
          break;
        }
      } else if (std::abs(e1(nexti)) == std::abs(e2(prevj))) {
        if (p1BeforeShare != kNone) return kNone;
        p1BeforeShare = i;
        p2AfterShare = j;
        break;
      }
    }
  }
  if (p1BeforeShare == kNone || p1AfterShare == kNone || p2BeforeShare == kNone || p2AfterShare == kNone)
    return kNone;

  // Convexity at both junctions.
  auto edgeDelta = [&](int edgeNum) { return edgeEnd(edgeNum) - edgeStart(edgeNum); };
  Vec3 normal = p1.plane.normal.cross(edgeDelta(e1(p1BeforeShare)));
  normalizeUnguarded(normal);
  Real dot = edgeDelta(e2(p2AfterShare)).dot(normal);
  if (dot < -tol::kContinuousEpsilon) return kNone;
  bool keep1 = dot > tol::kContinuousEpsilon;

  normal = p1.plane.normal.cross(edgeDelta(e2(p2BeforeShare)));
  normalizeUnguarded(normal);
  dot = edgeDelta(e1(p1AfterShare)).dot(normal);
  if (dot < -tol::kContinuousEpsilon) return kNone;
  bool keep2 = dot > tol::kContinuousEpsilon;

  // Collinear edges at a junction become one new edge.
  int newEdgeNum1 = 0;
  int newEdgeNum2 = 0;
  if (!keep1) {
    const Vec3 a = edgeStart(e1(p1BeforeShare));
    const Vec3 b = edgeEnd(e2(p2AfterShare));
    getEdge(a, b, newEdgeNum1, kNone);
    if (newEdgeNum1 == 0) keep1 = true;
  }
  if (!keep2) {
    const Vec3 a = edgeStart(e2(p2BeforeShare));
    const Vec3 b = edgeEnd(e1(p1AfterShare));
    getEdge(a, b, newEdgeNum2, kNone);
    if (newEdgeNum2 == 0) keep2 = true;
  }
  // getEdge may have grown edges_ but not polygons_: p1, p2 stay valid.
  EdgeList newEdges;  // (no room reserved: two quads' n1 + n2 would leave the list's own)
  const int k1 = keep1 ? 0 : 1;
  const int k2 = keep2 ? 0 : 1;
  if (!keep2) newEdges.push_back(newEdgeNum2);
  if (p1AfterShare < p1BeforeShare) {
    for (int i = p1AfterShare + k2; i <= p1BeforeShare - k1; ++i) newEdges.push_back(e1(i));
  } else {
    for (int i = p1AfterShare + k2; i <= p1BeforeShare - k1 + n1; ++i) newEdges.push_back(e1(i % n1));
  }
  if (!keep1) newEdges.push_back(newEdgeNum1);
  if (p2AfterShare < p2BeforeShare) {
    for (int i = p2AfterShare + k1; i <= p2BeforeShare - k2; ++i) newEdges.push_back(e2(i));
  } else {
    for (int i = p2AfterShare + k1; i <= p2BeforeShare - k2 + n2; ++i) newEdges.push_back(e2(i % n2));
  }
  if (newEdges.size() > static_cast<std::size_t>(tol::kMaxPolygonEdges)) {
    // The original would overflow its edge array here; cmkit does not merge.
    // (The edges getEdge may have made stay, like those of rejected polygons.)
    return kNone;
  }
  // With odd geometry (found by fuzzing: a patch point at 6.5e13) the shared
  // run is not what the splice above assumes and the original makes a
  // polygon whose edges do not form a loop; cmkit keeps the two polygons.
  // Real maps never get here (their .cm files validate).
  if (!edgesFormLoop(newEdges)) return kNone;

  BPolygon np;
  np.bounds = unionBounds(p1.bounds, p2.bounds);
  np.plane = p1.plane;
  np.contents = p1.contents;
  np.material = p1.material;
  np.checkcount = 0;
  for (const int e : newEdges) {
    if (!keep1 && e == newEdgeNum1) continue;
    if (!keep2 && e == newEdgeNum2) continue;
    edge(e).numUsers++;
  }
  np.edges = std::move(newEdges);
  polygons_.push_back(std::move(np));
  return static_cast<int>(polygons_.size()) - 1;
}

void ModelBuilder::replacePolygons(int nodeNum, int p1, int p2, int newp) {
  for (;;) {
    bool linked = false;
    int last = kNone;
    for (int r = node(nodeNum).polygons, next; r != kNone; r = next) {
      next = polygonRef(r).next;
      const int p = polygonRef(r).item;
      if (p == p1 || p == p2) {
        if (linked) {
          // the new polygon is already linked here: drop this reference
          if (last != kNone) {
            polygonRef(last).next = next;
          } else {
            node(nodeNum).polygons = next;
          }
          polygonRef(r).next = freePolygonRef_;
          freePolygonRef_ = r;
          counters_.numPolygonRefs--;
        } else {
          polygonRef(r).item = newp;
          linked = true;
          linkedNodes_.push_back(nodeNum);
          last = r;
        }
      } else {
        last = r;
      }
    }
    const BNode& here = node(nodeNum);
    if (here.isLeaf()) break;
    const Bounds& b1 = polygon(p1).bounds;
    const Bounds& b2 = polygon(p2).bounds;
    if (b1.min[here.planeType] > here.planeDist && b2.min[here.planeType] > here.planeDist) {
      nodeNum = here.children[0];
    } else if (b1.max[here.planeType] < here.planeDist && b2.max[here.planeType] < here.planeDist) {
      nodeNum = here.children[1];
    } else {
      const int front = here.children[0];
      replacePolygons(here.children[1], p1, p2, newp);
      nodeNum = front;
    }
  }
}

}  // namespace cmkit::detail
